// Rigger actions (rigging.h): control looks, locators and mirrored joints.

#include "rigel/tools/rigging.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "mirror_map.h"
#include "rigel/rig/meta.h"
#include "rigel/rig/templates.h"
#include "rigel/scene/shapes.h"
#include "rigel/math/transform.h"
#include "rigel/scene/transform_types.h"

namespace rigel::tools {

using graph::NodeId;
using math::Mat4;
using math::Vec3;
namespace xform = scene::xform;
namespace control_attr = scene::control_attr;

namespace {

Status refuse(const std::string& field, const std::string& message) {
  return Status(ErrorCode::kInvalidArgument, field + ": " + message).with_field(field);
}

std::string name_of(const graph::Graph& g, NodeId id) {
  const graph::Node* n = g.node(id);
  return n ? "'" + n->name() + "'" : std::string("a deleted node");
}

Status need_controls(const graph::Graph& g, const std::vector<NodeId>& controls) {
  if (controls.empty()) return refuse("controls", "no controls given");
  for (NodeId id : controls) {
    const graph::Node* n = g.node(id);
    if (!n || n->type().name() != scene::kControlType)
      return refuse("controls", name_of(g, id) + (n ? " is a " + n->type().name() + ", not a control" : ""));
  }
  return Status::ok();
}

// Writes `world` into the node's channels under its parent space as
// evaluated now (translate, rotation, scale and shear).
Status place(scene::Scene& scene, NodeId node, const Mat4& world) {
  auto ch = scene.channels_for_world(node, world);
  if (!ch) return ch.status();
  graph::Graph& g = scene.graph();
  Status s = g.set_value({node, xform::kTranslate}, graph::Value(ch->translate));
  if (s) s = g.set_value({node, ch->rotation_attr}, ch->rotation);
  if (s) s = g.set_value({node, xform::kScale}, graph::Value(ch->scale));
  if (s) s = g.set_value({node, xform::kShear}, graph::Value(ch->shear));
  return s;
}

// The node holding a joint's channels: the control feeding its translate
// (an ephemeral rig's: its world is the joint's), else the joint.
NodeId channel_holder(const graph::Graph& g, NodeId joint) {
  const auto src = g.source({joint, xform::kTranslate});
  if (src && src->attr == xform::kTranslate && g.node(src->node) &&
      g.node(src->node)->type().name() == scene::kControlType)
    return src->node;
  return joint;
}

std::vector<Vec3> points_of(const graph::Graph& g, NodeId control) {
  graph::Graph& eval = const_cast<graph::Graph&>(g);  // evaluation caches; the values do not change
  const auto* p = std::get_if<std::vector<Vec3>>(&eval.evaluate(control, control_attr::kShapePoints));
  return p ? *p : std::vector<Vec3>{};
}

}  // namespace

Result<ControlLook> control_look(const graph::Graph& graph, NodeId control) {
  if (Status s = need_controls(graph, {control}); !s) return s;
  graph::Graph& g = const_cast<graph::Graph&>(graph);  // evaluation caches; the values do not change
  ControlLook look;
  look.points = points_of(graph, control);
  if (const auto* c = std::get_if<bool>(&g.evaluate(control, control_attr::kShapeClosed))) look.closed = *c;
  if (const auto* c = std::get_if<Vec3>(&g.evaluate(control, control_attr::kShapeColor))) look.color = *c;
  return look;
}

Status paste_control_look(graph::Graph& graph, const std::vector<NodeId>& controls, const ControlLook& look,
                          LookParts parts) {
  if (Status s = need_controls(graph, controls); !s) return s;
  if (!parts.shape && !parts.color) return refuse("parts", "nothing to paste: give the shape, the colour or both");
  for (std::size_t i = 0; i < look.points.size(); ++i)
    if (!look.points[i].allFinite()) return refuse("shape.points[" + std::to_string(i) + "]", "not a finite point");
  for (int i = 0; i < 3; ++i)
    if (!(look.color[i] >= 0.0 && look.color[i] <= 1.0))
      return refuse("shape.color", "each of r, g, b must be in [0, 1]");
  graph::Transaction tx(graph, parts.shape ? "paste control shape" : "paste control colour");
  for (NodeId c : controls) {
    Status s = Status::ok();
    if (parts.shape) s = graph.set_value({c, control_attr::kShapePoints}, graph::Value(look.points));
    if (s && parts.shape) s = graph.set_value({c, control_attr::kShapeClosed}, graph::Value(look.closed));
    if (s && parts.color) s = graph.set_value({c, control_attr::kShapeColor}, graph::Value(look.color));
    if (!s) {
      tx.rollback();
      return s.with_context("controls: " + name_of(graph, c));
    }
  }
  return Status::ok();
}

Status edit_control_shape(graph::Graph& graph, const std::vector<NodeId>& controls, ShapeEdit edit, MirrorPlane plane) {
  if (Status s = need_controls(graph, controls); !s) return s;
  // The plane's normal axis, and the in-plane axis the flip turns about.
  const int normal = plane == MirrorPlane::kYZ ? 0 : plane == MirrorPlane::kXZ ? 1 : 2;
  const int other = (normal + 2) % 3;  // YZ: z; XZ: x; XY: y (negated with the normal by a flip)
  graph::Transaction tx(graph, edit == ShapeEdit::kMirror ? "mirror control shape" : "flip control shape");
  for (NodeId c : controls) {
    std::vector<Vec3> points = points_of(graph, c);
    for (Vec3& p : points) {
      p[normal] = -p[normal];
      if (edit == ShapeEdit::kFlip) p[other] = -p[other];
    }
    if (Status s = graph.set_value({c, control_attr::kShapePoints}, graph::Value(std::move(points))); !s) {
      tx.rollback();
      return s.with_context("controls: " + name_of(graph, c));
    }
  }
  return Status::ok();
}

Result<NodeId> opposite_control(const graph::Graph& graph, NodeId control) {
  if (Status s = need_controls(graph, {control}); !s) return s;
  if (rig::rig_of(graph, control).is_valid()) {
    auto pair = rig::mirror_pair(graph, control);
    if (!pair) return refuse("controls", pair.status().message());
    if (*pair == control) return refuse("controls", name_of(graph, control) + " is a centre control: it has no opposite");
    return *pair;
  }
  const std::string name = graph.node(control)->name();
  const std::string other = rig::mirror_name(name);
  if (other == name) return refuse("controls", "'" + name + "' names no side: it has no opposite control");
  const NodeId id = graph.find(other);
  const graph::Node* n = graph.node(id);
  if (!n || n->type().name() != scene::kControlType)
    return refuse("controls", "'" + name + "' has no opposite control: no control is named '" + other + "'");
  return id;
}

Result<std::vector<MirroredShape>> mirror_shape_to_opposite(scene::Scene& scene, const std::vector<NodeId>& controls,
                                                            MirrorPlane plane) {
  graph::Graph& g = scene.graph();
  if (Status s = need_controls(g, controls); !s) return s;
  std::vector<MirroredShape> pairs;
  for (NodeId c : controls) {
    auto to = opposite_control(g, c);
    if (!to) return to.status();
    pairs.push_back({c, *to});
  }
  const Mat4 m = internal::reflection(plane);
  // Read every source before writing any target (a pair given both ways
  // swaps its shapes).
  std::vector<std::vector<Vec3>> shapes;
  std::vector<bool> closed;
  for (const MirroredShape& p : pairs) {
    const Mat4 world_from = scene.world_matrix(p.from);
    const Mat4 world_to = scene.world_matrix(p.to);
    if (std::abs(world_to.block<3, 3>(0, 0).determinant()) < 1e-12)
      return refuse("controls", name_of(g, p.to) + " has a singular world matrix: its shape cannot be placed");
    const Mat4 into = world_to.inverse() * m * world_from;
    std::vector<Vec3> points = points_of(g, p.from);
    for (Vec3& v : points) v = (into * v.homogeneous()).head<3>();
    shapes.push_back(std::move(points));
    auto look = control_look(g, p.from);
    closed.push_back(look ? look->closed : true);
  }
  graph::Transaction tx(g, "mirror control shape to the opposite side");
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    Status s = g.set_value({pairs[i].to, control_attr::kShapePoints}, graph::Value(std::move(shapes[i])));
    if (s) s = g.set_value({pairs[i].to, control_attr::kShapeClosed}, graph::Value(static_cast<bool>(closed[i])));
    if (!s) {
      tx.rollback();
      return s.with_context("controls: " + name_of(g, pairs[i].to));
    }
  }
  return pairs;
}

