// `rigel graph run|convert|validate` (graph_commands.h): a build graph is
// built as `rigel build` builds a definition (the graph compiles to one);
// convert and validate are the app and rig layers' calls.

#include "graph_commands.h"

#include <iostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_util.h"
#include "diagnostics_json.h"
#include "rig_commands.h"
#include "rigel/app/graphs.h"
#include "rigel/app/rig_files.h"
#include "rigel/rig/build_graph.h"

namespace rigel::cli {
namespace {

using Json = nlohmann::ordered_json;

struct ValidateArgs {
  std::vector<std::string> files;
  bool json = false;
};

// Every problem of each graph (node and socket named) and its warnings.
int run_validate(const ValidateArgs& args) {
  Json files = Json::array();
  bool all_valid = true;
  for (const std::string& file : args.files) {
    // check_build_graph's steps, keeping the graph to place each problem on its node.
    rig::BuildGraphCompile checked;
    rig::BuildGraphParse parsed;
    if (!rig::is_build_graph_path(file))
      checked.errors.push_back({file, {}, "not a build graph: the file name must end in .build.json"});
    else if (parsed = rig::load_build_graph(file); !parsed.ok())
      checked.errors = std::move(parsed.errors);
    else
      checked = rig::compile_build_graph(parsed.graph);
    const std::vector<rig::Diagnostic>& errors = checked.errors;
    const std::vector<rig::Diagnostic>& warnings = checked.warnings;
    const std::vector<std::string>& order = checked.order;
    all_valid &= errors.empty();
    if (args.json) {
      files.push_back(Json{{"file", file},
                           {"valid", errors.empty()},
                           {"errors", diagnostics_json(errors, &parsed.graph)},
                           {"warnings", diagnostics_json(warnings, &parsed.graph)},
                           {"order", errors.empty() ? Json(order) : Json::array()}});
      continue;
    }
    for (const rig::Diagnostic& d : errors) std::cerr << d.str() << "\n";
    for (const rig::Diagnostic& d : warnings) std::cerr << d.str() << " (warning)\n";
    if (errors.empty()) std::cerr << "rigel: " << file << ": valid (" << order.size() << " nodes on the exec chain)\n";
    else std::cerr << "rigel: " << file << ": " << errors.size() << (errors.size() == 1 ? " error\n" : " errors\n");
  }
  if (args.json) std::cout << Json{{"files", std::move(files)}}.dump(2, ' ', false, Json::error_handler_t::replace) << "\n";
  return all_valid ? 0 : kExitInvalidInput;
}

struct ConvertArgs {
  std::string definition;
  std::string output;
  bool json = false;
};

int run_convert(const ConvertArgs& args) {
  if (!rig::is_build_graph_path(args.output)) return usage_error("--output: a build graph's file name ends in .build.json");
  auto graph = app::convert_definition_file(args.definition, args.output);
  if (!graph) return fail(graph.status());
  if (args.json) {
    std::cout << Json{{"graph", args.output}, {"rig", graph->rig.name}, {"nodes", graph->nodes.size()},
                      {"links", graph->links.size()}}
                     .dump(2)
              << "\n";
  } else {
    std::cerr << "rigel: " << args.definition << " -> " << args.output << " (" << graph->nodes.size() << " nodes, "
              << graph->links.size() << " links)\n";
  }
  return 0;
}

int run_graph(const BuildArgs& args) {
  if (!rig::is_build_graph_path(args.definition))
    return usage_error(args.definition + ": not a build graph (the name ends in .build.json); build a definition "
                                         "with `rigel build`");
  // What builds but not as drawn is said before building.
  for (const rig::Diagnostic& d : rig::check_build_graph(args.definition).warnings)
    std::cerr << d.str() << " (warning)\n";
  return run_build(args);
}

}  // namespace

struct GraphCommands::State {
  CLI::App* graph_cmd = nullptr;
  CLI::App* run_cmd = nullptr;
  CLI::App* convert_cmd = nullptr;
  CLI::App* validate_cmd = nullptr;
  BuildArgs run;
  ConvertArgs convert;
  ValidateArgs validate;
};

GraphCommands::GraphCommands() : state_(std::make_unique<State>()) {}
GraphCommands::~GraphCommands() = default;

void add_graph_commands(CLI::App& app, GraphCommands& commands) {
  GraphCommands::State& s = commands.state();
  s.graph_cmd = app.add_subcommand("graph", "Build graphs: a rig build as an execution graph (.build.json)");
  s.graph_cmd->require_subcommand(1);
  s.run_cmd = s.graph_cmd->add_subcommand("run", "Build a build graph onto a character");
  s.run_cmd->footer("Example:\n  rigel graph run biped.build.json -o hero.rigel\n"
                    "  rigel graph run arm.build.json --character tests/data/gltf/rigify_human_metarig.glb --steps 5 -o partial.rigel");
  s.run_cmd->add_option("GRAPH", s.run.definition, "Build graph (.build.json)")->required();
  s.run_cmd->add_option("--character", s.run.character,
                        "Character to build on (.glb, .gltf, .bvh, .rigel); default: the graph's geometry");
  s.run_cmd->add_option("-o,--output", s.run.output, "Scene file to write (.rigel)")->required();
  s.run_cmd->add_option("--steps", s.run.steps, "Stop after this many build steps")->check(CLI::NonNegativeNumber);
  s.run_cmd->add_flag("--json", s.run.json, "Print a JSON summary on stdout");

  s.convert_cmd = s.graph_cmd->add_subcommand("convert", "Make the build graph of a rig definition");
  s.convert_cmd->footer("Example:\n  rigel graph convert examples/biped.rig.xml -o biped.build.json");
  s.convert_cmd->add_option("DEFINITION", s.convert.definition, "Rig definition (.rig.xml, .rig.json)")->required();
  s.convert_cmd->add_option("-o,--output", s.convert.output, "Build graph to write (.build.json)")->required();
  s.convert_cmd->add_flag("--json", s.convert.json, "Print a JSON summary on stdout");

  s.validate_cmd = s.graph_cmd->add_subcommand("validate", "Check build graphs: every problem with its node and socket");
  s.validate_cmd->footer("Example:\n  rigel graph validate biped.build.json --json");
  s.validate_cmd->add_option("GRAPH", s.validate.files, "Build graphs (.build.json)")->required();
  s.validate_cmd->add_flag("--json", s.validate.json, "Print JSON on stdout");
}

std::optional<int> run_graph_commands(const GraphCommands& commands) {
  const GraphCommands::State& s = commands.state();
  if (!*s.graph_cmd) return std::nullopt;
  if (*s.run_cmd) return run_graph(s.run);
  if (*s.convert_cmd) return run_convert(s.convert);
  if (*s.validate_cmd) return run_validate(s.validate);
  return std::nullopt;
}

}  // namespace rigel::cli
