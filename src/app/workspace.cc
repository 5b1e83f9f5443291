// The workspace (workspace.h): construction, paths, nodes and reports.

#include "rigel/app/workspace.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_set>

#include "rigel/ephemeral/keying.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/math/rotation.h"
#include "rigel/math/transform.h"
#include "rigel/rig/meta.h"
#include "rigel/scene/transform_types.h"

namespace rigel::app {

namespace xform = scene::xform;

Quat rotation_from_euler_degrees(const Vec3& degrees) {
  return math::euler_to_quat(degrees * (M_PI / 180.0), math::RotateOrder::kXYZ);
}

double key_frame(double seconds, double fps) {
  const double frame = seconds * fps;
  if (std::abs(frame - std::round(frame)) <= ephemeral::kKeyFrameTolerance) return std::round(frame);
  return std::round(frame * 1e6) / 1e6;
}

Result<fs::path> confined_path(const fs::path& root, const std::string& path, const std::string& field) {
  auto bad = [&](std::string message) { return Status(ErrorCode::kInvalidArgument, field + ": " + message).with_field(field); };
  if (path.empty()) return bad("empty path");
  if (path.find('\0') != std::string::npos) return bad("bad path");
  const fs::path p(path);
  if (p.is_absolute()) return bad("'" + path + "' is absolute; give a path relative to the served folder");
  std::error_code ec;
  const fs::path base = fs::weakly_canonical(root, ec);
  if (ec) return Status(ErrorCode::kIoError, "served folder " + root.string() + ": " + ec.message()).with_field(field);
  // weakly_canonical resolves the symbolic links of the part that exists and
  // every "..", so a path that leaves the root in any way ends outside it.
  const fs::path full = fs::weakly_canonical(base / p, ec);
  if (ec) return bad("'" + path + "': " + ec.message());
  const auto [b, f] = std::mismatch(base.begin(), base.end(), full.begin(), full.end());
  if (b != base.end()) return bad("'" + path + "' is outside the served folder");
  return full;
}

Workspace::Workspace(std::shared_ptr<scene::Scene> scene, fs::path scene_path, fs::path root,
                     const rig::ComponentFactory& factory, ephemeral::SessionOptions options)
    : scene_(std::move(scene)),
      session_(std::make_unique<ephemeral::Session>(*scene_, options)),
      scene_path_(std::move(scene_path)),
      root_(std::move(root)),
      factory_(factory) {}

Workspace::~Workspace() = default;

Result<fs::path> Workspace::resolve_path(const std::string& path, const std::string& field) const {
  if (!root_.empty()) return confined_path(root_, path, field);
  if (path.empty()) return Status(ErrorCode::kInvalidArgument, field + ": empty path").with_field(field);
  return fs::path(path);
}

// ---- nodes -------------------------------------------------------------------

Result<NodeId> Workspace::node(const std::string& ref, const std::string& field) const {
  NodeId id;
  if (auto u = graph::Uuid::parse(ref)) id = graph().find(*u);
  if (!id.is_valid() && graph::Graph::is_valid_name(ref)) id = graph().find(ref);
  // A rig's nameless address (`hero:arm_L/fkIkSwitch`), which no rename breaks.
  if (!id.is_valid() && ref.find(':') != std::string::npos) {
    auto at = rig::resolve_address(graph(), ref);
    if (at) id = *at;
    else if (rig::find_rig(graph(), ref.substr(0, ref.find(':'))).is_valid())
      return Status(ErrorCode::kNotFound, field + ": " + at.status().message()).with_field(field);
  }
  if (!id.is_valid()) return Status(ErrorCode::kNotFound, field + ": no node '" + ref + "'").with_field(field);
  return id;
}

bool Workspace::is_control(NodeId id) const {
  const graph::Node* n = graph().node(id);
  return n && n->type().name() == scene::kControlType;
}

Result<NodeId> Workspace::control(const std::string& ref, const std::string& field) const {
  auto id = node(ref, field);
  if (!id) return id;
  return control_of(*id, field);
}

NodeId Workspace::key_target(NodeId id) const {
  if (is_control(id)) return id;
  const NodeId c = ephemeral::control_of(graph(), id);
  return c.is_valid() ? c : id;
}

Result<NodeId> Workspace::key_target(const std::string& ref, const std::string& field) const {
  auto id = node(ref, field);
  if (!id) return id;
  return key_target(*id);
}

Result<NodeId> Workspace::control_of(NodeId id, const std::string& field) const {
  if (is_control(id)) return id;
  const NodeId c = ephemeral::control_of(graph(), id);
  if (!c.is_valid()) {
    return Status(ErrorCode::kInvalidArgument, field + ": '" + graph().node(id)->name() +
                                                   "' is not a control of an ephemeral rig or a built rig (nor a joint "
                                                   "driven by one)")
        .with_field(field);
  }
  return c;
}

std::vector<NodeId> Workspace::all_controls() const {
  const graph::Graph& g = graph();
  std::vector<NodeId> out;
  std::unordered_set<std::uint32_t> listed;  // NodeId::index
  for (NodeId rig : ephemeral::rigs_find(g))
    for (NodeId c : ephemeral::rig_controls(g, rig))
      if (listed.insert(c.index).second) out.push_back(c);
  for (NodeId id : scene_->hierarchy())
    if (is_control(id) && listed.insert(id.index).second) out.push_back(id);
  return out;
}

NodeId Workspace::parent_of(NodeId id) const {
  auto src = graph().source(graph::Plug{id, xform::kParentMatrix});
  return src ? src->node : NodeId{};
}

std::vector<NodeId> Workspace::selection() const {
  std::vector<NodeId> out;
  for (NodeId id : graph().selection())
    if (graph().node(id)) out.push_back(id);
  return out;
}

std::vector<NodeEntry> Workspace::nodes() const {
  std::vector<NodeEntry> out;
  for (NodeId id : scene_->hierarchy()) out.push_back(NodeEntry{id, parent_of(id)});
  return out;
}

std::vector<ControlEntry> Workspace::controls() const {
  std::vector<ControlEntry> out;
  graph::Graph& g = scene_->graph();
  // Child controls per control: an ephemeral control's group is the nearest
  // control above it with three or more (a region: the face, a hand).
  std::map<std::uint32_t, int> child_controls;  // by node index
  for (NodeId id : scene_->hierarchy())
    if (is_control(id) && is_control(g.parent(id))) ++child_controls[g.parent(id).index];
  auto region = [&](NodeId id) -> std::string {
    for (NodeId p = g.parent(id); p.is_valid() && is_control(p); p = g.parent(p))
      if (child_controls[p.index] >= 3) return g.node(p)->name();
    return {};
  };
  for (NodeId id : scene_->hierarchy()) {
    if (!is_control(id)) continue;
    ControlEntry c;
    c.node = id;
    if (const auto* p = std::get_if<std::vector<Vec3>>(&g.evaluate(id, scene::control_attr::kShapePoints))) c.points = *p;
    if (const auto* closed = std::get_if<bool>(&g.evaluate(id, scene::control_attr::kShapeClosed))) c.closed = *closed;
    if (const auto* color = std::get_if<Vec3>(&g.evaluate(id, scene::control_attr::kShapeColor))) c.color = *color;
    const NodeId erig = ephemeral::rig_of(g, id);
    const NodeId built = rig::rig_of(g, id);
    c.ephemeral = erig.is_valid();
    if (erig.is_valid()) c.rig = g.node(erig)->name();
    if (c.rig.empty() && built.is_valid()) c.rig = rig::meta_string(g, built, "rigName");
    if (!c.ephemeral && built.is_valid()) {
      const NodeId component = rig::component_of(g, id);
      if (component.is_valid() && component != built) c.group = rig::meta_string(g, component, "componentName");
    } else {
      c.group = region(id);
    }
    if (c.group.empty()) c.group = c.rig;
    out.push_back(std::move(c));
  }
  return out;
}

SceneSummary Workspace::summary() const {
  const graph::Graph& g = graph();
  SceneSummary s;
  s.fps = g.fps();
  s.frame = scene_->frame();
  s.time = g.time();
  // The frame range: the union of the keys of the ephemeral rigs' controls.
  double first = 0, last = 0;
  bool any = false;
  for (NodeId c : ephemeral::rigs_find(g)) {
    const std::vector<double> t = ephemeral::key_times(g, ephemeral::rig_controls(g, c));
    if (t.empty()) continue;
    first = any ? std::min(first, t.front()) : t.front();
    last = any ? std::max(last, t.back()) : t.back();
    any = true;
  }
  s.range = {std::round(first * g.fps()), std::round(last * g.fps())};
  s.playback = scene::playback_range(g);
  s.mode = session_->mode();
  s.auto_key = session_->options().auto_key;
  for (NodeId r : ephemeral::rigs_find(g))
    s.key_scopes.emplace_back(g.node(r)->name(), ephemeral::key_scope_name(ephemeral::key_scope(g, r)));
  s.can_undo = g.can_undo();
  s.can_redo = g.can_redo();
  s.undo_label = g.undo_label();
  s.redo_label = g.redo_label();
  s.selection = selection();
  return s;
}

std::vector<Trs> Workspace::pose(Space space) const {
  std::vector<Trs> out;
  graph::Graph& g = scene_->graph();
  const std::vector<NodeId> order = scene_->hierarchy();
  out.reserve(order.size());
  for (NodeId id : order) {
    Mat4 m;
    if (space == Space::kWorld) {
      m = scene_->world_matrix(id);
    } else {
      const Mat4 local = scene_->local_matrix(id);
      const auto* opm = std::get_if<Mat4>(&g.evaluate(id, xform::kOffsetParentMatrix));
      m = opm ? Mat4(*opm * local) : local;
    }
    const math::Decomposed d = math::decompose(m);
    out.push_back(Trs{id, d.translate, d.rotation, d.scale});
  }
  return out;
}

// ---- keys --------------------------------------------------------------------

KeyReport Workspace::keys(const std::vector<NodeId>& controls) const {
  const graph::Graph& g = graph();
  KeyReport r;
  r.set = ephemeral::keying_set(g, controls);
  r.times = ephemeral::key_times(g, controls);
  for (double t : r.times) r.frames.push_back(key_frame(t, g.fps()));
  // The keying scope of the controls' ephemeral rig; controls of a built
  // rig are keyed one by one ("controls").
  if (!controls.empty()) {
    const NodeId rig = ephemeral::rig_of(g, controls.front());
    r.scope = rig.is_valid() ? ephemeral::key_scope_name(ephemeral::key_scope(g, rig)) : "controls";
  }
  return r;
}

}  // namespace rigel::app
