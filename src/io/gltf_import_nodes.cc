// The glTF importer: the node hierarchy (one parent each, no cycles),
// skins, node transforms and scenes checked, then the scene nodes built.
#include "gltf_importer.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "rigel/ops/deform/skin.h"
#include "rigel/scene/transform_types.h"

namespace rigel::io::gltf_importer {
namespace {

// Numbers of the file in messages: 9 digits tell any two floats apart.
std::string number(double v) { return gltf::number(v, 9); }

}  // namespace

Status Importer::check_hierarchy() {
  const std::size_t count = m_.nodes.size();
  parent_.assign(count, -1);
  for (std::size_t i = 0; i < count; ++i) {
    const auto& children = m_.nodes[i].children;
    for (std::size_t k = 0; k < children.size(); ++k) {
      const auto c = static_cast<std::size_t>(children[k]);
      if (parent_[c] == static_cast<int>(i))
        return bad(at(dot(at("nodes", i), "children"), k), "node " + std::to_string(c) + " is listed twice");
      if (parent_[c] >= 0)
        return bad(at(dot(at("nodes", i), "children"), k), "node " + std::to_string(c) + " already has parent node " +
                                                               std::to_string(parent_[c]) + " (a node has one parent)");
      parent_[c] = static_cast<int>(i);
    }
  }
  // Cycles: walk up from every node, marking the walk (1) and what is done (2).
  std::vector<std::uint8_t> state(count, 0);
  std::vector<int> walk;
  for (std::size_t start = 0; start < count; ++start) {
    walk.clear();
    int x = static_cast<int>(start);
    while (x >= 0 && state[static_cast<std::size_t>(x)] == 0) {
      state[static_cast<std::size_t>(x)] = 1;
      walk.push_back(x);
      x = parent_[static_cast<std::size_t>(x)];
    }
    if (x >= 0 && state[static_cast<std::size_t>(x)] == 1) {
      // walk holds child -> parent steps; the cycle is its tail from x.
      std::vector<int> cycle(std::find(walk.begin(), walk.end(), x), walk.end());
      std::reverse(cycle.begin(), cycle.end());  // parent -> child
      std::rotate(cycle.begin(), std::min_element(cycle.begin(), cycle.end()), cycle.end());
      std::string text;
      for (int n : cycle) text += std::to_string(n) + " -> ";
      text += std::to_string(cycle.front());
      return bad(at("nodes", static_cast<std::size_t>(cycle.front())), "node is its own ancestor (cycle " + text + ")");
    }
    for (int n : walk) state[static_cast<std::size_t>(n)] = 2;
  }
  root_.assign(count, -1);
  for (std::size_t i = 0; i < count; ++i) {
    walk.clear();
    int x = static_cast<int>(i);
    while (root_[static_cast<std::size_t>(x)] < 0 && parent_[static_cast<std::size_t>(x)] >= 0) {
      walk.push_back(x);
      x = parent_[static_cast<std::size_t>(x)];
    }
    const int root = root_[static_cast<std::size_t>(x)] >= 0 ? root_[static_cast<std::size_t>(x)] : x;
    root_[static_cast<std::size_t>(x)] = root;
    for (int n : walk) root_[static_cast<std::size_t>(n)] = root;
  }
  return Status::ok();
}

Status Importer::check_skins() {
  is_joint_.assign(m_.nodes.size(), false);
  inverse_bind_.resize(m_.skins.size());
  for (std::size_t s = 0; s < m_.skins.size(); ++s) {
    const tinygltf::Skin& skin = m_.skins[s];
    const std::string path = at("skins", s);
    if (skin.joints.size() > ops::kMaxSkinJoints)
      return bad(dot(path, "joints"), std::to_string(skin.joints.size()) + " joints (at most " + std::to_string(ops::kMaxSkinJoints) + ")");
    std::map<int, std::size_t> seen;
    for (std::size_t k = 0; k < skin.joints.size(); ++k) {
      const int j = skin.joints[k];
      if (auto [it, fresh] = seen.emplace(j, k); !fresh)
        return bad(at(dot(path, "joints"), k), "node " + std::to_string(j) + " is also joints[" + std::to_string(it->second) + "]");
      is_joint_[static_cast<std::size_t>(j)] = true;
    }
    const int root = root_[static_cast<std::size_t>(skin.joints[0])];
    for (std::size_t k = 1; k < skin.joints.size(); ++k) {
      const int j = skin.joints[k];
      if (root_[static_cast<std::size_t>(j)] != root)
        return bad(dot(path, "joints"), "the joints have no common root (node " + std::to_string(skin.joints[0]) + " is under root node " +
                                            std::to_string(root) + ", node " + std::to_string(j) + " under root node " +
                                            std::to_string(root_[static_cast<std::size_t>(j)]) + ")");
    }
    if (skin.skeleton >= 0) {
      for (std::size_t k = 0; k < skin.joints.size(); ++k) {
        int x = skin.joints[k];
        while (x >= 0 && x != skin.skeleton) x = parent_[static_cast<std::size_t>(x)];
        if (x < 0)
          return bad(dot(path, "skeleton"), "node " + std::to_string(skin.skeleton) + " is not a common root of the joints (joints[" +
                                                std::to_string(k) + "] = node " + std::to_string(skin.joints[k]) + " is not below it)");
      }
    }
    if (skin.inverseBindMatrices >= 0) {
      const std::string ip = dot(path, "inverseBindMatrices");
      const tinygltf::Accessor& a = m_.accessors[static_cast<std::size_t>(skin.inverseBindMatrices)];
      if (a.type != TINYGLTF_TYPE_MAT4 || a.componentType != kFloat)
        return bad(ip, accessor_summary(skin.inverseBindMatrices) + "; MAT4 of FLOAT expected");
      if (a.count < skin.joints.size())
        return bad(ip, "accessors[" + std::to_string(skin.inverseBindMatrices) + "] has " + std::to_string(a.count) +
                           " matrices for " + std::to_string(skin.joints.size()) + " joints");
    }
  }
  // The matrices themselves (finite, affine) matter where a node skins with them.
  std::vector<bool> used(m_.skins.size(), false);
  for (const tinygltf::Node& n : m_.nodes) {
    if (n.skin >= 0) used[static_cast<std::size_t>(n.skin)] = true;
  }
  for (std::size_t s = 0; s < m_.skins.size(); ++s) {
    const tinygltf::Skin& skin = m_.skins[s];
    std::vector<Mat4>& ibm = inverse_bind_[s];
    ibm.assign(skin.joints.size(), Mat4::Identity());
    if (used[s] && skin.inverseBindMatrices >= 0) {
      const std::string ip = dot(at("skins", s), "inverseBindMatrices");
      auto values = read(skin.inverseBindMatrices);
      if (!values) return values.status().with_context(ip);
      for (std::size_t k = 0; k < skin.joints.size(); ++k) {
        Mat4 matrix = Eigen::Map<const Mat4>((*values)->data() + 16 * k);  // column-major, as glTF
        const double off = std::max({std::abs(matrix(3, 0)), std::abs(matrix(3, 1)), std::abs(matrix(3, 2)), std::abs(matrix(3, 3) - 1.0)});
        if (off > 1e-5)
          return bad(ip, "matrix " + std::to_string(k) + " is not affine (its last row is not 0 0 0 1)");
        matrix.row(3) << 0.0, 0.0, 0.0, 1.0;
        matrix.topRightCorner<3, 1>() *= options_.scale;
        ibm[k] = matrix;
      }
    }
  }
  return Status::ok();
}

Status Importer::check_nodes() {
  const std::size_t count = m_.nodes.size();
  rest_translate_.assign(count, Vec3::Zero());
  rest_scale_.assign(count, Vec3::Ones());
  rest_rotate_.assign(count, Quat::Identity());
  for (std::size_t i = 0; i < count; ++i) {
    const tinygltf::Node& n = m_.nodes[i];
    const std::string path = at("nodes", i);
    if (n.skin >= 0 && n.mesh < 0) return bad(dot(path, "skin"), "a skin needs a mesh on the node");
    if (!n.weights.empty() && n.mesh < 0) return bad(dot(path, "weights"), "morph target weights need a mesh on the node");
    if (n.mesh >= 0) {
      const tinygltf::Mesh& mesh = m_.meshes[static_cast<std::size_t>(n.mesh)];
      if (n.skin >= 0) {
        for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
          if (!mesh.primitives[p].attributes.count("JOINTS_0"))
            return bad(dot(path, "skin"), "meshes[" + std::to_string(n.mesh) + "].primitives[" + std::to_string(p) +
                                              "] has no JOINTS_0 to bind to skins[" + std::to_string(n.skin) + "]");
        }
      }
      const std::size_t targets = mesh.primitives.empty() ? 0 : mesh.primitives[0].targets.size();
      if (!n.weights.empty() && n.weights.size() != targets)
        return bad(dot(path, "weights"), std::to_string(n.weights.size()) + " weights, meshes[" + std::to_string(n.mesh) + "] has " +
                                             std::to_string(targets) + " morph targets");
    }
    if (!n.matrix.empty()) {
      const Mat4 matrix = Eigen::Map<const Mat4>(n.matrix.data());
      if (matrix(3, 0) != 0.0 || matrix(3, 1) != 0.0 || matrix(3, 2) != 0.0 || matrix(3, 3) != 1.0)
        return bad(dot(path, "matrix"), "not an affine transform (last row " + number(matrix(3, 0)) + " " + number(matrix(3, 1)) + " " +
                                            number(matrix(3, 2)) + " " + number(matrix(3, 3)) + ", 0 0 0 1 expected)");
      // m = T R SH S exactly; rest values for animation come from here.
      const math::Decomposed d = math::decompose(matrix);
      rest_translate_[i] = d.translate * options_.scale;
      rest_rotate_[i] = d.rotation;
      rest_scale_[i] = d.scale;
    } else {
      if (!n.translation.empty()) rest_translate_[i] = Vec3(n.translation[0], n.translation[1], n.translation[2]) * options_.scale;
      if (!n.scale.empty()) rest_scale_[i] = Vec3(n.scale[0], n.scale[1], n.scale[2]);
      if (!n.rotation.empty()) {
        const Quat q = quat_from_xyzw(n.rotation.data());
        if (!(q.norm() >= 1e-6)) return bad(dot(path, "rotation"), "not a rotation (a zero quaternion)");
        rest_rotate_[i] = q.normalized();
      }
    }
    if (!rest_translate_[i].allFinite()) return bad(path, "the translation overflows at this scale");
  }
  return check_finite_world();
}

