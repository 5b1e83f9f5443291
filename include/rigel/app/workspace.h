#pragma once
// The service layer (ARCHITECTURE.md "app"): everything a user can do to a
// held scene, once, for every driver. The CLI opens a Workspace on a file,
// runs one operation and saves; `rigel serve` holds one and turns each HTTP
// request into a call; Python wraps it. No JSON, HTTP or pybind11 here: the
// drivers translate their input into these calls and the answers into their
// output, and every rule, range check and conversion lives here or below.
//
// Errors are Status / Result with the input at fault in Status::field() (the
// API's name of it: "controls", "to.q", "magnetFraction"). The codes say
// whose fault it is: kInvalidArgument and kParseError: the input;
// kNotFound: a node, rig or file it names; kFailedPrecondition (and the
// library's other codes): the scene cannot do it in its state; kIoError:
// the system refused a read or write.
//
// A Workspace is not thread-safe: a driver serving several clients
// serialises the calls (the server holds a mutex).

#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "rigel/app/scene_files.h"
#include "rigel/base/status.h"
#include "rigel/ephemeral/session.h"
#include "rigel/graph/graph.h"
#include "rigel/math/types.h"
#include "rigel/rig/build.h"
#include "rigel/rig/component.h"
#include "rigel/rig/definition.h"
#include "rigel/rig/manager.h"
#include "rigel/scene/scene.h"
#include "rigel/scene/scene_options.h"
#include "rigel/tools/bind_pose.h"
#include "rigel/tools/blendshape_data.h"
#include "rigel/tools/curves.h"
#include "rigel/tools/driven_poses.h"
#include "rigel/tools/keys.h"
#include "rigel/tools/match.h"
#include "rigel/tools/trails.h"
#include "rigel/tools/transfer.h"
#include "rigel/tools/mirror.h"
#include "rigel/tools/spaces.h"
#include "rigel/tools/poses.h"
#include "rigel/tools/rigging.h"
#include "rigel/tools/shape_data.h"
#include "rigel/tools/skin_weights.h"
#include "rigel/tools/tween.h"

namespace rigel::rig {
struct BuildGraph;
class NodeKindRegistry;
}  // namespace rigel::rig

