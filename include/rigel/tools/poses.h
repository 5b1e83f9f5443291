#pragma once
// The pose library (issue 16): named poses of a built character, or of a
// selection of its controls, kept as files in a folder and applied to any
// character built from the same definition.
//
// A pose holds one entry per node: the component's rigId (metaComponent),
// the node's role and index in it (tags rig.role / rig.index, what
// rig::get_meta_connection resolves) and the values of its keyable
// channels (tools::channels_of: free or keyed ones): a transform's
// translate and scale, its local rotation as a quaternion (through its
// rotate order, so it applies whatever rotate order or mode the target
// has), and scalars such as a limb's fkIk or a foot's roll. Entries are
// resolved on the target by rigId, role and index, never by names, so a
// pose applies to another character built from the same definition and
// survives renames of components and nodes and rebuilds. The rig's name
// and each component's name, side and type are kept for people (diffs and
// messages) only.
//
// Files: LIBRARY/NAME.pose.json, diffable JSON (io/diffable_json.h: one
// member per line, entries in the rig's component and member order),
// written atomically. A name is 1-128 of [A-Za-z0-9_.-], not starting with
// '.', so nothing outside the library is ever read or written; pose files
// that are symbolic links are not read.

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/graph/graph.h"
#include "rigel/scene/scene.h"
#include "rigel/tools/mirror.h"

