// The glTF importer: meshes read (attributes, skin sets, morph targets,
// indices into triangles) and checked against their skins, then the mesh,
// blendShape and skinCluster nodes built.
#include "gltf_importer.h"

#include <set>
#include <string_view>

#include "rigel/ops/deform/nodes.h"
#include "rigel/ops/deform/skin.h"
#include "rigel/scene/transform_types.h"

namespace rigel::io::gltf_importer {
namespace {

// "JOINTS_12" -> 12; -1 when `name` is not prefix + a decimal number.
int set_index(const std::string& name, std::string_view prefix) {
  if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) return -1;
  const std::string digits = name.substr(prefix.size());
  if (digits.size() > 4 || (digits.size() > 1 && digits[0] == '0')) return -1;
  int n = 0;
  for (char c : digits) {
    if (c < '0' || c > '9') return -1;
    n = n * 10 + (c - '0');
  }
  return n;
}

// The names of a mesh's morph targets, from the common convention
// mesh.extras.targetNames (glTF has no place for them): one string per
// target, else none (with a warning: extras are the exporter's own, so
// names that do not fit are not a reason to refuse the file).
std::vector<std::string> target_names(const tinygltf::Mesh& mesh, std::size_t count, const std::string& path,
                                      std::vector<std::string>* warnings) {
  if (!mesh.extras.IsObject() || !mesh.extras.Has("targetNames")) return {};
  const tinygltf::Value& list = mesh.extras.Get("targetNames");
  std::vector<std::string> names;
  for (std::size_t t = 0; list.IsArray() && t < list.ArrayLen(); ++t) {
    const tinygltf::Value& name = list.Get(static_cast<int>(t));
    if (!name.IsString() || !graph::is_valid_utf8(name.Get<std::string>())) break;
    names.push_back(name.Get<std::string>());
  }
  if (list.IsArray() && names.size() == list.ArrayLen() && names.size() == count) return names;
  if (warnings)
    warnings->push_back(path + ".extras.targetNames: expected " + std::to_string(count) +
                        " names, one per morph target; the targets are left unnamed");
  return {};
}

}  // namespace

// The component types an accessor of `type` may have: (component type,
// normalized) pairs; `expected` names them for the message.
Status Importer::require(const std::string& where, int index, int type, const Allowed& allowed, const char* expected) const {
  const tinygltf::Accessor& a = m_.accessors[static_cast<std::size_t>(index)];
  bool ok = a.type == type;
  if (ok) {
    ok = false;
    for (const auto& [component, normalized] : allowed) ok |= a.componentType == component && a.normalized == normalized;
  }
  return ok ? Status::ok() : bad(where, accessor_summary(index) + "; " + expected + " expected");
}

// KHR_mesh_quantization lets positions, normals and morph deltas be integers.
Importer::Allowed Importer::position_types() const {
  return quantized_ ? Allowed{{kFloat, false}, {kByte, false}, {kByte, true}, {kUnsignedByte, false},
                              {kUnsignedByte, true}, {kShort, false}, {kShort, true},
                              {kUnsignedShort, false}, {kUnsignedShort, true}}
                    : Allowed{{kFloat, false}};
}

Importer::Allowed Importer::normal_types() const {
  return quantized_ ? Allowed{{kFloat, false}, {kByte, true}, {kShort, true}} : Allowed{{kFloat, false}};
}

