// Private to rigel_io: a glTF file as the importer reads it. The bytes of a
// .gltf or .glb, the .glb container checked against the file's real size,
// the JSON parsed (depth-bounded), and the checked JSON handed to tinygltf
// with file access confined to the buffers the checks allowed.
#pragma once

#include <tiny_gltf.h>

#include <cstdint>
#include <filesystem>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "rigel/base/status.h"

namespace rigel::io::gltf_importer {

using Json = nlohmann::json;

// The file's bytes and where its parts lie.
struct Source {
  std::vector<unsigned char> bytes;  // the whole file
  bool binary = false;
  std::string_view json;             // the JSON text (a .glb's first chunk)
  bool has_bin = false;              // a .glb with a BIN chunk
  std::size_t bin_offset = 0;        // where the BIN chunk's 8-byte header starts
  std::uint64_t bin_length = 0;      // the BIN chunk's data length
};

// What the JSON checks (gltf_json_checks.h) learn of the file, for loading it.
struct SchemaContext {
  const Source* source = nullptr;
  std::string base_dir;                // the folder of the file, as tinygltf joins paths
  std::filesystem::path folder;        // that folder, absolute, symbolic links resolved
  std::set<std::string> buffer_files;  // external buffer files tinygltf may read
  bool quantized = false;              // KHR_mesh_quantization in extensionsUsed
};

// The whole of a regular file of at most 4 GiB.
Status read_file(const std::filesystem::path& path, std::vector<unsigned char>& out);

// Checks the .glb header and chunks against the file's real size, or finds
// the JSON text of a .gltf; fills in `s` past its bytes.
Status parse_container(Source& s);

// The JSON text parsed, refused when nested deeper than 128 levels.
Result<Json> parse_json(std::string_view text);

// Hands the checked JSON to tinygltf, without `images` (nothing of them is
// used, and a broken embedded picture should not stop a rig from loading);
// tinygltf reads only the files in ctx.buffer_files.
Result<tinygltf::Model> load_model(Json doc, const Source& source, SchemaContext& ctx);

}  // namespace rigel::io::gltf_importer
