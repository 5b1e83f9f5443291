#pragma once
// How the tools find a built node again without its name: its role in its
// component and its index among the role's nodes, as
// rig::get_meta_connection counts them (poses.cc; the pose library and the
// control shapes file use it). Internal to the tools layer.

#include <optional>
#include <string>
#include <utility>

#include "rigel/graph/graph.h"

namespace rigel::tools::internal {

// nullopt for a node without a role tag or that the count does not give back.
std::optional<std::pair<std::string, int>> role_of(const graph::Graph& g, graph::NodeId meta, graph::NodeId id);

}  // namespace rigel::tools::internal
