#pragma once
// The one JSON layout of rigel's text files (.rigel scenes, .rig.json
// definitions): made to be read and diffed line by line in version control.
//
//   - objects: one member per line;
//   - arrays of scalars (a vector, a quaternion, a matrix): on one line;
//   - other arrays: one element per line;
//   - with `inline_flat_objects_in_arrays`, an object inside an array whose
//     members are scalars or arrays of scalars (a guide, a control, a key)
//     goes on one line too.
//
// Scalars are written by `scalar` (nlohmann's shortest round-trip text, with
// invalid UTF-8 replaced, when none is given). The text ends with a newline.

#include <functional>
#include <string>

#include <nlohmann/json.hpp>

namespace rigel::io {

struct DiffableJsonOptions {
  bool inline_flat_objects_in_arrays = false;
  std::function<std::string(const nlohmann::ordered_json&)> scalar;
};

std::string diffable_json(const nlohmann::ordered_json& value, const DiffableJsonOptions& options = {});

}  // namespace rigel::io
