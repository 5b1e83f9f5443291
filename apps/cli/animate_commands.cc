// The animator tools' commands (see animate_commands.h).

#include "animate_commands.h"

#include <cmath>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_util.h"
#include "rigel/app/workspace.h"
#include "rigel/ephemeral/component.h"
#include "rigel/tools/data_files.h"

namespace rigel::cli {
namespace {

using Json = nlohmann::ordered_json;
using rig::components::MatchSide;

// --frames FIRST:LAST into first and last (both left unset when empty);
// false when the text is not a range.
bool read_frames(const std::string& text, std::optional<double>& first, std::optional<double>& last) {
  if (text.empty()) return true;
  const auto range = parse_frames(text);
  if (!range) return false;
  first = range->first;
  last = range->second;
  return true;
}

// ---- match ---------------------------------------------------------------

struct MatchArgs {
  std::string scene;
  std::string rig, component, to;
  std::optional<double> frame;
  std::string frames;
  std::string output;
  bool json = false;
};

// The option a workspace error's field stands for.
std::string option_of(const std::string& field) {
  if (field == "rig") return "--rig";
  if (field == "component") return "--component";
  if (field == "frames") return "--frames";
  return "";
}

int run_match(const MatchArgs& args) {
  if (args.to != "fk" && args.to != "ik") return usage_error("--to must be fk or ik, got '" + args.to + "'");
  if (args.frame && !std::isfinite(*args.frame)) return usage_error("--frame must be a finite number");
  tools::MatchOptions options;
  options.to = args.to == "fk" ? MatchSide::kFk : MatchSide::kIk;
  if (!read_frames(args.frames, options.first, options.last))
    return usage_error("--frames '" + args.frames + "': " + kFramesExpected);
  auto scene = load(args.scene);
  if (!scene) return fail(scene.status());
  app::Workspace ws(std::move(*scene), args.scene, {}, tools::components());
  if (args.frame) {
    if (Status s = ws.set_frame(*args.frame); !s) return fail(Status(s.code(), args.scene + ": --" + s.message()));
  }
  TerminalProgress progress("matching");
  options.progress = progress.callback();
  auto report = ws.match(args.rig, args.component, options);
  progress.finish();
  if (!report) {
    const Status& s = report.status();
    const std::string option = option_of(s.field());
    return fail(s.with_context(args.scene + (option.empty() ? "" : ": " + option)));
  }
  if (auto saved = ws.save(args.output); !saved) return fail(saved.status());
  const graph::Graph& g = ws.graph();
  const double first = options.first.value_or(ws.scene().frame()), last = options.last.value_or(first);
  if (args.json) {
    Json controls = Json::array();
    for (graph::NodeId c : report->controls) controls.push_back(g.node(c)->name());
    std::cout << Json{{"rig", args.rig},       {"component", args.component}, {"to", args.to},
                      {"frames", {first, last}}, {"framesKeyed", report->frames},  {"keys", report->keys},
                      {"controls", controls},  {"maxError", report->max_error}, {"worstFrame", report->worst_frame},
                      {"output", args.output}}
                     .dump()
              << "\n";
  }
  std::cerr << "rigel: matched " << args.component << " to " << (args.to == "fk" ? "FK" : "IK") << " at "
            << report->frames << (report->frames == 1 ? " frame" : " frames") << " (" << report->keys
            << " keys); largest joint difference " << number_text(report->max_error);
  if (report->max_error > 1e-6)
    std::cerr << " at frame " << number_text(report->worst_frame)
              << " (the IK side cannot reach that FK pose: the middle joint bends off its hinge)";
  std::cerr << "; wrote " << args.output << "\n";
  return 0;
}

// ---- mirror --------------------------------------------------------------

struct MirrorArgs {
  std::string scene;
  std::vector<std::string> controls;
  bool all = false, flip = false;
  std::string from = "L", plane = "yz";
  std::optional<double> frame;
  std::string frames;
  std::string output;
  bool json = false;
};

int run_mirror(const MirrorArgs& args) {
  if (args.controls.empty() && !args.all) return usage_error("give --controls A,B,... or --all");
  if (args.from != "L" && args.from != "R") return usage_error("--from must be L or R, got '" + args.from + "'");
  if (args.plane != "yz" && args.plane != "xy" && args.plane != "xz")
    return usage_error("--plane must be yz, xy or xz, got '" + args.plane + "'");
  if (args.frame && !std::isfinite(*args.frame)) return usage_error("--frame must be a finite number");
  for (const std::string& name : args.controls)
    if (name.empty()) return usage_error("--controls: empty name (expected A,B,...)");
  tools::MirrorOptions options;
  options.all = args.all;
  options.flip = args.flip;
  options.from = args.from[0];
  options.plane = args.plane == "yz" ? tools::MirrorPlane::kYZ : args.plane == "xy" ? tools::MirrorPlane::kXY
                                                                                    : tools::MirrorPlane::kXZ;
  if (!read_frames(args.frames, options.first, options.last))
    return usage_error("--frames '" + args.frames + "': " + kFramesExpected);
  auto scene = load(args.scene);
  if (!scene) return fail(scene.status());
  app::Workspace ws(std::move(*scene), args.scene, {}, tools::components());
  for (const std::string& name : args.controls) {
    auto id = ws.node(name, "controls");
    if (!id) return fail(Status(id.status().code(), args.scene + ": --controls: no node named '" + name + "'"));
    options.controls.push_back(*id);
  }
  if (args.frame) {
    if (Status s = ws.set_frame(*args.frame); !s) return fail(Status(s.code(), args.scene + ": --" + s.message()));
  }
  TerminalProgress progress(args.flip ? "flipping" : "mirroring");
  options.progress = progress.callback();
  auto report = ws.mirror(options);
  progress.finish();
  if (!report) {
    const Status& s = report.status();
    return fail(s.with_context(args.scene + (s.field() == "frames" ? ": --frames" : s.field() == "controls" ? ": --controls" : "")));
  }
  if (auto saved = ws.save(args.output); !saved) return fail(saved.status());
  if (args.json) {
    Json set = Json::array();
    for (graph::NodeId n : report->set) set.push_back(ws.graph().node(n)->name());
    std::cout << Json{{"flip", args.flip}, {"frames", report->frames}, {"keys", report->keys}, {"set", set},
                      {"output", args.output}}
                     .dump()
              << "\n";
  }
  std::cerr << "rigel: " << (args.flip ? "flipped " : "mirrored onto ") << report->set.size() << " nodes at "
            << report->frames << (report->frames == 1 ? " frame" : " frames") << " (" << report->keys << " keys); wrote "
            << args.output << "\n";
  return 0;
}

// ---- bind-pose -----------------------------------------------------------

struct BindPoseArgs {
  std::string scene;
  std::vector<std::string> controls;
  std::optional<double> frame;
  bool key = false;
  std::string output;
  bool json = false;
};

int run_bind_pose(const BindPoseArgs& args) {
  if (args.frame && !std::isfinite(*args.frame)) return usage_error("--frame must be a finite number");
  for (const std::string& name : args.controls)
    if (name.empty()) return usage_error("--controls: empty name (expected A,B,...)");
  auto scene = load(args.scene);
  if (!scene) return fail(scene.status());
  app::Workspace ws(std::move(*scene), args.scene, {}, tools::components());
  std::vector<graph::NodeId> nodes;
  for (const std::string& name : args.controls) {
    auto id = ws.node(name, "controls");
    if (!id) return fail(Status(id.status().code(), args.scene + ": --controls: " + id.status().message()));
    nodes.push_back(*id);
  }
  if (args.frame) {
    if (Status s = ws.set_frame(*args.frame); !s) return fail(Status(s.code(), args.scene + ": --" + s.message()));
  }
  auto report = ws.reset_bind_pose(nodes, args.key);
  if (!report) return fail(report.status().with_context(args.scene + ": --controls"));
  if (auto saved = ws.save(args.output); !saved) return fail(saved.status());
  if (args.json) {
    Json set = Json::array();
    for (graph::NodeId n : report->set) set.push_back(ws.graph().node(n)->name());
    std::cout << Json{{"channels", report->channels}, {"set", set}, {"keyed", args.key}, {"output", args.output}}.dump()
              << "\n";
  }
  std::cerr << "rigel: reset " << report->set.size() << " nodes (" << report->channels << " channels) to the bind pose"
            << (args.key ? ", keyed" : "") << "; wrote " << args.output << "\n";
  return 0;
}

// --frame F and --frames A:B, one or the other.
void add_frame_options(CLI::App* cmd, std::optional<double>& frame, std::string& frames) {
  CLI::Option* one = cmd->add_option("--frame", frame, "One frame (default: the scene's current frame)");
  CLI::Option* range = cmd->add_option("--frames", frames, "A range FIRST:LAST, every frame keyed");
  one->excludes(range);
}

}  // namespace

struct AnimateCommands::State {
  CLI::App* match_cmd = nullptr;
  MatchArgs match;
  CLI::App* mirror_cmd = nullptr;
  MirrorArgs mirror;
  CLI::App* bind_cmd = nullptr;
  BindPoseArgs bind;
};

AnimateCommands::AnimateCommands() : state_(std::make_unique<State>()) {}
AnimateCommands::~AnimateCommands() = default;

void add_animate_commands(CLI::App& app, AnimateCommands& commands) {
  AnimateCommands::State& s = commands.state();
  s.match_cmd = app.add_subcommand("match", "FK/IK match and bake: key a limb's FK controls to its IK pose, or back");
  s.match_cmd->footer(
      "--to fk keys the FK controls (and a foot's FK toe) to the IK pose at each frame and keys the switch to FK; "
      "--to ik keys the ik and pole controls (and a foot's toe tap) to the FK pose and the switch to IK. The switch "
      "is keyed with step tangents at the range's ends; no other frame gets a key.\n"
      "Examples:\n  rigel match shot.rigel --rig hero --component arm_L --to fk --frame 12 -o shot.rigel\n"
      "  rigel match shot.rigel --rig hero --component leg_L --to ik --frames 0:100 -o shot.rigel --json");
  s.match_cmd->add_option("SCENE", s.match.scene, "Scene file (.rigel)")->required();
  s.match_cmd->add_option("--rig", s.match.rig, "The built rig's name")->required();
  s.match_cmd->add_option("--component", s.match.component, "The limb: component name or rigId")->required();
  s.match_cmd->add_option("--to", s.match.to, "The side to key and switch to: fk or ik")->required();
  add_frame_options(s.match_cmd, s.match.frame, s.match.frames);
  s.match_cmd->add_option("-o,--output", s.match.output, "Scene file to write (.rigel)")->required();
  s.match_cmd->add_flag("--json", s.match.json, "Print a JSON report on stdout");

  s.mirror_cmd = app.add_subcommand("mirror", "Mirror a built rig's pose to the other side, or flip both sides");
  s.mirror_cmd->footer(
      "Pairs come from the rig's components (the same type and name on the other side), never from node names. "
      "Without --flip each given control's pose goes onto its pair (--all: every control of the rig, from the --from "
      "side, with its switches and foot values); with --flip both sides swap and centre controls mirror in place.\n"
      "Examples:\n  rigel mirror shot.rigel --controls hero_arm_L_fk0,hero_arm_L_fk1 -o shot.rigel\n"
      "  rigel mirror shot.rigel --all --flip --frames 0:200 -o flipped.rigel --json");
  s.mirror_cmd->add_option("SCENE", s.mirror.scene, "Scene file (.rigel)")->required();
  s.mirror_cmd->add_option("--controls", s.mirror.controls, "Built rigs' controls (names or rig addresses)")->delimiter(',');
  s.mirror_cmd->add_flag("--all", s.mirror.all, "Every control of the rig (of every rig without --controls)");
  s.mirror_cmd->add_option("--from", s.mirror.from, "With --all: the side copied, L (default) or R");
  s.mirror_cmd->add_flag("--flip", s.mirror.flip, "Swap both sides' poses (centre controls mirror in place)");
  s.mirror_cmd->add_option("--plane", s.mirror.plane, "Mirror plane: yz (x -> -x, the default), xy or xz");
  add_frame_options(s.mirror_cmd, s.mirror.frame, s.mirror.frames);
  s.mirror_cmd->add_option("-o,--output", s.mirror.output, "Scene file to write (.rigel)")->required();
  s.mirror_cmd->add_flag("--json", s.mirror.json, "Print a JSON report on stdout");

  s.bind_cmd = app.add_subcommand("bind-pose", "Reset controls, components or whole built rigs to their bind pose");
  s.bind_cmd->footer(
      "Controls go back to their rest as built (translate 0, rotation 0, scale 1); a component's switches and foot "
      "values to theirs as built. Name controls, components (RIG:COMPONENT) or rigs (RIG:).\n"
      "Examples:\n  rigel bind-pose shot.rigel --controls hero_arm_L_fk1 -o shot.rigel\n"
      "  rigel bind-pose shot.rigel --controls hero:arm_L,hero:leg_L --frame 24 --key -o shot.rigel\n"
      "  rigel bind-pose shot.rigel --controls hero: -o rest.rigel");
  s.bind_cmd->add_option("SCENE", s.bind.scene, "Scene file (.rigel)")->required();
  s.bind_cmd->add_option("--controls", s.bind.controls, "Controls, RIG:COMPONENT or RIG:")->delimiter(',')->required();
  s.bind_cmd->add_option("--frame", s.bind.frame, "The frame (default: the scene's current frame)");
  s.bind_cmd->add_flag("--key", s.bind.key, "Key the reset channels at that frame");
  s.bind_cmd->add_option("-o,--output", s.bind.output, "Scene file to write (.rigel)")->required();
  s.bind_cmd->add_flag("--json", s.bind.json, "Print a JSON report on stdout");
}

std::optional<int> run_animate_commands(const AnimateCommands& commands) {
  const AnimateCommands::State& s = commands.state();
  if (*s.match_cmd) return run_match(s.match);
  if (*s.mirror_cmd) return run_mirror(s.mirror);
  if (*s.bind_cmd) return run_bind_pose(s.bind);
  return std::nullopt;
}

}  // namespace rigel::cli
