#include "common.h"

#include <cmath>

#include "rigel/math/rotation.h"

namespace rigel::python {

// ---- nodes -------------------------------------------------------------------

NodeId NodeRef::id() const {
  const NodeId id = scene->graph().find(uuid);
  if (!id.is_valid())
    raise(ErrorCode::kNotFound, "node '" + last_name + "' (" + uuid.str() + ") no longer exists");
  last_name = scene->graph().node(id)->name();
  return id;
}

NodeRef node_ref(const SceneRef& scene, NodeId id) {
  const graph::Node* node = scene->graph().node(id);
  if (node == nullptr) raise(ErrorCode::kNotFound, "stale node handle");
  return NodeRef{scene, node->uuid(), node->name()};
}

py::object node_or_none(const SceneRef& scene, NodeId id) {
  if (!id.is_valid() || scene->graph().node(id) == nullptr) return py::none();
  return py::cast(node_ref(scene, id));
}

py::list node_list(const SceneRef& scene, const std::vector<NodeId>& ids) {
  py::list out;
  for (NodeId id : ids) out.append(py::cast(node_ref(scene, id)));
  return out;
}

NodeId resolve(const SceneRef& scene, const NodeArg& arg) {
  if (const NodeRef* ref = std::get_if<NodeRef>(&arg)) {
    if (ref->scene != scene)
      raise(ErrorCode::kInvalidArgument, "node '" + ref->last_name + "' belongs to another scene");
    return ref->id();
  }
  const std::string& name = std::get<std::string>(arg);
  const NodeId id = scene->graph().find(name);
  if (!id.is_valid()) raise(ErrorCode::kNotFound, "no node named '" + name + "'");
  return id;
}

std::vector<NodeId> resolve_all(const SceneRef& scene, const std::vector<NodeArg>& args) {
  std::vector<NodeId> out;
  out.reserve(args.size());
  for (const NodeArg& a : args) out.push_back(resolve(scene, a));
  return out;
}

// ---- values to Python --------------------------------------------------------

py::tuple vec3_to_python(const math::Vec3& v) { return py::make_tuple(v.x(), v.y(), v.z()); }
py::tuple quat_to_python(const math::Quat& q) { return py::make_tuple(q.x(), q.y(), q.z(), q.w()); }
py::tuple matrix_to_python(const math::Mat4& m) {
  py::tuple t(16);
  for (int i = 0; i < 16; ++i) t[static_cast<std::size_t>(i)] = py::float_(m.data()[i]);  // Eigen: column-major
  return t;
}

namespace {

template <typename T, typename Fn>
py::list list_of(const std::vector<T>& values, Fn&& fn) {
  py::list out;
  for (const T& v : values) out.append(fn(v));
  return out;
}

}  // namespace

py::object to_python(const graph::Value& value) {
  return std::visit(
      [](const auto& v) -> py::object {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, std::monostate>) {
          return py::none();
        } else if constexpr (std::is_same_v<T, bool>) {
          return py::bool_(v);
        } else if constexpr (std::is_same_v<T, std::int64_t>) {
          return py::int_(v);
        } else if constexpr (std::is_same_v<T, double>) {
          return py::float_(v);
        } else if constexpr (std::is_same_v<T, math::Vec3>) {
          return vec3_to_python(v);
        } else if constexpr (std::is_same_v<T, math::Quat>) {
          return quat_to_python(v);
        } else if constexpr (std::is_same_v<T, math::Mat4>) {
          return matrix_to_python(v);
        } else if constexpr (std::is_same_v<T, std::string>) {
          return py::str(v);
        } else if constexpr (std::is_same_v<T, std::vector<bool>>) {
          py::list out;
          for (bool b : v) out.append(py::bool_(b));
          return out;
        } else if constexpr (std::is_same_v<T, std::vector<std::int64_t>>) {
          return list_of(v, [](std::int64_t x) { return py::int_(x); });
        } else if constexpr (std::is_same_v<T, std::vector<double>>) {
          return list_of(v, [](double x) { return py::float_(x); });
        } else if constexpr (std::is_same_v<T, std::vector<math::Vec3>>) {
          return list_of(v, vec3_to_python);
        } else if constexpr (std::is_same_v<T, std::vector<math::Quat>>) {
          return list_of(v, quat_to_python);
        } else if constexpr (std::is_same_v<T, std::vector<math::Mat4>>) {
          return list_of(v, matrix_to_python);
        } else {
          static_assert(std::is_same_v<T, std::vector<std::string>>);
          return list_of(v, [](const std::string& s) { return py::str(s); });
        }
      },
      value);
}

