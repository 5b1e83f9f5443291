// The JSON API of `rigel serve` (workspace.h, docs/SERVER.md): each route
// reads its request's fields, calls the app layer and writes the answer.

#include "workspace.h"

#include "animate_routes.h"
#include "curve_routes.h"
#include "editor_routes.h"
#include "rigging_routes.h"
#include "settings_routes.h"
#include "trail_routes.h"
#include "api_fields.h"

#include <unistd.h>

#include <atomic>
#include <climits>
#include <cmath>
#include <fstream>
#include <sstream>
#include <vector>

#include "rigel/ephemeral/rig.h"
#include "rigel/io/gltf_export.h"
#include "rigel/ops/anim/channel_keys.h"
#include "rigel/rig/definition_io.h"
#include "rigel/rig/manager.h"

namespace rigel::server {

using namespace api;
using graph::NodeId;
using math::Quat;
using math::Vec3;

struct Workspace::Impl {
  explicit Impl(app::Workspace& w) : ws(w) {}

  app::Workspace& ws;

  graph::Graph& g() { return ws.graph(); }
  std::string uuid(NodeId id) { return g().node(id)->uuid().str(); }

  fs::path path_field(const Json& j, const std::string& field) { return take(ws.resolve_path(as_string(j, field), field)); }
  NodeId control_ref(const Json& j, const std::string& field) { return take(ws.control(as_string(j, field), field)); }
  std::vector<NodeId> controls_ref(const Json& j, const std::string& field) {
    if (!j.is_array()) refuse(400, field + ": expected an array of node uuids or names", field);
    std::vector<NodeId> out;
    for (std::size_t i = 0; i < j.size(); ++i) out.push_back(control_ref(j[i], field + "[" + std::to_string(i) + "]"));
    return out;
  }
  // The request's rig: one the scene holds, or (where the route takes one)
  // a rig stepped back to step 0.
  std::string rig_name(const Json& body, bool unbuilt_too = false) {
    const std::string name = as_string(need(body, "rig"), "rig");
    check(ws.check_rig(name, unbuilt_too));
    return name;
  }

  Json uuids_json(const std::vector<NodeId>& ids) {
    Json list = Json::array();
    for (NodeId id : ids) list.push_back(uuid(id));
    return list;
  }
  Json frame_json() { return Json{{"frame", ws.scene().frame()}, {"time", g().time()}}; }

  // The pose answer: every node, or (a drag's answer, "partial") only those listed.
  Json pose_json(app::Space space, const std::vector<app::Trs>& values, bool partial) {
    Json nodes = Json::object();
    // Keys are unique (one per node): append to the ordered map's vector
    // directly instead of its insert, which searches every key (quadratic
    // over a character's hundreds of nodes).
    auto& entries = static_cast<std::vector<std::pair<const std::string, Json>>&>(nodes.get_ref<Json::object_t&>());
    entries.reserve(values.size());
    for (const app::Trs& v : values) {
      const Quat& q = v.rotate;
      entries.emplace_back(uuid(v.node), Json::array({v.translate.x(), v.translate.y(), v.translate.z(), q.x(), q.y(),
                                                      q.z(), q.w(), v.scale.x(), v.scale.y(), v.scale.z()}));
    }
    Json out{{"revision", ws.revision()}};
    out.update(frame_json());
    out["space"] = space == app::Space::kWorld ? "world" : "local";
    out["partial"] = partial;
    out["nodes"] = std::move(nodes);
    return out;
  }

  Json keys_json(const app::KeyReport& k) {
    return Json{{"scope", k.scope.empty() ? Json(nullptr) : Json(k.scope)}, {"frames", k.frames}, {"times", k.times}};
  }

  // ---- routes: the scene ---------------------------------------------------------

  Json get_revision(const Request&, const Json&) { return Json{{"revision", ws.revision()}}; }

  Json get_scene(const Request&, const Json&) {
    const app::SceneSummary s = ws.summary();
    Json modes = Json::array();
    for (int m = 0; m < ephemeral::kModeCount; ++m) modes.push_back(ephemeral::mode_name(static_cast<ephemeral::Mode>(m)));
    Json scopes = Json::object();
    for (const auto& [rig, scope] : s.key_scopes) scopes[rig] = scope;
    Json out{{"revision", ws.revision()}, {"path", ws.scene_path().string()}, {"fps", s.fps}};
    out.update(frame_json());
    out["range"] = Json::array({s.range[0], s.range[1]});
    out["playbackRange"] = s.playback ? Json::array({(*s.playback)[0], (*s.playback)[1]}) : Json();
    out["mode"] = ephemeral::mode_name(s.mode);
    out["modes"] = modes;
    out["autoKey"] = s.auto_key;
    out["keyScopes"] = scopes;
    out["canUndo"] = s.can_undo;
    out["canRedo"] = s.can_redo;
    out["undo"] = s.undo_label;
    out["redo"] = s.redo_label;
    out["selection"] = uuids_json(s.selection);
    out["root"] = ws.root().string();
    out["character"] = ws.character().empty() ? Json(nullptr) : Json(ws.character().string());
    return out;
  }

