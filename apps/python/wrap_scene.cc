// rigel.Scene: the files a scene is read from and written to, its nodes,
// attributes and connections, evaluation and time, undo and hierarchy; and
// rigel.open.

#include <filesystem>

#include "common.h"
#include "rigel/app/workspace.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/io/bvh.h"
#include "rigel/io/bvh_import.h"
#include "rigel/io/gltf_export.h"
#include "rigel/io/gltf_import.h"
#include "rigel/io/scene_file.h"

namespace rigel::python {

// Every node type this build knows: scene, ops, the metadata network and
// ephemeral rigs (what the CLI loads files with).
std::shared_ptr<const graph::Registry> registry() { return ephemeral::default_registry(); }

SceneRef load_scene(const std::string& path) { return SceneRef(unwrap(io::load_scene(path, registry()))); }

SceneRef import_gltf(const std::string& path, double scale) {
  io::GltfImportOptions options;
  options.scale = scale;
  options.registry = registry();
  return SceneRef(unwrap(io::import_gltf(path, options)));
}

SceneRef import_bvh(const std::string& path, double scale, bool skip_end_sites) {
  io::BvhFile file = unwrap(io::load_bvh(path));
  io::BvhImportOptions options;
  options.scale = scale;
  options.skip_end_sites = skip_end_sites;
  options.registry = registry();
  return SceneRef(unwrap(io::import_bvh(file, options)));
}

SceneRef open_any(const std::string& path) { return SceneRef(unwrap(app::open_scene(path))); }

graph::Plug plug_of(const SceneRef& s, const std::string& path) { return unwrap(s->graph().plug_find(path)); }

graph::Plug plug_of(const SceneRef& s, NodeId node, const std::string& attr, int element) {
  return unwrap(s->graph().plug_find(node, attr, element));
}

py::object get_plug(const SceneRef& s, const graph::Plug& plug) { return to_python(unwrap(s->graph().evaluate(plug))); }

void set_plug(const SceneRef& s, const graph::Plug& plug, py::handle value) {
  check(s->graph().set_value(plug, value_from_python(s->graph(), plug, value)));
}

py::list connection_list(const SceneRef& s, std::span<const graph::Connection> connections) {
  py::list out;
  for (const graph::Connection& c : connections)
    out.append(py::make_tuple(s->graph().plug_name(c.src), s->graph().plug_name(c.dst)));
  return out;
}

namespace {

using SceneClass = py::class_<scene::Scene, SceneRef>;

SceneRef new_scene() { return std::make_shared<scene::Scene>(registry()); }

py::dict export_report(const io::GltfExportReport& r) {
  py::dict d;
  d["nodes"] = r.node_count;
  d["meshes"] = r.mesh_count;
  d["skins"] = r.skin_count;
  d["animations"] = r.animation_count;
  d["channels"] = r.channel_count;
  d["baked"] = r.baked;
  d["bake_reason"] = r.bake_reason;
  d["first_frame"] = r.first_frame;
  d["last_frame"] = r.last_frame;
  d["notes"] = r.notes;
  return d;
}

void def_files(py::module_& m, SceneClass& cls) {
  cls.def(py::init(&new_scene))
      .def_static("load", &load_scene, py::arg("path"), "Reads a .rigel scene file.")
      .def_static("import_gltf", &import_gltf, py::arg("path"), py::arg("scale") = 1.0,
                  "Imports a .glb/.gltf (joints, meshes, skins, blend shapes, clips); `scale` changes units.")
      .def_static("import_bvh", &import_bvh, py::arg("path"), py::arg("scale") = 1.0, py::arg("skip_end_sites") = false,
                  "Imports a BVH file (joints and motion curves).")
      .def(
          "save", [](const SceneRef& s, const std::string& path) { check(io::save_scene(*s, path)); }, py::arg("path"),
          "Writes a .rigel scene file atomically.")
      .def(
          "to_text", [](const SceneRef& s) { return io::write_scene(*s); },
          "The .rigel text of the scene (deterministic: equal scenes give equal text).")
      .def(
          "export_gltf",
          [](const SceneRef& s, const std::string& path, std::optional<std::pair<double, double>> frames, bool bake,
             bool deform_only) {
            io::GltfExportOptions options;
            options.frames = frames;
            options.bake = bake;
            options.deform_only = deform_only;
            io::GltfExportReport report;
            check(io::export_gltf(*s, path, options, &report));
            return export_report(report);
          },
          py::arg("path"), py::arg("frames") = py::none(), py::arg("bake") = false, py::arg("deform_only") = false,
          "Writes .glb or .gltf; `frames` = (first, last) bakes that range; `deform_only` writes only the skins' "
          "joints and the meshes, baked (a game engine's skeleton). Returns the export report as a dict.");
  m.def("open", &open_any, py::arg("path"),
        "A scene from a file by its extension: .glb/.gltf and .bvh are imported, anything else loaded as .rigel.");
}

void def_nodes(SceneClass& cls) {
  cls.def(
         "node_types", [](const SceneRef& s) { return s->graph().registry().type_names(); },
         "Names of the node types this scene can create.")
      .def(
          "create_node",
          [](const SceneRef& s, const std::string& type, const std::string& name, std::optional<NodeArg> parent) {
            const NodeId p = parent ? resolve(s, *parent) : NodeId{};
            return node_ref(s, unwrap(s->create(type, name, p)));
          },
          py::arg("type"), py::arg("name") = "", py::arg("parent") = py::none(),
          "Creates a node (one undo step). A taken name gets a numeric suffix; `parent` must be a transform.")
      .def(
          "node",
          [](const SceneRef& s, const std::string& key) {
            NodeId id = s->graph().find(key);
            if (!id.is_valid()) {
              if (std::optional<graph::Uuid> u = graph::Uuid::parse(key)) id = s->graph().find(*u);
            }
            if (!id.is_valid()) raise(ErrorCode::kNotFound, "no node named '" + key + "'");
            return node_ref(s, id);
          },
          py::arg("name_or_uuid"), "The node with this name (or UUID); raises NotFoundError.")
      .def(
          "find", [](const SceneRef& s, const std::string& name) { return node_or_none(s, s->graph().find(name)); },
          py::arg("name"), "The node with this name, or None.")
      .def("__contains__", [](const SceneRef& s, const std::string& name) { return s->graph().find(name).is_valid(); })
      .def("__len__", [](const SceneRef& s) { return s->graph().node_count(); })
      .def(
          "nodes",
          [](const SceneRef& s, std::optional<std::string> type) {
            std::vector<NodeId> ids;
            for (NodeId id : s->graph().nodes())
              if (!type || s->graph().node(id)->type().name() == *type) ids.push_back(id);
            return node_list(s, ids);
          },
          py::arg("type") = py::none(), "Every node (of `type`), in creation order.")
      .def(
          "delete", [](const SceneRef& s, const NodeArg& n) { check(s->graph().delete_node(resolve(s, n))); },
          py::arg("node"), "Deletes a node after breaking its connections (one undo step).")
      .def(
          "rename",
          [](const SceneRef& s, const NodeArg& n, const std::string& name) {
            check(s->graph().rename(resolve(s, n), name));
          },
          py::arg("node"), py::arg("name"));
}

void def_attributes(SceneClass& cls) {
  cls.def(
         "get", [](const SceneRef& s, const std::string& plug) { return get_plug(s, plug_of(s, plug)); },
         py::arg("plug"), "The evaluated value of \"node.attr\" (pulls what it depends on).")
      .def(
          "get",
          [](const SceneRef& s, const NodeArg& n, const std::string& attr, int element) {
            return get_plug(s, plug_of(s, resolve(s, n), attr, element));
          },
          py::arg("node"), py::arg("attr"), py::arg("element") = -1)
      .def(
          "set", [](const SceneRef& s, const std::string& plug, py::object value) { set_plug(s, plug_of(s, plug), value); },
          py::arg("plug"), py::arg("value"), "Sets an unconnected input (one undo step).")
      .def(
          "set",
          [](const SceneRef& s, const NodeArg& n, const std::string& attr, py::object value, int element) {
            set_plug(s, plug_of(s, resolve(s, n), attr, element), value);
          },
          py::arg("node"), py::arg("attr"), py::arg("value"), py::arg("element") = -1)
      .def(
          "connect",
          [](const SceneRef& s, const std::string& src, const std::string& dst) {
            check(s->graph().connect(plug_of(s, src), plug_of(s, dst)));
          },
          py::arg("src"), py::arg("dst"), "Connects plug src -> dst (types must match; cycles are refused).")
      .def(
          "disconnect",
          [](const SceneRef& s, const std::string& src, const std::string& dst) {
            check(s->graph().disconnect(plug_of(s, src), plug_of(s, dst)));
          },
          py::arg("src"), py::arg("dst"))
      .def(
          "disconnect_input",
          [](const SceneRef& s, const std::string& dst) { check(s->graph().disconnect_input(plug_of(s, dst))); },
          py::arg("dst"), "Breaks whatever feeds `dst` (nothing when unconnected).")
      .def(
          "source",
          [](const SceneRef& s, const std::string& dst) -> py::object {
            const std::optional<graph::Plug> src = s->graph().source(plug_of(s, dst));
            if (!src) return py::none();
            return py::str(s->graph().plug_name(*src));
          },
          py::arg("dst"), "The plug feeding `dst`, or None.")
      .def(
          "connections",
          [](const SceneRef& s) {
            const std::vector<graph::Connection> c = s->graph().connections();
            return connection_list(s, c);
          },
          "Every connection as (src, dst) plug names, sorted by destination.");
}

void def_evaluation(SceneClass& cls) {
  cls.def(
         "evaluate",
         [](const SceneRef& s, bool parallel) {
           s->graph().evaluate_all(parallel ? graph::Execution::kParallel : graph::Execution::kSerial);
         },
         py::arg("parallel") = true, "Evaluates every dirty node.")
      .def(
          "world_matrix", [](const SceneRef& s, const NodeArg& n) { return matrix_to_python(s->world_matrix(resolve(s, n))); },
          py::arg("node"), "Evaluated world matrix: 16 floats, column-major (translation at [12:15]).")
      .def(
          "local_matrix", [](const SceneRef& s, const NodeArg& n) { return matrix_to_python(s->local_matrix(resolve(s, n))); },
          py::arg("node"))
      .def_property(
          "evaluation", [](const SceneRef& s) { return std::string(graph::evaluation_name(s->graph().evaluation())); },
          [](const SceneRef& s, const std::string& name) {
            s->graph().set_evaluation(unwrap(graph::evaluation_from_name(name)));
          },
          "How evaluate() runs the dirty nodes: 'compiled' (the default: a program made from the graph on each "
          "topology change) or 'interpreted' (the reference; the same values). Not saved, not undoable.")
      .def_property(
          "time", [](const SceneRef& s) { return s->graph().time(); },
          [](const SceneRef& s, double seconds) { s->graph().set_time(seconds); }, "Current time in seconds.")
      .def_property(
          "frame", [](const SceneRef& s) { return s->frame(); }, [](const SceneRef& s, double f) { s->set_frame(f); },
          "Current time in frames (time * fps).")
      .def_property(
          "fps", [](const SceneRef& s) { return s->graph().fps(); },
          [](const SceneRef& s, double fps) { check(s->graph().set_fps(fps)); })
      .def_property(
          "selection", [](const SceneRef& s) { return node_list(s, s->graph().selection()); },
          [](const SceneRef& s, const std::vector<NodeArg>& nodes) { s->graph().select(resolve_all(s, nodes)); });
}

void def_undo(SceneClass& cls) {
  cls.def(
         "transaction",
         [](const SceneRef& s, const std::string& label) { return TransactionScope{s, label, false}; },
         py::arg("label"),
         "`with scene.transaction('label'):` makes the edits inside one undo step; an exception rolls them back.")
      .def(
          "undo", [](const SceneRef& s) { return s->graph().undo(); }, "Undoes one step; False when there is none.")
      .def(
          "redo", [](const SceneRef& s) { return s->graph().redo(); }, "Redoes one step; False when there is none.")
      .def_property_readonly("can_undo", [](const SceneRef& s) { return s->graph().can_undo(); })
      .def_property_readonly("can_redo", [](const SceneRef& s) { return s->graph().can_redo(); })
      .def_property_readonly("undo_label", [](const SceneRef& s) { return s->graph().undo_label(); })
      .def_property_readonly("redo_label", [](const SceneRef& s) { return s->graph().redo_label(); })
      .def_property_readonly("undo_count", [](const SceneRef& s) { return s->graph().undo_count(); })
      .def("clear_history", [](const SceneRef& s) { s->graph().clear_history(); });
}

void def_hierarchy(SceneClass& cls) {
  cls.def(
         "roots", [](const SceneRef& s) { return node_list(s, s->roots()); }, "Transforms without a parent.")
      .def(
          "hierarchy", [](const SceneRef& s) { return node_list(s, s->hierarchy()); },
          "Every transform, depth first, parents before children.")
      .def(
          "reparent",
          [](const SceneRef& s, const NodeArg& child, std::optional<NodeArg> parent, bool keep_world) {
            check(s->reparent(resolve(s, child), parent ? resolve(s, *parent) : NodeId{}, keep_world));
          },
          py::arg("child"), py::arg("parent"), py::arg("keep_world") = true,
          "Parents `child` under `parent` (None: the world); keep_world rewrites its channels so it stays put.");
}

}  // namespace

void wrap_scene(py::module_& m) {
  SceneClass cls(m, "Scene", R"(A scene: a dependency graph of nodes with a transform hierarchy.

Scene() is empty; Scene.load / Scene.import_gltf / Scene.import_bvh (or
rigel.open) read files. Every node type rigel knows is available (scene,
operators, rig metadata, ephemeral rigs). Plugs are named "node.attr",
"node.attr[3]" (an element) or "node.translateX" (a component).)");
  def_files(m, cls);
  def_nodes(cls);
  def_attributes(cls);
  def_evaluation(cls);
  def_undo(cls);
  def_hierarchy(cls);
}

}  // namespace rigel::python
