#pragma once
// The ephemeral session: seed 000's master node. It holds the mode, the
// grabbed controls (the graph's selection) and, while the animator drags,
// the plan: which controls move and how (drivers chosen, chains and their
// anchors). The plan is built on the first drag after a change of selection
// or mode by walking relations from the grabbed controls (seed 000's
// walkNodes, with seed 001's isNotDrivenByNode and chooseDriver), reused for
// every drag until the selection, the mode or the time changes, an undo or
// any edit the session did not make happens; then it is dropped. It lives in
// memory only: no temporary node, connection or attribute ever enters the
// scene, so after a release the scene is exactly what the drags wrote.
//
// A drag solves the plan and writes control channels (translate and
// rotate/rotateQuaternion) as one undo step. Semantics per mode, including
// several grabbed controls at once, are in docs/EPHEMERAL.md.

#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/math/types.h"
#include "rigel/scene/scene.h"

namespace rigel::ephemeral {

using math::Mat4;
using math::Quat;
using math::Vec3;

enum class Mode : std::uint8_t {
  kForward = 0,         // FK: grabbed controls move, what they drive follows rigidly
  kSuspended,           // only the grabbed controls (and their pair groups) move
  kPseudoInverse,       // seed 000 §5.7: the delta spread along the chain, controls re-aim
  kPseudoInverseLength, // the same, then bone lengths restored from the anchor out
  kInverse,             // true IK to the anchor: two-bone (3 controls, bend plane kept), FABRIK beyond
  kMagnet,              // each hop gets `magnet_fraction` of its driver's motion, up and down
  kMagnetRadius,        // every control within `magnet_radius` gets a falloff share
  kBody,                // the whole character about the body pivot (rotate, translate, scale)
};
inline constexpr int kModeCount = 8;
// "forward", "suspended", "pseudo-inverse", "pseudo-inverse-length",
// "inverse", "magnet", "magnet-radius", "body".
const char* mode_name(Mode mode);
std::optional<Mode> mode_from_name(std::string_view name);

struct SessionOptions {
  // Magnet: the share of its driver's motion a control receives per hop.
  double magnet_fraction = 0.65;
  // Magnet: controls whose share would fall below this are left out.
  double magnet_min_weight = 0.01;
  // Magnet radius: world distance (at plan time) within which controls move;
  // the share falls smoothly from 1 at the grabbed control to 0 at the radius.
  double magnet_radius = 1.0;
  // Inverse chains: the most controls in a chain (grabbed and top
  // included); 0: up to the first branching control or a root.
  int max_chain = 0;
  // Keys (keying.h): a drag on a keyed control at a time with no key keys
  // its keying group there first (true), or is refused (false). On a key,
  // the key takes the new pose either way.
  bool auto_key = false;
  // FABRIK (chains of 4 or more).
  int fabrik_iterations = 64;
  double fabrik_tolerance = 1e-10;

  // The one check of the ranges above, run by every driver before a session
  // takes the options: kInvalidArgument naming the option (its API name,
  // Status::field(): "magnetFraction", "magnetMinWeight", "magnetRadius",
  // "maxChain", "fabrikIterations", "fabrikTolerance").
  Status validate() const;
  // The most controls a chain may be limited to (max_chain).
  static constexpr int kMaxChainLimit = 1000;
};

// A rigid motion in world space. Rotation turns about each grabbed control's
// own pivot (its world position), or about the body pivot in body mode.
struct Delta {
  Vec3 translate = Vec3::Zero();
  Quat rotate = Quat::Identity();
  // Body mode only: scale about the body pivot, in its axes. Controls are
  // repositioned, never scaled (seed 001's concatenation).
  Vec3 scale = Vec3::Ones();
};

// How a control of the plan gets its new world matrix.
enum class Role : std::uint8_t {
  kGrabbed,    // applies the delta (after being carried by `driver`, if any)
  kChain,      // solved by an inverse or pseudo-inverse chain
  kFollow,     // carried rigidly by `driver` (free when driver is its hierarchy parent)
  kMagnet,     // gets `weight` of `driver`'s motion
  kBody,       // carried by the body pivot
  kKeepWorld,  // its hierarchy parent moves, it must not: its channels compensate
};
const char* role_name(Role role);

struct PlanEntry {
  NodeId control;
  Role role = Role::kFollow;
  int driver = -1;    // plan entry index, -1: none
  double weight = 1;  // magnet share
  int chain = -1;     // index into Plan::chains (kChain and the chain's grabbed end)
};

struct PlanChain {
  std::vector<int> entries;  // top (position fixed unless carried) ... grabbed end
  int anchor = -1;           // plan entry the top hangs from (moves it), -1: fixed
  NodeId anchor_control;     // the control the walk stopped at (invalid: a root)
  // The top is the anchor itself: a grabbed control above, solved by its own
  // chain first; this chain starts where that one put it and turns it (its
  // position stays) to aim at the rest of this chain.
  bool shared_top = false;
};

// The temporary graph: in memory only.
struct Plan {
  Mode mode = Mode::kForward;
  std::vector<NodeId> grabbed;      // hierarchy order
  std::vector<PlanEntry> entries;   // grabbed first, then in discovery order
  std::vector<PlanChain> chains;
  std::vector<int> order;           // solve order over entries (drivers and anchors first)
  // nullptr when `control` is not in the plan (it does not move).
  const PlanEntry* entry_find(NodeId control) const;
};

class Session : public graph::Observer {
 public:
  explicit Session(scene::Scene& scene, SessionOptions options = {});
  ~Session() override;
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  Mode mode() const { return mode_; }
  // Switching mode drops the plan.
  void set_mode(Mode mode);
  const SessionOptions& options() const { return options_; }
  // Drops the plan.
  void set_options(const SessionOptions& options);

