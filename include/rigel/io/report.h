#pragma once
// Read-only reports on a scene as JSON: what `rigel inspect --json` and
// `rigel eval --json` print, and what the server and Python module return.
// The eval report's shape is a contract (DESIGN.md, CLI contract).

#include <nlohmann/json.hpp>

#include "rigel/scene/scene.h"

namespace rigel::io {

// {"fps", "time", "frame", "node_count", "types": {type: count},
//  "roots": [name...],
//  "nodes": [{"name", "type", "uuid", "parent"?, "children": [...], "tags": {...}}],
//  "connections": [{"src", "dst"}]}  (hierarchy links are in parent/children)
nlohmann::ordered_json inspect_report(scene::Scene& scene);

// {"frame": F, "time": S, "nodes": {NAME: {"t": [x,y,z], "q": [x,y,z,w],
// "s": [x,y,z]}}}: world-space translation, rotation and scale of every
// transform node at the scene's current time (shear, if any, is dropped).
nlohmann::ordered_json eval_report(scene::Scene& scene);

}  // namespace rigel::io
