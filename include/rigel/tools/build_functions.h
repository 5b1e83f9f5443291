#pragma once
// The build functions rigel ships for build graphs' function nodes
// (rig/build_function.h, docs/BUILD_GRAPH.md): rigger actions a build can
// run on the components it made.
//
//   rigel.mirrorControlShapes  each control's shape onto its opposite control, mirrored in the world
//   rigel.setControlColor      every control of a component takes a colour
//   rigel.addSpace             a control of a component gets a space that follows another component's hook
//   rigel.joinText             (pure) two texts joined with a separator
//   rigel.intText              (pure) an int as text, zero-padded
//   rigel.range                (pure) count ints from start by step
//   rigel.splitText            (pure) a text split at a separator
//
// and the flow kinds (node kinds that steer the exec chain):
//
//   rigel.sequence             runs first, second and third in turn
//   rigel.repeat               runs its body count times (index 0..count-1), then completed
//
// Registered once per process into rig::build_functions() and
// rig::flow_kinds(); the drivers
// (CLI, server, Python) register them at start, before reading any graph.

#include "rigel/base/status.h"
#include "rigel/rig/build_function.h"

namespace rigel::tools {

// Adds the functions to `registry` (kAlreadyExists when one is there).
Status add_build_functions(rig::FunctionRegistry& registry);
// Adds the flow kinds to `registry` (kAlreadyExists when one is there).
Status add_flow_kinds(rig::FlowKindRegistry& registry);
// add_build_functions(rig::build_functions()) and
// add_flow_kinds(rig::flow_kinds()), once per process.
void register_build_functions();

}  // namespace rigel::tools
