// Asset data imported by kind (data_files.h): one table from a kind to its
// files' extension and the manager that imports them.

#include "rigel/tools/data_files.h"

#include <algorithm>
#include <fstream>
#include <iterator>
#include <sstream>

#include "rigel/base/log.h"
#include "rigel/ephemeral/component.h"
#include "rigel/tools/build_functions.h"
#include "rigel/rig/definition.h"
#include "rigel/rig/meta.h"
#include "rigel/tools/blendshape_data.h"
#include "rigel/tools/driven_poses.h"
#include "rigel/tools/shape_data.h"
#include "rigel/tools/skin_weights.h"

namespace rigel::tools {

namespace fs = std::filesystem;
using graph::NodeId;

namespace {

Result<DataFileReport> import_weights(scene::Scene& scene, NodeId, const fs::path& file, const std::string& text) {
  auto skins = skin_weights_from_json(text, file.string(), side_files_beside(file));
  if (!skins) return skins.status();
  auto r = apply_skin_weights(scene, *skins);
  if (!r) return r.status().with_context(file.string());
  DataFileReport report;
  report.weights_vertices = r->vertices;
  return report;
}

Result<DataFileReport> import_blend(scene::Scene& scene, NodeId, const fs::path& file, const std::string& text) {
  auto sets = blend_shapes_from_json(text, file.string());
  if (!sets) return sets.status();
  auto r = apply_blend_shapes(scene.graph(), *sets);
  if (!r) return r.status().with_context(file.string());
  for (const std::string& d : r->driven) log::warn(file.string() + ": " + d + " is driven (the file's weight is left out)");
  DataFileReport report;
  report.blend_shape_targets = r->targets;
  return report;
}

template <DrivenData kKind>
Result<DataFileReport> import_driven(scene::Scene& scene, NodeId, const fs::path& file, const std::string& text) {
  auto set = driven_poses_from_json(text, file.string(), kKind);
  if (!set) return set.status();
  auto r = apply_driven_poses(scene.graph(), *set);
  if (!r) return r.status().with_context(file.string());
  DataFileReport report;
  report.driven_curves = r->curves;
  return report;
}

Result<DataFileReport> import_shapes(scene::Scene& scene, NodeId rig, const fs::path& file, const std::string& text) {
  auto shapes = control_shapes_from_json(text, file.string());
  if (!shapes) return shapes.status();
  graph::Graph& g = scene.graph();
  const NodeId target = rig.is_valid() ? rig : rig::find_rig(g, shapes->rig);
  if (!target.is_valid())
    return Status(ErrorCode::kInvalidArgument, file.string() + ": no rig '" + shapes->rig + "' was built");
  auto r = apply_control_shapes(g, target, *shapes);
  if (!r) return r.status().with_context(file.string());
  DataFileReport report;
  report.shapes_set = r->set;
  report.missing = std::move(r->missing);
  return report;
}

// One row per kind, in kDataKinds order. `extension`: of the kind's files
// in data/KIND/; null (with `import`) while this build cannot read the kind.
struct Kind {
  const char* name;
  const char* extension;
  Result<DataFileReport> (*import)(scene::Scene&, NodeId, const fs::path&, const std::string&);
};
constexpr Kind kKinds[] = {
    {"weights", ".weights.json", import_weights},
    {"shapes", ".shapes.json", import_shapes},
    {"blendshapes", ".blendshapes.json", import_blend},
    {"driven_poses", ".drivenposes.json", import_driven<DrivenData::kPoses>},
    {"correctives", ".correctives.json", import_driven<DrivenData::kCorrectives>},
};

constexpr bool same_text(const char* a, const char* b) {
  for (; *a && *a == *b; ++a, ++b) {
  }
  return *a == *b;
}
// The table, the asset folders (project.h) and the definition's kinds agree.
constexpr bool kinds_agree() {
  if (std::size(kKinds) != std::size(kDataKinds) || std::size(kKinds) != std::size(rig::kDataImportKinds)) return false;
  for (std::size_t i = 0; i < std::size(kKinds); ++i)
    if (!same_text(kKinds[i].name, kDataKinds[i]) || !same_text(kKinds[i].name, rig::kDataImportKinds[i])) return false;
  return true;
}
static_assert(kinds_agree(), "data_files.cc's kinds must be tools::kDataKinds and rig::kDataImportKinds, in order");

const Kind* find_kind(std::string_view kind) {
  for (const Kind& k : kKinds)
    if (kind == k.name) return &k;
  return nullptr;
}

std::string kind_names() {
  std::string out;
  for (const Kind& k : kKinds) out += (out.empty() ? "" : ", ") + std::string(k.name);
  return out;
}

}  // namespace

bool data_kind_importable(std::string_view kind) {
  const Kind* k = find_kind(kind);
  return k && k->import;
}

Result<DataFileReport> import_data_file(scene::Scene& scene, NodeId rig, std::string_view kind, const fs::path& file) {
  const Kind* k = find_kind(kind);
  if (!k)
    return Status(ErrorCode::kInvalidArgument,
                  file.string() + ": unknown data kind '" + std::string(kind) + "' (kinds: " + kind_names() + ")")
        .with_field("kind");
  std::error_code ec;
  if (!fs::is_regular_file(file, ec))
    return Status(ErrorCode::kNotFound, file.string() + ": no such " + std::string(kind) + " file").with_field("file");
  std::ifstream in(file, std::ios::binary);
  if (!in) return Status(ErrorCode::kIoError, file.string() + ": cannot be read").with_field("file");
  std::ostringstream text;
  text << in.rdbuf();
  Result<DataFileReport> r = k->import(scene, rig, file, text.str());
  if (r) r->kind = k->name;
  return r;
}

std::vector<DataFile> asset_data_files(const Asset& asset) {
  std::vector<DataFile> out;
  for (const Kind& k : kKinds) {
    if (!k.import) continue;
    const std::string ext = k.extension;
    std::vector<fs::path> files;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(asset.dir / "data" / k.name, ec)) {
      const std::string n = e.path().filename().string();
      if (!e.is_regular_file(ec) || n.rfind('.', 0) == 0) continue;
      if (n.size() > ext.size() && n.ends_with(ext)) files.push_back(e.path());
    }
    std::sort(files.begin(), files.end());
    for (fs::path& f : files) out.push_back(DataFile{k.name, std::move(f)});
  }
  return out;
}

rig::ComponentFactory::DataImporter data_importer() {
  return [](scene::Scene& scene, NodeId rig, const rig::DataImport& entry, const fs::path& file) -> Status {
    Result<DataFileReport> r = import_data_file(scene, rig, entry.kind, file);
    if (!r) return r.status();
    for (const std::string& m : r->missing) log::warn(file.string() + ": the rig has no " + m + " (left out)");
    return Status::ok();
  };
}

const rig::ComponentFactory& components() {
  // Builds with this factory run build graphs' calls: the shipped functions are there.
  register_build_functions();
  static const rig::ComponentFactory factory = [] {
    rig::ComponentFactory f = ephemeral::components();
    f.set_data_importer(data_importer());
    return f;
  }();
  return factory;
}

}  // namespace rigel::tools
