#include "rigel/io/json_depth.h"

#include <string>

namespace rigel::io {

std::size_t json_too_deep(std::string_view text, std::size_t limit) {
  std::size_t depth = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '"') {
      for (++i; i < text.size() && text[i] != '"'; ++i)
        if (text[i] == '\\') ++i;
    } else if (c == '[' || c == '{') {
      if (++depth > limit) return i;
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return std::string_view::npos;
}

std::string line_column(std::string_view text, std::size_t byte) {
  std::size_t line = 1, column = 1;
  for (std::size_t i = 0; i < byte && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return std::to_string(line) + ":" + std::to_string(column);
}

Result<nlohmann::ordered_json> parse_json(std::string_view text, const std::string& source, std::size_t max_depth) {
  if (const std::size_t deep = json_too_deep(text, max_depth); deep != std::string_view::npos)
    return Status(ErrorCode::kParseError, source + ":" + line_column(text, deep) + ": nested too deep");
  try {
    return nlohmann::ordered_json::parse(text);
  } catch (const nlohmann::ordered_json::parse_error& e) {
    return Status(ErrorCode::kParseError,
                  source + ":" + line_column(text, e.byte == 0 ? 0 : e.byte - 1) + ": malformed JSON (" + e.what() + ")");
  }
}

}  // namespace rigel::io
