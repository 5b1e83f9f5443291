// `rigel key` and `rigel keys` (see key_commands.h).

#include "key_commands.h"

#include <cmath>
#include <iostream>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_util.h"
#include "rigel/app/workspace.h"
#include "rigel/ephemeral/component.h"
#include "rigel/ops/anim/channel_keys.h"
#include "rigel/tools/data_files.h"

namespace rigel::cli {
namespace {

using Json = nlohmann::ordered_json;
using graph::NodeId;

// A node given to --control, by name or by a rig's nameless address
// (`hero:arm_L/fkIkSwitch`; app::Workspace::node): a control (a joint
// stands for its ephemeral control) or any other node with keyable
// channels (a switch).
Result<NodeId> key_node(const app::Workspace& ws, const std::string& scene, const std::string& name) {
  auto id = ws.key_target(name, "controls");
  if (!id) {
    std::string message = id.status().message();
    if (message.rfind("controls: no node '", 0) == 0) message = "no node named '" + name + "'";
    else if (message.rfind("controls: ", 0) == 0) message = message.substr(10);
    return Status(id.status().code(), scene + ": --control: " + message);
  }
  return *id;
}

// Every name given to --control, as key_node resolves it.
Result<std::vector<NodeId>> key_nodes(const app::Workspace& ws, const std::string& scene,
                                      const std::vector<std::string>& names) {
  std::vector<NodeId> nodes;
  for (const std::string& name : names) {
    auto id = key_node(ws, scene, name);
    if (!id) return id.status();
    nodes.push_back(*id);
  }
  return nodes;
}

Json value_json(const graph::Value& v) {
  if (const auto* d = std::get_if<double>(&v)) return *d;
  if (const auto* p = std::get_if<math::Vec3>(&v)) return Json::array({p->x(), p->y(), p->z()});
  if (const auto* q = std::get_if<math::Quat>(&v)) return Json::array({q->x(), q->y(), q->z(), q->w()});
  return nullptr;
}

std::string value_text(const graph::Value& v) {
  const Json j = value_json(v);
  if (j.is_number()) return number_text(j.get<double>());
  std::string out = "(";
  for (std::size_t i = 0; i < j.size(); ++i) out += (i ? ", " : "") + number_text(j[i].get<double>());
  return out + ")";
}

Json keys_json(const std::vector<tools::PlugKeys>& keys, double fps) {
  Json out = Json::array();
  for (const tools::PlugKeys& k : keys) {
    Json frames = Json::array(), values = Json::array();
    for (double t : k.times) frames.push_back(app::key_frame(t, fps));
    for (const graph::Value& v : k.values) values.push_back(value_json(v));
    Json entry{{"plug", k.name}, {"frames", frames}, {"seconds", k.times}, {"values", values}};
    if (!k.in_tangents.empty()) {
      entry["inTangents"] = k.in_tangents;
      entry["outTangents"] = k.out_tangents;
    }
    out.push_back(std::move(entry));
  }
  return out;
}

// ---- key -----------------------------------------------------------------

struct KeyArgs {
  std::string scene;
  std::vector<std::string> controls;
  std::vector<std::string> attrs;
  std::optional<double> frame, time, value, move_to;
  std::string tangent, in_tangent, out_tangent;
  bool remove = false;
  bool copy = false;
  std::string output;
  bool json = false;
};

int run_key(const KeyArgs& args) {
  if ((args.frame && !std::isfinite(*args.frame)) || (args.time && !std::isfinite(*args.time)))
    return usage_error(std::string(args.frame ? "--frame" : "--time") + " must be a finite number");
  if (args.value && !std::isfinite(*args.value)) return usage_error("--value must be a finite number");
  if (args.value && args.remove) return usage_error("--value sets a key; --delete removes one: give one of them");
  if (args.move_to && (args.remove || args.value))
    return usage_error("--move-to moves the keys at --frame; it takes no --value or --delete");
  if (args.move_to && !std::isfinite(*args.move_to)) return usage_error("--move-to must be a finite number");
  if (args.copy && !args.move_to) return usage_error("--copy copies the keys at --frame to --move-to; give --move-to");
  tools::Tangents tangents;
  for (auto [text, option, both, in] :
       {std::tuple{&args.tangent, "--tangent", true, false}, {&args.in_tangent, "--in-tangent", false, true},
        {&args.out_tangent, "--out-tangent", false, false}}) {
    if (text->empty()) continue;
    const auto type = ops::anim::tangent_type_from_name(*text);
    if (!type)
      return usage_error(std::string(option) + " '" + *text +
                         "': expected auto, spline, linear, flat, step, stepNext, clamped, plateau or fixed");
    if (both || in) tangents.in = type;
    if (both || !in) tangents.out = type;
  }
  if (tangents.any() && args.remove) return usage_error("--delete removes keys; a tangent type applies to keys it sets");
  for (const std::string& name : args.controls)
    if (name.empty()) return usage_error("--control: empty name (expected A,B,...)");
  for (const std::string& name : args.attrs)
    if (name.empty()) return usage_error("--attr: empty name (expected ATTR,...)");
  auto scene = load(args.scene);
  if (!scene) return fail(scene.status());
  app::Workspace ws(std::move(*scene), args.scene, {}, tools::components());
  auto resolved = key_nodes(ws, args.scene, args.controls);
  if (!resolved) return fail(resolved.status());
  const std::vector<NodeId>& nodes = *resolved;
  if (args.frame) {
    if (Status s = ws.set_frame(*args.frame); !s) return usage_error("--" + s.message());
  }
  if (args.time) {
    if (Status s = ws.set_time(*args.time); !s) return usage_error("--" + s.message());
  }
  auto channels = ws.key_channels(nodes, args.attrs);
  if (!channels) return fail(channels.status().with_context(args.scene + ": --" + (channels.status().field() == "attrs" ? "attr" : "control")));
  if (tangents.any() && args.move_to) return usage_error("--move-to keeps the keys' tangents; it takes no --tangent");
  auto keys = args.move_to  ? ws.move_channel_keys(nodes, args.attrs, *args.move_to, args.copy)
              : args.remove ? ws.delete_channel_keys(nodes, args.attrs)
                            : ws.set_channel_keys(nodes, args.attrs, args.value, tangents);
  if (!keys) {
    const Status& s = keys.status();
    const std::string option = s.field() == "value"     ? ": --value"
                               : s.field() == "tangent" ? ": --tangent"
                               : s.field() == "moveTo"  ? ": --move-to"
                               : s.field() == "controls" ? ": --control"
                                                         : "";
    return fail(s.with_context(args.scene + option));
  }
  if (auto saved = ws.save(args.output); !saved) return fail(saved.status());
  const double fps = ws.graph().fps();
  const double frame = app::key_frame(ws.graph().time(), fps);
  if (args.json) {
    Json names = Json::array();
    for (const tools::Channel& c : *channels) names.push_back(ws.graph().plug_name(graph::Plug{c.node, c.attr, -1}));
    Json out{{"frame", frame}, {"deleted", args.remove}, {"channels", names}, {"keys", keys_json(*keys, fps)},
             {"output", args.output}};
    if (args.move_to) out[args.copy ? "copiedTo" : "movedTo"] = *args.move_to;
    std::cout << out.dump() << "\n";
  }
  std::cerr << "rigel: " << (args.move_to ? (args.copy ? "copied the keys of " : "moved the keys of ") : args.remove ? "deleted the keys of " : "keyed ")
            << channels->size() << (channels->size() == 1 ? " channel" : " channels") << " at frame " << number_text(frame);
  if (args.move_to) std::cerr << " to frame " << number_text(*args.move_to);
  std::cerr << "; wrote " << args.output << "\n";
  return 0;
}

// ---- keys ----------------------------------------------------------------

struct KeysArgs {
  std::string scene;
  std::string control;
  std::vector<std::string> attrs;
  bool json = false;
};

int run_keys(const KeysArgs& args) {
  auto scene = load(args.scene);
  if (!scene) return fail(scene.status());
  app::Workspace ws(std::move(*scene), args.scene, {}, tools::components());
  auto id = key_node(ws, args.scene, args.control);
  if (!id) return fail(id.status());
  auto keys = ws.channel_keys({*id}, args.attrs);
  if (!keys) return fail(keys.status().with_context(args.scene + ": --attr"));
  const double fps = ws.graph().fps();
  const std::string name = ws.graph().node(*id)->name();
  if (args.json) {
    std::cout << Json{{"control", name}, {"fps", fps}, {"channels", keys_json(*keys, fps)}}.dump() << "\n";
    return 0;
  }
  if (keys->empty()) std::cout << name << ": no keys\n";
  for (const tools::PlugKeys& k : *keys) {
    std::cout << k.name << ":";
    for (std::size_t i = 0; i < k.times.size(); ++i)
      std::cout << (i ? ", " : " ") << "frame " << number_text(app::key_frame(k.times[i], fps)) << " = "
                << value_text(k.values[i]);
    std::cout << "\n";
  }
  return 0;
}

// ---- tween ---------------------------------------------------------------

struct TweenArgs {
  std::string scene;
  std::vector<std::string> controls, attrs;
  double fraction = 0.5;
  std::optional<double> frame;
  bool no_key = false;
  std::string output;
  bool json = false;
};

int run_tween(const TweenArgs& args) {
  if (!std::isfinite(args.fraction)) return usage_error("--fraction must be a finite number");
  if (args.frame && !std::isfinite(*args.frame)) return usage_error("--frame must be a finite number");
  auto scene = load(args.scene);
  if (!scene) return fail(scene.status());
  app::Workspace ws(std::move(*scene), args.scene, {}, tools::components());
  auto resolved = key_nodes(ws, args.scene, args.controls);
  if (!resolved) return fail(resolved.status());
  const std::vector<NodeId>& nodes = *resolved;
  if (args.frame) {
    if (Status s = ws.set_frame(*args.frame); !s) return usage_error("--" + s.message());
  }
  auto keys = ws.tween(nodes, args.attrs, args.fraction, !args.no_key);
  if (!keys) {
    const Status& s = keys.status();
    const std::string option = s.field() == "attrs" ? "--attr" : s.field() == "fraction" ? "--fraction" : "--control";
    return fail(s.with_context(args.scene + ": " + option));
  }
  if (auto saved = ws.save(args.output); !saved) return fail(saved.status());
  const double fps = ws.graph().fps();
  const double frame = app::key_frame(ws.graph().time(), fps);
  if (args.json)
    std::cout << Json{{"frame", frame}, {"fraction", args.fraction}, {"keys", keys_json(*keys, fps)}, {"output", args.output}}.dump()
              << "\n";
  std::cerr << "rigel: tweened at frame " << number_text(frame) << " by " << number_text(args.fraction) << "; wrote "
            << args.output << "\n";
  return 0;
}

// ---- set -----------------------------------------------------------------

struct SetArgs {
  std::string scene;
  std::vector<std::string> controls, attrs;
  std::vector<double> values;
  std::optional<double> frame;
  bool auto_key = false;
  std::string output;
  bool json = false;
};

int run_set(const SetArgs& args) {
  if (args.frame && !std::isfinite(*args.frame)) return usage_error("--frame must be a finite number");
  for (double v : args.values)
    if (!std::isfinite(v)) return usage_error("--value must be finite numbers");
  auto scene = load(args.scene);
  if (!scene) return fail(scene.status());
  app::Workspace ws(std::move(*scene), args.scene, {}, tools::components());
  auto resolved = key_nodes(ws, args.scene, args.controls);
  if (!resolved) return fail(resolved.status());
  if (args.frame) {
    if (Status s = ws.set_frame(*args.frame); !s) return usage_error("--" + s.message());
  }
  if (args.auto_key) {
    ephemeral::SessionOptions options = ws.session().options();
    options.auto_key = true;
    if (Status s = ws.set_options(options); !s) return fail(s);
  }
  auto set = ws.set_channel_values(*resolved, args.attrs, args.values);
  if (!set) {
    const Status& s = set.status();
    const std::string option = s.field() == "attrs" ? "--attr" : s.field() == "value" ? "--value" : "--control";
    return fail(s.with_context(args.scene + ": " + option));
  }
  if (auto saved = ws.save(args.output); !saved) return fail(saved.status());
  const double fps = ws.graph().fps();
  const double frame = app::key_frame(ws.graph().time(), fps);
  if (args.json) {
    Json names = Json::array();
    for (const tools::Channel& c : set->channels) names.push_back(ws.graph().plug_name(graph::Plug{c.node, c.attr, -1}));
    std::cout << Json{{"frame", frame}, {"channels", names}, {"keys", keys_json(set->keys, fps)}, {"output", args.output}}.dump()
              << "\n";
  }
  std::cerr << "rigel: set " << set->channels.size() << (set->channels.size() == 1 ? " channel" : " channels")
            << " at frame " << number_text(frame) << "; wrote " << args.output << "\n";
  return 0;
}

}  // namespace

struct KeyCommands::State {
  CLI::App* key_cmd = nullptr;
  KeyArgs key;
  CLI::App* keys_cmd = nullptr;
  KeysArgs keys;
  CLI::App* tween_cmd = nullptr;
  TweenArgs tween;
  CLI::App* set_cmd = nullptr;
  SetArgs set;
};

KeyCommands::KeyCommands() : state_(std::make_unique<State>()) {}
KeyCommands::~KeyCommands() = default;

void add_key_commands(CLI::App& app, KeyCommands& commands) {
  KeyCommands::State& s = commands.state();
  s.key_cmd = app.add_subcommand("key", "Set or delete keys on the keyable channels of any rig's controls and switches");
  s.key_cmd->footer(
      "Without --attr a key keys the controls' keying group (a built rig's whole character, an ephemeral rig's "
      "keying set); with --attr only those channels of the nodes named.\n"
      "Examples:\n  rigel key hero.rigel --control hero_arm_L_fk1 --frame 10 -o keyed.rigel\n"
      "  rigel key keyed.rigel --control hero_arm_L_fkIkSwitch --attr fkIk --value 1 --frame 24 -o keyed.rigel\n"
      "  rigel key keyed.rigel --control hero_arm_L_fk1 --attr rotate --frame 10 --delete -o keyed.rigel\n"
      "  rigel key keyed.rigel --control hero:arm_L/fkIkSwitch --attr fkIk --value 0 --frame 30 --tangent step -o keyed.rigel\n"
      "  rigel key keyed.rigel --control hero_arm_L_fk1 --frame 10 --move-to 14 -o keyed.rigel");
  s.key_cmd->add_option("SCENE", s.key.scene, "Scene file (.rigel)")->required();
  s.key_cmd->add_option("--control", s.key.controls, "Controls or other nodes (a switch) to key")->delimiter(',')->required();
  s.key_cmd->add_option("--attr", s.key.attrs, "Only these channels (translate, rotate, fkIk, ...)")->delimiter(',');
  CLI::Option* frame = s.key_cmd->add_option("--frame", s.key.frame, "Frame to key at (default: the scene's current time)");
  CLI::Option* time = s.key_cmd->add_option("--time", s.key.time, "Time in seconds to key at");
  frame->excludes(time);
  s.key_cmd->add_option("--value", s.key.value, "The key's value (scalar channels such as fkIk); default: the current value");
  s.key_cmd->add_option("--tangent", s.key.tangent,
                        "Tangent type of the keys made, in and out: auto (default), spline, linear, flat, step, stepNext, "
                        "clamped, plateau, fixed");
  s.key_cmd->add_option("--in-tangent", s.key.in_tangent, "In-tangent type of the keys made");
  s.key_cmd->add_option("--out-tangent", s.key.out_tangent, "Out-tangent type of the keys made");
  s.key_cmd->add_flag("--delete", s.key.remove, "Delete the keys at that time instead");
  s.key_cmd->add_option("--move-to", s.key.move_to,
                        "Move the keys at that time to this frame, keeping values and tangents (a key there is replaced)");
  s.key_cmd->add_flag("--copy", s.key.copy, "With --move-to: copy the keys there, keeping those at --frame");
  s.key_cmd->add_option("-o,--output", s.key.output, "Scene file to write (.rigel)")->required();
  s.key_cmd->add_flag("--json", s.key.json, "Print a JSON report on stdout");

  s.keys_cmd = app.add_subcommand("keys", "List the keys of a control's (or a switch's) channels: frames and values");
  s.keys_cmd->footer("Examples:\n  rigel keys keyed.rigel --control hero_arm_L_fk1\n"
                     "  rigel keys keyed.rigel --control hero_arm_L_fkIkSwitch --attr fkIk --json");
  s.keys_cmd->add_option("SCENE", s.keys.scene, "Scene file (.rigel)")->required();
  s.keys_cmd->add_option("--control", s.keys.control, "The control or node")->required();
  s.keys_cmd->add_option("--attr", s.keys.attrs, "Only these channels")->delimiter(',');
  s.keys_cmd->add_flag("--json", s.keys.json, "Print JSON on stdout");

  s.tween_cmd = app.add_subcommand("tween", "Tween / breakdown: channels set between their previous and next keys");
  s.tween_cmd->footer(
      "--fraction 0 gives the previous key's values, 1 the next's, 0.5 halfway; below 0 or above 1 overshoots. "
      "Rotations blend by quaternion slerp. Keyed at the frame (--no-key: only keys already there change).\n"
      "Examples:\n  rigel tween shot.rigel --control hero_arm_L_fk1 --frame 12 --fraction 0.3 -o shot.rigel\n"
      "  rigel tween shot.rigel --control hero_global_main --attr translate --frame 8 --fraction 1.1 -o shot.rigel");
  s.tween_cmd->add_option("SCENE", s.tween.scene, "Scene file (.rigel)")->required();
  s.tween_cmd->add_option("--control", s.tween.controls, "Controls (their keying group) or other nodes")->delimiter(',')->required();
  s.tween_cmd->add_option("--attr", s.tween.attrs, "Only these channels")->delimiter(',');
  s.tween_cmd->add_option("--fraction", s.tween.fraction, "0: the previous key, 1: the next (default 0.5)");
  s.tween_cmd->add_option("--frame", s.tween.frame, "The frame (default: the scene's current frame)");
  s.tween_cmd->add_flag("--no-key", s.tween.no_key, "Do not add keys: only keys at the frame take the blend");
  s.tween_cmd->add_option("-o,--output", s.tween.output, "Scene file to write (.rigel)")->required();
  s.tween_cmd->add_flag("--json", s.tween.json, "Print a JSON report on stdout");

  s.set_cmd = app.add_subcommand("set", "Set scalar channels (a switch's fkIk, a foot's roll, a finger's curl) of any rig");
  s.set_cmd->footer(
      "A keyed channel gets a key at the frame with the value (its curve drives it); a free one is set, and keyed "
      "too with --auto-key. A built rig's control stands for its component's node with that channel.\n"
      "Examples:\n  rigel set shot.rigel --control hero_arm_L_ik --attr fkIk --value 1 --frame 12 -o shot.rigel\n"
      "  rigel set shot.rigel --control hero:foot_L/foot --attr roll,bank --value 20,0 --auto-key -o shot.rigel");
  s.set_cmd->add_option("SCENE", s.set.scene, "Scene file (.rigel)")->required();
  s.set_cmd->add_option("--control", s.set.controls, "Controls or other nodes (a switch)")->delimiter(',')->required();
  s.set_cmd->add_option("--attr", s.set.attrs, "The channels (fkIk, roll, curl, ...)")->delimiter(',');
  s.set_cmd->add_option("--value", s.set.values, "One value, or one per channel")->delimiter(',')->required();
  s.set_cmd->add_option("--frame", s.set.frame, "The frame (default: the scene's current frame)");
  s.set_cmd->add_flag("--auto-key", s.set.auto_key, "Key free channels too");
  s.set_cmd->add_option("-o,--output", s.set.output, "Scene file to write (.rigel)")->required();
  s.set_cmd->add_flag("--json", s.set.json, "Print a JSON report on stdout");
}

std::optional<int> run_key_commands(const KeyCommands& commands) {
  const KeyCommands::State& s = commands.state();
  if (*s.key_cmd) return run_key(s.key);
  if (*s.keys_cmd) return run_keys(s.keys);
  if (*s.tween_cmd) return run_tween(s.tween);
  if (*s.set_cmd) return run_set(s.set);
  return std::nullopt;
}

}  // namespace rigel::cli
