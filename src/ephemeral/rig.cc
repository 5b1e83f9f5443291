#include "rigel/ephemeral/rig.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <unordered_map>

#include "rigel/math/transform.h"
#include "rigel/ops/registry.h"
#include "rigel/rig/meta.h"
#include "rigel/rig/templates.h"
#include "rigel/scene/shapes.h"
#include "rigel/scene/transform_types.h"

namespace rigel::ephemeral {
namespace {

using graph::AttrIndex;
using graph::AttrSpec;
using math::Vec3;
using graph::AttrType;
using graph::Plug;
using graph::Value;
using graph::ValueType;
namespace xform = scene::xform;

AttrSpec array_input(std::string name, ValueType type) {
  AttrSpec spec;
  spec.name = std::move(name);
  spec.type = AttrType{type, true};
  spec.flags = graph::kInput | graph::kStorable | graph::kHidden;
  return spec;
}

const graph::NodeType* rig_type(const Graph& graph) { return graph.registry().find(kRigType); }

bool is_rig(const Graph& graph, NodeId id) {
  const graph::Node* n = graph.node(id);
  return n && n->type().name() == kRigType;
}

struct RigData {
  std::vector<std::string> controls;
  std::vector<std::int64_t> kind, from, to;
};

RigData rig_data(const Graph& graph, NodeId rig) {
  const graph::Node& n = *graph.node(rig);
  RigData d;
  d.controls = std::get<std::vector<std::string>>(n.value(rig_attr::kControls));
  d.kind = std::get<std::vector<std::int64_t>>(n.value(rig_attr::kRelationKind));
  d.from = std::get<std::vector<std::int64_t>>(n.value(rig_attr::kRelationFrom));
  d.to = std::get<std::vector<std::int64_t>>(n.value(rig_attr::kRelationTo));
  return d;
}

Status rig_data_write(Graph& graph, NodeId rig, RigData d) {
  graph::Transaction tx(graph, "edit ephemeral relations");
  Status s = graph.set_value(Plug{rig, rig_attr::kControls, -1}, std::move(d.controls));
  if (s) s = graph.set_value(Plug{rig, rig_attr::kRelationKind, -1}, std::move(d.kind));
  if (s) s = graph.set_value(Plug{rig, rig_attr::kRelationFrom, -1}, std::move(d.from));
  if (s) s = graph.set_value(Plug{rig, rig_attr::kRelationTo, -1}, std::move(d.to));
  if (!s) tx.rollback();
  return s;
}

// Index of `control` in d.controls; appended when `add` and absent.
std::int64_t control_slot(const Graph& graph, RigData& d, NodeId control, bool add) {
  const std::string uuid = graph.node(control)->uuid().str();
  auto it = std::find(d.controls.begin(), d.controls.end(), uuid);
  if (it != d.controls.end()) return it - d.controls.begin();
  if (!add) return -1;
  d.controls.push_back(uuid);
  return static_cast<std::int64_t>(d.controls.size()) - 1;
}

Status check_relation_ends(const Graph& graph, NodeId rig, const Relation& r) {
  if (!is_rig(graph, rig)) return error(ErrorCode::kInvalidArgument, "not an ephemeralRig node");
  for (NodeId c : {r.from, r.to}) {
    const graph::Node* n = graph.node(c);
    if (!n) return error(ErrorCode::kNotFound, "relation: no such control (stale handle)");
    if (n->type().name() != scene::kControlType)
      return error(ErrorCode::kInvalidArgument, "relation: '" + n->name() + "' is not a control");
    NodeId owner = rig_of(graph, c);
    if (owner.is_valid() && owner != rig)
      return error(ErrorCode::kInvalidArgument, "relation: '" + n->name() + "' belongs to another rig");
  }
  if (r.from == r.to) return error(ErrorCode::kInvalidArgument, "relation: a control cannot drive itself");
  if (static_cast<std::int64_t>(r.kind) < 0 || static_cast<std::int64_t>(r.kind) >= kRelationKindCount)
    return error(ErrorCode::kInvalidArgument, "relation: unknown kind");
  return Status::ok();
}

// Index of the relation in d, -1 when absent.
int relation_slot(const Graph& graph, RigData& d, const Relation& r) {
  std::int64_t f = control_slot(graph, d, r.from, false), t = control_slot(graph, d, r.to, false);
  if (f < 0 || t < 0) return -1;
  for (std::size_t i = 0; i < d.kind.size(); ++i)
    if (d.kind[i] == static_cast<std::int64_t>(r.kind) && d.from[i] == f && d.to[i] == t) return static_cast<int>(i);
  return -1;
}


}  // namespace

const char* relation_kind_name(RelationKind kind) {
  switch (kind) {
    case RelationKind::kForward: return "forward";
    case RelationKind::kInverse: return "inverse";
    case RelationKind::kPair: return "pair";
    case RelationKind::kMagnet: return "magnet";
  }
  return "unknown";
}

std::optional<RelationKind> relation_kind_from_name(std::string_view name) {
  for (int k = 0; k < kRelationKindCount; ++k)
    if (name == relation_kind_name(static_cast<RelationKind>(k))) return static_cast<RelationKind>(k);
  return std::nullopt;
}

Status register_ephemeral_types(graph::Registry& registry) {
  graph::NodeTypeSpec spec;
  spec.name = kRigType;
  spec.description =
      "An ephemeral rig: its controls (by uuid) and the directed relations between them "
      "(kind, from, to as indices into controls), its keying scope, and its merge group and "
      "carrier (keying.h). Sessions walk these; nothing computes.";
  AttrSpec scope = graph::input_attr("keyScope", AttrType{ValueType::kEnum, false}, std::int64_t{0});
  scope.enum_names = {"character", "controls"};
  spec.attrs = {array_input("controls", ValueType::kString), array_input("relationKind", ValueType::kInt),
                array_input("relationFrom", ValueType::kInt), array_input("relationTo", ValueType::kInt),
                std::move(scope),
                graph::input_attr("mergeGroup", AttrType{ValueType::kString, false}, std::string()),
                graph::input_attr("carrier", AttrType{ValueType::kString, false}, std::string())};
  return registry.add(std::move(spec));
}

std::shared_ptr<const graph::Registry> default_registry() {
  static const std::shared_ptr<const graph::Registry> registry = [] {
    auto r = std::make_shared<graph::Registry>();
    Status s = scene::register_scene_types(*r);
    if (s) s = ops::register_ops_types(*r);
    if (s) s = rig::register_rig_types(*r);
    if (s) s = register_ephemeral_types(*r);
    assert(s.is_ok() && "the built-in node types must register");
    (void)s;
    return r;
  }();
  return registry;
}

NodeId control_of(const Graph& graph, NodeId id) {
  const graph::Node* n = graph.node(id);
  if (!n) return {};
  if (n->type().name() == scene::kControlType) return rig_of(graph, id).is_valid() ? id : NodeId{};
  for (const graph::Connection& c : n->inputs()) {
    if (c.dst.attr != xform::kTranslate || c.dst.component >= 0) continue;
    const graph::Node* src = graph.node(c.src.node);
    if (src && src->type().name() == scene::kControlType && rig_of(graph, c.src.node).is_valid()) return c.src.node;
  }
  return {};
}

std::vector<NodeId> rigs_find(const Graph& graph) {
  std::vector<NodeId> out;
  for (NodeId id : graph.nodes())
    if (is_rig(graph, id)) out.push_back(id);
  return out;
}

NodeId rig_of(const Graph& graph, NodeId control) {
  const graph::Node* n = graph.node(control);
  if (!n) return {};
  const std::string uuid = n->uuid().str();
  for (NodeId rig : rigs_find(graph)) {
    const auto& list = std::get<std::vector<std::string>>(graph.node(rig)->value(rig_attr::kControls));
    if (std::find(list.begin(), list.end(), uuid) != list.end()) return rig;
  }
  return {};
}

std::vector<NodeId> rig_controls(const Graph& graph, NodeId rig) {
  std::vector<NodeId> out;
  if (!is_rig(graph, rig)) return out;
  for (const std::string& u : std::get<std::vector<std::string>>(graph.node(rig)->value(rig_attr::kControls))) {
    auto uuid = graph::Uuid::parse(u);
    NodeId id = uuid ? graph.find(*uuid) : NodeId{};
    if (id.is_valid()) out.push_back(id);
  }
  return out;
}

Result<std::vector<Relation>> relations(const Graph& graph, NodeId rig) {
  if (!is_rig(graph, rig)) return error(ErrorCode::kInvalidArgument, "not an ephemeralRig node");
  RigData d = rig_data(graph, rig);
  std::vector<NodeId> ids(d.controls.size());
  for (std::size_t i = 0; i < d.controls.size(); ++i) {
    auto uuid = graph::Uuid::parse(d.controls[i]);
    if (uuid) ids[i] = graph.find(*uuid);
  }
  std::vector<Relation> out;
  const std::size_t n = std::min({d.kind.size(), d.from.size(), d.to.size()});
  for (std::size_t i = 0; i < n; ++i) {
    auto ok = [&](std::int64_t k) { return k >= 0 && k < static_cast<std::int64_t>(ids.size()) && ids[k].is_valid(); };
    if (!ok(d.from[i]) || !ok(d.to[i]) || d.kind[i] < 0 || d.kind[i] >= kRelationKindCount) continue;
    out.push_back(Relation{static_cast<RelationKind>(d.kind[i]), ids[d.from[i]], ids[d.to[i]]});
  }
  return out;
}

Status relation_add(Graph& graph, NodeId rig, const Relation& r) {
  if (Status s = check_relation_ends(graph, rig, r); !s) return s;
  RigData d = rig_data(graph, rig);
  if (relation_slot(graph, d, r) >= 0)
    return error(ErrorCode::kAlreadyExists, std::string("relation: this ") + relation_kind_name(r.kind) +
                                                " relation exists already");
  d.kind.push_back(static_cast<std::int64_t>(r.kind));
  d.from.push_back(control_slot(graph, d, r.from, true));
  d.to.push_back(control_slot(graph, d, r.to, true));
  return rig_data_write(graph, rig, std::move(d));
}

Status relation_remove(Graph& graph, NodeId rig, const Relation& r) {
  if (!is_rig(graph, rig)) return error(ErrorCode::kInvalidArgument, "not an ephemeralRig node");
  if (!graph.node(r.from) || !graph.node(r.to)) return error(ErrorCode::kNotFound, "relation: no such control");
  RigData d = rig_data(graph, rig);
  int i = relation_slot(graph, d, r);
  if (i < 0) return error(ErrorCode::kNotFound, "relation: no such relation");
  d.kind.erase(d.kind.begin() + i);
  d.from.erase(d.from.begin() + i);
  d.to.erase(d.to.begin() + i);
  return rig_data_write(graph, rig, std::move(d));
}

Status relation_set_kind(Graph& graph, NodeId rig, const Relation& r, RelationKind kind) {
  if (!is_rig(graph, rig)) return error(ErrorCode::kInvalidArgument, "not an ephemeralRig node");
  if (!graph.node(r.from) || !graph.node(r.to)) return error(ErrorCode::kNotFound, "relation: no such control");
  RigData d = rig_data(graph, rig);
  int i = relation_slot(graph, d, r);
  if (i < 0) return error(ErrorCode::kNotFound, "relation: no such relation");
  Relation changed = r;
  changed.kind = kind;
  if (relation_slot(graph, d, changed) >= 0) return error(ErrorCode::kAlreadyExists, "relation: the result exists already");
  d.kind[i] = static_cast<std::int64_t>(kind);
  return rig_data_write(graph, rig, std::move(d));
}

Status group_add(Graph& graph, NodeId rig, const std::vector<NodeId>& controls) {
  if (controls.size() < 2) return error(ErrorCode::kInvalidArgument, "group: needs two controls or more");
  graph::Transaction tx(graph, "add ephemeral group");
  for (std::size_t i = 0; i < controls.size(); ++i) {
    for (std::size_t j = 0; j < controls.size(); ++j) {
      if (i == j) continue;
      Relation r{RelationKind::kPair, controls[i], controls[j]};
      Status s = check_relation_ends(graph, rig, r);
      if (s) {
        RigData d = rig_data(graph, rig);
        if (relation_slot(graph, d, r) >= 0) continue;
        s = relation_add(graph, rig, r);
      }
      if (!s) {
        tx.rollback();
        return s;
      }
    }
  }
  return Status::ok();
}

Status SetupOptions::validate() const {
  if (!(shape_radius >= 0.0) || !std::isfinite(shape_radius))
    return Status(ErrorCode::kInvalidArgument, "the shape radius must be a number >= 0").with_field("shapeRadius");
  if (!Graph::is_valid_name("joint" + control_suffix))
    return Status(ErrorCode::kInvalidArgument,
                  "the control suffix '" + control_suffix + "': control names would not be valid node names")
        .with_field("controlSuffix");
  if (!Graph::is_valid_name(rig_name))
    return Status(ErrorCode::kInvalidArgument, "the rig name '" + rig_name + "': not a valid node name").with_field("rigName");
  return Status::ok();
}

namespace {

// Each control's circle radius: shape_radius, or, sized from the bones, a
// third of the joint's shortest bone to a child joint (a leaf's: of the
// bone from its parent), within [shape_radius / 10, shape_radius], so that
// a face's or a finger's many short bones get small controls that do not
// cover each other.
std::vector<double> control_radii(scene::Scene& scene, const std::vector<NodeId>& joints, const SetupOptions& options) {
  std::vector<double> out(joints.size(), options.shape_radius);
  if (!options.size_from_bones || !(options.shape_radius > 0)) return out;
  Graph& graph = scene.graph();
  auto is_joint = [&](NodeId id) { return id.is_valid() && graph.node(id)->type().name() == scene::kJointType; };
  auto position = [&](NodeId id) { return Vec3(scene.world_matrix(id).topRightCorner<3, 1>()); };
  std::unordered_map<std::uint32_t, double> shortest;  // joint index -> its shortest bone to a child
  for (NodeId id : scene.hierarchy()) {
    const NodeId parent = graph.parent(id);
    if (!is_joint(id) || !is_joint(parent)) continue;
    const double bone = (position(id) - position(parent)).norm();
    if (!(bone > 1e-9) || !std::isfinite(bone)) continue;
    auto [it, fresh] = shortest.emplace(parent.index, bone);
    if (!fresh) it->second = std::min(it->second, bone);
  }
  for (std::size_t i = 0; i < joints.size(); ++i) {
    double bone = 0;
    if (auto it = shortest.find(joints[i].index); it != shortest.end()) bone = it->second;
    else if (is_joint(graph.parent(joints[i]))) bone = (position(joints[i]) - position(graph.parent(joints[i]))).norm();
    if (bone > 0 && std::isfinite(bone))
      out[i] = std::clamp(bone / 3.0, options.shape_radius / 10.0, options.shape_radius);
  }
  return out;
}

}  // namespace

Result<SetupResult> setup_ephemeral(scene::Scene& scene, const SetupOptions& options) {
  Graph& graph = scene.graph();
  if (!rig_type(graph))
    return error(ErrorCode::kUnsupported, "setup: the scene's registry has no ephemeralRig type (use ephemeral::default_registry())");
  if (Status s = options.validate(); !s) return s.with_context("setup");

  // The joints, parent first.
  std::vector<NodeId> joints;
  {
    std::vector<NodeId> order = scene.hierarchy();
    auto is_joint = [&](NodeId id) { return graph.node(id)->type().name() == scene::kJointType; };
    if (options.joints.empty()) {
      for (NodeId id : order)
        if (is_joint(id)) joints.push_back(id);
    } else {
      for (NodeId id : options.joints) {
        const graph::Node* n = graph.node(id);
        if (!n) return error(ErrorCode::kNotFound, "setup: no such joint (stale handle)");
        if (!is_joint(id)) return error(ErrorCode::kInvalidArgument, "setup: '" + n->name() + "' is not a joint");
      }
      for (NodeId id : order)
        if (std::find(options.joints.begin(), options.joints.end(), id) != options.joints.end()) joints.push_back(id);
    }
  }
  if (joints.empty()) return error(ErrorCode::kNotFound, "setup: the scene has no joints");

  const AttrIndex kChannels[] = {xform::kTranslate, xform::kRotate, xform::kRotateQuaternion, xform::kScale};
  const AttrIndex kCopied[] = {xform::kTranslate,  xform::kRotate,    xform::kRotateOrder, xform::kRotateMode,
                               xform::kRotateQuaternion, xform::kScale, xform::kShear,  xform::kRotateAxis,
                               xform::kOffsetParentMatrix};
  for (NodeId j : joints) {
    const graph::Node& n = *graph.node(j);
    auto where = [&](const char* what) { return "setup: joint '" + n.name() + "': " + what; };
    if (!std::get<Vec3>(n.value(scene::joint_attr::kJointOrient)).isZero(0.0))
      return error(ErrorCode::kUnsupported, where("has a joint orient (controls have none); zero it first"));
    for (AttrIndex a : {xform::kRotatePivot, xform::kRotatePivotTranslate, xform::kScalePivot, xform::kScalePivotTranslate})
      if (!std::get<Vec3>(n.value(a)).isZero(0.0)) return error(ErrorCode::kUnsupported, where("has pivots"));
    for (const graph::Connection& c : n.inputs()) {
      if (c.dst.attr == xform::kOffsetParentMatrix || c.dst.attr == xform::kShear || c.dst.attr == xform::kRotateAxis)
        return error(ErrorCode::kUnsupported, where("offsetParentMatrix, shear or rotateAxis is driven by a connection"));
      const graph::Node* src = graph.node(c.src.node);
      if (src && src->type().name() == scene::kControlType &&
          (c.dst.attr == xform::kTranslate || c.dst.attr == xform::kRotateQuaternion))
        return error(ErrorCode::kAlreadyExists, where("is already driven by a control"));
    }
  }

  graph::Transaction tx(graph, "ephemeral setup");
  auto fail = [&](Status s) -> Result<SetupResult> {
    tx.rollback();
    return s;
  };
  const std::vector<double> radii = control_radii(scene, joints, options);
  SetupResult result;
  std::unordered_map<std::uint32_t, NodeId> control_by_joint;  // joint index -> control
  for (NodeId j : joints) {
    const double radius = radii[result.joints.size()];
    const std::string name = graph.node(j)->name() + options.control_suffix;
    NodeId jparent = graph.parent(j);
    NodeId cparent = jparent;
    if (auto it = control_by_joint.find(jparent.index); jparent.is_valid() && it != control_by_joint.end()) cparent = it->second;
    Result<NodeId> created = scene.create(scene::kControlType, name, cparent);
    if (!created) return fail(created.status().with_context("setup"));
    NodeId c = *created;
    control_by_joint[j.index] = c;
    // Move (or break) what drives the joint's channels, then copy the values.
    std::vector<graph::Connection> driven;
    for (const graph::Connection& conn : graph.node(j)->inputs())
      if (std::find(std::begin(kChannels), std::end(kChannels), conn.dst.attr) != std::end(kChannels)) driven.push_back(conn);
    for (const graph::Connection& conn : driven) {
      if (Status s = graph.disconnect(conn.src, conn.dst); !s) return fail(s.with_context("setup"));
    }
    for (AttrIndex a : kCopied) {
      Value v = graph.node(j)->value(a);
      if (Status s = graph.set_value(Plug{c, a, -1}, std::move(v)); !s) return fail(s.with_context("setup"));
    }
    if (options.keep_animation) {
      for (const graph::Connection& conn : driven) {
        Plug dst = conn.dst;
        dst.node = c;
        if (Status s = graph.connect(conn.src, dst); !s) return fail(s.with_context("setup"));
      }
    }
    for (AttrIndex a : kChannels) {
      if (Status s = graph.connect(Plug{c, a, -1}, Plug{j, a, -1}); !s) return fail(s.with_context("setup"));
    }
    if (radius > 0) {
      std::vector<Vec3> points;
      for (int k = 0; k < 16; ++k) {
        const double t = 2.0 * math::kPi * k / 16.0;
        points.emplace_back(0.0, radius * std::cos(t), radius * std::sin(t));
      }
      if (Status s = graph.set_value(Plug{c, scene::control_attr::kShapePoints, -1}, std::move(points)); !s)
        return fail(s.with_context("setup"));
      if (Status s = graph.set_value(Plug{c, scene::control_attr::kShapeClosed, -1}, true); !s)
        return fail(s.with_context("setup"));
      const NameSide side = side_from_name(graph.node(j)->name());
      const char* color = side == NameSide::kLeft ? "blue" : side == NameSide::kRight ? "red" : "yellow";
      if (Status s = graph.set_value(Plug{c, scene::control_attr::kShapeColor, -1}, *scene::color_from_name(color)); !s)
        return fail(s.with_context("setup"));
    }
    result.joints.push_back(j);
    result.controls.push_back(c);
  }

  Result<NodeId> rig = graph.create_node(kRigType, options.rig_name);
  if (!rig) return fail(rig.status().with_context("setup"));
  RigData d;
  for (NodeId c : result.controls) d.controls.push_back(graph.node(c)->uuid().str());
  for (std::size_t i = 0; i < result.controls.size(); ++i) {
    NodeId p = graph.parent(result.controls[i]);
    auto it = std::find(result.controls.begin(), result.controls.end(), p);
    if (!p.is_valid() || it == result.controls.end()) continue;
    const std::int64_t pi = it - result.controls.begin(), ci = static_cast<std::int64_t>(i);
    d.kind.push_back(static_cast<std::int64_t>(RelationKind::kForward));
    d.from.push_back(pi);
    d.to.push_back(ci);
    d.kind.push_back(static_cast<std::int64_t>(RelationKind::kInverse));
    d.from.push_back(ci);
    d.to.push_back(pi);
  }
  if (Status s = rig_data_write(graph, *rig, std::move(d)); !s) return fail(s.with_context("setup"));
  result.rig = *rig;
  return result;
}

NameSide side_from_name(std::string_view name) {
  if (const std::size_t colon = name.rfind(':'); colon != std::string_view::npos) name.remove_prefix(colon + 1);
  static const rig::MirrorOptions kJointTokens = [] {
    rig::MirrorOptions o;
    o.side_tokens = {{"L", "R"}, {"l", "r"}, {"Left", "Right"}, {"left", "right"}, {"LEFT", "RIGHT"}};
    return o;
  }();
  return rig::side_of_name(name, kJointTokens).value_or(rig::Side::kCenter);
}

}  // namespace rigel::ephemeral
