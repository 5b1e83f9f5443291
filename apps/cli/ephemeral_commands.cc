// The ephemeral-rig commands of `rigel` (see ephemeral_commands.h): setup,
// relations, keys, keying scopes and merged characters.

#include "ephemeral_commands.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_util.h"
#include "relations_command.h"
#include "rigel/app/workspace.h"
#include "rigel/ephemeral/component.h"
#include "rigel/ephemeral/keying.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/ephemeral/session.h"
#include "rigel/io/bvh_import.h"
#include "rigel/io/gltf_import.h"
#include "rigel/io/scene_file.h"
#include "rigel/math/transform.h"
#include "rigel/tools/data_files.h"

namespace rigel::cli {
namespace {

using rigel::Status;
using rigel::graph::NodeId;

// ---- ephemeral setup -----------------------------------------------------------

struct EphemeralSetupArgs {
  std::string scene;
  std::string output;
  std::vector<std::string> joints;
  std::string suffix = "_ctrl";
  std::string rig_name = "ephemeralRig";
  bool drop_animation = false;
  double shape_radius = 0.0;
  bool size_from_bones = false;
  bool json = false;
};

int run_ephemeral_setup(const EphemeralSetupArgs& args) {
  rigel::ephemeral::SetupOptions options;
  options.control_suffix = args.suffix;
  options.rig_name = args.rig_name;
  options.keep_animation = !args.drop_animation;
  options.shape_radius = args.shape_radius;
  options.size_from_bones = args.size_from_bones;
  // A bad option value is a usage error (exit 2), checked before the scene is read.
  if (Status st = options.validate(); !st) {
    const std::string& f = st.field();
    if (f == "shapeRadius") return usage_error("--shape-radius must be a number >= 0");
    if (f == "controlSuffix") return usage_error("--suffix '" + args.suffix + "': control names would not be valid node names");
    return usage_error("--rig-name '" + args.rig_name + "': not a valid node name");
  }
  for (const std::string& name : args.joints)
    if (name.empty()) return usage_error("--joints: empty joint name (expected A,B,...)");
  auto scene = load_or_import(args.scene);
  if (!scene) return fail(scene.status());
  rigel::scene::Scene& s = **scene;
  rigel::graph::Graph& g = s.graph();
  for (const std::string& name : args.joints) {
    const NodeId id = g.find(name);
    if (!id.is_valid()) return fail(Status(rigel::ErrorCode::kNotFound, args.scene + ": --joints: no node named '" + name + "'"));
    options.joints.push_back(id);
  }
  auto result = rigel::ephemeral::setup_ephemeral(s, options);
  if (!result) return fail(result.status().with_context(args.scene));
  if (Status st = rigel::io::save_scene(s, args.output); !st) return fail(st);
  const std::string rig = g.node(result->rig)->name();
  if (args.json) {
    nlohmann::ordered_json out;
    out["rig"] = rig;
    out["controls"] = nlohmann::ordered_json::array();
    out["joints"] = nlohmann::ordered_json::array();
    for (NodeId id : result->controls) out["controls"].push_back(g.node(id)->name());
    for (NodeId id : result->joints) out["joints"].push_back(g.node(id)->name());
    std::cout << out.dump() << "\n";
  }
  std::cerr << "rigel: ephemeral rig '" << rig << "': " << result->controls.size()
            << (result->controls.size() == 1 ? " control" : " controls") << " into " << args.output << "\n";
  return 0;
}

// ---- ephemeral: names, keys and scopes (shared by the key commands) ----------------

// A key time in seconds as a frame (app::key_frame).
double frame_of(const rigel::graph::Graph& g, double seconds) { return rigel::app::key_frame(seconds, g.fps()); }


// The rigs of `controls`, first appearance order.
std::vector<NodeId> rigs_of(const rigel::graph::Graph& g, const std::vector<NodeId>& controls) {
  std::vector<NodeId> out;
  for (NodeId c : controls) {
    const NodeId rig = rigel::ephemeral::rig_of(g, c);
    if (rig.is_valid() && std::find(out.begin(), out.end(), rig) == out.end()) out.push_back(rig);
  }
  return out;
}

// "RIG=SCOPE, ..." for `rigs`.
std::string scopes_text(const rigel::graph::Graph& g, const std::vector<NodeId>& rigs) {
  std::string text;
  for (NodeId r : rigs)
    text += (text.empty() ? "" : ", ") + g.node(r)->name() + "=" + rigel::ephemeral::key_scope_name(rigel::ephemeral::key_scope(g, r));
  return text;
}

nlohmann::ordered_json names_json(const rigel::graph::Graph& g, const std::vector<NodeId>& ids) {
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (NodeId id : ids) out.push_back(g.node(id)->name());
  return out;
}

// Key times of `controls`' keying set, as frames.
std::vector<double> key_frames(const rigel::graph::Graph& g, const std::vector<NodeId>& controls) {
  std::vector<double> frames;
  for (double t : rigel::ephemeral::key_times(g, controls)) frames.push_back(frame_of(g, t));
  return frames;
}

std::string frames_text(const std::vector<double>& frames) {
  if (frames.empty()) return "none";
  std::string text;
  for (double f : frames) text += (text.empty() ? "" : ", ") + number_text(f);
  return text;
}
// ---- ephemeral key, keys, scope, merge, unmerge ----------------------------------

struct EphemeralKeyArgs {
  std::string scene;
  std::string output;
  std::vector<std::string> controls;
  std::optional<double> frame;
  std::optional<double> time;
  bool remove = false;
  bool json = false;
};

int run_ephemeral_key(const EphemeralKeyArgs& args) {
  namespace eph = rigel::ephemeral;
  if ((args.frame && !std::isfinite(*args.frame)) || (args.time && !std::isfinite(*args.time)))
    return usage_error(std::string(args.frame ? "--frame" : "--time") + " must be a finite number");
  for (const std::string& name : args.controls)
    if (name.empty()) return usage_error("--control: empty control name (expected A,B,...)");
  auto scene = load_rigged(args.scene);
  if (!scene) return fail(scene.status());
  rigel::app::Workspace ws(std::move(*scene), args.scene, {}, rigel::tools::components());
  rigel::graph::Graph& g = ws.graph();
  std::vector<NodeId> controls;
  for (const std::string& name : args.controls) {
    auto control = resolve_control(g, args.scene, "--control", name);
    if (!control) return fail(control.status());
    controls.push_back(*control);
  }
  if (args.frame) {
    if (Status s = ws.set_frame(*args.frame); !s) return usage_error("--" + s.message());
  }
  if (args.time) {
    if (Status s = ws.set_time(*args.time); !s) return usage_error("--" + s.message());
  }
  const auto keyed = args.remove ? ws.delete_key(controls) : ws.set_key(controls);
  if (!keyed) return fail(keyed.status().with_context(args.scene));
  const std::vector<NodeId>& set = keyed->set;
  if (auto saved = ws.save(args.output); !saved) return fail(saved.status());
  const std::vector<double>& frames = keyed->frames;
  if (args.json) {
    nlohmann::ordered_json out;
    out["frame"] = frame_of(g, g.time());
    out["keyed"] = names_json(g, set);
    out["times"] = frames;
    std::cout << out.dump() << "\n";
  }
  std::cerr << "rigel: " << (args.remove ? "deleted the keys of " : "keyed ") << set.size()
            << (set.size() == 1 ? " control" : " controls") << " at frame " << number_text(frame_of(g, g.time()))
            << " (keying scope: " << scopes_text(g, rigs_of(g, controls)) << "); key frames: " << frames_text(frames)
            << "; wrote " << args.output << "\n";
  return 0;
}

struct EphemeralKeysArgs {
  std::string scene;
  std::string control;
  bool json = false;
};

int run_ephemeral_keys(const EphemeralKeysArgs& args) {
  namespace eph = rigel::ephemeral;
  auto scene = load_rigged(args.scene);
  if (!scene) return fail(scene.status());
  const rigel::graph::Graph& g = (*scene)->graph();
  auto control = resolve_control(g, args.scene, "--control", args.control);
  if (!control) return fail(control.status());
  const NodeId rig = eph::rig_of(g, *control);
  const std::vector<NodeId> set = eph::keying_set(g, {*control});
  const std::vector<double> seconds = eph::key_times(g, {*control});
  const std::vector<double> frames = key_frames(g, {*control});
  if (args.json) {
    nlohmann::ordered_json out;
    out["control"] = g.node(*control)->name();
    out["rig"] = g.node(rig)->name();
    out["keyScope"] = eph::key_scope_name(eph::key_scope(g, rig));
    out["keyingSet"] = names_json(g, set);
    out["times"] = frames;
    out["seconds"] = seconds;
    std::cout << out.dump() << "\n";
    return 0;
  }
  std::cout << g.node(*control)->name() << ": rig " << g.node(rig)->name()
            << ", keying scope: " << eph::key_scope_name(eph::key_scope(g, rig)) << " (a key keys " << set.size()
            << (set.size() == 1 ? " control" : " controls") << ")\n";
  std::cout << "key frames: " << frames_text(frames) << " (" << g.fps() << " fps)\n";
  return 0;
}

struct EphemeralScopeArgs {
  std::string scene;
  std::string rig;
  std::optional<std::string> set;
  std::optional<std::string> output;
  bool json = false;
};

int run_ephemeral_scope(const EphemeralScopeArgs& args) {
  namespace eph = rigel::ephemeral;
  std::optional<eph::KeyScope> scope;
  if (args.set) {
    scope = eph::key_scope_from_name(*args.set);
    if (!scope) return usage_error("--set '" + *args.set + "': expected character or controls");
    if (!args.output) return usage_error("--set needs -o OUT (the scene to write)");
  } else if (args.output) {
    return usage_error("-o applies with --set only (without --set, scope prints the keying scope)");
  }
  auto scene = load_rigged(args.scene);
  if (!scene) return fail(scene.status());
  rigel::graph::Graph& g = (*scene)->graph();
  auto rig = resolve_rig(g, args.scene, "--rig", args.rig);
  if (!rig) return fail(rig.status());
  if (scope) {
    if (Status st = eph::set_key_scope(g, *rig, *scope); !st) return fail(st.with_context(args.scene));
    if (Status st = rigel::io::save_scene(**scene, *args.output); !st) return fail(st);
  }
  const char* name = eph::key_scope_name(eph::key_scope(g, *rig));
  if (args.json) {
    nlohmann::ordered_json out;
    out["rig"] = args.rig;
    out["keyScope"] = name;
    std::cout << out.dump() << "\n";
  } else if (!scope) {
    std::cout << args.rig << ": keying scope: " << name << "\n";
  }
  if (scope) std::cerr << "rigel: " << args.rig << ": keying scope: " << name << "; wrote " << *args.output << "\n";
  return 0;
}

struct EphemeralMergeArgs {
  std::string scene;
  std::string output;
  std::vector<std::string> rigs;
  std::optional<std::string> carrier;
  std::optional<std::string> carried;
  bool json = false;
};

int run_ephemeral_merge(const EphemeralMergeArgs& args) {
  namespace eph = rigel::ephemeral;
  for (const std::string& name : args.rigs)
    if (name.empty()) return usage_error("--rigs: empty rig name (expected A,B,...)");
  if (args.rigs.size() < 2) return usage_error("--rigs: name two rigs or more (A,B,...)");
  if (args.carrier.has_value() != args.carried.has_value())
    return usage_error("--carrier CONTROL and --carried RIG go together");
  auto scene = load_rigged(args.scene);
  if (!scene) return fail(scene.status());
  rigel::graph::Graph& g = (*scene)->graph();
  std::vector<NodeId> rigs;
  for (const std::string& name : args.rigs) {
    auto rig = resolve_rig(g, args.scene, "--rigs", name);
    if (!rig) return fail(rig.status());
    rigs.push_back(*rig);
  }
  NodeId carrier, carried;
  if (args.carrier) {
    auto c = resolve_control(g, args.scene, "--carrier", *args.carrier);
    if (!c) return fail(c.status());
    auto r = resolve_rig(g, args.scene, "--carried", *args.carried);
    if (!r) return fail(r.status());
    carrier = *c;
    carried = *r;
  }
  if (Status st = eph::merge_characters(g, rigs); !st) return fail(st.with_context(args.scene));
  if (carried.is_valid()) {
    if (Status st = eph::set_carrier(g, carried, carrier); !st) return fail(st.with_context(args.scene + ": --carrier"));
  }
  if (Status st = rigel::io::save_scene(**scene, args.output); !st) return fail(st);
  const std::vector<NodeId> group = eph::merged_rigs(g, rigs.front());
  if (args.json) {
    nlohmann::ordered_json out;
    out["merged"] = names_json(g, group);
    out["carriers"] = nlohmann::ordered_json::object();
    for (NodeId r : group)
      if (const NodeId c = eph::carrier_of(g, r); c.is_valid()) out["carriers"][g.node(r)->name()] = g.node(c)->name();
    std::cout << out.dump() << "\n";
  }
  std::string names;
  for (NodeId r : group) names += (names.empty() ? "" : ", ") + g.node(r)->name();
  std::cerr << "rigel: merged " << names;
  if (carried.is_valid()) std::cerr << "; " << g.node(carrier)->name() << " carries " << g.node(carried)->name();
  std::cerr << "; wrote " << args.output << "\n";
  return 0;
}

struct EphemeralUnmergeArgs {
  std::string scene;
  std::string output;
  std::string rig;
  bool json = false;
};

int run_ephemeral_unmerge(const EphemeralUnmergeArgs& args) {
  namespace eph = rigel::ephemeral;
  auto scene = load_rigged(args.scene);
  if (!scene) return fail(scene.status());
  rigel::graph::Graph& g = (*scene)->graph();
  auto rig = resolve_rig(g, args.scene, "--rig", args.rig);
  if (!rig) return fail(rig.status());
  std::vector<NodeId> others;
  for (NodeId r : eph::merged_rigs(g, *rig))
    if (r != *rig) others.push_back(r);
  if (Status st = eph::unmerge_character(g, *rig); !st) return fail(st.with_context(args.scene));
  if (Status st = rigel::io::save_scene(**scene, args.output); !st) return fail(st);
  if (args.json) {
    nlohmann::ordered_json out;
    out["rig"] = args.rig;
    out["unmergedFrom"] = names_json(g, others);
    std::cout << out.dump() << "\n";
  }
  std::string names;
  for (NodeId r : others) names += (names.empty() ? "" : ", ") + g.node(r)->name();
  std::cerr << "rigel: " << args.rig << (others.empty() ? " was not merged" : " unmerged from " + names) << "; wrote "
            << args.output << "\n";
  return 0;
}


}  // namespace

struct EphemeralCommands::State {
  EphemeralSetupArgs setup;
  EphemeralRelationsArgs relations;
  EphemeralKeyArgs key;
  EphemeralKeysArgs keys;
  EphemeralScopeArgs scope;
  EphemeralMergeArgs merge;
  EphemeralUnmergeArgs unmerge;
  CLI::App* setup_cmd = nullptr;
  CLI::App* relations_cmd = nullptr;
  CLI::Option* relations_add = nullptr;
  CLI::Option* relations_remove = nullptr;
  CLI::Option* relations_set_kind = nullptr;
  CLI::Option* relations_group = nullptr;
  CLI::App* key_cmd = nullptr;
  CLI::App* keys_cmd = nullptr;
  CLI::App* scope_cmd = nullptr;
  CLI::App* merge_cmd = nullptr;
  CLI::App* unmerge_cmd = nullptr;

