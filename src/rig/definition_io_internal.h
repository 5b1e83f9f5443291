#pragma once
// Helpers shared by the definition readers and writers (definition_io.cc,
// definition_xml.cc, definition_json.cc, validate.cc,
// definition_schema_files.cc). Not a public header.

#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "rigel/rig/definition_io.h"

namespace rigel::rig::detail {

// Line starts of a text, to turn byte offsets into 1-based line:column.
// Columns count UTF-8 code points (a tab is one column), as editors do.
class LineIndex {
 public:
  explicit LineIndex(std::string_view text);
  SourceLocation at(std::size_t offset) const;

 private:
  std::string_view text_;
  std::vector<std::size_t> starts_;
};

// Shortest text that reads back to the same double (std::to_chars).
std::string format_double(double value);
// The same, with ".0" added when it would read as an integer (JSON, where
// the kind of a number is part of the value).
std::string format_double_json(double value);
// The whole of `text` as one finite number; nullopt otherwise.
std::optional<double> parse_double(std::string_view text);
std::optional<std::int64_t> parse_int(std::string_view text);
// "x y z" (any whitespace between, none required around); nullopt otherwise.
std::optional<math::Vec3> parse_vec3(std::string_view text);
std::string vec3_text(const math::Vec3& v);
// Whitespace-separated words ("a b  c" -> {a, b, c}), and back with one space.
std::vector<std::string_view> split_words(std::string_view text);
std::string join_words(const std::vector<std::string>& words);
// "x,y" (guiLocation in XML).
std::optional<std::pair<double, double>> parse_pair(std::string_view text);
std::string pair_text(const std::pair<double, double>& v);

// The spec of parameter `name` of component type `type`, or null.
const ParamSpec* find_param_spec(const SchemaRegistry& schemas, std::string_view type, std::string_view name);
// A parameter value as XML attribute text (bool true/false, numbers
// shortest, vec3 "x y z", strings as they are).
std::string param_text(const ParamValue& value);
// XML text typed by `spec` (null: kept as a string). Text that does not fit
// the spec's type is kept as a string too, for validate() to report.
ParamValue param_from_text(std::string_view text, const ParamSpec* spec);
// "bool", "int", "double", "string", "vec3": the alternative a value holds.
const char* value_kind(const ParamValue& value);

// The parsers. `fatal` is set when the text could not be read at all (a
// syntax error): the definition is then empty.
ParseResult parse_xml(std::string_view text, const std::string& source, const SchemaRegistry& schemas, bool* fatal);
ParseResult parse_json(std::string_view text, const std::string& source, const SchemaRegistry& schemas, bool* fatal);
std::string write_xml(const Definition& definition);
std::string write_json(const Definition& definition);

// A parameter value as JSON: bool, integer, number, [x, y, z] or string
// (the schemas' defaults and `rigel components --json`).
nlohmann::ordered_json param_value_json(const ParamValue& v);

// The parts of other JSON files that are written as in a `.rig.json` (a
// rig's settings, a component): read with the same checks and the same
// places (file:line:column by JSON pointer), and written the same way. The
// build graph's reader and writer use them (build_graph_json.cc).
class DefinitionJsonParts {
 public:
  // The text, parsed: nullopt (with the error in `errors`) when it nests
  // deeper than kMaxTextDepth or is not JSON.
  static std::optional<nlohmann::ordered_json> parse(std::string_view text, const std::string& source,
                                                     std::vector<Diagnostic>& errors);
  // `text` is the whole document `parse` read; problems go to `errors`.
  DefinitionJsonParts(std::string_view text, const std::string& source, const SchemaRegistry& schemas,
                      std::vector<Diagnostic>& errors);
  ~DefinitionJsonParts();
  DefinitionJsonParts(const DefinitionJsonParts&) = delete;
  DefinitionJsonParts& operator=(const DefinitionJsonParts&) = delete;

  // A rig object ({"name", "version", "geometry", ...}) at `pointer`.
  void read_rig(const nlohmann::ordered_json& j, const std::string& pointer, Definition& out);
  // A component object at `pointer`, as a root component.
  void read_component(const nlohmann::ordered_json& j, const std::string& pointer, std::vector<Component>& out);
  // A parameter-like value (true/false, a number, a string, [x, y, z]) typed
  // by `spec` when given, as a component's parameters are.
  std::optional<ParamValue> read_value(const std::string& name, const nlohmann::ordered_json& j,
                                       const std::string& pointer, const ParamSpec* spec);
  // Problems of the caller's own keys, at the value or at the key.
  void error(const std::string& pointer, std::string message);
  void key_error(const std::string& pointer, std::string message);
  SourceLocation at(const std::string& pointer) const;
  // Reports every key of `object` not in `allowed`.
  void check_keys(const nlohmann::ordered_json& object, const std::string& pointer,
                  std::initializer_list<const char*> allowed, const char* what);

  // Writing: the objects the `.rig.json` writer makes, and its scalars.
  static nlohmann::ordered_json rig_json(const Definition& definition);  // without components
  static nlohmann::ordered_json component_json(const Component& component);  // with its children
  static std::string scalar_text(const nlohmann::ordered_json& j);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rigel::rig::detail
