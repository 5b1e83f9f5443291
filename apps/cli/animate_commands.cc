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

namespace rigel::cli {
namespace {

using Json = nlohmann::ordered_json;
using rig::components::MatchSide;

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
  if (!args.frames.empty()) {
    const auto range = parse_frames(args.frames);
    if (!range) return usage_error("--frames '" + args.frames + "': " + kFramesExpected);
    options.first = range->first;
    options.last = range->second;
  }
  auto scene = load(args.scene);
  if (!scene) return fail(scene.status());
  app::Workspace ws(std::move(*scene), args.scene, {}, ephemeral::components());
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

}  // namespace

struct AnimateCommands::State {
  CLI::App* match_cmd = nullptr;
  MatchArgs match;
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
  CLI::Option* frame = s.match_cmd->add_option("--frame", s.match.frame, "One frame (default: the scene's current frame)");
  CLI::Option* frames = s.match_cmd->add_option("--frames", s.match.frames, "A range FIRST:LAST, every frame keyed");
  frame->excludes(frames);
  s.match_cmd->add_option("-o,--output", s.match.output, "Scene file to write (.rigel)")->required();
  s.match_cmd->add_flag("--json", s.match.json, "Print a JSON report on stdout");
}

std::optional<int> run_animate_commands(const AnimateCommands& commands) {
  const AnimateCommands::State& s = commands.state();
  if (*s.match_cmd) return run_match(s.match);
  return std::nullopt;
}

}  // namespace rigel::cli
