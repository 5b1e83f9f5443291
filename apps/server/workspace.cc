// Over 800 lines: the routes still carry logic the service layer of issue 15
// takes out (build-or-rebuild, saves, drags of built rigs); split with it.
// The JSON API of `rigel serve` (workspace.h, docs/SERVER.md).

#include "workspace.h"

#include <unistd.h>

#include <array>
#include <atomic>
#include <cmath>
#include <fstream>
#include <functional>
#include <sstream>
#include <vector>

#include "rigel/ephemeral/keying.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/io/gltf_export.h"
#include "rigel/io/scene_file.h"
#include "rigel/math/transform.h"
#include "rigel/rig/build.h"
#include "rigel/rig/definition_io.h"
#include "rigel/rig/manager.h"
#include "rigel/rig/meta.h"
#include "rigel/scene/transform_types.h"

namespace rigel::server {
namespace {

using graph::NodeId;
using math::Mat4;
using math::Quat;
using math::Vec3;
namespace xform = scene::xform;

// A refused request: status, message, and the request field at fault.
struct ApiError {
  int status = 400;
  std::string message;
  std::string field;
};

[[noreturn]] void refuse(int status, std::string message, std::string field = {}) {
  throw ApiError{status, std::move(message), std::move(field)};
}

// The HTTP status of a library error in answer to a well-formed request:
// what the scene cannot do in its state is a conflict, not a bad request.
int status_of(ErrorCode code) {
  switch (code) {
    case ErrorCode::kNotFound: return 404;
    case ErrorCode::kParseError: return 400;
    case ErrorCode::kIoError: return 500;
    default: return 409;
  }
}

void check(const Status& s, const std::string& field = {}) {
  if (!s) refuse(status_of(s.code()), s.message(), field);
}

template <typename T>
T take(Result<T> r, const std::string& field = {}) {
  if (!r) refuse(status_of(r.status().code()), r.status().message(), field);
  return std::move(*r);
}

// ---- request fields ----------------------------------------------------------

const Json* opt(const Json& body, const char* key) {
  auto it = body.find(key);
  return it == body.end() || it->is_null() ? nullptr : &*it;
}

const Json& need(const Json& body, const char* key) {
  const Json* j = opt(body, key);
  if (!j) refuse(400, std::string("missing field '") + key + "'", key);
  return *j;
}

std::string as_string(const Json& j, const std::string& field) {
  if (!j.is_string()) refuse(400, field + ": expected a string, got " + j.type_name(), field);
  return j.get<std::string>();
}

double as_number(const Json& j, const std::string& field) {
  if (!j.is_number()) refuse(400, field + ": expected a number, got " + j.type_name(), field);
  const double v = j.get<double>();
  if (!std::isfinite(v)) refuse(400, field + ": not a finite number", field);
  return v;
}

bool as_bool(const Json& j, const std::string& field) {
  if (!j.is_boolean()) refuse(400, field + ": expected true or false, got " + j.type_name(), field);
  return j.get<bool>();
}

template <int N>
Eigen::Matrix<double, N, 1> as_numbers(const Json& j, const std::string& field) {
  if (!j.is_array() || j.size() != N)
    refuse(400, field + ": expected an array of " + std::to_string(N) + " numbers", field);
  Eigen::Matrix<double, N, 1> v;
  for (int i = 0; i < N; ++i) v[i] = as_number(j[static_cast<std::size_t>(i)], field + "[" + std::to_string(i) + "]");
  return v;
}

Quat as_quat(const Json& j, const std::string& field) {
  if (j.is_object()) {
    const Vec3 e = as_numbers<3>(need(j, "euler"), field + ".euler") * (M_PI / 180.0);
    return Quat(Eigen::AngleAxisd(e.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(e.y(), Vec3::UnitY()) *
                Eigen::AngleAxisd(e.x(), Vec3::UnitX()));
  }
  const Eigen::Vector4d v = as_numbers<4>(j, field);
  if (v.norm() < 1e-9) refuse(400, field + ": not a rotation (zero length)", field);
  return Quat(v[3], v[0], v[1], v[2]).normalized();
}

Json vec_json(const Vec3& v) { return Json::array({v.x(), v.y(), v.z()}); }

// ---- time --------------------------------------------------------------------

Json frame_json(const scene::Scene& s) { return Json{{"frame", s.frame()}, {"time", s.graph().time()}}; }

}  // namespace

Result<fs::path> confined_path(const fs::path& root, const std::string& path, const std::string& field) {
  if (path.empty()) return error(ErrorCode::kInvalidArgument, field + ": empty path");
  if (path.find('\0') != std::string::npos) return error(ErrorCode::kInvalidArgument, field + ": bad path");
  const fs::path p(path);
  if (p.is_absolute()) return error(ErrorCode::kInvalidArgument, field + ": '" + path + "' is absolute; give a path relative to the served folder");
  std::error_code ec;
  const fs::path base = fs::weakly_canonical(root, ec);
  if (ec) return error(ErrorCode::kIoError, "served folder " + root.string() + ": " + ec.message());
  // weakly_canonical resolves the symbolic links of the part that exists and
  // every "..", so a path that leaves the root in any way ends outside it.
  const fs::path full = fs::weakly_canonical(base / p, ec);
  if (ec) return error(ErrorCode::kInvalidArgument, field + ": '" + path + "': " + ec.message());
  const auto [b, f] = std::mismatch(base.begin(), base.end(), full.begin(), full.end());
  if (b != base.end()) return error(ErrorCode::kInvalidArgument, field + ": '" + path + "' is outside the served folder");
  return full;
}

struct Workspace::Impl {
  Impl(scene::Scene& s, fs::path path, fs::path r, const rig::ComponentFactory& f)
      : scene(s), session(s), scene_path(std::move(path)), root(std::move(r)), factory(f) {}

