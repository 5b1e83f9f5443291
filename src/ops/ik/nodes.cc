#include "rigel/ops/ik/nodes.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <optional>
#include <utility>
#include <string>
#include <vector>

#include "ik_math.h"
#include "rigel/graph/graph.h"
#include "rigel/math/transform.h"
#include "rigel/ops/ik/ccd.h"
#include "rigel/ops/ik/fabrik.h"
#include "rigel/ops/ik/spline_ik.h"
#include "rigel/ops/ik/two_bone_ik.h"
#include "rigel/scene/transform_types.h"

namespace rigel::ops::ik {
namespace {

using graph::AttrIndex;
using graph::AttrSpec;
using graph::AttrType;
using graph::ComputeContext;
using graph::NodeId;
using graph::Plug;
using graph::Value;
using graph::ValueType;

constexpr AttrType kMatrixType{ValueType::kMatrix, false};
constexpr AttrType kMatrixArray{ValueType::kMatrix, true};
constexpr AttrType kDouble3Type{ValueType::kDouble3, false};
constexpr AttrType kDouble3Array{ValueType::kDouble3, true};
constexpr AttrType kDoubleType{ValueType::kDouble, false};
constexpr AttrType kDoubleArray{ValueType::kDouble, true};
constexpr AttrType kQuatArray{ValueType::kQuat, true};
constexpr AttrType kBoolType{ValueType::kBool, false};
constexpr AttrType kIntType{ValueType::kInt, false};
constexpr AttrType kStringType{ValueType::kString, false};

// Largest arc-length table a node builds (8 MiB of doubles).
constexpr std::int64_t kMaxArcLengthSamples = 1 << 20;
// Arc-length samples per control point span when arcLengthSamples is 0.
constexpr std::int64_t kSamplesPerSpan = 64;

// ---- attribute specs ----------------------------------------------------------

AttrSpec input(std::string name, AttrType type, Value value, std::uint32_t extra = 0) {
  return graph::input_attr(std::move(name), type, std::move(value), {}, extra);
}

AttrSpec output(std::string name, AttrType type, std::uint32_t extra = 0) {
  return graph::output_attr(std::move(name), type, extra);
}

AttrSpec enum_input(std::string name, AttrType type, Value value, std::vector<std::string> names) {
  AttrSpec spec = input(std::move(name), type, std::move(value));
  spec.enum_names = std::move(names);
  return spec;
}

// The attributes every IK type starts with, in ik_attr:: order.
std::vector<AttrSpec> chain_attrs() {
  return {
      input("parentMatrix", kMatrixType, Mat4(Mat4::Identity())),
      input("restMatrix", kMatrixArray, std::vector<Mat4>{}),
      input("restOffsetParentMatrix", kMatrixArray, std::vector<Mat4>{}),
      input("restJointOrient", kDouble3Array, std::vector<Vec3>{}, graph::kAngle),
      input("restRotateAxis", kDouble3Array, std::vector<Vec3>{}, graph::kAngle),
      input("weight", kDoubleType, 1.0, graph::kKeyable),
      output("error", kStringType, graph::kHidden),
      output("outRotations", kQuatArray),
      output("outTranslations", kDouble3Array),
      output("outScales", kDouble3Array),
      output("outShears", kDouble3Array),
      output("outWorldMatrices", kMatrixArray, graph::kHidden),
  };
}

// Every input of an IK node affects every output: the solve reads them all.
graph::NodeTypeSpec finish(graph::NodeTypeSpec spec) {
  std::vector<std::string> outputs;
  for (const AttrSpec& a : spec.attrs) {
    if (a.flags & graph::kOutput) outputs.push_back(a.name);
  }
  for (AttrSpec& a : spec.attrs) {
    if (a.flags & graph::kInput) a.affects = outputs;
  }
  return spec;
}

// ---- evaluation ---------------------------------------------------------------

// Per-thread scratch: nodes of one schedule level compute in parallel.
struct Scratch {
  std::vector<Mat4> local;      // rest local matrices (offset parent included)
  std::vector<Mat4> world;      // rest world matrices
  std::vector<Mat4> local_out;  // solved local matrices (offset parent included)
  std::vector<Mat4> world_out;  // solved world matrices (spline)
  std::vector<Quat> corrections;
  std::vector<Vec3> positions;
  std::vector<Vec3> points;
  std::vector<double> translate_scale;
  std::vector<double> arc_lengths;
  std::vector<JointLimit> limits;
};

Scratch& scratch() {
  thread_local Scratch s;
  return s;
}

// One joint's channels: local matrix = T * JO * R * RA * SH * S.
struct Channels {
  Vec3 translate = Vec3::Zero();
  Quat rotation = Quat::Identity();
  Vec3 scale = Vec3::Ones();
  Vec3 shear = Vec3::Zero();
};

template <typename T>
const T& element_or(const std::vector<T>& values, std::size_t i, const T& fallback) {
  return i < values.size() ? values[i] : fallback;
}

bool finite(const Mat4& m) { return m.allFinite(); }

// "not finite" / "not affine (last row 0 0 0 1)" / empty.
std::string matrix_problem(const Mat4& m) {
  if (!finite(m)) return "not finite";
  if (!detail::is_affine(m)) return "not affine (its last row must be 0 0 0 1)";
  return {};
}

std::string indexed(const char* attr, std::size_t i) { return std::string(attr) + "[" + std::to_string(i) + "]"; }

std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", v);
  return text;
}

Quat orient_quat(const Vec3& degrees) { return math::euler_to_quat(math::to_radians(degrees), math::RotateOrder::kXYZ); }

// The joint rest data of a node, read once per evaluation.
struct ChainData {
  const std::vector<Mat4>* rest = nullptr;
  const std::vector<Mat4>* offset = nullptr;
  const std::vector<Vec3>* orient = nullptr;
  const std::vector<Vec3>* axis = nullptr;
  Mat4 parent = Mat4::Identity();
  std::size_t count = 0;

