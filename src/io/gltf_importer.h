// Private to rigel_io: the glTF importer, turning a model tinygltf loaded
// (after gltf_json_checks.h) into a rigel Scene. Its checks of what the JSON
// cannot say (hierarchy, skins, accessor contents) run first, then reading
// (meshes, animations), then building the scene; io/gltf_import.h documents
// the mapping. One file per concept: gltf_import.cc (the driver),
// gltf_import_nodes.cc, gltf_import_meshes.cc, gltf_import_animation.cc.
#pragma once

#include <tiny_gltf.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "rigel/graph/graph.h"
#include "rigel/io/gltf_import.h"
#include "rigel/math/transform.h"
#include "rigel/ops/anim/track.h"
#include "rigel/scene/scene.h"

#include "gltf_accessors.h"
#include "gltf_materials.h"
#include "gltf_messages.h"

namespace rigel::io::gltf_importer {

using gltf::at;
using gltf::bad;
using gltf::dot;
using gltf::kByte;
using gltf::kFloat;
using gltf::kShort;
using gltf::kUnsignedByte;
using gltf::kUnsignedInt;
using gltf::kUnsignedShort;
using gltf::node_name;
using gltf::Path;
using gltf::quote_text;
using graph::Graph;
using graph::NodeId;
using graph::Plug;
using math::Mat4;
using math::Quat;
using math::Vec3;

// glTF's [x, y, z, w] as a quaternion.
inline Quat quat_from_xyzw(const double* v) { return Quat(v[3], v[0], v[1], v[2]); }

// One animated channel's keys in one clip, flattened: `width` numbers per key
// (3 for translation/scale, 4 for rotation [x, y, z, w], the morph target
// count for weights).
struct ClipKeys {
  ops::anim::Interpolation interpolation = ops::anim::Interpolation::kLinear;
  std::vector<double> times;
  std::vector<double> values;
  std::vector<double> in_tangents;   // cubic only
  std::vector<double> out_tangents;  // cubic only
};

struct Channel {
  int node = 0;
  Path path = Path::kTranslation;
  std::vector<std::optional<ClipKeys>> clips;  // one per glTF animation
};

// A primitive's data, read once per mesh.
struct PrimitiveData {
  bool make_node = false;  // triangles (or strips, fans) with POSITION
  std::size_t vertex_count = 0;
  std::vector<Vec3> points, normals;
  std::vector<std::int64_t> triangles;
  std::vector<std::vector<Vec3>> target_deltas;
  // Skin data of every JOINTS_n/WEIGHTS_n set, interleaved per vertex:
  // vertex v owns [v * per_vertex, (v + 1) * per_vertex).
  std::vector<int> sets;  // the n of each set, ascending
  std::size_t per_vertex = 0;
  std::vector<std::int64_t> joints;
  std::vector<double> weights;
};

// A skinned primitive's influences as the skinCluster takes them; vertices
// without a weight above zero are bound to one extra joint matrix (index =
// the skin's joint count), the world matrix of the glTF node holding the mesh.
struct SkinBinding {
  std::vector<std::int64_t> offsets, joints;
  std::vector<double> weights;
  std::vector<std::size_t> unweighted;
};

struct MeshData {
  std::vector<PrimitiveData> primitives;
  std::size_t target_count = 0;
  std::vector<std::string> target_names;  // extras.targetNames, one per target; empty: unnamed
};

class Importer {
 public:
  Importer(const tinygltf::Model& model, const GltfImportOptions& options, bool quantized)
      : m_(model), options_(options), quantized_(quantized), accessors_(model) {}

  Result<std::unique_ptr<scene::Scene>> run();

  // After run(): the mesh nodes made, with their primitives, and the
  // accessor reader, for the materials and uv sets (gltf_materials.h).
  std::span<const gltf_look::MeshSource> mesh_sources() const { return mesh_sources_; }
  Result<const std::vector<double>*> accessor_values(int accessor) { return read(accessor); }

 private:
  // checks and reading
  Result<const std::vector<double>*> read(int accessor) { return accessors_.read(accessor); }
  Status check_hierarchy();
  Status check_skins();
  Status check_nodes();
  Status check_finite_world();
  Status check_scenes();
  Status read_meshes();
  Status read_primitive(std::size_t m, std::size_t p, PrimitiveData& out);
  Status read_skin_sets(const tinygltf::Primitive& prim, const std::string& attr_path, std::size_t count, PrimitiveData& out);
  Status read_targets(const tinygltf::Primitive& prim, const std::string& path, const std::string& reference, std::size_t count,
                      PrimitiveData& out);
  Status read_surface(const tinygltf::Primitive& prim, const std::string& path, std::size_t count, bool has_position,
                      PrimitiveData& out);
  Result<std::vector<SkinBinding>> bind_skin(std::size_t node);
  Status read_animations();
  Status read_channel(std::size_t a, std::size_t c, ClipKeys& out, std::size_t width, Path path);

  // building
  Status build_nodes();
  Status build_meshes();
  Status build_animations();
  Status build_track(const Channel& channel, NodeId clips);
  Status build_weight_curves(const Channel& channel, NodeId clips);

  Status set(NodeId node, graph::AttrIndex attr, graph::Value value);
  Status connect(NodeId src, graph::AttrIndex src_attr, NodeId dst, graph::AttrIndex dst_attr, std::int32_t element = -1);

  std::string accessor_summary(int index) const { return accessors_.summary(index); }
  using Allowed = std::vector<std::pair<int, bool>>;  // (component type, normalized)
  Status require(const std::string& where, int index, int type, const Allowed& allowed, const char* expected) const;
  Allowed position_types() const;
  Allowed normal_types() const;

  const tinygltf::Model& m_;
  GltfImportOptions options_;
  bool quantized_ = false;
  std::unique_ptr<scene::Scene> scene_;

  gltf::AccessorReader accessors_;  // accessor values, read once
  std::vector<int> parent_;         // per node, -1 for a root
  std::vector<int> root_;           // per node, the root of its hierarchy
  std::vector<bool> is_joint_;
  std::vector<std::vector<Mat4>> inverse_bind_;  // per skin, one per joint
  std::vector<MeshData> meshes_;
  std::vector<Channel> channels_;   // sorted by (node, path)
  std::vector<std::string> clip_names_;
  std::vector<double> clip_starts_, clip_ends_;

  std::vector<NodeId> ids_;         // per glTF node
  std::vector<Vec3> rest_translate_, rest_scale_;
  std::vector<Quat> rest_rotate_;
  std::vector<std::vector<NodeId>> blend_shapes_;  // per glTF node
  std::vector<gltf_look::MeshSource> mesh_sources_;
};

}  // namespace rigel::io::gltf_importer