  scene::Scene& scene;
  ephemeral::Session session;
  fs::path scene_path;
  fs::path root;
  fs::path character;  // the file the scene was opened from, or empty
  const rig::ComponentFactory& factory;
  std::uint64_t revision = 1;
  std::uint64_t gesture = 0;  // undo merge key of the current direct (non-ephemeral) drag

  // Rigs stepped back to step 0 (POST /api/rigs/step). The scene keeps
  // nothing of a rig with no step built (its metaRoot is step 1's work), so
  // the workspace keeps its definition, to list the rig and step it forward
  // again, as a Build object held in Python does. An entry stands while the
  // scene has no rig of its name and the undo history is at or after the
  // step that made it: undoing that step hides it (the rig is back), redo
  // shows it again, and a new edit made from before it drops it for good.
  struct Unbuilt {
    rig::Definition definition;
    rig::BuildOptions options;
    std::size_t since = 0;     // undo_count() after the step to 0
    std::uint64_t serial = 0;  // which entry (a name may be stepped to 0 again)
  };
  std::map<std::string, Unbuilt> unbuilt;
  std::uint64_t unbuilt_serial = 0;

  const Unbuilt* unbuilt_rig(const std::string& name) {
    auto it = unbuilt.find(name);
    if (it == unbuilt.end() || g().undo_count() < it->second.since || rig::find_rig(g(), name).is_valid()) return nullptr;
    return &it->second;
  }

  // The entries whose step an undo took back: a request that leaves nothing
  // to redo has dropped them from the history.
  std::vector<std::uint64_t> unbuilt_undone() {
    std::vector<std::uint64_t> out;
    for (const auto& [name, u] : unbuilt)
      if (u.since > g().undo_count()) out.push_back(u.serial);
    return out;
  }
  void drop_unbuilt(const std::vector<std::uint64_t>& undone) {
    if (undone.empty() || g().can_redo()) return;
    for (auto it = unbuilt.begin(); it != unbuilt.end();)
      it = std::find(undone.begin(), undone.end(), it->second.serial) != undone.end() ? unbuilt.erase(it) : std::next(it);
  }

  graph::Graph& g() { return scene.graph(); }

  // A request path inside the root, or 400.
  fs::path confined(const std::string& path, const std::string& field) {
    auto r = confined_path(root, path, field);
    if (!r) refuse(r.status().code() == ErrorCode::kIoError ? 500 : 400, r.status().message(), field);
    return *r;
  }

  // Makes the folder a file is about to be saved in; a folder (or anything
  // else that is not a file) where the file goes is the request's fault.
  static void make_parent(const fs::path& file, const std::string& field) {
    std::error_code ec;
    const fs::file_status st = fs::status(file, ec);
    if (fs::exists(st) && !fs::is_regular_file(st))
      refuse(400, field + ": '" + file.string() + "' is " + (fs::is_directory(st) ? "a folder" : "not a file"), field);
    fs::create_directories(file.parent_path(), ec);
    if (ec) refuse(409, field + ": cannot make " + file.parent_path().string() + ": " + ec.message(), field);
  }

  // A save that failed: where the request said to write cannot take it.
  static void check_saved(const Status& s, const std::string& field) {
    if (!s) refuse(s.code() == ErrorCode::kIoError ? 409 : status_of(s.code()), s.message(), field);
  }

  // ---- nodes -------------------------------------------------------------------

  NodeId node_ref(const Json& j, const std::string& field) {
    const std::string ref = as_string(j, field);
    NodeId id;
    if (auto u = graph::Uuid::parse(ref)) id = g().find(*u);
    if (!id.is_valid() && graph::Graph::is_valid_name(ref)) id = g().find(ref);
    if (!id.is_valid()) refuse(404, field + ": no node '" + ref + "'", field);
    return id;
  }

  bool is_control(NodeId id) {
    const graph::Node* n = g().node(id);
    return n && n->type().name() == scene::kControlType;
  }

  // A control: a control node, or a joint standing for its ephemeral control.
  NodeId control_ref(const Json& j, const std::string& field) {
    const NodeId id = node_ref(j, field);
    if (is_control(id)) return id;
    const NodeId c = ephemeral::control_of(g(), id);
    if (!c.is_valid())
      refuse(400, field + ": '" + g().node(id)->name() + "' is not a control (nor a joint driven by one)", field);
    return c;
  }

  std::vector<NodeId> controls_ref(const Json& j, const std::string& field) {
    if (!j.is_array()) refuse(400, field + ": expected an array of node uuids or names", field);
    std::vector<NodeId> out;
    for (std::size_t i = 0; i < j.size(); ++i) out.push_back(control_ref(j[i], field + "[" + std::to_string(i) + "]"));
    return out;
  }

  std::string uuid(NodeId id) { return g().node(id)->uuid().str(); }

  Json selection_json() {
    Json list = Json::array();
    for (NodeId id : g().selection())
      if (g().node(id)) list.push_back(uuid(id));
    return list;
  }

  NodeId parent_of(NodeId id) {
    auto src = g().source(graph::Plug{id, xform::kParentMatrix});
    return src ? src->node : NodeId{};
  }

  // ---- pose --------------------------------------------------------------------