  // Selects controls (graph selection; drops the plan). Selected joints
  // stand for their controls.
  void select(std::vector<NodeId> controls);
  // The controls of ephemeral rigs in the selection, hierarchy order.
  std::vector<NodeId> grabbed();

  // Body mode's pivot, world space (rigid). Unset: the first grabbed
  // control's world position and orientation, taken when the plan is built.
  void set_body_pivot(const Mat4& world);
  void clear_body_pivot();
  std::optional<Mat4> body_pivot() const { return body_pivot_; }

  // Builds the plan if there is none (the first change to a grabbed control
  // does this too) and returns it. Fails when nothing is grabbed, or the
  // relations form a dependency the plan cannot order.
  Result<const Plan*> plan();
  bool has_plan() const { return plan_ != nullptr; }
  // Drops the plan (release). Nothing in the scene changes.
  void release();
  // How many plans were built (tests check reuse).
  int plans_built() const { return plans_built_; }

  // Moves the grabbed controls by `delta` and writes the result. All drags of
  // one plan (grab to release: one gesture) are one undo step ("ephemeral
  // drag (MODE)"): undo returns to the pose before the grab. A zero motion writes nothing. Fails (writing
  // nothing) when nothing is grabbed, a channel to write is driven by a
  // connection (keyed), or delta.scale is not 1 outside body mode.
  Status drag(const Delta& delta);
  // Moves so that `control` (grabbed) reaches `world` (rotation and
  // translation; its scale is kept): the delta that takes it there is
  // applied to every grabbed control.
  Status drag_to(NodeId control, const Mat4& world);
  // What the last drag could not do, one sentence each, naming the controls:
  // an inverse chain that cannot reach its target (out of reach, no length
  // to turn), a control that keeps its position because moving it would
  // stretch its bone. Empty when every grabbed control reached its target.
  const std::vector<std::string>& notes() const { return notes_; }

  // graph::Observer: any edit the session did not make drops the plan.
  void node_added(const Graph&, NodeId) override { external_change(true); }
  void node_removed(const Graph&, NodeId) override { external_change(true); }
  void node_renamed(const Graph&, NodeId, const std::string&) override {}
  void attribute_changed(const Graph&, const graph::Plug& plug) override;
  void connection_made(const Graph&, const graph::Connection&) override { external_change(true); }
  void connection_broken(const Graph&, const graph::Connection&) override { external_change(true); }
  void selection_changed(const Graph&) override { external_change(false); }
  void time_changed(const Graph&) override { external_change(false); }

 private:
  struct Index;
  struct Scratch;
  void external_change(bool topology);
  Status index_ensure();
  Result<std::unique_ptr<Plan>> plan_build();
  Status solve(const Delta& delta);

  scene::Scene& scene_;
  SessionOptions options_;
  Mode mode_ = Mode::kForward;
  std::optional<Mat4> body_pivot_;
  std::optional<Mat4> plan_body_pivot_;  // the pivot the current plan uses
  std::unique_ptr<Index> index_;
  std::unique_ptr<Plan> plan_;
  std::unique_ptr<Scratch> scratch_;
  bool writing_ = false;
  int plans_built_ = 0;
  std::vector<std::string> notes_;
  std::uint64_t gesture_ = 0;  // undo merge key of the current plan's drags
};

}  // namespace rigel::ephemeral
