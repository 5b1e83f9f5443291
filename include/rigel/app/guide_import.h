#pragma once
// mGear guide templates imported from files (`rigel import-guides`, Python's
// rigel.import_guides; tools/mgear_guides.h): the template read, the
// skeleton its guides imply written as a glTF, and a definition that names
// it as its geometry, so `rigel build OUT.rig.xml` builds it as it is.

#include <filesystem>

#include "rigel/base/status.h"
#include "rigel/tools/mgear_guides.h"

namespace rigel::app {

namespace fs = std::filesystem;

struct ImportedGuides {
  fs::path definition;  // written
  fs::path skeleton;    // written
  tools::MgearImport imported;
};

// Reads `sgt` and writes `output` (.rig.xml or .rig.json) and `skeleton`
// (.glb or .gltf; empty: beside the output, NAME.glb for NAME.rig.xml),
// both atomically; the definition's geometry is the skeleton, relative to
// the definition's folder. kInvalidArgument naming "output" or "skeleton"
// for a file name of the wrong kind; the template's errors
// (tools::import_mgear_guides) as they are. Components without a
// counterpart are in the report, not errors.
Result<ImportedGuides> import_guides_file(const fs::path& sgt, const fs::path& output, const fs::path& skeleton = {});

}  // namespace rigel::app
