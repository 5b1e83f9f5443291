#pragma once
// Set-driven keys and the data managers built on them (seed 004 §4.10's
// DrivenPoseManager and SDKCorrectiveManager).
//
// A set-driven key (Maya's SDK) makes one attribute, the driver (a
// control's custom attribute, a joint's rotateX), drive others: each driven
// channel is fed by a `drivenKey` node whose keys map driver values to the
// channel's values (ops/anim/nodes.h). A "pose" is one driver value with
// the driven values at it: keying the pose `curl = 10` with the finger
// controls bent writes one key at 10 on each finger channel's curve.
//
// Two kinds of driven data, told apart by what they drive:
//   - driven poses: channels of controls and other transforms (not joints);
//   - correctives: blend shape weights (`body_blendShape.weights[2]`) and
//     joints (corrective joints), usually driven by a joint's angle (a
//     pose reader: create_pose_reader below).
// Each is exported to diffable JSON and imported back, so a rebuild from
// scratch gets the poses a rigger keyed:
//
//   {
//     "rigelDrivenPoses": 1,
//     "kind": "drivenPoses",            or "correctives"
//     "drivers": [
//       {
//         "driver": "hero_hand_L_fk0.rotateX",
//         "curves": [
//           {
//             "node": "hero_index_L_fk0_rotateZ_drivenKey",
//             "driven": "hero_index_L_fk0.rotateZ",
//             "keys": [
//               [0, 0],                     driver value, driven value
//               [90, -45]
//             ],
//             "inTangents": ["linear", "linear"],   the node's optional arrays, when set
//             ...
//           }
//         ]
//       }
//     ]
//   }
//
// Nodes and plugs are named (the names a build gives are the same on every
// build of a definition with the same naming template). The curves keep
// every array and setting of their nodes, so export after import gives
// the same file byte for byte.

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/graph/graph.h"
#include "rigel/math/types.h"
#include "rigel/ops/anim/curve.h"

namespace rigel::tools {

inline constexpr int kDrivenPosesFormat = 1;

enum class DrivenData { kPoses, kCorrectives };
// "drivenPoses", "correctives".
std::string_view driven_data_name(DrivenData kind);

struct DrivenCurve {
  std::string node;    // the drivenKey node
  std::string driven;  // the channel it feeds ("ctrl.rotateZ", "mesh_blendShape.weights[2]")
  std::vector<double> times, values;  // driver values (increasing) and driven values
  // The node's optional per-key arrays: empty, or one entry per key.
  std::vector<std::string> in_types, out_types;  // tangent type names ("auto", "linear", ...)
  std::vector<double> in_slopes, out_slopes, in_weights, out_weights;
  bool weighted = false;
  std::string pre_infinity = "constant", post_infinity = "constant";
};

struct DrivenDriver {
  std::string driver;  // the driving plug ("hero_hand_L_ctrl.curl")
  std::vector<DrivenCurve> curves;
};

struct DrivenPoseSet {
  DrivenData kind = DrivenData::kPoses;
  std::vector<DrivenDriver> drivers;  // in the order their first curve was made
};

// The kind of data a driven channel belongs to: kCorrectives for a blend
// shape's weights or a joint's channel, kPoses for anything else.
DrivenData driven_data_of(const graph::Graph& graph, const graph::Plug& driven);

// Every drivenKey node of the graph whose input is connected and whose
// output feeds a channel of `kind`, grouped by driver (in creation order).
Result<DrivenPoseSet> capture_driven_poses(const graph::Graph& graph, DrivenData kind);

std::string driven_poses_to_json(const DrivenPoseSet& poses);
// kParseError naming `source` and the place (line:column, or the member:
// "drivers[0].curves[1].keys[2]") for text that is not a driven-poses file
// (or is one of another kind than `kind`).
Result<DrivenPoseSet> driven_poses_from_json(std::string_view text, const std::string& source, DrivenData kind);

struct DrivenPosesReport {
  std::size_t curves = 0, created = 0, keys = 0;
};

// Puts each curve back: the channel's drivenKey (the one feeding it, else
// a new one named as the file says) takes the file's keys and settings and
// is connected from the file's driver. One undo step; on failure nothing
// changes. kInvalidArgument naming the plug for a driver or channel the
// scene lacks, or a channel fed by something other than a drivenKey.
Result<DrivenPosesReport> apply_driven_poses(graph::Graph& graph, const DrivenPoseSet& poses);

// Keys a pose (Maya's "Key" in the Set Driven Key window): at driver value
// `at` (default: the driver's value now) each driven channel takes its
// given value (default: its value now). A channel without a driven key gets
// a drivenKey node connected from the driver; one already driven by this
// driver gets the key added, or replaced at the same driver value (within
// 1e-9). New keys take `tangent`. One undo step.
struct DrivenKeyRequest {
  std::string driver;
  std::optional<double> at;
  std::vector<std::pair<std::string, std::optional<double>>> driven;
  ops::anim::TangentType tangent = ops::anim::TangentType::kAuto;
};
struct DrivenKeyReport {
  double at = 0.0;
  std::vector<std::string> curves;  // the drivenKey node of each driven channel, in order
  std::size_t created = 0;          // of which made by this call
};
// kInvalidArgument naming the plug: a driver or channel that does not
// exist or is not a double (or a double3's component), a channel fed by
// something other than a drivenKey of this driver, a value not finite, a
// channel named twice, no channel.
Result<DrivenKeyReport> set_driven_key(graph::Graph& graph, const DrivenKeyRequest& request);

// A pose reader on `joint` (ops/util poseReader, named "<joint>_poseReader"):
// its local matrix connected, its rest the local matrix now, `axis` the
// axis whose swing `angle` measures. Its `angle` and `rotateX/Y/Z` are
// drivers for correctives ("forearm.L_poseReader.angle"). kInvalidArgument
// naming "joint" for a node that is not a transform, "axis" for a zero or
// non-finite axis. One undo step.
Result<graph::NodeId> create_pose_reader(graph::Graph& graph, graph::NodeId joint, const math::Vec3& axis);

// Removes the drivenKey feeding each named channel (the channel keeps the
// value it had). kInvalidArgument naming a channel no drivenKey feeds.
// One undo step.
Status remove_driven_keys(graph::Graph& graph, const std::vector<std::string>& driven);

}  // namespace rigel::tools
