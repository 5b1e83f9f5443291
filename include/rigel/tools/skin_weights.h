#pragma once
// Skin weights as data (seed 004 §4.10's SkinManager): every skinCluster's
// weights exported to diffable JSON and imported back, onto the same
// skeleton, a copy with renamed joints (a name table) or another skeleton
// (the nearest joint by bind position), or mirrored across the
// character's plane, so a rebuild from scratch gets the painted weights
// back. A file:
//
//   {
//     "rigelWeights": 1,
//     "skins": [
//       {
//         "skin": "body_skinCluster",
//         "mesh": "body",
//         "vertexCount": 10037,
//         "influences": [
//           {"joint": "spine", "uuid": "...", "bind": [x, y, z]},
//           ...
//         ],
//         "vertices": [
//           [0, 0.75, 3, 0.25],          one line per vertex: influence, weight, ...
//           ...
//         ]
//       }
//     ]
//   }
//
// `bind` is the joint's world position at bind (its inverse bind matrix's
// inverse); influences are the skin's joint list in order (a skin's extra
// entry for unweighted vertices, the mesh node itself, is listed with its
// name too). Numbers are written shortest round-trip, so export after
// import gives the same file byte for byte.
//
// Large arrays may go to a binary side file instead (the format "binary",
// the setting data.weights): each skin has "block": {"offset", "entries"}
// in place of "vertices", and the file names its side file with its size
// and checksum:
//
//   "binary": {"file": "body.weights.3f2a9c1e.bin", "bytes": 602290, "checksum": "fnv1a64:..."}
//
// The side file lies beside the weights file; its name holds the start of
// its checksum, so a new export never overwrites the side file an older
// weights file names (the pair is replaced atomically: the side file
// first, the JSON last, the old side file removed after). It is "RIGELWB1",
// then per skin: each vertex's influence count (uint32), every entry's
// influence (uint32), every entry's weight (float64), little-endian.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/math/types.h"
#include "rigel/scene/scene.h"

namespace rigel::tools {

inline constexpr int kWeightsFormat = 1;

struct SkinInfluence {
  std::string joint, uuid;
  math::Vec3 bind = math::Vec3::Zero();
};

struct SkinWeights {
  std::string skin, mesh;
  std::vector<SkinInfluence> influences;
  // Per vertex v: influences offsets[v] .. offsets[v + 1] - 1 of joints and weights.
  std::vector<std::int64_t> offsets, joints;
  std::vector<double> weights;
  std::size_t vertex_count() const { return offsets.empty() ? 0 : offsets.size() - 1; }
};

// Every skinCluster of the scene (in creation order), as evaluated now.
// kInvalidArgument when it has none.
Result<std::vector<SkinWeights>> capture_skin_weights(scene::Scene& scene);

enum class WeightsFormat { kJson, kBinary };
// "json" or "binary" (the setting data.weights); kInvalidArgument else.
Result<WeightsFormat> weights_format_named(std::string_view name);

// The file, all in JSON.
std::string skin_weights_to_json(const std::vector<SkinWeights>& skins);

struct WeightsFiles {
  std::string json;
  std::string side_name, side;  // the binary side file (kBinary only)
};
// The file in `format`; the side file is named `stem`.CHECKSUM8.bin
// (stem: the weights file's name without ".json").
WeightsFiles skin_weights_to_files(const std::vector<SkinWeights>& skins, WeightsFormat format, const std::string& stem);

// The bytes of the side file a weights file names (a plain file name).
using SideFileReader = std::function<Result<std::string>(const std::string& name)>;
// kParseError naming `source` and the place (line:column, or the member:
// "skins[0].vertices[12]", "binary.checksum") for text that is not a
// weights file or a side file that is not the one it was written with.
// A file with a side file needs `read_side`.
Result<std::vector<SkinWeights>> skin_weights_from_json(std::string_view text, const std::string& source,
                                                        const SideFileReader& read_side = {});

// Reads side files from `file`'s folder.
SideFileReader side_files_beside(const std::filesystem::path& file);

// Writes `file` (and its side file, for kBinary) atomically; a side file
// the old `file` named is removed once the new pair is written.
Status write_skin_weights(const std::filesystem::path& file, const std::vector<SkinWeights>& skins, WeightsFormat format);
// Reads `file` and the side file it names, from its folder only.
Result<std::vector<SkinWeights>> read_skin_weights(const std::filesystem::path& file);

struct WeightsImport {
  // File joint name -> scene joint name, for joints the scene names otherwise.
  std::map<std::string, std::string> rename;
  // A joint found neither by uuid nor by name (after `rename`): the
  // target skin's joint nearest its bind position.
  bool nearest = false;
  // Each vertex takes the weights of the file's vertex nearest its mirror
  // image (x -> -x, by bind points), each joint swapped for the joint of
  // the other side's name (rig::mirror_name; a centre joint stays).
  bool mirror = false;
};

struct WeightsReport {
  std::size_t skins = 0, vertices = 0;
  std::vector<std::string> remapped;  // "file joint -> scene joint" for those not matched by uuid
};

// Sets the weights of each file skin onto the scene's skin of the same
// name (else the skin of the mesh of the same name), its influences
// matched to the skin's joints by uuid, else name (after `rename`), else
// (with `nearest`) position. One undo step; on failure nothing changes.
// kInvalidArgument naming the skin for one the scene lacks or a vertex
// count that differs, naming the joint for one it cannot match.
Result<WeightsReport> apply_skin_weights(scene::Scene& scene, const std::vector<SkinWeights>& skins,
                                         const WeightsImport& options = {});

}  // namespace rigel::tools
