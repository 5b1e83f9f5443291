// The rig-definition commands of `rigel` (see definition_commands.h):
// validate, components, schema, diff.

#include "definition_commands.h"

#include <iostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_util.h"
#include "diagnostics_json.h"
#include "pipeline_commands.h"
#include "rigel/rig/definition_io.h"
#include "rigel/rig/diff.h"
#include "rigel/rig/manager.h"
#include "rigel/rig/schema.h"

namespace rigel::cli {
namespace {

using Json = nlohmann::ordered_json;

// ---- validate ------------------------------------------------------------------

struct ValidateArgs {
  std::vector<std::string> files;
  bool json = false;
};

int run_validate(const ValidateArgs& args) {
  Json files = Json::array();
  bool all_valid = true;
  for (const std::string& given : args.files) {
    const std::string file = in_current_asset(given, tools::AssetFile::kDefinition);
    const std::vector<rig::Diagnostic> errors = rig::check_definition(file);
    all_valid &= errors.empty();
    if (args.json) {
      files.push_back(Json{{"file", file}, {"valid", errors.empty()}, {"errors", diagnostics_json(errors)}});
      continue;
    }
    for (const rig::Diagnostic& d : errors) std::cerr << d.str() << "\n";
    if (errors.empty()) std::cerr << "rigel: " << file << ": valid\n";
    else std::cerr << "rigel: " << file << ": " << errors.size() << (errors.size() == 1 ? " error\n" : " errors\n");
  }
  if (args.json) std::cout << Json{{"files", std::move(files)}}.dump(2, ' ', false, Json::error_handler_t::replace) << "\n";
  return all_valid ? 0 : kExitInvalidInput;
}

// ---- components ----------------------------------------------------------------

struct ComponentsArgs {
  std::string type;  // "" = every type
  bool json = false;
};

std::string value_text(const rig::ParamValue& v) {
  if (const auto* b = std::get_if<bool>(&v)) return *b ? "true" : "false";
  if (const auto* i = std::get_if<std::int64_t>(&v)) return std::to_string(*i);
  if (const auto* d = std::get_if<double>(&v)) return number_text(*d);
  if (const auto* x = std::get_if<math::Vec3>(&v))
    return number_text(x->x()) + " " + number_text(x->y()) + " " + number_text(x->z());
  return std::get<std::string>(v);
}

std::string join(const std::vector<std::string>& items, const char* separator = ", ") {
  std::string out;
  for (const std::string& s : items) out += (out.empty() ? "" : separator) + s;
  return out;
}

std::string guide_count(const rig::GuideSpec& g) {
  if (g.max == g.min) return "exactly " + std::to_string(g.min);
  if (g.max < 0) return "at least " + std::to_string(g.min);
  return std::to_string(g.min) + " to " + std::to_string(g.max);
}

void print_schema(const rig::ComponentSchema& s) {
  std::cout << s.type << ": " << s.help << "\n";
  if (s.root_only) std::cout << "  root only: it cannot be nested\n";
  if (s.needs_parent) std::cout << "  needs a parent: it cannot be a root\n";
  if (s.params.empty()) {
    std::cout << "  parameters: none\n";
  } else {
    std::cout << "  parameters:\n";
    for (const rig::ParamSpec& p : s.params) {
      std::string type = rig::param_type_name(p.type);
      if (!p.choices.empty()) type += " " + join(p.choices, "|");
      if (p.min && p.max) type += " " + number_text(*p.min) + " to " + number_text(*p.max);
      else if (p.min) type += " >= " + number_text(*p.min);
      else if (p.max) type += " <= " + number_text(*p.max);
      std::cout << "    " << p.name << " (" << type << ", default " << value_text(p.default_value) << "): " << p.help
                << "\n";
    }
  }
  std::cout << "  guides: " << guide_count(s.guides);
  if (!s.guides.names.empty()) std::cout << " (" << join(s.guides.names) << ")";
  std::cout << ": " << s.guides.help << "\n";
  if (s.controls.empty()) {
    std::cout << "  controls: none\n";
  } else {
    std::cout << "  controls:\n";
    for (const rig::ControlSpec& c : s.controls)
      std::cout << "    " << c.role << " (" << c.shape << ", " << c.color << ", size " << number_text(c.size)
                << "): " << c.help << "\n";
  }
  std::cout << "  hooks: " << join(s.hooks) << (s.hooks.size() == 1 && s.hooks[0] == "guide[i]" ? " (one per guide)" : "")
            << "\n";
  if (!s.features.empty()) std::cout << "  features: " << join(s.features) << "\n";
}

int run_components(const ComponentsArgs& args) {
  const rig::SchemaRegistry& schemas = rig::builtin_schemas();
  std::vector<std::string> types = schemas.types();
  if (!args.type.empty()) {
    if (!schemas.find(args.type)) {
      std::cerr << "rigel: unknown component type '" << args.type << "' (types: " << join(types) << ")\n";
      return kExitInvalidInput;
    }
    types = {args.type};
  }
  if (args.json) {
    Json list = Json::array();
    for (const std::string& t : types) list.push_back(rig::component_schema_json(*schemas.find(t)));
    std::cout << Json{{"components", std::move(list)}}.dump(2) << "\n";
    return 0;
  }
  for (std::size_t i = 0; i < types.size(); ++i) {
    if (i) std::cout << "\n";
    print_schema(*schemas.find(types[i]));
  }
  return 0;
}

// ---- schema --------------------------------------------------------------------

struct SchemaArgs {
  bool json = false;
  bool xsd = false;
};

int run_schema(const SchemaArgs& args) {
  if (args.json == args.xsd) return usage_error("schema: give one of --json (JSON Schema) or --xsd (XML Schema)");
  std::cout << (args.json ? rig::definition_json_schema() : rig::definition_xsd());
  return 0;
}

// ---- diff ----------------------------------------------------------------------

// diff(1)'s convention: 0 the same, 1 different, 2 trouble (a file that
// cannot be read or parsed, a usage error).
constexpr int kDiffDifferent = 1;
constexpr int kDiffTrouble = 2;

struct DiffArgs {
  std::string a, b;
  bool json = false;
};

int run_diff(const DiffArgs& args) {
  rig::ParseResult a = rig::load_definition(args.a), b = rig::load_definition(args.b);
  if (!a.ok() || !b.ok()) {
    for (const rig::Diagnostic& d : a.errors) std::cerr << d.str() << "\n";
    for (const rig::Diagnostic& d : b.errors) std::cerr << d.str() << "\n";
    return kDiffTrouble;
  }
  const std::vector<rig::Difference> differences = rig::diff(a.definition, b.definition);
  if (args.json) {
    Json list = Json::array();
    for (const rig::Difference& d : differences) {
      Json e = Json::object();
      e["kind"] = rig::difference_kind_name(d.kind);
      e["rigId"] = d.rig_id;
      e["component"] = d.component;
      e["item"] = d.item;
      e["old"] = d.old_value;
      e["new"] = d.new_value;
      e["text"] = d.str();
      list.push_back(std::move(e));
    }
    std::cout << Json{{"equal", differences.empty()}, {"differences", std::move(list)}}.dump(
                     2, ' ', false, Json::error_handler_t::replace)
              << "\n";
  } else {
    for (const rig::Difference& d : differences) std::cout << d.str() << "\n";
  }
  return differences.empty() ? 0 : kDiffDifferent;
}

}  // namespace

struct DefinitionCommands::State {
  ValidateArgs validate;
  ComponentsArgs components;
  SchemaArgs schema;
  DiffArgs diff;
  CLI::App* validate_cmd = nullptr;
  CLI::App* components_cmd = nullptr;
  CLI::App* schema_cmd = nullptr;
  CLI::App* diff_cmd = nullptr;
};

DefinitionCommands::DefinitionCommands() : state_(std::make_unique<State>()) {}
DefinitionCommands::~DefinitionCommands() = default;

void add_definition_commands(CLI::App& app, DefinitionCommands& commands) {
  DefinitionCommands::State& s = commands.state();

  s.validate_cmd = app.add_subcommand(
      "validate", "Check rig definitions (.rig.xml, .rig.json): every problem as FILE:LINE:COLUMN: MESSAGE on stderr");
  s.validate_cmd->add_option("DEFINITION", s.validate.files, "Definition files (.xml, .json)")->required();
  s.validate_cmd->add_flag("--json", s.validate.json,
                           "Print {\"files\": [{\"file\", \"valid\", \"errors\": [{\"line\", \"column\", \"message\"}]}]}");
  s.validate_cmd->footer(
      "Exit status: 0 every file valid, 1 a problem found, 2 usage error.\n"
      "Example: rigel validate biped.rig.xml quadruped.rig.json");

  s.components_cmd = app.add_subcommand(
      "components", "List the component types: help, parameters (type, default, range, choices), guides, controls, hooks");
  s.components_cmd->add_option("TYPE", s.components.type, "Only this component type (e.g. limb)");
  s.components_cmd->add_flag("--json", s.components.json, "Print {\"components\": [...]} instead of text");
  s.components_cmd->footer("Example: rigel components limb");

  s.schema_cmd = app.add_subcommand("schema", "Print the JSON Schema or the XSD of the rig definition formats");
  CLI::Option* json = s.schema_cmd->add_flag("--json", s.schema.json, "JSON Schema (draft 2020-12) of .rig.json");
  CLI::Option* xsd = s.schema_cmd->add_flag("--xsd", s.schema.xsd, "XML Schema (XSD 1.0) of .rig.xml");
  json->excludes(xsd);
  s.schema_cmd->footer(
      "The shipped copies are this output; regenerate them with\n"
      "  rigel schema --json > schemas/rig.schema.json\n"
      "  rigel schema --xsd > schemas/rig.xsd");

  s.diff_cmd = app.add_subcommand(
      "diff", "Semantic differences between two rig definitions, components matched by rigId (either syntax)");
  s.diff_cmd->add_option("A", s.diff.a, "Old definition (.xml, .json)")->required();
  s.diff_cmd->add_option("B", s.diff.b, "New definition (.xml, .json)")->required();
  s.diff_cmd->add_flag("--json", s.diff.json,
                       "Print {\"equal\", \"differences\": [{\"kind\", \"rigId\", \"component\", \"item\", \"old\", "
                       "\"new\", \"text\"}]}");
  s.diff_cmd->footer(
      "Exit status (as diff(1)): 0 the same, 1 different, 2 a file could not be read or parsed, or a usage error.\n"
      "Example: rigel diff biped_v1.rig.xml biped_v2.rig.json");
}

std::optional<int> run_definition_commands(const DefinitionCommands& commands) {
  const DefinitionCommands::State& s = commands.state();
  if (*s.validate_cmd) return run_validate(s.validate);
  if (*s.components_cmd) return run_components(s.components);
  if (*s.schema_cmd) return run_schema(s.schema);
  if (*s.diff_cmd) return run_diff(s.diff);
  return std::nullopt;
}

}  // namespace rigel::cli