namespace rigel::app {

namespace fs = std::filesystem;
using graph::NodeId;
using math::Mat4;
using math::Quat;
using math::Vec3;

// The farthest the current time may move from 0, in frames.
inline constexpr double kMaxFrame = 1e6;

// A rotation given as Euler angles in degrees, x applied first about world
// axes (R = Rz * Ry * Rx): what the CLI's --rotate, the API's {"euler": ...}
// and Python's euler= mean.
Quat rotation_from_euler_degrees(const Vec3& degrees);

// A key time in seconds as a frame: a whole frame when within
// ephemeral::kKeyFrameTolerance of one (the key is that frame's key: glTF's
// float seconds put CesiumMan's frame 38 at 37.999921), else rounded to 1e-6
// frame so that frame 10 at 24 fps reads 10, not 10.000000000000002.
double key_frame(double seconds, double fps);

// `path` resolved inside `root` (what a user who named `root` allows to be
// read or written): absolute paths, paths that leave the root through ".."
// or a symbolic link, and empty paths are refused (kInvalidArgument naming
// `field`).
Result<fs::path> confined_path(const fs::path& root, const std::string& path, const std::string& field);

// Opening, importing, exporting and baking scene files: scene_files.h.

// One transform's translation, rotation and scale (a decomposed matrix).
struct Trs {
  NodeId node;
  Vec3 translate = Vec3::Zero();
  Quat rotate = Quat::Identity();
  Vec3 scale = Vec3::Ones();
  bool operator==(const Trs& o) const {
    return node == o.node && translate == o.translate && rotate.coeffs() == o.rotate.coeffs() && scale == o.scale;
  }
};
enum class Space { kLocal, kWorld };

// A node of the hierarchy and, for controls, what the viewport draws.
struct NodeEntry {
  NodeId node;
  NodeId parent;  // invalid for roots
};
struct ControlEntry {
  NodeId node;
  std::string rig;         // the ephemeral or built rig's name ("" for none)
  bool ephemeral = false;  // of an ephemeral rig (posed through the session)
  // What it is shown and hidden with: a built rig's component ("arm_L"); an
  // ephemeral control's region, the nearest control above it with three or
  // more child controls ("face_ctrl": every face control, "hand.L_ctrl": the
  // fingers), else its rig.
  std::string group;
  std::vector<Vec3> points;
  bool closed = true;
  Vec3 color{1, 1, 0};
};

// The picker (seed 002's future-work picker): the controls laid out by body
// part and side, generated from the rigs (a built rig's components: their
// type, name and side; an ephemeral rig's regions and joint names).
struct PickerGroup {
  std::string rig;
  std::string name;   // the component ("arm_L") or region ("face_ctrl", "hand.L_ctrl")
  std::string part;   // "head", "torso", "arm", "hand", "leg", "tail", "root" or "other"
  char side = 'C';    // 'L', 'R' or 'C'
  struct Entry {
    NodeId control;
    std::string label;  // a built control's role and index ("fk 1"), an ephemeral one's joint ("index.02.L")
  };
  std::vector<Entry> controls;
};

// Ghosts (onion skin) of the skeleton: every joint's world position at some
// frames, with each joint's parent (an index into joints, -1 for a root) so
// a client draws bones as lines.
struct GhostOptions {
  std::vector<double> frames;  // these frames; else:
  int before = 0, after = 0;   // this many ghosts each side of the current frame,
  double step = 1;             // this many frames apart; or
  bool at_keys = false;        // at the keys of the selection's keying group (every control's without one)
};
struct Ghosts {
  std::vector<NodeId> joints;
  std::vector<int> parents;
  std::vector<double> frames;
  std::vector<std::vector<Vec3>> points;  // [frame][joint]
};

// The scene's summary: what a client shows before anything else.
struct SceneSummary {
  double fps = 24;
  double frame = 0, time = 0;
  std::array<double, 2> range{0, 0};  // first and last keyed frame (0, 0 with no keys)
  std::optional<std::array<double, 2>> playback;  // the playback range the animator set (scene_options.h)
  ephemeral::Mode mode = ephemeral::Mode::kForward;
  bool auto_key = false;
  std::vector<std::pair<std::string, std::string>> key_scopes;  // ephemeral rig -> keying scope name
  bool can_undo = false, can_redo = false;
  std::string undo_label, redo_label;
  std::vector<NodeId> selection;
};

// The keys of some controls: their keying set's key times.
struct KeyReport {
  std::string scope;  // the ephemeral rig's keying scope, "controls" for built rigs, "" for no controls
  std::vector<NodeId> set;     // the keying set: the controls keyed together with them
  std::vector<double> times;   // seconds
  std::vector<double> frames;  // the same, as frames (key_frame)
};

// A drag's answer: the controls it dragged (an ephemeral rig's grab, or the
// built rigs' controls), what it moved (the transforms whose local values
// changed, hierarchy order; and the controls whose world matrix moved, with
// their world values) and what it could not do (a target out of reach, a
// bone that would stretch).
struct DragReport {
  std::vector<NodeId> dragged;
  std::vector<Trs> moved;
  std::vector<Trs> moved_controls;  // world space
  std::vector<std::string> notes;
};

// A rig's build position after a step.
struct StepReport {
  std::string rig;
  int position = 0, steps = 0;
  std::string step;  // the label of the last step built ("" at 0)
  std::string rig_id;  // the rigId of its component ("" at 0 or for the rig's own step)
};
// A feature of a rig's steps (seed 003), with its rig-level state.
struct FeatureState {
  std::string feature, switch_name;
  bool enabled = true;
};
struct FeatureReport {
  std::string rig;
  std::vector<FeatureState> features;
  int position = 0, steps = 0;
};
// What committing a rig's edit-mode changes did.
struct CommitReport {
  std::string rig, version;
  rig::Definition definition;  // the definition with the moved guides
  std::vector<std::string> changed, ignored;
  fs::path definition_path;  // where the definition was saved (empty when nothing changed)
  bool edit_mode = false;
};
// A rig the workspace lists: built, or stepped back to step 0 (nothing of
// it in the scene; the workspace keeps its definition).
struct RigEntry {
  std::string name;
  bool unbuilt = false;
  int steps = 0;
  std::vector<FeatureState> features;
  // For unbuilt rigs (built ones: rig::rigs_report and rig::rig_state).
  std::string version;
  std::string definition;                        // its file ("" when none)
  std::optional<std::string> definition_version;  // the file's version, when it can be read
  bool edit_mode = false;
};
// A definition parsed and checked: every problem, none when it can build.
struct CheckedDefinition {
  rig::Definition definition;
  std::vector<rig::Diagnostic> problems;
};
// A build (or live rebuild) from a definition.
struct BuildReport {
  std::string rig;
  std::vector<std::string> rebuilt;  // rig ids, build order
};
struct SavedDefinition {
  fs::path path;
  std::string version;
};
// The build graph calls' answers (app/graphs.h, so that the files that
// include this one do not depend on the build graph model).
struct CheckedGraph;
struct GraphBuildReport;
struct RigGraph;
struct SavedGraph;

class Workspace {
 public:
  // `scene`: the scene the workspace works on (shared: Python's Scene
  // objects hold it too; the CLI and the server pass theirs on).
  // `scene_path`: where save() without a path writes (may be empty).
  // `root`: the folder the paths of confined() calls are relative to and
  // confined in (empty: paths are taken as given, for the CLI and Python,
  // whose users name their files themselves). `factory`: the component
  // classes builds use (it must outlive the workspace).
  Workspace(std::shared_ptr<scene::Scene> scene, fs::path scene_path, fs::path root,
            const rig::ComponentFactory& factory, ephemeral::SessionOptions options = {});
  ~Workspace();
  Workspace(const Workspace&) = delete;
  Workspace& operator=(const Workspace&) = delete;