  const Mat4& offset_of(std::size_t i) const {
    static const Mat4 kIdentity = Mat4::Identity();
    return element_or(*offset, i, kIdentity);
  }
  Vec3 orient_of(std::size_t i) const { return element_or(*orient, i, Vec3(Vec3::Zero())); }
  Vec3 axis_of(std::size_t i) const { return element_or(*axis, i, Vec3(Vec3::Zero())); }
};

ChainData chain_data(const ComputeContext& c) {
  ChainData d;
  d.rest = &c.get<std::vector<Mat4>>(ik_attr::kRestMatrix);
  d.offset = &c.get<std::vector<Mat4>>(ik_attr::kRestOffsetParentMatrix);
  d.orient = &c.get<std::vector<Vec3>>(ik_attr::kRestJointOrient);
  d.axis = &c.get<std::vector<Vec3>>(ik_attr::kRestRotateAxis);
  d.parent = c.get<Mat4>(ik_attr::kParentMatrix);
  d.count = d.rest->size();
  return d;
}

// Checks the shared inputs and builds the rest local and world matrices in
// `s`. Returns why the chain cannot be solved, or empty.
std::string read_chain(const ComputeContext& c, const ChainData& d, const char* type, std::size_t min_joints,
                       std::size_t max_joints, Scratch& s) {
  if (d.count < min_joints || d.count > max_joints) {
    const std::string need = min_joints == max_joints ? "exactly " + std::to_string(min_joints)
                                                      : "at least " + std::to_string(min_joints);
    return "restMatrix: " + std::string(type) + " needs " + need + " joints, got " + std::to_string(d.count);
  }
  if (std::string p = matrix_problem(d.parent); !p.empty()) return "parentMatrix: " + p;
  s.local.resize(d.count);
  s.world.resize(d.count);
  for (std::size_t i = 0; i < d.count; ++i) {
    if (std::string p = matrix_problem((*d.rest)[i]); !p.empty()) return indexed("restMatrix", i) + ": " + p;
    const Mat4& offset = d.offset_of(i);
    if (std::string p = matrix_problem(offset); !p.empty()) return indexed("restOffsetParentMatrix", i) + ": " + p;
    if (!(std::abs(offset.topLeftCorner<3, 3>().determinant()) > 1e-300)) {
      return indexed("restOffsetParentMatrix", i) + ": singular (no inverse)";
    }
    if (!d.orient_of(i).allFinite()) return indexed("restJointOrient", i) + ": not finite";
    if (!d.axis_of(i).allFinite()) return indexed("restRotateAxis", i) + ": not finite";
    s.local[i] = offset * (*d.rest)[i];
    s.world[i] = (i == 0 ? d.parent : s.world[i - 1]) * s.local[i];
    if (!finite(s.world[i])) return "the chain's rest world matrices overflow (restMatrix too large)";
  }
  const double weight = c.get<double>(ik_attr::kWeight);
  if (!(weight >= 0.0 && weight <= 1.0)) return "weight: must be in [0, 1], got " + number(weight);
  return {};
}

// The channels of a joint whose local matrix (without offset parent) is
// `matrix`: T * rotation * SH * S decomposed, and R = JO^-1 * rotation * RA^-1.
Channels channels_of(const Mat4& matrix, const Vec3& orient_degrees, const Vec3& axis_degrees) {
  const math::Decomposed parts = math::decompose(matrix);
  Channels out;
  out.translate = parts.translate;
  out.scale = parts.scale;
  out.shear = parts.shear;
  out.rotation = (orient_quat(orient_degrees).conjugate() * parts.rotation * orient_quat(axis_degrees).conjugate())
                     .normalized();
  return out;
}

// The local matrix a joint computes from `channels` (math::compose, as the
// joint type does in quaternion mode).
Mat4 compose_channels(const Channels& ch, const Vec3& orient_degrees, const Vec3& axis_degrees) {
  math::TransformParts p;
  p.translate = ch.translate;
  p.rotate_mode = math::RotateMode::kQuaternion;
  p.rotate_quaternion = ch.rotation;
  p.scale = ch.scale;
  p.shear = ch.shear;
  p.joint_orient = math::to_radians(orient_degrees);
  p.rotate_axis = math::to_radians(axis_degrees);
  return math::compose(p);
}

// Writes the out* arrays from per-joint channels, and outWorldMatrices from
// them (identity where not finite, for the fallback).
void write_channels(ComputeContext& c, const ChainData& d, std::span<const Channels> channels) {
  const std::size_t n = channels.size();
  auto& rotations = std::get<std::vector<Quat>>(c.output(ik_attr::kOutRotations));
  auto& translations = std::get<std::vector<Vec3>>(c.output(ik_attr::kOutTranslations));
  auto& scales = std::get<std::vector<Vec3>>(c.output(ik_attr::kOutScales));
  auto& shears = std::get<std::vector<Vec3>>(c.output(ik_attr::kOutShears));
  auto& worlds = std::get<std::vector<Mat4>>(c.output(ik_attr::kOutWorldMatrices));
  const std::size_t previous = rotations.size();
  rotations.resize(n);
  translations.resize(n);
  scales.resize(n);
  shears.resize(n);
  worlds.resize(n);
  Mat4 parent = matrix_problem(d.parent).empty() ? d.parent : Mat4(Mat4::Identity());
  for (std::size_t i = 0; i < n; ++i) {
    Quat q = channels[i].rotation;
    // q and -q are the same rotation: keep the hemisphere of the last
    // evaluation so that sampled or baked quaternions do not jump sign.
    if (i < previous && rotations[i].coeffs().dot(q.coeffs()) < 0.0) q.coeffs() = -q.coeffs();
    rotations[i] = q;
    translations[i] = channels[i].translate;
    scales[i] = channels[i].scale;
    shears[i] = channels[i].shear;
    const Vec3 orient = d.orient_of(i);
    const Vec3 axis = d.axis_of(i);
    Mat4 world = parent * d.offset_of(i) * compose_channels(channels[i], orient, axis);
    if (!finite(world)) world = Mat4::Identity();
    worlds[i] = world;
    parent = world;
  }
}

// The rest channels of every joint (the fallback and the weight-0 pose).
void rest_channels(const ChainData& d, std::vector<Channels>& out) {
  out.assign(d.count, Channels{});
  for (std::size_t i = 0; i < d.count; ++i) {
    const Mat4& m = (*d.rest)[i];
    if (!finite(m)) continue;
    const Vec3 orient = d.orient_of(i);
    const Vec3 axis = d.axis_of(i);
    Channels ch = channels_of(m, orient.allFinite() ? orient : Vec3(Vec3::Zero()),
                              axis.allFinite() ? axis : Vec3(Vec3::Zero()));
    if (ch.translate.allFinite() && ch.rotation.coeffs().allFinite() && ch.scale.allFinite() &&
        ch.shear.allFinite()) {
      out[i] = ch;
    }
  }
}

thread_local std::vector<Channels> t_channels;
thread_local std::vector<Channels> t_rest_channels;

// Error: the rest pose, and the message.
void write_fallback(ComputeContext& c, const ChainData& d, std::string message) {
  rest_channels(d, t_channels);
  write_channels(c, d, t_channels);
  std::get<std::string>(c.output(ik_attr::kError)) = std::move(message);
}

// Success: channels from the solved local matrices (offset parent included),
// blended with the rest channels when `blend` < 1.
void write_solved(ComputeContext& c, const ChainData& d, std::span<const Mat4> solved_local, double blend) {
  t_channels.resize(d.count);
  for (std::size_t i = 0; i < d.count; ++i) {
    const Mat4 matrix = math::affine_inverse(d.offset_of(i)) * solved_local[i];
    t_channels[i] = channels_of(matrix, d.orient_of(i), d.axis_of(i));
  }
  if (blend < 1.0) {
    rest_channels(d, t_rest_channels);
    for (std::size_t i = 0; i < d.count; ++i) {
      const Channels& a = t_rest_channels[i];
      Channels& b = t_channels[i];
      b.translate = a.translate + blend * (b.translate - a.translate);
      b.rotation = a.rotation.slerp(blend, b.rotation).normalized();  // Eigen's slerp takes the short path
      b.scale = a.scale + blend * (b.scale - a.scale);
      b.shear = a.shear + blend * (b.shear - a.shear);
    }
  }
  write_channels(c, d, t_channels);
  std::get<std::string>(c.output(ik_attr::kError)).clear();
}

Vec3 translation_of(const Mat4& m) { return m.topRightCorner<3, 1>(); }

std::string unit_problem(const char* attr, const Vec3& v) {
  if (detail::is_unit(v)) return {};
  return std::string(attr) + ": not a unit vector (length " + number(v.norm()) + ")";
}

// ---- ikTwoBone, ikThreeBone ----

// Reads the two-bone solve's inputs (shared by both types) into `job`,
// from the start joint at `start`. Returns what is wrong, or "".
std::string read_two_bone(const ComputeContext& c, const Vec3& start, TwoBoneIkJob& job) {
  namespace a = two_bone_attr;
  job.target = translation_of(c.get<Mat4>(a::kTargetMatrix));
  const bool use_pole_matrix = c.get<bool>(a::kUsePoleMatrix);
  job.pole_vector =
      use_pole_matrix ? Vec3(translation_of(c.get<Mat4>(a::kPoleMatrix)) - start) : c.get<Vec3>(a::kPoleVector);
  job.pole_mode = static_cast<TwoBonePoleMode>(std::clamp<std::int64_t>(c.get<std::int64_t>(a::kPoleMode), 0, 1));
  job.mid_axis = c.get<Vec3>(a::kMidAxis);
  job.twist_angle = math::to_radians(c.get<double>(a::kTwist));
  job.soft = c.get<double>(a::kSoft);
  job.stretch = c.get<bool>(a::kStretch);
  job.max_stretch = c.get<double>(a::kMaxStretch);
  job.weight = c.get<double>(ik_attr::kWeight);
  if (!detail::all_finite(job.target)) return "targetMatrix: the target position is not finite";
  if (!detail::all_finite(job.pole_vector))
    return use_pole_matrix ? "poleMatrix: the pole position is not finite" : "poleVector: not finite";
  if (std::string problem = unit_problem("midAxis", job.mid_axis); !problem.empty()) return problem;
  if (!std::isfinite(job.twist_angle)) return "twist: not finite";
  if (!(job.soft >= 0.0 && job.soft <= 1.0)) return "soft: must be in [0, 1], got " + number(job.soft);
  if (job.stretch && !(job.max_stretch >= 1.0))
    return "maxStretch: must be at least 1 while stretch is on, got " + number(job.max_stretch);
  return {};
}

// Takes the solved world matrices in s.world_out into the joints' channels.
void write_world_out(ComputeContext& c, const ChainData& d, Scratch& s, const TwoBoneIkOutput& out, double blend) {
  namespace a = two_bone_attr;
  s.local_out.resize(d.count);
  ChainWorldToLocalJob to_local;
  to_local.world = s.world_out;
  to_local.parent_world = d.parent;
  to_local.local = s.local_out;
  if (!to_local.run()) return write_fallback(c, d, "the solve gave a singular joint");
  write_solved(c, d, s.local_out, blend);
  c.output(a::kOutStretch) = out.stretch;
  c.output(a::kReached) = out.reached;
}

// A world matrix with `linear` and `position`.
Mat4 world_of(const math::Mat3& linear, const Vec3& position) {
  Mat4 m = Mat4::Identity();
  m.topLeftCorner<3, 3>() = linear;
  m.topRightCorner<3, 1>() = position;
  return m;
}

// The solver's world turns applied to the first two joints of the rest
// chain in s.world (start_turn about the start joint, then mid_turn about
// the mid joint, the bones stretched), written to s.world_out (sized
// `count`), and where the third joint's position lands.
struct Turns {
  math::Mat3 r0, r01;
  Vec3 third;
};
Turns solved_upper_lower(Scratch& s, const TwoBoneIkOutput& out, std::size_t count) {
  Turns t;
  t.r0 = out.start_turn.normalized().toRotationMatrix();
  t.r01 = t.r0 * out.mid_turn.normalized().toRotationMatrix();
  const Vec3 p0 = translation_of(s.world[0]), p1 = translation_of(s.world[1]), p2 = translation_of(s.world[2]);
  s.world_out.resize(count);
  s.world_out[0] = world_of(t.r0 * s.world[0].topLeftCorner<3, 3>(), p0);
  s.world_out[1] = world_of(t.r01 * s.world[1].topLeftCorner<3, 3>(), p0 + t.r0 * (p1 - p0) * out.stretch);
  t.third = translation_of(s.world_out[1]) + t.r01 * (p2 - p1) * out.stretch;
  return t;
}

void compute_two_bone(ComputeContext& c) {
  namespace a = two_bone_attr;
  Scratch& s = scratch();
  const ChainData d = chain_data(c);
  c.output(a::kOutStretch) = 1.0;
  c.output(a::kReached) = false;
  std::string problem = read_chain(c, d, kIkTwoBoneType, 3, 3, s);

  TwoBoneIkJob job;
  TwoBoneIkOutput out;
  if (problem.empty()) {
    job.start_world = &s.world[0];
    job.mid_world = &s.world[1];
    job.end_world = &s.world[2];
    job.output = &out;
    problem = read_two_bone(c, translation_of(s.world[0]), job);
    if (problem.empty() && !job.run()) problem = "the two-bone solve refused its inputs";  // a check is missing
  }
  if (!problem.empty()) return write_fallback(c, d, std::move(problem));

  // The solved world matrices: the solver's world turns applied to the rest
  // chain (start_turn about the start joint, mid_turn about the mid joint,
  // the bones stretched), then taken into each joint's parent. Exact for any
  // scale: a joint under a non-uniformly scaled parent gets the shear that
  // keeps its bones rigid (applying the corrections in each joint's own
  // frame would miss by the parent's non-uniformity, ~1e-6 on joints read
  // from single-precision files).
  const Turns t = solved_upper_lower(s, out, 3);
  s.world_out[2] = world_of(t.r01 * s.world[2].topLeftCorner<3, 3>(), t.third);
  write_world_out(c, d, s, out, 1.0);  // the kernel applied the weight
}

// ikThreeBone (nodes.h): a two-bone solve on a chain of four joints.
void compute_three_bone(ComputeContext& c) {
  namespace a = two_bone_attr;
  Scratch& s = scratch();
  const ChainData d = chain_data(c);
  c.output(a::kOutStretch) = 1.0;
  c.output(a::kReached) = false;
  std::string problem = read_chain(c, d, kIkThreeBoneType, 4, 4, s);
  const bool pinned = c.get<std::int64_t>(three_bone_attr::kHockMode) == 1;
  const Mat4 hock = c.get<Mat4>(three_bone_attr::kHockMatrix);

  TwoBoneIkJob job;
  TwoBoneIkOutput out;
  Mat4 virtual_mid = Mat4::Identity();
  const Vec3 p0 = problem.empty() ? translation_of(s.world[0]) : Vec3::Zero();
  if (problem.empty()) {
    const Vec3 p1 = translation_of(s.world[1]), p2 = translation_of(s.world[2]), p3 = translation_of(s.world[3]);
    // spring: the first and third bones turn together (a pantograph), so
    // the chain is a two-bone one of (upper + hock bone, lower) whose middle
    // stands where the first and third bones meet, in the mid joint's frame.
    virtual_mid = s.world[1];
    virtual_mid.topRightCorner<3, 1>() = p0 + (p1 - p0) + (p3 - p2);
    job.start_world = &s.world[0];
    job.mid_world = pinned ? &s.world[1] : &virtual_mid;
    job.end_world = pinned ? &s.world[2] : &s.world[3];
    job.output = &out;
    problem = read_two_bone(c, p0, job);
    if (problem.empty() && pinned) {
      if (std::string bad = matrix_problem(hock); !bad.empty())
        problem = "hockMatrix: " + bad;
      else
        job.target = translation_of(hock);  // the hock joint reaches the hock matrix
    }
    const double weight = c.get<double>(ik_attr::kWeight);
    if (problem.empty()) {
      job.weight = 1.0;  // blended in the channels, as the hock's own turn is
      if (!job.run()) problem = "the two-bone solve refused its inputs";  // a check is missing
    }
    if (problem.empty()) {
      const Turns t = solved_upper_lower(s, out, 4);
      if (pinned) {
        s.world_out[2] = world_of(hock.topLeftCorner<3, 3>(), t.third);
        s.world_out[3] = s.world_out[2] * math::affine_inverse(s.world[2]) * s.world[3];
      } else {
        s.world_out[2] = world_of(t.r0 * s.world[2].topLeftCorner<3, 3>(), t.third);
        s.world_out[3] = world_of(t.r0 * s.world[3].topLeftCorner<3, 3>(), t.third + t.r0 * (p3 - p2) * out.stretch);
      }
      return write_world_out(c, d, s, out, weight);
    }
  }
  write_fallback(c, d, std::move(problem));
}

// ---- ikFabrik / ikCcd ----

// Radians of a limit angle given in degrees; values within the valid range
// [-180, 180] map into [-pi, pi] exactly (180 * kDegToRad may round past pi).
double limit_radians(double degrees) {
  const double r = degrees * math::kDegToRad;
  return (degrees >= -180.0 && degrees <= 180.0) ? std::clamp(r, -math::kPi, math::kPi) : r;
}

// Reads the limit arrays into s.limits (empty when limitType is empty).
std::string read_limits(const ComputeContext& c, std::size_t count, Scratch& s) {
  namespace a = chain_attr;
  const auto& types = c.get<std::vector<std::int64_t>>(a::kLimitType);
  const auto& axes = c.get<std::vector<Vec3>>(a::kLimitAxis);
  const auto& references = c.get<std::vector<Vec3>>(a::kLimitReference);
  const auto& mins = c.get<std::vector<double>>(a::kLimitMinAngle);
  const auto& maxs = c.get<std::vector<double>>(a::kLimitMaxAngle);
  const auto& halves = c.get<std::vector<double>>(a::kLimitHalfAngle);
  s.limits.clear();
  if (types.empty()) return {};
  s.limits.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    JointLimit& limit = s.limits[i];
    const std::int64_t kind = std::clamp<std::int64_t>(element_or(types, i, std::int64_t{0}), 0, 2);
    limit.kind = static_cast<LimitKind>(kind);
    if (limit.kind == LimitKind::kNone) continue;
    limit.axis = element_or(axes, i, Vec3(Vec3::UnitZ()));
    if (std::string p = unit_problem(indexed("limitAxis", i).c_str(), limit.axis); !p.empty()) return p;
    if (limit.kind == LimitKind::kHinge) {
      limit.reference = element_or(references, i, Vec3(Vec3::UnitX()));
      if (std::string p = unit_problem(indexed("limitReference", i).c_str(), limit.reference); !p.empty()) return p;
      if (!(std::abs(limit.axis.dot(limit.reference)) <= kUnitTolerance)) {
        return indexed("limitReference", i) + ": not perpendicular to " + indexed("limitAxis", i);
      }
      const double lo = element_or(mins, i, -180.0);
      const double hi = element_or(maxs, i, 180.0);
      if (!(lo >= -180.0 && hi <= 180.0 && lo <= hi)) {
        return indexed("limitMinAngle", i) + ", " + indexed("limitMaxAngle", i) +
               ": the hinge range must be -180 <= min <= max <= 180, got " + number(lo) + ", " + number(hi);
      }
      limit.min_angle = limit_radians(lo);
      limit.max_angle = limit_radians(hi);
    } else {
      const double half = element_or(halves, i, 180.0);
      if (!(half >= 0.0 && half <= 180.0)) {
        return indexed("limitHalfAngle", i) + ": the cone half angle must be in [0, 180], got " + number(half);
      }
      limit.half_angle = limit_radians(half);
    }
    if (const char* why = joint_limit_error(limit)) return "limit of joint " + std::to_string(i) + ": " + why;
  }
  return {};
}