// Numbers that are finite one by one can still overflow together: a matrix
// of 1e308 decomposes into an infinite scale, and a chain of large scales
// multiplies out to infinity. Every node's decomposed transform, local
// matrix and world matrix (and the world matrix's decomposition, which is
// what reports print) must be finite; the first node that breaks it is named.
Status Importer::check_finite_world() {
  const std::size_t count = m_.nodes.size();
  auto finite = [](const math::Decomposed& d) {
    return d.translate.allFinite() && d.rotation.coeffs().allFinite() && d.scale.allFinite() && d.shear.allFinite();
  };
  auto name_of = [&](std::size_t i) {
    return at("nodes", i) + (m_.nodes[i].name.empty() ? std::string() : " (" + quote_text(m_.nodes[i].name) + ")");
  };
  std::vector<Mat4> world(count, Mat4::Identity());
  std::vector<bool> done(count, false);
  std::vector<std::size_t> chain;
  for (std::size_t start = 0; start < count; ++start) {
    chain.clear();
    for (int x = static_cast<int>(start); x >= 0 && !done[static_cast<std::size_t>(x)]; x = parent_[static_cast<std::size_t>(x)])
      chain.push_back(static_cast<std::size_t>(x));
    for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
      const std::size_t i = *it;
      const tinygltf::Node& n = m_.nodes[i];
      Mat4 local = math::trs_matrix(rest_translate_[i], rest_rotate_[i], rest_scale_[i]);
      if (!n.matrix.empty()) {
        local = Eigen::Map<const Mat4>(n.matrix.data());
        local.topRightCorner<3, 1>() *= options_.scale;
        if (!finite(math::decompose(local)))
          return bad(name_of(i), "its matrix overflows when decomposed into translation, rotation, scale and shear");
      }
      if (!local.allFinite()) return bad(name_of(i), "its local transform overflows (numbers beyond a double's range)");
      const int parent = parent_[i];
      world[i] = parent >= 0 ? Mat4(world[static_cast<std::size_t>(parent)] * local) : local;
      if (!world[i].allFinite() || !finite(math::decompose(world[i])))
        return bad(name_of(i), "its world matrix overflows (the transforms down to it multiply out of a double's range)");
      done[i] = true;
    }
  }
  return Status::ok();
}

