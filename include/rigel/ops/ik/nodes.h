#pragma once
// Graph node types for the IK kernels: ikTwoBone (TwoBoneIkJob), ikFabrik
// (FabrikJob), ikCcd (CcdJob) and ikSpline (SplineIkJob), and the helpers
// that put one on a joint chain. The maths lives in the kernels; a node reads
// its inputs, runs the job and writes the channels the joints consume.
//
// No node-level cycles: a solver never reads the joints it drives. The chain's
// rest pose is the node's own stored input (copied from the joints by the
// setup helpers), the chain's parent space comes from a connection of the
// root joint's PARENT worldMatrix, and the target, pole and curve from
// control/locator worldMatrix connections. Per evaluation a node:
//   1. builds the chain's rest world matrices
//        world[i] = world[i - 1] * restOffsetParentMatrix[i] * restMatrix[i]
//      (world[-1] = parentMatrix);
//   2. runs its job on them and gets the solved world pose (rotational
//      solvers through ChainCorrectionJob, the one path of ik_chain.h);
//   3. writes, per joint, the channels that reproduce the solved pose:
//        matrix'[i] = inverse(restOffsetParentMatrix[i]) * solved_local[i]
//                   = T * JO * R * RA * SH * S      (pivots zero)
//      decomposed (math::decompose) into outTranslations[i] (T),
//      outScales[i] (S), outShears[i] (SH) and
//      outRotations[i] = R = JO^-1 * rotation * RA^-1, the value that, in a
//      joint's rotateQuaternion (rotateMode quaternion), gives the solved
//      world matrix: jointOrient and rotateAxis are accounted for.
//      outWorldMatrices[i] is the world matrix those channels give
//      (math::compose, as a joint computes it), what the joints evaluate to.
//   Exact for any joint whose pivots are zero (the helpers refuse others);
//   scale, shear, joint orient, rotate axis and offset parent matrices are
//   all accounted for.
//
// Shared attributes (every type, indices ik_attr::):
//   parentMatrix            matrix    world matrix of the root joint's parent:
//                                     connected from parent.worldMatrix, or
//                                     stored (identity for a root chain)
//   restMatrix              matrix[]  each chain joint's local `matrix` at setup;
//                                     its size is the chain's joint count
//   restOffsetParentMatrix  matrix[]  each joint's offsetParentMatrix (missing: identity)
//   restJointOrient         double3[] angle: each joint's jointOrient (missing: 0)
//   restRotateAxis          double3[] angle: each joint's rotateAxis (missing: 0)
//   weight                  double    keyable, 0..1: blend from the rest pose (0)
//                                     to the solve (1). Two-bone: the kernel's
//                                     weight; FABRIK/CCD: each correction
//                                     slerped from the identity; spline: each
//                                     joint's channels (rotation slerped,
//                                     translate/scale/shear lerped)
//   error                   string    hidden output: empty while the inputs
//                                     are valid, else what is wrong, naming the
//                                     attribute
//   outRotations            quat[]    connect [i] -> joint_i.rotateQuaternion
//                                     (sign kept continuous with the previous
//                                     evaluation, so baked curves do not pop)
//   outTranslations         double3[] connect [i] -> joint_i.translate (stretch)
//   outScales               double3[] connect [i] -> joint_i.scale (spline stretch/squash)
//   outShears               double3[] connect [i] -> joint_i.shear (spline squash)
//   outWorldMatrices        matrix[]  hidden: the solved world matrices
//
// Fallback: while `error` is non-empty every out* array holds the REST pose
// (each joint's restMatrix decomposed, so the joints show the pose they had
// at setup), with identity channels for a joint whose restMatrix is not
// finite; outWorldMatrices holds the world matrices of those channels under
// parentMatrix (under the identity when parentMatrix is not finite and
// affine; identity where a product is not finite). A node never crashes and
// never writes NaN channels. The out arrays have restMatrix's size, so with a
// restMatrix that is too short, joints beyond it read the arrays' zero
// elements. The type-specific result outputs (reached, iterations, ...)
// hold their zero then.
//
// Every failure a kernel's validate() documents surfaces in `error`, except
// those a node cannot produce: null pointers, scratch and output sizes
// (the node sizes them), overlapping spans, limits arrays of the wrong size
// (missing elements default), and an out-of-range poleMode or limitType
// (enums are kept in range by set_value, connections and files).
// Checks of the shared inputs (messages name the attribute):
//   - restMatrix has too few (or, two-bone, not exactly 3) joints;
//   - parentMatrix, restMatrix[i] or restOffsetParentMatrix[i] is not
//     finite or not affine (last row 0 0 0 1), or the offset parent matrix is
//     singular; restJointOrient/restRotateAxis not finite;
//   - weight outside [0, 1] (NaN included).
//
// ikTwoBone: the chain is exactly 3 joints (start, mid, end).
//   targetMatrix   matrix   the target's worldMatrix; the end joint reaches its translation
//   poleMode       enum     poleVector | planeNormal (TwoBonePoleMode)
//   poleVector     double3  keyable, world: the pole direction (from the start joint) or
//                           the plane normal, used unless usePoleMatrix
//   usePoleMatrix  bool     the pole direction is poleMatrix's translation minus the
//                           start joint's position
//   poleMatrix     matrix   the pole object's worldMatrix
//   midAxis        double3  unit, the mid joint's hinge axis in its own space
//   twist          double   keyable angle (degrees) about start-to-target
//   soft           double   keyable, 0..1 (soft IK)
//   stretch        bool     keyable
//   maxStretch     double   keyable, >= 1 when stretch is on (inf: no limit)
//   outputs: outStretch (double, the bones' length factor), reached (bool).
//   Failures: targetMatrix / poleMatrix (when used) / poleVector translation
//   not finite; midAxis not unit; twist not finite; soft or weight outside
//   [0, 1]; stretch on with maxStretch < 1 or NaN.
//   The joints are turned in world space (exact under non-uniformly
//   scaled parents, where a rigid turn takes a shear). The helper connects
//   outRotations, outScales and outShears[0..1] (start, mid) and
//   outTranslations[1..2] (mid, end: stretch); the end joint's rotation is
//   left to the animator (as Maya's ikHandle).
//
// ikThreeBone: a leg of three segments and its foot, exactly 4 joints
// (upper, lower, hock, foot: a quadruped's hind or front leg). Every
// ikTwoBone attribute at the same index (two_bone_attr::), then:
//   hockMode       enum     spring | pinned
//   hockMatrix     matrix   pinned: the hock bone's world matrix (a group under
//                           the hock control, at the hock joint's rest place)
//   spring: the hock bone keeps its angle to the upper bone (turns with it, a
//     pantograph, as a dog's or horse's cannon stays about parallel to the
//     femur), so the chain is a two-bone one of bones (upper + hock) and
//     lower whose middle stands where the two meet (in the lower joint's
//     frame: midAxis is that chain's hinge there); the foot reaches
//     targetMatrix's translation, exactly within reach.
//   pinned: upper and lower are a two-bone chain whose end, the hock joint,
//     reaches hockMatrix's translation; the hock bone takes hockMatrix's
//     orientation; the foot keeps its rest place in the hock bone's frame.
//     targetMatrix is not read. midAxis: the upper-lower hinge, as ikTwoBone's.
//   weight blends the joints' channels from the rest pose (as ikSpline's).
//   Failures: ikTwoBone's, and (pinned) hockMatrix not finite or not affine.
//   The foot's rotation is left to its IK control (fkIkSwitch's ikEndMatrix).
//
// ikFabrik / ikCcd: a chain of 2 or more joints.
//   targetMatrix    matrix     the end joint reaches its translation
//   tolerance       double     world units, >= 0 (default 1e-6)
//   maxIterations   int        >= 0 (default 64)
//   limitType       enum[]     none | hinge | cone per joint (missing: none)
//   limitAxis       double3[]  unit, in the parent joint's frame (missing: +z)
//   limitReference  double3[]  hinge angle-0 direction, unit, perpendicular to the axis (missing: +x)
//   limitMinAngle   double[]   angle (degrees), hinge range, -180..180 (missing: -180)
//   limitMaxAngle   double[]   angle (degrees) (missing: 180)
//   limitHalfAngle  double[]   angle (degrees), cone, 0..180 (missing: 180)
//   (JointLimit: limit i bounds the bone from joint i to joint i + 1, in the
//   frame of joint i - 1, parentMatrix for joint 0.)
//   outputs: iterations (int), endDistance (double, |end - target|), reached (bool).
//   Failures: targetMatrix translation not finite; a limit invalid
//   (joint_limit_error(), message names the attribute and joint); tolerance
//   negative or not finite; maxIterations negative.
//   The helpers connect outRotations[0..n-2]; the end joint's rotation is free.
//
// ikSpline: a chain of 2 or more joints along the B-spline of the control points.
//   controlMatrix     matrix[]  each control point's worldMatrix (its translation)
//   aimAxis, upAxis   double3   unit, perpendicular, joint space (default +x, +y)
//   worldUpVector     double3   world up (default +y), not zero
//   startTwist, endTwist double keyable angles (degrees)
//   stretch, squash   bool      keyable
//   arcLengthSamples  int       size of the arc-length table; 0 (default): 64 per
//                               control point span + 1 (at most 1048576); else
//                               2..1048576
//   outputs: curveLength, chainLength (double), overran (bool).
//   Failures: fewer than 2 control points or one not finite; arcLengthSamples
//   1, negative or too large; aimAxis or upAxis not unit or not
//   perpendicular; worldUpVector zero or not finite; a twist not finite;
//   the solved chain singular (a zero-length curve with stretch).
//   The helper connects outRotations, outTranslations, outScales and
//   outShears of every joint (the spline places all of them, root included).

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/graph/node_type.h"
#include "rigel/ops/ik/ik_chain.h"
#include "rigel/scene/scene.h"

