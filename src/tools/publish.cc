// Publishing an asset (publish.h).

#include "rigel/tools/publish.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "rigel/base/log.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/io/checksum.h"
#include "rigel/io/diffable_json.h"
#include "rigel/io/gltf_import.h"
#include "rigel/io/scene_file.h"
#include "rigel/rig/definition_io.h"
#include "rigel/rig/manager.h"
#include "rigel/rig/meta.h"
#include "rigel/scene/transform_types.h"
#include "rigel/tools/data_files.h"

namespace rigel::tools {

namespace fs = std::filesystem;
using graph::NodeId;
using Json = nlohmann::ordered_json;

namespace {

// The files of `folder` whose names end with one of `exts`, sorted.
std::vector<fs::path> files_in(const fs::path& folder, std::initializer_list<const char*> exts) {
  std::vector<fs::path> out;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(folder, ec)) {
    const std::string n = e.path().filename().string();
    if (!e.is_regular_file(ec) || n.rfind('.', 0) == 0) continue;
    for (const char* x : exts)
      if (n.size() > std::string(x).size() && n.ends_with(x)) out.push_back(e.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::map<std::string, math::Mat4> joint_worlds(scene::Scene& s) {
  std::map<std::string, math::Mat4> out;
  for (NodeId id : s.hierarchy())
    if (s.graph().node(id)->type().name() == scene::kJointType) out[s.graph().node(id)->uuid().str()] = s.world_matrix(id);
  return out;
}

std::string in_asset(const fs::path& p, const fs::path& base) { return p.lexically_relative(base).generic_string(); }

// A data file as the publish tells files apart (each is imported once).
fs::path same_file(const fs::path& p) {
  std::error_code ec;
  fs::path c = fs::weakly_canonical(p, ec);
  return ec ? fs::absolute(p, ec).lexically_normal() : c;
}

}  // namespace

namespace {


}  // namespace

Result<std::string> file_checksum(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return Status(ErrorCode::kIoError, file.string() + ": cannot be read for its checksum");
  io::Checksum sum;
  char buf[65536];
  while (in) {
    in.read(buf, sizeof buf);
    sum.update(std::string_view(buf, static_cast<std::size_t>(in.gcount())));
  }
  return sum.text();
}

Result<PublishReport> publish_asset(const Asset& asset, const rig::ComponentFactory& factory, const PublishOptions& options) {
  const std::string where = "asset " + asset.name;
  if (asset.skeleton.empty())
    return Status(ErrorCode::kFailedPrecondition, where + ": no skeleton (rigel asset new NAME --skeleton FILE)").with_field("asset");
  const fs::path skeleton = asset.dir / asset.skeleton;
  const std::vector<fs::path> definitions = files_in(asset.dir / "build", {".rig.xml", ".rig.json"});
  if (definitions.empty())
    return Status(ErrorCode::kFailedPrecondition, where + ": no rig definition in " + (asset.dir / "build").string()).with_field("asset");

  // The version folder, staged under a temporary name.
  const std::vector<int> versions = published_versions(asset);
  PublishReport report;
  report.version = versions.empty() ? 1 : versions.back() + 1;
  const fs::path stage = asset.dir / "rig" / (".publish-" + std::to_string(::getpid()));
  std::error_code ec;
  fs::remove_all(stage, ec);
  fs::create_directories(stage, ec);
  if (ec) return Status(ErrorCode::kIoError, stage.string() + ": " + ec.message());
  struct Cleanup {
    fs::path dir;
    ~Cleanup() {
      std::error_code e;
      if (!dir.empty()) fs::remove_all(dir, e);
    }
  } cleanup{stage};
  auto job = log::JobLog::open(stage / "publish.log", log::Level::kDebug);
  if (!job) return job.status();
  log::info("publishing " + where + " as version " + std::to_string(report.version));

  // Build from scratch.
  io::GltfImportOptions import;
  import.registry = ephemeral::default_registry();
  auto scene = io::import_gltf(skeleton, import);
  if (!scene) return scene.status().with_context(where + ": skeleton");
  const auto rest = joint_worlds(**scene);
  Json defs = Json::array();
  // The hand-made data back: what a definition names (<data>) its build
  // imports at its data step; then every file of the asset's data folders
  // that no definition named (each file imported once).
  Json data = Json::array();
  std::set<fs::path> imported;
  auto imported_file = [&](const DataFileReport& r, const fs::path& given) -> Status {
    const fs::path f = given.lexically_normal();  // "build/../data/x" as "data/x"
    Result<std::string> sum = file_checksum(f);
    if (!sum) return sum.status();
    report.weights_vertices += r.weights_vertices;
    report.shapes_set += r.shapes_set;
    report.driven_curves += r.driven_curves;
    report.blend_shape_targets += r.blend_shape_targets;
    for (const std::string& m : r.missing) log::warn(in_asset(f, asset.dir) + ": the rig has no " + m + " (left out)");
    log::info(r.kind + " from " + in_asset(f, asset.dir) + ": " +
              (r.kind == "weights"  ? std::to_string(r.weights_vertices) + " vertices"
               : r.kind == "shapes"      ? std::to_string(r.shapes_set) + " controls"
               : r.kind == "blendshapes" ? std::to_string(r.blend_shape_targets) + " targets"
                                         : std::to_string(r.driven_curves) + " curves"));
    imported.insert(same_file(f));
    data.push_back(Json{{"file", in_asset(f, asset.dir)}, {"kind", r.kind}, {"checksum", *sum}});
    return Status::ok();
  };
  rig::ComponentFactory builder = factory;
  builder.set_data_importer([&](scene::Scene& s, NodeId rig, const rig::DataImport& entry, const fs::path& f) -> Status {
    Result<DataFileReport> r = import_data_file(s, rig, entry.kind, f);
    return r ? imported_file(*r, f) : r.status();
  });
  for (const fs::path& d : definitions) {
    rig::ParseResult parsed = rig::load_definition(d, factory.schemas());
    if (!parsed.ok()) return Status(ErrorCode::kParseError, parsed.errors.front().str()).with_context(where);
    for (const rig::Diagnostic& problem : rig::validate(parsed.definition, factory.schemas())) {
      if (options.checks) return Status(ErrorCode::kInvalidArgument, problem.str()).with_context(where + ": validation");
      log::warn(problem.str());
    }
    rig::BuildOptions build;
    build.naming_template = options.naming_template;
    auto added = rig::add_rig(**scene, d, builder, build);
    if (!added) return added.status().with_context(where + ": " + in_asset(d, asset.dir));
    log::info("built " + added->name + " " + added->version + " (" + std::to_string(added->steps) + " steps) from " + in_asset(d, asset.dir));
    report.rigs.push_back(added->name);
    Result<std::string> sum = file_checksum(d);
    if (!sum) return sum.status();
    defs.push_back(Json{{"file", in_asset(d, asset.dir)}, {"rig", added->name}, {"version", added->version}, {"checksum", *sum}});
  }
  for (const DataFile& f : asset_data_files(asset)) {
    if (imported.count(same_file(f.file))) continue;  // a definition's build imported it
    Result<DataFileReport> r = import_data_file(**scene, NodeId{}, f.kind, f.file);
    if (!r) return r.status().with_context(where);
    if (Status s = imported_file(*r, f.file); !s) return s;
  }
  // Checks.
  Json checks = Json::array();
  const auto after = joint_worlds(**scene);
  for (const auto& [uuid, m] : rest)
    if (auto it = after.find(uuid); it != after.end()) report.rest_error = std::max(report.rest_error, (it->second - m).block<3, 1>(0, 3).norm());
  const bool rest_ok = report.rest_error <= 1e-6;
  checks.push_back(Json{{"name", "validation"}, {"ok", true}});
  checks.push_back(Json{{"name", "rest pose"}, {"ok", rest_ok}, {"maxError", report.rest_error}});
  if (!rest_ok) {
    const std::string message = where + ": the build moves the skeleton at rest by " + std::to_string(report.rest_error) + " m";
    if (options.checks) return Status(ErrorCode::kFailedPrecondition, message).with_field("checks");
    log::warn(message);
  }
  // Where it came from, on every rig (the version folder, relative to the scene when saved).
  graph::Graph& g = (*scene)->graph();
  const std::string number = std::to_string(report.version);
  const fs::path final_dir = asset.dir / "rig" / ("v" + std::string(number.size() < 3 ? 3 - number.size() : 0, '0') + number);
  graph::Transaction tx(g, "publish");
  for (NodeId r : rig::list_rigs(g)) {
    auto set = [&](const char* attr, graph::Value v) { return g.set_value({r, g.node(r)->type().attr_find(attr), -1}, std::move(v)); };
    Status s = set("publishedAsset", graph::Value(asset.name));
    if (s) s = set("publishedVersion", graph::Value(static_cast<std::int64_t>(report.version)));
    if (s) s = set("publishedFrom", graph::Value(fs::absolute(final_dir).lexically_normal().string()));
    if (!s) return s;
  }
  (*job)->flush();
  report.warnings = (*job)->warnings();
  // Written into the stage, then moved into place.
  const fs::path staged_scene = stage / "rig.rigel";
  if (Status s = io::save_scene(**scene, staged_scene); !s) return s;
  Result<std::string> skeleton_sum = file_checksum(skeleton);
  if (!skeleton_sum) return skeleton_sum.status();
  const Json manifest{{"rigelPublish", kPublishFormat},
                      {"asset", asset.name},
                      {"type", asset.type},
                      {"version", report.version},
                      {"rigel", options.rigel_version},
                      {"created", utc_now_iso()},
                      {"skeleton", Json{{"file", asset.skeleton}, {"checksum", *skeleton_sum}}},
                      {"definitions", defs},
                      {"data", data},
                      {"checks", checks},
                      {"warnings", report.warnings},
                      {"scene", "rig.rigel"},
                      {"log", "publish.log"}};
  if (Status s = io::write_file_atomic(stage / "manifest.json", io::diffable_json(manifest)); !s) return s;
  job->reset();  // the log closed before the move
  // Never over a version: one published meanwhile makes this one fail.
  if (fs::exists(final_dir, ec))
    return Status(ErrorCode::kFailedPrecondition, where + ": " + final_dir.filename().string() +
                                                      " was published meanwhile; publish again");
  fs::rename(stage, final_dir, ec);
  if (ec) return Status(ErrorCode::kIoError, final_dir.string() + ": " + ec.message());
  cleanup.dir.clear();
  report.dir = final_dir;
  report.scene = final_dir / "rig.rigel";
  report.manifest = final_dir / "manifest.json";
  report.log = final_dir / "publish.log";
  return report;
}

std::vector<PublishedRig> published_rigs(const graph::Graph& g) {
  std::vector<PublishedRig> out;
  for (NodeId r : rig::list_rigs(g)) {
    const std::string asset = rig::meta_string(g, r, "publishedAsset");
    if (asset.empty()) continue;
    PublishedRig p;
    p.rig = rig::meta_string(g, r, "rigName");
    p.asset = asset;
    p.version = std::atoi(rig::meta_string(g, r, "publishedVersion").c_str());
    p.from = rig::meta_string(g, r, "publishedFrom");
    const fs::path asset_dir = p.from.parent_path().parent_path();
    std::error_code ec;
    if (!p.from.empty() && fs::exists(asset_dir / (asset + kAssetExtension), ec)) {
      Asset a;
      a.dir = asset_dir;
      const std::vector<int> v = published_versions(a);
      p.newest = v.empty() ? 0 : v.back();
    }
    out.push_back(std::move(p));
  }
  return out;
}

}  // namespace rigel::tools
