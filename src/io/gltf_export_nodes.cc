// The glTF exporter: the nodes to export (the scene's hierarchy, parents
// first), their transforms at the export time with shear taken out, and the
// placement of skinned meshes checked.
#include "gltf_exporter.h"

#include <cmath>
#include <unordered_set>

#include "rigel/ops/deform/nodes.h"

namespace rigel::io::gltf_exporter {
namespace {

// The deform skeleton (GltfExportOptions::deform_only): every transform
// whose worldMatrix feeds a skinCluster's jointMatrices, and every mesh;
// in a scene without skins, every joint and mesh.
std::unordered_set<std::uint32_t> deform_set(const Graph& g, const std::vector<NodeId>& hierarchy) {
  std::unordered_set<std::uint32_t> keep;
  bool skinned = false;
  for (NodeId id : g.nodes()) {
    const Node& n = *g.node(id);
    if (n.type().name() != ops::kSkinClusterType) continue;
    skinned = true;
    for (const graph::Connection& c : n.inputs())
      if (c.dst.attr == ops::skin_cluster_attr::kJointMatrices) keep.insert(c.src.node.index);
  }
  for (NodeId id : hierarchy) {
    const std::string& type = g.node(id)->type().name();
    if (type == scene::kMeshType || (!skinned && type == scene::kJointType)) keep.insert(id.index);
  }
  return keep;
}

}  // namespace

Status Exporter::collect_nodes() {
  Result<scene::Skeleton> skeleton = scene::Skeleton::compile(scene_);
  if (!skeleton) return skeleton.status();
  skeleton_ = std::move(*skeleton);
  std::unordered_map<std::uint32_t, std::size_t> in_skeleton;
  for (std::size_t i = 0; i < skeleton_.size(); ++i) in_skeleton[skeleton_.nodes()[i].index] = i;
  const std::vector<NodeId> hierarchy = scene_.hierarchy();
  std::unordered_set<std::uint32_t> keep;
  if (options_.deform_only) {
    keep = deform_set(g_, hierarchy);
    if (keep.empty())
      return error(ErrorCode::kInvalidArgument, "deform-only export: the scene has no skinned mesh, joint or mesh to export");
  }
  for (NodeId id : hierarchy) {
    if (options_.deform_only && !keep.count(id.index)) continue;
    ExportNode n;
    n.id = id;
    n.skeleton = in_skeleton.at(id.index);
    index_[id.index] = static_cast<int>(nodes_.size());
    nodes_.push_back(std::move(n));
  }
  return Status::ok();
}

int Exporter::gltf_index(NodeId id) const {
  auto it = index_.find(id.index);
  return it == index_.end() ? -1 : it->second;
}

Status Exporter::rest_pose() {
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    ExportNode& n = nodes_[i];
    // The nearest exported ancestor (a deform-only export leaves nodes out).
    NodeId parent = g_.parent(n.id);
    while (parent.is_valid() && gltf_index(parent) < 0) parent = g_.parent(parent);
    n.reparented = parent != g_.parent(n.id);
    if (parent.is_valid() && !n.detached) {
      n.parent = gltf_index(parent);
      nodes_[static_cast<std::size_t>(n.parent)].children.push_back(static_cast<int>(i));
    }
  }
  std::vector<Mat4> local(skeleton_.size()), world(skeleton_.size());
  if (Status s = skeleton_.evaluate(scene_, local, world); !s) return s;
  Placement placement(nodes_.size());
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    ExportNode& n = nodes_[i];
    n.rest = place(i, local, world, placement);
    n.under_shear = n.parent >= 0 && placement.displaced[static_cast<std::size_t>(n.parent)];
    n.rest_matrix = math::trs_matrix(n.rest.translate, n.rest.rotation, n.rest.scale);
    // A rotated matrix decomposes to scales a rounding away from 1: write
    // those as 1 (and leave them out of the file).
    for (int k = 0; k < 3; ++k)
      if (std::abs(n.rest.scale[k] - 1.0) <= kUnitScaleTolerance) n.rest.scale[k] = 1.0;
    n.rest.rotation.normalize();
    if (n.rest.rotation.w() < 0) n.rest.rotation.coeffs() *= -1.0;
    n.has_shear = n.rest.shear.cwiseAbs().maxCoeff() > kShearTolerance;
    if (n.rest.shear.cwiseAbs().maxCoeff() > kVisibleShear)
      report_.notes.push_back(name(n.id) + ": its shear (up to " + number(n.rest.shear.cwiseAbs().maxCoeff()) +
                              ") is left out, since glTF nodes hold translation, rotation and scale only; "
                              "nodes keep their positions, and mesh points and skinned vertices their place");
  }
  compensate_shear(world, placement);
  return check_skinned_placement(world);
}

