// Reading and writing rig definitions: the entry points of definition_io.h
// and the helpers both syntaxes share (definition_io_internal.h). The XML
// syntax is in definition_xml.cc, JSON in definition_json.cc, the semantic
// checks in validate.cc, the JSON Schema and XSD in
// definition_schema_files.cc.
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include "definition_io_internal.h"
#include "rigel/io/scene_file.h"
#include "rigel/rig/build_graph.h"

namespace rigel::rig {

namespace detail {

LineIndex::LineIndex(std::string_view text) : text_(text) {
  starts_.push_back(0);
  for (std::size_t i = 0; i < text.size(); ++i)
    if (text[i] == '\n') starts_.push_back(i + 1);
}

SourceLocation LineIndex::at(std::size_t offset) const {
  offset = std::min(offset, text_.size());
  const auto it = std::upper_bound(starts_.begin(), starts_.end(), offset);
  const std::size_t line = static_cast<std::size_t>(it - starts_.begin());  // >= 1
  const std::size_t start = starts_[line - 1];
  int column = 1;
  for (std::size_t i = start; i < offset; ++i)
    if ((static_cast<unsigned char>(text_[i]) & 0xC0) != 0x80) ++column;  // not a UTF-8 continuation byte
  return {static_cast<int>(line), column};
}

std::string format_double(double value) {
  if (value == 0.0) value = 0.0;  // -0 reads back as 0 anyway where it matters; write "0"
  char buffer[64];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, value);
  return ec == std::errc() ? std::string(buffer, end) : std::string("0");
}

std::string format_double_json(double value) {
  std::string text = format_double(value);
  if (text.find_first_of(".eEn") == std::string::npos) text += ".0";
  return text;
}

std::optional<double> parse_double(std::string_view text) {
  if (text.empty()) return std::nullopt;
  double value = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(value)) return std::nullopt;
  return value;
}

std::optional<std::int64_t> parse_int(std::string_view text) {
  if (text.empty()) return std::nullopt;
  std::int64_t value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return value;
}

namespace {
bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }
}  // namespace

std::vector<std::string_view> split_words(std::string_view text) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && is_space(text[i])) ++i;
    const std::size_t start = i;
    while (i < text.size() && !is_space(text[i])) ++i;
    if (i > start) out.push_back(text.substr(start, i - start));
  }
  return out;
}

std::optional<math::Vec3> parse_vec3(std::string_view text) {
  const auto words = split_words(text);
  if (words.size() != 3) return std::nullopt;
  math::Vec3 v;
  for (int i = 0; i < 3; ++i) {
    const auto d = parse_double(words[static_cast<std::size_t>(i)]);
    if (!d) return std::nullopt;
    v[i] = *d;
  }
  return v;
}

std::string vec3_text(const math::Vec3& v) {
  return format_double(v.x()) + " " + format_double(v.y()) + " " + format_double(v.z());
}

std::optional<std::pair<double, double>> parse_pair(std::string_view text) {
  const std::size_t comma = text.find(',');
  if (comma == std::string_view::npos) return std::nullopt;
  auto trim = [](std::string_view s) {
    while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
    while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
    return s;
  };
  const auto x = parse_double(trim(text.substr(0, comma)));
  const auto y = parse_double(trim(text.substr(comma + 1)));
  if (!x || !y) return std::nullopt;
  return std::pair{*x, *y};
}

std::string pair_text(const std::pair<double, double>& v) {
  return format_double(v.first) + "," + format_double(v.second);
}

const ParamSpec* find_param_spec(const SchemaRegistry& schemas, std::string_view type, std::string_view name) {
  const ComponentSchema* schema = schemas.find(type);
  return schema ? schema->param(name) : nullptr;
}

std::string param_text(const ParamValue& value) {
  if (const auto* b = std::get_if<bool>(&value)) return *b ? "true" : "false";
  if (const auto* i = std::get_if<std::int64_t>(&value)) return std::to_string(*i);
  if (const auto* d = std::get_if<double>(&value)) return format_double(*d);
  if (const auto* v = std::get_if<math::Vec3>(&value)) return vec3_text(*v);
  return std::get<std::string>(value);
}

ParamValue param_from_text(std::string_view text, const ParamSpec* spec) {
  if (spec) {
    switch (spec->type) {
      case ParamType::kBool:
        if (text == "true") return true;
        if (text == "false") return false;
        break;
      case ParamType::kInt:
        if (const auto i = parse_int(text)) return *i;
        break;
      case ParamType::kDouble:
        if (const auto d = parse_double(text)) return *d;
        break;
      case ParamType::kVec3:
        if (const auto v = parse_vec3(text)) return *v;
        break;
      case ParamType::kString:
      case ParamType::kEnum: break;
    }
  }
  return std::string(text);
}

const char* value_kind(const ParamValue& value) {
  switch (value.index()) {
    case 0: return "bool";
    case 1: return "int";
    case 2: return "double";
    case 3: return "string";
    default: return "vec3";
  }
}

}  // namespace detail