Status Importer::read_primitive(std::size_t m, std::size_t p, PrimitiveData& out) {
  const tinygltf::Primitive& prim = m_.meshes[m].primitives[p];
  const std::string path = at(dot(at("meshes", m), "primitives"), p);
  const std::string attr_path = dot(path, "attributes");

  // Counts: every attribute has POSITION's (or, without POSITION, the first one's).
  auto position = prim.attributes.find("POSITION");
  const auto reference = position != prim.attributes.end() ? position : prim.attributes.begin();
  if (reference == prim.attributes.end()) return bad(attr_path, "no attributes");
  const std::size_t count = m_.accessors[static_cast<std::size_t>(reference->second)].count;
  out.vertex_count = count;
  for (const auto& [name, index] : prim.attributes) {
    const std::size_t n = m_.accessors[static_cast<std::size_t>(index)].count;
    if (n != count)
      return bad(dot(attr_path, name), "accessor " + std::to_string(index) + " has " + std::to_string(n) + " elements, " +
                                           reference->first + " has " + std::to_string(count));
  }

  if (position != prim.attributes.end()) {
    if (Status s = require(dot(attr_path, "POSITION"), position->second, TINYGLTF_TYPE_VEC3, position_types(), "VEC3 of FLOAT"); !s)
      return s;
    auto values = read(position->second);
    if (!values) return values.status().with_context(dot(attr_path, "POSITION"));
    out.points.resize(count);
    for (std::size_t v = 0; v < count; ++v) out.points[v] = Vec3((**values)[3 * v], (**values)[3 * v + 1], (**values)[3 * v + 2]) * options_.scale;
  }
  if (auto normal = prim.attributes.find("NORMAL"); normal != prim.attributes.end()) {
    if (Status s = require(dot(attr_path, "NORMAL"), normal->second, TINYGLTF_TYPE_VEC3, normal_types(), "VEC3 of FLOAT"); !s) return s;
    auto values = read(normal->second);
    if (!values) return values.status().with_context(dot(attr_path, "NORMAL"));
    out.normals.resize(count);
    for (std::size_t v = 0; v < count; ++v) out.normals[v] = Vec3((**values)[3 * v], (**values)[3 * v + 1], (**values)[3 * v + 2]);
  }
  if (Status s = read_skin_sets(prim, attr_path, count, out); !s) return s;
  if (Status s = read_targets(prim, path, reference->first, count, out); !s) return s;
  return read_surface(prim, path, count, position != prim.attributes.end(), out);
}

// Skin sets: JOINTS_n and WEIGHTS_n in pairs.
Status Importer::read_skin_sets(const tinygltf::Primitive& prim, const std::string& attr_path, std::size_t count,
                                PrimitiveData& out) {
  std::set<int> joint_sets, weight_sets;
  for (const auto& [name, index] : prim.attributes) {
    if (const int n = set_index(name, "JOINTS_"); n >= 0) joint_sets.insert(n);
    if (const int n = set_index(name, "WEIGHTS_"); n >= 0) weight_sets.insert(n);
  }
  for (int n : joint_sets) {
    if (!weight_sets.count(n)) return bad(attr_path, "JOINTS_" + std::to_string(n) + " has no WEIGHTS_" + std::to_string(n));
  }
  for (int n : weight_sets) {
    if (!joint_sets.count(n)) return bad(attr_path, "WEIGHTS_" + std::to_string(n) + " has no JOINTS_" + std::to_string(n));
  }
  out.sets.assign(joint_sets.begin(), joint_sets.end());
  out.per_vertex = 4 * out.sets.size();
  out.joints.assign(count * out.per_vertex, 0);
  out.weights.assign(count * out.per_vertex, 0.0);
  for (std::size_t k = 0; k < out.sets.size(); ++k) {
    const std::string jn = "JOINTS_" + std::to_string(out.sets[k]), wn = "WEIGHTS_" + std::to_string(out.sets[k]);
    const int ja = prim.attributes.at(jn), wa = prim.attributes.at(wn);
    if (Status s = require(dot(attr_path, jn), ja, TINYGLTF_TYPE_VEC4, Allowed{{kUnsignedByte, false}, {kUnsignedShort, false}},
                           "VEC4 of UNSIGNED_BYTE or UNSIGNED_SHORT");
        !s)
      return s;
    if (Status s = require(dot(attr_path, wn), wa, TINYGLTF_TYPE_VEC4, Allowed{{kFloat, false}, {kUnsignedByte, true}, {kUnsignedShort, true}},
                           "VEC4 of FLOAT, or of normalized UNSIGNED_BYTE or UNSIGNED_SHORT");
        !s)
      return s;
    auto joints = read(ja);
    if (!joints) return joints.status().with_context(dot(attr_path, jn));
    auto weights = read(wa);
    if (!weights) return weights.status().with_context(dot(attr_path, wn));
    for (std::size_t v = 0; v < count; ++v) {
      for (std::size_t c = 0; c < 4; ++c) {
        const double w = (**weights)[4 * v + c];
        if (w < 0.0) return bad(dot(attr_path, wn), "element " + std::to_string(v) + " has a negative weight");
        out.joints[v * out.per_vertex + 4 * k + c] = static_cast<std::int64_t>((**joints)[4 * v + c]);
        out.weights[v * out.per_vertex + 4 * k + c] = w;
      }
    }
  }
  return Status::ok();
}

