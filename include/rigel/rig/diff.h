// Semantic differences between two rig definitions (`rigel diff`): what
// changed for the rig and for each component, components matched by rigId
// (seed 002: identity across versions is the rigId, never the name), so a
// renamed or moved component is reported as renamed or moved, not as one
// removed and one added. Works on the model, so the two sides may come from
// different syntaxes.
#pragma once

#include <string>
#include <vector>

#include "rigel/rig/definition.h"

namespace rigel::rig {

enum class DifferenceKind {
  kRigName,            // old/new: the names
  kRigVersion,         // old/new: the versions
  kRigGuiLocation,     // old/new: "x,y" ("" when absent)
  kGeometryAdded,      // item: "file" or "file#name"; new
  kGeometryRemoved,    // item as above; old
  kDataChanged,        // old/new: the data entries in order, "kind file, kind file" ("" when none)
  kFeatureAdded,       // item: feature name; new: "true"/"false" (+ switches); rig-level when rig_id is ""
  kFeatureRemoved,
  kFeatureChanged,     // old/new: "enabled=... switches a=true,b=false"
  kComponentAdded,     // new: "TYPE under PARENT at HOOK"
  kComponentRemoved,   // old: as above
  kComponentMoved,     // old/new: "under PARENT at HOOK" (a different nesting parent or attach)
  kComponentRenamed,   // old/new: "NAME (SIDE)" (name or side changed)
  kComponentTypeChanged,
  kComponentVersionChanged,
  kComponentGuiLocation,
  kParamAdded,         // item: parameter name; new: its value as XML text
  kParamRemoved,       // item; old
  kParamChanged,       // item; old/new
  kGuideAdded,         // item: "guide I (NAME)"; new: its fields
  kGuideRemoved,       // item; old
  kGuideChanged,       // item; old/new: its fields ("joint=hips translate=0 1 0")
  kControlAdded,       // item: role; new: "shape color size"
  kControlRemoved,
  kControlChanged,
};

// "rigName", "componentAdded", "paramChanged", ...: the names `--json` prints.
const char* difference_kind_name(DifferenceKind kind);

struct Difference {
  DifferenceKind kind;
  std::string rig_id;     // the component's; "" for the rig itself
  std::string component;  // its name in B ("" for the rig; A's name when removed)
  std::string item;       // parameter, guide, control role, feature, geometry; "" when the whole component
  std::string old_value;  // A's value as text ("" when added)
  std::string new_value;  // B's value as text ("" when removed)
  // One line for people: "component 'arm' (3b1f...): parameter 'stretch': true -> false".
  std::string str() const;
};

// Every difference from `a` to `b`, deterministic: the rig's first, then
// removed components (in a's order), then each component of b in b's
// order. Components match by rigId (compared as UUIDs: case and dashes
// ignored); components without a rigId match by name and side. Sibling order
// and source locations are not differences. Empty: the same rig.
std::vector<Difference> diff(const Definition& a, const Definition& b);

}  // namespace rigel::rig
