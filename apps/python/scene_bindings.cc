// Scene and Node: nodes, attributes, connections, evaluation, time, undo,
// hierarchy, and the files a scene is read from and written to.

#include <cctype>
#include <filesystem>

#include "common.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/io/bvh.h"
#include "rigel/io/bvh_import.h"
#include "rigel/io/gltf_export.h"
#include "rigel/io/gltf_import.h"
#include "rigel/io/scene_file.h"
#include "rigel/rig/meta.h"

namespace rigel::python {
namespace {

// Every node type this build knows: scene, ops, the metadata network and
// ephemeral rigs (what the CLI loads files with).
std::shared_ptr<const graph::Registry> registry() { return ephemeral::default_registry(); }

SceneRef new_scene() { return std::make_shared<scene::Scene>(registry()); }

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

SceneRef open_any(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".glb" || ext == ".gltf") return import_gltf(path, 1.0);
  if (ext == ".bvh") return import_bvh(path, 1.0, false);
  return load_scene(path);
}

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

py::object attribute_info(const graph::AttrSpec& spec) {
  py::dict d;
  d["name"] = spec.name;
  d["type"] = graph::type_name(spec.type);
  d["input"] = (spec.flags & graph::kInput) != 0;
  d["output"] = (spec.flags & graph::kOutput) != 0;
  d["keyable"] = (spec.flags & graph::kKeyable) != 0;
  d["storable"] = (spec.flags & graph::kStorable) != 0;
  d["hidden"] = (spec.flags & graph::kHidden) != 0;
  d["angle"] = (spec.flags & graph::kAngle) != 0;
  d["enum_names"] = spec.enum_names;
  d["default"] = to_python(std::holds_alternative<std::monostate>(spec.default_value) ? graph::zero_value(spec.type)
                                                                                       : spec.default_value);
  return record(d);
}

// `with scene.transaction("label"):` groups edits into one undo step; an
// exception inside rolls them back.
struct TransactionScope {
  SceneRef scene;
  std::string label;
  bool open = false;
};

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

}  // namespace

