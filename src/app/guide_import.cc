// mGear guide templates imported from files (app/guide_import.h).
#include "rigel/app/guide_import.h"

#include "rigel/ephemeral/rig.h"
#include "rigel/io/gltf_export.h"
#include "rigel/rig/definition_io.h"

namespace rigel::app {
namespace {

bool ends_with(const std::string& text, const std::string& tail) {
  return text.size() >= tail.size() && text.compare(text.size() - tail.size(), tail.size(), tail) == 0;
}

}  // namespace

Result<ImportedGuides> import_guides_file(const fs::path& sgt, const fs::path& output, const fs::path& skeleton) {
  const std::string out = output.filename().string();
  std::string stem;
  if (ends_with(out, ".rig.xml") || ends_with(out, ".rig.json"))
    stem = out.substr(0, out.rfind(".rig."));
  if (stem.empty())
    return Status(ErrorCode::kInvalidArgument, output.string() + ": the definition must be NAME.rig.xml or NAME.rig.json")
        .with_field("output");
  ImportedGuides result;
  result.definition = output;
  result.skeleton = skeleton.empty() ? output.parent_path() / (stem + ".glb") : skeleton;
  const std::string ext = result.skeleton.extension().string();
  if (ext != ".glb" && ext != ".gltf")
    return Status(ErrorCode::kInvalidArgument, result.skeleton.string() + ": the skeleton must be a .glb or .gltf file")
        .with_field("skeleton");

  Result<tools::MgearImport> imported = tools::import_mgear_guides_file(sgt);
  if (!imported) return imported.status();
  result.imported = std::move(*imported);

  Result<std::unique_ptr<scene::Scene>> bones =
      tools::guide_skeleton_scene(result.imported, ephemeral::default_registry());
  if (!bones) return bones.status();
  io::GltfExportOptions options;
  options.skeleton_skin = true;
  if (Status s = io::export_gltf(**bones, result.skeleton, options); !s) return s;

  rig::Definition& d = result.imported.definition;
  rig::Geometry g;
  const fs::path base = output.parent_path().empty() ? fs::path(".") : output.parent_path();
  g.file = fs::absolute(result.skeleton).lexically_relative(fs::absolute(base)).generic_string();
  d.geometry = {g};
  d.source.clear();
  if (Status s = rig::save_definition(d, output); !s) return s;
  return result;
}

}  // namespace rigel::app
