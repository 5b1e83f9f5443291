// The glTF exporter: the collected nodes, meshes, skins and animations
// written into a tinygltf model, with the looks of the meshes
// (gltf_materials.h), and the model into the file.
#include "gltf_exporter.h"

#include <algorithm>
#include <limits>
#include <map>
#include <set>
#include <span>
#include <sstream>

#include "rigel/io/scene_file.h"

#include "gltf_materials.h"

namespace rigel::io::gltf_exporter {
namespace {

std::vector<double> flatten(std::span<const Vec3> points) {
  std::vector<double> out;
  out.reserve(points.size() * 3);
  for (const Vec3& p : points) out.insert(out.end(), {p.x(), p.y(), p.z()});
  return out;
}

}  // namespace

Status Exporter::write(const fs::path& out, bool binary) {
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "rigel";
  BufferWriter buffer(model);

  // Merged mesh nodes (merge_mesh_nodes) are no glTF node: every index
  // into nodes_ goes through `out` (a merged one: its owner's).
  std::vector<int> index_out(nodes_.size(), -1);
  int written = 0;
  for (std::size_t i = 0; i < nodes_.size(); ++i)
    if (nodes_[i].merged_into < 0) index_out[i] = written++;
  for (std::size_t i = 0; i < nodes_.size(); ++i)
    if (nodes_[i].merged_into >= 0) index_out[i] = index_out[static_cast<std::size_t>(nodes_[i].merged_into)];
  for (AnimationExport& a : animations_) {
    // A merged mesh node's own transform channels have no node to go to
    // (its transform is identity, or ignored when skinned); its morph
    // weights go to its owner, which holds the mesh.
    std::erase_if(a.channels, [&](const Channel& ch) {
      return nodes_[static_cast<std::size_t>(ch.node)].merged_into >= 0 && ch.path != Path::kWeights;
    });
    for (Channel& ch : a.channels) nodes_[static_cast<std::size_t>(ch.node)].animated = true;
  }
  animations_.erase(std::remove_if(animations_.begin(), animations_.end(),
                                   [](const AnimationExport& a) { return a.channels.empty(); }),
                    animations_.end());

  for (const ExportNode& n : nodes_) {
    if (n.merged_into >= 0) continue;
    tinygltf::Node node;
    node.name = name(n.id);
    // The node's rigel uuid, so a client (the web app) maps glTF nodes back
    // to scene nodes whatever their names become.
    node.extras = tinygltf::Value(tinygltf::Value::Object{{"uuid", tinygltf::Value(g_.node(n.id)->uuid().str())}});
    for (int c : n.children)
      if (nodes_[static_cast<std::size_t>(c)].merged_into < 0) node.children.push_back(index_out[static_cast<std::size_t>(c)]);
    {  // TRS, never `matrix`: shear was dropped (rest_pose)
      if (n.rest.translate != Vec3::Zero()) node.translation = {n.rest.translate.x(), n.rest.translate.y(), n.rest.translate.z()};
      const Quat& q = n.rest.rotation;
      if (q.coeffs() != Quat::Identity().coeffs()) node.rotation = {q.x(), q.y(), q.z(), q.w()};
      if (n.rest.scale != Vec3::Ones()) node.scale = {n.rest.scale.x(), n.rest.scale.y(), n.rest.scale.z()};
    }
    if (const int mesh = n.mesh >= 0 ? n.mesh : n.owned_mesh; mesh >= 0) {
      const MeshExport& m = meshes_[static_cast<std::size_t>(mesh)];
      node.mesh = static_cast<int>(model.meshes.size());
      node.skin = m.skin;
      model.meshes.push_back(write_mesh(m, buffer));
    }
    model.nodes.push_back(std::move(node));
  }

  // glTF wants a skin's joints under one common root; rigel lets them sit
  // in separate trees. Such trees go under one added identity node.
  const std::vector<int> grouped = roots_to_group();
  if (!grouped.empty()) {
    tinygltf::Node group;
    group.name = unused_name("skeleton_root");
    for (int r : grouped) group.children.push_back(index_out[static_cast<std::size_t>(r)]);
    model.nodes.push_back(std::move(group));
    report_.notes.push_back("the joints of a skin sit in " + std::to_string(grouped.size()) +
                            " separate trees; glTF asks for one common root, so '" + model.nodes.back().name +
                            "' (identity) holds them");
  }

  write_skins(model, buffer, index_out);
  write_animations(model, buffer, index_out);

  // Materials, textures, uv sets and colours of the meshes (gltf_materials.h).
  gltf_look::LookWriter looks(g_, model, buffer.bytes(), report_.notes);
  for (std::size_t k = 0; k < written_meshes_.size() && k < model.meshes.size(); ++k) {
    if (Status s = looks.write(written_meshes_[k], static_cast<int>(k)); !s) return s;
  }

  if (!buffer.error().empty()) return error(ErrorCode::kInvalidArgument, buffer.error());
  if (binary && buffer.bytes().size() > std::numeric_limits<std::uint32_t>::max() - 4096u)
    return error(ErrorCode::kInvalidArgument, out.string() + ": more than 4 GiB of data, beyond what .glb holds");
  if (!buffer.bytes().empty()) {
    tinygltf::Buffer data;
    data.data = std::move(buffer.bytes());
    model.buffers.push_back(std::move(data));
  }
  if (!nodes_.empty()) {
    tinygltf::Scene gltf_scene;
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
      const bool in_group = std::find(grouped.begin(), grouped.end(), static_cast<int>(i)) != grouped.end();
      if (nodes_[i].parent < 0 && !in_group && nodes_[i].merged_into < 0) gltf_scene.nodes.push_back(index_out[i]);
    }
    if (!grouped.empty()) gltf_scene.nodes.push_back(written);
    model.scenes.push_back(std::move(gltf_scene));
    model.defaultScene = 0;
  }

