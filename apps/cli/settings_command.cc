// `rigel playback` and `rigel sets` (see settings_command.h).

#include "settings_command.h"

#include <algorithm>
#include <cmath>
#include <iostream>
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

struct PlaybackArgs {
  std::string scene, range, output;
  bool json = false;
};

struct PickerArgs {
  std::string scene;
  bool json = false;
};

struct TrailArgs {
  std::string scene, frames;
  std::vector<std::string> controls;
  double step = 1;
  bool json = false;
};

struct SetsArgs {
  std::string scene, save, remove, output;
  std::vector<std::string> controls;
  bool json = false;
};

int run_playback(const PlaybackArgs& args) {
  if (args.range.empty() != args.output.empty()) return usage_error("--range writes a scene: give it with -o OUT");
  auto scene = load(args.scene);
  if (!scene) return fail(scene.status());
  app::Workspace ws(std::move(*scene), args.scene, {}, tools::components());
  if (!args.range.empty()) {
    const auto range = parse_frames(args.range);
    if (!range) return usage_error("--range '" + args.range + "': " + kFramesExpected);
    if (Status s = ws.set_playback_range(range->first, range->second); !s)
      return fail(s.with_context(args.scene + ": --range"));
    if (auto saved = ws.save(args.output); !saved) return fail(saved.status());
  }
  const auto r = ws.playback_range();
  if (args.json) {
    std::cout << Json{{"playbackRange", r ? Json::array({(*r)[0], (*r)[1]}) : Json()}, {"fps", ws.graph().fps()}}.dump()
              << "\n";
  } else if (r) {
    std::cout << number_text((*r)[0]) << ":" << number_text((*r)[1]) << " @ " << number_text(ws.graph().fps())
              << " fps\n";
  } else {
    std::cout << "no playback range set (the keys' range is used)\n";
  }
  if (!args.range.empty()) std::cerr << "rigel: playback range " << args.range << "; wrote " << args.output << "\n";
  return 0;
}

Json sets_json(const app::Workspace& ws) {
  Json sets = Json::array();
  for (const scene::SelectionSet& s : ws.selection_sets()) {
    Json members = Json::array();
    for (graph::NodeId id : s.members) members.push_back(ws.graph().node(id)->name());
    sets.push_back(Json{{"name", s.name}, {"members", members}, {"missing", s.missing}});
  }
  return sets;
}

int run_sets(const SetsArgs& args) {
  if (!args.save.empty() && !args.remove.empty()) return usage_error("give --save or --remove, not both");
  const bool writes = !args.save.empty() || !args.remove.empty();
  if (writes != !args.output.empty()) return usage_error("--save and --remove write a scene: give them with -o OUT");
  if (!args.controls.empty() && args.save.empty()) return usage_error("--control goes with --save");
  if (!args.save.empty() && args.controls.empty()) return usage_error("--save needs --control A,B,...");
  auto scene = load(args.scene);
  if (!scene) return fail(scene.status());
  app::Workspace ws(std::move(*scene), args.scene, {}, tools::components());
  if (!args.save.empty()) {
    std::vector<graph::NodeId> members;
    for (const std::string& name : args.controls) {
      auto id = ws.key_target(name, "control");
      if (!id) return fail(Status(id.status().code(), args.scene + ": --control: " + id.status().message()));
      members.push_back(*id);
    }
    if (auto saved = ws.save_selection_set(args.save, members); !saved)
      return fail(saved.status().with_context(args.scene + ": --save"));
  } else if (!args.remove.empty()) {
    if (Status s = ws.remove_selection_set(args.remove); !s) return fail(s.with_context(args.scene + ": --remove"));
  }
  if (writes)
    if (auto saved = ws.save(args.output); !saved) return fail(saved.status());
  if (args.json) {
    std::cout << Json{{"sets", sets_json(ws)}}.dump() << "\n";
  } else {
    for (const Json& s : sets_json(ws)) {
      std::cout << s["name"].get<std::string>() << ":";
      for (const Json& m : s["members"]) std::cout << " " << m.get<std::string>();
      if (!s["missing"].empty()) std::cout << "  (" << s["missing"].size() << " missing)";
      std::cout << "\n";
    }
  }
  if (writes)
    std::cerr << "rigel: " << (args.save.empty() ? "removed selection set " + args.remove : "saved selection set " + args.save)
              << "; wrote " << args.output << "\n";
  return 0;
}

int run_picker(const PickerArgs& args) {
  auto scene = load(args.scene);
  if (!scene) return fail(scene.status());
  app::Workspace ws(std::move(*scene), args.scene, {}, tools::components());
  Json groups = Json::array();
  for (const app::PickerGroup& p : ws.picker()) {
    Json controls = Json::array();
    for (const app::PickerGroup::Entry& e : p.controls)
      controls.push_back(Json{{"name", ws.graph().node(e.control)->name()}, {"label", e.label}});
    groups.push_back(Json{{"rig", p.rig}, {"name", p.name}, {"part", p.part}, {"side", std::string(1, p.side)},
                          {"controls", controls}});
    if (!args.json)
      std::cout << p.rig << "  " << p.part << " " << p.side << "  " << p.name << " (" << p.controls.size()
                << (p.controls.size() == 1 ? " control)\n" : " controls)\n");
  }
  if (args.json) std::cout << Json{{"groups", groups}}.dump() << "\n";
  return 0;
}

