// `rigel space` (see space_command.h).

#include "space_command.h"

#include <cmath>
#include <iostream>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_util.h"
#include "rigel/app/workspace.h"
#include "rigel/ephemeral/component.h"
#include "rigel/tools/data_files.h"

namespace rigel::cli {
namespace {

using Json = nlohmann::ordered_json;

struct SpaceArgs {
  std::string scene;
  std::string control;
  bool list = false;
  std::string add, target, to;
  std::optional<double> frame;
  std::string frames;
  std::string output;
  bool json = false;
};

Json spaces_json(const app::Workspace& ws, const rig::ControlSpaces& s) {
  Json list = Json::array();
  for (const rig::Space& space : s.spaces)
    list.push_back({{"name", space.name},
                    {"target", space.target.is_valid() ? Json(ws.graph().node(space.target)->name()) : Json(nullptr)}});
  return Json{{"control", ws.graph().node(s.control)->name()},
              {"spaces", list},
              {"current", s.spaces.empty() ? Json(nullptr) : Json(s.spaces[static_cast<std::size_t>(s.current)].name)}};
}

std::string option_of(const std::string& field) {
  if (field == "control") return ": --control";
  if (field == "space") return ": --switch";
  if (field == "target") return ": --target";
  if (field == "frames") return ": --frames";
  return "";
}

int run_space(const SpaceArgs& args) {
  const int modes = (args.list ? 1 : 0) + (args.add.empty() ? 0 : 1) + (args.to.empty() ? 0 : 1);
  if (modes != 1) return usage_error("give one of --list, --add NAME or --switch NAME");
  if (!args.list && args.output.empty()) return usage_error("--add and --switch write a scene: give -o OUT");
  if (args.list && !args.output.empty()) return usage_error("--list writes nothing: drop -o");
  if (!args.target.empty() && args.add.empty()) return usage_error("--target goes with --add");
  if ((args.frame || !args.frames.empty()) && args.to.empty()) return usage_error("--frame and --frames go with --switch");
  if (args.frame && !std::isfinite(*args.frame)) return usage_error("--frame must be a finite number");
  tools::SpaceSwitchOptions options;
  options.space = args.to;
  options.frame = args.frame;
  if (!args.frames.empty()) {
    const auto range = parse_frames(args.frames);
    if (!range) return usage_error("--frames '" + args.frames + "': " + kFramesExpected);
    options.first = range->first;
    options.last = range->second;
  }
  auto scene = load(args.scene);
  if (!scene) return fail(scene.status());
  app::Workspace ws(std::move(*scene), args.scene, {}, tools::components());
  auto control = ws.node(args.control, "control");
  if (!control) return fail(Status(control.status().code(), args.scene + ": --control: " + control.status().message()));
  const std::string name = ws.graph().node(*control)->name();
  if (args.list) {
    const rig::ControlSpaces s = ws.spaces(*control);
    if (args.json) {
      std::cout << spaces_json(ws, s).dump() << "\n";
    } else if (s.spaces.empty()) {
      std::cout << name << ": no spaces\n";
    } else {
      for (std::size_t i = 0; i < s.spaces.size(); ++i) {
        const rig::Space& space = s.spaces[i];
        std::cout << (static_cast<int>(i) == s.current ? "* " : "  ") << i << " " << space.name << "  "
                  << (space.target.is_valid() ? ws.graph().node(space.target)->name() : std::string("(world)")) << "\n";
      }
    }
    return 0;
  }
  if (!args.add.empty()) {
    graph::NodeId target;
    if (!args.target.empty()) {
      auto t = ws.node(args.target, "target");
      if (!t) return fail(Status(t.status().code(), args.scene + ": --target: " + t.status().message()));
      target = *t;
    }
    auto index = ws.add_space(*control, args.add, target);
    if (!index) return fail(index.status().with_context(args.scene + option_of(index.status().field())));
    if (auto saved = ws.save(args.output); !saved) return fail(saved.status());
    if (args.json) std::cout << spaces_json(ws, ws.spaces(*control)).dump() << "\n";
    std::cerr << "rigel: added space " << args.add << " (" << *index << ") to " << name << ", following "
              << (target.is_valid() ? ws.graph().node(target)->name() : std::string("the world")) << "; wrote "
              << args.output << "\n";
    return 0;
  }
  TerminalProgress progress("switching space");
  options.progress = progress.callback();
  auto report = ws.switch_space(*control, options);
  progress.finish();
  if (!report) return fail(report.status().with_context(args.scene + option_of(report.status().field())));
  if (auto saved = ws.save(args.output); !saved) return fail(saved.status());
  if (args.json)
    std::cout << Json{{"control", name},          {"from", report->from},         {"to", report->to},
                      {"frames", report->frames}, {"keys", report->keys},         {"maxError", report->max_error},
                      {"worstFrame", report->worst_frame}, {"output", args.output}}
                     .dump()
              << "\n";
  std::cerr << "rigel: " << name << " from space " << report->from << " to " << report->to
            << (options.first ? " baked over " : " at ") << report->frames << (report->frames == 1 ? " frame" : " frames")
            << " (" << report->keys << " keys); largest change of its world matrix " << number_text(report->max_error)
            << "; wrote " << args.output << "\n";
  return 0;
}

}  // namespace

struct SpaceCommand::State {
  CLI::App* cmd = nullptr;
  SpaceArgs args;
};

SpaceCommand::SpaceCommand() : state_(std::make_unique<State>()) {}
SpaceCommand::~SpaceCommand() = default;

void add_space_command(CLI::App& app, SpaceCommand& command) {
  SpaceCommand::State& s = command.state();
  s.cmd = app.add_subcommand("space", "A control's spaces: list, add, switch at a frame, bake a range");
  s.cmd->footer(
      "A switch keys the control's space and a compensation with step tangents at the frame, so the control stays "
      "where it is there, frames before it are unchanged and the control keeps its own keys; --frames bakes the "
      "range into the space, keying the control at every frame so its world motion is kept. Built limbs' IK controls "
      "come with spaces (parent, world, global, chest, head / hip); --add gives any control more.\n"
      "Examples:\n  rigel space shot.rigel --control hero_arm_L_ik --list\n"
      "  rigel space shot.rigel --control hero_arm_L_ik --add prop --target sword -o shot.rigel\n"
      "  rigel space shot.rigel --control hero_arm_L_ik --switch world --frame 40 -o shot.rigel\n"
      "  rigel space shot.rigel --control hero_arm_L_ik --switch chest --frames 10:60 -o shot.rigel --json");
  s.cmd->add_option("SCENE", s.args.scene, "Scene file (.rigel)")->required();
  s.cmd->add_option("--control", s.args.control, "The control (name or rig address)")->required();
  s.cmd->add_flag("--list", s.args.list, "List its spaces (* marks the one followed now)");
  s.cmd->add_option("--add", s.args.add, "Add a space of this name");
  s.cmd->add_option("--target", s.args.target, "With --add: the transform it follows (default: the world)");
  s.cmd->add_option("--switch", s.args.to, "Switch to this space");
  CLI::Option* one = s.cmd->add_option("--frame", s.args.frame, "The switch's frame (default: the scene's current frame)");
  CLI::Option* range = s.cmd->add_option("--frames", s.args.frames, "Bake a range FIRST:LAST into the space");
  one->excludes(range);
  s.cmd->add_option("-o,--output", s.args.output, "Scene file to write (.rigel)");
  s.cmd->add_flag("--json", s.args.json, "Print a JSON report on stdout");
}

std::optional<int> run_space_command(const SpaceCommand& command) {
  const SpaceCommand::State& s = command.state();
  if (*s.cmd) return run_space(s.args);
  return std::nullopt;
}

}  // namespace rigel::cli
