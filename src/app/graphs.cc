// The workspace's build graphs (workspace.h, rig/build_graph.h): what the
// graph editor, `rigel graph` and Python's Workspace do with them. A graph
// compiles to a definition, and its rig is built (or live-rebuilt) as a
// definition's is, so everything after compiling is build_definition's.

#include <algorithm>

#include "internal.h"
#include "rigel/app/graphs.h"
#include "rigel/app/workspace.h"
#include "rigel/rig/definition_io.h"

namespace rigel::app {

using internal::make_parent;
using internal::saved;

namespace {

std::vector<GraphProblem> placed(const rig::BuildGraph& graph, std::vector<rig::Diagnostic> diagnostics) {
  std::vector<GraphProblem> out;
  out.reserve(diagnostics.size());
  for (rig::Diagnostic& d : diagnostics) {
    rig::GraphPlace place = rig::place_of(graph, d);
    out.push_back(GraphProblem{std::move(d), std::move(place)});
  }
  return out;
}

// "what: first problem (and N more)".
Status refused(const std::string& field, const std::vector<rig::Diagnostic>& problems) {
  std::string message = field + ": " + problems.front().str();
  if (problems.size() > 1) message += " (and " + std::to_string(problems.size() - 1) + " more)";
  return Status(ErrorCode::kInvalidArgument, message).with_field(field);
}

}  // namespace

rig::NodeKindRegistry Workspace::graph_kinds() const {
  rig::NodeKindRegistry kinds = rig::builtin_node_kinds(factory_.schemas());
  // The root's graph files, as sub-graph nodes of a graph at the root.
  if (auto files = graph_files()) {
    for (const fs::path& rel : *files) {
      rig::BuildGraphParse p = rig::load_build_graph(root_ / rel, factory_.schemas());
      if (p.ok()) (void)kinds.add(rig::subgraph_node_kind(rel.generic_string(), p.graph));
    }
  }
  return kinds;
}

CheckedGraph Workspace::check_graph(const std::string& text, const std::string& where) const {
  rig::BuildGraphParse p = rig::parse_build_graph(text, where, factory_.schemas());
  // Its sub-graphs' files are beside it, or at the root when it is no file.
  std::error_code ec;
  if (!root_.empty() && !fs::is_regular_file(where, ec)) p.graph.folder = root_;
  if (!p.ok()) {
    CheckedGraph out;
    out.problems = placed(p.graph, std::move(p.errors));
    out.graph = std::move(p.graph);
    return out;
  }
  return check_graph(std::move(p.graph));
}

CheckedGraph Workspace::check_graph(rig::BuildGraph graph) const {
  rig::BuildGraphCompile c = rig::compile_build_graph(graph, factory_.schemas());
  CheckedGraph out;
  out.parsed = true;
  out.problems = placed(graph, std::move(c.errors));
  out.warnings = placed(graph, std::move(c.warnings));
  out.order = std::move(c.order);
  out.rig_ids = std::move(c.rig_ids);
  out.definition = std::move(c.definition);
  out.graph = std::move(graph);
  return out;
}

Result<GraphBuildReport> Workspace::build_graph(rig::BuildGraph graph) {
  CheckedGraph c = check_graph(std::move(graph));
  if (!c.ok()) {
    std::vector<rig::Diagnostic> problems;
    for (const GraphProblem& p : c.problems) problems.push_back(p.diagnostic);
    return refused("graph", problems);
  }
  auto built = build_definition(std::move(c.definition));
  if (!built) return built.status().with_field(built.status().field() == "definition" ? "graph" : built.status().field());
  return GraphBuildReport{built->rig, std::move(built->rebuilt), std::move(c.rig_ids)};
}

Result<SavedGraph> Workspace::save_graph(rig::BuildGraph graph, const fs::path& path) {
  if (!rig::is_build_graph_path(path))
    return Status(ErrorCode::kInvalidArgument, "path: '" + path.string() + "' is not a .build.json").with_field("path");
  if (Status s = make_parent(path, "path"); !s) return s;
  graph.rig.version = internal::version_to_save(
      path, graph.rig.version,
      [&]() -> std::optional<std::string> {
        rig::BuildGraphParse old = rig::load_build_graph(path, factory_.schemas());
        if (!old.ok()) return std::nullopt;
        return old.graph.rig.version;
      },
      [&](const std::string& v) {
        rig::BuildGraph same = graph;
        same.rig.version = v;
        return rig::write_build_graph(same);
      });
  if (Status s = saved(rig::save_build_graph(graph, path), "path"); !s) return s;
  graph.source = path.string();
  const std::string version = graph.rig.version;
  CheckedGraph c = check_graph(std::move(graph));
  return SavedGraph{path, version, std::move(c.problems)};
}

Result<rig::BuildGraph> Workspace::open_graph(const fs::path& path) const {
  if (!rig::is_build_graph_path(path))
    return Status(ErrorCode::kInvalidArgument, "path: '" + path.string() + "' is not a .build.json").with_field("path");
  std::error_code ec;
  if (!fs::is_regular_file(path, ec))
    return Status(ErrorCode::kNotFound, "path: no file '" + path.string() + "'").with_field("path");
  rig::BuildGraphParse p = rig::load_build_graph(path, factory_.schemas());
  if (!p.ok()) return refused("path", p.errors);
  return std::move(p.graph);
}

Result<RigGraph> Workspace::rig_graph(const std::string& name) {
  auto def = definition(name);
  if (!def) return def.status();
  const fs::path source = def->source;
  std::error_code ec;
  if (!source.empty() && rig::is_build_graph_path(source) && fs::is_regular_file(source, ec)) {
    auto g = open_graph(source);
    if (!g) return g.status();
    return RigGraph{std::move(*g), source, false};
  }
  return RigGraph{rig::convert_definition(*def), {}, true};
}

Result<std::vector<fs::path>> Workspace::graph_files() const {
  if (root_.empty())
    return Status(ErrorCode::kFailedPrecondition, "the workspace has no root folder to list graphs under");
  constexpr int kMaxDepth = 8;
  constexpr std::size_t kMaxFiles = 1000;
  std::vector<fs::path> out;
  std::error_code ec;
  fs::recursive_directory_iterator it(root_, fs::directory_options::skip_permission_denied, ec), end;
  for (; !ec && it != end && out.size() < kMaxFiles; it.increment(ec)) {
    const fs::directory_entry& e = *it;
    const std::string leaf = e.path().filename().string();
    std::error_code sec;
    if (e.is_directory(sec)) {
      if (leaf.starts_with(".") || leaf == "node_modules" || it.depth() >= kMaxDepth - 1 || e.is_symlink(sec))
        it.disable_recursion_pending();
      continue;
    }
    if (e.is_regular_file(sec) && !e.is_symlink(sec) && rig::is_build_graph_path(e.path()))
      out.push_back(e.path().lexically_relative(root_));
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace rigel::app