  // Local (offsetParentMatrix * matrix, what a glTF node holds) or world
  // translation, rotation, scale of every transform node, hierarchy order.
  using Trs = std::array<double, 10>;
  std::vector<std::pair<NodeId, Trs>> pose_values(bool world) {
    std::vector<std::pair<NodeId, Trs>> out;
    const std::vector<NodeId> order = scene.hierarchy();
    out.reserve(order.size());
    for (NodeId id : order) {
      Mat4 m;
      if (world) {
        m = scene.world_matrix(id);
      } else {
        const Mat4 local = scene.local_matrix(id);
        const auto* opm = std::get_if<Mat4>(&g().evaluate(id, xform::kOffsetParentMatrix));
        m = opm ? Mat4(*opm * local) : local;
      }
      const math::Decomposed d = math::decompose(m);
      const Quat& q = d.rotation;
      out.emplace_back(id, Trs{d.translate.x(), d.translate.y(), d.translate.z(), q.x(), q.y(), q.z(), q.w(),
                               d.scale.x(), d.scale.y(), d.scale.z()});
    }
    return out;
  }

  // The pose answer. With `before` (the values before a change), only the
  // nodes whose values changed are listed ("partial": a drag's answer).
  Json pose_json(bool world, const std::vector<std::pair<NodeId, Trs>>* before = nullptr) {
    const std::vector<std::pair<NodeId, Trs>> now = pose_values(world);
    const bool partial = before && before->size() == now.size();
    Json nodes = Json::object();
    // Keys are unique (one per node): append to the ordered map's vector
    // directly instead of its insert, which searches every key (quadratic
    // over a character's hundreds of nodes).
    auto& entries = static_cast<std::vector<std::pair<const std::string, Json>>&>(nodes.get_ref<Json::object_t&>());
    entries.reserve(now.size());
    for (std::size_t i = 0; i < now.size(); ++i) {
      const auto& [id, v] = now[i];
      if (partial && (*before)[i].first == id && (*before)[i].second == v) continue;
      entries.emplace_back(uuid(id), v);
    }
    Json out{{"revision", revision}};
    out.update(frame_json(scene));
    out["space"] = world ? "world" : "local";
    out["partial"] = partial;
    out["nodes"] = std::move(nodes);
    return out;
  }

  // ---- routes: the scene ---------------------------------------------------------

  Json get_revision(const Request&, const Json&) { return Json{{"revision", revision}}; }

  Json get_scene(const Request&, const Json&) {
    Json modes = Json::array();
    for (int m = 0; m < ephemeral::kModeCount; ++m) modes.push_back(ephemeral::mode_name(static_cast<ephemeral::Mode>(m)));
    // The frame range: the union of the keys of the scene's curves.
    double first = 0, last = 0;
    bool any = false;
    for (NodeId c : ephemeral::rigs_find(g())) {
      const std::vector<double> t = ephemeral::key_times(g(), ephemeral::rig_controls(g(), c));
      if (t.empty()) continue;
      first = any ? std::min(first, t.front()) : t.front();
      last = any ? std::max(last, t.back()) : t.back();
      any = true;
    }
    Json scopes = Json::object();
    for (NodeId r : ephemeral::rigs_find(g()))
      scopes[g().node(r)->name()] = ephemeral::key_scope_name(ephemeral::key_scope(g(), r));
    Json out{{"revision", revision}, {"path", scene_path.string()}, {"fps", g().fps()}};
    out.update(frame_json(scene));
    out["range"] = Json::array({std::round(first * g().fps()), std::round(last * g().fps())});
    out["mode"] = ephemeral::mode_name(session.mode());
    out["modes"] = modes;
    out["autoKey"] = session.options().auto_key;
    out["keyScopes"] = scopes;
    out["canUndo"] = g().can_undo();
    out["canRedo"] = g().can_redo();
    out["undo"] = g().undo_label();
    out["redo"] = g().redo_label();
    out["selection"] = selection_json();
    out["root"] = root.string();
    out["character"] = character.empty() ? Json(nullptr) : Json(character.string());
    return out;
  }

  Json get_nodes(const Request&, const Json&) {
    Json nodes = Json::array(), controls = Json::array();
    for (NodeId id : scene.hierarchy()) {
      const graph::Node* n = g().node(id);
      const NodeId parent = parent_of(id);
      nodes.push_back(Json{{"uuid", uuid(id)},
                           {"name", n->name()},
                           {"type", n->type().name()},
                           {"parent", parent.is_valid() ? Json(uuid(parent)) : Json(nullptr)}});
      if (n->type().name() != scene::kControlType) continue;
      Json points = Json::array();
      if (const auto* p = std::get_if<std::vector<Vec3>>(&g().evaluate(id, scene::control_attr::kShapePoints)))
        for (const Vec3& v : *p) points.push_back(vec_json(v));
      const auto* closed = std::get_if<bool>(&g().evaluate(id, scene::control_attr::kShapeClosed));
      const auto* color = std::get_if<Vec3>(&g().evaluate(id, scene::control_attr::kShapeColor));
      const NodeId erig = ephemeral::rig_of(g(), id);
      const NodeId built = rig::rig_of(g(), id);
      std::string rig_name = erig.is_valid() ? g().node(erig)->name() : "";
      if (rig_name.empty() && built.is_valid()) rig_name = rig::meta_string(g(), built, "rigName");
      controls.push_back(Json{{"uuid", uuid(id)},
                              {"name", n->name()},
                              {"rig", rig_name},
                              {"ephemeral", erig.is_valid()},
                              {"shape", Json{{"points", std::move(points)},
                                             {"closed", closed ? *closed : true},
                                             {"color", color ? vec_json(*color) : vec_json(Vec3(1, 1, 0))}}}});
    }
    return Json{{"revision", revision}, {"nodes", std::move(nodes)}, {"controls", std::move(controls)}};
  }

  Json get_pose(const Request& req, const Json&) {
    auto it = req.query.find("space");
    const std::string space = it == req.query.end() ? "local" : it->second;
    if (space != "local" && space != "world") refuse(400, "space: expected local or world, got '" + space + "'", "space");
    return pose_json(space == "world");
  }

