#pragma once
// What the posing modes share with the session (private to src/ephemeral):
// the index of every rig's controls, the plan's working arrays, and the two
// contexts each mode works in. A mode is one planner (from the grabbed
// controls, the plan's entries and chains: modes/<mode>.cc) and one solver
// (per drag, the new world matrix of every entry that moves). The session
// (session.cc) owns the selection, the plan's life and the writes; Planner
// and Drag carry what a mode reads and fills.
//
// Solving is in world space; the session turns the new world matrices into
// channels through scene::Scene::channels_for_world (write.cc).

#include <cstdint>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "rigel/ephemeral/session.h"
#include "rigel/math/transform.h"
#include "rigel/scene/transform_types.h"

namespace rigel::ephemeral::modes {

using math::Mat3;
namespace xform = scene::xform;

inline Vec3 pos(const Mat4& m) { return m.topRightCorner<3, 1>(); }
inline Mat3 lin(const Mat4& m) { return m.topLeftCorner<3, 3>(); }
inline Mat4 make(const Mat3& linear, const Vec3& translation) {
  Mat4 out = Mat4::Identity();
  out.topLeftCorner<3, 3>() = linear;
  out.topRightCorner<3, 1>() = translation;
  return out;
}
inline const Mat4& eval_mat(Graph& graph, NodeId id, graph::AttrIndex attr) {
  return std::get<Mat4>(graph.evaluate(id, attr));
}

// The controls of every rig, their hierarchy and relations (index.cc).
// Rebuilt when the scene's topology or a rig changes.
struct Index {
  struct Edge {
    int to;
    RelationKind kind;
  };
  struct Ctrl {
    NodeId id;
    int parent = -1;  // hierarchy parent, when it is an indexed control or a joint one drives
    // The hierarchy parent is a joint that `parent` drives (a character
    // rigged under another one's joint): it moves rigidly with `parent`.
    bool parent_via_joint = false;
    std::vector<int> children;
    std::vector<Edge> out;
    int order = 0;  // position in Scene::hierarchy()
    int rig = 0;
    int forward_out = 0;
  };
  std::vector<Ctrl> ctrls;
  std::unordered_map<std::uint32_t, int> by_index;  // NodeId.index -> ctrl (controls and the joints they drive)
  std::vector<std::vector<int>> rig_members;
  std::vector<std::vector<int>> rig_group;  // rig -> the rigs merged with it (itself included)

  // The control `id` is, or the control driving joint `id`; -1: none.
  int find(const Graph& graph, NodeId id) const;
};

// Fills `index` from the scene's rigs. Fails when a rig's relations do not
// read.
Status index_build(scene::Scene& scene, Index& index);

// The plan's working arrays (filled by the planner and plan_finish) and
// each drag's (kept to reuse their memory).
struct Scratch {
  std::vector<int> ctrl;           // entry -> index control
  std::vector<int> entry_of;       // index control -> entry (-1)
  std::vector<int> units;          // solve order: >= 0 entry, < 0 chain -(c + 1)
  std::vector<std::uint8_t> free;  // follower of its hierarchy parent: never written
  std::vector<Mat4> w, wn;
  std::vector<std::uint8_t> has_w, has_wn, has_motion;
  std::vector<Mat4> last;  // world matrices the last drag of this plan wrote
  std::vector<std::uint8_t> has_last;
  std::uint64_t last_gesture = 0;
  std::vector<Quat> motion;  // magnet: each driver's rotation this drag
  std::vector<Mat4> chain_world;
  std::vector<Vec3> positions, solved;
  std::vector<double> lengths;
  std::vector<Quat> corrections;
  std::vector<Mat3> turns;
  struct Write {
    int entry;
    Vec3 translate;
    graph::AttrIndex rotation_attr;  // xform::kRotate (degrees) or kRotateQuaternion
    graph::Value rotation;
    bool set_t, set_r;
  };
  std::vector<Write> writes;
};

// ---- planning -----------------------------------------------------------------

// What a mode's planner reads and fills: the grabbed controls are in
// plan.grabbed (hierarchy order) and `grabbed` (their index controls); the
// planner adds entries (grabbed first) and chains. plan_finish() then adds
// what every mode needs (see there).
struct Planner {
  Graph& graph;
  const Index& ix;
  const SessionOptions& options;
  Plan& plan;
  Scratch& sc;
  std::vector<int> grabbed;
  // Body mode: the pivot the session was given (unset: the first grabbed
  // control's), and the one the plan uses.
  const std::optional<Mat4>& body_pivot;
  std::optional<Mat4>& plan_body_pivot;

