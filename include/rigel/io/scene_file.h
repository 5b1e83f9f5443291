#pragma once
// The .rigel scene file: JSON, versioned, holding every node (uuid, name,
// type, parent, storable attribute values that differ from the default,
// tags), every connection, the frame rate and the current time.
//
//   { "rigel": "scene", "version": 1, "fps": 24, "time": 0,
//     "nodes": [ { "name": "hips", "type": "joint", "uuid": "...",
//                  "parent": "root", "attrs": { "translate": [0, 1, 0] },
//                  "tags": { "side": "C" } } ],
//     "connections": [ { "src": "a.worldMatrix", "dst": "b.offsetParentMatrix" } ] }
//
// Angles are degrees (as stored in the attributes), quaternions [x, y, z, w],
// matrices 16 numbers column-major, enums by name, non-finite numbers as the
// strings "nan", "inf", "-inf". Parents and connections name nodes by name
// (unique within a file); identity across renames is the uuid.

#include <filesystem>
#include <memory>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "rigel/base/status.h"
#include "rigel/scene/scene.h"

namespace rigel::io {

inline constexpr int kSceneFormatVersion = 1;

// Parses a scene from text. `source` names it in error messages ("file.rigel").
// Errors name the place: "file.rigel:12:5: ..." for syntax, and a path such
// as "file.rigel: nodes[3] (hips).attrs.translate: ..." for content.
// Node types come from `registry` (default: every type this build knows,
// ops::default_registry()).
Result<std::unique_ptr<scene::Scene>> parse_scene(std::string_view text, const std::string& source,
                                                  std::shared_ptr<const graph::Registry> registry = nullptr);
Result<std::unique_ptr<scene::Scene>> load_scene(const std::filesystem::path& path,
                                                 std::shared_ptr<const graph::Registry> registry = nullptr);

// Serialises a scene (evaluates it first so that connected array elements
// hold current values). Deterministic: the same scene gives the same text.
std::string write_scene(scene::Scene& scene);
// Writes atomically: a temporary file beside `path`, flushed, then renamed.
Status save_scene(scene::Scene& scene, const std::filesystem::path& path);

// One attribute value as scene files write it (enums by name, quaternions
// [x, y, z, w], matrices column-major, NaN/inf as strings), and back.
nlohmann::ordered_json attribute_to_json(const graph::Value& value, const graph::AttrSpec& spec);
Result<graph::Value> attribute_from_json(const nlohmann::ordered_json& json, const graph::AttrSpec& spec);

// File paths inside scenes. A string attribute declared here holds the path
// of another file (a rig's metaRoot.definitionPath). save_scene() writes it
// relative to the scene file's folder and load_scene() reads it back as an
// absolute path (symbolic links resolved), so the current directory plays
// no part and a scene saved elsewhere names the same file. In memory such a
// path is absolute (a relative one is taken from the current directory);
// write_scene() and parse_scene(), which know no file, leave it as it is.
// The layer that owns the node type declares it (rig::register_rig_types).
void declare_path_attribute(std::string_view node_type, std::string_view attr);
bool is_path_attribute(std::string_view node_type, std::string_view attr);
// `path` as a scene file in folder `folder` stores it (relative when it can
// be), and back.
std::string path_relative_to(const std::string& path, const std::filesystem::path& folder);
std::string path_from(const std::string& stored, const std::filesystem::path& folder);

// Writes `content` to `path` atomically (used by every rigel writer).
Status write_file_atomic(const std::filesystem::path& path, std::string_view content);

}  // namespace rigel::io
