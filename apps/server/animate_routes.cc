// The JSON API's animator-tool routes (docs/SERVER.md): FK/IK match,
// mirror, bind pose, tween, transfer keys, channel values, spaces, the pose library and
// glTF export. Each reads its request's fields and
// calls the app layer; workspace.cc routes to them.

#include "animate_routes.h"

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "api_fields.h"
#include "rigel/io/gltf_export.h"

namespace rigel::server::routes {

namespace fs = std::filesystem;
using namespace api;
using graph::NodeId;

Json export_scene(app::Workspace& ws, const Json& body) {
  const fs::path path = take(ws.resolve_path(as_string(need(body, "path"), "path"), "path"));
  if (Status s = app::check_export_path(path); !s) refuse(400, "path: " + s.message(), "path");
  io::GltfExportOptions options;
  options.frames = frames_field(body);
  if (const Json* b = opt(body, "bake")) options.bake = as_bool(*b, "bake");
  if (const Json* d = opt(body, "deformOnly")) options.deform_only = as_bool(*d, "deformOnly");
  std::error_code ec;
  if (path.has_parent_path()) fs::create_directories(path.parent_path(), ec);
  if (ec) refuse(409, "path: cannot make the folder " + path.parent_path().string() + ": " + ec.message(), "path");
  io::GltfExportReport report;
  if (Status s = app::export_scene(ws.scene(), path, options, &report); !s)
    refuse(s.code() == ErrorCode::kIoError ? 409 : 400, s.message(), s.field().empty() ? "path" : s.field());
  Json out{{"path", path.string()}, {"nodes", report.node_count},         {"meshes", report.mesh_count},
           {"skins", report.skin_count}, {"animations", report.animation_count}, {"channels", report.channel_count},
           {"baked", report.baked}, {"notes", report.notes}};
  if (report.baked) out["bakedFrames"] = {report.first_frame, report.last_frame};
  return out;
}

Json match(app::Workspace& ws, const Json& body) {
  const std::string rig = as_string(need(body, "rig"), "rig");
  const std::string component = as_string(need(body, "component"), "component");
  const std::string to = as_string(need(body, "to"), "to");
  if (to != "fk" && to != "ik") refuse(400, "to: expected \"fk\" or \"ik\", got \"" + to + "\"", "to");
  tools::MatchOptions options;
  options.to = to == "fk" ? rig::components::MatchSide::kFk : rig::components::MatchSide::kIk;
  if (const auto f = frames_field(body)) {
    options.first = f->first;
    options.last = f->second;
  }
  if (const Json* k = opt(body, "key")) options.key = as_bool(*k, "key");
  const tools::MatchReport r = take(ws.match(rig, component, options));
  Json controls = Json::array();
  for (NodeId c : r.controls) controls.push_back(ws.graph().node(c)->name());
  return Json{{"revision", ws.revision()}, {"frames", r.frames},       {"keys", r.keys},
              {"controls", controls},      {"maxError", r.max_error}, {"worstFrame", r.worst_frame}};
}

Json mirror(app::Workspace& ws, const Json& body) {
  tools::MirrorOptions options;
  auto node = [&](const std::string& ref, const std::string& field) { return ws.node(ref, field); };
  if (auto c = nodes_field(body, "controls", node)) options.controls = std::move(*c);
  if (const Json* a = opt(body, "all")) options.all = as_bool(*a, "all");
  if (const Json* f = opt(body, "flip")) options.flip = as_bool(*f, "flip");
  if (const Json* f = opt(body, "from")) {
    const std::string side = as_string(*f, "from");
    if (side != "L" && side != "R") refuse(400, "from: expected \"L\" or \"R\"", "from");
    options.from = side[0];
  }
  if (const Json* p = opt(body, "plane")) {
    const std::string plane = as_string(*p, "plane");
    if (plane != "yz" && plane != "xy" && plane != "xz") refuse(400, "plane: expected \"yz\", \"xy\" or \"xz\"", "plane");
    options.plane = plane == "yz" ? tools::MirrorPlane::kYZ : plane == "xy" ? tools::MirrorPlane::kXY : tools::MirrorPlane::kXZ;
  }
  if (const auto f = frames_field(body)) {
    options.first = f->first;
    options.last = f->second;
  }
  if (const Json* k = opt(body, "key")) options.key = as_bool(*k, "key");
  if (options.controls.empty() && !options.all) options.controls = ws.selection();
  const tools::MirrorReport r = take(ws.mirror(options));
  Json set = Json::array();
  for (NodeId n : r.set) set.push_back(ws.graph().node(n)->name());
  return Json{{"revision", ws.revision()}, {"frames", r.frames}, {"keys", r.keys}, {"set", set}};
}

Json bind_pose(app::Workspace& ws, const Json& body) {
  auto node = [&](const std::string& ref, const std::string& field) { return ws.node(ref, field); };
  const std::vector<NodeId> nodes = nodes_field(body, "controls", node).value_or(ws.selection());
  bool key = false;
  if (const Json* k = opt(body, "key")) key = as_bool(*k, "key");
  const tools::BindPoseReport r = take(ws.reset_bind_pose(nodes, key));
  Json set = Json::array();
  for (NodeId n : r.set) set.push_back(ws.graph().node(n)->name());
  return Json{{"revision", ws.revision()}, {"channels", r.channels}, {"set", set}};
}

Json tween(app::Workspace& ws, const Json& body) {
  auto target = [&](const std::string& ref, const std::string& field) { return ws.key_target(ref, field); };
  const std::vector<NodeId> nodes = nodes_field(body, "controls", target).value_or(ws.selection());
  std::vector<std::string> attrs;
  if (const Json* a = opt(body, "attrs")) {
    if (!a->is_array()) refuse(400, "attrs: expected an array of attribute names", "attrs");
    for (std::size_t i = 0; i < a->size(); ++i) attrs.push_back(as_string((*a)[i], "attrs[" + std::to_string(i) + "]"));
  }
  const double fraction = as_number(need(body, "fraction"), "fraction");
  bool key = true;
  if (const Json* k = opt(body, "key")) key = as_bool(*k, "key");
  const std::vector<tools::PlugKeys> keys = take(ws.tween(nodes, attrs, fraction, key));
  Json list = Json::array();
  const double fps = ws.graph().fps();
  for (const tools::PlugKeys& k : keys) {
    Json frames = Json::array();
    for (double t : k.times) frames.push_back(app::key_frame(t, fps));
    list.push_back(Json{{"plug", k.name}, {"frames", frames}});
  }
  return Json{{"revision", ws.revision()}, {"keys", list}};
}

Json transfer(app::Workspace& ws, const Json& body) {
  const std::string from = as_string(need(body, "from"), "from");
  const std::string to = as_string(need(body, "to"), "to");
  std::optional<std::array<double, 2>> frames;
  if (const auto f = frames_field(body)) frames = std::array<double, 2>{f->first, f->second};
  double offset = 0;
  if (const Json* o = opt(body, "offset")) offset = as_number(*o, "offset");
  const tools::TransferReport r = take(ws.transfer_keys(from, to, frames, offset));
  const graph::Graph& g = ws.graph();
  Json set = Json::array(), components = Json::array();
  for (NodeId n : r.set) set.push_back(g.node(n)->name());
  for (const auto& [a, b] : r.components) components.push_back(Json{{"from", g.node(a)->name()}, {"to", g.node(b)->name()}});
  Json out{{"revision", ws.revision()}, {"channels", r.channels}, {"keys", r.keys}, {"components", components}, {"set", set}};
  out["frames"] = r.first ? Json::array({*r.first, *r.last}) : Json(nullptr);
  return out;
}

Json channel_values(app::Workspace& ws, const Json& body) {
  auto target = [&](const std::string& ref, const std::string& field) { return ws.key_target(ref, field); };
  const std::vector<NodeId> nodes = nodes_field(body, "controls", target).value_or(ws.selection());
  std::vector<std::string> attrs;
  if (const Json* a = opt(body, "attrs")) {
    if (!a->is_array()) refuse(400, "attrs: expected an array of attribute names", "attrs");
    for (std::size_t i = 0; i < a->size(); ++i) attrs.push_back(as_string((*a)[i], "attrs[" + std::to_string(i) + "]"));
  }
  // "value": one number for every channel, or an array of one per channel.
  std::vector<double> values;
  const Json& v = need(body, "value");
  if (v.is_array()) {
    for (std::size_t i = 0; i < v.size(); ++i) values.push_back(as_number(v[i], "value[" + std::to_string(i) + "]"));
  } else {
    values.push_back(as_number(v, "value"));
  }
  const app::Workspace::ChannelValues r = take(ws.set_channel_values(nodes, attrs, values));
  graph::Graph& g = ws.graph();
  Json channels = Json::array(), keys = Json::array();
  for (const tools::Channel& c : r.channels) {
    const graph::Plug plug{c.node, c.attr, -1};
    const graph::Value v = g.evaluate(c.node, c.attr);
    if (c.component >= 0)  // one component of a vector: "translateY"
      channels.push_back(Json{{"plug", g.plug_name(plug) + "XYZ"[c.component]},
                              {"value", std::get<math::Vec3>(v)[c.component]}});
    else
      channels.push_back(Json{{"plug", g.plug_name(plug)}, {"value", std::get<double>(v)}});
  }
  const double fps = g.fps();
  for (const tools::PlugKeys& k : r.keys) {
    Json frames = Json::array();
    for (double t : k.times) frames.push_back(app::key_frame(t, fps));
    keys.push_back(Json{{"plug", k.name}, {"frames", frames}});
  }
  return Json{{"revision", ws.revision()}, {"channels", channels}, {"keys", keys}};
}

namespace {

Json spaces_json(app::Workspace& ws, NodeId control) {
  const rig::ControlSpaces s = ws.spaces(control);
  Json list = Json::array();
  for (const rig::Space& space : s.spaces)
    list.push_back({{"name", space.name},
                    {"target", space.target.is_valid() ? Json(ws.graph().node(space.target)->name()) : Json(nullptr)}});
  return Json{{"revision", ws.revision()},
              {"control", ws.graph().node(control)->name()},
              {"spaces", list},
              {"current", s.spaces.empty() ? Json(nullptr) : Json(s.spaces[static_cast<std::size_t>(s.current)].name)}};
}

}  // namespace

Json spaces(app::Workspace& ws, const std::string& control) { return spaces_json(ws, take(ws.node(control, "control"))); }

Json space(app::Workspace& ws, const Json& body) {
  const NodeId control = take(ws.node(as_string(need(body, "control"), "control"), "control"));
  const Json* add = opt(body, "add");
  const Json* to = opt(body, "switch");
  if ((add != nullptr) == (to != nullptr)) refuse(400, "give one of \"add\" (a new space's name) or \"switch\"", "add");
  if (add) {
    NodeId target;
    if (const Json* t = opt(body, "target"); t && !t->is_null()) target = take(ws.node(as_string(*t, "target"), "target"));
    const int index = take(ws.add_space(control, as_string(*add, "add"), target));
    Json out = spaces_json(ws, control);
    out["index"] = index;
    return out;
  }
  tools::SpaceSwitchOptions options;
  options.space = as_string(*to, "switch");
  if (const Json* f = opt(body, "frame")) options.frame = as_number(*f, "frame");
  if (const auto f = frames_field(body)) {
    if (options.frame) refuse(400, "frames: give \"frame\" or \"frames\", not both", "frames");
    options.first = f->first;
    options.last = f->second;
  }
  const tools::SpaceSwitchReport r = take(ws.switch_space(control, options));
  return Json{{"revision", ws.revision()}, {"from", r.from},           {"to", r.to},
              {"frames", r.frames},        {"keys", r.keys},           {"maxError", r.max_error},
              {"worstFrame", r.worst_frame}};
}

// ---- the pose library --------------------------------------------------------

Json poses_save(app::Workspace& ws, const Json& body) {
  const std::string library = as_string(need(body, "library"), "library");
  const std::string name = as_string(need(body, "name"), "name");
  std::string rig;
  if (const Json* r = opt(body, "rig")) rig = as_string(*r, "rig");
  auto node = [&](const std::string& ref, const std::string& field) { return ws.node(ref, field); };
  const std::vector<NodeId> controls = nodes_field(body, "controls", node).value_or(std::vector<NodeId>{});
  const tools::SavedPose saved = take(ws.save_pose(library, name, rig, controls));
  return Json{{"revision", ws.revision()}, {"name", name}, {"entries", saved.entries}};
}

Json poses_apply(app::Workspace& ws, const Json& body) {
  const std::string library = as_string(need(body, "library"), "library");
  const std::string name = as_string(need(body, "name"), "name");
  std::string rig;
  if (const Json* r = opt(body, "rig")) rig = as_string(*r, "rig");
  tools::ApplyPoseOptions options;
  auto node = [&](const std::string& ref, const std::string& field) { return ws.node(ref, field); };
  if (auto c = nodes_field(body, "controls", node)) options.controls = std::move(*c);
  if (const Json* m = opt(body, "mirror")) options.mirrored = as_bool(*m, "mirror");
  if (const Json* p = opt(body, "plane")) {
    const std::string plane = as_string(*p, "plane");
    if (plane != "yz" && plane != "xy" && plane != "xz") refuse(400, "plane: expected \"yz\", \"xy\" or \"xz\"", "plane");
    options.plane = plane == "yz" ? tools::MirrorPlane::kYZ : plane == "xy" ? tools::MirrorPlane::kXY : tools::MirrorPlane::kXZ;
  }
  if (const Json* f = opt(body, "fraction")) options.fraction = as_number(*f, "fraction");
  if (const Json* k = opt(body, "key")) options.key = as_bool(*k, "key");
  const tools::ApplyPoseReport r = take(ws.apply_pose(library, name, rig, options));
  Json set = Json::array();
  for (NodeId n : r.set) set.push_back(ws.graph().node(n)->name());
  return Json{{"revision", ws.revision()}, {"set", set},           {"channels", r.channels},
              {"keyed", r.keyed},          {"unpaired", r.unpaired}, {"skipped", r.skipped}};
}

Json poses_list(app::Workspace& ws, const Json& query) {
  const std::vector<tools::PoseInfo> list = take(ws.list_poses(as_string(need(query, "library"), "library")));
  Json poses = Json::array();
  for (const tools::PoseInfo& p : list) {
    Json j{{"name", p.name}, {"rig", p.rig}, {"entries", p.entries}, {"thumbnail", p.thumbnail}};
    if (!p.error.empty()) j["error"] = p.error;
    poses.push_back(std::move(j));
  }
  return Json{{"revision", ws.revision()}, {"poses", poses}};
}

Json poses_remove(app::Workspace& ws, const Json& body) {
  check(ws.remove_pose(as_string(need(body, "library"), "library"), as_string(need(body, "name"), "name")));
  return Json{{"revision", ws.revision()}, {"removed", body.at("name")}};
}

}  // namespace rigel::server::routes
