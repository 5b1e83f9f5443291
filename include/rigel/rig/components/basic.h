#pragma once
// Component classes of the rig layer, grouped by file; builtin_components()
// adds them all.
#include "rigel/base/status.h"

namespace rigel::rig {
class ComponentFactory;
}

namespace rigel::rig::components {

// global, hip, control, meta, fkChain.
Status add_basic_components(ComponentFactory& factory);

}  // namespace rigel::rig::components