// Morph targets: dense POSITION deltas; every target attribute has the
// vertex count of `reference`.
Status Importer::read_targets(const tinygltf::Primitive& prim, const std::string& path, const std::string& reference,
                              std::size_t count, PrimitiveData& out) {
  out.target_deltas.resize(prim.targets.size());
  for (std::size_t t = 0; t < prim.targets.size(); ++t) {
    const std::string tp = at(dot(path, "targets"), t);
    for (const auto& [name, index] : prim.targets[t]) {
      const std::size_t n = m_.accessors[static_cast<std::size_t>(index)].count;
      if (n != count)
        return bad(dot(tp, name), "accessor " + std::to_string(index) + " has " + std::to_string(n) + " elements, " + reference +
                                      " has " + std::to_string(count));
    }
    out.target_deltas[t].assign(count, Vec3::Zero());
    if (auto delta = prim.targets[t].find("POSITION"); delta != prim.targets[t].end()) {
      if (Status s = require(dot(tp, "POSITION"), delta->second, TINYGLTF_TYPE_VEC3, position_types(), "VEC3 of FLOAT"); !s) return s;
      auto values = read(delta->second);
      if (!values) return values.status().with_context(dot(tp, "POSITION"));
      for (std::size_t v = 0; v < count; ++v)
        out.target_deltas[t][v] = Vec3((**values)[3 * v], (**values)[3 * v + 1], (**values)[3 * v + 2]) * options_.scale;
    }
  }
  return Status::ok();
}

// Indices, checked for every mode; triangles for the surface modes.
Status Importer::read_surface(const tinygltf::Primitive& prim, const std::string& path, std::size_t count, bool has_position,
                              PrimitiveData& out) {
  const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
  std::vector<std::int64_t> indices;
  if (prim.indices >= 0) {
    const std::string ip = dot(path, "indices");
    if (Status s = require(ip, prim.indices, TINYGLTF_TYPE_SCALAR, Allowed{{kUnsignedByte, false}, {kUnsignedShort, false}, {kUnsignedInt, false}},
                           "SCALAR of UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT");
        !s)
      return s;
    auto values = read(prim.indices);
    if (!values) return values.status().with_context(ip);
    indices.resize((*values)->size());
    for (std::size_t k = 0; k < indices.size(); ++k) {
      const double v = (**values)[k];
      if (v >= static_cast<double>(count))
        return bad(ip, "element " + std::to_string(k) + " is not below the vertex count " + std::to_string(count));
      indices[k] = static_cast<std::int64_t>(v);
    }
  } else {
    indices.resize(count);
    for (std::size_t k = 0; k < count; ++k) indices[k] = static_cast<std::int64_t>(k);
  }
  const bool surface = mode == TINYGLTF_MODE_TRIANGLES || mode == TINYGLTF_MODE_TRIANGLE_STRIP || mode == TINYGLTF_MODE_TRIANGLE_FAN;
  if (mode == TINYGLTF_MODE_TRIANGLES && indices.size() % 3 != 0)
    return bad(prim.indices >= 0 ? dot(path, "indices") : path,
               std::to_string(indices.size()) + (prim.indices >= 0 ? " indices" : " vertices (no indices)") + " do not make whole triangles");
  out.make_node = surface && has_position;
  if (!out.make_node) return Status::ok();
  if (mode == TINYGLTF_MODE_TRIANGLES) {
    out.triangles = std::move(indices);
  } else if (indices.size() >= 3) {
    out.triangles.reserve(3 * (indices.size() - 2));
    for (std::size_t i = 0; i + 2 < indices.size(); ++i) {
      // glTF 2.0 §3.7.2.1: strips alternate the winding, fans turn around vertex 0.
      if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
        const bool odd = i % 2 == 1;
        out.triangles.insert(out.triangles.end(), {indices[i], indices[odd ? i + 2 : i + 1], indices[odd ? i + 1 : i + 2]});
      } else {
        out.triangles.insert(out.triangles.end(), {indices[i + 1], indices[i + 2], indices[0]});
      }
    }
  }
  return Status::ok();
}

Status Importer::read_meshes() {
  meshes_.resize(m_.meshes.size());
  for (std::size_t m = 0; m < m_.meshes.size(); ++m) {
    const tinygltf::Mesh& mesh = m_.meshes[m];
    MeshData& data = meshes_[m];
    data.primitives.resize(mesh.primitives.size());
    data.target_count = mesh.primitives.empty() ? 0 : mesh.primitives[0].targets.size();
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
      if (mesh.primitives[p].targets.size() != data.target_count)
        return bad(dot(at(dot(at("meshes", m), "primitives"), p), "targets"),
                   std::to_string(mesh.primitives[p].targets.size()) + " morph targets, primitives[0] has " + std::to_string(data.target_count));
      if (Status s = read_primitive(m, p, data.primitives[p]); !s) return s;
    }
    if (!mesh.weights.empty() && mesh.weights.size() != data.target_count)
      return bad(dot(at("meshes", m), "weights"),
                 std::to_string(mesh.weights.size()) + " weights for " + std::to_string(data.target_count) + " morph targets");
    if (data.target_count > 0) data.target_names = target_names(mesh, data.target_count, at("meshes", m), options_.warnings);
  }
  return Status::ok();
}

