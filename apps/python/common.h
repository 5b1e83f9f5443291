// What the binding files of the Python module share: how a failed rigel
// call becomes a Python exception, how attribute and parameter values cross
// the boundary, and the handles Python holds (docs/PYTHON.md).
//
// Conventions at the boundary (as in .rigel files): angles in degrees,
// vectors as 3-tuples, quaternions (x, y, z, w), matrices 16 floats
// column-major (a 4x4 nested sequence indexed [row][column] is accepted on
// input), enums as their index (their name is accepted on input).
#pragma once

#include <memory>
#include <optional>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "rigel/base/status.h"
#include "rigel/ephemeral/session.h"
#include "rigel/graph/graph.h"
#include "rigel/rig/build.h"
#include "rigel/rig/definition_io.h"
#include "rigel/scene/scene.h"

namespace rigel::python {

namespace py = pybind11;
using graph::NodeId;
using SceneRef = std::shared_ptr<scene::Scene>;

// ---- errors ------------------------------------------------------------------

// A failed Status on its way to Python; module.cc translates it into the
// exception class of its ErrorCode.
class StatusError : public std::exception {
 public:
  explicit StatusError(Status status) : status_(std::move(status)) {}
  const Status& status() const { return status_; }
  const char* what() const noexcept override { return status_.message().c_str(); }

 private:
  Status status_;
};

// Problems of a rig definition (file:line:column each); raised as
// rigel.DefinitionError with a `diagnostics` list.
class DefinitionError : public std::exception {
 public:
  DefinitionError(std::string message, std::vector<rig::Diagnostic> diagnostics)
      : message_(std::move(message)), diagnostics_(std::move(diagnostics)) {}
  const char* what() const noexcept override { return message_.c_str(); }
  const std::vector<rig::Diagnostic>& diagnostics() const { return diagnostics_; }

 private:
  std::string message_;
  std::vector<rig::Diagnostic> diagnostics_;
};

[[noreturn]] inline void raise(Status status) { throw StatusError(std::move(status)); }
[[noreturn]] inline void raise(ErrorCode code, std::string message) { throw StatusError(Status(code, std::move(message))); }
inline void check(const Status& status) {
  if (!status) throw StatusError(status);
}
template <typename T>
T unwrap(Result<T> result) {
  if (!result) throw StatusError(result.status());
  return std::move(result).value();
}

// ---- nodes -------------------------------------------------------------------

// A node as Python holds it: its scene (kept alive) and its UUID, resolved
// on every use, so a handle survives undo and redo of its deletion (which
// give the node a new NodeId but keep its UUID) and a stale handle raises
// NotFoundError instead of touching another node.
struct NodeRef {
  SceneRef scene;
  graph::Uuid uuid;
  mutable std::string last_name;  // refreshed on each use; for the message when the node is gone

  NodeId id() const;  // raises NotFoundError when the node no longer exists
  bool exists() const { return scene->graph().find(uuid).is_valid(); }
};

NodeRef node_ref(const SceneRef& scene, NodeId id);
py::object node_or_none(const SceneRef& scene, NodeId id);
py::list node_list(const SceneRef& scene, const std::vector<NodeId>& ids);

// What Python may pass where a node is wanted: a Node of this scene or a
// node name.
using NodeArg = std::variant<NodeRef, std::string>;
NodeId resolve(const SceneRef& scene, const NodeArg& arg);
std::vector<NodeId> resolve_all(const SceneRef& scene, const std::vector<NodeArg>& args);

// ---- values ------------------------------------------------------------------

py::object to_python(const graph::Value& value);
// Converts `object` to the value type of `plug` (an element plug takes the
// element type, a component plug a double). `where` names the plug in errors.
graph::Value value_from_python(const graph::Graph& graph, const graph::Plug& plug, py::handle object);

math::Vec3 vec3_from_python(py::handle object, const std::string& where);
math::Quat quat_from_python(py::handle object, const std::string& where);
math::Mat4 matrix_from_python(py::handle object, const std::string& where);
py::tuple vec3_to_python(const math::Vec3& v);
py::tuple quat_to_python(const math::Quat& q);
py::tuple matrix_to_python(const math::Mat4& m);

// A rotation given as 3 Euler angles in degrees (XYZ order: x applied
// first, R = Rz * Ry * Rx) or as a quaternion (x, y, z, w).
math::Quat rotation_from_python(py::handle object, const std::string& where);

// types.SimpleNamespace(**fields): small result records.
py::object record(py::dict fields);

// ---- scenes ------------------------------------------------------------------

// Every node type this build knows: scene, ops, the metadata network and
// ephemeral rigs (what the CLI loads files with).
std::shared_ptr<const graph::Registry> registry();
// A scene from a file by its extension (rigel.open): .glb/.gltf and .bvh
// imported, anything else loaded as .rigel.
SceneRef open_any(const std::string& path);

graph::Plug plug_of(const SceneRef& s, const std::string& path);
graph::Plug plug_of(const SceneRef& s, NodeId node, const std::string& attr, int element);
py::object get_plug(const SceneRef& s, const graph::Plug& plug);
void set_plug(const SceneRef& s, const graph::Plug& plug, py::handle value);
py::list connection_list(const SceneRef& s, std::span<const graph::Connection> connections);

// `with scene.transaction("label"):` groups edits into one undo step; an
// exception inside rolls them back.
struct TransactionScope {
  SceneRef scene;
  std::string label;
  bool open = false;
};

// ---- posing ------------------------------------------------------------------

// A posing mode by name (InvalidArgumentError listing the modes).
ephemeral::Mode mode_from(const std::string& name);
std::vector<std::string> mode_names();
// An ephemeralRig node (InvalidArgumentError for another node).
NodeId ephemeral_rig(const SceneRef& s, const NodeArg& arg);

// ---- rigs --------------------------------------------------------------------

// 'xml' or 'json' (InvalidArgumentError naming the syntax).
rig::Syntax syntax_from_name(const std::string& name);
// keep_keys: 'local' or 'world' (InvalidArgumentError).
rig::Build::KeepKeys keep_keys_from_name(const std::string& keep);

// ---- binding entry points ------------------------------------------------------
//
// One file per bound class (wrap_<class>.cc), called in this order by
// module.cc: a signature names the Python classes registered before it, so
// Node is declared before Scene, whose methods take and return nodes (and
// Component before Definition).

void declare_node(py::module_& m);   // wrap_node.cc: the class only
void wrap_transaction(py::module_& m);
void wrap_scene(py::module_& m);     // and rigel.open
void wrap_node(py::module_& m);      // Node's methods
// rig_common.h: the wraps of definitions, components, builds and the metadata network.
void wrap_ephemeral(py::module_& m);  // ephemeral rigs and relations (module functions)
void wrap_keys(py::module_& m);       // keys and keying scopes (module functions)
void wrap_session(py::module_& m);
void wrap_workspace(py::module_& m);
void wrap_rig_tests(py::module_& m);  // rigel.record_rig_tests, rigel.check_rig (rig regression tests)
void wrap_guides(py::module_& m);     // rigel.import_guides (mGear guide templates)
void wrap_pipeline(py::module_& m);  // projects, assets, settings, the log level (module functions)

}  // namespace rigel::python
