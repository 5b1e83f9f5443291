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
  if (!is_transform(node)) return error(ErrorCode::kInvalidArgument, "channels for a world matrix: not a transform");
  const graph::Node& n = *graph_.node(node);
  for (AttrIndex a : {xform::kRotateAxis, xform::kRotatePivot, xform::kRotatePivotTranslate, xform::kScalePivot,
                      xform::kScalePivotTranslate}) {
    if (!std::get<math::Vec3>(n.value(a)).isZero())
      return error(ErrorCode::kInvalidArgument, "'" + n.name() + "': " + n.type().attr(a).name + " must be zero");
  }
  Result<graph::Value> parent_world = graph_.evaluate(graph::Plug{node, xform::kParentMatrix, -1});
  if (!parent_world) return parent_world.status();
  const Mat4 above = std::get<Mat4>(*parent_world) * std::get<Mat4>(n.value(xform::kOffsetParentMatrix));
  if (!(std::abs(above.topLeftCorner<3, 3>().determinant()) > 1e-12))
    return error(ErrorCode::kInvalidArgument, "'" + n.name() + "': its parent space is singular (zero scale?)");
  Mat4 local = math::affine_inverse(above) * world;
  // The joint orient stays; the rotation absorbs the difference.
  const AttrIndex jo = n.type().attr_find("jointOrient");
  if (jo != graph::kNoAttr) {
    Mat4 orient = math::rotation_matrix(
        math::euler_to_quat(math::to_radians(std::get<math::Vec3>(n.value(jo))), math::RotateOrder::kXYZ));
    Mat4 t = local;
    t.block<3, 1>(0, 3).setZero();
    Mat4 rest = orient.transpose() * t;
    rest.block<3, 1>(0, 3) = local.block<3, 1>(0, 3);
    local = rest;
  }
  const auto order = static_cast<math::RotateOrder>(std::get<std::int64_t>(n.value(xform::kRotateOrder)));
  const math::TransformParts parts = math::decompose_to_parts(local, order);
  LocalChannels out;
  out.translate = parts.translate;
  out.scale = parts.scale;
  out.shear = parts.shear;
  if (xform::is_quaternion_mode(n)) {
    out.rotation_attr = xform::kRotateQuaternion;
    out.rotation = math::euler_to_quat(parts.rotate, order);
  } else {
    out.rotation_attr = xform::kRotate;
    out.rotation = math::to_degrees(parts.rotate);
  }
  return out;
}

}  // namespace rigel::scene