void bind_scene(py::module_& m) {
  py::class_<scene::Scene, SceneRef> scene_cls(m, "Scene", R"(A scene: a dependency graph of nodes with a transform hierarchy.

Scene() is empty; Scene.load / Scene.import_gltf / Scene.import_bvh (or
rigel.open) read files. Every node type rigel knows is available (scene,
operators, rig metadata, ephemeral rigs). Plugs are named "node.attr",
"node.attr[3]" (an element) or "node.translateX" (a component).)");
  py::class_<NodeRef> node_cls(m, "Node", R"(A node of a scene, held by UUID.

A handle survives renames and undo/redo of its deletion; using a handle to
a node that no longer exists raises NotFoundError.)");

  // ---- files ------------------------------------------------------------------
  scene_cls.def(py::init(&new_scene))
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
          [](const SceneRef& s, const std::string& path, std::optional<std::pair<double, double>> frames, bool bake) {
            io::GltfExportOptions options;
            options.frames = frames;
            options.bake = bake;
            io::GltfExportReport report;
            check(io::export_gltf(*s, path, options, &report));
            return export_report(report);
          },
          py::arg("path"), py::arg("frames") = py::none(), py::arg("bake") = false,
          "Writes .glb or .gltf; `frames` = (first, last) bakes that range. Returns the export report as a dict.");
  m.def("open", &open_any, py::arg("path"),
        "A scene from a file by its extension: .glb/.gltf and .bvh are imported, anything else loaded as .rigel.");

  // ---- nodes --------------------------------------------------------------------
  scene_cls
      .def(
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

  // ---- attributes and connections --------------------------------------------------
  scene_cls
      .def(
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

  // ---- evaluation and time --------------------------------------------------------
  scene_cls
      .def(
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

  // ---- undo ---------------------------------------------------------------------------
  py::class_<TransactionScope>(m, "Transaction", "Context manager from Scene.transaction(label).")
      .def(
          "__enter__",
          [](TransactionScope& t) -> TransactionScope& {
            if (t.open) raise(ErrorCode::kInvalidArgument, "transaction '" + t.label + "' is already open");
            t.scene->graph().begin_transaction(t.label);
            t.open = true;
            return t;
          },
          py::return_value_policy::reference_internal)
      .def("__exit__", [](TransactionScope& t, py::object type, py::object, py::object) {
        if (!t.open) return false;
        t.open = false;
        if (type.is_none()) {
          t.scene->graph().commit_transaction();
        } else {
          t.scene->graph().rollback_transaction();
        }
        return false;
      });
  scene_cls
      .def(
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

  // ---- hierarchy ------------------------------------------------------------------------
  scene_cls
      .def(
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

  // ---- Node -------------------------------------------------------------------------------
  node_cls
      .def_property_readonly("scene", [](const NodeRef& n) { return n.scene; })
      .def_property(
          "name", [](const NodeRef& n) { return n.scene->graph().node(n.id())->name(); },
          [](NodeRef& n, const std::string& name) {
            check(n.scene->graph().rename(n.id(), name));
            n.last_name = name;
          },
          "The node's name; assigning renames it (one undo step).")
      .def_property_readonly("uuid", [](const NodeRef& n) { return n.uuid.str(); })
      .def_property_readonly("type", [](const NodeRef& n) { return n.scene->graph().node(n.id())->type().name(); })
      .def_property_readonly("exists", &NodeRef::exists)
      .def(
          "rename",
          [](NodeRef& n, const std::string& name) {
            check(n.scene->graph().rename(n.id(), name));
            n.last_name = name;
          },
          py::arg("name"))
      .def(
          "delete", [](const NodeRef& n) { check(n.scene->graph().delete_node(n.id())); }, "Deletes the node.")
      .def(
          "attributes",
          [](const NodeRef& n, bool hidden) {
            std::vector<std::string> names;
            for (const graph::AttrSpec& a : n.scene->graph().node(n.id())->type().attrs())
              if (hidden || (a.flags & graph::kHidden) == 0) names.push_back(a.name);
            return names;
          },
          py::arg("hidden") = true, "Attribute names of the node's type.")
      .def(
          "attribute",
          [](const NodeRef& n, const std::string& attr) {
            const graph::NodeType& t = n.scene->graph().node(n.id())->type();
            const graph::AttrIndex i = t.attr_find(attr);
            if (i == graph::kNoAttr) raise(ErrorCode::kNotFound, t.name() + " '" + n.last_name + "' has no attribute '" + attr + "'");
            return attribute_info(t.attr(i));
          },
          py::arg("attr"),
          "What an attribute is: name, type, input/output, keyable, storable, hidden, angle, enum_names, default.")
      .def(
          "get",
          [](const NodeRef& n, const std::string& attr, int element) {
            return get_plug(n.scene, plug_of(n.scene, n.id(), attr, element));
          },
          py::arg("attr"), py::arg("element") = -1, "The evaluated value of an attribute (or one element).")
      .def(
          "set",
          [](const NodeRef& n, const std::string& attr, py::object value, int element) {
            set_plug(n.scene, plug_of(n.scene, n.id(), attr, element), value);
          },
          py::arg("attr"), py::arg("value"), py::arg("element") = -1)
      .def("__getitem__",
           [](const NodeRef& n, const std::string& attr) { return get_plug(n.scene, plug_of(n.scene, n.id(), attr, -1)); })
      .def("__setitem__",
           [](const NodeRef& n, const std::string& attr, py::object value) {
             set_plug(n.scene, plug_of(n.scene, n.id(), attr, -1), value);
           })
      .def(
          "plug",
          [](const NodeRef& n, const std::string& attr) {
            return n.scene->graph().plug_name(plug_of(n.scene, n.id(), attr, -1));
          },
          py::arg("attr"), "\"node.attr\" (checks that the attribute exists).")
      .def(
          "inputs", [](const NodeRef& n) { return connection_list(n.scene, n.scene->graph().node(n.id())->inputs()); },
          "Connections into this node as (src, dst).")
      .def(
          "outputs", [](const NodeRef& n) { return connection_list(n.scene, n.scene->graph().node(n.id())->outputs()); },
          "Connections out of this node as (src, dst).")
      .def_property_readonly(
          "tags", [](const NodeRef& n) { return n.scene->graph().node(n.id())->tags(); }, "The node's string tags.")
      .def(
          "set_tag",
          [](const NodeRef& n, const std::string& key, const std::string& value) {
            check(n.scene->graph().set_tag(n.id(), key, value));
          },
          py::arg("key"), py::arg("value"))
      .def(
          "remove_tag", [](const NodeRef& n, const std::string& key) { check(n.scene->graph().remove_tag(n.id(), key)); },
          py::arg("key"))
      .def_property_readonly(
          "parent", [](const NodeRef& n) { return node_or_none(n.scene, n.scene->graph().parent(n.id())); },
          "The hierarchy parent, or None.")
      .def_property_readonly(
          "children", [](const NodeRef& n) { return node_list(n.scene, n.scene->graph().children(n.id())); })
      .def(
          "set_parent",
          [](const NodeRef& n, std::optional<NodeArg> parent, bool keep_world) {
            check(n.scene->reparent(n.id(), parent ? resolve(n.scene, *parent) : NodeId{}, keep_world));
          },
          py::arg("parent"), py::arg("keep_world") = true)
      .def_property_readonly("world_matrix", [](const NodeRef& n) { return matrix_to_python(n.scene->world_matrix(n.id())); })
      .def_property_readonly("local_matrix", [](const NodeRef& n) { return matrix_to_python(n.scene->local_matrix(n.id())); })
      .def(
          "__eq__",
          [](const NodeRef& a, py::object b) {
            if (!py::isinstance<NodeRef>(b)) return false;
            const NodeRef& r = b.cast<const NodeRef&>();
            return a.scene == r.scene && a.uuid == r.uuid;
          },
          py::is_operator())
      .def("__hash__", [](const NodeRef& n) { return n.uuid.hash(); })
      .def("__repr__", [](const NodeRef& n) {
        if (!n.exists()) return "<rigel.Node '" + n.last_name + "' (deleted)>";
        const graph::Node* node = n.scene->graph().node(n.id());
        return "<rigel.Node '" + node->name() + "' " + node->type().name() + ">";
      });
}

}  // namespace rigel::python