  scene::Scene& scene() { return *scene_; }
  const scene::Scene& scene() const { return *scene_; }
  graph::Graph& graph() { return scene_->graph(); }
  const graph::Graph& graph() const { return scene_->graph(); }
  ephemeral::Session& session() { return *session_; }
  const rig::ComponentFactory& factory() const { return factory_; }
  const fs::path& scene_path() const { return scene_path_; }
  const fs::path& root() const { return root_; }
  // The character file the scene was opened from ("" when unknown).
  const fs::path& character() const { return character_; }
  void set_character(fs::path file) { character_ = std::move(file); }

  // Counts changes: every call that changed the scene, the session or the
  // workspace's rigs increments it (clients poll it to see others' edits).
  std::uint64_t revision() const { return revision_; }
  void bump_revision() { ++revision_; }

  // `path` inside root() (confined_path), or as given when there is no root.
  Result<fs::path> resolve_path(const std::string& path, const std::string& field) const;

  // ---- nodes -----------------------------------------------------------------
  // A node by uuid or name (kNotFound naming `field`).
  Result<NodeId> node(const std::string& ref, const std::string& field) const;
  // A control: a control node, or a joint standing for its ephemeral control.
  Result<NodeId> control(const std::string& ref, const std::string& field) const;
  Result<NodeId> control_of(NodeId id, const std::string& field) const;
  // What a key on a node keys: the ephemeral control a joint stands for,
  // else the node itself (a control, or a switch such as a fkIkSwitch).
  NodeId key_target(NodeId id) const;
  Result<NodeId> key_target(const std::string& ref, const std::string& field) const;
  bool is_control(NodeId id) const;
  // Every control: the ephemeral rigs' (rig by rig, each rig's order), then
  // the others (built rigs'), hierarchy order.
  std::vector<NodeId> all_controls() const;
  NodeId parent_of(NodeId id) const;
  // The live nodes of the selection, in order.
  std::vector<NodeId> selection() const;
  std::vector<NodeEntry> nodes() const;
  std::vector<ControlEntry> controls() const;
  SceneSummary summary() const;
  // Local (offsetParentMatrix * matrix, what a glTF node holds) or world
  // values of every transform, hierarchy order.
  std::vector<Trs> pose(Space space) const;

  // ---- posing ----------------------------------------------------------------
  // Selects `controls` (or adds them to the selection).
  void select(std::vector<NodeId> controls, bool add = false);
  void set_mode(ephemeral::Mode mode);
  // Body mode's pivot: at `control` (its world matrix without scale or
  // shear), or at the world point `at` in world axes.
  void set_body_pivot(NodeId control, const std::optional<Vec3>& at = std::nullopt);
  // Checks the options (SessionOptions::validate) before the session takes them.
  Status set_options(const ephemeral::SessionOptions& options);
  // Moves the selected controls by a world delta: ephemeral rigs' through
  // the session (a grab), built rigs' directly (each about its own pivot,
  // into its channels, keys as the session does; scale refused). The
  // motion must be finite, its rotation of non-zero length (it is
  // normalised), its scale positive and other than 1 in body mode only
  // (kInvalidArgument naming "translate", "rotate" or "scale").
  Result<DragReport> drag(const ephemeral::Delta& delta);
  // Whether drags fill DragReport::moved_controls (on by default). The
  // world matrices of every control before and after are its cost; a
  // client that reads only `moved` (the server) turns it off.
  void set_report_moved_controls(bool on) { report_moved_controls_ = on; }
  // Drags `control` so that its world translation / rotation become the
  // given ones (unset: unchanged); it is selected when it is not. An
  // ephemeral control moves its rig through the session, a built rig's
  // moves with the other selected built-rig controls by the same delta.
  Result<DragReport> drag_to(NodeId control, const std::optional<Vec3>& translate, const std::optional<Quat>& rotate);
  // Ends the gesture: the next drag is a new undo step.
  void release();
  // The label of what was undone / redone; kFailedPrecondition when there is nothing.
  Result<std::string> undo();
  Result<std::string> redo();
  // The current time, as a frame or in seconds (|frame| <= kMaxFrame).
  Status set_frame(double frame);
  Status set_time(double seconds);

