// rigel.Workspace's build graphs (app::Workspace's check_graph, build_graph,
// save_graph, open_graph, rig_graph, graph_files): what the graph editor
// does through the JSON API, from Python. A graph is its `.build.json`
// text; a problem is a record naming its node and socket.

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "rigel/app/graphs.h"
#include "rigel/rig/build_graph.h"
#include "wrap_workspace.h"

namespace rigel::python {

namespace fs = std::filesystem;

namespace {

py::list problems_list(const std::vector<app::GraphProblem>& problems) {
  py::list out;
  for (const app::GraphProblem& p : problems) {
    py::dict d;
    d["where"] = p.diagnostic.str();
    d["message"] = p.diagnostic.message;
    d["node"] = p.place.node;
    d["socket"] = p.place.socket;
    out.append(record(d));
  }
  return out;
}

py::dict rig_ids_dict(const std::vector<std::pair<std::string, std::string>>& ids) {
  py::dict d;
  for (const auto& [node, rig_id] : ids) d[py::str(rig_id)] = node;
  return d;
}

// The `.build.json` text a call names and the name its messages give it:
// the text itself ("graph"), or a file's (kNotFound when it is missing).
std::pair<std::string, std::string> graph_source(const WorkspaceRef& w, const std::string& graph) {
  if (graph.find('{') != std::string::npos) return {graph, "graph"};
  const fs::path p = unwrap(w.ws->resolve_path(graph, "graph"));
  std::ifstream in(p, std::ios::binary);
  if (!in) raise(ErrorCode::kNotFound, "graph: cannot read '" + p.string() + "'");
  std::ostringstream text;
  text << in.rdbuf();
  return {text.str(), p.string()};
}

// The graph a call names, read (kInvalidArgument with its first problem
// when its text cannot be read as a graph).
rig::BuildGraph graph_arg(const WorkspaceRef& w, const std::string& graph) {
  const auto [text, where] = graph_source(w, graph);
  app::CheckedGraph c = w.ws->check_graph(text, where);
  if (!c.parsed) raise(ErrorCode::kInvalidArgument, "graph: " + c.problems.front().diagnostic.str());
  return std::move(c.graph);
}

}  // namespace

void def_graphs(WorkspaceClass& cls) {
  cls.def(
         "check_graph",
         [](const WorkspaceRef& w, const std::string& graph) {
           const auto [text, where] = graph_source(w, graph);
           const app::CheckedGraph c = w.ws->check_graph(text, where);
           py::dict d;
           d["ok"] = c.ok();
           d["problems"] = problems_list(c.problems);
           d["warnings"] = problems_list(c.warnings);
           d["order"] = c.order;
           d["rig_ids"] = rig_ids_dict(c.rig_ids);
           return record(d);
         },
         py::arg("graph"),
         "Reads and compiles a build graph (its .build.json text, or a file's path): ok, problems and warnings "
         "(each: where, message, node, socket), order (the nodes the exec chain runs), rig_ids ({rigId: node}: the node each component and call comes from; a for-each's body has one per item).")
      .def(
          "build_graph",
          [](const WorkspaceRef& w, const std::string& graph) {
            rig::BuildGraph g = graph_arg(w, graph);
            app::GraphBuildReport r = edit(w, [&](app::Workspace& ws) { return unwrap(ws.build_graph(std::move(g))); });
            py::dict d;
            d["rig"] = r.rig;
            d["rebuilt"] = r.rebuilt;
            d["rig_ids"] = rig_ids_dict(r.rig_ids);
            return record(d);
          },
          py::arg("graph"),
          "Builds a build graph (its .build.json text, or a file's path), or live-rebuilds only the nodes that "
          "changed, and what reads them, when the scene has its rig (one undo step): rig, rebuilt (rigIds), rig_ids.")
      .def(
          "save_graph",
          [](const WorkspaceRef& w, const std::string& graph, const std::string& path) {
            const fs::path p = unwrap(w.ws->resolve_path(path, "path"));
            app::SavedGraph saved = unwrap(w.ws->save_graph(graph_arg(w, graph), p));
            py::dict d;
            d["path"] = saved.path.string();
            d["version"] = saved.version;
            d["problems"] = problems_list(saved.problems);
            return record(d);
          },
          py::arg("graph"), py::arg("path"),
          "Saves a build graph (its .build.json text) at path (a .build.json), atomically; over a file with other "
          "content the version moves to the next one. A graph that does not compile is saved with its problems: "
          "path, version, problems.")
      .def(
          "rig_graph",
          [](const WorkspaceRef& w, const std::string& rig) {
            app::RigGraph g = unwrap(w.ws->rig_graph(rig));
            py::dict d;
            d["graph"] = rig::write_build_graph(g.graph);
            d["path"] = g.path.string();
            d["converted"] = g.converted;
            return record(d);
          },
          py::arg("rig"),
          "The graph a rig was built from (its file), or its definition converted: graph (.build.json text), path "
          "('' when converted), converted.")
      .def(
          "graph_files", [](const WorkspaceRef& w) {
            std::vector<std::string> out;
            for (const fs::path& f : unwrap(w.ws->graph_files())) out.push_back(f.generic_string());
            return out;
          },
          "The .build.json files under the workspace's root (relative, sorted).");
}

}  // namespace rigel::python