  // Adds index control k as an entry; returns the entry.
  int add(int k, Role role, int driver);
  // isNotDrivenByNode (seed 001): `candidate` may drive `entry` only if
  // `entry` is not already upstream of it.
  bool is_not_driven_by(int candidate, int entry) const;
  // walkNodes (seed 000): breadth first from `queue` over forward (when
  // `forward`) and pair (when `pair`) relations, adding followers. With
  // `adopt_grabbed`, reaching a grabbed control without a driver makes the
  // walker its driver (forward mode: a grabbed control under another one
  // is carried by it, then applies its own motion).
  void walk_followers(std::vector<int> queue, bool forward, bool pair, bool adopt_grabbed);
  // The rigs of the grabbed controls and the rigs merged with them.
  std::vector<int> grabbed_rigs() const;
};

// One planner per mode.
void plan_forward(Planner& p);
void plan_suspended(Planner& p);
void plan_pseudo_inverse(Planner& p);
void plan_pseudo_inverse_length(Planner& p);
void plan_inverse(Planner& p);
void plan_magnet(Planner& p);
void plan_magnet_radius(Planner& p);
void plan_body(Planner& p);
// What the chain modes (inverse, pseudo-inverse) share: a chain per
// grabbed control up its inverse relations, then what the chains carry.
void plan_chains(Planner& p);

// After the mode's planner: hierarchy children of moving controls that the
// plan leaves out keep their world (kKeepWorld); followers of their
// hierarchy parent are marked free; the solve order; the drag scratch
// sized. Fails when the relations form a loop the order cannot break.
Status plan_finish(Planner& p);

// ---- solving ------------------------------------------------------------------

// One drag of a plan: the world matrices before (`world`) and after
// (`new_world`) for every entry, computed on demand (drag.cc). A mode's
// solver sets the new world of what it moves, unit by unit in sc.units.
class Drag {
 public:
  Drag(Graph& graph, const Index& ix, Scratch& sc, const Plan& plan, const SessionOptions& options,
       const Delta& delta, std::vector<std::string>& notes);

  Graph& graph;
  const Index& ix;
  Scratch& sc;
  const Plan& plan;
  const SessionOptions& options;
  const Delta& delta;
  const Quat rot;    // delta.rotate, normalised
  const Mat3 rot_m;  // its matrix

  // Body mode (set by its solver): every control's motion about the pivot,
  // the pivot's new world, and whether the motion is rigid (no scale: the
  // hierarchy carries everything below the roots).
  Mat4 pivot_motion = Mat4::Identity();
  Mat4 pivot_new = Mat4::Identity();
  bool body_rigid = false;

  // Entry e's world matrix before this drag.
  const Mat4& world(int e);
  // Entry e's world matrix after it: what the solver set, else composed
  // through the hierarchy from its parent's new world (body entries: moved
  // about the pivot).
  const Mat4& new_world(int e);
  // The new world of entry e's hierarchy parent (a parent outside the plan
  // stays).
  Mat4 parent_new_world(int e);
  void set_new(int e, const Mat4& m);
  // Temporary parenting (seed 001): `w` carried by `driver`'s motion this
  // drag, concatenated without scale or shear.
  Mat4 carry(int driver, const Mat4& w);
  // `base` turned by the drag's rotation about its own position, and
  // translated by the drag's translation when `translate`.
  Mat4 apply(const Mat4& base, bool translate) const;
  // Body mode: entry e turned by the pivot's rotation (its own linear part
  // kept, so its local rotation does not change), its position moved by the
  // pivot's motion.
  Mat4 body_world(int e);
  // The roles every mode may have: grabbed (the motion, carried by its
  // driver when it has one), follow (carried by its driver; free ones are
  // left to the hierarchy) and keep-world.
  void move(int e);

  std::string node_name(NodeId id) const;
  std::string entry_name(int e) const { return node_name(plan.entries[e].control); }
  void note(std::string text) { notes_.push_back(std::move(text)); }

 private:
  std::vector<std::string>& notes_;
};

// One solver per mode.
Status solve_forward(Drag& d);
Status solve_suspended(Drag& d);
Status solve_pseudo_inverse(Drag& d);
Status solve_pseudo_inverse_length(Drag& d);
Status solve_inverse(Drag& d);
Status solve_magnet(Drag& d);
Status solve_magnet_radius(Drag& d);
// `pivot`: the plan's body pivot (rigid, world).
Status solve_body(Drag& d, const Mat4& pivot);

// What the chain modes share (chains.cc). A chain's solve: its controls'
// current world, carried by what carries its top (chain_world), and the
// target of its grabbed end. A chain of one control is solved here.
struct ChainStart {
  int m = 0;           // controls in the chain
  Mat4 target;         // the grabbed end's target world
  bool done = false;   // a one-control chain: solved
};
ChainStart chain_start(Drag& d, const PlanChain& chain, bool keeps_lengths);
// Sets the chain's new worlds from sc.solved and sc.turns: every control but
// the end re-aimed at its child (turn * its world), the end at its target's
// rotation.
void chain_finish(Drag& d, const PlanChain& chain, const ChainStart& start);
// Solves the plan's units: chains with `solve_chain`, entries with
// Drag::move().
template <typename SolveChain>
Status solve_units(Drag& d, SolveChain&& solve_chain) {
  for (int unit : d.sc.units) {
    if (unit < 0) {
      if (Status s = solve_chain(d.plan.chains[-unit - 1]); !s) return s;
    } else {
      d.move(unit);
    }
  }
  return Status::ok();
}

// ---- writing ------------------------------------------------------------------

// The local channels of everything the drag moved (sc.writes), through the
// scene's world-to-local routine, before anything is written. `exact`:
// every written rotation reproduces its world matrix (not a projection), so
// the next drag may take the new worlds as current.
Status local_writes(scene::Scene& scene, Drag& d, bool& exact);

}  // namespace rigel::ephemeral::modes
