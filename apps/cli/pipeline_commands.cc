// `rigel project`, `rigel asset`, `rigel config`, `rigel data` and the log
// level (see pipeline_commands.h).

#include "pipeline_commands.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_util.h"
#include "rigel/app/workspace.h"
#include "rigel/ephemeral/component.h"
#include "rigel/base/log.h"
#include "rigel/tools/config.h"
#include "rigel/tools/batch.h"
#include "rigel/tools/batch_run.h"
#include "rigel/io/scene_file.h"
#include "rigel/tools/data_files.h"
#include "rigel/tools/project.h"
#include "rigel/tools/publish.h"

namespace rigel::cli {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

struct ProjectArgs {
  std::string dir, name;
  bool json = false;
};

struct AssetArgs {
  std::string name, type = "character", skeleton, project;
  bool json = false;
};

struct ConfigArgs {
  std::string key, value;
  bool user = false, project = false, json = false;
};

Json asset_json(const tools::Asset& a) {
  const std::vector<int> versions = tools::published_versions(a);
  return Json{{"name", a.name},
              {"type", a.type},
              {"dir", a.dir.string()},
              {"skeleton", a.skeleton},
              {"published", versions},
              {"latest", versions.empty() ? Json() : Json(versions.back())},
              {"created", a.created},
              {"modified", a.modified}};
}

// The project given, or the one the current folder is in.
Result<tools::Project> project_of(const std::string& dir) {
  return dir.empty() ? tools::find_project(fs::current_path()) : tools::open_project(dir);
}

// The asset `name` of the project, or (no name) the one the current folder is in.
Result<tools::Asset> asset_named(const std::string& name, const std::string& project) {
  if (name.empty()) return tools::find_asset(fs::current_path());
  auto p = project_of(project);
  if (!p) return p.status();
  return tools::open_asset(*p, name);
}

int run_project_new(const ProjectArgs& a) {
  auto p = tools::create_project(a.dir, a.name);
  if (!p) return fail(p.status());
  if (a.json) std::cout << Json{{"name", p->name}, {"dir", p->dir.string()}, {"format", p->format}}.dump() << "\n";
  std::cerr << "rigel: created project " << p->name << " in " << p->dir.string() << "\n";
  return 0;
}

int run_project_info(const ProjectArgs& a) {
  auto p = project_of(a.dir);
  if (!p) return fail(p.status());
  auto assets = tools::list_assets(*p);
  if (!assets) return fail(assets.status());
  if (a.json) {
    Json list = Json::array();
    for (const tools::Asset& x : *assets) list.push_back(asset_json(x));
    std::cout << Json{{"name", p->name}, {"dir", p->dir.string()}, {"format", p->format}, {"created", p->created}, {"assets", list}}.dump()
              << "\n";
    return 0;
  }
  std::cout << p->name << " (" << p->dir.string() << ", format " << p->format << ")\n";
  for (const tools::Asset& x : *assets) {
    const std::vector<int> v = tools::published_versions(x);
    std::cout << "  " << x.type << " " << x.name << (v.empty() ? "  unpublished" : "  published v" + std::to_string(v.back()))
              << "\n";
  }
  return 0;
}

int run_asset_new(const AssetArgs& a) {
  auto p = project_of(a.project);
  if (!p) return fail(p.status());
  auto asset = tools::create_asset(*p, a.name, a.type, a.skeleton);
  if (!asset) return fail(asset.status().with_context(p->dir.string()));
  if (a.json) std::cout << asset_json(*asset).dump() << "\n";
  std::cerr << "rigel: created " << asset->type << " " << asset->name << " in " << asset->dir.string() << "\n";
  return 0;
}

int run_asset_info(const AssetArgs& a) {
  Result<tools::Asset> asset = asset_named(a.name, a.project);
  if (!asset) return fail(asset.status());
  if (a.json) {
    std::cout << asset_json(*asset).dump() << "\n";
  } else {
    const Json j = asset_json(*asset);
    std::cout << asset->type << " " << asset->name << " (" << asset->dir.string() << ")\n  skeleton: "
              << (asset->skeleton.empty() ? "none" : asset->skeleton) << "\n  published: " << j["published"].dump() << "\n";
  }
  return 0;
}

// The project's settings file (the current folder's project), or empty.
fs::path project_config() {
  auto p = tools::find_project(fs::current_path());
  return p ? p->dir / tools::kProjectConfigFile : fs::path();
}

int run_config(const std::string& op, const ConfigArgs& a) {
  if (a.user && a.project) return usage_error("give --user or --project, not both");
  if (op == "set" || op == "unset") {
    fs::path file;
    if (a.user) {
      file = tools::user_config_path();
    } else {
      file = project_config();
      if (file.empty() && a.project) return fail(tools::find_project(fs::current_path()).status());
      if (file.empty()) file = tools::user_config_path();
    }
    std::optional<std::string_view> value;
    if (op == "set") value = a.value;
    if (Status s = tools::Config::set(file, a.key, value); !s) return fail(s);
    std::cerr << "rigel: " << (op == "set" ? "set " + a.key + " = " + a.value : "unset " + a.key) << " in " << file.string() << "\n";
    return 0;
  }
  auto config = tools::Config::load(tools::user_config_path(), project_config());
  if (!config) return fail(config.status());
  auto entry_json = [](const tools::Config::Entry& e) {
    Json value;
    std::visit([&](const auto& x) { value = x; }, e.value);
    return Json{{"key", e.spec->key}, {"value", value}, {"source", tools::config_source_name(e.source)}, {"help", e.spec->help}};
  };
  if (op == "get") {
    auto e = config->get(a.key);
    if (!e) return fail(e.status());
    if (a.json) std::cout << entry_json(*e).dump() << "\n";
    else std::cout << tools::setting_text(e->value) << "\n";
    return 0;
  }
  Json list = Json::array();
  for (const tools::Config::Entry& e : config->list()) {
    list.push_back(entry_json(e));
    if (!a.json) std::cout << e.spec->key << " = " << tools::setting_text(e.value) << "  (" << tools::config_source_name(e.source) << ")\n";
  }
  if (a.json) std::cout << Json{{"settings", list}, {"user", tools::user_config_path().string()}, {"project", project_config().string()}}.dump() << "\n";
  return 0;
}

struct DataArgs {
  std::string kind, scene, file, output, rig, rename, format;
  bool nearest = false, mirror = false, json = false;
};

// A bare data file name inside an asset goes to its data folder (with the
// kind's extension when it has none); anything else is a path as given.
std::string data_path(const std::string& kind, const std::string& given) {
  if (given.find('/') != std::string::npos) return given;
  auto asset = tools::find_asset(fs::current_path());
  if (!asset) return given;
  const std::string ext = kind == "driven_poses" ? ".drivenposes.json" : "." + kind + ".json";  // .weights.json, .shapes.json, ...
  const std::string name = given.size() > 5 && given.ends_with(".json") ? given : given + ext;
  return (asset->dir / "data" / kind / name).string();
}

Result<std::map<std::string, std::string>> read_rename(const std::string& path) {
  std::ifstream in(path);
  if (!in) return Status(ErrorCode::kNotFound, "--rename: " + path + ": cannot be read");
  std::stringstream text;
  text << in.rdbuf();
  const Json j = Json::parse(text.str(), nullptr, false);
  if (j.is_discarded() || !j.is_object()) return Status(ErrorCode::kParseError, "--rename: " + path + ": expected a JSON object {\"old name\": \"new name\", ...}");
  std::map<std::string, std::string> out;
  for (auto it = j.begin(); it != j.end(); ++it) {
    if (!it.value().is_string()) return Status(ErrorCode::kParseError, "--rename: " + path + ": " + it.key() + ": expected a name");
    out[it.key()] = it.value().get<std::string>();
  }
  return out;
}

int run_data(bool exporting, const DataArgs& a) {
  const bool driven = a.kind == "driven_poses" || a.kind == "correctives";
  if (a.kind != "weights" && a.kind != "shapes" && a.kind != "blendshapes" && !driven)
    return usage_error("KIND '" + a.kind + "': expected weights, shapes, blendshapes, driven_poses or correctives");
  const tools::DrivenData driven_kind = a.kind == "correctives" ? tools::DrivenData::kCorrectives : tools::DrivenData::kPoses;
  if (a.kind != "weights" && (a.nearest || a.mirror || !a.rename.empty() || !a.format.empty()))
    return usage_error("--rename, --nearest, --mirror and --format are for weights");
  auto format = tools::weights_format_named(a.format.empty() ? settings().string("data.weights") : a.format);
  if (!format) return usage_error("--format: " + format.status().message());
  auto scene = load(a.scene);
  if (!scene) return fail(scene.status());
  app::Workspace ws(std::move(*scene), a.scene, {}, tools::components());
  const std::string file = data_path(a.kind, exporting ? a.output : a.file);
  if (exporting) {
    auto path = a.kind == "weights"       ? ws.export_skin_weights(file, *format)
                : a.kind == "shapes"      ? ws.export_control_shapes(a.rig, file)
                : a.kind == "blendshapes" ? ws.export_blend_shapes(file)
                                          : ws.export_driven_poses(driven_kind, file);
    if (!path) return fail(path.status().with_context(a.scene));
    if (a.json) std::cout << Json{{"kind", a.kind}, {"file", path->string()}}.dump() << "\n";
    std::cerr << "rigel: wrote " << a.kind << " to " << path->string() << "\n";
    return 0;
  }
  Json report;
  if (a.kind == "weights") {
    tools::WeightsImport options;
    options.nearest = a.nearest;
    options.mirror = a.mirror;
    if (!a.rename.empty()) {
      auto table = read_rename(a.rename);
      if (!table) return fail(table.status());
      options.rename = std::move(*table);
    }
    auto r = ws.import_skin_weights(file, options);
    if (!r) return fail(r.status().with_context(a.scene));
    report = Json{{"skins", r->skins}, {"vertices", r->vertices}, {"remapped", r->remapped}};
  } else if (driven) {
    auto r = ws.import_driven_poses(driven_kind, file);
    if (!r) return fail(r.status().with_context(a.scene));
    report = Json{{"curves", r->curves}, {"created", r->created}, {"keys", r->keys}};
  } else if (a.kind == "blendshapes") {
    auto r = ws.import_blend_shapes(file);
    if (!r) return fail(r.status().with_context(a.scene));
    report = Json{{"blendShapes", r->blend_shapes}, {"targets", r->targets}, {"created", r->created}, {"added", r->added},
                  {"driven", r->driven}};
    for (const std::string& d : r->driven) log::warn(file + ": " + d + " is driven (the file's weight is left out)");
  } else {
    auto r = ws.import_control_shapes(a.rig, file);
    if (!r) return fail(r.status().with_context(a.scene));
    report = Json{{"set", r->set}, {"missing", r->missing}};
    for (const std::string& m : r->missing) log::warn(file + ": the rig has no " + m + " (left out)");
  }
  if (auto saved = ws.save(a.output); !saved) return fail(saved.status());
  if (a.json) std::cout << report.dump() << "\n";
  std::cerr << "rigel: imported " << a.kind << " from " << file << "; wrote " << a.output << "\n";
  return 0;
}

struct BatchArgs {
  std::string operation, output, report, retry, frames;
  std::vector<std::string> shots;
  int jobs = -1;  // -1: the setting batch.jobs
  bool json = false;
  bool slurm = false;
  std::string partition;
};

std::string self_exe() {
  std::error_code ec;
  const fs::path p = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string("rigel") : p.string();
}

int run_batch(const BatchArgs& a) {
  tools::BatchRequest request;
  request.operation = a.operation;
  request.shots = a.shots;
  request.output = a.output;
  request.frames = a.frames;
  request.report = a.report;
  request.retry_failed = a.retry;
  request.parallel = static_cast<std::size_t>(a.jobs >= 0 ? a.jobs : settings().integer("batch.jobs"));
  request.slurm = a.slurm;
  request.partition = a.slurm && a.partition.empty() ? settings().string("batch.partition") : a.partition;
  request.program = self_exe();
  const std::string op = a.operation;
  const bool tty = isatty(2);
  std::size_t last_done = static_cast<std::size_t>(-1);
  auto show = [&](const tools::BatchProgress& p) {
    if (tty) std::cerr << "\rrigel: batch " << op << ": " << tools::progress_line(p) << "   " << std::flush;
    else if (p.done != last_done && (p.running == 0 || p.done == p.total)) log::info("batch " + op + ": " + tools::progress_line(p));
    last_done = p.done;
  };
  auto outcome = tools::run_batch(request, show);
  if (tty) std::cerr << "\n";
  if (!outcome) {
    // A request that cannot run is a usage error, with the option's name.
    static const std::map<std::string, std::string> option = {{"operation", "OPERATION"}, {"output", "-o"},
                                                              {"frames", "--frames"},     {"shots", "SHOTS"},
                                                              {"retry_failed", "--retry-failed"}, {"partition", "--partition"}};
    const Status& s = outcome.status();
    auto it = option.find(s.field());
    if (s.code() == ErrorCode::kInvalidArgument && it != option.end()) return usage_error(it->second + ": " + s.message());
    return fail(s);
  }
  const tools::BatchReport& report = outcome->run;
  if (a.json) std::cout << tools::batch_report_to_json(outcome->report);
  for (const tools::BatchResult& r : report.shots)
    if (r.status != "ok") std::cerr << "rigel: " << r.shot << ": " << r.status << "; its log: " << r.log.string() << "\n";
  std::cerr << "rigel: batch " << op << ": " << report.shots.size() - report.failed() << " of " << report.shots.size()
            << " shots ok in " << number_text(report.seconds) << " s; report " << outcome->report_path.string() << "\n";
  return outcome->report.failed() == 0 ? 0 : kExitInvalidInput;
}

struct PublishArgs {
  std::string asset, project;
  bool json = false;
};

int run_publish(const PublishArgs& a) {
  Result<tools::Asset> asset = asset_named(a.asset, a.project);
  if (!asset) return fail(asset.status());
  tools::PublishOptions options;
  options.naming_template = settings().string("naming.template");
  options.checks = settings().flag("publish.checks");
  options.rigel_version = RIGEL_VERSION;
  auto r = tools::publish_asset(*asset, tools::components(), options);
  if (!r) return fail(r.status());
  if (a.json) {
    std::cout << Json{{"asset", asset->name}, {"version", r->version}, {"dir", r->dir.string()}, {"scene", r->scene.string()},
                      {"manifest", r->manifest.string()}, {"rigs", r->rigs}, {"warnings", r->warnings},
                      {"weightsVertices", r->weights_vertices}, {"shapesSet", r->shapes_set}, {"drivenCurves", r->driven_curves}, {"restError", r->rest_error}}
                     .dump()
              << "\n";
  }
  for (const std::string& w : r->warnings) std::cerr << "rigel: " << w << "\n";
  std::cerr << "rigel: published " << asset->name << " v" << r->version << " to " << r->dir.string() << "\n";
  return 0;
}

}  // namespace

