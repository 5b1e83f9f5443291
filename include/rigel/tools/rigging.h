#pragma once
// Rigger actions (seed 004 §4.5's shape, transform and joint action
// groups): a control's shape and colour copied and pasted, mirrored, flipped
// and mirrored onto the control on the other side; locators made at nodes;
// a joint hierarchy mirrored to the other side with its names swapped (a
// joint an ephemeral rig drives is moved through the control holding its
// channels).
// Each is one undo step, and on failure nothing changes. (Matching one
// selection's position or rotation to another's goes through the posing
// session: app::Workspace::align.)
//
// Sides are named as rig templates name them (rig::mirror_name: ".L" /
// ".R", "_L" / "_R", "Left" / "Right", ...); a built rig's control finds
// its pair through the metadata (rig::mirror_pair), so renamed controls
// still pair.

#include <cstddef>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/math/types.h"
#include "rigel/scene/scene.h"
#include "rigel/tools/mirror.h"

namespace rigel::tools {

// A control's look: its shape (points in its local space, closed or not)
// and colour (linear RGB), as copy and paste carry it.
struct ControlLook {
  std::vector<math::Vec3> points;
  bool closed = true;
  math::Vec3 color{1, 1, 0};
};

// kInvalidArgument naming `control` when it is not a `control` node.
Result<ControlLook> control_look(const graph::Graph& graph, graph::NodeId control);

// What a paste sets: the shape (points and closed), the colour, or both.
struct LookParts {
  bool shape = true;
  bool color = true;
};
// Sets each control's shape and/or colour to `look`'s. kInvalidArgument
// for no controls, a node that is not a control, non-finite points or a
// colour outside [0, 1].
Status paste_control_look(graph::Graph& graph, const std::vector<graph::NodeId>& controls, const ControlLook& look,
                          LookParts parts = {});

// In place, in the control's local space:
//   kMirror: reflected over the local plane (YZ: x -> -x), a mirror image;
//   kFlip:   turned over, a half turn about the plane's first in-plane
//            axis (YZ: about Y, x -> -x and z -> -z), so it keeps its
//            handedness (an arrow pointing +Z then points -Z).
enum class ShapeEdit { kMirror, kFlip };
Status edit_control_shape(graph::Graph& graph, const std::vector<graph::NodeId>& controls, ShapeEdit edit,
                          MirrorPlane plane = MirrorPlane::kYZ);

// The control on the other side: a built rig's pair from its metadata,
// otherwise the control named with its sides swapped. kInvalidArgument
// naming the control when it has none (a centre control is its own).
Result<graph::NodeId> opposite_control(const graph::Graph& graph, graph::NodeId control);

struct MirroredShape {
  graph::NodeId from, to;
};
// Each control's shape copied onto its opposite control, reflected in the
// world plane (the character's left-right plane for kYZ) and expressed in
// the opposite control's local space, so the two shapes are mirror images
// in the world whatever axes either control has; each keeps its own
// colour. Evaluated at the current time.
Result<std::vector<MirroredShape>> mirror_shape_to_opposite(scene::Scene& scene,
                                                            const std::vector<graph::NodeId>& controls,
                                                            MirrorPlane plane = MirrorPlane::kYZ);

// A locator at each node's world position and rotation: a root `control`
// node named "<node>_loc" (unique) drawn as the locator cross `size` across
// its half-extent, so it is drawn, picked, posed, keyed and used as a space
// target like any control. Returns the locators in the order given.
Result<std::vector<graph::NodeId>> create_locators(scene::Scene& scene, const std::vector<graph::NodeId>& at,
                                                   double size = 0.1);

struct MirrorJointsOptions {
  MirrorPlane plane = MirrorPlane::kYZ;
  // A joint whose mirrored name is already taken by a joint: moved onto
  // the mirror (symmetrising a skeleton); otherwise the call is refused.
  bool update_existing = false;
};
struct MirrorJointsReport {
  std::vector<graph::NodeId> created, updated;  // the mirrored joints, parents first
};
// Each root's joint hierarchy (the root and the joints below it) mirrored:
// a joint named with its sides swapped for each, under the mirror of its
// parent (the root's: its parent's opposite joint when there is one, else
// its parent), with world matrix M * W * M for the source's W (M the
// reflection), so positions are reflected, frames stay right-handed and
// mirroring back gives the skeleton back; radius copied. kInvalidArgument
// naming a node that is not a joint, a joint whose name has no side (a
// centre joint), or a mirrored name already taken (unless
// update_existing, and then only by a joint). Evaluated at the current time.
Result<MirrorJointsReport> mirror_joints(scene::Scene& scene, const std::vector<graph::NodeId>& roots,
                                         const MirrorJointsOptions& options = {});

}  // namespace rigel::tools
