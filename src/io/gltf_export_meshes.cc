// The glTF exporter: the meshes to export, with their morph targets (dense
// deltas of a blendShape) and skins (joints of a skinCluster, influences
// sorted per vertex into JOINTS_n / WEIGHTS_n sets).
#include "gltf_exporter.h"

#include <algorithm>
#include <limits>
#include <map>

#include "rigel/io/gltf_import.h"
#include "rigel/math/transform.h"
#include "rigel/ops/deform/nodes.h"
#include "rigel/ops/deform/skin.h"
#include "rigel/scene/transform_types.h"

namespace rigel::io::gltf_exporter {

NodeId Exporter::fed_by(const Plug& plug, const char* type, AttrIndex attr) const {
  const std::optional<Plug> source = g_.source(plug);
  if (!source || source->attr != attr || source->element >= 0 || type_of(g_, source->node) != type) return NodeId{};
  return source->node;
}

Status Exporter::collect_meshes() {
  namespace ma = scene::mesh_attr;
  namespace sa = ops::skin_cluster_attr;
  namespace ba = ops::blend_shape_attr;
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    const NodeId id = nodes_[i].id;
    if (type_of(g_, id) != scene::kMeshType) continue;
    MeshExport m;
    m.node = i;
    m.cluster = fed_by(Plug{id, ma::kPoints, -1}, ops::kSkinClusterType, sa::kOutPoints);
    std::vector<Vec3> points;
    if (m.cluster.is_valid()) {
      m.blend = fed_by(Plug{m.cluster, sa::kBindPoints, -1}, ops::kBlendShapeType, ba::kOutPoints);
      points = value_as<std::vector<Vec3>>(g_, m.cluster, sa::kBindPoints);
      m.normals = value_as<std::vector<Vec3>>(g_, m.cluster, sa::kBindNormals);
    } else {
      m.blend = fed_by(Plug{id, ma::kPoints, -1}, ops::kBlendShapeType, ba::kOutPoints);
      points = value_as<std::vector<Vec3>>(g_, id, ma::kPoints);
      m.normals = value_as<std::vector<Vec3>>(g_, id, ma::kNormals);
    }
    m.points = m.blend.is_valid() ? value_as<std::vector<Vec3>>(g_, m.blend, ba::kBasePoints) : std::move(points);
    m.triangles = value_as<std::vector<std::int64_t>>(g_, id, ma::kTriangles);
    if (m.points.empty() || m.triangles.empty()) {
      report_.notes.push_back(name(id) + ": a mesh without " + (m.points.empty() ? "points" : "triangles") +
                              " is written as a plain node");
      continue;
    }
    if (m.normals.size() != m.points.size()) {
      if (!m.normals.empty())
        report_.notes.push_back(name(id) + ": " + std::to_string(m.normals.size()) + " normals for " +
                                std::to_string(m.points.size()) + " points are left out");
      m.normals.clear();
    }
    if (Status s = check_triangles(id, m); !s) return s;
    if (m.blend.is_valid()) {
      if (Status s = collect_targets(m); !s) return s;
    }
    if (m.cluster.is_valid()) {
      nodes_[i].detached = true;
      if (Status s = collect_skin(m); !s) return s;
    }
    nodes_[i].mesh = static_cast<int>(meshes_.size());
    meshes_.push_back(std::move(m));
  }
  return Status::ok();
}

void Exporter::merge_mesh_nodes() {
  for (std::size_t k = 0; k < meshes_.size(); ++k) {
    const MeshExport& m = meshes_[k];
    const NodeId id = nodes_[m.node].id;
    const std::string* tag = g_.node(id)->tag_find(kTagGltfNode);
    if (!tag) continue;
    const NodeId owner = g_.find(*tag);
    const int o = owner.is_valid() ? gltf_index(owner) : -1;
    if (o < 0 || owner == id) continue;
    ExportNode& target = nodes_[static_cast<std::size_t>(o)];
    if (target.mesh >= 0 || target.owned_mesh >= 0 || target.merged_into >= 0) continue;
    if (!g_.children(id).empty() || is_skin_joint(id)) continue;
    if (!m.cluster.is_valid()) {
      if (g_.parent(id) != owner || !static_identity(*g_.node(id))) continue;
    }
    nodes_[m.node].merged_into = o;
    target.owned_mesh = static_cast<int>(k);
  }
}

void Exporter::collect_skeleton_skin() {
  if (!options_.skeleton_skin || !skins_.empty()) return;
  SkinExport skin;
  skin.name = "skeleton";
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    const NodeId id = nodes_[i].id;
    if (type_of(g_, id) != scene::kJointType) continue;
    skin.joints.push_back(static_cast<int>(i));
    skin.inverse_bind.push_back(math::affine_inverse(scene_.world_matrix(id)));
  }
  if (!skin.joints.empty()) skins_.push_back(std::move(skin));
}

bool Exporter::is_skin_joint(NodeId id) const {
  for (const SkinExport& s : skins_)
    for (int j : s.joints)
      if (nodes_[static_cast<std::size_t>(j)].id == id) return true;
  return false;
}