  // tinygltf writes to a stream (buffers embedded for .gltf, the BIN chunk
  // for .glb); the bytes then go through the atomic writer, which checks
  // every write (tinygltf's own file writer does not) and renames.
  std::ostringstream stream(std::ios::binary);
  tinygltf::TinyGLTF gltf;
  if (!gltf.WriteGltfSceneToStream(&model, stream, !binary, binary) || !stream)
    return error(ErrorCode::kIoError, out.string() + ": tinygltf could not serialise the model");
  if (Status s = write_file_atomic(out, stream.str()); !s) return s;

  report_.node_count = model.nodes.size();
  report_.mesh_count = model.meshes.size();
  report_.skin_count = model.skins.size();
  report_.animation_count = model.animations.size();
  return Status::ok();
}

void Exporter::write_skins(tinygltf::Model& model, BufferWriter& buffer, std::span<const int> index_out) {
  for (const SkinExport& s : skins_) {
    tinygltf::Skin skin;
    skin.name = s.name;
    for (int j : s.joints) skin.joints.push_back(index_out[static_cast<std::size_t>(j)]);
    std::vector<double> matrices;
    for (const Mat4& m : s.inverse_bind) matrices.insert(matrices.end(), m.data(), m.data() + 16);
    skin.inverseBindMatrices =
        buffer.floats(matrices, TINYGLTF_TYPE_MAT4, 16, 0, false, s.name + ".bindPreMatrices");
    model.skins.push_back(std::move(skin));
  }
}

void Exporter::write_animations(tinygltf::Model& model, BufferWriter& buffer, std::span<const int> index_out) {
  for (const AnimationExport& a : animations_) {
    tinygltf::Animation animation;
    animation.name = a.name;
    for (const Channel& ch : a.channels) {
      const std::string what = "animation '" + a.name + "', " + name(nodes_[static_cast<std::size_t>(ch.node)].id) +
                               " " + path_name(ch.path);
      tinygltf::AnimationSampler sampler;
      sampler.interpolation = ch.interpolation;
      sampler.input = buffer.shared_times(ch.times, what + " times");
      if (ch.path == Path::kWeights)
        sampler.output = buffer.floats(ch.values, TINYGLTF_TYPE_SCALAR, 1, 0, false, what);
      else if (ch.path == Path::kRotation)
        sampler.output = buffer.floats(ch.values, TINYGLTF_TYPE_VEC4, 4, 0, false, what);
      else
        sampler.output = buffer.floats(ch.values, TINYGLTF_TYPE_VEC3, 3, 0, false, what);
      tinygltf::AnimationChannel channel;
      channel.sampler = static_cast<int>(animation.samplers.size());
      channel.target_node = index_out[static_cast<std::size_t>(ch.node)];
      channel.target_path = path_name(ch.path);
      animation.samplers.push_back(std::move(sampler));
      animation.channels.push_back(std::move(channel));
      ++report_.channel_count;
    }
    model.animations.push_back(std::move(animation));
  }
}

std::vector<int> Exporter::roots_to_group() const {
  std::set<int> group;
  for (const SkinExport& s : skins_) {
    std::set<int> tops;
    for (int j : s.joints) {
      while (nodes_[static_cast<std::size_t>(j)].parent >= 0) j = nodes_[static_cast<std::size_t>(j)].parent;
      tops.insert(j);
    }
    if (tops.size() > 1) group.insert(tops.begin(), tops.end());
  }
  return std::vector<int>(group.begin(), group.end());
}

