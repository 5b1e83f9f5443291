#pragma once
// Component classes of the body (src/rig/components/body.cc): spine, neck,
// tail, eye and simple. builtin_components() adds them.
#include "rigel/base/status.h"

namespace rigel::rig {
class ComponentFactory;
}

namespace rigel::rig::components {

// spine, neck, tail, eye, simple.
Status add_body_components(ComponentFactory& factory);

}  // namespace rigel::rig::components
