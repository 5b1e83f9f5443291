#pragma once
// Mechanical component classes (src/rig/components/mechanical.cc).
//
// piston  guides: start, end (joints). Controls `start` and `end` at the
//         joints, hanging from the attach point. Each end has a `hook`
//         group under its control, turned by an aimConstraint (role
//         "aimConstraint") at the other end's control, and drives its joint
//         (BuildContext::drive): the two joints keep pointing at each other
//         wherever the controls go. Each end's aim vector is the direction
//         to the other joint at rest in that joint's own frame, its up the
//         joint axis most across it, its world up following its own control
//         (objectRotation), set so that at rest the constraint gives the
//         joint's own rotation: nothing moves at rest, whatever the joints'
//         orientations. Hooks "start", "end": the hook groups. The build
//         fails, naming the component, when a guide names no joint or the
//         two joints coincide.
//
// squash  guides: start (a joint), end (a joint or values). `start` control
//         at the joint (hanging from the attach point), `end` control at
//         the end under it, a `hook` group under `start` turned by an
//         aimConstraint at the end control as a piston's ends are. The
//         joint's translate and rotate follow the hook (a parentConstraint,
//         role "drive"); its scale comes from a squashStretch node (role
//         "squashStretch", ops/util/nodes.h): `axis` times d / d0 (d the
//         distance between the controls, d0 at rest), the other two axes
//         times (d / d0)^(-volume / 2). Hooks "start" (the hook group) and
//         "end" (the end control).
#include "rigel/base/status.h"

namespace rigel::rig {
class ComponentFactory;
}

namespace rigel::rig::components {

// piston, squash.
Status add_mechanical_components(ComponentFactory& factory);

}  // namespace rigel::rig::components
