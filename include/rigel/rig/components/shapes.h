// Component types driving shapes and correctives (src/rig/components/
// shapes.cc), each through drivenKey nodes (ops/anim/nodes.h).
//
// blendShapeSliders: guide 0 is where the slider column stands (a joint or
//   values). A `panel` group there (hook "panel") holds one `slider`
//   control per target of a blendShape node (`blendShape`: its name; empty:
//   the scene's only one), listed by `targets` (names or indices,
//   comma-separated; empty: every target), `spacing` apart downwards. A
//   slider's translateY drives its weight through a drivenKey: weight =
//   clamp(w0 + y, min, max), w0 the weight at build time, so nothing moves
//   at rest.
// corrective: guide 0 is the driver joint, guide 1 (optional) a corrective
//   joint. A poseReader (role reader) reads how far the driver's `axis` has
//   swung from its rest (degrees); from startAngle to endAngle a drivenKey
//   takes the corrective joint from its rest translate to rest + `offset`
//   (one drivenKey per axis, roles offsetX/Y/Z) and, with `blendShape`
//   and `target` set, a blendShape target's weight from 0 to 1 (role
//   weight). No controls: the driver's pose is the control.
#pragma once

#include "rigel/base/status.h"

namespace rigel::rig {
class ComponentFactory;
}

namespace rigel::rig::components {

// blendShapeSliders, corrective.
Status add_shape_components(ComponentFactory& factory);

}  // namespace rigel::rig::components