template <typename Job>
void compute_chain(ComputeContext& c, const char* type) {
  namespace a = chain_attr;
  Scratch& s = scratch();
  const ChainData d = chain_data(c);
  c.output(a::kIterations) = std::int64_t{0};
  c.output(a::kEndDistance) = 0.0;
  c.output(a::kReached) = false;
  std::string problem = read_chain(c, d, type, 2, std::size_t(-1), s);

  Job job;
  IkChainResult result;
  if (problem.empty()) {
    job.world = s.world;
    job.target = translation_of(c.get<Mat4>(a::kTargetMatrix));
    job.tolerance = c.get<double>(a::kTolerance);
    const std::int64_t iterations = c.get<std::int64_t>(a::kMaxIterations);
    job.max_iterations = static_cast<int>(std::clamp<std::int64_t>(iterations, -1, INT_MAX));
    job.parent_world = d.parent;
    s.positions.resize(d.count);
    s.corrections.resize(d.count);
    job.positions = s.positions;
    job.corrections = s.corrections;
    job.result = &result;
    if (!detail::all_finite(job.target)) {
      problem = "targetMatrix: the target position is not finite";
    } else if (!(job.tolerance >= 0.0 && std::isfinite(job.tolerance))) {
      problem = "tolerance: must be finite and >= 0, got " + number(job.tolerance);
    } else if (iterations < 0) {
      problem = "maxIterations: must be >= 0, got " + std::to_string(iterations);
    } else if (problem = read_limits(c, d.count, s); !problem.empty()) {
    } else {
      job.limits = s.limits;
      if (!job.run()) problem = std::string(type) + ": the solve refused its inputs";  // a check above is missing
    }
  }
  if (!problem.empty()) return write_fallback(c, d, std::move(problem));

  const double weight = c.get<double>(ik_attr::kWeight);
  if (weight < 1.0) {
    for (Quat& q : s.corrections) q = Quat::Identity().slerp(weight, q);
  }
  s.local_out.resize(d.count);
  ChainCorrectionJob apply;
  apply.local = s.local;
  apply.corrections = s.corrections;
  apply.parent_world = d.parent;
  apply.local_out = s.local_out;
  if (!apply.run()) return write_fallback(c, d, std::string(type) + ": the corrections did not apply");
  write_solved(c, d, s.local_out, 1.0);
  c.output(a::kIterations) = std::int64_t{result.iterations};
  c.output(a::kEndDistance) = result.error;
  c.output(a::kReached) = result.reached;
}

