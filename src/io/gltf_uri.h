// The files a glTF file's external URIs (buffers, images) may name: private
// to the io layer, shared by the importer (gltf_import.cc) and the look
// import (gltf_materials.cc), so both confine reads to the same rule
// (docs/INTERCHANGE.md).
#pragma once

#include <filesystem>
#include <string>

#include "rigel/base/status.h"

namespace rigel::io::gltf_uri {

// tinygltf's URI decoding (dlib::urldecode), so that the file checked is the
// file tinygltf asks for.
std::string url_decode(const std::string& text);

// tinygltf's JoinPath.
std::string join_path(const std::string& dir, const std::string& file);

// Whether `path` (absolute, links resolved) lies inside `folder` (likewise).
bool inside(const std::filesystem::path& folder, const std::filesystem::path& path);

// The glTF file's folder (`base_dir`, as tinygltf joins paths; empty for the
// current directory), absolute, symbolic links resolved.
Result<std::filesystem::path> resolved_folder(const std::string& base_dir, const std::string& where);

// The file an external URI names, as tinygltf will ask for it: the URI
// decoded and joined to `base_dir`. Only relative names that stay inside
// `folder` (resolved_folder(base_dir)) are allowed: no scheme (file:,
// http:), no absolute path, no ".." that climbs out, and no symbolic link
// (in the name or the folders on the way) that leads out; checked on the
// resolved path, so the file read is the file checked, and it must be a
// regular file. Refusals name `where` and the URI, never anything about the
// file it pointed at (its size, its bytes).
Result<std::string> confined_file(const std::filesystem::path& folder, const std::string& base_dir,
                                  const std::string& uri, const std::string& where);

}  // namespace rigel::io::gltf_uri
