#pragma once
// The answers of Workspace's build graph calls (workspace.h, "build
// graphs"): kept apart so the many files that include workspace.h do not
// depend on the build graph model (rig/build_graph.h).

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "rigel/rig/build_graph.h"
#include "rigel/rig/definition.h"

namespace rigel::app {

namespace fs = std::filesystem;

// A build graph's problem (or warning) and the node and socket it is about
// (rig::place_of), for an editor to mark.
struct GraphProblem {
  rig::Diagnostic diagnostic;
  rig::GraphPlace place;
};
// A build graph read and compiled.
struct CheckedGraph {
  rig::BuildGraph graph;
  bool parsed = false;  // false: `problems` are the text's (nothing compiled)
  rig::Definition definition;  // what it compiles to (when no problems)
  std::vector<GraphProblem> problems, warnings;
  std::vector<std::string> order;  // the nodes the exec chain ran
  std::vector<std::pair<std::string, std::string>> rig_ids;  // (node id, rigId)
  bool ok() const { return parsed && problems.empty(); }
};
// A build (or live rebuild) from a graph.
struct GraphBuildReport {
  std::string rig;
  std::vector<std::string> rebuilt;  // rig ids, build order
  std::vector<std::pair<std::string, std::string>> rig_ids;  // (node id, rigId)
};
// A scene rig's build graph: the graph file it was built from, or its
// definition converted (rig::convert_definition).
struct RigGraph {
  rig::BuildGraph graph;
  fs::path path;  // the graph file ("" when converted)
  bool converted = false;
};
struct SavedGraph {
  fs::path path;
  std::string version;
  std::vector<GraphProblem> problems;  // compile's: a graph being drawn may be saved with them
};

}  // namespace rigel::app
