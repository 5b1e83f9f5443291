#pragma once
// fingerCurl: turns a hand's finger controls by curl and spread values. It
// holds the keyable values a hand's curl attributes stand for (node types
// have fixed attributes, so the values live here, not on the hand control)
// and writes each finger control's offsetParentMatrix, so the curl is a
// layer under the animator's FK channels: at curl = spread = 0 every control
// sits at its rest offset with zeroed channels, and its own rotate turns it
// further from wherever the curl put it. FingerCurlJob (finger_curl.h) does
// the maths.
//
// Inputs:
//   curl                    double    keyable, angle: curl of every finger
//   spread                  double    keyable, angle: spread of every finger
//   fingerCurl              double[]  keyable, angle: extra curl per finger
//                                     (missing element: 0)
//   fingerNames             string[]  per finger, for people (no effect)
//   finger                  int[]     per control: its finger's index k
//   restOffsetParentMatrix  matrix[]  per control: offsetParentMatrix at rest
//   bendAxis                double3[] per control: curl axis, control frame
//   spreadAxis              double3[] per control: spread axis, control frame
//   spreadWeight            double[]  per control (missing: 0)
// Outputs: outOffsetParentMatrix (matrix[], one per control), error
//   (hidden). An axis that is zero or not finite while its angle is not zero,
//   or a missing finger/axis element, gives that control no turn for that
//   part and names it in `error`.

#include "rigel/base/status.h"
#include "rigel/graph/node_type.h"
#include "rigel/math/types.h"
#include "rigel/ops/util/finger_curl.h"

namespace rigel::ops::util {

inline constexpr const char* kFingerCurlType = "fingerCurl";

namespace finger_attr {
enum : graph::AttrIndex {
  kCurl = 0,
  kSpread,
  kFingerCurl,
  kFingerNames,
  kFinger,
  kRestOffsetParentMatrix,
  kBendAxis,
  kSpreadAxis,
  kSpreadWeight,
  kOutOffsetParentMatrix,
  kError,
  kCount
};
}  // namespace finger_attr

// Adds fingerCurl (called by register_util_types).
Status register_finger_types(graph::Registry& registry);

}  // namespace rigel::ops::util