struct PipelineCommands::State {
  CLI::App *project_new = nullptr, *project_info = nullptr, *asset_new = nullptr, *asset_info = nullptr;
  CLI::App *config_get = nullptr, *config_set = nullptr, *config_unset = nullptr, *config_list = nullptr;
  ProjectArgs project;
  AssetArgs asset;
  ConfigArgs config;
  CLI::App *data_export = nullptr, *data_import = nullptr;
  DataArgs data;
  CLI::App* publish = nullptr;
  PublishArgs publish_args;
  CLI::App* batch = nullptr;
  BatchArgs batch_args;
};

PipelineCommands::PipelineCommands() : state_(std::make_unique<State>()) {}
PipelineCommands::~PipelineCommands() = default;

void add_pipeline_commands(CLI::App& app, PipelineCommands& commands) {
  PipelineCommands::State& s = commands.state();
  CLI::App* project = app.add_subcommand("project", "Rigging projects: make one, or show it and its assets");
  project->require_subcommand(1);
  s.project_new = project->add_subcommand("new", "Make a folder a rigging project");
  s.project_new->footer("Examples:\n  rigel project new ~/rigs/show\n  rigel project new show --name the_show --json");
  s.project_new->add_option("DIR", s.project.dir, "The project's folder (made as needed; empty)")->required();
  s.project_new->add_option("--name", s.project.name, "Its name (default: the folder's)");
  s.project_new->add_flag("--json", s.project.json, "Print a JSON report on stdout");
  s.project_info = project->add_subcommand("info", "The project (the current folder's, or DIR) and its assets");
  s.project_info->add_option("DIR", s.project.dir, "The project's folder (default: the one the current folder is in)");
  s.project_info->add_flag("--json", s.project.json, "Print the project as JSON on stdout");

  CLI::App* asset = app.add_subcommand("asset", "Assets of a rigging project: make one, or show one");
  asset->require_subcommand(1);
  s.asset_new = asset->add_subcommand("new", "Make an asset in the current project (its build, skeleton, data, poses and rig folders)");
  s.asset_new->footer("Examples:\n  rigel asset new hero --skeleton body.glb\n  rigel asset new sword --type prop --project ~/rigs/show");
  s.asset_new->add_option("NAME", s.asset.name, "The asset's name")->required();
  s.asset_new->add_option("--type", s.asset.type, "character (default) or prop");
  s.asset_new->add_option("--skeleton", s.asset.skeleton, "A character file to copy into its skeleton/ folder");
  s.asset_new->add_option("--project", s.asset.project, "The project (default: the one the current folder is in)");
  s.asset_new->add_flag("--json", s.asset.json, "Print the asset as JSON on stdout");
  s.asset_info = asset->add_subcommand("info", "An asset (NAME, or the one the current folder is in)");
  s.asset_info->add_option("NAME", s.asset.name, "The asset's name");
  s.asset_info->add_option("--project", s.asset.project, "The project (default: the one the current folder is in)");
  s.asset_info->add_flag("--json", s.asset.json, "Print the asset as JSON on stdout");

  CLI::App* config = app.add_subcommand("config", "Settings: the current project's over the user's over the defaults");
  config->require_subcommand(1);
  config->footer("Examples:\n  rigel config list\n  rigel config set log.level info --user\n  rigel config get naming.template --json");
  s.config_get = config->add_subcommand("get", "A setting's value");
  s.config_get->add_option("KEY", s.config.key, "The setting (rigel config list shows them)")->required();
  s.config_get->add_flag("--json", s.config.json, "Print the value, its source and help as JSON");
  s.config_set = config->add_subcommand("set", "Set a setting in the project's file (in a project) or the user's");
  s.config_set->add_option("KEY", s.config.key, "The setting")->required();
  s.config_set->add_option("VALUE", s.config.value, "Its value")->required();
  s.config_unset = config->add_subcommand("unset", "Remove a setting from the project's file (in a project) or the user's");
  s.config_unset->add_option("KEY", s.config.key, "The setting")->required();
  for (CLI::App* c : {s.config_set, s.config_unset}) {
    c->add_flag("--user", s.config.user, "The user's settings file");
    c->add_flag("--project", s.config.project, "The current project's settings file");
  }
  s.config_list = config->add_subcommand("list", "Every setting with its value and where it comes from");
  s.config_list->add_flag("--json", s.config.json, "Print the settings as JSON on stdout");

  CLI::App* data = app.add_subcommand("data", "Hand-made rig data kept across rebuilds: skin weights, control shapes, blend shapes, driven poses, correctives");
  data->require_subcommand(1);
  data->footer("Examples:\n  rigel data export weights hero.rigel -o hero.weights.json\n"
               "  rigel data import weights copy.rigel hero.weights.json --rename names.json -o copy.rigel\n"
               "  rigel data import weights hero.rigel hero.weights.json --mirror -o hero.rigel\n"
               "  rigel data export shapes hero.rigel -o hero   (in an asset: data/shapes/hero.shapes.json)\n"
               "  rigel data export weights hero.rigel -o hero.weights.json --format binary\n"
               "  rigel data export driven_poses hero.rigel -o hero.drivenposes.json\n"
               "  rigel data import correctives hero.rigel hero.correctives.json -o hero.rigel\n"
               "  rigel data import blendshapes hero.rigel face -o hero.rigel   (in an asset: data/blendshapes/face.blendshapes.json)");
  s.data_export = data->add_subcommand("export", "Write a scene's data of one kind to a diffable JSON file");
  s.data_export->add_option("KIND", s.data.kind, "weights, shapes, blendshapes, driven_poses or correctives")->required();
  s.data_export->add_option("SCENE", s.data.scene, "Scene file (.rigel)")->required();
  s.data_export->add_option("-o,--output", s.data.output, "The data file (a bare name in an asset: its data folder)")->required();
  s.data_export->add_option("--format", s.data.format,
                            "Weights: json (all in the file) or binary (the arrays in a side file beside it, with a checksum); "
                            "default: the setting data.weights");
  s.data_import = data->add_subcommand("import", "Set a scene's data of one kind from a file and write the scene");
  s.data_import->add_option("KIND", s.data.kind, "weights, shapes, blendshapes, driven_poses or correctives")->required();
  s.data_import->add_option("SCENE", s.data.scene, "Scene file (.rigel)")->required();
  s.data_import->add_option("FILE", s.data.file, "The data file (a bare name in an asset: its data folder)")->required();
  s.data_import->add_option("-o,--output", s.data.output, "Scene file to write (.rigel)")->required();
  s.data_import->add_option("--rename", s.data.rename, "Weights: a JSON object of file joint name -> scene joint name");
  s.data_import->add_flag("--nearest", s.data.nearest, "Weights: joints found by neither uuid nor name go to the nearest joint");
  s.data_import->add_flag("--mirror", s.data.mirror, "Weights: mirrored across the character's plane (x -> -x), sides swapped");
  s.publish = app.add_subcommand("publish", "Build an asset from scratch, put its data back, check it, and write the next rig version");
  s.publish->footer("Examples:\n  rigel publish            (in an asset's folder)\n  rigel publish hero --project ~/rigs/show --json");
  s.publish->add_option("ASSET", s.publish_args.asset, "The asset (default: the one the current folder is in)");
  s.publish->add_option("--project", s.publish_args.project, "The project (default: the one the current folder is in)");
  s.publish->add_flag("--json", s.publish_args.json, "Print a JSON report on stdout");

  BatchArgs& b = s.batch_args;
  s.batch = app.add_subcommand("batch", "Run update, bake, export or validate over many shots, one process per shot, with a report");
  s.batch->footer("Examples:\n  rigel batch bake shots/*.rigel --frames 1:48 -o baked --jobs 2\n"
                  "  rigel batch update shots/*.rigel -o updated --json\n"
                  "  rigel batch bake --frames 1:48 -o baked --retry-failed baked/batch-report.json\n"
                  "  rigel batch validate shots/*.rigel --report validate.json");
  s.batch->add_option("OPERATION", b.operation, "update, bake, export or validate")->required();
  s.batch->add_option("SHOTS", b.shots, "Scene files (.rigel)");
  s.batch->add_option("-o,--output", b.output, "The folder each shot's output goes to (SHOT's name .rigel or .glb), and logs/");
  s.batch->add_option("--frames", b.frames, "bake (required) and export: FIRST:LAST");
  s.batch->add_option("--jobs", b.jobs, "Shots at once (default: the setting batch.jobs; 0: one per core)");
  s.batch->add_option("--report", b.report, "The report file (default: OUTDIR/batch-report.json)");
  s.batch->add_option("--retry-failed", b.retry, "Rerun the shots a report lists as failed, and update that report");
  s.batch->add_flag("--slurm", b.slurm, "Run the shots as one Slurm job array (sbatch) instead of local processes");
  s.batch->add_option("--partition", b.partition, "With --slurm: the partition (default: the setting batch.partition)");
  s.batch->add_flag("--json", b.json, "Print the report on stdout");

  for (CLI::App* c : {s.data_export, s.data_import}) {
    c->add_option("--rig", s.data.rig, "Shapes: the built rig (default: the scene's only one)");
    c->add_flag("--json", s.data.json, "Print a JSON report on stdout");
  }
}

