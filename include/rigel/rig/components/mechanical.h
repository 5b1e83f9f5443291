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
//
// wheel   guide: the wheel's joint. `main` control at the joint (hanging
//         from the attach point: it moves the wheel, or the whole vehicle
//         moves it), a `roll` group under it whose rotate a wheelRoll node
//         (ops/util/nodes.h) writes from how far `main` has moved along
//         `forward` since rest (in the world, so the vehicle's own motion
//         counts) over `radius`, about `axle` (both in the joint's frame;
//         axle = up x forward rolls it the right way), and a `spin` control
//         under the roll (a manual turn on top) driving the joint. Hooks
//         "hub" (main: does not spin) and "wheel" (spin). Displacement, not
//         path length: a wheel driven round a loop comes back to its rest
//         angle. Fails, naming the component, without a joint or with the
//         axle along forward.
#include "rigel/base/status.h"

namespace rigel::rig {
class ComponentFactory;
}

namespace rigel::rig::components {

// piston, squash, wheel.
Status add_mechanical_components(ComponentFactory& factory);

}  // namespace rigel::rig::components