Status Importer::check_scenes() {
  for (std::size_t s = 0; s < m_.scenes.size(); ++s) {
    const auto& roots = m_.scenes[s].nodes;
    std::set<int> in_scene;
    for (std::size_t k = 0; k < roots.size(); ++k) {
      const int n = roots[k];
      if (parent_[static_cast<std::size_t>(n)] >= 0)
        return bad(at(dot(at("scenes", s), "nodes"), k), "node " + std::to_string(n) + " is not a root (it is a child of node " +
                                                             std::to_string(parent_[static_cast<std::size_t>(n)]) + ")");
      if (!in_scene.insert(n).second) return bad(at(dot(at("scenes", s), "nodes"), k), "node " + std::to_string(n) + " is listed twice");
    }
    for (std::size_t i = 0; i < m_.nodes.size(); ++i) {
      const int skin = m_.nodes[i].skin;
      if (skin < 0 || !in_scene.count(root_[i])) continue;
      const auto& joints = m_.skins[static_cast<std::size_t>(skin)].joints;
      for (std::size_t k = 0; k < joints.size(); ++k) {
        if (!in_scene.count(root_[static_cast<std::size_t>(joints[k])]))
          return bad(at("nodes", i), "its skinned mesh is in scenes[" + std::to_string(s) + "], which does not hold its joints (skins[" +
                                         std::to_string(skin) + "].joints[" + std::to_string(k) + "] = node " +
                                         std::to_string(joints[k]) + ")");
      }
    }
  }
  return Status::ok();
}

