// Scene files as a user names them (scene_files.h).

#include "rigel/app/scene_files.h"

#include <cctype>
#include <cmath>

#include "rigel/ephemeral/rig.h"
#include "rigel/io/bvh.h"
#include "rigel/io/bvh_import.h"
#include "rigel/io/gltf_import.h"
#include "rigel/io/scene_file.h"
#include "rigel/ops/anim/clips.h"
#include "rigel/scene/transform_types.h"

namespace rigel::app {

namespace {

std::string lower_extension(const fs::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

bool is_gltf(const std::string& ext) { return ext == ".glb" || ext == ".gltf"; }

std::size_t clip_count(const graph::Graph& g) {
  const graph::NodeId clips = ops::anim::find_clips_node(g);
  if (!clips.is_valid()) return 0;
  auto list = ops::anim::clips_of(g, clips);
  return list ? list->size() : 0;
}

}  // namespace

bool is_importable(const fs::path& path) {
  const std::string ext = lower_extension(path);
  return is_gltf(ext) || ext == ".bvh";
}

Result<Imported> import_character(const fs::path& path, const OpenOptions& options) {
  const std::string ext = lower_extension(path);
  if (!is_importable(path))
    return Status(ErrorCode::kInvalidArgument, path.string() + ": unsupported file type '" + ext +
                                                   "' (this build imports .bvh, .glb, .gltf)")
        .with_field("input");
  if (!(options.scale > 0.0) || !std::isfinite(options.scale))
    return Status(ErrorCode::kInvalidArgument, "the scale must be a positive number").with_field("scale");
  Imported out;
  if (is_gltf(ext)) {
    io::GltfImportOptions gltf;
    gltf.scale = options.scale;
    gltf.registry = ephemeral::default_registry();
    gltf.warnings = &out.warnings;
    auto scene = io::import_gltf(path, gltf);
    if (!scene) return scene.status();
    out.scene = std::move(*scene);
    const graph::Graph& g = out.scene->graph();
    for (graph::NodeId id : g.nodes()) {
      out.joints += g.node(id)->type().name() == scene::kJointType;
      out.meshes += g.node(id)->type().name() == scene::kMeshType;
    }
    out.clips = clip_count(g);
    return out;
  }
  auto file = io::load_bvh(path);
  if (!file) return file.status();
  io::BvhImportOptions bvh;
  bvh.scale = options.scale;
  bvh.skip_end_sites = options.skip_end_sites;
  bvh.registry = ephemeral::default_registry();
  auto scene = io::import_bvh(*file, bvh);
  if (!scene) return scene.status();
  out.scene = std::move(*scene);
  out.motion = true;
  out.joints = file->joints.size();
  out.frames = static_cast<std::size_t>(file->frame_count);
  out.clips = clip_count(out.scene->graph());
  return out;
}

Result<std::unique_ptr<scene::Scene>> open_scene(const fs::path& path, const OpenOptions& options) {
  if (is_importable(path)) {
    auto imported = import_character(path, options);
    if (!imported) return imported.status();
    return std::move(imported->scene);
  }
  return io::load_scene(path, ephemeral::default_registry());
}

bool is_scene_file(const fs::path& path) { return lower_extension(path) == ".rigel"; }

Result<std::optional<std::string>> play_clip(scene::Scene& scene, const std::optional<std::string>& clip) {
  graph::Graph& g = scene.graph();
  const graph::NodeId clips = ops::anim::find_clips_node(g);
  if (!clips.is_valid()) {
    if (clip) return Status(ErrorCode::kNotFound, "the scene has no animation clips").with_field("clip");
    return std::optional<std::string>{};
  }
  if (clip) {
    auto index = ops::anim::resolve_clip(g, clips, *clip);
    if (!index) return index.status().with_field("clip");
    if (Status s = ops::anim::set_active_clip(g, clips, *index); !s) return s;
  }
  auto list = ops::anim::clips_of(g, clips);
  if (!list) return list.status();
  if (list->empty()) return std::optional<std::string>{};
  const auto active = std::get<std::int64_t>(g.evaluate(clips, ops::anim::clips_attr::kActiveClip));
  return std::optional<std::string>((*list)[static_cast<std::size_t>(active)].name);
}

Status check_export_path(const fs::path& path) {
  const std::string ext = lower_extension(path);
  if (is_gltf(ext)) return Status::ok();
  return Status(ErrorCode::kInvalidArgument,
                path.string() + ": unsupported file type '" + ext + "' (export writes .glb or .gltf)")
      .with_field("output");
}

Status export_scene(scene::Scene& scene, const fs::path& path, const io::GltfExportOptions& options,
                    io::GltfExportReport* report) {
  if (Status s = check_export_path(path); !s) return s;
  return io::export_gltf(scene, path, options, report);
}

Result<tools::BakeReport> bake_nodes(scene::Scene& scene, double first, double last,
                                     const std::vector<std::string>& nodes, std::function<void(double)> progress,
                                     bool keep_history) {
  tools::BakeOptions options;
  options.first = first;
  options.last = last;
  for (const std::string& name : nodes) {
    const graph::NodeId id = scene.graph().find(name);
    if (!id.is_valid()) return Status(ErrorCode::kNotFound, "no node '" + name + "'").with_field("nodes");
    options.nodes.push_back(id);
  }
  options.progress = std::move(progress);
  auto report = tools::bake(scene, options);
  if (report && !keep_history) scene.graph().clear_history();
  return report;
}

}  // namespace rigel::app
