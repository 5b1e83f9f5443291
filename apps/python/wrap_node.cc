// rigel.Node: a node of a scene held by UUID: its name, type, attributes,
// connections, tags and place in the hierarchy.

#include "common.h"

namespace rigel::python {
namespace {

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

using NodeClass = py::class_<NodeRef>;

void def_identity(NodeClass& cls) {
  cls.def_property_readonly("scene", [](const NodeRef& n) { return n.scene; })
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
          "delete", [](const NodeRef& n) { check(n.scene->graph().delete_node(n.id())); }, "Deletes the node.");
}

void def_attributes(NodeClass& cls) {
  cls.def(
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
          "Connections out of this node as (src, dst).");
}

void def_tags_and_hierarchy(NodeClass& cls) {
  cls.def_property_readonly(
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
      .def_property_readonly("local_matrix", [](const NodeRef& n) { return matrix_to_python(n.scene->local_matrix(n.id())); });
}

void def_identity_operators(NodeClass& cls) {
  cls.def(
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

}  // namespace

void declare_node(py::module_& m) {
  NodeClass(m, "Node", R"(A node of a scene, held by UUID.

A handle survives renames and undo/redo of its deletion; using a handle to
a node that no longer exists raises NotFoundError.)");
}

void wrap_node(py::module_& m) {
  auto cls = py::reinterpret_borrow<NodeClass>(m.attr("Node"));
  def_identity(cls);
  def_attributes(cls);
  def_tags_and_hierarchy(cls);
  def_identity_operators(cls);
}

}  // namespace rigel::python
