#include "rigel/io/gltf_import.h"

#include <cmath>
#include <new>

#include "rigel/ops/registry.h"

#include "gltf_container.h"
#include "gltf_importer.h"
#include "gltf_json_checks.h"
#include "gltf_materials.h"
#include "gltf_uri.h"

namespace rigel::io {
namespace gltf_importer {

Status Importer::set(NodeId node, graph::AttrIndex attr, graph::Value value) {
  return scene_->graph().set_value(Plug{node, attr, -1}, std::move(value));
}

Status Importer::connect(NodeId src, graph::AttrIndex src_attr, NodeId dst, graph::AttrIndex dst_attr, std::int32_t element) {
  return scene_->graph().connect(Plug{src, src_attr, -1}, Plug{dst, dst_attr, element});
}

Result<std::unique_ptr<scene::Scene>> Importer::run() {
  if (Status s = accessors_.check(); !s) return s;
  if (Status s = check_hierarchy(); !s) return s;
  if (Status s = check_skins(); !s) return s;
  if (Status s = check_nodes(); !s) return s;
  if (Status s = check_scenes(); !s) return s;
  if (Status s = read_meshes(); !s) return s;
  if (Status s = read_animations(); !s) return s;
  scene_ = std::make_unique<scene::Scene>(options_.registry ? options_.registry : ops::default_registry());
  if (Status s = build_nodes(); !s) return s;
  if (Status s = build_meshes(); !s) return s;
  if (Status s = build_animations(); !s) return s;
  scene_->graph().clear_history();
  return std::move(scene_);
}

}  // namespace gltf_importer

Result<std::unique_ptr<scene::Scene>> import_gltf(const std::filesystem::path& path, const GltfImportOptions& options) {
  using namespace gltf_importer;
  namespace fs = std::filesystem;
  const std::string where = path.string();
  if (!(options.scale > 0.0) || !std::isfinite(options.scale))
    return error(ErrorCode::kInvalidArgument, where + ": glTF import: scale must be a positive number");
  try {
    Source source;
    if (Status s = read_file(path, source.bytes); !s) return s.with_context(where);
    if (Status s = parse_container(source); !s) return s.with_context(where);
    Result<Json> doc = parse_json(source.json);
    if (!doc) return doc.status().with_context(where);
    SchemaContext ctx;
    ctx.source = &source;
    // tinygltf's GetBaseDir: the text before the last separator.
    const std::size_t slash = where.find_last_of('/');
    ctx.base_dir = slash == std::string::npos ? std::string() : slash == 0 ? std::string("/") : where.substr(0, slash);
    std::error_code ec;
    Result<fs::path> folder = gltf_uri::resolved_folder(ctx.base_dir, where);
    if (!folder) return folder.status();
    ctx.folder = std::move(*folder);
    if (Status s = check_json(*doc, ctx); !s) return s.with_context(where);
    const Json images = doc->contains("images") ? doc->at("images") : Json();  // tinygltf never sees them
    Result<tinygltf::Model> model = load_model(std::move(*doc), source, ctx);
    if (!model) return model.status().with_context(where);
    Importer importer(*model, options, ctx.quantized);
    Result<std::unique_ptr<scene::Scene>> scene = importer.run();
    if (!scene) return scene.status().with_context(where);
    if (Status s = gltf_look::import_looks(**scene, *model, images, ctx.base_dir, importer.mesh_sources(),
                                           [&](int a) { return importer.accessor_values(a); });
        !s)
      return s.with_context(where);
    (*scene)->graph().clear_history();
    return scene;
  } catch (const std::bad_alloc&) {
    return error(ErrorCode::kIoError, where + ": out of memory");
  } catch (const std::exception& e) {
    return error(ErrorCode::kParseError, where + ": " + e.what());
  }
}

}  // namespace rigel::io
