#include "rigel/scene/transform_types.h"

#include <algorithm>

#include "rigel/graph/graph.h"
#include "rigel/math/transform.h"
#include "rigel/scene/materials.h"
#include "rigel/scene/scene_options.h"

namespace rigel::scene {
namespace {

using graph::AttrSpec;
using graph::AttrType;
using graph::ComputeContext;
using graph::Value;
using graph::ValueType;
using math::Mat4;
using math::Quat;
using math::Vec3;

constexpr AttrType kDouble3{ValueType::kDouble3, false};
constexpr AttrType kMatrixType{ValueType::kMatrix, false};

const std::vector<std::string> kLocalOutputs = {"matrix", "worldMatrix"};

AttrSpec channel(std::string name, Value value, std::uint32_t extra = 0) {
  AttrSpec spec;
  spec.name = std::move(name);
  spec.type = kDouble3;
  spec.default_value = std::move(value);
  spec.flags = graph::kInput | graph::kStorable | extra;
  spec.affects = kLocalOutputs;
  return spec;
}

AttrSpec input(std::string name, AttrType type, Value value, std::uint32_t extra = 0,
               std::vector<std::string> affects = {}) {
  AttrSpec spec;
  spec.name = std::move(name);
  spec.type = type;
  spec.default_value = std::move(value);
  spec.flags = graph::kInput | graph::kStorable | extra;
  spec.affects = std::move(affects);
  return spec;
}

AttrSpec output(std::string name) {
  AttrSpec spec;
  spec.name = std::move(name);
  spec.type = kMatrixType;
  spec.flags = graph::kOutput | graph::kHidden;
  return spec;
}

std::vector<AttrSpec> transform_attrs() {
  const Vec3 zero = Vec3::Zero();
  AttrSpec rotate_order = input("rotateOrder", {ValueType::kEnum, false}, std::int64_t{0}, graph::kKeyable, kLocalOutputs);
  rotate_order.enum_names = {"xyz", "yzx", "zxy", "xzy", "yxz", "zyx"};
  AttrSpec rotate_mode = input("rotateMode", {ValueType::kEnum, false}, std::int64_t{0}, 0, kLocalOutputs);
  rotate_mode.enum_names = {"euler", "quaternion"};
  std::vector<AttrSpec> attrs = {
      channel("translate", zero, graph::kKeyable),
      channel("rotate", zero, graph::kKeyable | graph::kAngle),
      rotate_order,
      rotate_mode,
      input("rotateQuaternion", {ValueType::kQuat, false}, Quat(Quat::Identity()), graph::kKeyable, kLocalOutputs),
      channel("scale", Vec3(Vec3::Ones()), graph::kKeyable),
      channel("shear", zero),
      channel("rotateAxis", zero, graph::kAngle),
      channel("rotatePivot", zero),
      channel("rotatePivotTranslate", zero),
      channel("scalePivot", zero),
      channel("scalePivotTranslate", zero),
      input("offsetParentMatrix", kMatrixType, Mat4(Mat4::Identity()), 0, {"worldMatrix"}),
      // Fed by the parent's worldMatrix; stored (when not identity) only on a
      // root whose parentMatrix was set directly.
      input("parentMatrix", kMatrixType, Mat4(Mat4::Identity()), graph::kHidden, {"worldMatrix"}),
      input("visibility", {ValueType::kBool, false}, true, graph::kKeyable),
      output("matrix"),
      output("worldMatrix"),
  };
  return attrs;
}

// An enum fed by an int connection may be out of range: clamp it.
template <typename E>
E read_enum(const ComputeContext& c, AttrIndex attr, int count) {
  return static_cast<E>(std::clamp<std::int64_t>(c.get<std::int64_t>(attr), 0, count - 1));
}

math::TransformParts read_parts(const ComputeContext& c) {
  math::TransformParts p;
  p.translate = c.get<Vec3>(xform::kTranslate);
  p.rotate = math::to_radians(c.get<Vec3>(xform::kRotate));
  p.rotate_order = read_enum<math::RotateOrder>(c, xform::kRotateOrder, math::kRotateOrderCount);
  p.rotate_mode = read_enum<math::RotateMode>(c, xform::kRotateMode, 2);
  p.rotate_quaternion = c.get<Quat>(xform::kRotateQuaternion);
  p.scale = c.get<Vec3>(xform::kScale);
  p.shear = c.get<Vec3>(xform::kShear);
  p.rotate_axis = math::to_radians(c.get<Vec3>(xform::kRotateAxis));
  p.rotate_pivot = c.get<Vec3>(xform::kRotatePivot);
  p.rotate_pivot_translate = c.get<Vec3>(xform::kRotatePivotTranslate);
  p.scale_pivot = c.get<Vec3>(xform::kScalePivot);
  p.scale_pivot_translate = c.get<Vec3>(xform::kScalePivotTranslate);
  return p;
}

// The world matrix from the stored local matrix. When only the parent moved
// (the usual case while posing), the local matrix is clean and is not
// composed again: that is most of a hierarchy's evaluation cost.
void write_world(ComputeContext& c) {
  const Mat4& parent = c.get<Mat4>(xform::kParentMatrix);
  const Mat4& offset = c.get<Mat4>(xform::kOffsetParentMatrix);
  const Mat4& local = c.get<Mat4>(xform::kMatrix);
  Mat4& world = std::get<Mat4>(c.output(xform::kWorldMatrix));
  if (offset == Mat4::Identity()) world.noalias() = parent * local;
  else world = math::world_matrix(parent, offset, local);
}

void compute_transform(ComputeContext& c) {
  if (c.node().is_dirty(xform::kMatrix)) std::get<Mat4>(c.output(xform::kMatrix)) = math::compose(read_parts(c));
  write_world(c);
}

void compute_joint(ComputeContext& c) {
  if (c.node().is_dirty(xform::kMatrix)) {
    math::TransformParts parts = read_parts(c);
    parts.joint_orient = math::to_radians(c.get<Vec3>(joint_attr::kJointOrient));
    std::get<Mat4>(c.output(xform::kMatrix)) = math::compose(parts);
  }
  write_world(c);
}

graph::NodeTypeSpec transform_spec(std::string name, std::string description, graph::ComputeFn compute) {
  graph::NodeTypeSpec spec;
  spec.name = std::move(name);
  spec.description = std::move(description);
  spec.attrs = transform_attrs();
  spec.compute = compute;
  spec.parent_input = "parentMatrix";
  spec.world_output = "worldMatrix";
  return spec;
}

}  // namespace

Status register_scene_types(graph::Registry& registry) {
  graph::NodeTypeSpec transform = transform_spec(kTransformType, "A group: translate, rotate, scale in a hierarchy", compute_transform);

  graph::NodeTypeSpec joint = transform_spec(kJointType, "A skeleton joint: a transform with a joint orient", compute_joint);
  joint.attrs.push_back(channel("jointOrient", Vec3(Vec3::Zero()), graph::kAngle));
  joint.attrs.push_back(input("radius", {ValueType::kDouble, false}, 1.0));

  graph::NodeTypeSpec control = transform_spec(kControlType, "An animator's control: a transform drawn as a curve shape", compute_transform);
  control.attrs.push_back(input("shapePoints", {ValueType::kDouble3, true}, std::vector<Vec3>{}));
  control.attrs.push_back(input("shapeClosed", {ValueType::kBool, false}, true));
  control.attrs.push_back(input("shapeColor", kDouble3, Vec3(1.0, 1.0, 0.0)));

  graph::NodeTypeSpec locator = transform_spec(kLocatorType, "A locator: a transform drawn as a cross", compute_transform);
  locator.attrs.push_back(input("localScale", kDouble3, Vec3(Vec3::Ones())));

  graph::NodeTypeSpec mesh = transform_spec(kMeshType, "A triangle mesh with its transform", compute_transform);
  mesh.attrs.push_back(input("points", {ValueType::kDouble3, true}, std::vector<Vec3>{}));
  mesh.attrs.push_back(input("normals", {ValueType::kDouble3, true}, std::vector<Vec3>{}));
  mesh.attrs.push_back(input("triangles", {ValueType::kInt, true}, std::vector<std::int64_t>{}));
  add_mesh_look_attrs(mesh);  // uv0, uv1, colors, material (materials.h)

  for (graph::NodeTypeSpec* spec : {&transform, &joint, &control, &locator, &mesh}) {
    if (Status s = registry.add(std::move(*spec)); !s) return s;
  }
  if (Status s = register_material_types(registry); !s) return s;
  return register_scene_option_types(registry);
}

std::shared_ptr<const graph::Registry> default_registry() {
  static const std::shared_ptr<const graph::Registry> registry = [] {
    auto r = std::make_shared<graph::Registry>();
    Status s = register_scene_types(*r);
    assert(s.is_ok() && "the built-in scene types must register");
    (void)s;
    return r;
  }();
  return registry;
}

bool is_transform_type(const graph::NodeType& type) {
  return type.parent_input() == xform::kParentMatrix && type.world_output() == xform::kWorldMatrix &&
         type.attr_count() >= xform::kCount && type.attr(xform::kTranslate).name == "translate";
}

bool xform::is_quaternion_mode(const graph::Node& node) {
  const auto* mode = std::get_if<std::int64_t>(&node.value(kRotateMode));
  return mode && *mode == kQuaternionMode;
}

AttrIndex xform::rotation_channel(const graph::Node& node) {
  return is_quaternion_mode(node) ? kRotateQuaternion : kRotate;
}

}  // namespace rigel::scene
