#pragma once
// Component classes of the face (src/rig/components/face.cc).
//
// mouth   guides: jaw, upperLip, lowerLip (joints), then optionally the two
//         lip corners (cornerL, cornerR).
//         jaw      control at the jaw joint (its pivot), hanging from the
//                  attach point; drives the jaw joint; hook "jaw".
//         lipFollow[i]  one group per lip joint (i = its guide index - 1)
//                  at the joint, hanging from the attach point, held by a
//                  parentConstraint (role "lipFollowConstraint", offsets kept)
//                  between the attach point (weight 1 - f) and the jaw
//                  control (weight f), f = upperLipFollow, lowerLipFollow
//                  or cornerFollow: the lip takes that share of the jaw's
//                  motion (positions blend linearly, rotations by the
//                  normalised quaternion sum).
//         lip[i]   control at the lip joint under lipFollow[i]; drives it.
//                  Hooks "upperLip", "lowerLip": the lip controls.
// The build fails, naming the component, when a guide names no joint.
//
// eyelid: guides the eye joint, the upper and the lower lid joints.
//   lidFollow[0..1]  groups at the eye (the lids' pivot) in its parent's frame,
//                    turned (rotate) by the eyelidBlink node (role eyelid,
//                    ops/util/eyelid.h) reading the eye joint's local matrix:
//                    each lid follows the eye's turn about `axis` by
//                    upperFollow / lowerFollow, and `blink` (keyable on the
//                    node) closes them by `gap` degrees, meeting at
//                    blinkHeight.
//   lid[0..1]        controls at the lid joints under them; drive them.
//                    Hooks "upper", "lower".
//
// brows: guides the brow joints, inner first. A `main` control at their
//   middle (hook "main"); per joint a browFollow group between the attach
//   point and `main` (weights 1 - f, f; f from innerFollow to outerFollow,
//   linearly) and a `brow` control under it driving the joint.
#include "rigel/base/status.h"

namespace rigel::rig {
class ComponentFactory;
}

namespace rigel::rig::components {

// mouth, eyelid, brows.
Status add_face_components(ComponentFactory& factory);

}  // namespace rigel::rig::components
