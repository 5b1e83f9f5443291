// The metadata network (docs/RIG.md) on Scene and Node: a scene's rigs,
// components and addresses, and each node's place in the network.

#include "rig_common.h"
#include "rigel/rig/build.h"
#include "rigel/rig/meta.h"

namespace rigel::python {
namespace {

py::object component_record(const SceneRef& s, NodeId meta) {
  const graph::Graph& g = s->graph();
  const NodeId parent = rig::meta_parent(g, meta);
  py::dict d;
  d["name"] = rig::meta_string(g, meta, "componentName");
  d["side"] = rig::meta_string(g, meta, "side");
  d["type"] = rig::meta_string(g, meta, "metaType");
  d["version"] = rig::meta_string(g, meta, "version");
  d["rig_id"] = rig::meta_string(g, meta, "rigId");
  d["parent"] = parent.is_valid() && g.node(parent)->type().name() == rig::kMetaComponentType
                    ? rig::meta_string(g, parent, "componentName")
                    : std::string();
  d["node"] = node_ref(s, meta);
  d["members"] = rig::meta_members(g, meta).size();
  return record(d);
}

py::object rig_record(const SceneRef& s, NodeId root) {
  const graph::Graph& g = s->graph();
  py::list comps;
  for (NodeId c : rig::rig_components(g, root)) comps.append(component_record(s, c));
  py::dict d;
  d["name"] = rig::meta_string(g, root, "rigName");
  d["version"] = rig::meta_string(g, root, "version");
  d["definition"] = rig::meta_string(g, root, "definitionPath");
  const std::string position = rig::meta_string(g, root, "buildPosition");
  d["build_position"] = position.empty() ? 0 : std::stoi(position);
  d["node"] = node_ref(s, root);
  d["components"] = comps;
  return record(d);
}

NodeId rig_node(const SceneRef& s, const NodeArg& rig) {
  if (const std::string* name = std::get_if<std::string>(&rig)) {
    const NodeId r = rig::find_rig(s->graph(), *name);
    if (!r.is_valid()) raise(ErrorCode::kNotFound, "the scene has no rig '" + *name + "'");
    return r;
  }
  return resolve(s, rig);
}

void require_meta(const NodeRef& n, NodeId id) {
  if (!rig::is_meta_node(n.scene->graph(), id))
    raise(ErrorCode::kInvalidArgument, "'" + n.scene->graph().node(id)->name() + "' is not a meta node");
}

void def_scene_methods(py::module_& m) {
  auto cls = py::reinterpret_borrow<py::class_<scene::Scene, SceneRef>>(m.attr("Scene"));
  cls
      .def(
          "rigs",
          [](const SceneRef& s) {
            py::list out;
            for (NodeId r : rig::list_rigs(s->graph())) out.append(rig_record(s, r));
            return out;
          },
          "The rigs: name, version, definition path, build_position, node (metaRoot), components.")
      .def(
          "find_rig", [](const SceneRef& s, const std::string& name) { return node_or_none(s, rig::find_rig(s->graph(), name)); },
          py::arg("name"), "The metaRoot of rig `name`, or None.")
      .def(
          "resolve",
          [](const SceneRef& s, const std::string& address) { return node_ref(s, unwrap(rig::resolve_address(s->graph(), address))); },
          py::arg("address"), "The node at a nameless address 'RIG:COMPONENT[/joint[J]]/NAME[I]'.")
      .def(
          "find_component",
          [](const SceneRef& s, const NodeArg& rig, const std::string& key) {
            const NodeId r = rig_node(s, rig);
            return node_or_none(s, rig::find_component(s->graph(), r, key));
          },
          py::arg("rig"), py::arg("key"), "A component meta node of a rig (metaRoot or rig name) by rigId or name.")
      .def(
          "remove_rig",
          [](const SceneRef& s, const std::string& name) {
            std::unique_ptr<rig::Build> b = unwrap(rig::Build::reopen(*s, name, factory()));
            check(b->remove());
          },
          py::arg("name"), "Removes a rig: exactly what its metadata network links to.");
}

void def_node_methods(py::module_& m) {
  auto cls = py::reinterpret_borrow<py::class_<NodeRef>>(m.attr("Node"));
  cls
      .def_property_readonly(
          "component", [](const NodeRef& n) { return node_or_none(n.scene, rig::component_of(n.scene->graph(), n.id())); },
          "The meta node (metaComponent or metaRoot) that built this node, or None.")
      .def_property_readonly(
          "rig", [](const NodeRef& n) { return node_or_none(n.scene, rig::rig_of(n.scene->graph(), n.id())); },
          "The metaRoot above this node, or None.")
      .def_property_readonly(
          "address", [](const NodeRef& n) { return unwrap(rig::address_of(n.scene->graph(), n.id())); },
          "The node's nameless address (raises NotFoundError when it is not part of a rig).")
      .def_property_readonly(
          "meta_parent", [](const NodeRef& n) { return node_or_none(n.scene, rig::meta_parent(n.scene->graph(), n.id())); })
      .def(
          "meta_children",
          [](const NodeRef& n) {
            const NodeId id = n.id();
            require_meta(n, id);
            return node_list(n.scene, rig::meta_children(n.scene->graph(), id));
          },
          "Component meta nodes directly under this metaRoot / metaComponent.")
      .def(
          "members",
          [](const NodeRef& n) {
            const NodeId id = n.id();
            require_meta(n, id);
            return node_list(n.scene, rig::meta_members(n.scene->graph(), id));
          },
          "Every node this meta node built.")
      .def(
          "meta_connection",
          [](const NodeRef& n, const std::string& role, int index) {
            const NodeId id = n.id();
            require_meta(n, id);
            return node_ref(n.scene, unwrap(rig::get_meta_connection(n.scene->graph(), id, role, index)));
          },
          py::arg("role"), py::arg("index") = 0, "getMetaNodeConnection: the member with this role (or step) and index.")
      .def(
          "meta_child",
          [](const NodeRef& n, const std::string& rig_id) {
            const NodeId id = n.id();
            require_meta(n, id);
            return node_or_none(n.scene, rig::get_meta_child_by_id(n.scene->graph(), id, rig_id));
          },
          py::arg("rig_id"), "getMetaChildById: a direct child component by rigId, or None.");
}

}  // namespace

void wrap_meta(py::module_& m) {
  def_scene_methods(m);
  def_node_methods(m);
}

}  // namespace rigel::python