  // The scene as binary glTF: exported beside nothing, to a private file.
  Response get_character() {
    static std::atomic<int> counter{0};
    const fs::path tmp = fs::temp_directory_path() /
                         ("rigel-serve-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + ".glb");
    Status s = io::export_gltf(scene, tmp);
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
    fs::path path = scene_path;
    if (const Json* p = opt(body, "path")) path = confined(as_string(*p, "path"), "path");
    if (path.empty()) refuse(400, "path: the scene has no file yet; give a path", "path");
    make_parent(path, "path");
    check_saved(io::save_scene(scene, path), "path");
    scene_path = path;
    return Json{{"path", path.string()}};
  }

  // ---- routes: posing ----------------------------------------------------------

  Json post_select(const Request&, const Json& body) {
    std::vector<NodeId> ids = controls_ref(need(body, "controls"), "controls");
    if (const Json* add = opt(body, "add"); add && as_bool(*add, "add")) {
      std::vector<NodeId> all = g().selection();
      for (NodeId id : ids)
        if (std::find(all.begin(), all.end(), id) == all.end()) all.push_back(id);
      ids = std::move(all);
    }
    session.select(std::move(ids));
    gesture = 0;
    return Json{{"selection", selection_json()}};
  }

  Json post_mode(const Request&, const Json& body) {
    const std::string name = as_string(need(body, "mode"), "mode");
    auto mode = ephemeral::mode_from_name(name);
    if (!mode) refuse(400, "mode: unknown mode '" + name + "'", "mode");
    session.set_mode(*mode);
    gesture = 0;
    return Json{{"mode", ephemeral::mode_name(session.mode())}};
  }

  Json options_json() {
    const ephemeral::SessionOptions& o = session.options();
    return Json{{"autoKey", o.auto_key},
                {"magnetFraction", o.magnet_fraction},
                {"magnetRadius", o.magnet_radius},
                {"maxChain", o.max_chain}};
  }

  Json post_options(const Request&, const Json& body) {
    ephemeral::SessionOptions o = session.options();
    if (const Json* j = opt(body, "autoKey")) o.auto_key = as_bool(*j, "autoKey");
    if (const Json* j = opt(body, "magnetFraction")) {
      o.magnet_fraction = as_number(*j, "magnetFraction");
      if (o.magnet_fraction <= 0 || o.magnet_fraction > 1) refuse(400, "magnetFraction: must be in (0, 1]", "magnetFraction");
    }
    if (const Json* j = opt(body, "magnetRadius")) {
      o.magnet_radius = as_number(*j, "magnetRadius");
      if (o.magnet_radius <= 0) refuse(400, "magnetRadius: must be positive", "magnetRadius");
    }
    if (const Json* j = opt(body, "maxChain")) {
      const double n = as_number(*j, "maxChain");
      if (n < 0 || n != std::floor(n) || n > 1000) refuse(400, "maxChain: expected a whole number from 0 to 1000", "maxChain");
      o.max_chain = static_cast<int>(n);
    }
    session.set_options(o);
    return options_json();
  }

  // Moves controls that belong to no ephemeral rig (a built rig's): each
  // gets the world delta about its own pivot, written into its channels
  // (keys as the session does: the key at this time, or a new one with
  // auto-key). One undo step per gesture.
  void drag_direct(const std::vector<NodeId>& controls, const Vec3& dt, const Quat& dq) {
    if (gesture == 0) gesture = graph::Graph::new_merge_key();
    graph::Transaction tx(g(), "drag", gesture);
    for (NodeId c : controls) {
      const Mat4 w = scene.world_matrix(c);
      Mat4 target = w;
      target.block<3, 3>(0, 0) = dq.toRotationMatrix() * w.block<3, 3>(0, 0);
      target.block<3, 1>(0, 3) = w.block<3, 1>(0, 3) + dt;
      auto ch = scene.channels_for_world(c, target);
      if (!ch) {
        tx.rollback();
        check(ch.status(), "control");
      }
      const bool insert = session.options().auto_key;
      Status s = ephemeral::write_channel(g(), c, xform::kTranslate, graph::Value(ch->translate), insert);
      if (s) s = ephemeral::write_channel(g(), c, ch->rotation_attr, ch->rotation, insert);
      if (!s) {
        tx.rollback();
        refuse(409, s.message(), "control");
      }
    }
  }

  Json post_drag(const Request&, const Json& body) {
    const auto before = pose_values(false);
    bool session_dragged = false;  // the session's notes are this drag's
    std::vector<NodeId> selected;
    for (NodeId id : g().selection())
      if (g().node(id)) selected.push_back(id);
    if (const Json* c = opt(body, "control")) {
      const NodeId control = control_ref(*c, "control");
      const Json& to = need(body, "to");
      if (!to.is_object()) refuse(400, "to: expected {\"t\": [x, y, z], \"q\": [x, y, z, w]}", "to");
      const Mat4 now = scene.world_matrix(control);
      const Vec3 t = opt(to, "t") ? Vec3(as_numbers<3>(*opt(to, "t"), "to.t")) : Vec3(now.block<3, 1>(0, 3));
      const math::Decomposed d = math::decompose(now);
      const Quat q = opt(to, "q") ? as_quat(*opt(to, "q"), "to.q") : d.rotation;
      if (std::find(selected.begin(), selected.end(), control) == selected.end()) {
        session.select({control});
        selected = {control};
      }
      if (ephemeral::rig_of(g(), control).is_valid()) {
        Mat4 world = math::trs_matrix(t, q, d.scale);
        check(session.drag_to(control, world), "control");
        session_dragged = true;
      } else {
        std::vector<NodeId> direct;
        for (NodeId id : selected)
          if (is_control(id) && !ephemeral::rig_of(g(), id).is_valid()) direct.push_back(id);
        drag_direct(direct, t - d.translate, (q * d.rotation.conjugate()).normalized());
      }
    } else {
      ephemeral::Delta delta;
      if (const Json* t = opt(body, "translate")) delta.translate = as_numbers<3>(*t, "translate");
      if (const Json* r = opt(body, "rotate")) delta.rotate = as_quat(*r, "rotate");
      if (const Json* s = opt(body, "scale")) delta.scale = as_numbers<3>(*s, "scale");
      if (selected.empty()) refuse(409, "nothing is selected: select controls first (POST /api/select)", "controls");
      if (!session.grabbed().empty()) {
        check(session.drag(delta));
        session_dragged = true;
      } else {
        if (delta.scale != Vec3::Ones()) refuse(400, "scale: only body mode on an ephemeral rig scales", "scale");
        std::vector<NodeId> direct;
        for (NodeId id : selected)
          if (is_control(id)) direct.push_back(id);
        drag_direct(direct, delta.translate, delta.rotate);
      }
    }
    // The answer lists only what moved: the revision after this drag is the
    // caller's pose plus these nodes; "notes" says what the drag could not
    // do (a target out of reach, a bone that would stretch).
    Json answer = pose_json(false, &before);
    if (session_dragged && !session.notes().empty()) answer["notes"] = session.notes();
    return answer;
  }

  Json post_release(const Request&, const Json&) {
    session.release();
    gesture = 0;
    return Json::object();
  }

  Json post_undo(const Request&, const Json&) {
    const std::string label = g().undo_label();
    if (!g().undo()) refuse(409, "nothing to undo");
    gesture = 0;
    return Json{{"label", label}};
  }

  Json post_redo(const Request&, const Json&) {
    const std::string label = g().redo_label();
    if (!g().redo()) refuse(409, "nothing to redo");
    gesture = 0;
    return Json{{"label", label}};
  }

  // ---- routes: time and keys -----------------------------------------------------

  Json post_time(const Request&, const Json& body) {
    if (const Json* f = opt(body, "frame")) {
      const double frame = as_number(*f, "frame");
      if (std::abs(frame) > kMaxFrame) refuse(400, "frame: " + f->dump() + " is out of range (at most " + std::to_string(static_cast<int>(kMaxFrame)) + " frames either side of 0)", "frame");
      scene.set_frame(frame);
    } else if (const Json* t = opt(body, "time")) {
      const double time = as_number(*t, "time");
      if (std::abs(time * g().fps()) > kMaxFrame)
        refuse(400, "time: " + t->dump() + " s is out of range (at most " + std::to_string(static_cast<int>(kMaxFrame)) + " frames either side of 0)", "time");
      g().set_time(time);
    } else {
      refuse(400, "missing field 'frame' (or 'time')", "frame");
    }
    gesture = 0;
    return frame_json(scene);
  }

  std::vector<NodeId> controls_or_selection(const Json& body) {
    if (const Json* c = opt(body, "controls")) return controls_ref(*c, "controls");
    std::vector<NodeId> out;
    for (NodeId id : g().selection())
      if (g().node(id)) out.push_back(id);
    if (out.empty()) refuse(409, "nothing is selected and no 'controls' given", "controls");
    return out;
  }

  Json keys_json(const std::vector<NodeId>& controls) {
    const std::vector<double> times = ephemeral::key_times(g(), controls);
    Json frames = Json::array();
    for (double t : times) frames.push_back(std::round(t * g().fps() * 1e6) / 1e6);
    // The keying scope of the controls' ephemeral rig; controls of a built
    // rig are keyed one by one ("controls"); no controls, no scope (null).
    Json scope = nullptr;
    if (!controls.empty()) {
      const NodeId rig = ephemeral::rig_of(g(), controls.front());
      scope = rig.is_valid() ? ephemeral::key_scope_name(ephemeral::key_scope(g(), rig)) : "controls";
    }
    return Json{{"scope", std::move(scope)}, {"frames", std::move(frames)}, {"times", times}};
  }

  Json get_keys(const Request& req, const Json&) {
    std::vector<NodeId> controls;
    if (auto it = req.query.find("controls"); it != req.query.end()) {
      Json list = Json::array();
      std::stringstream ss(it->second);
      for (std::string item; std::getline(ss, item, ',');) list.push_back(item);
      controls = controls_ref(list, "controls");
    } else {
      for (NodeId id : g().selection())
        if (g().node(id)) controls.push_back(id);
    }
    return keys_json(controls);
  }

  Json post_key(const Request&, const Json& body) {
    const std::vector<NodeId> controls = controls_or_selection(body);
    const Json* del = opt(body, "delete");
    if (del && as_bool(*del, "delete")) {
      check(ephemeral::delete_key(g(), controls));
    } else {
      check(ephemeral::set_key(g(), controls));
    }
    return keys_json(controls);
  }

  // ---- routes: rigs --------------------------------------------------------------

  // The request's rig: one the scene holds, or (where the route takes one)
  // a rig stepped back to step 0.
  std::string rig_name(const Json& body, bool unbuilt_too = false) {
    const std::string name = as_string(need(body, "rig"), "rig");
    if (rig::find_rig(g(), name).is_valid()) return name;
    if (unbuilt_rig(name)) {
      if (unbuilt_too) return name;
      refuse(409, "rig: '" + name + "' is at step 0 (nothing built): step it forward first", "rig");
    }
    refuse(404, "rig: the scene has no rig '" + name + "'", "rig");
  }

  // A Build of the rig: the scene's, or at step 0 for a rig stepped back there.
  std::unique_ptr<rig::Build> open_rig(const std::string& name) {
    if (const Unbuilt* u = unbuilt_rig(name)) return take(rig::Build::open(scene, u->definition, factory, u->options));
    return take(rig::Build::reopen(scene, name, factory));
  }

  // What rigs_report() says of a rig, for one at step 0.
  static Json unbuilt_report(const std::string& name, const rig::Build& build) {
    const rig::Definition& def = build.definition();
    Json on_disk = nullptr;
    std::error_code ec;
    if (!def.source.empty() && fs::is_regular_file(def.source, ec)) {
      rig::ParseResult p = rig::load_definition(def.source);
      if (p.ok()) on_disk = p.definition.version;
    }
    return Json{{"name", name},
                {"version", def.version},
                {"definition", def.source},
                {"definitionVersion", on_disk},
                {"outOfDate", on_disk.is_string() && on_disk.get<std::string>() != def.version},
                {"editMode", build.edit_mode()},
                {"buildPosition", 0},
                {"components", Json::array()}};
  }

  Json get_rigs(const Request&, const Json&) {
    Json rigs = rig::rigs_report(g());
    for (Json& r : rigs) {
      auto build = rig::Build::reopen(scene, r["name"].get<std::string>(), factory);
      r["steps"] = build ? static_cast<int>((*build)->plan().size()) : 0;
      r["features"] = build ? features_json(**build) : Json::array();
    }
    for (const auto& [name, u] : unbuilt) {
      if (!unbuilt_rig(name)) continue;
      auto build = open_rig(name);
      Json r = unbuilt_report(name, *build);
      r["steps"] = static_cast<int>(build->plan().size());
      r["features"] = features_json(*build);
      rigs.push_back(std::move(r));
    }
    return Json{{"rigs", std::move(rigs)}};
  }

  rig::Definition read_definition_at(const fs::path& path, const std::string& field) {
    auto def = rig::read_definition(path, factory.schemas());
    if (!def) refuse(def.status().code() == ErrorCode::kNotFound ? 404 : 400, def.status().message(), field);
    return std::move(*def);
  }

  Json post_rigs_add(const Request&, const Json& body) {
    const fs::path path = confined(as_string(need(body, "definition"), "definition"), "definition");
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) refuse(404, "definition: no file '" + path.string() + "'", "definition");
    read_definition_at(path, "definition");  // 400 with every problem before building
    rig::BuildOptions options;
    if (const Json* e = opt(body, "editMode")) options.edit_mode = as_bool(*e, "editMode");
    const rig::AddedRig added = take(rig::add_rig(scene, path, factory, options), "definition");
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
    const bool force = f && as_bool(*f, "force");
    const rig::UpdateReport r = take(rig::update_rig(scene, name, factory, {}, force, keep));
    return Json{{"rig", r.rig}, {"from", r.from}, {"to", r.to}, {"updated", r.updated}, {"rebuilt", r.rebuilt}};
  }