std::optional<int> run_pipeline_commands(const PipelineCommands& commands) {
  const PipelineCommands::State& s = commands.state();
  if (*s.project_new) return run_project_new(s.project);
  if (*s.project_info) return run_project_info(s.project);
  if (*s.asset_new) return run_asset_new(s.asset);
  if (*s.asset_info) return run_asset_info(s.asset);
  if (*s.config_get) return run_config("get", s.config);
  if (*s.config_set) return run_config("set", s.config);
  if (*s.config_unset) return run_config("unset", s.config);
  if (*s.config_list) return run_config("list", s.config);
  if (*s.publish) return run_publish(s.publish_args);
  if (*s.batch) return run_batch(s.batch_args);
  if (*s.data_export) return run_data(true, s.data);
  if (*s.data_import) return run_data(false, s.data);
  return std::nullopt;
}

void add_log_level_option(CLI::App& app, std::string& level) {
  app.add_option("--log-level", level, std::string("What to print on stderr: ") + log::level_names() +
                                           " (default: the settings' log.level, warn)");
  app.fallthrough();
}

namespace {
tools::Config& loaded_settings() {
  static tools::Config c;
  return c;
}
}  // namespace

const tools::Config& settings() { return loaded_settings(); }

std::string in_current_asset(const std::string& given, tools::AssetFile kind) {
  std::error_code ec;
  if (given.empty() || fs::exists(given, ec)) return given;
  auto asset = tools::find_asset(fs::current_path());
  if (!asset) return given;
  auto found = tools::resolve_in_asset(*asset, given, kind, "file");
  if (found) log::debug(given + " is " + found->string() + " in asset " + asset->name);
  return found ? found->string() : given;
}

std::string current_asset_skeleton() {
  auto asset = tools::find_asset(fs::current_path());
  return asset && !asset->skeleton.empty() ? (asset->dir / asset->skeleton).string() : std::string();
}

std::optional<int> apply_log_level(const std::string& given) {
  std::optional<log::Level> level;
  if (!given.empty()) {
    level = log::level_from_name(given);
    if (!level) return usage_error("--log-level '" + given + "': expected one of " + log::level_names());
    log::set_level(*level);
  }
  auto config = tools::Config::load(tools::user_config_path(), project_config());
  if (!config) {
    log::warn("settings left out: " + config.status().message());
    return std::nullopt;
  }
  loaded_settings() = std::move(*config);
  if (!level)
    if (const auto from = log::level_from_name(loaded_settings().string("log.level"))) log::set_level(*from);
  return std::nullopt;
}

}  // namespace rigel::cli
