#pragma once
// Asset data imported by kind (seed 004 §4.9-4.10): one dispatcher from a
// data kind (rig::kDataImportKinds, the folders of an asset's data/) to the
// manager that reads its files, so a build's data step (a definition's
// <data kind file/>, rig/build.h), a publish and PyBuild's post() import the
// same way. The rig layer cannot see the managers: it calls the importer
// its ComponentFactory is given, and components() here is the factory that
// has it.
//
//   weights       skin_weights.h: onto the scene's skins (by skin, else mesh name)
//   shapes        shape_data.h: onto the controls of the rig (its metaRoot)
//   driven_poses, correctives
//                 driven_poses.h: the driven keys recreated from the file's drivers
//   blendshapes   blendshape_data.h: onto the scene's blendShapes (by name, else mesh name;
//                 a mesh without one gets one)

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/graph/graph.h"
#include "rigel/rig/component.h"
#include "rigel/scene/scene.h"
#include "rigel/tools/project.h"

namespace rigel::tools {

struct DataFileReport {
  std::string kind;
  std::size_t weights_vertices = 0;  // weights: vertices set
  std::size_t shapes_set = 0;        // shapes: controls set
  std::vector<std::string> missing;  // shapes: entries the rig lacks ("arm_L ik[0]"), left out
  std::size_t driven_curves = 0;     // driven_poses, correctives: driven-key curves set
  std::size_t blend_shape_targets = 0;  // blendshapes: targets set
};

// Imports `file`, a data file of `kind`. Shapes go onto the controls of the
// rig whose metaRoot is `rig`, or, when `rig` is invalid, of the rig the
// file names. One undo step; on failure nothing changes. Errors name the
// file: kNotFound when it cannot be read, kParseError when it is not a file
// of its kind, kInvalidArgument when the scene lacks what it names (a skin,
// the rig) or for an unknown kind, kUnsupported for a kind this build
// cannot read yet.
Result<DataFileReport> import_data_file(scene::Scene& scene, graph::NodeId rig, std::string_view kind,
                                        const std::filesystem::path& file);

// Whether import_data_file reads files of `kind`.
bool data_kind_importable(std::string_view kind);

struct DataFile {
  std::string kind;
  std::filesystem::path file;
};
// Every file of the asset's data folders that import_data_file reads: per
// importable kind in kDataKinds order, data/KIND/*.KIND.json sorted by name
// (data/weights/*.weights.json, data/shapes/*.shapes.json). Hidden files
// are left out.
std::vector<DataFile> asset_data_files(const Asset& asset);

// A ComponentFactory::DataImporter calling import_data_file for the rig
// being built; shapes entries the rig lacks are logged as warnings.
rig::ComponentFactory::DataImporter data_importer();

// Every component class (ephemeral::components()) with data_importer(),
// the shipped build functions registered (build_functions.h):
// the factory the drivers (CLI, Python, server, publish) build with.
const rig::ComponentFactory& components();

}  // namespace rigel::tools
