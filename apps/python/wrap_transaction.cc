// rigel.Transaction: what Scene.transaction(label) returns, a context
// manager making the edits inside one undo step.

#include "common.h"

namespace rigel::python {

void wrap_transaction(py::module_& m) {
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
}

}  // namespace rigel::python
