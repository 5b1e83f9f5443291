// Private to rigel_io: the glTF JSON checked before tinygltf reads it.
// tinygltf skips members of the wrong type silently (a "skin": "x" would
// make a skinned mesh static) and keeps indices unchecked, so every member
// the importer relies on is checked here: types, required members, indices
// in range, buffer and view bounds, external buffer files. Messages name
// the place ("nodes[3].children[0]: node 9 does not exist").
#pragma once

#include "rigel/base/status.h"

#include "gltf_container.h"

namespace rigel::io::gltf_importer {

// Checks the whole document; fills in ctx.buffer_files (the external
// buffers tinygltf may read) and ctx.quantized.
Status check_json(const Json& doc, SchemaContext& ctx);

}  // namespace rigel::io::gltf_importer
