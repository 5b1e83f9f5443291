#pragma once
// A rig definition built onto a character file (the `app` layer): what
// `rigel build` does, start to end. A Workspace's add_rig builds onto the
// scene it holds; this opens the character itself.

#include <cstddef>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/rig/build_graph.h"
#include "rigel/rig/component.h"
#include "rigel/rig/definition.h"
#include "rigel/rig/definition_io.h"
#include "rigel/scene/scene.h"

namespace rigel::app {

namespace fs = std::filesystem;

struct BuildFileOptions {
  // The character (.glb, .gltf, .bvh, .rigel); empty: the definition's
  // first geometry file, relative to the definition's folder.
  fs::path character;
  int steps = -1;  // stop after this many steps (seed 003's VCR); -1: all
  bool edit_mode = false;
  // How built nodes are named (rig::BuildOptions::naming_template; empty:
  // the default).
  std::string naming_template;
  // Called before each step with the step's number (from 1) and the total.
  std::function<void(int, int)> progress;
};

struct BuiltComponent {
  std::string name, type, rig_id;
  rig::Side side = rig::Side::kCenter;
};

struct BuiltFile {
  std::unique_ptr<scene::Scene> scene;
  fs::path character;  // the file it was built on
  std::string rig, version;
  int steps = 0, of = 0;  // built, in all
  std::vector<BuiltComponent> components;
  std::size_t nodes = 0;  // the nodes the rig's metadata network links to
};

// The character a build of `definition` (read from `definition_path`) goes
// onto: `given`, else the definition's first geometry file relative to the
// definition's folder; empty when it names none.
fs::path rig_character(const rig::Definition& definition, const fs::path& definition_path, const fs::path& given = {});

// Builds `definition` (read from `definition_path`, its folder the base of
// its geometry paths) onto its character. Fails with kInvalidArgument
// naming "character" when the definition names no geometry and none is
// given, "steps" when more steps are asked than the build has, and, when
// guide joints are missing from the character, kNotFound naming "guides"
// with every one in `missing` (file:line:column). Other errors name the
// character or the definition file.
Result<BuiltFile> build_rig_file(const rig::Definition& definition, const fs::path& definition_path,
                                 const rig::ComponentFactory& factory, const BuildFileOptions& options = {},
                                 std::vector<rig::Diagnostic>* missing = nullptr);

// `rigel graph convert`: the build graph of the definition at
// `definition_path` (read and checked: kInvalidArgument listing every
// problem), with its geometry and data files made relative to the folder of
// `graph_path` (a `.build.json`), saved there atomically.
Result<rig::BuildGraph> convert_definition_file(const fs::path& definition_path, const fs::path& graph_path);

}  // namespace rigel::app
