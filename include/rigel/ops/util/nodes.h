#pragma once
// ops/util: the rig operators the rig layer's components build with, and a
// utility node (Maya's math nodes) for rigs that wire matrices between
// operators. Each rig operator is a kernel (a job, where the maths lives)
// and the node type that calls it:
//
//   node          node header  kernel (job)                   kernel header
//   fkIkSwitch    blend.h      FkIkBlendJob, ik_end_world()   fk_ik_blend.h
//   twistShare    twist.h      TwistShareJob, twist_angle()   twist_share.h
//   reverseFoot   foot.h       ReverseFootJob                 reverse_foot.h
//   fingerCurl    finger.h     FingerCurlJob                  finger_curl.h
//   spaceSwitch   space.h      (a matrix product: space.h)
//
//   inverseMatrix  inputMatrix, offsetMatrix (matrix inputs) ->
//                  outputMatrix = (inputMatrix * offsetMatrix)^-1
//                  Connect a transform's parent worldMatrix to inputMatrix and
//                  set offsetMatrix to its offsetParentMatrix: the output is
//                  the parent-space inverse a constraint's parentInverseMatrix
//                  needs, following the parent as it moves. A singular input
//                  gives the identity and says so in `error`.
//
//   poseReader     matrix, restMatrix (matrix inputs), axis (double3,
//                  default 1 0 0) -> angle (degrees: how far `axis` has
//                  swung from rest, 0..180) and rotate (double3, degrees:
//                  the rotation from rest as Euler XYZ). Connect a joint's
//                  local matrix and set restMatrix to its rest: the driver
//                  of corrective shapes and joints (tools/driven_poses.h).
//
//   squashStretch  startMatrix, endMatrix (matrix inputs: two world
//                  matrices), restLength (double), axis (enum x y z),
//                  volume (double 0..1), restScale (double3) -> stretch
//                  (d / restLength, d the distance between the matrices'
//                  positions; 1 when restLength is not positive) and scale
//                  (double3): restScale with `axis` times stretch and the
//                  other two times stretch^(-volume / 2), so at volume 1 the
//                  volume is kept (squash and stretch, the squash component).
//
//   wheelRoll      matrix, restMatrix (matrix inputs: a wheel's world now
//                  and at rest), forward, axle (double3, in the rest frame),
//                  radius (double) -> travel (the distance moved along
//                  the forward direction since rest, in the world) and
//                  rotate (double3 degrees: axle * travel / radius, the
//                  turn that rolls the wheel that far without slipping; 0
//                  when radius is not positive). Displacement, not path
//                  length: a wheel driven round a loop comes back to its
//                  rest angle (the wheel component).

#include "rigel/base/status.h"
#include "rigel/graph/node_type.h"

namespace rigel::ops::util {

inline constexpr const char* kInverseMatrixType = "inverseMatrix";
inline constexpr const char* kPoseReaderType = "poseReader";
inline constexpr const char* kSquashStretchType = "squashStretch";
inline constexpr const char* kWheelRollType = "wheelRoll";
namespace wheel_attr {
enum : graph::AttrIndex { kMatrix = 0, kRestMatrix, kForward, kAxle, kRadius, kTravel, kRotate, kCount };
}
namespace squash_attr {
enum : graph::AttrIndex { kStartMatrix = 0, kEndMatrix, kRestLength, kAxis, kVolume, kRestScale, kStretch, kScale, kCount };
}
namespace pose_reader_attr {
enum : graph::AttrIndex { kMatrix = 0, kRestMatrix, kAxis, kAngle, kRotate, kCount };
}

// Adds inverseMatrix and the rig operators' node types.
Status register_util_types(graph::Registry& registry);

}  // namespace rigel::ops::util
