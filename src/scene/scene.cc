#include "rigel/scene/scene.h"

#include <algorithm>
#include <cmath>

#include "rigel/math/transform.h"

namespace rigel::scene {

Scene::Scene() : Scene(default_registry()) {}
Scene::Scene(std::shared_ptr<const graph::Registry> registry) : graph_(std::move(registry)) {}

Result<NodeId> Scene::create(std::string_view type, std::string_view name, NodeId parent) {
  graph::Transaction transaction(graph_, "create " + std::string(name));
  Result<NodeId> id = graph_.create_node(type, name);
  if (!id) return id;
  if (parent.is_valid()) {
    if (Status s = graph_.set_parent(*id, parent); !s) {
      transaction.rollback();
      return s;
    }
  }
  return id;
}

bool Scene::is_transform(NodeId id) const {
  const graph::Node* n = graph_.node(id);
  return n && is_transform_type(n->type());
}

std::vector<NodeId> Scene::roots() const {
  std::vector<NodeId> result;
  for (NodeId id : graph_.nodes()) {
    if (is_transform(id) && !graph_.parent(id).is_valid()) result.push_back(id);
  }
  return result;
}

std::vector<NodeId> Scene::hierarchy() const {
  std::vector<NodeId> result;
  std::vector<NodeId> stack;
  std::vector<NodeId> top = roots();
  stack.assign(top.rbegin(), top.rend());
  while (!stack.empty()) {
    NodeId id = stack.back();
    stack.pop_back();
    result.push_back(id);
    std::vector<NodeId> kids = graph_.children(id);
    stack.insert(stack.end(), kids.rbegin(), kids.rend());
  }
  return result;
}

int Scene::depth(NodeId id) const {
  int d = 0;
  for (NodeId p = graph_.parent(id); p.is_valid(); p = graph_.parent(p)) ++d;
  return d;
}

double Scene::frame() const {
  const double f = graph_.time() * graph_.fps();
  const double whole = std::round(f);
  return std::abs(f - whole) <= 1e-9 * std::max(1.0, std::abs(f)) ? whole : f;
}

Mat4 Scene::local_matrix(NodeId id) {
  if (!is_transform(id)) return Mat4::Identity();
  return std::get<Mat4>(graph_.evaluate(id, xform::kMatrix));
}
Mat4 Scene::world_matrix(NodeId id) {
  if (!is_transform(id)) return Mat4::Identity();
  return std::get<Mat4>(graph_.evaluate(id, xform::kWorldMatrix));
}

Status Scene::reparent(NodeId child, NodeId parent, bool keep_world) {
  if (!is_transform(child)) return error(ErrorCode::kInvalidArgument, "reparent: the child is not a transform");
  if (parent.is_valid() && !is_transform(parent)) return error(ErrorCode::kInvalidArgument, "reparent: the parent is not a transform");
  if (!keep_world) return graph_.set_parent(child, parent);
  // Already under `parent` (or already a root): a no-op, as set_parent() is.
  // Decomposing and rewriting the channels anyway would record an undo step
  // and drift them by rounding on every call.
  const bool in_place = parent.is_valid() ? graph_.parent(child) == parent
                                          : !graph_.source(graph::Plug{child, xform::kParentMatrix, -1}).has_value();
  if (in_place) return Status::ok();

  const Mat4 world = world_matrix(child);
  graph::Transaction transaction(graph_, "reparent " + graph_.node(child)->name());
  Status s = graph_.set_parent(child, parent);
  Result<LocalChannels> channels = s ? channels_for_world(child, world) : Result<LocalChannels>(s);
  if (!channels) {
    transaction.rollback();
    return channels.status().with_context("reparent '" + graph_.node(child)->name() + "' keeping its world position");
  }
  auto set = [&](AttrIndex a, graph::Value v) { return graph_.set_value(graph::Plug{child, a, -1}, std::move(v)); };
  s = set(xform::kTranslate, channels->translate);
  if (s) s = set(xform::kScale, channels->scale);
  if (s) s = set(xform::kShear, channels->shear);
  if (s) s = set(channels->rotation_attr, channels->rotation);
  if (!s) transaction.rollback();
  return s;
}

Result<Scene::LocalChannels> Scene::channels_for_world(NodeId node, const Mat4& world) {
  return channels_for_world(node, world, ChannelFit{});
}

namespace {

using math::Mat3;
using math::Quat;
using math::Vec3;

// The node's jointOrient attribute (kNoAttr for types without one). A
// drag fits every control it moves: the scene's own types answer without
// the name lookup (a joint holds it at joint_attr::kJointOrient).
AttrIndex joint_orient_attr(const graph::Node& n) {
  const graph::NodeType& type = n.type();
  if (type.attr_count() > joint_attr::kJointOrient && type.attr(joint_attr::kJointOrient).name == "jointOrient")
    return joint_attr::kJointOrient;
  const std::string& name = type.name();
  if (name == kControlType || name == kTransformType || name == kLocatorType || name == kMeshType) return graph::kNoAttr;
  return type.attr_find("jointOrient");
}

// A joint's orient as a matrix (identity for other types).
Mat4 joint_orient_matrix(const graph::Node& n) {
  const AttrIndex jo = joint_orient_attr(n);
  if (jo == graph::kNoAttr) return Mat4::Identity();
  return math::rotation_matrix(math::euler_to_quat(math::to_radians(std::get<Vec3>(n.value(jo))), math::RotateOrder::kXYZ));
}

// The rotation channel's value for the Euler angles `euler` (or, when given,
// `quaternion`), nearest the node's current rotation when asked.
graph::Value rotation_value(const graph::Node& n, const Vec3& euler, const Quat* quaternion, math::RotateOrder order,
                            bool nearest) {
  if (xform::is_quaternion_mode(n)) {
    Quat q = quaternion ? *quaternion : math::euler_to_quat(euler, order);
    if (nearest && q.dot(std::get<Quat>(n.value(xform::kRotateQuaternion))) < 0) q.coeffs() = -q.coeffs();
    return q;
  }
  if (!nearest) return Vec3(math::to_degrees(euler));
  const Vec3 previous = math::to_radians(std::get<Vec3>(n.value(xform::kRotate)));
  return Vec3(math::to_degrees(math::euler_closest(euler, previous, order)));
}

// The whole local matrix decomposed (rotate axis and pivots are zero).
Result<Scene::LocalChannels> fit_full(const graph::Node& n, const Mat4& above, const Mat4& world,
                                      const Scene::ChannelFit& fit) {
  if (!(std::abs(above.topLeftCorner<3, 3>().determinant()) > 1e-12))
    return error(ErrorCode::kInvalidArgument, "'" + n.name() + "': its parent space is singular (zero scale?)");
  Mat4 local = math::affine_inverse(above) * world;
  // The joint orient stays; the rotation absorbs the difference.
  if (joint_orient_attr(n) != graph::kNoAttr) {
    const Mat4 orient = joint_orient_matrix(n);
    Mat4 t = local;
    t.block<3, 1>(0, 3).setZero();
    Mat4 rest = orient.transpose() * t;
    rest.block<3, 1>(0, 3) = local.block<3, 1>(0, 3);
    local = rest;
  }
  const auto order = static_cast<math::RotateOrder>(std::get<std::int64_t>(n.value(xform::kRotateOrder)));
  const math::TransformParts parts = math::decompose_to_parts(local, order);
  Scene::LocalChannels out;
  out.rotation_attr = xform::rotation_channel(n);
  out.translate = parts.translate;
  out.scale = parts.scale;
  out.shear = parts.shear;
  out.rotation = rotation_value(n, parts.rotate, nullptr, order, fit.nearest_rotation);
  return out;
}

// Scale, shear and rotate axis kept: local = T * (pivots) * JO * R * RA * SH * S
// solved for T and R. What a solver writes on every drag: the parent space
// is inverted once as a 3x3 and the translation taken from its origin (the
// difference first, then the product), which rounds less than a product
// with the full affine inverse.
Result<Scene::LocalChannels> fit_keeping(const graph::Node& n, const Mat4& parent_world, const Mat4& world,
                                         const Scene::ChannelFit& fit) {
  const Mat4& offset = std::get<Mat4>(n.value(xform::kOffsetParentMatrix));
  const Mat3 parent_linear = parent_world.topLeftCorner<3, 3>();
  const Mat3 offset_linear = offset.topLeftCorner<3, 3>();
  const Mat3 above = parent_linear * offset_linear;
  if (!(std::abs(above.determinant()) > 1e-12))
    return error(ErrorCode::kInvalidArgument, "'" + n.name() + "': its parent space is singular (zero scale?)");
  const Mat3 inverse = above.inverse();
  const Vec3 origin = parent_linear * Vec3(offset.topRightCorner<3, 1>()) + Vec3(parent_world.topRightCorner<3, 1>());
  const Vec3 translate = inverse * (Vec3(world.topRightCorner<3, 1>()) - origin);
  if (fit.translate_only && std::get<Vec3>(n.value(xform::kRotatePivot)).isZero() &&
      std::get<Vec3>(n.value(xform::kRotatePivotTranslate)).isZero() &&
      std::get<Vec3>(n.value(xform::kScalePivot)).isZero() && std::get<Vec3>(n.value(xform::kScalePivotTranslate)).isZero()) {
    Scene::LocalChannels out;
    out.translate = translate;
    out.rotation_attr = xform::rotation_channel(n);
    out.rotation = n.value(out.rotation_attr);
    out.scale = std::get<Vec3>(n.value(xform::kScale));
    out.shear = std::get<Vec3>(n.value(xform::kShear));
    return out;
  }
  Mat3 rotation = inverse * Mat3(world.topLeftCorner<3, 3>());
  if (joint_orient_attr(n) != graph::kNoAttr)
    rotation = Mat3(joint_orient_matrix(n).topLeftCorner<3, 3>()).transpose() * rotation;

  math::TransformParts kept;
  kept.scale = std::get<Vec3>(n.value(xform::kScale));
  kept.shear = std::get<Vec3>(n.value(xform::kShear));
  kept.rotate_axis = math::to_radians(std::get<Vec3>(n.value(xform::kRotateAxis)));
  if (kept.shear == Vec3::Zero() && kept.rotate_axis == Vec3::Zero()) {
    if ((kept.scale.array() == 0).any())
      return error(ErrorCode::kInvalidArgument, "'" + n.name() + "': its scale is zero, no rotation fits");
    rotation = rotation * kept.scale.cwiseInverse().asDiagonal();  // local = R * S
  } else {
    const Mat3 ss = math::compose(kept).topLeftCorner<3, 3>();
    if (!(std::abs(ss.determinant()) > 0))
      return error(ErrorCode::kInvalidArgument, "'" + n.name() + "': its scale and shear are singular, no rotation fits");
    rotation = rotation * ss.inverse();  // local = R * (RA * SH * S)
  }
  const auto order = static_cast<math::RotateOrder>(std::get<std::int64_t>(n.value(xform::kRotateOrder)));
  Scene::LocalChannels out;
  out.rotation_attr = xform::rotation_channel(n);
  out.exact = (rotation.transpose() * rotation).isIdentity(1e-10);
  out.scale = kept.scale;
  out.shear = kept.shear;
  const Quat quaternion = Quat(rotation).normalized();
  out.rotation = rotation_value(n, math::matrix_to_euler(rotation, order), &quaternion, order, fit.nearest_rotation);
  out.translate = translate;
  math::TransformParts pivots = kept;
  pivots.rotate_pivot = std::get<Vec3>(n.value(xform::kRotatePivot));
  pivots.rotate_pivot_translate = std::get<Vec3>(n.value(xform::kRotatePivotTranslate));
  pivots.scale_pivot = std::get<Vec3>(n.value(xform::kScalePivot));
  pivots.scale_pivot_translate = std::get<Vec3>(n.value(xform::kScalePivotTranslate));
  if (!pivots.rotate_pivot.isZero() || !pivots.rotate_pivot_translate.isZero() || !pivots.scale_pivot.isZero() ||
      !pivots.scale_pivot_translate.isZero()) {
    // The pivots' share of the local translation, for the rotation found.
    const AttrIndex jo = joint_orient_attr(n);
    if (jo != graph::kNoAttr) pivots.joint_orient = math::to_radians(std::get<Vec3>(n.value(jo)));
    pivots.rotate_order = order;
    if (out.rotation_attr == xform::kRotateQuaternion) {
      pivots.rotate_mode = math::RotateMode::kQuaternion;
      pivots.rotate_quaternion = std::get<Quat>(out.rotation);
    } else {
      pivots.rotate = math::to_radians(std::get<Vec3>(out.rotation));
    }
    out.translate -= math::compose(pivots).topRightCorner<3, 1>();
  }
  return out;
}

}  // namespace

Result<Scene::LocalChannels> Scene::channels_for_world(NodeId node, const Mat4& world, const ChannelFit& fit) {
  if (!is_transform(node)) return error(ErrorCode::kInvalidArgument, "channels for a world matrix: not a transform");
  const graph::Node& n = *graph_.node(node);
  if (!fit.keep_scale_shear) {
    for (AttrIndex a : {xform::kRotateAxis, xform::kRotatePivot, xform::kRotatePivotTranslate, xform::kScalePivot,
                        xform::kScalePivotTranslate}) {
      if (!std::get<Vec3>(n.value(a)).isZero())
        return error(ErrorCode::kInvalidArgument, "'" + n.name() + "': " + n.type().attr(a).name + " must be zero");
    }
  }
  Mat4 parent_world;
  if (fit.parent_world) {
    parent_world = *fit.parent_world;
  } else {
    Result<graph::Value> evaluated = graph_.evaluate(graph::Plug{node, xform::kParentMatrix, -1});
    if (!evaluated) return evaluated.status();
    parent_world = std::get<Mat4>(*evaluated);
  }
  if (fit.keep_scale_shear) return fit_keeping(n, parent_world, world, fit);
  return fit_full(n, parent_world * std::get<Mat4>(n.value(xform::kOffsetParentMatrix)), world, fit);
}

}  // namespace rigel::scene