  Json get_nodes(const Request&, const Json&) {
    Json nodes = Json::array(), controls = Json::array();
    for (const app::NodeEntry& e : ws.nodes()) {
      const graph::Node* n = g().node(e.node);
      nodes.push_back(Json{{"uuid", uuid(e.node)},
                           {"name", n->name()},
                           {"type", n->type().name()},
                           {"parent", e.parent.is_valid() ? Json(uuid(e.parent)) : Json(nullptr)}});
    }
    for (const app::ControlEntry& c : ws.controls()) {
      Json points = Json::array();
      for (const Vec3& v : c.points) points.push_back(vec_json(v));
      controls.push_back(Json{{"uuid", uuid(c.node)},
                              {"name", g().node(c.node)->name()},
                              {"rig", c.rig},
                              {"ephemeral", c.ephemeral},
                              {"group", c.group},
                              {"shape", Json{{"points", std::move(points)}, {"closed", c.closed}, {"color", vec_json(c.color)}}}});
    }
    return Json{{"revision", ws.revision()}, {"nodes", std::move(nodes)}, {"controls", std::move(controls)}};
  }

  Json get_pose(const Request& req, const Json&) {
    auto it = req.query.find("space");
    const std::string space = it == req.query.end() ? "local" : it->second;
    if (space != "local" && space != "world") refuse(400, "space: expected local or world, got '" + space + "'", "space");
    const app::Space sp = space == "world" ? app::Space::kWorld : app::Space::kLocal;
    return pose_json(sp, ws.pose(sp), false);
  }

  // The scene as binary glTF: exported beside nothing, to a private file.
  // GET /api/poses/thumbnail?library=L&name=N: the pose's SVG thumbnail.
  Response get_pose_thumbnail(const Request& req) {
    return Response{200, routes::pose_thumbnail(ws, req.query), "image/svg+xml"};
  }

