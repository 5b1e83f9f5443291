#pragma once
// Component classes for limbs (Luna's FKIK, IK and Twist components, seed
// 004 §4.8): ikChain, limb and twist, and the limb's FK/IK matching.
//
// Every chain these classes drive goes through one fkIkSwitch node
// (ops/util/blend.h, role "fkIkSwitch", holding the keyable `fkIk`): it
// turns the FK controls' and the IK solver's world poses into the joints'
// channels (translate, rotateQuaternion, scale, shear; the joints go to
// quaternion mode) under the joints' real parents, so the joints follow
// the attach point in both modes. The IK solver (role "ikSolver") solves in
// the space of an "ikSpace" group that hangs from the attach point at the
// root joint's parent (its parentMatrix), so it never reads the joints.
// Hooks are "hook" transforms under the rig's noTransform group that follow
// the blended joints (offsetParentMatrix <- the switch's outWorldMatrices).
//
//   ikChain  controls: ik (at the last joint; it also sets the last joint's
//            orientation), pole (two-bone only: the other solvers have no pole
//            input). solver auto = twoBone for 3 joints, fabrik otherwise.
//            stretch (two-bone, feature "stretch"; no limit).
//   limb     controls: fk0..fk2, ik and pole (feature "ik"), switch (a
//            control standing for the switch; the value is the fkIkSwitch
//            node's fkIk). defaultMode sets fkIk (fk 0, ik 1); stretch and
//            maxStretch under feature "stretch". FK/IK matching below.
//   twist    `count` joints (role "twistJoint") under the start joint, at
//            (i + 1) / (count + 1) of the way to the end joint, each turned
//            about `axis` by that share of the end's twist since rest
//            (a twistShare node, ops/util/twist.h, role "twistShare").
#include <vector>

#include "rigel/base/status.h"
#include "rigel/graph/graph.h"
#include "rigel/math/types.h"
#include "rigel/scene/scene.h"

namespace rigel::rig {
class ComponentFactory;
}

namespace rigel::rig::components {

// ikChain, limb, quadLeg, springChain, twist.
Status add_limb_components(ComponentFactory& factory);

// FK/IK matching of a built limb (src/rig/components/limb_match.cc;
// `limb_meta`: its metaComponent; the nodes are found through the metadata
// network by role, never by name), the reverse foot of a child foot
// component included.
//
// plan_fk_ik_match says, at the graph's time, what the side being set must
// take so that its pose equals the other side's; match_fk_to_ik and
// match_ik_to_fk apply a plan (one undo step each, controls only; fkIk stays
// as it is); tools/match.h keys plans over frames.
//
// Setting FK (to equal IK): fk0..fk2 (translate, rotate, scale, shear) take
// the IK pose the solver gives now (stretch and the foot's roll included),
// and a foot's toeFk the ball joint's IK pose. Exact.
// Setting IK (to equal FK): the ik control goes where the IK end (the ik
// control's end group, or the reverse foot's ankle, whatever its roll, bank
// and twists) lands on the FK end joint's pose; the pole where the two-bone
// solver turns the chain's hinge onto the FK pose's (pole mode and twist
// included), on the middle joint's side at its current distance from the
// middle joint; a foot's toeTap turns the toes onto toeFk's. Exact when
// the FK pose is one the IK side can reach: the middle joint turned about
// the solver's midAxis only, bone lengths as at rest or within the stretch,
// toeFk turned about the foot's roll axis (the toes' hinge). A straight FK
// pose leaves the pole where it is.

enum class MatchSide { kFk, kIk };  // the side that is set

struct MatchControl {
  graph::NodeId control;
  math::Mat4 world;  // what its worldMatrix must be
};
struct MatchValue {
  graph::Plug plug;  // a scalar input (a foot's toeTap)
  double value = 0;
};
struct FkIkMatch {
  std::vector<MatchControl> controls;  // parents before children
  std::vector<MatchValue> values;
  graph::Plug fk_ik;  // the switch (the limb's fkIkSwitch.fkIk): 0 is FK, 1 IK
  // The deform joints the switch drives (the limb's three, a foot's ball
  // joint) and the world matrix each has on the side matched to, now.
  std::vector<graph::NodeId> joints;
  std::vector<math::Mat4> joint_worlds;
};

// kInvalidArgument naming the component when it is not a limb with both
// sides (an FK/IK switch, FK controls and an IK solver); kNotFound naming the
// role a damaged rig lacks.
Result<FkIkMatch> plan_fk_ik_match(scene::Scene& scene, graph::NodeId limb_meta, MatchSide set);
// The world matrices the joints of `plan` have on `side` now (what the
// switch blends from; fkIk plays no part).
std::vector<math::Mat4> fk_ik_side_worlds(scene::Scene& scene, graph::NodeId limb_meta, MatchSide side);

Status match_fk_to_ik(scene::Scene& scene, graph::NodeId limb_meta);
Status match_ik_to_fk(scene::Scene& scene, graph::NodeId limb_meta);

}  // namespace rigel::rig::components