void compute_fabrik(ComputeContext& c) { compute_chain<FabrikJob>(c, kIkFabrikType); }
void compute_ccd(ComputeContext& c) { compute_chain<CcdJob>(c, kIkCcdType); }

// ---- ikSpline ----

void compute_spline(ComputeContext& c) {
  namespace a = spline_attr;
  Scratch& s = scratch();
  const ChainData d = chain_data(c);
  c.output(a::kCurveLength) = 0.0;
  c.output(a::kChainLength) = 0.0;
  c.output(a::kOverran) = false;
  std::string problem = read_chain(c, d, kIkSplineType, 2, std::size_t(-1), s);

  SplineIkJob job;
  SplineIkResult result;
  if (problem.empty()) {
    const auto& controls = c.get<std::vector<Mat4>>(a::kControlMatrix);
    s.points.resize(controls.size());
    for (std::size_t i = 0; i < controls.size(); ++i) s.points[i] = translation_of(controls[i]);
    const std::int64_t samples = c.get<std::int64_t>(a::kArcLengthSamples);
    job.control_points = s.points;
    job.world = s.world;
    job.aim_axis = c.get<Vec3>(a::kAimAxis);
    job.up_axis = c.get<Vec3>(a::kUpAxis);
    job.up_vector = c.get<Vec3>(a::kWorldUpVector);
    job.start_twist = math::to_radians(c.get<double>(a::kStartTwist));
    job.end_twist = math::to_radians(c.get<double>(a::kEndTwist));
    job.stretch = c.get<bool>(a::kStretch);
    job.squash = c.get<bool>(a::kSquash);
    job.result = &result;
    if (controls.size() < 2) {
      problem = "controlMatrix: ikSpline needs at least 2 control points, got " + std::to_string(controls.size());
    } else if (auto bad = std::find_if(s.points.begin(), s.points.end(),
                                       [](const Vec3& p) { return !detail::all_finite(p); });
               bad != s.points.end()) {
      problem = indexed("controlMatrix", static_cast<std::size_t>(bad - s.points.begin())) +
                ": the control point is not finite";
    } else if (samples == 1 || samples < 0 || samples > kMaxArcLengthSamples) {
      problem = "arcLengthSamples: must be 0 (automatic) or 2.." + std::to_string(kMaxArcLengthSamples) + ", got " +
                std::to_string(samples);
    } else if (problem = unit_problem("aimAxis", job.aim_axis); !problem.empty()) {
    } else if (problem = unit_problem("upAxis", job.up_axis); !problem.empty()) {
    } else if (!(std::abs(job.aim_axis.dot(job.up_axis)) <= kUnitTolerance)) {
      problem = "upAxis: not perpendicular to aimAxis";
    } else if (!detail::all_finite(job.up_vector) || !(job.up_vector.norm() > detail::kTinyLength)) {
      problem = "worldUpVector: must be finite and not zero";
    } else if (!std::isfinite(job.start_twist)) {
      problem = "startTwist: not finite";
    } else if (!std::isfinite(job.end_twist)) {
      problem = "endTwist: not finite";
    } else {
      const std::int64_t automatic = std::min<std::int64_t>(
          kMaxArcLengthSamples, kSamplesPerSpan * static_cast<std::int64_t>(controls.size() - 1) + 1);
      const std::int64_t count = samples != 0 ? samples : automatic;
      s.arc_lengths.resize(static_cast<std::size_t>(count));
      s.world_out.resize(d.count);
      job.arc_lengths = s.arc_lengths;
      job.world_out = s.world_out;
      if (!job.run()) problem = "ikSpline: the solve refused its inputs";  // a check above is missing
    }
  }
  if (problem.empty()) {
    s.local_out.resize(d.count);
    ChainWorldToLocalJob to_local;
    to_local.world = s.world_out;
    to_local.parent_world = d.parent;
    to_local.local = s.local_out;
    if (!to_local.run()) problem = "the solved chain is singular (a curve of zero length with stretch on?)";
  }
  if (!problem.empty()) return write_fallback(c, d, std::move(problem));
  write_solved(c, d, s.local_out, c.get<double>(ik_attr::kWeight));
  c.output(a::kCurveLength) = result.curve_length;
  c.output(a::kChainLength) = result.chain_length;
  c.output(a::kOverran) = result.overran;
}

}  // namespace