  Json post_rigs_remove(const Request&, const Json& body) {
    const std::string name = rig_name(body, true);
    if (unbuilt_rig(name)) {
      // Nothing of it is in the scene: it leaves the list.
      unbuilt.erase(name);
      return Json{{"rig", name}};
    }
    unbuilt.erase(name);
    auto build = take(rig::Build::reopen(scene, name, factory));
    graph::Transaction tx(g(), "remove rig " + name);
    if (Status s = build->remove(); !s) {
      tx.rollback();
      check(s);
    }
    return Json{{"rig", name}};
  }

  Json post_rigs_edit(const Request&, const Json& body) {
    const std::string name = rig_name(body);
    std::optional<fs::path> out;
    if (const Json* o = opt(body, "definitionOut"))
      out = confined(as_string(*o, "definitionOut"), "definitionOut");
    bool keep_editing = false;
    if (const Json* k = opt(body, "keepEditing")) keep_editing = as_bool(*k, "keepEditing");
    auto build = take(rig::Build::reopen(scene, name, factory));
    const fs::path def_path = out ? *out : fs::path(build->definition().source);
    // As `rigel edit`: the rig records the file its moved guides are saved
    // to (so it is up to date with it) and leaves edit mode unless asked not to.
    const rig::Edits edits = take(build->commit_edits(def_path.string(), !keep_editing));
    if (!edits.changed.empty()) {
      if (def_path.empty()) refuse(400, "definitionOut: the rig has no definition path; give one", "definitionOut");
      make_parent(def_path, "definitionOut");
      check_saved(rig::save_definition(edits.definition, def_path), "definitionOut");
    }
    return Json{{"rig", name},
                {"version", edits.definition.version},
                {"changed", edits.changed},
                {"ignored", edits.ignored},
                {"definition", edits.changed.empty() ? Json(nullptr) : Json(def_path.string())},
                {"editMode", build->edit_mode()}};
  }

