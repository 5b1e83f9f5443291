#pragma once
// Private to rigel_io: the look of glTF meshes (materials, textures,
// samplers, images, TEXCOORD_0/1, COLOR_0) on import and export, kept apart
// from the importer and the exporter (gltf_importer.h, gltf_exporter.h),
// which call in here once each. The scene side is scene/materials.h; the
// mapping is documented there, in io/gltf_import.h, io/gltf_export.h and
// docs/ARCHITECTURE.md.

#include <tiny_gltf.h>

#include <functional>
#include <map>
#include <span>
#include <string>
#include <tuple>
#include <vector>

#include <nlohmann/json.hpp>

#include "rigel/base/status.h"
#include "rigel/graph/graph.h"
#include "rigel/scene/scene.h"

namespace rigel::io::gltf_look {

// RFC 4648 base64 with padding; decode refuses anything else, naming the
// offending character's position.
std::string base64_encode(std::span<const unsigned char> bytes);
Result<std::vector<unsigned char>> base64_decode(std::string_view text);

// An image file larger than this is refused on import.
inline constexpr std::uint64_t kMaxImageBytes = std::uint64_t{256} << 20;

// ---- import ----

// One mesh node the importer made, and the primitive it came from.
struct MeshSource {
  graph::NodeId mesh;
  std::size_t gltf_mesh = 0;
  std::size_t primitive = 0;
};

// The importer's accessor reader (normalisation and sparse applied, NaN refused).
using AccessorReader = std::function<Result<const std::vector<double>*>(int accessor)>;

// Gives each mesh of `meshes` its uv0/uv1 (TEXCOORD_0/1), colors (COLOR_0)
// and material, creating the `material` nodes those primitives use (in
// material order, after every other node) and the `texture` nodes those
// materials use (before them). `images` is the file's "images" array (or
// null): tinygltf never sees it, the bytes are read here from a bufferView,
// a data: URI or a file inside `base_dir` (symlinks resolved). Errors name
// the element ("materials[0].pbrMetallicRoughness.baseColorTexture.index:
// texture 4 does not exist").
Status import_looks(scene::Scene& scene, const tinygltf::Model& model, const nlohmann::json& images,
                    const std::string& base_dir, std::span<const MeshSource> meshes, const AccessorReader& read);

// ---- export ----

// Writes the look of mesh nodes onto the exported glTF model: each call adds
// TEXCOORD_n / COLOR_0 accessors to the mesh's primitives (bytes appended to
// the one buffer, 4-byte aligned) and its material, sharing materials,
// textures, samplers and images (identical bytes are stored once) between
// meshes. What glTF cannot carry is left out with a note.
class LookWriter {
 public:
  LookWriter(graph::Graph& graph, tinygltf::Model& model, std::vector<unsigned char>& bytes, std::vector<std::string>& notes)
      : g_(graph), model_(model), bytes_(bytes), notes_(notes) {}

  // `mesh` is a mesh node, exported as model.meshes[gltf_mesh].
  Status write(graph::NodeId mesh, int gltf_mesh);

 private:
  int view(const void* data, std::size_t size, int target);
  Result<int> floats(const std::vector<double>& values, int type, int components, const std::string& what);
  Result<int> material(graph::NodeId node);
  Result<int> texture(graph::NodeId node);
  std::string name(graph::NodeId node) const { return g_.node(node)->name(); }

  graph::Graph& g_;
  tinygltf::Model& model_;
  std::vector<unsigned char>& bytes_;
  std::vector<std::string>& notes_;
  std::map<std::uint64_t, int> materials_;  // NodeId packed -> glTF material (-1: not writable)
  std::map<std::uint64_t, int> textures_;   // NodeId packed -> glTF texture (-1: not writable)
  std::map<std::string, int> images_;       // image bytes -> glTF image
  std::map<std::tuple<int, int, int, int>, int> samplers_;
  std::map<int, std::vector<int>> material_uv_sets_;  // glTF material -> texCoords it uses
};

}  // namespace rigel::io::gltf_look