// ---- values from Python ------------------------------------------------------

namespace {

std::string type_of(py::handle object) { return py::str(py::type::of(object).attr("__name__")); }

bool is_text(py::handle object) { return py::isinstance<py::str>(object) || py::isinstance<py::bytes>(object); }

bool is_number(py::handle object) {
  return !is_text(object) && (py::isinstance<py::float_>(object) || py::isinstance<py::int_>(object) ||
                              PyNumber_Check(object.ptr()) != 0);
}

double number(py::handle object, const std::string& where) {
  if (!is_number(object)) raise(ErrorCode::kInvalidArgument, where + ": expected a number, got " + type_of(object));
  const double d = PyFloat_AsDouble(object.ptr());
  if (PyErr_Occurred()) throw py::error_already_set();
  return d;
}

py::sequence sequence(py::handle object, const std::string& where, const char* wanted) {
  if (is_text(object) || !py::isinstance<py::sequence>(object))
    raise(ErrorCode::kInvalidArgument, where + ": expected " + wanted + ", got " + type_of(object));
  return py::reinterpret_borrow<py::sequence>(object);
}

std::vector<double> numbers(py::handle object, std::size_t count, const std::string& where, const char* wanted) {
  py::sequence seq = sequence(object, where, wanted);
  if (seq.size() != count)
    raise(ErrorCode::kInvalidArgument, where + ": expected " + wanted + ", got " + std::to_string(seq.size()) + " items");
  std::vector<double> out;
  for (std::size_t i = 0; i < count; ++i) out.push_back(number(seq[i], where));
  return out;
}

}  // namespace

math::Vec3 vec3_from_python(py::handle object, const std::string& where) {
  const std::vector<double> n = numbers(object, 3, where, "3 numbers (x, y, z)");
  return math::Vec3(n[0], n[1], n[2]);
}

math::Quat quat_from_python(py::handle object, const std::string& where) {
  const std::vector<double> n = numbers(object, 4, where, "4 numbers (x, y, z, w)");
  return math::Quat(n[3], n[0], n[1], n[2]);  // Eigen's constructor takes w first
}

math::Mat4 matrix_from_python(py::handle object, const std::string& where) {
  const char* wanted = "16 numbers (column-major) or 4 rows of 4";
  py::sequence seq = sequence(object, where, wanted);
  math::Mat4 m;
  if (seq.size() == 16) {
    for (int i = 0; i < 16; ++i) m.data()[i] = number(seq[static_cast<std::size_t>(i)], where);
    return m;
  }
  if (seq.size() == 4) {
    for (int r = 0; r < 4; ++r) {
      const std::vector<double> row = numbers(seq[static_cast<std::size_t>(r)], 4, where + " row " + std::to_string(r), "4 numbers");
      for (int c = 0; c < 4; ++c) m(r, c) = row[static_cast<std::size_t>(c)];
    }
    return m;
  }
  raise(ErrorCode::kInvalidArgument, where + ": expected " + wanted + ", got " + std::to_string(seq.size()) + " items");
}

math::Quat rotation_from_python(py::handle object, const std::string& where) {
  py::sequence seq = sequence(object, where, "3 angles in degrees or a quaternion (x, y, z, w)");
  if (seq.size() == 4) return quat_from_python(object, where).normalized();
  const math::Vec3 degrees = vec3_from_python(object, where);
  return math::euler_to_quat(math::to_radians(degrees), math::RotateOrder::kXYZ);
}