  Json post_rigs_step(const Request&, const Json& body) {
    const std::string name = rig_name(body, true);
    auto build = open_rig(name);
    const bool was_built = build->position() > 0;
    const int steps = static_cast<int>(build->plan().size());
    int to = build->position();
    if (const Json* t = opt(body, "to")) {
      const double v = as_number(*t, "to");
      if (v != std::floor(v) || v < 0 || v > steps)
        refuse(400, "to: expected a step from 0 to " + std::to_string(steps), "to");
      to = static_cast<int>(v);
    } else {
      const double by = as_number(need(body, "by"), "by");
      if (by != std::floor(by)) refuse(400, "by: expected a whole number", "by");
      to = static_cast<int>(std::clamp(to + by, 0.0, static_cast<double>(steps)));
    }
    {
      graph::Transaction tx(g(), "step " + name + " to " + std::to_string(to));
      if (Status s = build->go_to(to); !s) {
        tx.rollback();
        check(s);
      }
    }
    const int position = build->position();
    if (position == 0 && was_built)
      unbuilt[name] = Unbuilt{build->definition(), rig::BuildOptions{build->edit_mode()}, g().undo_count(), ++unbuilt_serial};
    return Json{{"rig", name},
                {"position", position},
                {"steps", steps},
                {"step", position > 0 ? build->plan()[static_cast<std::size_t>(position - 1)].label() : ""}};
  }