Result<std::vector<NodeId>> create_locators(scene::Scene& scene, const std::vector<NodeId>& at, double size) {
  graph::Graph& g = scene.graph();
  if (at.empty()) return refuse("nodes", "no nodes given");
  if (!std::isfinite(size) || size <= 0) return refuse("size", "must be a positive number");
  std::vector<Mat4> worlds;
  for (NodeId id : at) {
    if (!g.node(id) || !scene.is_transform(id)) return refuse("nodes", name_of(g, id) + " is not a transform node");
    const math::Decomposed d = math::decompose(scene.world_matrix(id));
    worlds.push_back(math::trs_matrix(d.translate, d.rotation, Vec3::Ones()));
  }
  graph::Transaction tx(g, at.size() == 1 ? "create locator" : "create locators");
  std::vector<NodeId> out;
  const scene::ControlShape shape = *scene::control_shape("locator", size);
  for (std::size_t i = 0; i < at.size(); ++i) {
    auto loc = scene.create(scene::kControlType, g.node(at[i])->name() + "_loc");
    Status s = loc.status();
    if (s) s = g.set_value({*loc, control_attr::kShapePoints}, graph::Value(shape.points));
    if (s) s = g.set_value({*loc, control_attr::kShapeClosed}, graph::Value(shape.closed));
    if (s) s = g.set_value({*loc, control_attr::kShapeColor}, graph::Value(*scene::color_from_name("white")));
    if (s) s = place(scene, *loc, worlds[i]);
    if (!s) {
      tx.rollback();
      return s.with_context("nodes: " + name_of(g, at[i]));
    }
    out.push_back(*loc);
  }
  return out;
}