namespace rigel::ops::ik {

inline constexpr const char* kIkTwoBoneType = "ikTwoBone";
inline constexpr const char* kIkThreeBoneType = "ikThreeBone";
inline constexpr const char* kIkFabrikType = "ikFabrik";
inline constexpr const char* kIkCcdType = "ikCcd";
inline constexpr const char* kIkSplineType = "ikSpline";

// Attributes every IK type has, at these indices.
namespace ik_attr {
enum : graph::AttrIndex {
  kParentMatrix = 0,
  kRestMatrix,
  kRestOffsetParentMatrix,
  kRestJointOrient,
  kRestRotateAxis,
  kWeight,
  kError,
  kOutRotations,
  kOutTranslations,
  kOutScales,
  kOutShears,
  kOutWorldMatrices,
  kCount  // first type-specific attribute
};
}  // namespace ik_attr

namespace two_bone_attr {
enum : graph::AttrIndex {
  kTargetMatrix = ik_attr::kCount,
  kPoleMode,
  kPoleVector,
  kUsePoleMatrix,
  kPoleMatrix,
  kMidAxis,
  kTwist,
  kSoft,
  kStretch,
  kMaxStretch,
  kOutStretch,  // output
  kReached,     // output
  kCount
};
}  // namespace two_bone_attr

// ikThreeBone: two_bone_attr's, then these.
namespace three_bone_attr {
enum : graph::AttrIndex { kHockMode = two_bone_attr::kCount, kHockMatrix, kCount };
}  // namespace three_bone_attr

// ikFabrik and ikCcd.
namespace chain_attr {
enum : graph::AttrIndex {
  kTargetMatrix = ik_attr::kCount,
  kTolerance,
  kMaxIterations,
  kLimitType,
  kLimitAxis,
  kLimitReference,
  kLimitMinAngle,
  kLimitMaxAngle,
  kLimitHalfAngle,
  kIterations,   // output
  kEndDistance,  // output
  kReached,      // output
  kCount
};
}  // namespace chain_attr

namespace spline_attr {
enum : graph::AttrIndex {
  kControlMatrix = ik_attr::kCount,
  kAimAxis,
  kUpAxis,
  kWorldUpVector,
  kStartTwist,
  kEndTwist,
  kStretch,
  kSquash,
  kArcLengthSamples,
  kCurveLength,  // output
  kChainLength,  // output
  kOverran,      // output
  kCount
};
}  // namespace spline_attr

// Adds the four IK types to `registry`. Fails if a name is taken.
Status register_ik_types(graph::Registry& registry);

// ---- setup helpers ----------------------------------------------------------
// Each helper, as ONE undo step (a graph transaction, rolled back on any
// failure, so a failed call leaves the scene as it was):
//   - checks the chain: 2+ transforms (two-bone: exactly 3), chain[i + 1] the
//     child of chain[i], no repeats, pivots zero (rotatePivot,
//     rotatePivotTranslate, scalePivot, scalePivotTranslate);
//   - creates the node and copies the rest data: each joint's evaluated
//     `matrix`, offsetParentMatrix, jointOrient (joints) and rotateAxis;
//   - connects the root's parent's worldMatrix to parentMatrix, or stores the
//     root's parentMatrix when it has no parent;
//   - connects target / pole / control point worldMatrix outputs;
//   - switches the driven joints to rotateMode quaternion and connects the
//     outputs to their channels (see each type above).
// The graph refuses a connection that would close a cycle (a target below
// the chain, say); the helper then fails with the graph's message. A driven
// channel that is already connected fails the same way ("disconnect it
// first"). Right after setup (weight 1, target wherever it is) the chain
// solves toward the target; with weight 0 it shows its rest pose.

struct TwoBoneIkOptions {
  // Node name; empty: "<start>_ikTwoBone".
  std::string name;
  // The mid joint's hinge axis in its own space. Default: the normal of the
  // rest bend (cross(mid - start, end - mid)), or, for a straight chain, the
  // one that bends the knee toward the pole (cross(pole - start, mid - start));
  // a straight chain with neither fails.
  std::optional<Vec3> mid_axis;
  // Used when no pole node is given: the pole direction (world). Default:
  // toward the mid joint from the start-end line at rest (the rest bend).
  std::optional<Vec3> pole_vector;
};

// chain = {start, mid, end}; target: a transform whose worldMatrix is the
// target; pole (optional, invalid NodeId: none): a transform the knee points
// toward (usePoleMatrix on).
Result<graph::NodeId> setup_two_bone_ik(scene::Scene& scene, std::span<const graph::NodeId> chain,
                                        graph::NodeId target, graph::NodeId pole = graph::NodeId{},
                                        const TwoBoneIkOptions& options = {});

struct ChainIkOptions {
  // Node name; empty: "<root>_ikFabrik" / "<root>_ikCcd".
  std::string name;
  // Empty, or one per joint (radians, as JointLimit; written to the limit*
  // arrays in degrees).
  std::vector<JointLimit> limits;
  double tolerance = 1e-6;
  int max_iterations = 64;
};

Result<graph::NodeId> setup_fabrik_ik(scene::Scene& scene, std::span<const graph::NodeId> chain,
                                      graph::NodeId target, const ChainIkOptions& options = {});
Result<graph::NodeId> setup_ccd_ik(scene::Scene& scene, std::span<const graph::NodeId> chain,
                                   graph::NodeId target, const ChainIkOptions& options = {});

struct SplineIkOptions {
  // Node name; empty: "<root>_ikSpline".
  std::string name;
  // Joint-space axes; default: aim = the root joint's direction to its child
  // at rest, up = the root joint's axis nearest world_up_vector, made
  // perpendicular to the aim (so a curve through the rest joints keeps them
  // as they are).
  std::optional<Vec3> aim_axis;
  std::optional<Vec3> up_axis;
  Vec3 world_up_vector = Vec3::UnitY();
  bool stretch = false;
  bool squash = false;
};

// control_points: 2 or more transforms whose worldMatrix translations are the
// curve's control points.
Result<graph::NodeId> setup_spline_ik(scene::Scene& scene, std::span<const graph::NodeId> chain,
                                      std::span<const graph::NodeId> control_points,
                                      const SplineIkOptions& options = {});

}  // namespace rigel::ops::ik