// The node's mesh against its skin: joint indices (where the weight is not
// zero) below the joint count, and a weight on every vertex; then the
// skinCluster's own validation, so that it will skin and not pass through.
Result<std::vector<SkinBinding>> Importer::bind_skin(std::size_t node) {
  const tinygltf::Node& n = m_.nodes[node];
  const auto skin_index = static_cast<std::size_t>(n.skin);
  const std::size_t joint_count = m_.skins[skin_index].joints.size();
  const auto m = static_cast<std::size_t>(n.mesh);
  std::vector<SkinBinding> result(meshes_[m].primitives.size());
  for (std::size_t p = 0; p < meshes_[m].primitives.size(); ++p) {
    const PrimitiveData& prim = meshes_[m].primitives[p];
    const std::string path = at(dot(at("meshes", m), "primitives"), p);
    const std::string user = " (skins[" + std::to_string(skin_index) + "], used by nodes[" + std::to_string(node) + "])";
    SkinBinding& b = result[p];
    b.offsets = {0};
    for (std::size_t v = 0; v < prim.vertex_count; ++v) {
      for (std::size_t k = 0; k < prim.per_vertex; ++k) {
        const double w = prim.weights[v * prim.per_vertex + k];
        if (w == 0.0) continue;
        const std::int64_t j = prim.joints[v * prim.per_vertex + k];
        if (j < 0 || static_cast<std::size_t>(j) >= joint_count)
          return bad(dot(dot(path, "attributes"), "JOINTS_" + std::to_string(prim.sets[k / 4])),
                     "element " + std::to_string(v) + " has a joint index not below the joint count " +
                         std::to_string(joint_count) + user);
        b.joints.push_back(j);
        b.weights.push_back(w);
      }
      if (static_cast<std::size_t>(b.offsets.back()) == b.joints.size()) {
        // No weight above zero: bound to the glTF node that holds the mesh
        // (one more joint matrix, after the skin's own).
        b.unweighted.push_back(v);
        b.joints.push_back(static_cast<std::int64_t>(joint_count));
        b.weights.push_back(1.0);
      }
      b.offsets.push_back(static_cast<std::int64_t>(b.joints.size()));
    }
    ops::SkinBuildOptions build;
    build.joint_count = joint_count + (b.unweighted.empty() ? 0 : 1);
    if (Result<ops::Skin> skin = ops::build_skin({b.offsets, b.joints, b.weights}, build); !skin) return skin.status().with_context(path);
    if (!b.unweighted.empty() && options_.warnings) {
      std::string list;
      for (std::size_t k = 0; k < b.unweighted.size() && k < 10; ++k) list += (k ? ", " : "") + std::to_string(b.unweighted[k]);
      if (b.unweighted.size() > 10) list += ", ... (" + std::to_string(b.unweighted.size()) + " in all)";
      options_.warnings->push_back(path + ": vertices " + list + " have no joint weight above zero" + user +
                                   "; they follow the mesh's node " + quote_text(scene_->graph().node(ids_[node])->name()) +
                                   " instead of a joint");
    }
  }
  return result;
}