Result<MirrorJointsReport> mirror_joints(scene::Scene& scene, const std::vector<NodeId>& roots,
                                         const MirrorJointsOptions& options) {
  graph::Graph& g = scene.graph();
  if (roots.empty()) return refuse("joints", "no joints given");
  auto is_joint = [&](NodeId id) {
    const graph::Node* n = g.node(id);
    return n && n->type().name() == scene::kJointType;
  };
  // Every joint to mirror, parents first, each once.
  std::vector<NodeId> joints;
  auto listed = [&](NodeId id) { return std::find(joints.begin(), joints.end(), id) != joints.end(); };
  for (NodeId root : roots) {
    if (!is_joint(root)) return refuse("joints", name_of(g, root) + " is not a joint");
    if (listed(root)) continue;
    std::vector<NodeId> queue{root};
    for (std::size_t i = 0; i < queue.size(); ++i) {
      if (!listed(queue[i])) joints.push_back(queue[i]);
      for (NodeId child : g.children(queue[i]))
        if (is_joint(child)) queue.push_back(child);
    }
  }
  // The mirrored names, and what already holds them.
  struct Plan {
    NodeId source, target;
    std::string name;
    Mat4 world;
  };
  const Mat4 m = internal::reflection(options.plane);
  std::vector<Plan> plans;
  for (NodeId j : joints) {
    const std::string name = g.node(j)->name();
    Plan p{j, g.find(rig::mirror_name(name)), rig::mirror_name(name), {}};
    if (p.name == name) return refuse("joints", "'" + name + "' names no side: a centre joint cannot be mirrored");
    if (p.target.is_valid() && (!options.update_existing || !is_joint(p.target)))
      return refuse("joints", "'" + p.name + "' (the mirror of '" + name + "') exists" +
                                  (is_joint(p.target) ? ": update existing joints to move it onto the mirror"
                                                      : " and is not a joint"));
    p.world = m * scene.world_matrix(j) * m;
    plans.push_back(std::move(p));
  }
  graph::Transaction tx(g, "mirror joints");
  MirrorJointsReport report;
  auto fail = [&](Status s, const Plan& p) -> Status {
    tx.rollback();
    return s.with_context("joints: '" + g.node(p.source)->name() + "'");
  };
  for (Plan& p : plans) {
    if (!p.target.is_valid()) {
      // Under the mirror of its parent: a joint mirrored here, else the
      // parent's opposite, else the parent itself.
      const NodeId parent = g.parent(p.source);
      NodeId under = parent;
      for (const Plan& q : plans)
        if (q.source == parent) under = q.target;
      if (under == parent && parent.is_valid()) {
        const NodeId opposite = g.find(rig::mirror_name(g.node(parent)->name()));
        if (is_joint(opposite)) under = opposite;
      }
      auto made = scene.create(scene::kJointType, p.name, under);
      if (!made) return fail(made.status(), p);
      p.target = *made;
      const graph::Node& src = *g.node(p.source);
      Status s = g.set_value({p.target, xform::kRotateOrder}, src.value(xform::kRotateOrder));
      if (s) s = g.set_value({p.target, xform::kRotateMode}, src.value(xform::kRotateMode));
      if (s) s = g.set_value({p.target, scene::joint_attr::kRadius}, src.value(scene::joint_attr::kRadius));
      if (!s) return fail(s, p);
      report.created.push_back(p.target);
    } else {
      report.updated.push_back(p.target);
    }
    if (Status s = place(scene, channel_holder(g, p.target), p.world); !s) return fail(s, p);
  }
  return report;
}

}  // namespace rigel::tools