int run_trail(const TrailArgs& args) {
  const auto range = parse_frames(args.frames);
  if (!range) return usage_error("--frames '" + args.frames + "': " + kFramesExpected);
  if (!std::isfinite(args.step) || args.step <= 0) return usage_error("--step must be a positive number of frames");
  auto scene = load(args.scene);
  if (!scene) return fail(scene.status());
  app::Workspace ws(std::move(*scene), args.scene, {}, tools::components());
  std::vector<graph::NodeId> nodes;
  for (const std::string& name : args.controls) {
    auto id = ws.key_target(name, "control");
    if (!id) return fail(Status(id.status().code(), args.scene + ": --control: " + id.status().message()));
    nodes.push_back(*id);
  }
  auto trails = ws.motion_trails(nodes, range->first, range->second, args.step);
  if (!trails) return fail(trails.status().with_context(args.scene + ": --" + (trails.status().field() == "step" ? "step" : "frames")));
  Json out = Json::array();
  for (const tools::MotionTrail& t : *trails) {
    Json points = Json::array();
    for (const math::Vec3& p : t.points) points.push_back(Json::array({p.x(), p.y(), p.z()}));
    const std::string name = ws.graph().node(t.node)->name();
    out.push_back(Json{{"control", name}, {"frames", t.frames}, {"points", points}, {"keys", t.key_frames}});
    if (!args.json) {
      std::cout << name << ":\n";
      for (std::size_t i = 0; i < t.frames.size(); ++i)
        std::cout << "  " << number_text(t.frames[i]) << "  " << number_text(t.points[i].x()) << " "
                  << number_text(t.points[i].y()) << " " << number_text(t.points[i].z())
                  << (std::find(t.key_frames.begin(), t.key_frames.end(), t.frames[i]) != t.key_frames.end() ? "  key" : "")
                  << "\n";
    }
  }
  if (args.json) std::cout << Json{{"trails", out}}.dump() << "\n";
  return 0;
}

}  // namespace

struct SettingsCommands::State {
  CLI::App* playback = nullptr;
  CLI::App* sets = nullptr;
  CLI::App* picker = nullptr;
  CLI::App* trail = nullptr;
  TrailArgs trail_args;
  PlaybackArgs playback_args;
  PickerArgs picker_args;
  SetsArgs sets_args;
};

SettingsCommands::SettingsCommands() : state_(std::make_unique<State>()) {}
SettingsCommands::~SettingsCommands() = default;

void add_settings_commands(CLI::App& app, SettingsCommands& commands) {
  SettingsCommands::State& s = commands.state();
  s.playback = app.add_subcommand("playback", "The scene's playback range: show it, or set it (saved with the scene)");
  s.playback->footer("Examples:\n  rigel playback shot.rigel\n  rigel playback shot.rigel --range 1:120 -o shot.rigel");
  s.playback->add_option("SCENE", s.playback_args.scene, "Scene file (.rigel)")->required();
  s.playback->add_option("--range", s.playback_args.range, "Set the range FIRST:LAST (frames)");
  s.playback->add_option("-o,--output", s.playback_args.output, "Scene file to write (.rigel)");
  s.playback->add_flag("--json", s.playback_args.json, "Print a JSON report on stdout");

  s.sets = app.add_subcommand("sets", "Named selection sets of controls, saved with the scene: list, save, remove");
  s.sets->footer(
      "Examples:\n  rigel sets shot.rigel\n"
      "  rigel sets shot.rigel --save left_arm --control hero_arm_L_ik,hero_arm_L_fk1 -o shot.rigel\n"
      "  rigel sets shot.rigel --remove left_arm -o shot.rigel --json");
  s.sets->add_option("SCENE", s.sets_args.scene, "Scene file (.rigel)")->required();
  s.sets->add_option("--save", s.sets_args.save, "Save a set of this name (replacing its members if it exists)");
  s.sets->add_option("--control", s.sets_args.controls, "With --save: the members (names or rig addresses)")->delimiter(',');
  s.sets->add_option("--remove", s.sets_args.remove, "Remove the set of this name");
  s.sets->add_option("-o,--output", s.sets_args.output, "Scene file to write (.rigel)");
  s.sets->add_flag("--json", s.sets_args.json, "Print a JSON report on stdout");

  s.picker = app.add_subcommand("picker", "The picker's layout: every control grouped by rig, body part and side");
  s.picker->footer("Examples:\n  rigel picker shot.rigel\n  rigel picker shot.rigel --json");
  s.picker->add_option("SCENE", s.picker_args.scene, "Scene file (.rigel)")->required();
  s.picker->add_flag("--json", s.picker_args.json, "Print the groups as JSON on stdout");

  s.trail = app.add_subcommand("trail", "Motion trails: controls' world positions over a range of frames, keys marked");
  s.trail->footer("Examples:\n  rigel trail shot.rigel --control hero_arm_L_ik --frames 0:48\n"
                  "  rigel trail shot.rigel --control hero:arm_L/ik,hero:leg_L/ik --frames 0:48 --step 2 --json");
  s.trail->add_option("SCENE", s.trail_args.scene, "Scene file (.rigel)")->required();
  s.trail->add_option("--control", s.trail_args.controls, "Controls or other nodes (names or rig addresses)")
      ->delimiter(',')
      ->required();
  s.trail->add_option("--frames", s.trail_args.frames, "The range FIRST:LAST")->required();
  s.trail->add_option("--step", s.trail_args.step, "Frames between samples (default 1; keys are always sampled)");
  s.trail->add_flag("--json", s.trail_args.json, "Print the trails as JSON on stdout");
}

std::optional<int> run_settings_commands(const SettingsCommands& commands) {
  const SettingsCommands::State& s = commands.state();
  if (*s.playback) return run_playback(s.playback_args);
  if (*s.sets) return run_sets(s.sets_args);
  if (*s.picker) return run_picker(s.picker_args);
  if (*s.trail) return run_trail(s.trail_args);
  return std::nullopt;
}

}  // namespace rigel::cli
