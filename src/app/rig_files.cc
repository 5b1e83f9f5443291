// A rig definition built onto a character file (rig_files.h).

#include "rigel/app/rig_files.h"

#include "rigel/app/scene_files.h"
#include "rigel/rig/build.h"
#include "rigel/rig/manager.h"
#include "rigel/rig/meta.h"

namespace rigel::app {

fs::path rig_character(const rig::Definition& definition, const fs::path& definition_path, const fs::path& given) {
  if (!given.empty()) return given;
  if (definition.geometry.empty()) return {};
  return definition_path.parent_path() / definition.geometry.front().file;
}

Result<BuiltFile> build_rig_file(const rig::Definition& definition, const fs::path& definition_path,
                                 const rig::ComponentFactory& factory, const BuildFileOptions& options,
                                 std::vector<rig::Diagnostic>* missing) {
  BuiltFile out;
  out.character = rig_character(definition, definition_path, options.character);
  if (out.character.empty())
    return Status(ErrorCode::kInvalidArgument,
                  definition_path.string() + ": the definition names no geometry; give the character")
        .with_field("character");
  auto scene = open_scene(out.character);
  if (!scene) return scene.status().with_context(out.character.string());
  // Every guide joint the character lacks, each at its place, before building.
  if (std::vector<rig::Diagnostic> lacking = rig::check_guide_joints(definition, **scene); !lacking.empty()) {
    const std::size_t n = lacking.size();
    if (missing) *missing = std::move(lacking);
    return Status(ErrorCode::kNotFound, definition_path.string() + ": " + std::to_string(n) + " guide joint" +
                                            (n == 1 ? " is" : "s are") + " missing from " + out.character.string())
        .with_field("guides");
  }
  rig::BuildOptions build_options;
  build_options.edit_mode = options.edit_mode;
  build_options.naming_template = options.naming_template;
  auto build = rig::Build::open(**scene, definition, factory, build_options);
  if (!build) return build.status().with_context(definition_path.string());
  out.of = static_cast<int>((*build)->plan().size());
  if (options.steps > out.of)
    return Status(ErrorCode::kInvalidArgument,
                  "--steps " + std::to_string(options.steps) + ": the build has " + std::to_string(out.of) + " steps")
        .with_field("steps");
  out.steps = options.steps < 0 ? out.of : options.steps;
  for (int i = (*build)->position(); i < out.steps; ++i) {
    if (options.progress) options.progress(i + 1, out.steps);
    if (Status s = (*build)->forward(); !s) return s.with_context(definition_path.string());
  }
  const graph::Graph& g = (*scene)->graph();
  if (const graph::NodeId root = (*build)->root(); root.is_valid()) {
    out.nodes = rig::meta_members(g, root).size();
    for (graph::NodeId c : rig::rig_components(g, root)) out.nodes += rig::meta_members(g, c).size() + 1;
  }
  for (const rig::Component* c : (*build)->components())
    out.components.push_back(BuiltComponent{c->name, c->type, c->rig_id, c->side});
  out.rig = definition.name;
  out.version = definition.version;
  out.scene = std::move(*scene);
  return out;
}

namespace {

// `file`, relative to `from` (or absolute), as a path relative to `to`.
std::string rebased(const std::string& file, const fs::path& from, const fs::path& to) {
  const fs::path p(file);
  if (p.is_absolute() || file.empty()) return file;
  // Folders given as "" are the current one.
  std::error_code ec;
  const fs::path absolute = fs::weakly_canonical(fs::absolute(from.empty() ? p : from / p, ec), ec);
  const fs::path base = fs::weakly_canonical(fs::absolute(to.empty() ? fs::path(".") : to, ec), ec);
  const fs::path relative = absolute.lexically_relative(base);
  return relative.empty() ? absolute.generic_string() : relative.generic_string();
}

}  // namespace

Result<rig::BuildGraph> convert_definition_file(const fs::path& definition_path, const fs::path& graph_path) {
  if (!rig::is_build_graph_path(graph_path))
    return Status(ErrorCode::kInvalidArgument, graph_path.string() + ": a build graph's file name ends in .build.json")
        .with_field("output");
  auto definition = rig::read_definition(definition_path);
  if (!definition) return definition.status();
  rig::BuildGraph graph = rig::convert_definition(*definition);
  const fs::path from = definition_path.parent_path(), to = graph_path.parent_path();
  for (rig::Geometry& g : graph.rig.geometry) g.file = rebased(g.file, from, to);
  for (rig::DataImport& d : graph.rig.data) d.file = rebased(d.file, from, to);
  graph.source = graph_path.string();
  if (Status s = rig::save_build_graph(graph, graph_path); !s) return s;
  return graph;
}

}  // namespace rigel::app