  // ---- keys ------------------------------------------------------------------
  KeyReport keys(const std::vector<NodeId>& controls) const;
  // Keys (or deletes the keys of) the controls' keying set at the current time.
  Result<KeyReport> set_key(const std::vector<NodeId>& controls);
  Result<KeyReport> delete_key(const std::vector<NodeId>& controls);

  // ---- keys on any keyable channel (tools/keys.h) ----------------------------
  // The channels a key on `controls` (any nodes: built rigs' controls and
  // switches, ephemeral controls, joints standing for theirs) writes: with
  // `attrs`, those channels of the nodes given; without, every keyable
  // channel of their keying group (tools::keying_group: a built character
  // or an ephemeral rig's keying set). Errors name "controls" or "attrs".
  Result<std::vector<tools::Channel>> key_channels(const std::vector<NodeId>& controls,
                                                   const std::vector<std::string>& attrs) const;
  // Keys those channels at the current time with their values (or `value`,
  // scalar channels only: kInvalidArgument naming "value"), or deletes their
  // keys there (kNotFound when none has one); one undo step. The answer:
  // the keys of those channels afterwards.
  // `tangents`: the keys' tangent types (tools::set_keys; "tangent" names a
  // channel keyed by a track).
  Result<std::vector<tools::PlugKeys>> set_channel_keys(const std::vector<NodeId>& controls,
                                                        const std::vector<std::string>& attrs,
                                                        const std::optional<double>& value = std::nullopt,
                                                        const tools::Tangents& tangents = {});
  Result<std::vector<tools::PlugKeys>> delete_channel_keys(const std::vector<NodeId>& controls,
                                                           const std::vector<std::string>& attrs);
  // Tween / breakdown (tools::tween) of the channels set_channel_keys would
  // key, at the current time, by `fraction` (0: the previous key, 1: the
  // next); keyed when `key`. Errors name "controls", "attrs" or "fraction".
  // The answer: the blended channels' keys afterwards.
  Result<std::vector<tools::PlugKeys>> tween(const std::vector<NodeId>& controls, const std::vector<std::string>& attrs,
                                             double fraction, bool key = true);
  // The keys of the nodes' own channels: those named in `attrs`, or every
  // keyable one (no keying group: what `rigel keys` lists for a control).
  Result<std::vector<tools::PlugKeys>> channel_keys(const std::vector<NodeId>& controls,
                                                    const std::vector<std::string>& attrs) const;

  // ---- animator tools (tools/match.h, ...; src/app/animate.cc) -------------
  // The first and last keyed frame of every time curve in the scene (its
  // active clip), none when nothing is keyed: the clip the tools' frames
  // must lie in.
  std::optional<std::array<double, 2>> keyed_frames() const;
  // FK/IK match and bake of a rig's limb (tools::match): `rig` a built rig's
  // name, `component` its component's name or rigId. Errors name "rig",
  // "component" (not found, or no FK/IK switch) or "frames" (not finite,
  // reversed, beyond kMaxFrame, or outside keyed_frames() when the scene
  // has keys). One undo step.
  Result<tools::MatchReport> match(const std::string& rig, const std::string& component,
                                   const tools::MatchOptions& options);
  // Mirror or flip a built rig's pose (tools::mirror) of options.controls
  // (or, with options.all, their rigs'), at the current frame or over a
  // range. Errors name "controls" (not a built rig's control, no pair,
  // nothing to mirror) or "frames" (as match). One undo step.
  Result<tools::MirrorReport> mirror(const tools::MirrorOptions& options);
  // Controls, components (`hero:arm_L`) or rigs (`hero:`) back to their
  // bind pose at the current time (tools::reset_bind_pose), keyed when
  // `key`. Errors name "controls". One undo step.
  Result<tools::BindPoseReport> reset_bind_pose(const std::vector<NodeId>& nodes, bool key);

