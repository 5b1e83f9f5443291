#pragma once
// The foot component class (src/rig/components/foot.cc): a reverse foot
// (Luna's FootComponent, seed 004 §4.8; the heel / ball / toe roll, bank and
// toe tap of Maya auto-rigs). The pivot chain is one ops::util reverseFoot
// node (ops/util/foot.h, role "reverseFoot") that holds the keyable roll,
// rollBreak, bank, heelTwist, toeTwist, ballTwist and toeTap; the foot
// control stands for them (node types have fixed attributes) and its own
// channels move the whole foot.
//
// Guides (in this order):
//   ankle  a joint: the one the leg ends in
//   ball   a joint, child of the ankle (Rigify: toe.L): the toes turn here
//   toe    the toe tip, heel, and the inner and outer edge of the sole:
//   heel   pivots, joints or values (only their positions count; Rigify's
//   inner  heel.02.L serves as the heel: the roll axis runs across the foot,
//   outer  so a heel pivot off the centre line changes only heelTwist)
//
// The foot's frame at rest: up u = the normal of the ground plane spanned
// by toe - heel and outer - inner, pointing to the ankle's side; forward
// f = toe - ankle made perpendicular to u; roll axis a = u x f; outward
// o = +-a toward the outer guide; bank axis u x o, twist axis f x o.
// The build fails, naming the component, when the ankle or ball guide names
// no joint (or the ball is not the ankle's child), the heel and toe
// coincide, the four sole points span no plane, the ankle lies on that
// plane, the toe is straight below the ankle or behind the heel, or the
// inner and outer guides are not on either side of the foot.
//
// Nodes (roles):
//   foot        control on the ground below the ankle, axes (a, u, f).
//               With a parent that drives the ankle as the end of its IK
//               chain (limb or ikChain: its fkIkSwitch's last joint) it hangs
//               from the parent's "ik" control, so moving that still moves
//               everything; otherwise from the attach point.
//   toeFk       FK control of the ball joint, at the ball joint, hanging from
//               the parent's last "fk" control (a limb; none otherwise).
//   reverseFoot the pivot chain; controlMatrix <- foot.worldMatrix, pivots
//               and rest matrices in the foot control's rest space, rollBreak
//               from the parameter.
//   IK takeover (parent with an ikSolver): the solver's targetMatrix and the
//               parent fkIkSwitch's ikEndMatrix are reconnected from
//               reverseFoot.outAnkleMatrix (they came from the parent's ik
//               control), so in IK the roll moves the ankle and bends the leg
//               and the ankle takes the chain's orientation. The build's
//               recorder keeps the old connections, so destructing the foot
//               gives them back.
//   ankleDriver (no such parent) a transform under the rig's noTransform
//               group following outAnkleMatrix, driving the ankle joint
//               (BuildContext::drive).
//   fkIkSwitch  an ops::util fkIkSwitch over [ball joint]: IK side
//               outBallMatrix, FK side toeFk; fkIk connected from the parent
//               fkIkSwitch's fkIk (the limb's switch turns the toes too), 1
//               without a parent chain; it drives the ball joint's channels
//               (quaternion mode).
//   hook0..2    transforms under noTransform: ankle and ball follow their
//               joints; toe hangs from the ball hook at the toe guide's rest
//               offset from the ball joint, so it follows the toes.
//
// Limitation: limbs' FK/IK matching (limbs.h) matches the leg only, using
// the ankle pose the reverse foot gives; match_ik_to_fk assumes the foot's
// values and its control's channels are zero, and toeFk is not matched.
#include "rigel/base/status.h"

namespace rigel::rig {
class ComponentFactory;
}

namespace rigel::rig::components {

// foot.
Status add_foot_component(ComponentFactory& factory);

}  // namespace rigel::rig::components