  Response get_character() {
    static std::atomic<int> counter{0};
    const fs::path tmp = fs::temp_directory_path() /
                         ("rigel-serve-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + ".glb");
    Status s = io::export_gltf(ws.scene(), tmp);
    if (!s) {
      std::error_code ec;
      fs::remove(tmp, ec);
      refuse(409, "the scene cannot be exported as glTF: " + s.message());
    }
    std::ifstream in(tmp, std::ios::binary);
    std::ostringstream bytes;
    bytes << in.rdbuf();
    std::error_code ec;
    fs::remove(tmp, ec);
    return Response{200, bytes.str(), "model/gltf-binary"};
  }

  Json post_save(const Request&, const Json& body) {
    fs::path path;
    if (const Json* p = opt(body, "path")) path = path_field(*p, "path");
    return Json{{"path", take(ws.save(path)).string()}};
  }

  // Writes the scene as glTF at a path inside the root (.glb or .gltf), as
  // `rigel export` does.

  // ---- routes: posing ----------------------------------------------------------

  Json post_select(const Request&, const Json& body) {
    std::vector<NodeId> ids = controls_ref(need(body, "controls"), "controls");
    const Json* add = opt(body, "add");
    ws.select(std::move(ids), add && as_bool(*add, "add"));
    return Json{{"selection", uuids_json(ws.selection())}};
  }

  Json post_mode(const Request&, const Json& body) {
    const std::string name = as_string(need(body, "mode"), "mode");
    auto mode = ephemeral::mode_from_name(name);
    if (!mode) refuse(400, "mode: unknown mode '" + name + "'", "mode");
    ws.set_mode(*mode);
    return Json{{"mode", ephemeral::mode_name(ws.session().mode())}};
  }

  Json options_json() {
    const ephemeral::SessionOptions& o = ws.session().options();
    return Json{{"autoKey", o.auto_key},
                {"magnetFraction", o.magnet_fraction},
                {"magnetRadius", o.magnet_radius},
                {"maxChain", o.max_chain}};
  }

  Json post_options(const Request&, const Json& body) {
    ephemeral::SessionOptions o = ws.session().options();
    if (const Json* j = opt(body, "autoKey")) o.auto_key = as_bool(*j, "autoKey");
    if (const Json* j = opt(body, "magnetFraction")) o.magnet_fraction = as_number(*j, "magnetFraction");
    if (const Json* j = opt(body, "magnetRadius")) o.magnet_radius = as_number(*j, "magnetRadius");
    if (const Json* j = opt(body, "maxChain"))
      o.max_chain = as_int(*j, "maxChain", "a whole number from 0 (no limit) to " + std::to_string(ephemeral::SessionOptions::kMaxChainLimit));
    check(ws.set_options(o));
    return options_json();
  }

  // The answer lists only what moved: the revision after this drag is the
  // caller's pose plus these nodes; "notes" says what the drag could not do
  // (a target out of reach, a bone that would stretch).
  Json drag_json(const app::DragReport& r) {
    Json answer = pose_json(app::Space::kLocal, r.moved, true);
    if (!r.notes.empty()) answer["notes"] = r.notes;
    return answer;
  }

  Json post_drag(const Request&, const Json& body) {
    if (const Json* c = opt(body, "control")) {
      const NodeId control = control_ref(*c, "control");
      const Json& to = need(body, "to");
      if (!to.is_object()) refuse(400, "to: expected {\"t\": [x, y, z], \"q\": [x, y, z, w]}", "to");
      std::optional<Vec3> t;
      std::optional<Quat> q;
      if (const Json* j = opt(to, "t")) t = Vec3(as_numbers<3>(*j, "to.t"));
      if (const Json* j = opt(to, "q")) q = as_quat(*j, "to.q");
      return drag_json(take(ws.drag_to(control, t, q)));
    }
    ephemeral::Delta delta;
    if (const Json* t = opt(body, "translate")) delta.translate = as_numbers<3>(*t, "translate");
    if (const Json* r = opt(body, "rotate")) delta.rotate = as_quat(*r, "rotate");
    if (const Json* s = opt(body, "scale")) delta.scale = as_numbers<3>(*s, "scale");
    return drag_json(take(ws.drag(delta)));
  }

  Json post_release(const Request&, const Json&) {
    ws.release();
    return Json::object();
  }

  Json post_undo(const Request&, const Json&) { return Json{{"label", take(ws.undo())}}; }
  Json post_redo(const Request&, const Json&) { return Json{{"label", take(ws.redo())}}; }

  // ---- routes: time and keys -----------------------------------------------------

  Json post_time(const Request&, const Json& body) {
    if (const Json* f = opt(body, "frame")) {
      check(ws.set_frame(as_number(*f, "frame")));
    } else if (const Json* t = opt(body, "time")) {
      check(ws.set_time(as_number(*t, "time")));
    } else {
      refuse(400, "missing field 'frame' (or 'time')", "frame");
    }
    return frame_json();
  }

  std::vector<NodeId> controls_or_selection(const Json& body) {
    if (const Json* c = opt(body, "controls")) return controls_ref(*c, "controls");
    return ws.selection();
  }

  Json get_keys(const Request& req, const Json&) {
    std::vector<NodeId> controls;
    if (auto it = req.query.find("controls"); it != req.query.end()) {
      Json list = Json::array();
      std::stringstream ss(it->second);
      for (std::string item; std::getline(ss, item, ',');) list.push_back(item);
      controls = controls_ref(list, "controls");
    } else {
      controls = ws.selection();
    }
    return keys_json(ws.keys(controls));
  }

  Json post_key(const Request&, const Json& body) {
    const std::vector<NodeId> controls = controls_or_selection(body);
    const Json* del = opt(body, "delete");
    if (del && as_bool(*del, "delete")) return keys_json(take(ws.delete_key(controls)));
    return keys_json(take(ws.set_key(controls)));
  }

  // Keys on any keyable channel of any rig's controls and switches: one
  // answer entry per keyed plug of the channels (tools/keys.h).
  Json plug_keys_json(const std::vector<tools::PlugKeys>& keys) {
    Json out = Json::array();
    const double fps = g().fps();
    for (const tools::PlugKeys& k : keys) {
      Json frames = Json::array(), values = Json::array();
      for (double t : k.times) frames.push_back(app::key_frame(t, fps));
      for (const graph::Value& v : k.values) {
        if (const auto* d = std::get_if<double>(&v)) values.push_back(*d);
        else if (const auto* p = std::get_if<math::Vec3>(&v)) values.push_back(Json::array({p->x(), p->y(), p->z()}));
        else if (const auto* q = std::get_if<math::Quat>(&v)) values.push_back(Json::array({q->x(), q->y(), q->z(), q->w()}));
      }
      Json entry{{"plug", k.name}, {"frames", frames}, {"times", k.times}, {"values", values}};
      if (!k.in_tangents.empty()) {
        entry["inTangents"] = k.in_tangents;
        entry["outTangents"] = k.out_tangents;
      }
      out.push_back(std::move(entry));
    }
    return out;
  }
  // Nodes with keyable channels: controls (a joint stands for its ephemeral
  // control) and others, such as a limb's fkIkSwitch.
  std::vector<NodeId> key_nodes(const Json& body) {
    const Json* c = opt(body, "controls");
    if (!c) return ws.selection();
    if (!c->is_array()) refuse(400, "controls: expected an array of node uuids or names", "controls");
    std::vector<NodeId> out;
    for (std::size_t i = 0; i < c->size(); ++i) {
      const std::string field = "controls[" + std::to_string(i) + "]";
      out.push_back(take(ws.key_target(as_string((*c)[i], field), field)));
    }
    return out;
  }
  std::vector<std::string> attrs_of(const Json& body) {
    std::vector<std::string> attrs;
    if (const Json* a = opt(body, "attrs")) {
      if (!a->is_array()) refuse(400, "attrs: expected an array of attribute names", "attrs");
      for (std::size_t i = 0; i < a->size(); ++i) attrs.push_back(as_string((*a)[i], "attrs[" + std::to_string(i) + "]"));
    }
    return attrs;
  }

  // A query's comma-separated list ("controls=A,B") as a JSON array of its
  // items, empty ones kept (they are refused by name); empty when absent.
  static Json query_list(const Request& req, const char* key) {
    Json out = Json::array();
    auto it = req.query.find(key);
    if (it == req.query.end()) return out;
    for (std::size_t from = 0; from <= it->second.size();) {
      const std::size_t comma = std::min(it->second.find(',', from), it->second.size());
      out.push_back(it->second.substr(from, comma - from));
      from = comma + 1;
    }
    return out;
  }

  // GET /api/channel-keys?controls=A,B&attrs=x,y: the nodes' own channels'
  // keys (Workspace::channel_keys), changing nothing.
  Json get_channel_keys(const Request& req, const Json&) {
    if (req.query.find("controls") == req.query.end()) refuse(400, "missing query 'controls'", "controls");
    const Json query{{"controls", query_list(req, "controls")}, {"attrs", query_list(req, "attrs")}};
    const std::vector<NodeId> nodes = key_nodes(query);
    return Json{{"revision", ws.revision()}, {"keys", plug_keys_json(take(ws.channel_keys(nodes, attrs_of(query))))}};
  }

  // GET /api/channels[?controls=A,B]: the channel box of the controls (the
  // selection without): each one's keyable channels and its component's
  // switches, values now, keyed here / elsewhere / none.
  Json get_channels(const Request& req, const Json&) {
    Json query = Json::object();
    if (req.query.find("controls") != req.query.end()) query["controls"] = query_list(req, "controls");
    static const char* const kStates[] = {"none", "elsewhere", "here"};
    Json boxes = Json::array();
    for (const app::Workspace::ChannelBox& box : take(ws.channel_box(key_nodes(query)))) {
      Json rows = Json::array();
      for (const app::Workspace::ChannelRow& r : box.rows)
        rows.push_back(Json{{"node", g().node(r.node)->name()},
                            {"attr", r.attr},
                            {"keyAttr", r.key_attr},
                            {"plug", r.plug},
                            {"value", r.value},
                            {"keyed", kStates[static_cast<int>(r.state)]}});
      boxes.push_back(Json{{"control", g().node(box.control)->name()}, {"channels", rows}});
    }
    return Json{{"revision", ws.revision()}, {"frame", ws.scene().frame()}, {"controls", boxes}};
  }

  Json post_channel_keys(const Request&, const Json& body) {
    const std::vector<NodeId> nodes = key_nodes(body);
    const std::vector<std::string> attrs = attrs_of(body);
    const Json* del = opt(body, "delete");
    const Json* value = opt(body, "value");
    const Json* from = opt(body, "from");
    const Json* copy = opt(body, "copy");
    if (const Json* to = opt(body, "moveTo")) {  // the keys at `from` (the current time) moved or copied to a frame
      if (value || (del && as_bool(*del, "delete"))) refuse(400, "moveTo: a move takes no value or delete", "moveTo");
      const double frame = as_number(*to, "moveTo");
      std::optional<double> from_frame;
      if (from) from_frame = as_number(*from, "from");
      const bool copying = copy && as_bool(*copy, "copy");
      return Json{{"revision", ws.revision()},
                  {"keys", plug_keys_json(take(ws.move_channel_keys(nodes, attrs, frame, copying, from_frame)))}};
    }
    if (from || copy) refuse(400, std::string(from ? "from" : "copy") + ": only a move (moveTo) takes it", from ? "from" : "copy");
    if (del && as_bool(*del, "delete")) {
      if (value) refuse(400, "value: a delete takes no value", "value");
      return Json{{"revision", ws.revision()}, {"keys", plug_keys_json(take(ws.delete_channel_keys(nodes, attrs)))}};
    }
    std::optional<double> v;
    if (value) v = as_number(*value, "value");
    // Tangent types of the keys made: "tangent" (both), "inTangent", "outTangent".
    tools::Tangents tangents;
    auto tangent = [&](const char* field) -> std::optional<ops::anim::TangentType> {
      const Json* t = opt(body, field);
      if (!t) return std::nullopt;
      const std::string name = as_string(*t, field);
      auto type = ops::anim::tangent_type_from_name(name);
      if (!type)
        refuse(400, std::string(field) + ": '" + name +
                        "' is not a tangent type (auto, spline, linear, flat, step, stepNext, clamped, plateau, fixed)",
               field);
      return type;
    };
    if (auto both = tangent("tangent")) tangents.in = tangents.out = both;
    if (auto in = tangent("inTangent")) tangents.in = in;
    if (auto out = tangent("outTangent")) tangents.out = out;
    if (tangents.any() && del && as_bool(*del, "delete")) refuse(400, "tangent: a delete takes no tangent", "tangent");
    Json keys = plug_keys_json(take(ws.set_channel_keys(nodes, attrs, v, tangents)));
    return Json{{"revision", ws.revision()}, {"keys", keys}};
  }

  // ---- routes: the graph editor (curve_routes.cc) -------------------------------

  // GET /api/curves[?controls=A,B&first=F&last=L&step=S&euler=0|1]: the
  // curves of the channel box's channels (the selection's without controls).
  Json get_curves(const Request& req, const Json&) {
    Json query = Json::object();
    if (req.query.find("controls") != req.query.end()) query["controls"] = query_list(req, "controls");
    return routes::curves(ws, key_nodes(query), req.query);
  }
  Json post_curve_keys(const Request&, const Json& body) { return routes::curve_keys(ws, body); }

  // ---- routes: scene settings (settings_routes.cc) --------------------------------
  Json post_playback_range(const Request&, const Json& body) { return routes::playback_range(ws, body); }
  Json get_selection_sets(const Request&, const Json&) { return routes::selection_sets(ws); }
  Json get_picker(const Request&, const Json&) { return routes::picker(ws); }

  // ---- routes: motion trails and ghosts (trail_routes.cc) -----------------------
  Json get_trails(const Request& req, const Json&) {
    Json query = Json::object();
    if (req.query.find("controls") != req.query.end()) query["controls"] = query_list(req, "controls");
    return routes::trails(ws, key_nodes(query), req.query);
  }
  Json get_ghosts(const Request& req, const Json&) { return routes::ghosts(ws, req.query); }
  Json post_selection_sets(const Request&, const Json& body) {
    const bool save = body.is_object() && body.value("op", "") == "save";
    return routes::selection_set(ws, body, save && opt(body, "controls") ? key_nodes(body) : std::vector<NodeId>{});
  }

  // ---- routes: rigger actions (rigging_routes.cc) --------------------------------
  Json get_shape(const Request& req, const Json&) { return routes::shape(ws, req.query); }
  Json post_shape(const Request&, const Json& body) { return routes::shape_edit(ws, body); }
  Json post_align(const Request&, const Json& body) { return routes::align(ws, body); }
  Json post_locators(const Request&, const Json& body) { return routes::locators(ws, body); }
  Json post_mirror_joints(const Request&, const Json& body) { return routes::mirror_joints(ws, body); }
  Json post_data_export(const Request&, const Json& body) { return routes::data_export(ws, body); }
  Json post_data_import(const Request&, const Json& body) { return routes::data_import(ws, body); }
  Json get_driven_keys(const Request&, const Json&) { return routes::driven_keys(ws); }
  Json post_driven_keys(const Request&, const Json& body) { return routes::driven_key_edit(ws, body); }

  // ---- routes: build graphs (editor_routes.cc) ------------------------------------
  Json get_graph_palette(const Request&, const Json&) { return routes::graph_palette(ws); }
  Json get_graph_files(const Request&, const Json&) { return routes::graph_files(ws); }
  Json get_graph(const Request& req, const Json&) { return routes::graph_open(ws, req.query); }
  Json post_graph_validate(const Request&, const Json& body) { return routes::graph_validate(ws, body); }
  Json post_graph_build(const Request&, const Json& body) { return routes::graph_build(ws, body); }
  Json post_graph_save(const Request&, const Json& body) { return routes::graph_save(ws, body); }

  // ---- routes: animator tools (animate_routes.cc) ---------------------------------

  Json post_export(const Request&, const Json& body) { return routes::export_scene(ws, body); }
  Json post_match(const Request&, const Json& body) { return routes::match(ws, body); }
  Json post_mirror(const Request&, const Json& body) { return routes::mirror(ws, body); }
  Json post_bind_pose(const Request&, const Json& body) { return routes::bind_pose(ws, body); }
  Json post_tween(const Request&, const Json& body) { return routes::tween(ws, body); }
  Json post_transfer(const Request&, const Json& body) { return routes::transfer(ws, body); }
  Json post_channel_values(const Request&, const Json& body) { return routes::channel_values(ws, body); }
  Json post_space(const Request&, const Json& body) { return routes::space(ws, body); }
  Json get_spaces(const Request& req, const Json&) {
    auto it = req.query.find("control");
    if (it == req.query.end()) refuse(400, "missing query 'control'", "control");
    return routes::spaces(ws, it->second);
  }
  Json post_poses_save(const Request&, const Json& body) { return routes::poses_save(ws, body); }
  Json post_poses_apply(const Request&, const Json& body) { return routes::poses_apply(ws, body); }
  Json post_poses_remove(const Request&, const Json& body) { return routes::poses_remove(ws, body); }
  Json get_poses(const Request& req, const Json&) {
    const auto it = req.query.find("library");
    if (it == req.query.end()) refuse(400, "missing query 'library'", "library");
    return routes::poses_list(ws, Json{{"library", it->second}});
  }




  // ---- routes: rigs --------------------------------------------------------------

  Json get_rigs(const Request&, const Json&) {
    // The scene's rigs as the Rig Manager reports them, with their steps and
    // features, then those at step 0.
    Json rigs = rig::rigs_report(g());
    std::map<std::string, app::RigEntry> entries;
    std::vector<app::RigEntry> unbuilt;
    for (app::RigEntry& e : ws.rigs()) {
      if (e.unbuilt) unbuilt.push_back(std::move(e));
      else entries.emplace(e.name, std::move(e));
    }
    for (Json& r : rigs) {
      auto it = entries.find(r["name"].get<std::string>());
      r["steps"] = it == entries.end() ? 0 : it->second.steps;
      r["features"] = it == entries.end() ? Json::array() : features_json(it->second.features);
    }
    for (const app::RigEntry& e : unbuilt) {
      const Json on_disk = e.definition_version ? Json(*e.definition_version) : Json(nullptr);
      rigs.push_back(Json{{"name", e.name},
                          {"version", e.version},
                          {"definition", e.definition},
                          {"definitionVersion", on_disk},
                          {"outOfDate", e.definition_version && *e.definition_version != e.version},
                          {"editMode", e.edit_mode},
                          {"buildPosition", 0},
                          {"components", Json::array()},
                          {"steps", e.steps},
                          {"features", features_json(e.features)}});
    }
    return Json{{"rigs", std::move(rigs)}};
  }

  Json post_rigs_add(const Request&, const Json& body) {
    const fs::path path = path_field(need(body, "definition"), "definition");
    rig::BuildOptions options;
    if (const Json* e = opt(body, "editMode")) options.edit_mode = as_bool(*e, "editMode");
    const rig::AddedRig added = take(ws.add_rig(path, options));
    return Json{{"rig", added.name}, {"version", added.version}, {"steps", added.steps}, {"components", added.components}};
  }

  Json post_rigs_update(const Request&, const Json& body) {
    const std::string name = rig_name(body);
    auto keep = rig::Build::KeepKeys::kLocal;
    if (const Json* k = opt(body, "keepKeys")) {
      const std::string v = as_string(*k, "keepKeys");
      if (v == "world") keep = rig::Build::KeepKeys::kWorld;
      else if (v != "local") refuse(400, "keepKeys: expected local or world, got '" + v + "'", "keepKeys");
    }
    const Json* f = opt(body, "force");
    const rig::UpdateReport r = take(ws.update_rig(name, {}, f && as_bool(*f, "force"), keep));
    return Json{{"rig", r.rig}, {"from", r.from}, {"to", r.to}, {"updated", r.updated}, {"rebuilt", r.rebuilt}};
  }

  Json post_rigs_remove(const Request&, const Json& body) {
    const std::string name = rig_name(body, true);
    check(ws.remove_rig(name));
    return Json{{"rig", name}};
  }

  Json post_rigs_edit(const Request&, const Json& body) {
    const std::string name = rig_name(body);
    fs::path out;
    if (const Json* o = opt(body, "definitionOut")) out = path_field(*o, "definitionOut");
    bool keep_editing = false;
    if (const Json* k = opt(body, "keepEditing")) keep_editing = as_bool(*k, "keepEditing");
    const app::CommitReport r = take(ws.commit_edits(name, out, keep_editing));
    return Json{{"rig", name},
                {"version", r.version},
                {"changed", r.changed},
                {"ignored", r.ignored},
                {"definition", r.definition_path.empty() ? Json(nullptr) : Json(r.definition_path.string())},
                {"editMode", r.edit_mode}};
  }

  Json post_rigs_step(const Request&, const Json& body) {
    const std::string name = rig_name(body, true);
    std::optional<int> to;
    int by = 0;
    if (const Json* t = opt(body, "to")) to = as_int(*t, "to", "a whole number of steps");
    else by = as_int(need(body, "by"), "by");
    const app::StepReport r = take(ws.step_rig(name, to, by));
    return Json{{"rig", r.rig}, {"position", r.position}, {"steps", r.steps}, {"step", r.step}, {"rigId", r.rig_id}};
  }

  Json post_rigs_feature(const Request&, const Json& body) {
    const std::string name = rig_name(body, true);
    const std::string feature = as_string(need(body, "feature"), "feature");
    const bool enabled = as_bool(need(body, "enabled"), "enabled");
    std::string switch_name;
    if (const Json* sw = opt(body, "switch")) switch_name = as_string(*sw, "switch");
    const app::FeatureReport r = take(ws.set_feature(name, feature, switch_name, enabled));
    return Json{{"rig", r.rig}, {"features", features_json(r.features)}, {"position", r.position}, {"steps", r.steps}};
  }

  Json post_rigs_edit_mode(const Request&, const Json& body) {
    const std::string name = rig_name(body, true);
    const bool on = as_bool(need(body, "on"), "on");
    return Json{{"rig", name}, {"editMode", take(ws.set_edit_mode(name, on))}};
  }

  // ---- routes: definitions (editor_routes.cc) -------------------------------------
  Json get_definition(const Request& req, const Json&) { return routes::definition_open(ws, req.query); }
  Json get_components(const Request&, const Json&) { return routes::components(ws); }
  Json post_definition_validate(const Request&, const Json& body) { return routes::definition_validate(ws, body); }
  Json post_definition_build(const Request&, const Json& body) { return routes::definition_build(ws, body); }
  Json post_definition_save(const Request&, const Json& body) { return routes::definition_save(ws, body); }
};

Workspace::Workspace(std::unique_ptr<scene::Scene> scene, fs::path scene_path, fs::path root,
                     const rig::ComponentFactory& factory)
    : app_(std::make_unique<app::Workspace>(std::move(scene), std::move(scene_path), std::move(root), factory)),
      impl_(std::make_unique<Impl>(*app_)) {
  app_->set_report_moved_controls(false);  // drag answers list `moved` only
}

Workspace::~Workspace() = default;

void Workspace::set_character(fs::path file) {
  std::lock_guard lock(mutex_);
  app_->set_character(std::move(file));
}

std::uint64_t Workspace::revision() const {
  std::lock_guard lock(mutex_);
  return app_->revision();
}

namespace {

Response json_response(int status, const Json& body) {
  return Response{status, body.dump(-1, ' ', false, Json::error_handler_t::replace), "application/json"};
}

Response error_response(const ApiError& e) {
  Json body{{"error", e.message}};
  if (!e.field.empty()) body["field"] = e.field;
  return json_response(e.status, body);
}

}  // namespace

Response Workspace::handle(const Request& request) {
  using Handler = Json (Impl::*)(const Request&, const Json&);
  struct Route {
    const char* method;
    const char* path;
    Handler handler;
  };
  static const Route kRoutes[] = {
      {"GET", "/api/revision", &Impl::get_revision},
      {"GET", "/api/scene", &Impl::get_scene},
      {"GET", "/api/nodes", &Impl::get_nodes},
      {"GET", "/api/pose", &Impl::get_pose},
      {"GET", "/api/keys", &Impl::get_keys},
      {"GET", "/api/rigs", &Impl::get_rigs},
      {"GET", "/api/components", &Impl::get_components},
      {"GET", "/api/character.glb", nullptr},
      {"POST", "/api/save", &Impl::post_save},
      {"POST", "/api/select", &Impl::post_select},
      {"POST", "/api/mode", &Impl::post_mode},
      {"POST", "/api/options", &Impl::post_options},
      {"POST", "/api/drag", &Impl::post_drag},
      {"POST", "/api/release", &Impl::post_release},
      {"POST", "/api/undo", &Impl::post_undo},
      {"POST", "/api/redo", &Impl::post_redo},
      {"POST", "/api/time", &Impl::post_time},
      {"POST", "/api/key", &Impl::post_key},
      {"GET", "/api/channel-keys", &Impl::get_channel_keys},
      {"GET", "/api/channels", &Impl::get_channels},
      {"GET", "/api/curves", &Impl::get_curves},
      {"POST", "/api/curve-keys", &Impl::post_curve_keys},
      {"POST", "/api/playback-range", &Impl::post_playback_range},
      {"GET", "/api/selection-sets", &Impl::get_selection_sets},
      {"GET", "/api/picker", &Impl::get_picker},
      {"GET", "/api/trails", &Impl::get_trails},
      {"GET", "/api/ghosts", &Impl::get_ghosts},
      {"POST", "/api/selection-sets", &Impl::post_selection_sets},
      {"POST", "/api/channel-keys", &Impl::post_channel_keys},
      {"POST", "/api/match", &Impl::post_match},
      {"POST", "/api/mirror", &Impl::post_mirror},
      {"POST", "/api/bind-pose", &Impl::post_bind_pose},
      {"POST", "/api/tween", &Impl::post_tween},
      {"POST", "/api/transfer", &Impl::post_transfer},
      {"POST", "/api/channel-values", &Impl::post_channel_values},
      {"GET", "/api/spaces", &Impl::get_spaces},
      {"POST", "/api/space", &Impl::post_space},
      {"POST", "/api/export", &Impl::post_export},
      {"GET", "/api/shape", &Impl::get_shape},
      {"POST", "/api/shape", &Impl::post_shape},
      {"POST", "/api/align", &Impl::post_align},
      {"POST", "/api/locators", &Impl::post_locators},
      {"POST", "/api/mirror-joints", &Impl::post_mirror_joints},
      {"POST", "/api/data/export", &Impl::post_data_export},
      {"POST", "/api/data/import", &Impl::post_data_import},
      {"GET", "/api/driven-keys", &Impl::get_driven_keys},
      {"POST", "/api/driven-keys", &Impl::post_driven_keys},
      {"GET", "/api/poses", &Impl::get_poses},
      {"GET", "/api/poses/thumbnail", nullptr},
      {"POST", "/api/poses/save", &Impl::post_poses_save},
      {"POST", "/api/poses/apply", &Impl::post_poses_apply},
      {"POST", "/api/poses/remove", &Impl::post_poses_remove},
      {"POST", "/api/rigs/add", &Impl::post_rigs_add},
      {"POST", "/api/rigs/update", &Impl::post_rigs_update},
      {"POST", "/api/rigs/remove", &Impl::post_rigs_remove},
      {"POST", "/api/rigs/edit", &Impl::post_rigs_edit},
      {"POST", "/api/rigs/step", &Impl::post_rigs_step},
      {"POST", "/api/rigs/edit-mode", &Impl::post_rigs_edit_mode},
      {"POST", "/api/rigs/feature", &Impl::post_rigs_feature},
      {"GET", "/api/definition", &Impl::get_definition},
      {"POST", "/api/definition/validate", &Impl::post_definition_validate},
      {"POST", "/api/definition/build", &Impl::post_definition_build},
      {"POST", "/api/definition/save", &Impl::post_definition_save},
      {"GET", "/api/graph/palette", &Impl::get_graph_palette},
      {"GET", "/api/graph/files", &Impl::get_graph_files},
      {"GET", "/api/graph", &Impl::get_graph},
      {"POST", "/api/graph/validate", &Impl::post_graph_validate},
      {"POST", "/api/graph/build", &Impl::post_graph_build},
      {"POST", "/api/graph/save", &Impl::post_graph_save},
  };
  const Route* route = nullptr;
  bool path_known = false;
  for (const Route& r : kRoutes) {
    if (request.path != r.path) continue;
    path_known = true;
    if (request.method == r.method) route = &r;
  }
  if (!route) {
    if (path_known) return error_response(ApiError{405, request.method + " " + request.path + ": method not allowed", {}});
    return error_response(ApiError{404, "no such route: " + request.path, {}});
  }
  if (request.body.size() > kMaxBody)
    return error_response(ApiError{413, "the body is over " + std::to_string(kMaxBody) + " bytes", {}});

  std::lock_guard lock(mutex_);
  try {
    Json body = Json::object();
    if (route->method == std::string("POST") && !request.body.empty()) {
      try {
        body = Json::parse(request.body);
      } catch (const Json::exception& e) {
        // nlohmann's message names the line and column (a parse error) or
        // the number that does not fit a double (out_of_range 406).
        throw ApiError{400, std::string("malformed JSON: ") + e.what(), "body"};
      }
      if (!body.is_object()) throw ApiError{400, std::string("the body must be a JSON object, got ") + body.type_name(), "body"};
    }
    if (!route->handler)
      return route->path == std::string("/api/character.glb") ? impl_->get_character() : impl_->get_pose_thumbnail(request);
    // A new edit made after undoing a step to 0 drops that rig's entry.
    struct Prune {
      app::Workspace& ws;
      std::vector<std::uint64_t> undone;
      ~Prune() { ws.drop_unbuilt(undone); }
    } prune{*app_, route->handler == &Impl::post_undo || route->handler == &Impl::post_redo
                       ? std::vector<std::uint64_t>{}
                       : app_->unbuilt_undone()};
    const std::uint64_t revision = app_->revision();
    Json answer = (impl_.get()->*(route->handler))(request, body);
    // The revision this answer describes: after the change.
    if (answer.is_object() && (app_->revision() != revision || !answer.contains("revision")))
      answer["revision"] = app_->revision();
    return json_response(200, answer);
  } catch (const ApiError& e) {
    return error_response(e);
  } catch (const std::exception& e) {
    // Nothing below should throw past Status; if it does, the request fails
    // and the server goes on.
    return error_response(ApiError{500, std::string("internal error: ") + e.what(), {}});
  }
}

}  // namespace rigel::server