  // ---- transfer, move keys, channel values (src/app/transfer.cc) -------------
  // Transfer keys (tools::transfer_keys): `from` and `to` are "RIG:COMPONENT"
  // (component name or rigId) or "RIG:" (a whole character); `frames` the
  // source range (none: every key), `offset` in frames. Errors name "from"
  // or "to" (kNotFound for an unknown rig or component; kInvalidArgument for
  // other types, no match), "frames" or "offset". One undo step.
  Result<tools::TransferReport> transfer_keys(const std::string& from, const std::string& to,
                                              const std::optional<std::array<double, 2>>& frames, double offset = 0.0);
  // Moves the keys at frame `from_frame` (default: the current time) of the
  // channels set_channel_keys would key to frame `to_frame`, or copies them
  // there with `copy` (tools::move_keys; frames within kMaxFrame of 0, else
  // kInvalidArgument naming "moveTo" or "from"). The answer: the channels'
  // keys.
  Result<std::vector<tools::PlugKeys>> move_channel_keys(const std::vector<NodeId>& controls,
                                                         const std::vector<std::string>& attrs, double to_frame,
                                                         bool copy = false,
                                                         std::optional<double> from_frame = std::nullopt);
  // Sets scalar channels (`attrs` of the nodes; without, every scalar
  // keyable channel of theirs) at the current time (tools::set_values): a
  // keyed channel gets a key with the value, a free one is set (and keyed
  // when the session's auto_key is on). A built rig's control stands for
  // its component's node with that channel (`--control hero_arm_L_ik
  // --attr fkIk` sets the limb's switch). `values`: one, or one per
  // channel. Errors name "controls", "attrs" or "value". The answer: the
  // channels set and their keys afterwards.
  struct ChannelValues {
    std::vector<tools::Channel> channels;
    std::vector<tools::PlugKeys> keys;
  };
  Result<ChannelValues> set_channel_values(const std::vector<NodeId>& controls, const std::vector<std::string>& attrs,
                                           const std::vector<double>& values);
  // The channel box of `controls` at the current time: each one's keyable
  // channels (a vector as its components: translateX, rotateY; channels
  // driven by something other than a curve left out) and, for a built rig's
  // control, its component's own (the limb's fkIk, a foot's roll, a hand's
  // curl), each with its value now and whether it is keyed at this frame,
  // at other frames only, or not at all. Errors name "controls".
  enum class KeyState { kNone, kElsewhere, kHere };
  struct ChannelRow {
    NodeId node;           // the control, or its component's node that has the channel
    std::string attr;      // what set_channel_values takes ("translateX", "fkIk")
    std::string key_attr;  // what set_channel_keys takes ("translate", "fkIk")
    std::string plug;      // "hero_arm_L_ik.translateX"
    double value = 0;
    KeyState state = KeyState::kNone;
  };
  struct ChannelBox {
    NodeId control;
    std::vector<ChannelRow> rows;
  };
  Result<std::vector<ChannelBox>> channel_box(const std::vector<NodeId>& controls);
  // ---- graph editor (tools/curves.h; src/app/curves.cc) ---------------------
  // The curves of the channels the channel box shows for `controls` (each
  // control's keyable channels and, for a built rig's control, its
  // component's switches), sampled as `options` says, in FRAMES here, in
  // and out: first, last, step, key and sample times (samples to a
  // billionth of a frame) and slopes (per frame). Errors name "controls",
  // "first", "last" or "step".
  Result<std::vector<tools::CurveView>> curves(const std::vector<NodeId>& controls,
                                               const tools::CurveViewOptions& options = {});
  // Single-key edits on curves named by the plug they drive; times in
  // FRAMES here (key, to_time), as every frame the workspace takes. Errors
  // name "keys" (a frame beyond kMaxFrame too). One undo step each; the
  // number of keys changed. Slopes (in_slope, out_slope) are per frame.
  Result<std::size_t> edit_curve_keys(std::vector<tools::CurveKeyEdit> edits);
  Result<std::size_t> insert_curve_keys(std::vector<tools::CurveKeyRef> keys);
  Result<std::size_t> delete_curve_keys(std::vector<tools::CurveKeyRef> keys);
  // ---- motion trails and ghosts (tools/trails.h; src/app/trails.cc) -----------
  // A trail for each control (none: the selection) over frames first..last
  // every `step` frames, with its keys marked. Errors name "controls",
  // "frames" or "step". Changes nothing.
  Result<std::vector<tools::MotionTrail>> motion_trails(const std::vector<NodeId>& controls, double first, double last,
                                                        double step = 1);
  // Ghosts of the skeleton (at most 100 frames, each within kMaxFrame;
  // errors name "frames", "before", "after" or "step"). Changes nothing.
  Result<Ghosts> ghosts(const GhostOptions& options);
  // ---- picker (src/app/picker.cc) ---------------------------------------------
  // Every control in picker groups: rig by rig, parts head to toe, R C L
  // within a part, controls in hierarchy order.
  std::vector<PickerGroup> picker() const;
  // ---- scene settings (scene/scene_options.h; src/app/scene_settings.cc) ------
  // The playback range (frames) the animator set, saved with the scene;
  // none until one is set.
  std::optional<std::array<double, 2>> playback_range() const;
  // Errors name "range". One undo step.
  Status set_playback_range(double first, double last);
  // Named selection sets, saved with the scene, by name.
  std::vector<scene::SelectionSet> selection_sets() const;
  // Saves set `name` with `members` (none: the selection), replacing the
  // members of a set of that name. Errors name "name" or "members". One
  // undo step.
  Result<NodeId> save_selection_set(const std::string& name, const std::vector<NodeId>& members);
  // Errors name "name" (kNotFound). One undo step.
  Status remove_selection_set(const std::string& name);
  // Selects the members of set `name` (or adds them to the selection);
  // the selection after. kNotFound naming "name" for no such set.
  Result<std::vector<NodeId>> select_set(const std::string& name, bool add = false);
  // ---- spaces (rig/spaces.h, tools/spaces.h; src/app/spaces.cc) -------------
  // A control's spaces (none when it has no spaceSwitch).
  rig::ControlSpaces spaces(NodeId control) const;
  // Adds space `name` following `target` (invalid: the world) to a control
  // (rig::add_space); its index. Errors name "control", "space" or
  // "target". One undo step.
  Result<int> add_space(NodeId control, const std::string& name, NodeId target);
  // Switches the control to another space at a frame, or bakes a range into
  // it (tools::switch_space). Errors name "control", "space" or "frames"
  // (as match). One undo step.
  Result<tools::SpaceSwitchReport> switch_space(NodeId control, const tools::SpaceSwitchOptions& options);
  // ---- rigger actions (tools/rigging.h; src/app/rigging.cc) --------------------
  // A control's shape and colour; the same pasted onto controls; shapes
  // mirrored or flipped in place, or mirrored onto the opposite controls.
  // Errors name "controls" (and "shape" for a bad paste). One undo step each.
  Result<tools::ControlLook> control_look(NodeId control) const;
  Status paste_control_look(const std::vector<NodeId>& controls, const tools::ControlLook& look,
                            tools::LookParts parts = {});
  Status edit_control_shape(const std::vector<NodeId>& controls, tools::ShapeEdit edit);
  Result<std::vector<tools::MirroredShape>> mirror_shape_to_opposite(const std::vector<NodeId>& controls);
  // Locators (tools::create_locators) at nodes; errors name "nodes".
  Result<std::vector<NodeId>> create_locators(const std::vector<NodeId>& at, double size = 0.1);
  // Joint hierarchies mirrored (tools::mirror_joints); an ephemeral
  // control stands for its joint. Errors name "joints".
  Result<tools::MirrorJointsReport> mirror_joints(const std::vector<NodeId>& roots,
                                                  const tools::MirrorJointsOptions& options = {});
  // Matches the nodes' world position and/or rotation to `target`'s (seed
  // 004's match position / rotation): an ephemeral rig's control is moved
  // through the session in the current mode (as a drag to that place
  // would), any other transform (a built rig's control, a locator, a
  // joint) has its channels set (keyed when auto-key is on). The selection
  // is kept. Errors name "nodes" or "target"; one undo step.
  Result<std::vector<NodeId>> align(const std::vector<NodeId>& nodes, NodeId target, bool position, bool rotation);
  // ---- data managers (tools/skin_weights.h, tools/shape_data.h; src/app/data.cc)
  // Files resolved as resolve_path does (errors name "file"); written
  // atomically, their folder made. Imports are one undo step each.
  // Every skinCluster's weights to a .weights.json file (kBinary: its
  // arrays in a side file beside it, skin_weights.h).
  Result<fs::path> export_skin_weights(const std::string& file, tools::WeightsFormat format = tools::WeightsFormat::kJson);
  Result<tools::WeightsReport> import_skin_weights(const std::string& file, const tools::WeightsImport& options = {});
  // A built rig's control shapes and colours (`rig` empty: the scene's only
  // rig; errors name "rig") to a .shapes.json file, and back by rigId,
  // role and index.
  Result<fs::path> export_control_shapes(const std::string& rig, const std::string& file);
  Result<tools::ShapesReport> import_control_shapes(const std::string& rig, const std::string& file);
  // Every blendShape's targets and weights to a .blendshapes.json file, and
  // back by blendShape (else mesh) name, targets by name or index
  // (tools/blendshape_data.h).
  Result<fs::path> export_blend_shapes(const std::string& file);
  Result<tools::BlendShapesReport> import_blend_shapes(const std::string& file);
  // Driven poses or correctives (tools/driven_poses.h): every driven key of
  // that kind to a .drivenposes.json / .correctives.json file, and back.
  Result<fs::path> export_driven_poses(tools::DrivenData kind, const std::string& file);
  Result<tools::DrivenPosesReport> import_driven_poses(tools::DrivenData kind, const std::string& file);
  // The driven keys of that kind now.
  Result<tools::DrivenPoseSet> driven_poses(tools::DrivenData kind);
  // ---- set-driven keys (tools/driven_poses.h; src/app/data.cc) ---------------
  // Keys a pose: at the driver's value (or request.at) each driven channel
  // takes its value (or the given one). Errors name "driver" or "driven";
  // one undo step.
  Result<tools::DrivenKeyReport> set_driven_key(const tools::DrivenKeyRequest& request);
  // Removes the driven keys of the channels (each keeps its value now).
  Status remove_driven_keys(const std::vector<std::string>& driven);
  // A pose reader on a joint (a corrective's driver); errors name "joint"
  // or "axis"; one undo step.
  Result<NodeId> create_pose_reader(NodeId joint, const math::Vec3& axis);
  // ---- pose library (tools/poses.h; src/app/poses.cc) ------------------------
  // `library`: a folder, resolved as resolve_path does (inside root() when
  // there is one; errors name "library"); `name`: a pose name
  // (tools::check_pose_name; errors name "name").
  // Saves the pose of `controls` (built rigs' controls, components or rigs)
  // or, with none, of the whole of rig `rig` (empty: the scene's only rig)
  // as LIBRARY/NAME.pose.json, with its thumbnail (NAME.pose.svg: the
  // skeletons in the pose, tools::skeleton_thumbnail_svg). Errors name
  // "rig", "controls", "name" or "library". Changes nothing in the scene.
  Result<tools::SavedPose> save_pose(const std::string& library, const std::string& name, const std::string& rig,
                                     const std::vector<NodeId>& controls);
  // Applies a saved pose (tools::apply_pose) to rig `rig` (empty: the rig
  // of the pose's name, else the scene's only rig) at the current time.
  // Errors name "name" (no such pose, unreadable), "rig" (no such rig, or
  // the pose is of another rig: the missing rigId and role named),
  // "controls" or "fraction". One undo step.
  Result<tools::ApplyPoseReport> apply_pose(const std::string& library, const std::string& name, const std::string& rig,
                                            const tools::ApplyPoseOptions& options);
  // The library's poses by name (kNotFound naming "library" when there is
  // no such folder).
  Result<std::vector<tools::PoseInfo>> list_poses(const std::string& library) const;
  // Deletes a pose (kNotFound naming "name" when there is none).
  Status remove_pose(const std::string& library, const std::string& name);
  // A saved pose's thumbnail (the SVG save_pose writes beside it,
  // tools::skeleton_thumbnail_svg); kNotFound naming "name" without one.
  Result<std::string> pose_thumbnail(const std::string& library, const std::string& name) const;

