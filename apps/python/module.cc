// The extension `rigel._rigel` (the package `rigel` re-exports it;
// docs/PYTHON.md). This file defines the exceptions: every failing rigel
// call raises a subclass of rigel.Error chosen by its ErrorCode, with
// rigel's message, which names the place (file:line, node.attr, component),
// and, when rigel names the input at fault, `field` (its Python name).

#include <array>
#include <cctype>

#include "common.h"
#include "rig_common.h"
#include "rigel/tools/build_functions.h"

namespace rigel::python {
namespace {

// Exception classes by ErrorCode (index = code); [0] is rigel.Error itself.
// Owned by the module (module attributes), so plain pointers here are fine.
std::array<PyObject*, 9> exception_classes{};
PyObject* definition_error = nullptr;

struct ExceptionSpec {
  ErrorCode code;
  const char* name;
  PyObject* builtin;  // the standard exception it also derives from
  const char* doc;
};

// An API name (Status::field(), camelCase: magnetFraction, definitionOut) as
// Python spells it (magnet_fraction, definition_out).
std::string python_name(const std::string& field) {
  std::string out;
  for (char c : field) {
    if (std::isupper(static_cast<unsigned char>(c))) {
      out += '_';
      out += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    } else {
      out += c;
    }
  }
  return out;
}

PyObject* make_exception(py::module_& m, const char* name, PyObject* bases, const char* doc) {
  const std::string qualified = std::string("rigel.") + name;
  PyObject* cls = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, bases, nullptr);
  if (cls == nullptr) throw py::error_already_set();
  m.add_object(name, py::reinterpret_borrow<py::object>(cls));
  return cls;
}

void define_exceptions(py::module_& m) {
  PyObject* base = make_exception(m, "Error", PyExc_Exception,
                                  "Base of every rigel error; `code` names the kind (rigel's ErrorCode).");
  PyObject_SetAttrString(base, "code", py::str("error").ptr());
  exception_classes.fill(base);
  const ExceptionSpec specs[] = {
      {ErrorCode::kInvalidArgument, "InvalidArgumentError", PyExc_ValueError, "An unusable argument (bad name, wrong type)."},
      {ErrorCode::kNotFound, "NotFoundError", PyExc_LookupError, "A node, attribute, plug, rig or file that does not exist."},
      {ErrorCode::kAlreadyExists, "AlreadyExistsError", PyExc_ValueError, "A name or connection that is already taken."},
      {ErrorCode::kCycle, "CycleError", PyExc_ValueError, "A connection or parenting that would close a cycle."},
      {ErrorCode::kParseError, "ParseError", PyExc_ValueError, "A file that is not well-formed."},
      {ErrorCode::kIoError, "IoError", PyExc_OSError, "The operating system refused a read or write."},
      {ErrorCode::kUnsupported, "UnsupportedError", PyExc_NotImplementedError, "A version or feature this build does not know."},
      {ErrorCode::kFailedPrecondition, "StateError", PyExc_RuntimeError, "Well-formed, but the scene cannot do it in its state (nothing selected, nothing to undo)."},
  };
  for (const ExceptionSpec& s : specs) {
    py::tuple bases = py::make_tuple(py::handle(base), py::handle(s.builtin));
    PyObject* cls = make_exception(m, s.name, bases.ptr(), s.doc);
    PyObject_SetAttrString(cls, "code", py::str(error_code_name(s.code)).ptr());
    exception_classes[static_cast<std::size_t>(s.code)] = cls;
  }
  py::tuple bases = py::make_tuple(py::handle(base), py::handle(PyExc_ValueError));
  definition_error = make_exception(m, "DefinitionError", bases.ptr(),
                                    "Problems of a rig definition; `diagnostics` lists each with file, line and column.");
  PyObject_SetAttrString(definition_error, "code", py::str("definition").ptr());
  // The input at fault (an argument's name) when rigel names one, else None.
  PyObject_SetAttrString(base, "field", Py_None);

  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const StatusError& e) {
      const Status& s = e.status();
      const auto index = static_cast<std::size_t>(s.code());
      PyObject* cls = index < exception_classes.size() ? exception_classes[index] : exception_classes[0];
      if (s.field().empty()) {
        PyErr_SetString(cls, s.message().c_str());
        return;
      }
      // The input at fault in Python's spelling, in `field` and in the
      // message: "magnet_fraction: ...", not "magnetFraction: ...".
      const std::string field = python_name(s.field());
      std::string message = s.message();
      if (message.rfind(s.field() + ": ", 0) == 0) message = field + ": " + message.substr(s.field().size() + 2);
      py::object instance = py::reinterpret_borrow<py::object>(cls)(message);
      instance.attr("field") = field;
      PyErr_SetObject(cls, instance.ptr());
    } catch (const DefinitionError& e) {
      py::object instance = py::reinterpret_borrow<py::object>(definition_error)(e.what());
      instance.attr("diagnostics") = py::cast(e.diagnostics());
      PyErr_SetObject(definition_error, instance.ptr());
    }
  });
}

}  // namespace
}  // namespace rigel::python

PYBIND11_MODULE(_rigel, m) {
  using namespace rigel::python;
  m.doc() = "rigel: a character-rigging engine (scene graph, rig definitions and builds, ephemeral rigs)";
  // Build graphs name build functions: the shipped ones are there before any file is read.
  rigel::tools::register_build_functions();
  define_exceptions(m);
  declare_node(m);
  wrap_transaction(m);
  wrap_scene(m);
  wrap_node(m);
  wrap_diagnostic(m);
  wrap_guide(m);
  wrap_control_style(m);
  declare_component(m);
  wrap_definition(m);
  wrap_component(m);
  wrap_schemas(m);
  wrap_rig_build(m);
  wrap_meta(m);
  wrap_build_graph(m);
  wrap_component_types(m);
  wrap_serve(m);
  wrap_ephemeral(m);
  wrap_keys(m);
  wrap_session(m);
  wrap_workspace(m);
  wrap_pipeline(m);
  wrap_rig_tests(m);
  wrap_guides(m);
}