bool Exporter::static_identity(const Node& n) const {
  for (const graph::Connection& c : n.inputs())
    if (shapes_matrix(n, c.dst.attr)) return false;
  return std::get<Mat4>(g_.evaluate(n.id(), xf::kMatrix)) == Mat4::Identity() &&
         std::get<Mat4>(n.value(xf::kOffsetParentMatrix)) == Mat4::Identity();
}

Status Exporter::check_triangles(NodeId id, const MeshExport& m) const {
  const std::string where = name(id) + ".triangles";
  if (m.triangles.size() % 3 != 0)
    return error(ErrorCode::kInvalidArgument,
                 where + ": " + std::to_string(m.triangles.size()) + " indices is not a whole number of triangles");
  if (m.points.size() >= std::numeric_limits<std::uint32_t>::max())
    return error(ErrorCode::kInvalidArgument, name(id) + ".points: too many points for glTF's 32-bit indices");
  for (std::size_t k = 0; k < m.triangles.size(); ++k) {
    if (m.triangles[k] < 0 || static_cast<std::uint64_t>(m.triangles[k]) >= m.points.size())
      return error(ErrorCode::kInvalidArgument, where + "[" + std::to_string(k) + "]: index " +
                                                    std::to_string(m.triangles[k]) + " is not one of the " +
                                                    std::to_string(m.points.size()) + " points");
  }
  return Status::ok();
}

Status Exporter::collect_targets(MeshExport& m) {
  namespace ba = ops::blend_shape_attr;
  const std::string& b = name(m.blend);
  const auto& deltas = value_as<std::vector<Vec3>>(g_, m.blend, ba::kTargetDeltas);
  const auto& offsets = value_as<std::vector<std::int64_t>>(g_, m.blend, ba::kTargetOffsets);
  const auto& indices = value_as<std::vector<std::int64_t>>(g_, m.blend, ba::kTargetIndices);
  const auto& weights = value_as<std::vector<double>>(g_, m.blend, ba::kWeights);
  if (offsets.empty()) return Status::ok();
  if (offsets.front() != 0 || static_cast<std::uint64_t>(offsets.back()) != deltas.size() ||
      !std::is_sorted(offsets.begin(), offsets.end()))
    return error(ErrorCode::kInvalidArgument, b + ".targetOffsets: must rise from 0 to the " +
                                                  std::to_string(deltas.size()) + " targetDeltas");
  if (!indices.empty() && indices.size() != deltas.size())
    return error(ErrorCode::kInvalidArgument, b + ".targetIndices: " + std::to_string(indices.size()) +
                                                  " indices for " + std::to_string(deltas.size()) + " deltas");
  const std::size_t count = offsets.size() - 1;
  for (std::size_t t = 0; t < count; ++t) {
    const auto begin = static_cast<std::size_t>(offsets[t]), end = static_cast<std::size_t>(offsets[t + 1]);
    std::vector<Vec3> dense(m.points.size(), Vec3::Zero());
    if (indices.empty() && end - begin != m.points.size())
      return error(ErrorCode::kInvalidArgument, b + ".targetDeltas: dense target " + std::to_string(t) + " has " +
                                                    std::to_string(end - begin) + " deltas for " +
                                                    std::to_string(m.points.size()) + " points");
    for (std::size_t k = begin; k < end; ++k) {
      const std::int64_t v = indices.empty() ? static_cast<std::int64_t>(k - begin) : indices[k];
      if (v < 0 || static_cast<std::uint64_t>(v) >= m.points.size())
        return error(ErrorCode::kInvalidArgument, b + ".targetIndices[" + std::to_string(k) + "]: vertex " +
                                                      std::to_string(v) + " is not one of the " +
                                                      std::to_string(m.points.size()) + " points");
      dense[static_cast<std::size_t>(v)] += deltas[k];
    }
    m.targets.push_back(std::move(dense));
  }
  m.weights.assign(count, 0.0);
  std::copy_n(weights.begin(), std::min(count, weights.size()), m.weights.begin());
  const auto& names = value_as<std::vector<std::string>>(g_, m.blend, ba::kTargetNames);
  if (std::any_of(names.begin(), names.end(), [](const std::string& n) { return !n.empty(); })) {
    m.target_names.assign(count, std::string());
    std::copy_n(names.begin(), std::min(count, names.size()), m.target_names.begin());
  }
  return Status::ok();
}

