#pragma once
// The node types of the scene and ops layers together: what scenes loaded
// from files and built by rigs use.

#include <memory>

#include "rigel/base/status.h"
#include "rigel/graph/node_type.h"

namespace rigel::ops {

// Adds every ops node type (constraints, solvers, curves, deformers).
Status register_ops_types(graph::Registry& registry);

// Scene types plus ops types. Shared and immutable.
std::shared_ptr<const graph::Registry> default_registry();

}  // namespace rigel::ops