Status Importer::build_nodes() {
  Graph& g = scene_->graph();
  const std::size_t count = m_.nodes.size();
  ids_.resize(count);
  blend_shapes_.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    const tinygltf::Node& n = m_.nodes[i];
    const std::string path = at("nodes", i);
    Result<NodeId> id = g.create_node(is_joint_[i] ? scene::kJointType : scene::kTransformType,
                                      node_name(n.name, "node_" + std::to_string(i)));
    if (!id) return id.status().with_context(path);
    ids_[i] = *id;
    namespace x = scene::xform;
    Status s = set(*id, x::kTranslate, rest_translate_[i]);
    if (s) s = set(*id, x::kRotateMode, x::kQuaternionMode);
    if (s) s = set(*id, x::kRotateQuaternion, rest_rotate_[i]);
    if (s) s = set(*id, x::kScale, rest_scale_[i]);
    if (s && !n.matrix.empty()) s = set(*id, x::kShear, math::decompose(Eigen::Map<const Mat4>(n.matrix.data())).shear);
    if (!s) return s.with_context(path);
  }
  for (std::size_t i = 0; i < count; ++i) {
    if (parent_[i] < 0) continue;
    if (Status s = g.set_parent(ids_[i], ids_[static_cast<std::size_t>(parent_[i])]); !s) return s.with_context(at("nodes", i));
  }
  return Status::ok();
}

}  // namespace rigel::io::gltf_importer
