// Reading, writing and validating rig definitions (`.rig.xml` with pugixml,
// `.rig.json` with nlohmann-json). Both syntaxes carry the same model
// (definition.h) and convert losslessly: XML -> model -> JSON -> model -> XML
// gives the same text. The formats are described in docs/RIG.md and by the
// shipped schemas (schemas/rig.schema.json, schemas/rig.xsd), which
// `definition_json_schema()` / `definition_xsd()` generate from the
// component schemas.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/rig/definition.h"
#include "rigel/rig/schema.h"

namespace rigel::rig {

enum class Syntax { kXml, kJson };

// Nesting limits (docs/RIG.md): components nest at most kMaxComponentDepth
// levels (a root component is level 1), and the text itself, XML elements
// or JSON arrays and objects, at most kMaxTextDepth levels. Deeper input is
// refused where it passes the limit (file:line:column), before anything is
// built, so no reader, check or build recurses without bound.
inline constexpr std::size_t kMaxComponentDepth = 256;
inline constexpr std::size_t kMaxTextDepth = 1024;
// From the file name: ".rig.xml"/".xml" -> XML, ".rig.json"/".json" -> JSON.
std::optional<Syntax> syntax_of(const std::filesystem::path& path);

// One problem found in a definition, with its place.
struct Diagnostic {
  std::string file;
  SourceLocation where;
  std::string message;
  // "file:line:column: message" (line/column left out when unknown).
  std::string str() const;
};

// Parses text into the model. Syntax errors and structural errors (unknown
// element or key, a value of the wrong kind, a bad number) are reported,
// every one, with file:line:column; `source` names the file in messages.
// Parameters are typed here by their schema in `schemas`; a value that does
// not fit, an unknown parameter or one of an unknown type is kept as it is
// (XML: a string; JSON: its JSON kind) and left to validate().
struct ParseResult {
  Definition definition;
  std::vector<Diagnostic> errors;  // empty = parsed
  bool ok() const { return errors.empty(); }
};
ParseResult parse_definition(std::string_view text, Syntax syntax, const std::string& source,
                             const SchemaRegistry& schemas = builtin_schemas());
// Reads a file (syntax from its name) and parses it.
ParseResult load_definition(const std::filesystem::path& path, const SchemaRegistry& schemas = builtin_schemas());

// Semantic checks against the schemas, every problem reported: unknown
// component type, missing/invalid/duplicate rigId, unknown or ill-typed
// parameter, a value out of range or not among the choices, a guide count
// outside the schema's range, an unknown control role, shape or colour, an
// attach to a hook that does not exist, a cycle through hooks, a root-only
// component nested or a component that needs a parent at the root.
std::vector<Diagnostic> validate(const Definition& definition, const SchemaRegistry& schemas = builtin_schemas());

// Everything `rigel validate` reports for one file: load_definition()'s
// errors and, unless the text could not be read at all (a missing file, a
// syntax error), validate()'s, sorted by place.
std::vector<Diagnostic> check_definition(const std::filesystem::path& path,
                                         const SchemaRegistry& schemas = builtin_schemas());

// Deterministic text: the same model always gives the same bytes. XML:
// two-space indent, attributes in a fixed order; JSON: two-space indent,
// keys in a fixed order; doubles in the shortest form that reads back
// exactly; values equal to their defaults are still written where the
// format says "always" (docs/RIG.md).
std::string write_definition(const Definition& definition, Syntax syntax);
// Atomic: written beside the file, then renamed over it.
Status save_definition(const Definition& definition, const std::filesystem::path& path);

// JSON Schema (draft 2020-12) and XSD of the definition formats, with one
// entry per component type of `schemas` (parameters, choices, ranges, help).
std::string definition_json_schema(const SchemaRegistry& schemas = builtin_schemas());
std::string definition_xsd(const SchemaRegistry& schemas = builtin_schemas());

}  // namespace rigel::rig