math::Decomposed Exporter::place(std::size_t i, std::span<const Mat4> local, std::span<const Mat4> world, Placement& p) const {
  const ExportNode& n = nodes_[i];
  const bool under_displaced = n.parent >= 0 && p.displaced[static_cast<std::size_t>(n.parent)];
  const Mat4 wanted =
      under_displaced ? Mat4(p.written[static_cast<std::size_t>(n.parent)].inverse() * world[n.skeleton])
      : n.detached    ? world[n.skeleton]
      : n.reparented  ? (n.parent >= 0 ? Mat4(math::affine_inverse(world[nodes_[static_cast<std::size_t>(n.parent)].skeleton]) *
                                              world[n.skeleton])
                                       : world[n.skeleton])
                      : local[n.skeleton];
  const math::Decomposed d = math::decompose(wanted);
  p.displaced[i] = d.shear.cwiseAbs().maxCoeff() > kShearTolerance;
  if (p.displaced[i]) {
    const Mat4 parent = n.parent >= 0 && !n.detached
                            ? (under_displaced ? p.written[static_cast<std::size_t>(n.parent)] : world[nodes_[static_cast<std::size_t>(n.parent)].skeleton])
                            : Mat4(Mat4::Identity());
    p.written[i] = parent * math::trs_matrix(d.translate, d.rotation, d.scale);
  }
  return d;
}

void Exporter::compensate_shear(std::span<const Mat4> world, const Placement& p) {
  for (MeshExport& m : meshes_) {
    if (m.cluster.is_valid() || !p.displaced[m.node]) continue;
    const Mat4 c = p.written[m.node].inverse() * world[nodes_[m.node].skeleton];
    const Eigen::Matrix3d linear = c.topLeftCorner<3, 3>();
    const Eigen::Matrix3d normal = linear.inverse().transpose();
    for (Vec3& v : m.points) v = linear * v + c.topRightCorner<3, 1>();
    for (Vec3& v : m.normals) v = (normal * v).normalized();
    for (auto& target : m.targets)
      for (Vec3& v : target) v = linear * v;
  }
  for (SkinExport& s : skins_) {
    for (std::size_t k = 0; k < s.joints.size(); ++k) {
      const auto j = static_cast<std::size_t>(s.joints[k]);
      if (p.displaced[j]) s.inverse_bind[k] = p.written[j].inverse() * world[nodes_[j].skeleton] * s.inverse_bind[k];
    }
  }
}

Status Exporter::check_skinned_placement(std::span<const Mat4> world) {
  for (const MeshExport& m : meshes_) {
    if (!m.cluster.is_valid()) continue;
    const ExportNode& n = nodes_[m.node];
    const Mat4& geom = value_as<Mat4>(g_, m.cluster, ops::skin_cluster_attr::kGeomMatrix);
    if (!near_matrix(world[n.skeleton], geom, kGeomTolerance)) {
      std::string when = report_.baked ? " at time " + number(g_.time()) + " s" : "";
      return error(ErrorCode::kInvalidArgument,
                   name(n.id) + ": the world matrix of this skinned mesh differs from " + name(m.cluster) +
                       ".geomMatrix" + when +
                       "; glTF draws skinned meshes in world space, so export needs them equal (set " +
                       name(m.cluster) + ".geomMatrix to the mesh's world matrix, or move the mesh)");
    }
  }
  return Status::ok();
}

}  // namespace rigel::io::gltf_exporter
