// How deep JSON text nests, checked before it is parsed: nlohmann-json
// parses recursively, so a file of a few megabytes of '[' would exhaust the
// stack (and grow its memory with the square of the depth). The .rigel
// loader and the .rig.json parser refuse text past their limits with the
// place of the bracket that passes it.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "rigel/base/status.h"

namespace rigel::io {

// The offset of the first '[' or '{' that opens a level deeper than `limit`
// in `text`, or std::string_view::npos. Strings are skipped (their escapes
// too); the text need not be valid JSON. Linear in the text, no allocation.
std::size_t json_too_deep(std::string_view text, std::size_t limit);

// "LINE:COLUMN" (both from 1) of byte offset `byte` in `text`: where a
// parse error is, for messages.
std::string line_column(std::string_view text, std::size_t byte);

// `text` parsed, refused past `max_depth` levels first: kParseError
// "SOURCE:LINE:COLUMN: ..." for text too deep or not JSON. What rigel's
// small JSON files (settings, projects, data, reports) are read with.
Result<nlohmann::ordered_json> parse_json(std::string_view text, const std::string& source, std::size_t max_depth = 32);

}  // namespace rigel::io