Status Exporter::collect_skin(MeshExport& m) {
  namespace sa = ops::skin_cluster_attr;
  const std::string& c = name(m.cluster);
  // A skinCluster shared by several meshes is one glTF skin.
  for (std::size_t s = 0; s < skins_.size(); ++s)
    if (skins_[s].cluster == m.cluster) m.skin = static_cast<int>(s);
  const auto& joint_matrices = value_as<std::vector<Mat4>>(g_, m.cluster, sa::kJointMatrices);
  if (m.skin < 0) {
    SkinExport skin;
    skin.cluster = m.cluster;
    skin.name = c;
    std::size_t count = joint_matrices.size();
    std::map<std::int32_t, NodeId> sources;
    for (const graph::Connection& conn : g_.node(m.cluster)->inputs()) {
      if (conn.dst.attr != sa::kJointMatrices) continue;
      if (conn.dst.element < 0)
        return error(ErrorCode::kInvalidArgument,
                     c + ".jointMatrices: fed as a whole by " + describe(g_, conn.src) +
                         "; export needs each element fed by a joint's worldMatrix");
      if (conn.src.attr != xf::kWorldMatrix || conn.src.element >= 0 || !scene_.is_transform(conn.src.node))
        return error(ErrorCode::kInvalidArgument, c + ".jointMatrices[" + std::to_string(conn.dst.element) +
                                                      "]: fed by " + describe(g_, conn.src) +
                                                      ", not by a transform's worldMatrix");
      sources[conn.dst.element] = conn.src.node;
      count = std::max(count, static_cast<std::size_t>(conn.dst.element) + 1);
    }
    std::map<int, std::size_t> seen;
    for (std::size_t j = 0; j < count; ++j) {
      auto it = sources.find(static_cast<std::int32_t>(j));
      if (it == sources.end())
        return error(ErrorCode::kInvalidArgument, c + ".jointMatrices[" + std::to_string(j) +
                                                      "]: not fed by a joint's worldMatrix (glTF skins name "
                                                      "their joints)");
      const int joint = gltf_index(it->second);
      if (auto [at, fresh] = seen.emplace(joint, j); !fresh)
        return error(ErrorCode::kInvalidArgument,
                     c + ".jointMatrices[" + std::to_string(j) + "]: " + name(it->second) +
                         " also feeds jointMatrices[" + std::to_string(at->second) + "]; glTF joints are unique");
      skin.joints.push_back(joint);
    }
    const auto& bind_pre = value_as<std::vector<Mat4>>(g_, m.cluster, sa::kBindPreMatrices);
    for (std::size_t j = 0; j < count; ++j)
      skin.inverse_bind.push_back(j < bind_pre.size() ? bind_pre[j] : Mat4(Mat4::Identity()));
    if (std::int64_t method = value_as<std::int64_t>(g_, m.cluster, sa::kMethod); method != 0)
      report_.notes.push_back(c + ": dual quaternion skinning is written as glTF's linear blend skinning");
    m.skin = static_cast<int>(skins_.size());
    skins_.push_back(std::move(skin));
  }

  const std::size_t joint_count = skins_[static_cast<std::size_t>(m.skin)].joints.size();
  if (joint_count > ops::kMaxSkinJoints)
    return error(ErrorCode::kInvalidArgument, c + ".jointMatrices: " + std::to_string(joint_count) +
                                                  " joints; glTF's JOINTS_n hold at most 65536");
  const ops::SkinInfluenceView view{value_as<std::vector<std::int64_t>>(g_, m.cluster, sa::kInfluenceOffsets),
                                    value_as<std::vector<std::int64_t>>(g_, m.cluster, sa::kInfluenceJoints),
                                    value_as<std::vector<double>>(g_, m.cluster, sa::kInfluenceWeights)};
  ops::SkinBuildOptions options;
  options.joint_count = joint_count;
  options.normalize = true;  // glTF's weights sum to 1
  options.fixed_layout = false;
  ops::SkinBuildReport build_report;
  Result<ops::Skin> skin = ops::build_skin(view, options, &build_report);
  if (!skin) return skin.status().with_context(c + ".influenceWeights");
  if (skin->vertex_count() != m.points.size())
    return error(ErrorCode::kInvalidArgument, c + ".influenceOffsets: weights for " +
                                                  std::to_string(skin->vertex_count()) + " vertices, but " +
                                                  std::to_string(m.points.size()) + " bindPoints");
  if (!value_as<bool>(g_, m.cluster, sa::kNormalizeWeights) && !build_report.renormalized.empty())
    report_.notes.push_back(c + ": " + std::to_string(build_report.renormalized.size()) +
                            " vertices' weights do not sum to 1 and normalizeWeights is off; glTF normalises them");

  m.sets = std::max<std::size_t>(1, (skin->max_influences() + 3) / 4);
  const std::size_t stride = m.sets * 4;
  m.joints.assign(m.points.size() * stride, 0);
  m.joint_weights.assign(m.points.size() * stride, 0.0f);
  std::vector<std::pair<float, std::uint16_t>> influences;
  for (std::size_t v = 0; v < m.points.size(); ++v) {
    influences.clear();
    for (std::uint32_t k = skin->offsets()[v]; k < skin->offsets()[v + 1]; ++k)
      influences.emplace_back(skin->weights()[k], skin->joints()[k]);
    // Largest first; equal weights by joint, so the file is deterministic.
    std::sort(influences.begin(), influences.end(),
              [](const auto& a, const auto& b) { return a.first != b.first ? a.first > b.first : a.second < b.second; });
    for (std::size_t k = 0; k < influences.size(); ++k) {
      m.joints[v * stride + k] = influences[k].second;
      m.joint_weights[v * stride + k] = influences[k].first;
    }
  }
  return Status::ok();
}

}  // namespace rigel::io::gltf_exporter
