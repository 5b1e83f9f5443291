#pragma once
// Scene files as a user names them (the `app` layer, below every driver):
// opening a scene or importing a character, what a file holds, the clip
// that plays, exporting to glTF and baking. The CLI's inspect, eval,
// import, export and bake, the server's scene and Python's open are these.

#include <cstddef>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/io/gltf_export.h"
#include "rigel/scene/scene.h"
#include "rigel/tools/bake.h"

namespace rigel::app {

namespace fs = std::filesystem;

// How a character is imported: `scale` multiplies lengths (0.0254: inches
// to metres; positive and finite), `skip_end_sites` drops BVH End Sites.
struct OpenOptions {
  double scale = 1.0;
  bool skip_end_sites = false;
};

// What an import read: the scene, what the importer said it did that the
// file did not ask for (glTF), and the counts a summary shows. For a BVH
// file `joints` counts the file's joints and `frames` its frames; for a
// glTF `joints`, `meshes` and `clips` count the scene's.
struct Imported {
  std::unique_ptr<scene::Scene> scene;
  std::vector<std::string> warnings;
  std::size_t joints = 0, meshes = 0, clips = 0, frames = 0;
  bool motion = false;  // a .bvh
};

// Whether `path` names a character an import reads (.glb, .gltf, .bvh),
// by its extension.
bool is_importable(const fs::path& path);
// Imports a character (.glb/.gltf or .bvh, by extension) over every node
// type of this build (ephemeral::default_registry()). Another extension is
// kInvalidArgument naming "input" ("unsupported file type"), a scale not
// positive and finite kInvalidArgument naming "scale".
Result<Imported> import_character(const fs::path& path, const OpenOptions& options = {});

// Opens what a user names as a scene: a character imported (as
// import_character), anything else read as a .rigel file; every node type
// of this build. Errors name the file.
Result<std::unique_ptr<scene::Scene>> open_scene(const fs::path& path, const OpenOptions& options = {});
// Whether `path` is a .rigel scene file (what a save may write over; a
// character a scene was imported from is not), by its extension.
bool is_scene_file(const fs::path& path);

// Makes `clip` (a name or an index, DESIGN.md's "--clip NAME|INDEX") the
// scene's active animation clip when given, and returns the name of the
// clip that plays (nullopt when the scene has none). A clip asked of a
// scene without clips, or one it does not have, is kNotFound naming "clip".
Result<std::optional<std::string>> play_clip(scene::Scene& scene, const std::optional<std::string>& clip);

// Whether an export may write `path`: a .glb or .gltf (by extension;
// another is kInvalidArgument naming "output").
Status check_export_path(const fs::path& path);
// Writes a .glb or .gltf (check_export_path first), io::export_gltf's
// rules otherwise.
Status export_scene(scene::Scene& scene, const fs::path& path, const io::GltfExportOptions& options,
                    io::GltfExportReport* report);

// Bakes frames [first, last] of the named transforms (none: every joint)
// into keys (tools::bake). A name the scene lacks is kNotFound naming
// "nodes". The scene's undo history is cleared when `keep_history` is false
// (a one-shot run has no undo, and the bake's records would stay in memory).
Result<tools::BakeReport> bake_nodes(scene::Scene& scene, double first, double last,
                                     const std::vector<std::string>& nodes,
                                     std::function<void(double)> progress = {}, bool keep_history = true);

}  // namespace rigel::app
