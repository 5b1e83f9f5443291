// `rigel pose` (pose_command.h): one drag of an app::Workspace, then a save.

#include "pose_command.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>

#include <nlohmann/json.hpp>

#include "cli_util.h"
#include "rigel/app/workspace.h"
#include "rigel/ephemeral/component.h"
#include "rigel/ephemeral/keying.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/scene/transform_types.h"
#include "rigel/tools/data_files.h"

namespace rigel::cli {
namespace {

namespace eph = ephemeral;
using graph::NodeId;
using math::Quat;
using math::Vec3;
using Json = nlohmann::ordered_json;

// The CLI's spelling of the options' API names (SessionOptions::validate).
std::string option_name(const std::string& field) {
  static const std::map<std::string, std::string> names = {
      {"magnetFraction", "--magnet-fraction"}, {"magnetRadius", "--magnet-radius"}, {"maxChain", "--max-chain"},
      {"frame", "--frame"}, {"time", "--time"}};
  auto it = names.find(field);
  return it == names.end() ? field : it->second;
}

// A usage error for an app refusal of an option's value: "--option: reason".
int option_error(const Status& s) {
  const std::string prefix = s.field() + ": ";
  std::string message = s.message();
  if (message.rfind(prefix, 0) == 0) message = message.substr(prefix.size());
  return usage_error(option_name(s.field()) + ": " + message);
}

// The rigs of `controls` (ephemeral ones), first appearance order.
std::vector<NodeId> ephemeral_rigs_of(const graph::Graph& g, const std::vector<NodeId>& controls) {
  std::vector<NodeId> out;
  for (NodeId c : controls) {
    const NodeId rig = eph::rig_of(g, c);
    if (rig.is_valid() && std::find(out.begin(), out.end(), rig) == out.end()) out.push_back(rig);
  }
  return out;
}

std::string names_text(const graph::Graph& g, const std::vector<NodeId>& ids) {
  std::string text;
  for (NodeId id : ids) text += (text.empty() ? "" : ", ") + g.node(id)->name();
  return text;
}

}  // namespace

void add_pose_command(CLI::App& app, PoseArgs& args) {
  CLI::App* cmd = app.add_subcommand(
      "pose",
      "Grab controls of an ephemeral rig (moved in a mode: forward, inverse, ...) or of a built rig (moved as they "
      "are), and write the scene");
  args.command = cmd;
  cmd->add_option("SCENE", args.scene, "Scene file with an ephemeral or built rig (.rigel; see `rigel ephemeral setup`)")
      ->required();
  cmd->add_option("-o,--output", args.output, "Scene file to write (.rigel)")->required();
  cmd->add_option("--control", args.control, "The control the motion is given for (a joint name stands for its control)")
      ->required();
  cmd->add_option("--mode", args.mode,
                  "forward, suspended, pseudo-inverse, pseudo-inverse-length, inverse, magnet, magnet-radius, "
                  "body (docs/EPHEMERAL.md; a built rig's controls move as they are in every mode)")
      ->required();
  cmd->add_option("--translate", args.translate, "World-space translation X,Y,Z in scene units");
  cmd->add_option("--rotate", args.rotate,
                  "World-space rotation X,Y,Z in degrees, XYZ Euler (x applied first: rotation = Rz*Ry*Rx), about "
                  "each grabbed control's own pivot (body mode: the body pivot)");
  cmd->add_option("--select", args.select, "More controls grabbed with --control: A,B,... (all move together)")
      ->delimiter(',')
      ->allow_extra_args(false);
  CLI::Option* frame = cmd->add_option("--frame", args.frame, "Frame to pose at (default: the scene's current time)");
  CLI::Option* time = cmd->add_option("--time", args.time, "Time in seconds to pose at");
  frame->excludes(time);
  cmd->add_option("--scale", args.scale, "Body mode: scale X,Y,Z about the body pivot, in its axes");
  cmd->add_option("--pivot", args.pivot,
                  "Body mode: the body pivot's world position X,Y,Z, world axes (default: --control's position and axes)");
  cmd->add_option("--magnet-fraction", args.magnet_fraction, "Magnet mode: share of the motion per hop (default 0.65)");
  cmd->add_option("--magnet-radius", args.magnet_radius, "Magnet-radius mode: world distance of the falloff (default 1)");
  cmd->add_option("--max-chain", args.max_chain,
                  "Inverse modes: most controls in a chain, grabbed and top included (default 0: to a branch or root)");
  cmd->add_flag("--auto-key", args.auto_key,
                "A keyed control moved off its keys keys its keying group at this frame first (default: refused)");
  cmd->add_flag("--key", args.key,
                "After the motion, key the grabbed controls at this frame (their keying group: the whole "
                "character unless its keying scope is controls)");
  cmd->add_flag("--json", args.json,
                "Print {\"mode\", \"frame\", \"grabbed\": [NAME...], \"moved\": {NAME: {\"t\", \"q\"}}, "
                "\"keyScope\": {RIG: SCOPE}, \"keyed\": [NAME...], \"notes\": [TEXT...]} (moved: world space, "
                "every control whose world matrix changed; keyed: controls with a key at this frame; notes: what "
                "the motion could not do, e.g. a target out of an inverse chain's reach)");
}

int run_pose(const PoseArgs& args) {
  // Usage errors first (exit 2), before the scene is read.
  const std::optional<eph::Mode> mode = eph::mode_from_name(args.mode);
  if (!mode) {
    std::string modes;
    for (int m = 0; m < eph::kModeCount; ++m) modes += std::string(m ? ", " : "") + eph::mode_name(static_cast<eph::Mode>(m));
    return usage_error("--mode '" + args.mode + "': unknown mode; modes: " + modes);
  }
  if ((args.frame && !std::isfinite(*args.frame)) || (args.time && !std::isfinite(*args.time)))
    return usage_error(std::string(args.frame ? "--frame" : "--time") + " must be a finite number");
  eph::Delta delta;
  std::optional<Vec3> pivot;
  struct VecOption {
    const char* name;
    const std::optional<std::string>& text;
    std::optional<Vec3>* out;
  };
  std::optional<Vec3> translate, rotate, scale;
  for (const VecOption& o : {VecOption{"--translate", args.translate, &translate}, VecOption{"--rotate", args.rotate, &rotate},
                             VecOption{"--scale", args.scale, &scale}, VecOption{"--pivot", args.pivot, &pivot}}) {
    if (!o.text) continue;
    *o.out = parse_vec3(*o.text);
    if (!*o.out) return usage_error(std::string(o.name) + " '" + *o.text + "': expected X,Y,Z, three numbers such as 0,1.5,-2");
  }
  if (translate) delta.translate = *translate;
  if (rotate) delta.rotate = app::rotation_from_euler_degrees(*rotate);
  if (scale) delta.scale = *scale;
  eph::SessionOptions options;
  options.auto_key = args.auto_key;
  if (args.magnet_fraction) options.magnet_fraction = *args.magnet_fraction;
  if (args.magnet_radius) options.magnet_radius = *args.magnet_radius;
  if (args.max_chain) options.max_chain = *args.max_chain;
  if (Status s = options.validate(); !s) return option_error(s);
  for (const std::string& name : args.select)
    if (name.empty()) return usage_error("--select: empty control name (expected A,B,...)");
  if (args.scale && *mode != eph::Mode::kBody) return usage_error("--scale applies in body mode only (--mode body)");
  if (args.pivot && *mode != eph::Mode::kBody) return usage_error("--pivot applies in body mode only (--mode body)");

  auto scene = load(args.scene);
  if (!scene) return fail(scene.status());
  app::Workspace ws(std::move(*scene), args.scene, {}, tools::components(), options);
  graph::Graph& g = ws.graph();
  if (ws.all_controls().empty()) {
    return fail(Status(ErrorCode::kNotFound, args.scene + ": the scene has no ephemeral rig (nor a built rig's controls); run "
                                                          "`rigel ephemeral setup " + args.scene + " -o OUT.rigel` first"));
  }
  if (args.frame) {
    if (Status s = ws.set_frame(*args.frame); !s) return option_error(s);
  }
  if (args.time) {
    if (Status s = ws.set_time(*args.time); !s) return option_error(s);
  }
  ws.set_mode(*mode);

  // Each name must be a control, or a joint driven by an ephemeral one (it
  // stands for its control, as in Session::select).
  std::vector<NodeId> selection;
  NodeId primary;
  auto resolve = [&](const std::string& option, const std::string& name) -> std::optional<Status> {
    const NodeId id = g.find(name);
    if (!id.is_valid()) return Status(ErrorCode::kNotFound, args.scene + ": " + option + ": no node named '" + name + "'");
    auto control = ws.control_of(id, option);
    if (!control) return control.status().with_context(args.scene);
    if (!primary.is_valid()) primary = *control;
    selection.push_back(id);
    return std::nullopt;
  };
  if (auto st = resolve("--control", args.control)) return fail(*st);
  for (const std::string& name : args.select)
    if (auto st = resolve("--select", name)) return fail(*st);
  ws.select(selection);
  if (*mode == eph::Mode::kBody) ws.set_body_pivot(primary, pivot);  // at --control by default

  // A keyed channel off its keys is refused (the message names the channel
  // and the frame) unless --auto-key.
  auto dragged = ws.drag(delta);
  if (!dragged) {
    const Status& st = dragged.status();
    const int code = fail(st.with_context(args.scene + ": " + args.mode));
    if (!args.auto_key && st.message().find("auto-key") != std::string::npos) {
      std::cerr << "rigel: note: --auto-key keys the character at frame " << number_text(ws.scene().frame())
                << " first; or key it there with `rigel ephemeral key`\n";
    }
    return code;
  }
  ws.release();
  const std::vector<NodeId>& grabbed = dragged->dragged;
  // --key: key the grabbed controls' keying group at the pose time.
  std::size_t key_set = 0;
  if (args.key) {
    auto keyed = ws.set_key(grabbed);
    if (!keyed) return fail(keyed.status().with_context(args.scene + ": --key"));
    key_set = keyed->set.size();
  }
  std::vector<NodeId> keyed;
  for (NodeId c : ws.all_controls())
    if (eph::has_key_now(g, c)) keyed.push_back(c);
  const std::vector<NodeId> grabbed_rigs = ephemeral_rigs_of(g, grabbed);
  auto saved = ws.save(args.output);
  if (!saved) return fail(saved.status());
  if (args.json) {
    Json moved = Json::object();
    for (const app::Trs& m : dragged->moved_controls) {
      const Quat& q = m.rotate;
      moved[g.node(m.node)->name()] = {{"t", {m.translate.x(), m.translate.y(), m.translate.z()}},
                                       {"q", {q.x(), q.y(), q.z(), q.w()}}};
    }
    Json scopes = Json::object();
    for (NodeId r : grabbed_rigs) scopes[g.node(r)->name()] = eph::key_scope_name(eph::key_scope(g, r));
    Json out;
    out["mode"] = eph::mode_name(*mode);
    out["frame"] = ws.scene().frame();
    out["grabbed"] = Json::array();
    for (NodeId id : grabbed) out["grabbed"].push_back(g.node(id)->name());
    out["moved"] = std::move(moved);
    out["keyScope"] = std::move(scopes);
    out["keyed"] = Json::array();
    for (NodeId id : keyed) out["keyed"].push_back(g.node(id)->name());
    out["notes"] = dragged->notes;
    std::cout << out.dump() << "\n";
  }
  const std::size_t moved_count = dragged->moved_controls.size();
  std::cerr << "rigel: posed " << names_text(g, grabbed) << " (" << eph::mode_name(*mode) << ", frame "
            << ws.scene().frame() << "): " << moved_count << (moved_count == 1 ? " control" : " controls")
            << " moved; wrote " << args.output << "\n";
  std::string scopes_text;
  for (NodeId r : grabbed_rigs)
    scopes_text += (scopes_text.empty() ? "" : ", ") + g.node(r)->name() + "=" + eph::key_scope_name(eph::key_scope(g, r));
  if (grabbed_rigs.empty()) scopes_text = "controls";
  std::cerr << "rigel: keying scope: " << scopes_text;
  if (args.key) std::cerr << "; keyed " << key_set << (key_set == 1 ? " control" : " controls");
  std::cerr << "; " << keyed.size() << (keyed.size() == 1 ? " control has" : " controls have") << " a key at frame "
            << number_text(ws.scene().frame()) << "\n";
  // What the drag could not do (an inverse chain out of reach, a bone that
  // would stretch), so that "0 controls moved" is never silent.
  for (const std::string& note : dragged->notes) std::cerr << "rigel: note: " << note << "\n";
  return 0;
}

}  // namespace rigel::cli
