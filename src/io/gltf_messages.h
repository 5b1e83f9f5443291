// Private to rigel_io: the places glTF messages name. A place is a
// JSON-pointer-like path into the file ("meshes[0].primitives[1].indices"),
// and a message is "<place>: <what>" (gltf_import.h, "Checks").
#pragma once

#include <cstddef>
#include <cstdio>
#include <string>
#include <string_view>

#include "rigel/base/status.h"

namespace rigel::io::gltf {

// A parse error at `where` (nothing before the colon when it is empty).
inline Status bad(const std::string& where, const std::string& what) {
  return error(ErrorCode::kParseError, where.empty() ? what : where + ": " + what);
}

// "nodes" + 3 -> "nodes[3]"; "nodes[3]" + "children" -> "nodes[3].children".
inline std::string at(const std::string& path, std::size_t index) { return path + "[" + std::to_string(index) + "]"; }
inline std::string dot(const std::string& path, std::string_view key) {
  return path.empty() ? std::string(key) : path + "." + std::string(key);
}

// Text from the file, quoted and cut to `limit` characters.
inline std::string quote_text(std::string_view text, std::size_t limit = 60) {
  std::string out = "'";
  out += text.size() > limit ? std::string(text.substr(0, limit)) + "..." : std::string(text);
  return out + "'";
}

// A number as people write it, with up to `digits` significant digits:
// "12", "0.5", "1e-07".
inline std::string number(double value, int digits) {
  char text[40];
  std::snprintf(text, sizeof text, "%.*g", digits, value);
  return text;
}

}  // namespace rigel::io::gltf