Status Importer::build_meshes() {
  Graph& g = scene_->graph();
  namespace sc = ops::skin_cluster_attr;
  namespace bs = ops::blend_shape_attr;
  namespace ma = scene::mesh_attr;
  for (std::size_t i = 0; i < m_.nodes.size(); ++i) {
    const tinygltf::Node& n = m_.nodes[i];
    if (n.mesh < 0) continue;
    std::vector<SkinBinding> bindings;
    if (n.skin >= 0) {
      Result<std::vector<SkinBinding>> bound = bind_skin(i);
      if (!bound) return bound.status();
      bindings = std::move(*bound);
    }
    const auto mi = static_cast<std::size_t>(n.mesh);
    const tinygltf::Mesh& mesh = m_.meshes[mi];
    const MeshData& data = meshes_[mi];
    const std::string node_path = at("nodes", i);
    const std::string& owner = g.node(ids_[i])->name();
    std::vector<double> weights(data.target_count, 0.0);
    if (!n.weights.empty()) weights = n.weights;
    else if (!mesh.weights.empty()) weights = mesh.weights;
    for (std::size_t p = 0; p < data.primitives.size(); ++p) {
      const PrimitiveData& prim = data.primitives[p];
      if (!prim.make_node) continue;
      std::string name = node_name(mesh.name, owner + "_mesh");
      // append, not "_" + ...: GCC 12 warns falsely (-Wrestrict) on that form.
      if (data.primitives.size() > 1) name.append("_").append(std::to_string(p));
      const std::string where = node_path + ": meshes[" + std::to_string(mi) + "].primitives[" + std::to_string(p) + "]";
      const bool skinned = n.skin >= 0;
      Result<NodeId> mesh_id = scene_->create(scene::kMeshType, name, skinned ? NodeId{} : ids_[i]);
      if (!mesh_id) return mesh_id.status().with_context(where);
      mesh_sources_.push_back({*mesh_id, mi, p});
      const std::string& mesh_name = g.node(*mesh_id)->name();
      Status s = set(*mesh_id, ma::kTriangles, prim.triangles);
      // The glTF node holding the mesh: the exporter writes the mesh back on
      // it, so a round trip keeps the node tree (gltf_export.h).
      if (s) s = g.set_tag(*mesh_id, kTagGltfNode, g.node(ids_[i])->name());
      // Where the points come from: the file, a blendShape, a skinCluster.
      NodeId points_src;
      graph::AttrIndex points_attr = 0;
      if (s && data.target_count > 0) {
        Result<NodeId> shape = g.create_node(ops::kBlendShapeType, mesh_name + "_blendShape");
        if (!shape) return shape.status().with_context(where);
        std::vector<Vec3> deltas;
        std::vector<std::int64_t> offsets = {0};
        for (const auto& target : prim.target_deltas) {
          deltas.insert(deltas.end(), target.begin(), target.end());
          offsets.push_back(static_cast<std::int64_t>(deltas.size()));
        }
        s = set(*shape, bs::kBasePoints, prim.points);
        if (s) s = set(*shape, bs::kTargetDeltas, std::move(deltas));
        if (s) s = set(*shape, bs::kTargetOffsets, std::move(offsets));
        if (s) s = set(*shape, bs::kWeights, weights);
        if (s && !data.target_names.empty()) s = set(*shape, bs::kTargetNames, data.target_names);
        points_src = *shape;
        points_attr = bs::kOutPoints;
        blend_shapes_[i].push_back(*shape);
      }
      if (s && skinned) {
        const auto skin_index = static_cast<std::size_t>(n.skin);
        const auto& joints = m_.skins[skin_index].joints;
        Result<NodeId> skin = g.create_node(ops::kSkinClusterType, mesh_name + "_skinCluster");
        if (!skin) return skin.status().with_context(where);
        SkinBinding& binding = bindings[p];
        std::vector<Mat4> bind_pre = inverse_bind_[skin_index];
        if (!binding.unweighted.empty()) bind_pre.push_back(Mat4::Identity());
        if (points_src.is_valid()) s = connect(points_src, points_attr, *skin, sc::kBindPoints);
        else s = set(*skin, sc::kBindPoints, prim.points);
        if (s) s = set(*skin, sc::kBindNormals, prim.normals);
        if (s) s = set(*skin, sc::kBindPreMatrices, std::move(bind_pre));
        if (s) s = set(*skin, sc::kInfluenceOffsets, std::move(binding.offsets));
        if (s) s = set(*skin, sc::kInfluenceJoints, std::move(binding.joints));
        if (s) s = set(*skin, sc::kInfluenceWeights, std::move(binding.weights));
        if (s) s = set(*skin, sc::kNormalizeWeights, true);
        for (std::size_t k = 0; s && k < joints.size(); ++k)
          s = connect(ids_[static_cast<std::size_t>(joints[k])], scene::xform::kWorldMatrix, *skin, sc::kJointMatrices,
                      static_cast<std::int32_t>(k));
        if (s && !binding.unweighted.empty())
          s = connect(ids_[i], scene::xform::kWorldMatrix, *skin, sc::kJointMatrices, static_cast<std::int32_t>(joints.size()));
        if (s) s = connect(*skin, sc::kOutPoints, *mesh_id, ma::kPoints);
        if (s) s = connect(*skin, sc::kOutNormals, *mesh_id, ma::kNormals);
      } else if (s) {
        if (points_src.is_valid()) s = connect(points_src, points_attr, *mesh_id, ma::kPoints);
        else s = set(*mesh_id, ma::kPoints, prim.points);
        if (s) s = set(*mesh_id, ma::kNormals, prim.normals);
      }
      if (!s) return s.with_context(where);
    }
  }
  return Status::ok();
}

}  // namespace rigel::io::gltf_importer
