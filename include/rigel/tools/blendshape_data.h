#pragma once
// Blend shapes as data (seed 004 §4.10's BlendshapeManager): every
// blendShape's targets and weights exported to diffable JSON and imported
// back, so a rebuild from scratch (the character's glTF imported again, the
// rig built) gets a sculpted target and changed weights back. A file:
//
//   {
//     "rigelBlendShapes": 1,
//     "blendShapes": [
//       {
//         "blendShape": "face_blendShape",
//         "mesh": "face",
//         "vertexCount": 4212,
//         "targets": [
//           {
//             "index": 0,
//             "name": "smile",
//             "weight": 0.25,
//             "deltas": [
//               [12, 0.001, 0.0025, 0.0],      one line per moved vertex: vertex, dx, dy, dz
//               ...
//             ]
//           },
//           ...
//         ]
//       }
//     ]
//   }
//
// (each member on its line). `mesh` is the mesh the blendShape deforms
// (its outPoints feed the mesh's points, or the bindPoints of the
// skinCluster that feeds them); `vertexCount` its base point count; a
// target is its index in the blendShape and its name (the blendShape's
// targetNames, read from a glTF mesh's extras.targetNames; "" when it has
// none); `weight` the weight now; `deltas` only the vertices that move, in
// rising order. Numbers are written shortest round-trip, so export after
// import gives the same file byte for byte.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/graph/graph.h"
#include "rigel/math/types.h"

namespace rigel::tools {

inline constexpr int kBlendShapesFormat = 1;

struct BlendTarget {
  std::size_t index = 0;  // in the blendShape it was captured from
  std::string name;       // "" when unnamed
  double weight = 0;
  std::vector<std::int64_t> vertices;  // one per delta
  std::vector<math::Vec3> deltas;      // none zero
};

struct BlendShapeSet {
  std::string blend_shape, mesh;
  std::size_t vertex_count = 0;
  std::vector<BlendTarget> targets;
};

// Every blendShape of the graph (in creation order), as evaluated now
// (weights driven by curves at the current time). kInvalidArgument when it
// has none, or naming a blendShape whose targets do not validate (offsets,
// a dense target's count, a vertex out of range or listed twice).
Result<std::vector<BlendShapeSet>> capture_blend_shapes(graph::Graph& graph);

std::string blend_shapes_to_json(const std::vector<BlendShapeSet>& sets);
// kParseError naming `source` and the place (line:column, or the member:
// "blendShapes[0].targets[2].deltas[5]") for text that is not a blend
// shapes file: a vertex not below vertexCount or listed twice, a delta
// that is not three finite numbers, two targets of one index or name.
Result<std::vector<BlendShapeSet>> blend_shapes_from_json(std::string_view text, const std::string& source);

struct BlendShapesImport {
  // A file blendShape the scene lacks, whose mesh the scene has without
  // one: made, wired as the glTF importer wires one (in front of the
  // mesh's skinCluster, else of its points). False: refused naming the mesh.
  bool create = true;
};

struct BlendShapesReport {
  std::size_t blend_shapes = 0, targets = 0;
  std::vector<std::string> created;  // blendShapes made ("face_blendShape on face")
  std::vector<std::string> added;    // targets the blendShape lacked ("face_blendShape: smile")
  // Weights the file gives otherwise than what drives them gives now, left
  // to their driver ("face_blendShape.weights[1]").
  std::vector<std::string> driven;
};

// Each file blendShape onto the scene's blendShape of the same name, else
// the one deforming the mesh of the same name (else one made on that mesh,
// with `create`). A named file target replaces the scene's target of that
// name, else the scene's target at its index when that one is unnamed (it
// takes the name); an unnamed one, the target at its index; one that
// matches none is added after the scene's. Scene targets the file does not
// list are kept. Each target's weight is set unless something drives it (a
// curve: reported when the file's differs). One undo step; on failure
// nothing changes. kInvalidArgument naming the blendShape (field
// "blendShape") for one the scene lacks, a vertex count that differs, a
// vertex out of range or two file targets onto one; naming the mesh (field
// "mesh") for one that cannot take a new blendShape.
Result<BlendShapesReport> apply_blend_shapes(graph::Graph& graph, const std::vector<BlendShapeSet>& sets,
                                             const BlendShapesImport& options = {});

}  // namespace rigel::tools