std::optional<Syntax> syntax_of(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".xml") return Syntax::kXml;
  if (ext == ".json") return Syntax::kJson;
  return std::nullopt;
}

std::string detail::join_words(const std::vector<std::string>& words) {
  std::string out;
  for (const std::string& w : words) out += (out.empty() ? "" : " ") + w;
  return out;
}

std::string Diagnostic::str() const {
  std::string out = file;
  if (where.line > 0) {
    if (!out.empty()) out += ':';
    out += std::to_string(where.line);
    out += ':';
    out += std::to_string(where.column);
  }
  return out.empty() ? message : out + ": " + message;
}

namespace {

ParseResult parse_any(std::string_view text, Syntax syntax, const std::string& source, const SchemaRegistry& schemas,
                      bool* fatal) {
  ParseResult result = syntax == Syntax::kXml ? detail::parse_xml(text, source, schemas, fatal)
                                              : detail::parse_json(text, source, schemas, fatal);
  result.definition.source = source;
  return result;
}

// The file's text, or a diagnostic saying why there is none.
std::optional<std::string> read_file(const std::filesystem::path& path, std::vector<Diagnostic>& errors) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    errors.push_back({path.string(), {}, "is a folder, not a definition file"});
    return std::nullopt;
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    errors.push_back({path.string(), {}, "cannot be read (missing, or no permission)"});
    return std::nullopt;
  }
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return std::move(buffer).str();
}

// A build graph read and compiled: its definition, or every problem.
ParseResult load_graph(const std::filesystem::path& path, const SchemaRegistry& schemas, bool* fatal) {
  ParseResult result;
  BuildGraphCompile compiled = check_build_graph(path, schemas);
  result.definition = std::move(compiled.definition);
  result.definition.source = path.string();
  result.errors = std::move(compiled.errors);
  // Compiling validated the definition: what it found is all there is.
  *fatal = true;
  return result;
}

ParseResult load_impl(const std::filesystem::path& path, const SchemaRegistry& schemas, bool* fatal) {
  if (is_build_graph_path(path)) return load_graph(path, schemas, fatal);
  ParseResult result;
  result.definition.source = path.string();
  const auto syntax = syntax_of(path);
  if (!syntax) {
    result.errors.push_back({path.string(), {}, "unknown definition syntax: the name must end in .xml or .json"});
    *fatal = true;
    return result;
  }
  const auto text = read_file(path, result.errors);
  if (!text) {
    *fatal = true;
    return result;
  }
  return parse_any(*text, *syntax, path.string(), schemas, fatal);
}

}  // namespace

BuildGraphParse load_build_graph(const std::filesystem::path& path, const SchemaRegistry& schemas) {
  BuildGraphParse out;
  out.graph.source = path.string();
  const auto text = read_file(path, out.errors);
  if (!text) return out;
  return parse_build_graph(*text, path.string(), schemas);
}

BuildGraphCompile check_build_graph(const std::filesystem::path& path, const SchemaRegistry& schemas) {
  BuildGraphParse parsed = load_build_graph(path, schemas);
  if (!parsed.ok()) {
    BuildGraphCompile out;
    out.errors = std::move(parsed.errors);
    return out;
  }
  return compile_build_graph(parsed.graph, schemas);
}

ParseResult parse_definition(std::string_view text, Syntax syntax, const std::string& source,
                             const SchemaRegistry& schemas) {
  bool fatal = false;
  return parse_any(text, syntax, source, schemas, &fatal);
}

ParseResult load_definition(const std::filesystem::path& path, const SchemaRegistry& schemas) {
  bool fatal = false;
  return load_impl(path, schemas, &fatal);
}

std::vector<Diagnostic> check_definition(const std::filesystem::path& path, const SchemaRegistry& schemas) {
  bool fatal = false;
  ParseResult parsed = load_impl(path, schemas, &fatal);
  std::vector<Diagnostic> errors = std::move(parsed.errors);
  if (fatal) return errors;
  for (Diagnostic& d : validate(parsed.definition, schemas)) errors.push_back(std::move(d));
  std::stable_sort(errors.begin(), errors.end(), [](const Diagnostic& a, const Diagnostic& b) {
    return std::pair(a.where.line, a.where.column) < std::pair(b.where.line, b.where.column);
  });
  return errors;
}

std::string write_definition(const Definition& definition, Syntax syntax) {
  return syntax == Syntax::kXml ? detail::write_xml(definition) : detail::write_json(definition);
}

Status save_definition(const Definition& definition, const std::filesystem::path& path) {
  if (is_build_graph_path(path))
    return error(ErrorCode::kInvalidArgument,
                 path.string() + ": is a build graph: a definition is saved as .rig.xml or .rig.json (a graph is "
                                 "made from one by `rigel graph convert`)");
  const auto syntax = syntax_of(path);
  if (!syntax)
    return error(ErrorCode::kInvalidArgument,
                 path.string() + ": unknown definition syntax: the name must end in .xml or .json");
  return io::write_file_atomic(path, write_definition(definition, *syntax));
}

}  // namespace rigel::rig
