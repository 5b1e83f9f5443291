#pragma once
// Control shapes and colours as data (seed 004 §4.10's CtlShapeManager):
// every control of a built rig with its shape (points in its local space,
// closed or not) and colour, by component rigId, role and index (names are
// written for people reading a diff; nothing resolves by them), so a
// rebuild from scratch, a renamed component or another character built
// from the same definition gets the shapes a rigger drew back:
//
//   {
//     "rigelShapes": 1,
//     "rig": "hero",
//     "controls": [
//       {
//         "rigId": "...", "component": "arm_L", "role": "ik", "index": 0, "name": "hero_arm_L_ik",
//         "closed": false, "color": [r, g, b],
//         "points": [
//           [x, y, z],
//           ...
//         ]
//       },
//       ...
//     ]
//   }
//
// (each member on its line). Export after import gives the same file byte
// for byte.

#include <string>
#include <string_view>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/graph/graph.h"
#include "rigel/tools/rigging.h"

namespace rigel::tools {

inline constexpr int kShapesFormat = 1;

struct ShapeEntry {
  std::string rig_id, component, role, name;
  int index = 0;
  ControlLook look;
};

struct ShapeSet {
  std::string rig;
  std::vector<ShapeEntry> controls;
};

// The shapes of every control of built rig `rig` (its metaRoot), in the
// rig's component and member order.
Result<ShapeSet> capture_control_shapes(graph::Graph& graph, graph::NodeId rig);

std::string control_shapes_to_json(const ShapeSet& shapes);
// kParseError naming `source` and the place for text that is not a shapes file.
Result<ShapeSet> control_shapes_from_json(std::string_view text, const std::string& source);

struct ShapesReport {
  std::size_t set = 0;
  std::vector<std::string> missing;  // entries whose component or control the rig lacks ("arm_L ik[0]")
};
// Sets each entry's look on the control its rigId, role and index find in
// `rig` (one undo step); entries the rig lacks are reported, not refused.
Result<ShapesReport> apply_control_shapes(graph::Graph& graph, graph::NodeId rig, const ShapeSet& shapes);

}  // namespace rigel::tools