  // The relation edits in command-line order: CLI11 keeps each option's
  // values apart; its parse order (one entry per value) interleaves them.
  std::vector<RelationEdit> relation_edits() const {
    std::vector<RelationEdit> edits;
    std::size_t add = 0, remove = 0, set_kind = 0, group = 0;
    for (const CLI::Option* o : relations_cmd->parse_order()) {
      if (o == relations_add && add < relations.add.size()) {
        edits.push_back({RelationEdit::Op::kAdd, relations.add[add++]});
      } else if (o == relations_remove && remove < relations.remove.size()) {
        edits.push_back({RelationEdit::Op::kRemove, relations.remove[remove++]});
      } else if (o == relations_set_kind && set_kind < relations.set_kind.size()) {
        edits.push_back({RelationEdit::Op::kSetKind, relations.set_kind[set_kind++]});
      } else if (o == relations_group && group < relations.group.size()) {
        edits.push_back({RelationEdit::Op::kGroup, relations.group[group++]});
      }
    }
    return edits;
  }
};

EphemeralCommands::EphemeralCommands() : state_(std::make_unique<State>()) {}
EphemeralCommands::~EphemeralCommands() = default;

void add_ephemeral_commands(CLI::App& app, EphemeralCommands& commands) {
  EphemeralCommands::State& s = commands.state();
  CLI::App* ephemeral_cmd = app.add_subcommand(
      "ephemeral",
      "Ephemeral rigs: one control per joint (setup), relations between controls (relations), keys and keying "
      "scope (key, keys, scope), merged characters "
      "(merge, unmerge); posed with `rigel pose`");
  ephemeral_cmd->require_subcommand(1);
  s.setup_cmd = ephemeral_cmd->add_subcommand(
      "setup", "Give joints a control each (mirroring the joint hierarchy) and an ephemeralRig node relating them");
  s.setup_cmd->add_option("SCENE", s.setup.scene, "Scene file (.rigel), or a character to import first (.glb, .gltf, .bvh)")
      ->required();
  s.setup_cmd->add_option("-o,--output", s.setup.output, "Scene file to write (.rigel)")->required();
  s.setup_cmd->add_option("--joints", s.setup.joints, "Joints to rig, by name: A,B,... (default: every joint)")
      ->delimiter(',')
      ->allow_extra_args(false);
  s.setup_cmd->add_option("--suffix", s.setup.suffix, "Control name = joint name + this (default _ctrl)");
  s.setup_cmd->add_option("--rig-name", s.setup.rig_name,
                        "Name of the ephemeralRig node (default ephemeralRig; a taken name gets a number). Give a "
                        "second character (a prop set up with --joints) its own name");
  s.setup_cmd->add_flag("--drop-animation", s.setup.drop_animation,
                      "Break the animation connections into the joints, keeping the current pose (default: they move "
                      "onto the controls)");
  s.setup_cmd->add_option("--shape-radius", s.setup.shape_radius,
                        "Radius of each control's circle, in its own space (default 0: no shape)");
  s.setup_cmd->add_flag("--size-from-bones", s.setup.size_from_bones,
                      "Size each circle from its joint's bones (a third of the shortest), --shape-radius the largest");
  s.setup_cmd->add_flag("--json", s.setup.json,
                      "Print {\"rig\", \"controls\": [NAME...], \"joints\": [NAME...]} (controls[i] drives joints[i])");

  s.relations_cmd = ephemeral_cmd->add_subcommand(
      "relations", "Print a rig's relations between controls, or edit them (--add, --remove, --set-kind, --group; in "
                   "the order given, all or none)");
  s.relations_cmd->add_option("SCENE", s.relations.scene, "Scene file with an ephemeral rig (.rigel)")->required();
  s.relations_cmd->add_option("--rig", s.relations.rig,
                              "The ephemeralRig node, by name (default: printing, every rig; editing, the rig of "
                              "each edit's FROM control)");
  s.relations_add = s.relations_cmd
                        ->add_option("--add", s.relations.add,
                                     "Add a relation KIND:FROM:TO (KIND: forward, inverse, pair, magnet; a joint name "
                                     "stands for its control); repeatable")
                        ->allow_extra_args(false);
  s.relations_remove = s.relations_cmd->add_option("--remove", s.relations.remove, "Remove a relation KIND:FROM:TO; repeatable")
                           ->allow_extra_args(false);
  s.relations_set_kind = s.relations_cmd
                             ->add_option("--set-kind", s.relations.set_kind,
                                          "Change a relation's kind: KIND:FROM:TO=NEWKIND; repeatable")
                             ->allow_extra_args(false);
  s.relations_group = s.relations_cmd
                          ->add_option("--group", s.relations.group,
                                       "Pair relations both ways between every two of A,B,... (they move as one unit); "
                                       "repeatable")
                          ->allow_extra_args(false);
  s.relations_cmd->add_option("-o,--output", s.relations.output, "Scene file to write (.rigel; with edits only)");
  s.relations_cmd->add_flag("--json", s.relations.json,
                            "Print {\"rig\", \"relations\": [{\"kind\", \"from\", \"to\"}...]} (after the edits; one "
                            "object a line, one per rig; a carrier's relations into the rig last, with \"carrier\": true)");

  s.key_cmd = ephemeral_cmd->add_subcommand(
      "key", "Key controls at a frame (their keying group: the whole character unless its scope is controls)");
  s.key_cmd->add_option("SCENE", s.key.scene, "Scene file with an ephemeral rig (.rigel)")->required();
  s.key_cmd->add_option("-o,--output", s.key.output, "Scene file to write (.rigel)")->required();
  s.key_cmd->add_option("--control", s.key.controls, "Controls to key: A,B,... (a joint name stands for its control)")
      ->required()
      ->delimiter(',')
      ->allow_extra_args(false);
  CLI::Option* key_frame = s.key_cmd->add_option("--frame", s.key.frame, "Frame to key at (default: the scene's current time)");
  CLI::Option* key_time = s.key_cmd->add_option("--time", s.key.time, "Time in seconds to key at");
  key_frame->excludes(key_time);
  s.key_cmd->add_flag("--delete", s.key.remove, "Delete the keys of the keying group at that frame instead");
  s.key_cmd->add_flag("--json", s.key.json,
                    "Print {\"frame\", \"keyed\": [NAME...] (the keying group), \"times\": [FRAME...] (its key frames "
                    "after the edit)}");

  s.keys_cmd = ephemeral_cmd->add_subcommand(
      "keys", "Print a control's keying scope and the key frames of its keying group (reads only)");
  s.keys_cmd->add_option("SCENE", s.keys.scene, "Scene file with an ephemeral rig (.rigel)")->required();
  s.keys_cmd->add_option("--control", s.keys.control, "The control (a joint name stands for its control)")->required();
  s.keys_cmd->add_flag("--json", s.keys.json,
                     "Print {\"control\", \"rig\", \"keyScope\", \"keyingSet\": [NAME...], \"times\": [FRAME...], "
                     "\"seconds\": [S...]}");

  s.scope_cmd = ephemeral_cmd->add_subcommand(
      "scope", "Print a rig's keying scope, or set it (character: a key keys the whole character; controls: only "
               "the controls named)");
  s.scope_cmd->add_option("SCENE", s.scope.scene, "Scene file with an ephemeral rig (.rigel)")->required();
  s.scope_cmd->add_option("--rig", s.scope.rig, "The ephemeralRig node, by name (default name: ephemeralRig)")->required();
  s.scope_cmd->add_option("--set", s.scope.set, "character or controls (needs -o)");
  s.scope_cmd->add_option("-o,--output", s.scope.output, "Scene file to write (.rigel; with --set only)");
  s.scope_cmd->add_flag("--json", s.scope.json, "Print {\"rig\", \"keyScope\"}");

  s.merge_cmd = ephemeral_cmd->add_subcommand(
      "merge", "Merge characters: they move together in body mode and share keys; optionally a control of one carries another");
  s.merge_cmd->add_option("SCENE", s.merge.scene, "Scene file with ephemeral rigs (.rigel)")->required();
  s.merge_cmd->add_option("-o,--output", s.merge.output, "Scene file to write (.rigel)")->required();
  s.merge_cmd->add_option("--rigs", s.merge.rigs, "ephemeralRig nodes to merge, by name: A,B,... (two or more)")
      ->required()
      ->delimiter(',')
      ->allow_extra_args(false);
  s.merge_cmd->add_option("--carrier", s.merge.carrier,
                        "A control (of another merged character) that carries --carried's root controls, e.g. a hand");
  s.merge_cmd->add_option("--carried", s.merge.carried, "The rig that --carrier carries, e.g. a prop");
  s.merge_cmd->add_flag("--json", s.merge.json, "Print {\"merged\": [RIG...], \"carriers\": {RIG: CONTROL}}");

  s.unmerge_cmd = ephemeral_cmd->add_subcommand(
      "unmerge", "Take a character out of its merge group (clears carriers into and out of it; keys are kept)");
  s.unmerge_cmd->add_option("SCENE", s.unmerge.scene, "Scene file with ephemeral rigs (.rigel)")->required();
  s.unmerge_cmd->add_option("-o,--output", s.unmerge.output, "Scene file to write (.rigel)")->required();
  s.unmerge_cmd->add_option("--rig", s.unmerge.rig, "The ephemeralRig node, by name")->required();
  s.unmerge_cmd->add_flag("--json", s.unmerge.json, "Print {\"rig\", \"unmergedFrom\": [RIG...]}");
}

std::optional<int> run_ephemeral_commands(const EphemeralCommands& commands) {
  const EphemeralCommands::State& s = commands.state();
  if (*s.setup_cmd) return run_ephemeral_setup(s.setup);
  if (*s.relations_cmd) return run_ephemeral_relations(s.relations, s.relation_edits());
  if (*s.key_cmd) return run_ephemeral_key(s.key);
  if (*s.keys_cmd) return run_ephemeral_keys(s.keys);
  if (*s.scope_cmd) return run_ephemeral_scope(s.scope);
  if (*s.merge_cmd) return run_ephemeral_merge(s.merge);
  if (*s.unmerge_cmd) return run_ephemeral_unmerge(s.unmerge);
  return std::nullopt;
}

}  // namespace rigel::cli
