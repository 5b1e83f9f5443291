// Keys of ephemeral controls as module functions (docs/EPHEMERAL.md): a key
// keys the controls' keying set at the scene's time; a rig's keying scope
// says what that set is.

#include "common.h"
#include "rigel/ephemeral/keying.h"
#include "rigel/ephemeral/rig.h"

namespace rigel::python {

namespace eph = ephemeral;

void wrap_keys(py::module_& m) {
  m.def(
      "set_key", [](const SceneRef& s, const std::vector<NodeArg>& controls) { check(eph::set_key(s->graph(), resolve_all(s, controls))); },
      py::arg("scene"), py::arg("controls"),
      "Keys the keying set of `controls` (their characters, with scope 'character') at the scene's time.");
  m.def(
      "delete_key",
      [](const SceneRef& s, const std::vector<NodeArg>& controls) { check(eph::delete_key(s->graph(), resolve_all(s, controls))); },
      py::arg("scene"), py::arg("controls"), "Removes the keying set's keys at the scene's time.");
  m.def(
      "key_times",
      [](const SceneRef& s, const std::vector<NodeArg>& controls) { return eph::key_times(s->graph(), resolve_all(s, controls)); },
      py::arg("scene"), py::arg("controls"), "Sorted key times in seconds (frames: t * scene.fps).");
  m.def(
      "keying_set",
      [](const SceneRef& s, const std::vector<NodeArg>& controls) {
        return node_list(s, eph::keying_set(s->graph(), resolve_all(s, controls)));
      },
      py::arg("scene"), py::arg("controls"), "What a key on `controls` keys.");
  m.def(
      "has_key", [](const SceneRef& s, const NodeArg& c) { return eph::has_key_now(s->graph(), resolve(s, c)); },
      py::arg("scene"), py::arg("control"), "Whether the control has a key at the scene's time.");
  m.def(
      "is_keyed", [](const SceneRef& s, const NodeArg& c) { return eph::is_keyed(s->graph(), resolve(s, c)); },
      py::arg("scene"), py::arg("control"));
  m.def(
      "key_scope",
      [](const SceneRef& s, const NodeArg& rig) {
        return std::string(eph::key_scope_name(eph::key_scope(s->graph(), ephemeral_rig(s, rig))));
      },
      py::arg("scene"), py::arg("rig"), "'character' or 'controls'.");
  m.def(
      "set_key_scope",
      [](const SceneRef& s, const NodeArg& rig, const std::string& scope) {
        const std::optional<eph::KeyScope> k = eph::key_scope_from_name(scope);
        if (!k) raise(ErrorCode::kInvalidArgument, "key scope '" + scope + "': expected 'character' or 'controls'");
        check(eph::set_key_scope(s->graph(), ephemeral_rig(s, rig), *k));
      },
      py::arg("scene"), py::arg("rig"), py::arg("scope"));
}

}  // namespace rigel::python
