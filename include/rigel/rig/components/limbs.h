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
//            maxStretch under feature "stretch".
//   twist    `count` joints (role "twistJoint") under the start joint, at
//            (i + 1) / (count + 1) of the way to the end joint, each turned
//            about `axis` by that share of the end's twist since rest
//            (a twistShare node, ops/util/twist.h, role "twistShare").
#include "rigel/base/status.h"
#include "rigel/graph/graph.h"
#include "rigel/scene/scene.h"

namespace rigel::rig {
class ComponentFactory;
}

namespace rigel::rig::components {

// ikChain, limb, twist.
Status add_limb_components(ComponentFactory& factory);

// FK/IK matching of a built limb (`limb_meta`: its metaComponent; the nodes
// are found through the metadata network by role, never by name). Each call
// is one undo step and changes controls only; fkIk stays as it is.
//
// match_fk_to_ik: sets fk0..fk2 (translate, rotate, scale, shear) so the
// FK pose equals the IK pose the solver gives now (stretch included).
Status match_fk_to_ik(scene::Scene& scene, graph::NodeId limb_meta);
// match_ik_to_fk: puts the ik control on the FK end joint's pose and the pole
// control in the FK pose's bend plane, on the side of the middle joint, at its
// current distance from the middle joint, so the IK pose equals the FK pose.
// Exact when the FK pose is one the solver can reach: the middle joint bent
// about its rest hinge only, bone lengths as at rest or within the stretch.
// A straight FK pose leaves the pole where it is.
Status match_ik_to_fk(scene::Scene& scene, graph::NodeId limb_meta);

}  // namespace rigel::rig::components
