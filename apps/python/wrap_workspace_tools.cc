// rigel.Workspace's transfer keys, move keys and channel values
// (app::Workspace::transfer_keys, move_channel_keys, set_channel_values):
// Python values in, app calls, records out.

#include <array>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "wrap_workspace.h"

namespace rigel::python {

void def_transfer_and_values(WorkspaceClass& cls) {
  cls.def(
         "transfer_keys",
         [](const WorkspaceRef& w, const std::string& from, const std::string& to,
            const std::optional<std::pair<double, double>>& frames, double offset) {
           std::optional<std::array<double, 2>> range;
           if (frames) range = std::array<double, 2>{frames->first, frames->second};
           const tools::TransferReport r =
               edit(w, [&](app::Workspace& ws) { return unwrap(ws.transfer_keys(from, to, range, offset)); });
           py::dict d;
           d["channels"] = r.channels;
           d["keys"] = r.keys;
           py::list components;
           for (const auto& [a, b] : r.components) components.append(py::make_tuple(node_ref(w.scene, a), node_ref(w.scene, b)));
           d["components"] = components;
           d["set"] = node_list(w.scene, r.set);
           d["frames"] = r.first ? py::object(py::make_tuple(*r.first, *r.last)) : py::object(py::none());
           return record(d);
         },
         py::arg("source"), py::arg("target"), py::arg("frames") = py::none(), py::arg("offset") = 0.0,
         R"(Transfers keys from a built component ("hero:arm_L") or a whole character ("hero:") onto another
of the same type ("villain:arm_L", "villain:"): components pair by rigId, else name and side, controls and
switches by role and index, never node names. The keys of source frames `frames` (first, last; default
every key) land at their frame + `offset` with their values and tangents; the target's keys inside that
destination range are replaced, the others kept. One undo step. Returns a record (channels, keys,
components: (source, target) meta nodes, set: the nodes that took keys, frames: the source range).)")
      .def(
          "move_channel_keys",
          [](const WorkspaceRef& w, double to, const std::optional<std::vector<NodeArg>>& controls,
             const std::vector<std::string>& attrs, std::optional<double> from_frame, bool copy) {
            const std::vector<NodeId> ids = key_nodes_arg(w, controls);
            return plug_keys_list(
                w, edit(w, [&](app::Workspace& ws) { return unwrap(ws.move_channel_keys(ids, attrs, to, copy, from_frame)); }));
          },
          py::arg("to"), py::arg("controls") = py::none(), py::arg("attrs") = std::vector<std::string>{},
          py::arg("from_frame") = py::none(), py::arg("copy") = false,
          R"(Moves the keys at frame `from_frame` (default: the current frame) of the channels
set_channel_keys would key (default: the selection's keying group) to frame `to` (with copy=True copies
them there, the keys at `from_frame` kept), keeping their values and tangents; a key already there is
replaced. NotFoundError when none has a key now. Returns the channels' keys as records.)")
      .def(
          "set_channel_values",
          [](const WorkspaceRef& w, const std::variant<double, std::vector<double>>& value,
             const std::optional<std::vector<NodeArg>>& controls, const std::vector<std::string>& attrs) {
            const std::vector<NodeId> ids = key_nodes_arg(w, controls);
            const std::vector<double> values = std::holds_alternative<double>(value)
                                                   ? std::vector<double>{std::get<double>(value)}
                                                   : std::get<std::vector<double>>(value);
            const app::Workspace::ChannelValues r =
                edit(w, [&](app::Workspace& ws) { return unwrap(ws.set_channel_values(ids, attrs, values)); });
            py::dict d;
            py::list channels;
            for (const tools::Channel& c : r.channels) {
              std::string name = w.ws->graph().plug_name(graph::Plug{c.node, c.attr, -1});
              if (c.component >= 0) name += "XYZ"[c.component];
              channels.append(name);
            }
            d["channels"] = channels;
            d["keys"] = plug_keys_list(w, r.keys);
            return record(d);
          },
          py::arg("value"), py::arg("controls") = py::none(), py::arg("attrs") = std::vector<std::string>{},
          R"(Sets scalar channels now (a switch's fkIk, a foot's roll, a finger's curl; default: the selection):
a keyed channel gets a key with the value, a free one is set (and keyed when auto-key is on). A built
rig's control stands for its component's node with that channel (controls=["hero_arm_L_ik"],
attrs=["fkIk"]), and attrs=["translateX"] one component of a vector. `value`: one number, or one per
channel. Returns a record (channels, keys).)")
      .def(
          "channel_box",
          [](const WorkspaceRef& w, const std::optional<std::vector<NodeArg>>& controls) {
            const std::vector<NodeId> ids = key_nodes_arg(w, controls);
            static const char* const kStates[] = {"none", "elsewhere", "here"};
            py::list out;
            for (const app::Workspace::ChannelBox& box : unwrap(w.ws->channel_box(ids))) {
              py::list rows;
              for (const app::Workspace::ChannelRow& r : box.rows) {
                py::dict d;
                d["node"] = node_ref(w.scene, r.node);
                d["attr"] = r.attr;
                d["key_attr"] = r.key_attr;
                d["plug"] = r.plug;
                d["value"] = r.value;
                d["keyed"] = kStates[static_cast<int>(r.state)];
                rows.append(record(d));
              }
              py::dict d;
              d["control"] = node_ref(w.scene, box.control);
              d["channels"] = rows;
              out.append(record(d));
            }
            return out;
          },
          py::arg("controls") = py::none(),
          R"(The channel box of `controls` (default: the selection) now: per control a record (control,
channels), each channel a record (node, attr: what set_channel_values takes, key_attr: what
set_channel_keys keys, plug, value, keyed: "here", "elsewhere" or "none"); vectors as components
(translateX), and a built rig's control lists its component's switches (fkIk, roll, curl, space) too.)");
}

}  // namespace rigel::python
