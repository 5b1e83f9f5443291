// `rigel ephemeral relations` (relations_command.h).

#include "relations_command.h"

#include <algorithm>
#include <iostream>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_util.h"
#include "rigel/ephemeral/keying.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/io/scene_file.h"

namespace rigel::cli {
namespace {

using rigel::Status;
using rigel::graph::NodeId;

const char* edit_option(RelationEdit::Op op) {
  switch (op) {
    case RelationEdit::Op::kAdd: return "--add";
    case RelationEdit::Op::kRemove: return "--remove";
    case RelationEdit::Op::kSetKind: return "--set-kind";
    case RelationEdit::Op::kGroup: return "--group";
  }
  return "";
}

std::string relation_kinds_text() {
  std::string kinds;
  for (int k = 0; k < rigel::ephemeral::kRelationKindCount; ++k)
    kinds += std::string(k ? ", " : "") +
             rigel::ephemeral::relation_kind_name(static_cast<rigel::ephemeral::RelationKind>(k));
  return kinds;
}

// An edit's value, checked for form only (names are resolved against the
// scene later): KIND:FROM:TO (=NEWKIND for --set-kind), or A,B,... for
// --group. Control names may hold ':' themselves ("mixamorig:Hips"), so
// FROM:TO is split where both sides name nodes (see split_ends()).
struct RelationSpec {
  rigel::ephemeral::RelationKind kind = rigel::ephemeral::RelationKind::kForward;
  rigel::ephemeral::RelationKind new_kind = rigel::ephemeral::RelationKind::kForward;
  std::string ends;                // FROM:TO
  std::vector<std::string> names;  // --group's members
};

// The spec of `edit`, or the usage error's message.
std::variant<RelationSpec, std::string> parse_relation_edit(const RelationEdit& edit) {
  namespace eph = rigel::ephemeral;
  const std::string where = std::string(edit_option(edit.op)) + " '" + edit.text + "'";
  RelationSpec spec;
  if (edit.op == RelationEdit::Op::kGroup) {
    std::size_t start = 0;
    while (true) {
      const std::size_t comma = edit.text.find(',', start);
      spec.names.push_back(edit.text.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
      if (spec.names.back().empty()) return where + ": empty control name (expected A,B,... two controls or more)";
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
    if (spec.names.size() < 2) return where + ": a group needs two controls or more (A,B,...)";
    return spec;
  }
  const bool set_kind = edit.op == RelationEdit::Op::kSetKind;
  const std::string malformed = where + ": expected " + (set_kind ? "KIND:FROM:TO=NEWKIND, e.g. forward:elbow_ctrl:wrist_ctrl=pair"
                                                                  : "KIND:FROM:TO, e.g. pair:elbow_ctrl:wrist_ctrl");
  std::string text = edit.text;
  if (set_kind) {
    const std::size_t eq = text.rfind('=');
    if (eq == std::string::npos) return malformed;
    const std::string new_kind = text.substr(eq + 1);
    const std::optional<eph::RelationKind> k = eph::relation_kind_from_name(new_kind);
    if (!k) return where + ": unknown kind '" + new_kind + "'; kinds: " + relation_kinds_text();
    spec.new_kind = *k;
    text.resize(eq);
  }
  const std::size_t colon = text.find(':');
  if (colon == std::string::npos || colon + 1 >= text.size()) return malformed;
  spec.ends = text.substr(colon + 1);
  const std::size_t second = spec.ends.find(':');
  if (second == std::string::npos || second == 0 || spec.ends.back() == ':') return malformed;
  const std::string kind = text.substr(0, colon);
  const std::optional<eph::RelationKind> k = eph::relation_kind_from_name(kind);
  if (!k) return where + ": unknown kind '" + kind + "'; kinds: " + relation_kinds_text();
  spec.kind = *k;
  return spec;
}

// FROM:TO split at the one colon where both sides name nodes (a name may hold
// colons); the first colon when no split or several do, so that the error
// names what was not found.
std::pair<std::string, std::string> split_ends(const rigel::graph::Graph& g, const std::string& ends) {
  std::optional<std::size_t> found;
  int count = 0;
  for (std::size_t i = ends.find(':'); i != std::string::npos; i = ends.find(':', i + 1)) {
    if (g.find(ends.substr(0, i)).is_valid() && g.find(ends.substr(i + 1)).is_valid()) {
      found = i;
      ++count;
    }
  }
  const std::size_t at = count == 1 ? *found : ends.find(':');
  return {ends.substr(0, at), ends.substr(at + 1)};
}

// The relations `rig`'s carrier adds (keying.h): the carrier drives the
// rig's root controls (forward) and they reach back (inverse). They live
// with the carrier, not in the rig's relation list.
std::vector<rigel::ephemeral::Relation> carrier_relations_of(const rigel::graph::Graph& g, NodeId rig) {
  std::vector<rigel::ephemeral::Relation> out;
  for (const rigel::ephemeral::Relation& r : rigel::ephemeral::carrier_relations(g)) {
    const NodeId carried = r.kind == rigel::ephemeral::RelationKind::kForward ? r.to : r.from;
    if (rigel::ephemeral::rig_of(g, carried) == rig) out.push_back(r);
  }
  return out;
}

nlohmann::ordered_json relations_json(const rigel::graph::Graph& g, NodeId rig,
                                      const std::vector<rigel::ephemeral::Relation>& relations) {
  nlohmann::ordered_json out;
  out["rig"] = g.node(rig)->name();
  out["relations"] = nlohmann::ordered_json::array();
  for (const rigel::ephemeral::Relation& r : relations) {
    out["relations"].push_back({{"kind", rigel::ephemeral::relation_kind_name(r.kind)},
                                {"from", g.node(r.from)->name()},
                                {"to", g.node(r.to)->name()}});
  }
  for (const rigel::ephemeral::Relation& r : carrier_relations_of(g, rig)) {
    out["relations"].push_back({{"kind", rigel::ephemeral::relation_kind_name(r.kind)},
                                {"from", g.node(r.from)->name()},
                                {"to", g.node(r.to)->name()},
                                {"carrier", true}});
  }
  return out;
}

// Prints the relations of `rigs`: text (a `RIG:` line before each rig's when
// there are several) or one JSON object per rig, one a line.
int print_relations(const rigel::graph::Graph& g, const std::string& scene, const std::vector<NodeId>& rigs, bool json) {
  for (NodeId rig : rigs) {
    auto relations = rigel::ephemeral::relations(g, rig);
    if (!relations) return fail(relations.status().with_context(scene + ": " + g.node(rig)->name()));
    if (json) {
      std::cout << relations_json(g, rig, *relations).dump() << "\n";
      continue;
    }
    if (rigs.size() > 1) std::cout << g.node(rig)->name() << ":\n";
    for (const rigel::ephemeral::Relation& r : *relations) {
      std::printf("%-7s  %s -> %s\n", rigel::ephemeral::relation_kind_name(r.kind), g.node(r.from)->name().c_str(),
                  g.node(r.to)->name().c_str());
    }
    for (const rigel::ephemeral::Relation& r : carrier_relations_of(g, rig)) {
      std::printf("%-7s  %s -> %s  (carrier)\n", rigel::ephemeral::relation_kind_name(r.kind),
                  g.node(r.from)->name().c_str(), g.node(r.to)->name().c_str());
    }
  }
  std::fflush(stdout);
  return 0;
}

}  // namespace

int run_ephemeral_relations(const EphemeralRelationsArgs& args, const std::vector<RelationEdit>& edits) {
  namespace eph = rigel::ephemeral;
  // Usage errors first (exit 2), before the scene is read.
  std::vector<RelationSpec> specs;
  for (const RelationEdit& edit : edits) {
    auto spec = parse_relation_edit(edit);
    if (const std::string* message = std::get_if<std::string>(&spec)) return usage_error(*message);
    specs.push_back(std::get<RelationSpec>(std::move(spec)));
  }
  if (!edits.empty() && !args.output)
    return usage_error(std::string(edit_option(edits.front().op)) + " needs -o OUT (the scene to write)");
  if (edits.empty() && args.output)
    return usage_error(
        "-o applies with --add, --remove, --set-kind or --group only (without them, relations prints the relations)");

  auto scene = load_rigged(args.scene);
  if (!scene) return fail(scene.status());
  rigel::graph::Graph& g = (*scene)->graph();
  NodeId picked;
  if (args.rig) {
    auto rig = resolve_rig(g, args.scene, "--rig", *args.rig);
    if (!rig) return fail(rig.status());
    picked = *rig;
  }
  if (edits.empty())
    return print_relations(g, args.scene, args.rig ? std::vector<NodeId>{picked} : eph::rigs_find(g), args.json);

  // Every edit in one transaction: all apply, or none.
  std::vector<NodeId> touched;  // rigs edited, first edit first
  std::size_t added = 0, removed = 0, changed = 0, grouped = 0;
  rigel::graph::Transaction tx(g, "edit ephemeral relations");
  for (std::size_t i = 0; i < edits.size(); ++i) {
    const RelationEdit& edit = edits[i];
    const RelationSpec& spec = specs[i];
    const std::string where = std::string(edit_option(edit.op)) + " '" + edit.text + "'";
    std::vector<std::string> names = spec.names;
    if (edit.op != RelationEdit::Op::kGroup) {
      auto [from, to] = split_ends(g, spec.ends);
      names = {from, to};
    }
    std::vector<NodeId> controls;
    for (const std::string& name : names) {
      auto control = resolve_control(g, args.scene, where, name);
      if (!control) {
        tx.rollback();
        return fail(control.status());
      }
      controls.push_back(*control);
    }
    // The rig: --rig, else the rig of FROM's (the first member's) control.
    const NodeId rig = picked.is_valid() ? picked : eph::rig_of(g, controls.front());
    Status st;
    switch (edit.op) {
      case RelationEdit::Op::kAdd:
        st = eph::relation_add(g, rig, {spec.kind, controls[0], controls[1]});
        added += st.is_ok();
        break;
      case RelationEdit::Op::kRemove:
        st = eph::relation_remove(g, rig, {spec.kind, controls[0], controls[1]});
        removed += st.is_ok();
        break;
      case RelationEdit::Op::kSetKind:
        st = eph::relation_set_kind(g, rig, {spec.kind, controls[0], controls[1]}, spec.new_kind);
        changed += st.is_ok();
        break;
      case RelationEdit::Op::kGroup:
        st = eph::group_add(g, rig, controls);
        grouped += st.is_ok();
        break;
    }
    if (!st && edit.op != RelationEdit::Op::kAdd && edit.op != RelationEdit::Op::kGroup) {
      // A carrier's relation is not the rig's to edit: it goes with the carrier.
      const eph::Relation r{spec.kind, controls[0], controls[1]};
      for (NodeId carried : eph::rigs_find(g)) {
        const std::vector<eph::Relation> cr = carrier_relations_of(g, carried);
        if (std::find(cr.begin(), cr.end(), r) == cr.end()) continue;
        st = Status(rigel::ErrorCode::kInvalidArgument,
                    "a carrier relation (" + g.node(eph::carrier_of(g, carried))->name() + " carries " +
                        g.node(carried)->name() + "): it goes with the carrier; `rigel ephemeral unmerge --rig " +
                        g.node(carried)->name() + "` clears it");
        break;
      }
    }
    if (!st) {
      tx.rollback();
      return fail(st.with_context(args.scene + ": " + where));
    }
    if (std::find(touched.begin(), touched.end(), rig) == touched.end()) touched.push_back(rig);
  }
  if (Status st = rigel::io::save_scene(**scene, *args.output); !st) return fail(st);
  if (args.json) {
    if (int code = print_relations(g, args.scene, touched, true); code != 0) return code;
  }
  std::string rigs;
  for (NodeId r : touched) {
    auto relations = eph::relations(g, r);
    const std::size_t n = relations ? relations->size() : 0;
    rigs += (rigs.empty() ? "" : ", ") + g.node(r)->name() + " (" + std::to_string(n) +
            (n == 1 ? " relation)" : " relations)");
  }
  std::cerr << "rigel: relations: " << added << " added, " << removed << " removed, " << changed << " changed, " << grouped
            << (grouped == 1 ? " group" : " groups") << " added; " << rigs << "; wrote " << *args.output << "\n";
  return 0;
}

}  // namespace rigel::cli
