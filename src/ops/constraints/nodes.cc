#include "rigel/ops/constraints/nodes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "rigel/graph/graph.h"
#include "rigel/ops/constraints/constraints.h"

namespace rigel::ops::constraints {
namespace {

using graph::AttrIndex;
using graph::AttrSpec;
using graph::AttrType;
using graph::ComputeContext;
using graph::Value;
using graph::ValueType;
using math::RotateOrder;

constexpr AttrType kDouble3{ValueType::kDouble3, false};
constexpr AttrType kMatrix{ValueType::kMatrix, false};

// Attribute layout. Shared inputs first, then `error`, then each type's own.
namespace attr {
enum : AttrIndex {
  kTargetWorldMatrix = 0,
  kTargetWeight,
  kTargetOffset,
  kParentInverseMatrix,
  kRotateOrder,
  kJointOrient,
  kRestTranslate,
  kRestRotate,
  kRestScale,
  kError,
  kOwn,  // first type-specific attribute
};
}  // namespace attr
namespace parent_attr {
enum : AttrIndex { kRigid = attr::kOwn, kTranslate, kRotate, kScale };
}
namespace point_attr {
enum : AttrIndex { kTranslate = attr::kOwn };
}
namespace orient_attr {
enum : AttrIndex { kRotate = attr::kOwn };
}
namespace scale_attr {
enum : AttrIndex { kScale = attr::kOwn };
}
namespace aim_attr {
enum : AttrIndex {
  kAimVector = attr::kOwn,
  kUpVector,
  kWorldUpType,
  kWorldUpVector,
  kWorldUpMatrix,
  kConstraintTranslate,
  kOffset,
  kRotate
};
}
// poleVectorConstraint: the first four shared inputs, then these.
namespace pole_attr {
enum : AttrIndex { kStartPosition = attr::kRotateOrder, kHandlePosition, kRestPoleVector, kError, kPoleVector };
}

AttrSpec input(std::string name, AttrType type, Value value, const std::vector<std::string>& affects,
               std::uint32_t extra = 0) {
  return graph::input_attr(std::move(name), type, std::move(value), affects, extra);
}

AttrSpec output(std::string name, AttrType type, std::uint32_t extra = 0) {
  return graph::output_attr(std::move(name), type, extra);
}

std::vector<AttrSpec> target_attrs(const std::vector<std::string>& outs) {
  return {
      input("targetWorldMatrix", {ValueType::kMatrix, true}, std::vector<Mat4>{}, outs),
      input("targetWeight", {ValueType::kDouble, true}, std::vector<double>{}, outs, graph::kKeyable),
      input("targetOffset", {ValueType::kMatrix, true}, std::vector<Mat4>{}, outs),
      input("parentInverseMatrix", kMatrix, Mat4(Mat4::Identity()), outs),
  };
}

// Shared attributes of the blending types, in attr:: order.
std::vector<AttrSpec> blend_attrs(const std::vector<std::string>& outs) {
  std::vector<AttrSpec> attrs = target_attrs(outs);
  AttrSpec order = input("rotateOrder", {ValueType::kEnum, false}, std::int64_t{0}, outs);
  order.enum_names = {"xyz", "yzx", "zxy", "xzy", "yxz", "zyx"};
  attrs.push_back(order);
  attrs.push_back(input("jointOrient", kDouble3, Vec3(Vec3::Zero()), outs, graph::kAngle));
  attrs.push_back(input("restTranslate", kDouble3, Vec3(Vec3::Zero()), outs));
  attrs.push_back(input("restRotate", kDouble3, Vec3(Vec3::Zero()), outs, graph::kAngle));
  attrs.push_back(input("restScale", kDouble3, Vec3(Vec3::Ones()), outs));
  attrs.push_back(output("error", {ValueType::kString, false}, graph::kHidden));
  return attrs;
}

template <typename E>
E read_enum(const ComputeContext& c, AttrIndex a, int count) {
  return static_cast<E>(std::clamp<std::int64_t>(c.get<std::int64_t>(a), 0, count - 1));
}

// The target spans of a node: weights default to 1 and offsets to the
// identity where the arrays are shorter than targetWorldMatrix. Padded
// copies live in per-thread scratch (nodes compute in parallel), so the
// common case of full arrays copies nothing.
TargetSpans read_targets(const ComputeContext& c) {
  thread_local std::vector<double> weights;
  thread_local std::vector<Mat4> offsets;
  const auto& world = c.get<std::vector<Mat4>>(attr::kTargetWorldMatrix);
  const auto& w = c.get<std::vector<double>>(attr::kTargetWeight);
  const auto& o = c.get<std::vector<Mat4>>(attr::kTargetOffset);
  TargetSpans spans;
  spans.world = world;
  spans.weights = std::span<const double>(w);
  spans.offsets = std::span<const Mat4>(o);
  if (w.size() < world.size()) {
    weights.assign(w.begin(), w.end());
    weights.resize(world.size(), 1.0);
    spans.weights = weights;
  }
  spans.weights = spans.weights.first(std::min(spans.weights.size(), world.size()));
  if (o.size() < world.size()) {
    offsets.assign(o.begin(), o.end());
    offsets.resize(world.size(), Mat4::Identity());
    spans.offsets = offsets;
  }
  spans.offsets = spans.offsets.first(std::min(spans.offsets.size(), world.size()));
  return spans;
}

// Why a job built from the node's inputs does not validate: names the
// attribute for the common cases.
std::string reason(const TargetSpans& t) {
  if (t.world.empty()) return "targetWorldMatrix: no target";
  for (std::size_t i = 0; i < t.weights.size(); ++i) {
    if (!(t.weights[i] >= 0.0) || !std::isfinite(t.weights[i])) {
      return "targetWeight[" + std::to_string(i) + "]: must be finite and >= 0";
    }
  }
  return "a matrix or vector input is not affine or not finite";
}

void write_error(ComputeContext& c, AttrIndex a, const std::string& message) {
  std::get<std::string>(c.output(a)) = message;
}

// What a blending constraint derives from its rest inputs (rotateOrder,
// jointOrient, restTranslate, restRotate, restScale), which a rig sets once
// at build: kept between evaluations (their versions), so playback does not
// convert the same Euler angles to quaternions and matrices every frame.
struct RestCache final : graph::NodeCache {
  static constexpr AttrIndex kFirst = attr::kRotateOrder;
  static constexpr std::size_t kCount = attr::kRestScale - attr::kRotateOrder + 1;
  std::array<std::uint64_t, kCount> versions{};
  bool built = false;
  RotateOrder order = RotateOrder::kXYZ;
  Quat joint_orient = Quat::Identity();
  Quat rest_rotation = Quat::Identity();  // the rest rotation as the local rotation (joint orient included)
  Mat4 rest_local = Mat4::Identity();
};

const RestCache& rest(ComputeContext& c) {
  std::array<std::uint64_t, RestCache::kCount> now{};
  for (std::size_t i = 0; i < RestCache::kCount; ++i) now[i] = c.version(RestCache::kFirst + static_cast<AttrIndex>(i));
  RestCache& cache = c.cache<RestCache>();
  if (cache.built && cache.versions == now) return cache;
  cache.versions = now;
  cache.built = true;
  cache.order = read_enum<RotateOrder>(c, attr::kRotateOrder, math::kRotateOrderCount);
  cache.joint_orient = math::euler_to_quat(math::to_radians(c.get<Vec3>(attr::kJointOrient)), RotateOrder::kXYZ);
  cache.rest_rotation =
      cache.joint_orient * math::euler_to_quat(math::to_radians(c.get<Vec3>(attr::kRestRotate)), cache.order);
  cache.rest_local =
      math::trs_matrix(c.get<Vec3>(attr::kRestTranslate), cache.rest_rotation, c.get<Vec3>(attr::kRestScale));
  return cache;
}

// Writes a local rotation as Euler degrees in the driven's rotate order,
// with the joint orient taken out, closest to the previous output (no flips
// of 360 degrees between evaluations).
void write_rotate(ComputeContext& c, AttrIndex out, const Quat& local_rotation) {
  const RestCache& r_cache = rest(c);
  const RotateOrder order = r_cache.order;
  const Quat r = r_cache.joint_orient.conjugate() * local_rotation;
  Vec3& rotate = std::get<Vec3>(c.output(out));
  const Vec3 previous = math::to_radians(rotate);
  Vec3 euler = math::quat_to_euler(r.normalized(), order);
  if (previous.allFinite()) euler = math::euler_closest(euler, previous, order);
  rotate = math::to_degrees(euler);
}

void compute_parent(ComputeContext& c) {
  namespace a = parent_attr;
  ParentConstraintJob job;
  job.targets = read_targets(c);
  job.parent_inverse = c.get<Mat4>(attr::kParentInverseMatrix);
  job.rest_local = rest(c).rest_local;
  job.rigid = c.get<bool>(a::kRigid);
  Mat4 local;
  job.output = &local;
  if (!job.run()) {
    write_error(c, attr::kError, reason(job.targets));
    local = job.rest_local.allFinite() ? job.rest_local : Mat4(Mat4::Identity());
  } else {
    write_error(c, attr::kError, {});
  }
  const math::Decomposed d = math::decompose(local);
  c.output(a::kTranslate) = d.translate;
  c.output(a::kScale) = d.scale;
  write_rotate(c, a::kRotate, d.rotation);
}

void compute_point(ComputeContext& c) {
  PointConstraintJob job;
  job.targets = read_targets(c);
  job.parent_inverse = c.get<Mat4>(attr::kParentInverseMatrix);
  job.rest_translate = c.get<Vec3>(attr::kRestTranslate);
  Vec3 out;
  job.output = &out;
  const bool ok = job.run();
  write_error(c, attr::kError, ok ? std::string() : reason(job.targets));
  c.output(point_attr::kTranslate) = ok ? out : job.rest_translate;
}

void compute_orient(ComputeContext& c) {
  OrientConstraintJob job;
  job.targets = read_targets(c);
  job.parent_inverse = c.get<Mat4>(attr::kParentInverseMatrix);
  job.rest_rotation = rest(c).rest_rotation;
  Quat out;
  job.output = &out;
  const bool ok = job.run();
  write_error(c, attr::kError, ok ? std::string() : reason(job.targets));
  write_rotate(c, orient_attr::kRotate, ok ? out : job.rest_rotation);
}

void compute_scale(ComputeContext& c) {
  ScaleConstraintJob job;
  job.targets = read_targets(c);
  job.parent_inverse = c.get<Mat4>(attr::kParentInverseMatrix);
  job.rest_scale = c.get<Vec3>(attr::kRestScale);
  Vec3 out;
  job.output = &out;
  const bool ok = job.run();
  write_error(c, attr::kError, ok ? std::string() : reason(job.targets));
  c.output(scale_attr::kScale) = ok ? out : job.rest_scale;
}

void compute_aim(ComputeContext& c) {
  namespace a = aim_attr;
  AimConstraintJob job;
  job.targets = read_targets(c);
  job.parent_inverse = c.get<Mat4>(attr::kParentInverseMatrix);
  job.rest_rotation = rest(c).rest_rotation;
  job.aim_vector = c.get<Vec3>(a::kAimVector);
  job.up_vector = c.get<Vec3>(a::kUpVector);
  job.world_up_type = read_enum<WorldUpType>(c, a::kWorldUpType, kWorldUpTypeCount);
  job.world_up_vector = c.get<Vec3>(a::kWorldUpVector);
  job.world_up_matrix = c.get<Mat4>(a::kWorldUpMatrix);
  job.offset = math::euler_to_quat(math::to_radians(c.get<Vec3>(a::kOffset)), RotateOrder::kXYZ);
  // The driven's pivot in world: its translate taken out of parent space.
  const Mat4 parent_world = math::affine_inverse(job.parent_inverse);
  const Vec3 translate = c.get<Vec3>(a::kConstraintTranslate);
  job.driven_position = parent_world.topLeftCorner<3, 3>() * translate + parent_world.topRightCorner<3, 1>();
  Quat out;
  job.output = &out;
  const bool ok = job.run();
  write_error(c, attr::kError,
              ok ? std::string() : "aimVector/upVector zero or parallel, or " + reason(job.targets));
  write_rotate(c, a::kRotate, ok ? out : job.rest_rotation);
}

void compute_pole(ComputeContext& c) {
  namespace a = pole_attr;
  PoleVectorConstraintJob job;
  job.targets = read_targets(c);
  job.parent_inverse = c.get<Mat4>(attr::kParentInverseMatrix);
  job.start_position = c.get<Vec3>(a::kStartPosition);
  job.handle_position = c.get<Vec3>(a::kHandlePosition);
  job.rest_pole_vector = c.get<Vec3>(a::kRestPoleVector);
  Vec3 out;
  job.output = &out;
  const bool ok = job.run();
  write_error(c, a::kError, ok ? std::string() : reason(job.targets));
  c.output(a::kPoleVector) = ok ? out : job.rest_pole_vector;
}

graph::NodeTypeSpec blend_spec(std::string name, std::string description, graph::ComputeFn compute,
                               const std::vector<std::string>& outs) {
  std::vector<std::string> affected = outs;
  affected.push_back("error");
  graph::NodeTypeSpec spec;
  spec.name = std::move(name);
  spec.description = std::move(description);
  spec.attrs = blend_attrs(affected);
  spec.compute = compute;
  return spec;
}

std::vector<std::string> affects_of(const graph::NodeTypeSpec& spec) { return spec.attrs.front().affects; }

}  // namespace

Status register_constraint_types(graph::Registry& registry) {
  graph::NodeTypeSpec parent = blend_spec(kParentConstraintType,
                                          "Parent constraint: the driven follows the weighted targets' transforms",
                                          compute_parent, {"translate", "rotate", "scale"});
  parent.attrs.push_back(input("rigid", {ValueType::kBool, false}, false, affects_of(parent)));
  parent.attrs.push_back(output("translate", kDouble3));
  parent.attrs.push_back(output("rotate", kDouble3, graph::kAngle));
  parent.attrs.push_back(output("scale", kDouble3));

  graph::NodeTypeSpec point = blend_spec(kPointConstraintType, "Point constraint: the weighted targets' position",
                                         compute_point, {"translate"});
  point.attrs.push_back(output("translate", kDouble3));

  graph::NodeTypeSpec orient = blend_spec(kOrientConstraintType,
                                          "Orient constraint: the weighted targets' rotation (shortest path)",
                                          compute_orient, {"rotate"});
  orient.attrs.push_back(output("rotate", kDouble3, graph::kAngle));

  graph::NodeTypeSpec scale = blend_spec(kScaleConstraintType, "Scale constraint: the weighted targets' scale",
                                         compute_scale, {"scale"});
  scale.attrs.push_back(output("scale", kDouble3));

  graph::NodeTypeSpec aim = blend_spec(kAimConstraintType,
                                       "Aim constraint: an axis of the driven points at the weighted targets",
                                       compute_aim, {"rotate"});
  {
    const std::vector<std::string> outs = affects_of(aim);
    AttrSpec up_type = input("worldUpType", {ValueType::kEnum, false}, std::int64_t{0}, outs);
    up_type.enum_names = {"scene", "object", "objectRotation", "vector", "none"};
    aim.attrs.push_back(input("aimVector", kDouble3, Vec3(Vec3::UnitX()), outs));
    aim.attrs.push_back(input("upVector", kDouble3, Vec3(Vec3::UnitY()), outs));
    aim.attrs.push_back(up_type);
    aim.attrs.push_back(input("worldUpVector", kDouble3, Vec3(Vec3::UnitY()), outs));
    aim.attrs.push_back(input("worldUpMatrix", kMatrix, Mat4(Mat4::Identity()), outs));
    aim.attrs.push_back(input("constraintTranslate", kDouble3, Vec3(Vec3::Zero()), outs));
    aim.attrs.push_back(input("offset", kDouble3, Vec3(Vec3::Zero()), outs, graph::kAngle));
    aim.attrs.push_back(output("rotate", kDouble3, graph::kAngle));
  }

  graph::NodeTypeSpec pole;
  pole.name = kPoleVectorConstraintType;
  pole.description = "Pole vector constraint: the weighted poles' offset from the start-handle line";
  pole.compute = compute_pole;
  {
    const std::vector<std::string> outs = {"poleVector", "error"};
    pole.attrs = target_attrs(outs);
    pole.attrs.push_back(input("startPosition", kDouble3, Vec3(Vec3::Zero()), outs));
    pole.attrs.push_back(input("handlePosition", kDouble3, Vec3(Vec3::Zero()), outs));
    pole.attrs.push_back(input("restPoleVector", kDouble3, Vec3(Vec3::Zero()), outs));
    pole.attrs.push_back(output("error", {ValueType::kString, false}, graph::kHidden));
    pole.attrs.push_back(output("poleVector", kDouble3));
  }

  for (graph::NodeTypeSpec* spec : {&parent, &point, &orient, &scale, &aim, &pole}) {
    if (Status s = registry.add(std::move(*spec)); !s) return s;
  }
  return Status::ok();
}

}  // namespace rigel::ops::constraints
