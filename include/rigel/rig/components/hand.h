#pragma once
// The hand component class (src/rig/components/hand.cc): a hand control
// with FK fingers and a curl/spread layer (Luna's HandComponent with its
// finger FK chains, seed 004 §4.8; the curl/spread/fist attributes of the
// common auto-rigs).
//
// Guides: the hand joint first, then the finger joints, each named
// FINGER.N (thumb.0, thumb.1, index.0, ...): a finger's joints come
// together, numbered 0, 1, 2, ... in order, each the child of the one
// before; joint 0 hangs anywhere below the hand joint (Rigify's palm.0N
// joints sit between; they are not driven and follow the hand joint).
// Fingers are listed across the hand (thumb, index, middle, ring, pinky):
// the list order sets the spread fan.
//
// Controls and nodes (roles):
//   hand     at the hand joint, hanging from the attach point; hook 0.
//            It drives the hand joint (BuildContext::drive) unless a node of
//            another component already drives the joint's channels when
//            this component's drive step runs: a limb or ikChain whose end
//            joint is the hand (its fkIkSwitch), an fkChain that holds it.
//            Then the parent owns the wrist (FK, IK and the switch keep
//            working) and the hand control only carries the fingers: it
//            hangs from the parent's hook, so it follows the hand joint, and
//            its channels (normally left at zero) offset the fingers.
//   finger   one per finger joint (index = running index over every
//            finger's joints, in guide order), each finger a chain hanging
//            from the hand control, each driving its joint.
//   fingerCurl  (param curlAttributes) an ops::util fingerCurl node holding
//            the keyable curl, spread and fingerCurl[k] values; it writes
//            every finger control's offsetParentMatrix = rest offset * turn,
//            so at zero nothing moves and the FK channels work on top.
//
// Curl: every joint of finger k turns by curl + fingerCurl[k] degrees about
// the finger's bend axis b_k (positive closes the fist). With p_j the
// finger's joint positions at rest, s = sum_j (p_j+1 - p_j) x (p_j+2 - p_j+1):
// when |s| > 1e-3 * sum_j |p_j+1 - p_j| |p_j+2 - p_j+1| (the finger bends in
// a plane) b_k = s / |s|, signed to agree with h, the joint 0's `bendAxis`
// (param, in that joint's frame; glTF from Blender: x); otherwise (a straight
// finger, or fewer than three joints) b_k = h made perpendicular to the first
// bone. Each control gets b_k in its own rest frame, so the whole finger
// folds in its plane.
//
// Spread: the first joint of finger k turns about the hand's normal
// n = f x a (f: from the hand joint to the mean of the fingers' first
// joints; a: the sum of the bend axes of the fingers not named "thumb", or of
// all when only thumbs; fallback when parallel: the middle finger's first
// bone x its bend axis) by spread * |k - m| degrees, m the middle finger's
// place in the list (the finger named "middle", else (count - 1) / 2), in
// the direction that moves it away from the middle finger's first joint
// (by list side when level with it): each gap between neighbours opens by
// `spread`.
#include "rigel/base/status.h"

namespace rigel::rig {
class ComponentFactory;
}

namespace rigel::rig::components {

// hand.
Status add_hand_component(ComponentFactory& factory);

}  // namespace rigel::rig::components