Status register_ik_types(graph::Registry& registry) {
  graph::NodeTypeSpec two_bone;
  two_bone.name = kIkTwoBoneType;
  two_bone.description =
      "Two-bone analytic IK (start, mid, end): pole vector or plane, twist, soft IK, stretch with a limit";
  two_bone.compute = compute_two_bone;
  two_bone.attrs = chain_attrs();
  two_bone.attrs.push_back(input("targetMatrix", kMatrixType, Mat4(Mat4::Identity())));
  two_bone.attrs.push_back(enum_input("poleMode", {ValueType::kEnum, false}, std::int64_t{0},
                                      {"poleVector", "planeNormal"}));
  two_bone.attrs.push_back(input("poleVector", kDouble3Type, Vec3(Vec3::UnitY()), graph::kKeyable));
  two_bone.attrs.push_back(input("usePoleMatrix", kBoolType, false));
  two_bone.attrs.push_back(input("poleMatrix", kMatrixType, Mat4(Mat4::Identity())));
  two_bone.attrs.push_back(input("midAxis", kDouble3Type, Vec3(Vec3::UnitZ())));
  two_bone.attrs.push_back(input("twist", kDoubleType, 0.0, graph::kKeyable | graph::kAngle));
  two_bone.attrs.push_back(input("soft", kDoubleType, 0.0, graph::kKeyable));
  two_bone.attrs.push_back(input("stretch", kBoolType, false, graph::kKeyable));
  two_bone.attrs.push_back(
      input("maxStretch", kDoubleType, std::numeric_limits<double>::infinity(), graph::kKeyable));
  two_bone.attrs.push_back(output("outStretch", kDoubleType));
  two_bone.attrs.push_back(output("reached", kBoolType));

  graph::NodeTypeSpec three_bone;
  three_bone.name = kIkThreeBoneType;
  three_bone.description =
      "Two-bone IK on a leg of three segments (upper, lower, hock, foot): the hock bone turns with the upper one "
      "(spring) or takes the hock matrix's orientation (pinned)";
  three_bone.compute = compute_three_bone;
  three_bone.attrs = two_bone.attrs;
  three_bone.attrs.push_back(enum_input("hockMode", {ValueType::kEnum, false}, std::int64_t{0}, {"spring", "pinned"}));
  three_bone.attrs.push_back(input("hockMatrix", kMatrixType, Mat4(Mat4::Identity())));

  auto chain_spec = [](const char* name, const char* description, graph::ComputeFn compute) {
    graph::NodeTypeSpec spec;
    spec.name = name;
    spec.description = description;
    spec.compute = compute;
    spec.attrs = chain_attrs();
    spec.attrs.push_back(input("targetMatrix", kMatrixType, Mat4(Mat4::Identity())));
    spec.attrs.push_back(input("tolerance", kDoubleType, 1e-6));
    spec.attrs.push_back(input("maxIterations", kIntType, std::int64_t{64}));
    spec.attrs.push_back(enum_input("limitType", {ValueType::kEnum, true}, std::vector<std::int64_t>{},
                                    {"none", "hinge", "cone"}));
    spec.attrs.push_back(input("limitAxis", kDouble3Array, std::vector<Vec3>{}));
    spec.attrs.push_back(input("limitReference", kDouble3Array, std::vector<Vec3>{}));
    spec.attrs.push_back(input("limitMinAngle", kDoubleArray, std::vector<double>{}, graph::kAngle));
    spec.attrs.push_back(input("limitMaxAngle", kDoubleArray, std::vector<double>{}, graph::kAngle));
    spec.attrs.push_back(input("limitHalfAngle", kDoubleArray, std::vector<double>{}, graph::kAngle));
    spec.attrs.push_back(output("iterations", kIntType));
    spec.attrs.push_back(output("endDistance", kDoubleType));
    spec.attrs.push_back(output("reached", kBoolType));
    return spec;
  };
  graph::NodeTypeSpec fabrik = chain_spec(
      kIkFabrikType, "N-bone FABRIK IK with tolerance, iteration limit and optional hinge/cone limits", compute_fabrik);
  graph::NodeTypeSpec ccd = chain_spec(
      kIkCcdType, "N-bone CCD IK with tolerance, iteration limit and optional hinge/cone limits", compute_ccd);

  graph::NodeTypeSpec spline;
  spline.name = kIkSplineType;
  spline.description =
      "Spline IK: joints along the B-spline of the control points, by arc length, optional stretch/squash, twist";
  spline.compute = compute_spline;
  spline.attrs = chain_attrs();
  spline.attrs.push_back(input("controlMatrix", kMatrixArray, std::vector<Mat4>{}));
  spline.attrs.push_back(input("aimAxis", kDouble3Type, Vec3(Vec3::UnitX())));
  spline.attrs.push_back(input("upAxis", kDouble3Type, Vec3(Vec3::UnitY())));
  spline.attrs.push_back(input("worldUpVector", kDouble3Type, Vec3(Vec3::UnitY())));
  spline.attrs.push_back(input("startTwist", kDoubleType, 0.0, graph::kKeyable | graph::kAngle));
  spline.attrs.push_back(input("endTwist", kDoubleType, 0.0, graph::kKeyable | graph::kAngle));
  spline.attrs.push_back(input("stretch", kBoolType, false, graph::kKeyable));
  spline.attrs.push_back(input("squash", kBoolType, false, graph::kKeyable));
  spline.attrs.push_back(input("arcLengthSamples", kIntType, std::int64_t{0}));
  spline.attrs.push_back(output("curveLength", kDoubleType));
  spline.attrs.push_back(output("chainLength", kDoubleType));
  spline.attrs.push_back(output("overran", kBoolType));

  for (graph::NodeTypeSpec* spec : {&two_bone, &three_bone, &fabrik, &ccd, &spline}) {
    if (Status s = registry.add(finish(std::move(*spec))); !s) return s;
  }
  return Status::ok();
}

}  // namespace rigel::ops::ik
