#pragma once
// Problems of a file as `--json` prints them: [{line, column, message}],
// shared by `rigel validate` and `rigel graph validate` (which adds the
// node and socket a problem is about, rig::place_of).

#include <vector>

#include <nlohmann/json.hpp>

#include "rigel/rig/build_graph.h"
#include "rigel/rig/definition_io.h"

namespace rigel::cli {

inline nlohmann::ordered_json diagnostics_json(const std::vector<rig::Diagnostic>& list,
                                               const rig::BuildGraph* graph = nullptr) {
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (const rig::Diagnostic& d : list) {
    nlohmann::ordered_json j{{"line", d.where.line}, {"column", d.where.column}, {"message", d.message}};
    if (graph) {
      const rig::GraphPlace place = rig::place_of(*graph, d);
      if (!place.node.empty()) j["node"] = place.node;
      if (!place.socket.empty()) j["socket"] = place.socket;
    }
    out.push_back(std::move(j));
  }
  return out;
}

}  // namespace rigel::cli
