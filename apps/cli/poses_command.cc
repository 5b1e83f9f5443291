// `rigel poses ...`: the pose library (see poses_command.h). Each
// subcommand refuses bad input with exit 1 and a message naming the option
// at fault, writing nothing.

#include "poses_command.h"

#include <cmath>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_util.h"
#include "pipeline_commands.h"
#include "rigel/app/workspace.h"
#include "rigel/ephemeral/component.h"
#include "rigel/tools/data_files.h"

namespace rigel::cli {
namespace {

using Json = nlohmann::ordered_json;

struct PoseArgs {
  std::string library, scene;
  std::string name, rig;
  std::vector<std::string> controls;
  bool mirror = false;
  std::string plane = "yz";
  double fraction = 1;
  std::optional<double> frame;
  bool key = false;
  std::string output;
  bool json = false;
};

// The option a workspace error's field stands for ("" when none does).
std::string option_of(const std::string& field) {
  if (field == "rig") return "--rig";
  if (field == "name") return "--name";
  if (field == "fraction") return "--fraction";
  if (field == "library") return "LIBRARY";
  if (field.rfind("controls", 0) == 0) return "--controls";
  return "";
}

int failed(const Status& s, const std::string& where) {
  const std::string option = option_of(s.field());
  return fail(s.with_context(where + (option.empty() ? "" : ": " + option)));
}

Json names_json(const app::Workspace& ws, const std::vector<graph::NodeId>& ids) {
  Json out = Json::array();
  for (graph::NodeId n : ids) out.push_back(ws.graph().node(n)->name());
  return out;
}

// The workspace on SCENE with --controls resolved (exit code on failure).
struct Opened {
  std::unique_ptr<app::Workspace> ws;
  std::vector<graph::NodeId> controls;
};
std::optional<int> open(const PoseArgs& args, Opened& out) {
  for (const std::string& name : args.controls)
    if (name.empty()) return usage_error("--controls: empty name (expected A,B,...)");
  auto scene = load(args.scene);
  if (!scene) return fail(scene.status());
  out.ws = std::make_unique<app::Workspace>(std::move(*scene), args.scene, std::filesystem::path(), tools::components());
  for (const std::string& name : args.controls) {
    auto id = out.ws->node(name, "controls");
    if (!id) return fail(Status(id.status().code(), args.scene + ": --controls: no node named '" + name + "'"));
    out.controls.push_back(*id);
  }
  return std::nullopt;
}

int run_save(const PoseArgs& args) {
  Opened o;
  if (auto code = open(args, o)) return *code;
  auto saved = o.ws->save_pose(args.library, args.name, args.rig, o.controls);
  if (!saved) return failed(saved.status(), args.scene);
  if (args.json)
    std::cout << Json{{"name", args.name}, {"path", saved->path.string()}, {"entries", saved->entries}}.dump() << "\n";
  std::cerr << "rigel: saved pose '" << args.name << "' (" << saved->entries << " nodes) to " << saved->path.string() << "\n";
  return 0;
}

int run_apply(const PoseArgs& args) {
  if (!std::isfinite(args.fraction) || args.fraction < 0 || args.fraction > 1)
    return usage_error("--fraction must be a number within 0..1");
  if (args.frame && !std::isfinite(*args.frame)) return usage_error("--frame must be a finite number");
  if (args.plane != "yz" && args.plane != "xy" && args.plane != "xz")
    return usage_error("--plane must be yz, xy or xz, got '" + args.plane + "'");
  Opened o;
  if (auto code = open(args, o)) return *code;
  app::Workspace& ws = *o.ws;
  if (args.frame)
    if (Status s = ws.set_frame(*args.frame); !s) return fail(Status(s.code(), args.scene + ": --" + s.message()));
  tools::ApplyPoseOptions options;
  options.controls = o.controls;
  options.mirrored = args.mirror;
  options.plane = args.plane == "yz" ? tools::MirrorPlane::kYZ : args.plane == "xy" ? tools::MirrorPlane::kXY
                                                                                    : tools::MirrorPlane::kXZ;
  options.fraction = args.fraction;
  options.key = args.key;
  auto report = ws.apply_pose(args.library, args.name, args.rig, options);
  if (!report) return failed(report.status(), args.scene);
  if (auto saved = ws.save(args.output); !saved) return fail(saved.status());
  if (args.json) {
    std::cout << Json{{"name", args.name},         {"set", names_json(ws, report->set)}, {"channels", report->channels},
                      {"keyed", report->keyed},    {"unpaired", report->unpaired},      {"skipped", report->skipped},
                      {"output", args.output}}
                     .dump()
              << "\n";
  }
  std::cerr << "rigel: applied pose '" << args.name << "'" << (args.mirror ? " mirrored" : "") << " to "
            << report->set.size() << " nodes (" << report->channels << " channels, " << report->keyed << " keyed)";
  if (!report->unpaired.empty()) std::cerr << "; " << report->unpaired.size() << " entries without a pair left";
  std::cerr << "; wrote " << args.output << "\n";
  return 0;
}

// list and remove need no scene: a workspace on an empty one.
app::Workspace library_workspace() {
  return app::Workspace(std::make_shared<scene::Scene>(), {}, {}, tools::components());
}

int run_list(const PoseArgs& args) {
  auto list = library_workspace().list_poses(args.library);
  if (!list) return failed(list.status(), args.library);
  if (args.json) {
    Json poses = Json::array();
    for (const tools::PoseInfo& p : *list) {
      Json j{{"name", p.name}, {"rig", p.rig}, {"entries", p.entries}, {"thumbnail", p.thumbnail}};
      if (!p.error.empty()) j["error"] = p.error;
      poses.push_back(std::move(j));
    }
    std::cout << Json{{"library", args.library}, {"poses", poses}}.dump() << "\n";
    return 0;
  }
  for (const tools::PoseInfo& p : *list) {
    if (p.error.empty()) std::cout << p.name << "\t" << p.rig << "\t" << p.entries << " nodes\n";
    else std::cout << p.name << "\t(unreadable: " << p.error << ")\n";
  }
  return 0;
}

int run_remove(const PoseArgs& args) {
  if (Status s = library_workspace().remove_pose(args.library, args.name); !s) return failed(s, args.library);
  std::cerr << "rigel: removed pose '" << args.name << "' from " << args.library << "\n";
  return 0;
}

}  // namespace

struct PosesCommand::State {
  CLI::App* poses = nullptr;
  CLI::App *save = nullptr, *apply = nullptr, *list = nullptr, *remove = nullptr;
  PoseArgs save_args, apply_args, list_args, remove_args;
};

PosesCommand::PosesCommand() : state_(std::make_unique<State>()) {}
PosesCommand::~PosesCommand() = default;

void add_poses_command(CLI::App& app, PosesCommand& command) {
  PosesCommand::State& s = command.state();
  s.poses = app.add_subcommand("poses", "The pose library: save, apply, list and remove named poses of built rigs");
  s.poses->require_subcommand(1);
  s.poses->footer(
      "A pose is LIBRARY/NAME.pose.json (diffable JSON): each control's (and switch's) channels, found on the target "
      "by its component's rigId and its role, never by names, so it applies to any character built from the same "
      "definition, after renames and rebuilds.\n"
      "Examples:\n  rigel poses save poses shot.rigel --rig hero --name wave\n"
      "  rigel poses save poses shot.rigel --controls hero:arm_L/fk[0],hero:arm_L/fk[1] --name arm_up\n"
      "  rigel poses apply poses other.rigel --name wave --mirror --fraction 0.5 --frame 12 --key -o other.rigel\n"
      "  rigel poses list poses --json\n  rigel poses remove poses --name wave");
  auto library = [](CLI::App* c, PoseArgs& a) {
    c->add_option("LIBRARY", a.library, "The pose library (a folder)")->required();
  };
  s.save = s.poses->add_subcommand("save", "Save the pose of a rig or of some of its controls");
  library(s.save, s.save_args);
  s.save->add_option("SCENE", s.save_args.scene, "Scene file (.rigel)")->required();
  s.save->add_option("--rig", s.save_args.rig, "The built rig (default: the scene's only rig)");
  s.save->add_option("--controls", s.save_args.controls, "Only these controls (names or rig addresses)")->delimiter(',');
  s.save->add_option("--name", s.save_args.name, "The pose's name (letters, digits, _ - .)")->required();
  s.save->add_flag("--json", s.save_args.json, "Print a JSON report on stdout");

  s.apply = s.poses->add_subcommand("apply", "Apply a saved pose to a rig, all of it or a selection, mirrored, blended");
  library(s.apply, s.apply_args);
  s.apply->add_option("SCENE", s.apply_args.scene, "Scene file (.rigel)")->required();
  s.apply->add_option("--name", s.apply_args.name, "The pose's name")->required();
  s.apply->add_option("--rig", s.apply_args.rig, "The target rig (default: the pose's rig, or the scene's only one)");
  s.apply->add_option("--controls", s.apply_args.controls, "Only these controls of the target")->delimiter(',');
  s.apply->add_flag("--mirror", s.apply_args.mirror, "Each entry onto its pair on the other side");
  s.apply->add_option("--plane", s.apply_args.plane, "Mirror plane: yz (x -> -x, the default), xy or xz");
  s.apply->add_option("--fraction", s.apply_args.fraction, "0..1: blend from the current pose (default 1)");
  s.apply->add_option("--frame", s.apply_args.frame, "The frame (default: the scene's current frame)");
  s.apply->add_flag("--key", s.apply_args.key, "Key the channels at that frame");
  s.apply->add_option("-o,--output", s.apply_args.output, "Scene file to write (.rigel)")->required();
  s.apply->add_flag("--json", s.apply_args.json, "Print a JSON report on stdout");

  s.list = s.poses->add_subcommand("list", "List a library's poses: name, rig, nodes");
  library(s.list, s.list_args);
  s.list->add_flag("--json", s.list_args.json, "Print JSON on stdout");

  s.remove = s.poses->add_subcommand("remove", "Delete a pose from a library");
  library(s.remove, s.remove_args);
  s.remove->add_option("--name", s.remove_args.name, "The pose's name")->required();
}

std::optional<int> run_poses_command(const PosesCommand& command) {
  const PosesCommand::State& s = command.state();
  if (!*s.poses) return std::nullopt;
  // Inside an asset, "poses" (or a bare name) is its pose library.
  auto in_asset = [](PoseArgs a) {
    a.library = in_current_asset(a.library, tools::AssetFile::kPoseLibrary);
    return a;
  };
  if (*s.save) return run_save(in_asset(s.save_args));
  if (*s.apply) return run_apply(in_asset(s.apply_args));
  if (*s.list) return run_list(in_asset(s.list_args));
  if (*s.remove) return run_remove(in_asset(s.remove_args));
  return std::nullopt;
}

}  // namespace rigel::cli