  // ---- files -----------------------------------------------------------------
  // Saves the scene (atomically) at `path`, or at scene_path() when empty;
  // the path becomes scene_path(). Folders are made as needed.
  Result<fs::path> save(const fs::path& path = {});

  // ---- rigs ------------------------------------------------------------------
  // The rigs the workspace lists: the scene's, then those at step 0.
  std::vector<RigEntry> rigs();
  // A rig the scene holds or one at step 0 (with `unbuilt_too`); kNotFound /
  // kFailedPrecondition naming `field` otherwise.
  Status check_rig(const std::string& name, bool unbuilt_too, const std::string& field = "rig");
  Result<rig::AddedRig> add_rig(const fs::path& definition, rig::BuildOptions options = {});
  Result<rig::UpdateReport> update_rig(const std::string& name, const fs::path& definition = {}, bool force = false,
                                       rig::Build::KeepKeys keep = rig::Build::KeepKeys::kLocal);
  Status remove_rig(const std::string& name);
  // Moves the rig's build to step `to`, or `by` steps (clamped).
  Result<StepReport> step_rig(const std::string& name, std::optional<int> to, int by = 0);
  Result<FeatureReport> set_feature(const std::string& name, const std::string& feature, const std::string& switch_name,
                                    bool enabled);
  Result<bool> set_edit_mode(const std::string& name, bool on);
  // Commits the guides moved in edit mode to the definition, saved at `out`
  // (default: the rig's definition file; made absolute, the rig records it);
  // leaves edit mode unless `keep_editing`. No definition path when a guide
  // moved: kInvalidArgument naming "definitionOut".
  Result<CommitReport> commit_edits(const std::string& name, const fs::path& out = {}, bool keep_editing = false);
  // The rig's definition as built (its source path included).
  Result<rig::Definition> definition(const std::string& name);
  std::vector<std::string> component_types() const;