  // The features the rig's steps name (seed 003), each with its rig-level
  // state and switches.
  static Json features_json(const rig::Build& build) {
    Json list = Json::array();
    std::vector<std::pair<std::string, std::string>> seen;
    for (const rig::PlannedStep& p : build.plan()) {
      if (p.feature.empty()) continue;
      std::pair<std::string, std::string> key{p.feature, p.switch_name};
      if (std::find(seen.begin(), seen.end(), key) != seen.end()) continue;
      seen.push_back(key);
      bool enabled = true;
      for (const rig::Feature& f : build.definition().features) {
        if (f.name != p.feature) continue;
        enabled = f.enabled;
        if (!p.switch_name.empty())
          for (const rig::FeatureSwitch& sw : f.switches)
            if (sw.name == p.switch_name) enabled = enabled && sw.enabled;
      }
      list.push_back(Json{{"feature", p.feature}, {"switch", p.switch_name}, {"enabled", enabled}});
    }
    return list;
  }

  Json post_rigs_feature(const Request&, const Json& body) {
    const std::string name = rig_name(body, true);
    const std::string feature = as_string(need(body, "feature"), "feature");
    const bool enabled = as_bool(need(body, "enabled"), "enabled");
    std::string switch_name;
    if (const Json* sw = opt(body, "switch")) switch_name = as_string(*sw, "switch");
    auto build = open_rig(name);
    bool known = false;
    for (const rig::PlannedStep& p : build->plan()) known = known || p.feature == feature;
    if (!known) refuse(404, "feature: no step of rig '" + name + "' names feature '" + feature + "'", "feature");
    graph::Transaction tx(g(), std::string(enabled ? "enable " : "disable ") + feature);
    if (Status s = build->set_feature(feature, enabled, switch_name); !s) {
      tx.rollback();
      check(s, "feature");
    }
    if (build->position() == 0) {
      auto it = unbuilt.find(name);
      if (it != unbuilt.end()) it->second.definition = build->definition();
    }
    return Json{{"rig", name}, {"features", features_json(*build)}, {"position", build->position()},
                {"steps", static_cast<int>(build->plan().size())}};
  }

  Json post_rigs_edit_mode(const Request&, const Json& body) {
    const std::string name = rig_name(body, true);
    const bool on = as_bool(need(body, "on"), "on");
    auto build = open_rig(name);
    check(build->set_edit_mode(on));
    if (build->position() == 0) {
      auto it = unbuilt.find(name);
      if (it != unbuilt.end()) it->second.options.edit_mode = build->edit_mode();
    }
    return Json{{"rig", name}, {"editMode", build->edit_mode()}};
  }

  // ---- routes: definitions -------------------------------------------------------

  // A rig's definition as it was built (the .rig.json form), for the editor.
  Json get_definition(const Request& req, const Json&) {
    auto it = req.query.find("rig");
    if (it == req.query.end()) refuse(400, "missing query 'rig'", "rig");
    if (!rig::find_rig(g(), it->second).is_valid() && !unbuilt_rig(it->second))
      refuse(404, "rig: the scene has no rig '" + it->second + "'", "rig");
    auto build = open_rig(it->second);
    return Json{{"rig", it->second},
                {"path", build->definition().source},
                {"definition", Json::parse(rig::write_definition(build->definition(), rig::Syntax::kJson))}};
  }


  Json get_components(const Request&, const Json&) {
    Json list = Json::array();
    for (const std::string& t : factory.schemas().types()) list.push_back(rig::component_schema_json(*factory.schemas().find(t)));
    return Json{{"components", std::move(list)}};
  }

  // The request's definition, parsed (the .rig.json form) and validated.
  std::pair<rig::Definition, std::vector<rig::Diagnostic>> parse_request_definition(const Json& body) {
    const Json& def = need(body, "definition");
    if (!def.is_object()) refuse(400, "definition: expected the .rig.json object", "definition");
    rig::ParseResult p = rig::parse_definition(def.dump(2), rig::Syntax::kJson, "definition", factory.schemas());
    if (!p.ok()) return {std::move(p.definition), std::move(p.errors)};
    std::vector<rig::Diagnostic> problems = rig::validate(p.definition, factory.schemas());
    return {std::move(p.definition), std::move(problems)};
  }

  static Json problems_json(const std::vector<rig::Diagnostic>& problems) {
    Json list = Json::array();
    for (const rig::Diagnostic& d : problems) list.push_back(Json{{"where", d.str()}, {"message", d.message}});
    return list;
  }

  Json post_definition_validate(const Request&, const Json& body) {
    auto [def, problems] = parse_request_definition(body);
    return Json{{"ok", problems.empty()}, {"problems", problems_json(problems)}};
  }

