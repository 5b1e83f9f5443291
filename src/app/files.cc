// Opening what a user names as a scene (workspace.h).

#include <cctype>

#include "rigel/app/workspace.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/io/bvh.h"
#include "rigel/io/bvh_import.h"
#include "rigel/io/gltf_import.h"
#include "rigel/io/scene_file.h"

namespace rigel::app {

namespace {

std::string lower_extension(const fs::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

}  // namespace

Result<std::unique_ptr<scene::Scene>> open_scene(const fs::path& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".glb" || ext == ".gltf") {
    io::GltfImportOptions options;
    options.registry = ephemeral::default_registry();
    return io::import_gltf(path, options);
  }
  if (ext == ".bvh") {
    auto file = io::load_bvh(path);
    if (!file) return file.status();
    io::BvhImportOptions options;
    options.registry = ephemeral::default_registry();
    return io::import_bvh(*file, options);
  }
  return io::load_scene(path, ephemeral::default_registry());
}

bool is_scene_file(const fs::path& path) { return lower_extension(path) == ".rigel"; }

}  // namespace rigel::app