namespace {

graph::Value scalar_from_python(py::handle object, graph::ValueType type, const std::vector<std::string>& enum_names,
                                const std::string& where) {
  switch (type) {
    case graph::ValueType::kMessage:
      raise(ErrorCode::kInvalidArgument, where + ": a message attribute holds no value (connect it instead)");
    case graph::ValueType::kBool:
      if (!py::isinstance<py::bool_>(object))
        raise(ErrorCode::kInvalidArgument, where + ": expected a bool, got " + type_of(object));
      return graph::Value(object.cast<bool>());
    case graph::ValueType::kEnum:
      if (py::isinstance<py::str>(object)) {
        const std::string name = object.cast<std::string>();
        for (std::size_t i = 0; i < enum_names.size(); ++i)
          if (enum_names[i] == name) return graph::Value(static_cast<std::int64_t>(i));
        std::string names;
        for (const std::string& n : enum_names) names += (names.empty() ? "" : ", ") + n;
        raise(ErrorCode::kInvalidArgument, where + ": '" + name + "' is not one of " + names);
      }
      [[fallthrough]];
    case graph::ValueType::kInt:
      if (!py::isinstance<py::int_>(object))
        raise(ErrorCode::kInvalidArgument, where + ": expected an int, got " + type_of(object));
      return graph::Value(object.cast<std::int64_t>());
    case graph::ValueType::kDouble:
      return graph::Value(number(object, where));
    case graph::ValueType::kDouble3:
      return graph::Value(vec3_from_python(object, where));
    case graph::ValueType::kQuat:
      return graph::Value(quat_from_python(object, where));
    case graph::ValueType::kMatrix:
      return graph::Value(matrix_from_python(object, where));
    case graph::ValueType::kString:
      if (!py::isinstance<py::str>(object))
        raise(ErrorCode::kInvalidArgument, where + ": expected a str, got " + type_of(object));
      return graph::Value(object.cast<std::string>());
  }
  raise(ErrorCode::kInvalidArgument, where + ": unknown value type");
}

}  // namespace

graph::Value value_from_python(const graph::Graph& graph, const graph::Plug& plug, py::handle object) {
  const std::string where = graph.plug_name(plug);
  const graph::AttrType type = graph.plug_type(plug);
  const graph::AttrSpec& spec = graph.node(plug.node)->type().attr(plug.attr);
  static const std::vector<std::string> kNoNames;
  const std::vector<std::string>& names = plug.component >= 0 ? kNoNames : spec.enum_names;
  if (!type.array) return scalar_from_python(object, type.value, names, where);
  py::sequence seq = sequence(object, where, "a list");
  graph::Value array = graph::zero_value(type);
  for (std::size_t i = 0; i < seq.size(); ++i) {
    const graph::Value element =
        scalar_from_python(seq[i], type.value, names, where + "[" + std::to_string(i) + "]");
    graph::array_set_element(array, type, i, element);
  }
  return array;
}

py::object record(py::dict fields) {
  return py::module_::import("types").attr("SimpleNamespace")(**fields);
}

// ---- posing ------------------------------------------------------------------

std::vector<std::string> mode_names() {
  std::vector<std::string> out;
  for (int i = 0; i < ephemeral::kModeCount; ++i) out.emplace_back(ephemeral::mode_name(static_cast<ephemeral::Mode>(i)));
  return out;
}

ephemeral::Mode mode_from(const std::string& name) {
  if (std::optional<ephemeral::Mode> mode = ephemeral::mode_from_name(name)) return *mode;
  std::string modes;
  for (const std::string& n : mode_names()) modes += (modes.empty() ? "" : ", ") + n;
  raise(ErrorCode::kInvalidArgument, "mode '" + name + "': unknown mode; modes: " + modes);
}

// ---- rigs --------------------------------------------------------------------

rig::Syntax syntax_from_name(const std::string& name) {
  if (name == "xml") return rig::Syntax::kXml;
  if (name == "json") return rig::Syntax::kJson;
  raise(ErrorCode::kInvalidArgument, "syntax '" + name + "': expected 'xml' or 'json'");
}

rig::Build::KeepKeys keep_keys_from_name(const std::string& keep) {
  if (keep == "local") return rig::Build::KeepKeys::kLocal;
  if (keep == "world") return rig::Build::KeepKeys::kWorld;
  raise(ErrorCode::kInvalidArgument, "keep_keys '" + keep + "': expected 'local' or 'world'");
}

}  // namespace rigel::python