std::string Exporter::unused_name(const std::string& wanted) const {
  std::string candidate = wanted;
  for (int k = 1; g_.find(candidate).is_valid(); ++k) candidate = wanted + std::to_string(k);
  return candidate;
}

tinygltf::Mesh Exporter::write_mesh(const MeshExport& m, BufferWriter& buffer) {
  const std::string& mesh_name = name(nodes_[m.node].id);
  written_meshes_.push_back(nodes_[m.node].id);  // the caller pushes this mesh onto model.meshes next
  tinygltf::Mesh mesh;
  mesh.name = mesh_name;
  tinygltf::Primitive primitive;
  primitive.mode = TINYGLTF_MODE_TRIANGLES;
  primitive.attributes["POSITION"] = buffer.floats(flatten(m.points), TINYGLTF_TYPE_VEC3, 3,
                                                   TINYGLTF_TARGET_ARRAY_BUFFER, true, mesh_name + " points");
  if (!m.normals.empty())
    primitive.attributes["NORMAL"] = buffer.floats(flatten(m.normals), TINYGLTF_TYPE_VEC3, 3,
                                                   TINYGLTF_TARGET_ARRAY_BUFFER, false, mesh_name + " normals");
  // 65535 is the primitive-restart value, which glTF indices must not hold.
  if (m.points.size() <= 65535) {
    std::vector<std::uint16_t> indices(m.triangles.begin(), m.triangles.end());
    primitive.indices = buffer.integers(std::span<const std::uint16_t>(indices), TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                                        TINYGLTF_TYPE_SCALAR, indices.size(), TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
  } else {
    std::vector<std::uint32_t> indices(m.triangles.begin(), m.triangles.end());
    primitive.indices = buffer.integers(std::span<const std::uint32_t>(indices), TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT,
                                        TINYGLTF_TYPE_SCALAR, indices.size(), TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
  }
  if (m.skin >= 0) {
    const std::size_t joint_count = skins_[static_cast<std::size_t>(m.skin)].joints.size();
    const std::size_t stride = m.sets * 4;
    for (std::size_t set = 0; set < m.sets; ++set) {
      std::vector<double> weights;
      std::vector<std::uint16_t> joints16;
      std::vector<std::uint8_t> joints8;
      for (std::size_t v = 0; v < m.points.size(); ++v) {
        for (std::size_t k = 0; k < 4; ++k) {
          const std::size_t at = v * stride + set * 4 + k;
          weights.push_back(m.joint_weights[at]);
          joints16.push_back(m.joints[at]);
          joints8.push_back(static_cast<std::uint8_t>(m.joints[at]));
        }
      }
      const std::string suffix = "_" + std::to_string(set);
      primitive.attributes["JOINTS" + suffix] =
          joint_count <= 256
              ? buffer.integers(std::span<const std::uint8_t>(joints8), TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                                TINYGLTF_TYPE_VEC4, m.points.size(), TINYGLTF_TARGET_ARRAY_BUFFER)
              : buffer.integers(std::span<const std::uint16_t>(joints16), TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                                TINYGLTF_TYPE_VEC4, m.points.size(), TINYGLTF_TARGET_ARRAY_BUFFER);
      primitive.attributes["WEIGHTS" + suffix] = buffer.floats(weights, TINYGLTF_TYPE_VEC4, 4, TINYGLTF_TARGET_ARRAY_BUFFER,
                                                               false, mesh_name + " weights");
    }
  }
  for (std::size_t t = 0; t < m.targets.size(); ++t) {
    std::map<std::string, int> target;
    target["POSITION"] = buffer.floats(flatten(m.targets[t]), TINYGLTF_TYPE_VEC3, 3, TINYGLTF_TARGET_ARRAY_BUFFER,
                                       true, mesh_name + " morph target " + std::to_string(t));
    primitive.targets.push_back(std::move(target));
  }
  mesh.weights = m.weights;
  if (!m.target_names.empty()) {  // the common convention for morph target names
    tinygltf::Value::Array names;
    for (const std::string& n : m.target_names) names.emplace_back(n);
    mesh.extras = tinygltf::Value(tinygltf::Value::Object{{"targetNames", tinygltf::Value(std::move(names))}});
  }
  mesh.primitives.push_back(std::move(primitive));
  return mesh;
}

}  // namespace rigel::io::gltf_exporter
