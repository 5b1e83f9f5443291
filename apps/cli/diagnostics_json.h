#pragma once
// Problems of a file as `--json` prints them: [{line, column, message}],
// shared by `rigel validate` and `rigel graph validate`.

#include <vector>

#include <nlohmann/json.hpp>

#include "rigel/rig/definition_io.h"

namespace rigel::cli {

inline nlohmann::ordered_json diagnostics_json(const std::vector<rig::Diagnostic>& list) {
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (const rig::Diagnostic& d : list)
    out.push_back({{"line", d.where.line}, {"column", d.where.column}, {"message", d.message}});
  return out;
}

}  // namespace rigel::cli