  // ---- definitions -----------------------------------------------------------
  // Parses (the .rig.json or .rig.xml text) and validates a definition.
  CheckedDefinition check_definition(const std::string& text, rig::Syntax syntax, const std::string& where) const;
  // Builds the definition, or live-rebuilds the components that changed when
  // the scene has its rig already. One undo step.
  Result<BuildReport> build_definition(rig::Definition definition);
  // Saves the definition at `path` (.rig.xml or .rig.json by its name); over
  // a file with other content the version moves to the next one.
  Result<SavedDefinition> save_definition(rig::Definition definition, const fs::path& path);

  // ---- build graphs (rig/build_graph.h) -----------------------------------------
  // The node kinds a graph can hold now: the component types of factory(),
  // the build functions registered now, and the graph files under root()
  // (graph_files) as sub-graph nodes, by their path from the root.
  rig::NodeKindRegistry graph_kinds() const;
  // Parses `.build.json` text (`where` names it in messages) and compiles
  // it; its graph:PATH nodes' files are beside `where` when it is a file,
  // else under root().
  CheckedGraph check_graph(const std::string& text, const std::string& where) const;
  CheckedGraph check_graph(rig::BuildGraph graph) const;
  // Compiles the graph (kInvalidArgument naming "graph" with its first
  // problem) and builds its rig, or live-rebuilds only the nodes that
  // changed, and what reads them, when the scene has it: build_definition.
  Result<GraphBuildReport> build_graph(rig::BuildGraph graph);
  // Saves the graph at `path` (a .build.json) atomically; over a file with
  // other content its version moves to the next one. A graph that does not
  // compile is saved too (work in progress), its problems reported.
  Result<SavedGraph> save_graph(rig::BuildGraph graph, const fs::path& path);
  // Reads a .build.json (kInvalidArgument naming `path` with every problem
  // of its text; kNotFound when it is missing).
  Result<rig::BuildGraph> open_graph(const fs::path& path) const;
  // The graph a rig was built from, or its definition as a graph.
  Result<RigGraph> rig_graph(const std::string& name);
  // The .build.json files under root() (relative to it, sorted; hidden
  // folders and node_modules skipped, 8 levels deep, the first 1000).
  // kFailedPrecondition when the workspace has no root.
  Result<std::vector<fs::path>> graph_files() const;