  // Live rebuild: builds the rig, or rebuilds what changed when the scene
  // has it already.
  Json post_definition_build(const Request&, const Json& body) {
    auto [def, problems] = parse_request_definition(body);
    if (!problems.empty()) throw ApiError{400, "definition: " + problems.front().str(), "definition"};
    const std::string name = def.name;
    std::vector<std::string> rebuilt;
    if (rig::find_rig(g(), name).is_valid()) {
      auto build = take(rig::Build::reopen(scene, name, factory));
      def.source = build->definition().source;
      graph::Transaction tx(g(), "rebuild " + name);
      Status s = build->position() < static_cast<int>(build->plan().size()) ? build->build_all() : Status::ok();
      if (s) {
        auto r = build->rebuild_changed(std::move(def), rig::Build::Rebuild::kChanged);
        if (r) rebuilt = std::move(*r);
        else s = r.status();
      }
      if (!s) {
        tx.rollback();
        check(s, "definition");
      }
    } else {
      def.source.clear();  // built from the editor: no file behind it yet
      graph::Transaction tx(g(), "build " + name);
      auto build = rig::Build::open(scene, std::move(def), factory);
      if (!build) {
        tx.rollback();
        check(build.status(), "definition");
      }
      if (Status s = (*build)->build_all(); !s) {
        tx.rollback();
        check(s, "definition");
      }
      for (const rig::Component* c : (*build)->components()) rebuilt.push_back(c->rig_id);
    }
    return Json{{"rig", name}, {"rebuilt", rebuilt}};
  }

  Json post_definition_save(const Request&, const Json& body) {
    const std::string rel = as_string(need(body, "path"), "path");
    const fs::path path = confined(rel, "path");
    const auto syntax = rig::syntax_of(path);
    if (!syntax) refuse(400, "path: '" + rel + "' is neither .rig.xml nor .rig.json", "path");
    auto [def, problems] = parse_request_definition(body);
    if (!problems.empty()) throw ApiError{400, "definition: " + problems.front().str(), "definition"};
    make_parent(path, "path");
    // Saving over a definition with other content makes a new version.
    std::error_code ec;
    if (fs::exists(path, ec)) {
      rig::ParseResult old = rig::load_definition(path, factory.schemas());
      const std::string old_version = old.ok() ? old.definition.version : def.version;
      if (rig::compare_versions(def.version, old_version) <= 0) {
        rig::Definition same = def;
        same.version = old_version;
        std::ifstream in(path, std::ios::binary);
        std::ostringstream text;
        text << in.rdbuf();
        if (!old.ok() || text.str() != rig::write_definition(same, *syntax)) def.version = rig::next_version(old_version);
        else def.version = old_version;
      }
    }
    def.source = path.string();
    check_saved(rig::save_definition(def, path), "path");
    return Json{{"path", path.string()}, {"version", def.version}};
  }
};

Workspace::Workspace(std::unique_ptr<scene::Scene> scene, fs::path scene_path, fs::path root,
                     const rig::ComponentFactory& factory)
    : scene_(std::move(scene)),
      impl_(std::make_unique<Impl>(*scene_, std::move(scene_path), std::move(root), factory)) {}

Workspace::~Workspace() = default;

void Workspace::set_character(fs::path file) {
  std::lock_guard lock(mutex_);
  impl_->character = std::move(file);
}

std::uint64_t Workspace::revision() const {
  std::lock_guard lock(mutex_);
  return impl_->revision;
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
    bool changes;  // a success increments the revision
  };
  static const Route kRoutes[] = {
      {"GET", "/api/revision", &Impl::get_revision, false},
      {"GET", "/api/scene", &Impl::get_scene, false},
      {"GET", "/api/nodes", &Impl::get_nodes, false},
      {"GET", "/api/pose", &Impl::get_pose, false},
      {"GET", "/api/keys", &Impl::get_keys, false},
      {"GET", "/api/rigs", &Impl::get_rigs, false},
      {"GET", "/api/components", &Impl::get_components, false},
      {"GET", "/api/character.glb", nullptr, false},
      {"POST", "/api/save", &Impl::post_save, false},
      {"POST", "/api/select", &Impl::post_select, true},
      {"POST", "/api/mode", &Impl::post_mode, true},
      {"POST", "/api/options", &Impl::post_options, true},
      {"POST", "/api/drag", &Impl::post_drag, true},
      {"POST", "/api/release", &Impl::post_release, true},
      {"POST", "/api/undo", &Impl::post_undo, true},
      {"POST", "/api/redo", &Impl::post_redo, true},
      {"POST", "/api/time", &Impl::post_time, true},
      {"POST", "/api/key", &Impl::post_key, true},
      {"POST", "/api/rigs/add", &Impl::post_rigs_add, true},
      {"POST", "/api/rigs/update", &Impl::post_rigs_update, true},
      {"POST", "/api/rigs/remove", &Impl::post_rigs_remove, true},
      {"POST", "/api/rigs/edit", &Impl::post_rigs_edit, true},
      {"POST", "/api/rigs/step", &Impl::post_rigs_step, true},
      {"POST", "/api/rigs/edit-mode", &Impl::post_rigs_edit_mode, true},
      {"POST", "/api/rigs/feature", &Impl::post_rigs_feature, true},
      {"GET", "/api/definition", &Impl::get_definition, false},
      {"POST", "/api/definition/validate", &Impl::post_definition_validate, false},
      {"POST", "/api/definition/build", &Impl::post_definition_build, true},
      {"POST", "/api/definition/save", &Impl::post_definition_save, false},
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
    if (!route->handler) return impl_->get_character();
    // A new edit made after undoing a step to 0 drops that rig's entry.
    struct Prune {
      Impl& impl;
      std::vector<std::uint64_t> undone;
      ~Prune() { impl.drop_unbuilt(undone); }
    } prune{*impl_, route->handler == &Impl::post_undo || route->handler == &Impl::post_redo
                        ? std::vector<std::uint64_t>{}
                        : impl_->unbuilt_undone()};
    Json answer = (impl_.get()->*(route->handler))(request, body);
    if (route->changes) ++impl_->revision;
    // The revision this answer describes: after the change.
    if (answer.is_object() && (route->changes || !answer.contains("revision"))) answer["revision"] = impl_->revision;
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
