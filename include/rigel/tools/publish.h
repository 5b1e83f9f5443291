#pragma once
// Publishing an asset (the rigging pipeline's last step): the asset's rig
// built from scratch from its files, its hand-made data put back, its
// checks run, and the result written as the next numbered version,
// ASSET/rig/vNNN/, never overwriting one:
//
//   rig.rigel      the built scene (its rigs record the asset and version)
//   manifest.json  what it was made from: the skeleton, definitions (rig,
//                  version) and data files with their checksums, the
//                  checks and warnings, rigel's version
//   publish.log    the build's log (debug and above)
//
// The build: every definition in build/ (.rig.xml, .rig.json; sorted by
// name) onto the skeleton file (skeleton/ as the asset file names it),
// named by the naming template given, each definition's <data> imported
// by its build's data step; then every file of the asset's data folders
// that a definition did not name (data_files.h: data/weights/*.weights.json,
// data/shapes/*.shapes.json, data/blendshapes/*.blendshapes.json,
// data/driven_poses/*.drivenposes.json,
// data/correctives/*.correctives.json) imported, so no file is imported twice (the
// manifest lists each once). The builds get a copy of `factory` whose data
// importer is data_files.h's. Checks:
// every definition validates (errors stop the publish, warnings are kept);
// the skeleton's rest pose is unchanged by the build (no joint moves at
// rest by more than 1e-6). The version folder is made under a temporary
// name and renamed into place when everything is written, so a failed
// publish leaves nothing.
//
// Checksums are FNV-1a 64 of the file's bytes ("fnv1a64:" and 16 hex
// digits): a fingerprint that a file changed, not a signature.

#include <filesystem>
#include <string>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/graph/graph.h"
#include "rigel/rig/component.h"
#include "rigel/tools/project.h"

namespace rigel::tools {

inline constexpr int kPublishFormat = 1;

// "fnv1a64:0123456789abcdef" of a file's bytes; kIoError when it cannot be read.
Result<std::string> file_checksum(const std::filesystem::path& file);

struct PublishOptions {
  std::string naming_template;  // BuildOptions::naming_template
  bool checks = true;           // the setting publish.checks
  std::string rigel_version;    // written into the manifest
};

struct PublishReport {
  int version = 0;
  std::filesystem::path dir, scene, manifest, log;
  std::vector<std::string> rigs;
  std::vector<std::string> warnings;
  std::size_t weights_vertices = 0, shapes_set = 0, driven_curves = 0;
  std::size_t blend_shape_targets = 0;
  double rest_error = 0;  // the largest joint move at rest (metres)
};

// kFailedPrecondition naming "asset" when the asset has no skeleton or no
// definition; a definition's errors (file:line:column), a failed build or
// data import, or a failed check stop it with nothing written.
Result<PublishReport> publish_asset(const Asset& asset, const rig::ComponentFactory& factory,
                                    const PublishOptions& options = {});

// What a scene's rigs say of where they were published from: each rig
// built by publish_asset, with its version and the newest version the
// asset has now (0 when the asset folder cannot be found).
struct PublishedRig {
  std::string rig, asset;
  int version = 0, newest = 0;
  std::filesystem::path from;  // the version folder it came from
  bool out_of_date() const { return newest > version; }
};
std::vector<PublishedRig> published_rigs(const graph::Graph& graph);

}  // namespace rigel::tools