namespace rigel::tools {

inline constexpr const char* kPoseExtension = ".pose.json";
// A pose's thumbnail beside its file: NAME.pose.svg.
inline constexpr const char* kPoseThumbnailExtension = ".pose.svg";

// One channel's value: math::Vec3 (translate, scale, any other double3),
// math::Quat ("rotation": the local rotation, whatever the node's rotate
// mode) or double (a scalar).
struct PoseChannel {
  std::string attr;  // "translate", "rotation", "scale", or the attribute's name ("fkIk")
  graph::Value value;
};

struct PoseEntry {
  std::string rig_id;  // the component's rigId: what resolves it
  std::string role;    // the node's rig.role (or rig.step) in the component
  int index = 0;       // its index among the component's nodes of that role
  // For people only: the component's name, side and type, the node's name.
  std::string component, side, type, node;
  std::vector<PoseChannel> channels;
};

struct Pose {
  std::string name;
  std::string rig;  // the rig's name (its definition's) when saved
  std::vector<PoseEntry> entries;
};

// The pose of `nodes`, which belong to one built rig: controls and the
// other keyable nodes a component built (a fkIkSwitch), components (their
// metaComponent: every control and every node with bind values, as a bind
// pose resets) or the rig (its metaRoot: the whole character). An
// ephemeral component's controls (posed through their session) are left
// out. kInvalidArgument naming "controls" for a node of no built rig's
// component, nodes of two rigs, or nothing with a keyable channel.
Result<Pose> capture_pose(graph::Graph& graph, const std::vector<graph::NodeId>& nodes, const std::string& name);

// The file's text, and back (`source` names the file in messages: errors
// name the place, "poses/wave.pose.json:3:7: ..." for syntax and
// "poses/wave.pose.json: entries[2].channels.rotation: ..." for content;
// kParseError).
std::string pose_to_json(const Pose& pose);
Result<Pose> pose_from_json(std::string_view text, const std::string& source);

// kInvalidArgument naming "name" unless `name` is a safe pose name.
Status check_pose_name(const std::string& name);
// LIBRARY/NAME.pose.json, the name checked.
Result<std::filesystem::path> pose_path(const std::filesystem::path& library, const std::string& name);

struct SavedPose {
  std::filesystem::path path;
  std::size_t entries = 0;
};
// Captures and writes a pose (the folder made as needed; a pose of that
// name is replaced). kIoError when the file cannot be written.
Result<SavedPose> save_pose(graph::Graph& graph, const std::vector<graph::NodeId>& nodes, const std::string& name,
                            const std::filesystem::path& library);
// Reads LIBRARY/NAME.pose.json: kNotFound naming "name" when there is none.
Result<Pose> load_pose(const std::filesystem::path& library, const std::string& name);

struct PoseInfo {
  std::string name;       // the file's name without .pose.json
  std::string rig;        // the pose's rig
  std::size_t entries = 0;
  std::string error;      // why it cannot be read ("" when it can)
  bool thumbnail = false;  // NAME.pose.svg is beside it
};
// The library's poses by name (files named NAME.pose.json with a safe
// name; others are ignored). kNotFound naming "library" when the folder
// does not exist.
Result<std::vector<PoseInfo>> list_poses(const std::filesystem::path& library);
// Deletes LIBRARY/NAME.pose.json (and its thumbnail): kNotFound naming
// "name" when there is none.
Status remove_pose(const std::filesystem::path& library, const std::string& name);

// The pose library's thumbnails: a front view (looking down -Z, +Y up) of
// the scene's skeletons as evaluated now, each joint joined to its parent
// joint by a line, fitted with a margin into a 96 x 128 SVG (its aspect
// kept, numbers to 0.1 px, so the same pose gives the same bytes). A scene
// without joints gives an empty picture.
std::string skeleton_thumbnail_svg(scene::Scene& scene);
// LIBRARY/NAME.pose.svg, the name checked.
Result<std::filesystem::path> pose_thumbnail_path(const std::filesystem::path& library, const std::string& name);
// Writes the scene's thumbnail for pose `name` (atomically, beside the
// pose); kIoError naming "library" when it cannot.
Status save_pose_thumbnail(scene::Scene& scene, const std::filesystem::path& library, const std::string& name);
// The thumbnail's SVG text: kNotFound naming "name" when there is none.
Result<std::string> load_pose_thumbnail(const std::filesystem::path& library, const std::string& name);

struct ApplyPoseOptions {
  // The target rig's nodes to set (the selection); empty: every node the
  // pose has an entry for. Each must be a node the pose (mirrored, where
  // `mirrored`) sets: kInvalidArgument naming "controls" otherwise.
  std::vector<graph::NodeId> controls;
  // Each entry onto its pair on the other side (rig::mirror_pair), a
  // control's channels through K^-1 C K as tools::mirror does, scalars as
  // they are; a centre component's controls mirror in place. Entries whose
  // component has no pair are left (listed).
  bool mirrored = false;
  MirrorPlane plane = MirrorPlane::kYZ;
  // 0..1: from the current pose to the pose (1): translate, scale and
  // scalars by lerp, rotations by slerp. 0 writes nothing (the entries are
  // still resolved, so a pose that does not fit is refused all the same).
  double fraction = 1;
  // Key the channels at the graph's time; without, free channels are set
  // and keyed ones (a curve drives them, so a set value would not hold)
  // keyed all the same.
  bool key = false;
};

struct ApplyPoseReport {
  std::vector<graph::NodeId> set;  // the nodes whose channels it wrote
  std::size_t channels = 0;
  std::size_t keyed = 0;                 // of those, how many got a key
  std::vector<std::string> unpaired;    // mirrored: entries left ("arm_L fk 0"), their component having no pair
  std::vector<std::string> skipped;     // channels driven by something else on the target ("hero_foot_L.fkIk")
};

// Applies `pose` to the built rig `rig` (its metaRoot). kInvalidArgument
// naming "rig" when an entry does not resolve (no component with its
// rigId, no node of its role and index, no such channel: the message names
// the rigId, the component, the role and index), "controls" (above) or
// "fraction" (not within 0..1); kFailedPrecondition for a control without a
// recorded rest when mirrored. One undo step; on failure nothing changes.
Result<ApplyPoseReport> apply_pose(graph::Graph& graph, const Pose& pose, graph::NodeId rig,
                                   const ApplyPoseOptions& options);

}  // namespace rigel::tools