  // Drops the rigs at step 0 whose step an undo took back and that the new
  // edit just made can no longer redo. Drivers call it around each mutating
  // call (the server around every request but undo/redo).
  std::vector<std::uint64_t> unbuilt_undone() const;
  void drop_unbuilt(const std::vector<std::uint64_t>& undone);

 private:
  struct Unbuilt {
    rig::Definition definition;
    rig::BuildOptions options;
    std::size_t since = 0;     // undo_count() after the step to 0
    std::uint64_t serial = 0;  // which entry (a name may be stepped to 0 again)
  };
  const Unbuilt* unbuilt_rig(const std::string& name) const;
  Result<std::unique_ptr<rig::Build>> open_rig(const std::string& name);
  Status drag_direct(const std::vector<NodeId>& controls, const Vec3& dt, const Quat& dq);
  struct Before {
    std::vector<Trs> local;
    std::vector<std::pair<NodeId, Mat4>> controls;  // world
  };
  Before before_drag() const;
  DragReport drag_report(const Before& before, std::vector<NodeId> dragged, bool session_dragged) const;
  static std::vector<FeatureState> features_of(const rig::Build& build);

  std::shared_ptr<scene::Scene> scene_;
  std::unique_ptr<ephemeral::Session> session_;
  fs::path scene_path_;
  fs::path root_;
  fs::path character_;
  const rig::ComponentFactory& factory_;
  std::uint64_t revision_ = 1;
  bool report_moved_controls_ = true;
  std::uint64_t gesture_ = 0;  // undo merge key of the current direct (non-ephemeral) drag
  std::map<std::string, Unbuilt> unbuilt_;
  std::uint64_t unbuilt_serial_ = 0;
};

}  // namespace rigel::app
