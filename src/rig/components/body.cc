// Body component classes: spine (FK, spline IK, stretchy spline IK), neck
// (FK with a head that can keep its world orientation), tail (a spline moved
// by a few controls), eye (aim controls with a master) and simple (wraps
// given nodes). Seeds: 002 §4.1 and Appendix B (the spine and its shoulder
// control), 004 §4.8 (Luna's Spine, Head, IKSpline, Eye, Simple).
//
// Spline setups (spine splineIK/stretchySplineIK, tail) share one design:
//   - the curve is solved in the space of the attach node ("spline space"):
//     its points are groups under a still group whose positions are the
//     curve points' world positions taken into the attach node's space
//     (point constraints with the attach node's inverse as parent space).
//     ikSpline's worldUpVector is a plain world vector; solving in the attach
//     node's space makes that "up" turn with the rig, so turning the whole
//     character never twists the spline;
//   - the curve has one control point per joint, solved so that the clamped
//     B-spline passes through the joints at rest (global interpolation at
//     chord-length parameters), so the driver chain's rest positions are the
//     joints' and bone lengths are kept (or stretched) as the joints' own;
//     each control point hangs under one control (the nearest along the
//     chain);
//   - a driver chain of transforms (x down the chain, y toward the up) is
//     solved by ikSpline (ops::ik::setup_spline_ik); "splineFollow" groups
//     under the attach node take each driver's spline-space matrix as their
//     local matrix, so they are the drivers in the world;
//   - hooks are groups under those at the joints' rest, and each joint is
//     driven by its hook (BuildContext::drive, keeping the offset), so at
//     rest nothing moves whatever the solver's orientation conventions.
#include "rigel/rig/components/body.h"

#include "aim.h"

#include <algorithm>
#include <cmath>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "rigel/math/transform.h"
#include "rigel/ops/constraints/nodes.h"
#include "rigel/ops/ik/nodes.h"
#include "rigel/ops/ik/spline_ik.h"
#include "rigel/rig/component.h"
#include "rigel/rig/meta.h"
#include "rigel/scene/transform_types.h"

namespace rigel::rig::components {
namespace {

using graph::Plug;
using graph::Value;
using math::Mat3;
using math::Mat4;
using math::Vec3;
namespace xform = scene::xform;

// ---- small helpers ---------------------------------------------------------

Plug plug(graph::Graph& g, NodeId node, const char* attr, int element = -1) {
  return Plug{node, g.node(node)->type().attr_find(attr), element};
}

Vec3 position_of(const Mat4& m) { return m.topRightCorner<3, 1>(); }

Mat4 frame(const Mat3& rotation, const Vec3& position) {
  Mat4 m = Mat4::Identity();
  m.topLeftCorner<3, 3>() = rotation;
  m.topRightCorner<3, 1>() = position;
  return m;
}

// The joints' world matrices of every guide.
Result<std::vector<Mat4>> guide_worlds(BuildContext& ctx) {
  std::vector<Mat4> out;
  for (int i = 0; i < ctx.guide_count(); ++i) {
    Result<Mat4> w = ctx.guide_world(i);
    if (!w) return w.status();
    out.push_back(*w);
  }
  return out;
}

// Arc-length fraction (0..1) of each point along the polyline through them.
std::vector<double> chord_fractions(const std::vector<Vec3>& p) {
  std::vector<double> f(p.size(), 0.0);
  for (std::size_t i = 1; i < p.size(); ++i) f[i] = f[i - 1] + (p[i] - p[i - 1]).norm();
  const double total = f.back();
  for (double& x : f) x = total > 0.0 ? x / total : 0.0;
  if (total <= 0.0)
    for (std::size_t i = 0; i < f.size(); ++i) f[i] = p.size() > 1 ? double(i) / double(p.size() - 1) : 0.0;
  return f;
}

// A frame at arc-length fraction `t` of the joints' polyline: the position
// there, the rotation of the joint the segment starts at. `joint` gets that
// joint's index.
Mat4 frame_along(const std::vector<Mat4>& worlds, double t, int* joint) {
  std::vector<Vec3> p;
  for (const Mat4& w : worlds) p.push_back(position_of(w));
  const std::vector<double> f = chord_fractions(p);
  std::size_t i = 0;
  while (i + 2 < f.size() && f[i + 1] <= t) ++i;
  const double span = f[i + 1] - f[i];
  const double a = span > 0.0 ? std::clamp((t - f[i]) / span, 0.0, 1.0) : 0.0;
  if (joint) *joint = a > 0.5 ? static_cast<int>(i + 1) : static_cast<int>(i);
  return frame(rotation_of(worlds[a > 0.5 ? i + 1 : i]), p[i] + a * (p[i + 1] - p[i]));
}

// Control points of the clamped uniform B-spline (ops::ik::bspline_point)
// that passes through `p` at chord-length parameters; `p` itself when the
// system is singular (points repeated): the curve then only approximates the
// joints, which the drive offsets absorb.
std::vector<Vec3> interpolating_points(const std::vector<Vec3>& p) {
  const int n = static_cast<int>(p.size());
  const std::vector<double> u = chord_fractions(p);
  Eigen::MatrixXd basis(n, n);
  std::vector<Vec3> unit(n, Vec3::Zero());
  for (int j = 0; j < n; ++j) {
    unit[j] = Vec3::UnitX();
    for (int k = 0; k < n; ++k) basis(k, j) = ops::ik::bspline_point(unit, u[k]).x();
    unit[j] = Vec3::Zero();
  }
  Eigen::MatrixXd rhs(n, 3);
  for (int k = 0; k < n; ++k) rhs.row(k) = p[k].transpose();
  const Eigen::MatrixXd c = basis.colPivHouseholderQr().solve(rhs);
  double scale = 1e-300;
  for (const Vec3& q : p) scale = std::max(scale, q.norm());
  if (!c.allFinite() || (basis * c - rhs).norm() > 1e-9 * scale) return p;
  std::vector<Vec3> out(n);
  for (int j = 0; j < n; ++j) out[j] = c.row(j).transpose();
  return out;
}

// The spline setup of the file comment, in the current step. `cv_parents[j]`
// is the node control point j hangs under. Makes (roles): splineSpace,
// cv[j], curvePoint[j] (+ curvePointFollow), splineJoint[i], ikSpline,
// splineFollow[i] (+ splineFollowParent).
Status build_spline(BuildContext& ctx, const std::vector<Mat4>& worlds, const std::vector<NodeId>& cv_parents) {
  scene::Scene& scene = ctx.scene();
  const int n = static_cast<int>(worlds.size());
  const NodeId attach = ctx.attach_node();
  const Mat4 attach_world = attach.is_valid() ? scene.world_matrix(attach) : Mat4(Mat4::Identity());
  const Mat4 attach_inverse = math::affine_inverse(attach_world);
  if (!attach_inverse.allFinite())
    return error(ErrorCode::kInvalidArgument, ctx.full_name() + ": the attach node's world matrix is singular");
  // Joint positions in spline space (the attach node's).
  std::vector<Vec3> q;
  for (const Mat4& w : worlds) q.push_back(position_of(Mat4(attach_inverse * w)));
  for (int i = 0; i + 1 < n; ++i)
    if ((q[i + 1] - q[i]).norm() < 1e-9)
      return error(ErrorCode::kInvalidArgument,
                   ctx.full_name() + ": guides " + std::to_string(i) + " and " + std::to_string(i + 1) +
                       " are at the same place; a spline needs bones of some length");
  const std::vector<Vec3> cvs = interpolating_points(q);

  Result<NodeId> space = ctx.create_group("splineSpace", -1, Mat4::Identity(), ctx.rig_group("noTransform"));
  if (!space) return space.status();
  std::vector<NodeId> points;
  for (int j = 0; j < n; ++j) {
    const Mat4 cv_world = attach_world * frame(Mat3::Identity(), cvs[j]);
    Result<NodeId> cv = ctx.create_group("cv", j, cv_world, cv_parents[j]);
    if (!cv) return cv.status();
    Result<NodeId> point = ctx.create_group("curvePoint", j, frame(Mat3::Identity(), cvs[j]), *space);
    if (!point) return point.status();
    ConstraintSpec follow;
    follow.type = ops::constraints::kPointConstraintType;
    follow.role = "curvePointFollow";
    follow.targets = {*cv};
    follow.maintain_offset = false;
    follow.channels = {"translate"};
    follow.space = ConstraintSpec::Space::kNode;
    follow.space_node = attach;
    if (Result<NodeId> c = ctx.constrain(follow, *point, j); !c) return c.status();
    points.push_back(*point);
  }

  // The up: the root joint's axis least along the chain, in spline space.
  const Vec3 along = (q.back() - q.front()).normalized();
  const Mat3 root_rotation = rotation_of(Mat4(attach_inverse * worlds[0]));
  Vec3 up = root_rotation.col(0);
  for (int a = 1; a < 3; ++a)
    if (std::abs(root_rotation.col(a).dot(along)) < std::abs(up.dot(along))) up = root_rotation.col(a);
  // Driver frames: x down the chain (the end joint along the curve's end
  // tangent), y toward the up.
  std::vector<NodeId> drivers;
  Vec3 previous_y = up;
  for (int i = 0; i < n; ++i) {
    Vec3 x;
    if (i + 1 < n) {
      x = (q[i + 1] - q[i]).normalized();
    } else {
      Vec3 tangent;
      ops::ik::bspline_point(cvs, 1.0, &tangent);
      x = tangent.norm() > 1e-12 ? tangent.normalized() : Vec3((q[i] - q[i - 1]).normalized());
    }
    Vec3 y = up - up.dot(x) * x;
    if (y.norm() < 1e-6) y = previous_y - previous_y.dot(x) * x;
    y.normalize();
    previous_y = y;
    Mat3 r;
    r.col(0) = x;
    r.col(1) = y;
    r.col(2) = x.cross(y);
    Result<NodeId> driver = ctx.create_group("splineJoint", i, frame(r, q[i]), i == 0 ? *space : drivers.back());
    if (!driver) return driver.status();
    drivers.push_back(*driver);
  }
  ops::ik::SplineIkOptions options;
  options.name = ctx.rig_name() + "_" + ctx.full_name() + "_ikSpline";
  options.aim_axis = Vec3::UnitX();
  options.up_axis = Vec3::UnitY();
  options.world_up_vector = up;
  Result<NodeId> ik = ops::ik::setup_spline_ik(scene, drivers, points, options);
  if (!ik) return ik.status().with_context(ctx.full_name() + ": spline IK");
  if (Status s = ctx.link(*ik, "ikSpline"); !s) return s;

  // The drivers in the world: groups under the attach node whose local
  // matrix is the driver's spline-space world matrix.
  for (int i = 0; i < n; ++i) {
    Result<NodeId> follow = ctx.create(scene::kTransformType, "splineFollow", i, i, attach);
    if (!follow) return follow.status();
    ConstraintSpec spec;
    spec.role = "splineFollowParent";
    spec.targets = {drivers[i]};
    spec.maintain_offset = false;
    spec.channels = {"translate", "rotate", "scale"};
    spec.space = ConstraintSpec::Space::kIdentity;
    if (Result<NodeId> c = ctx.constrain(spec, *follow, i); !c) return c.status();
  }
  return Status::ok();
}

// Turns stretch on for the component's ikSpline.
Status enable_spline_stretch(BuildContext& ctx) {
  const NodeId ik = ctx.node("ikSpline");
  if (!ik.is_valid()) return Status::ok();
  graph::Graph& g = ctx.graph();
  return g.set_value(plug(g, ik, "stretch"), Value(true));
}

// Hooks under the splineFollow groups at the joints, published, each
// driving its joint.
Status drive_from_spline(BuildContext& ctx) {
  for (int i = 0; i < ctx.guide_count(); ++i) {
    Result<Mat4> world = ctx.guide_world(i);
    if (!world) return world.status();
    Result<NodeId> hook = ctx.create_group("hook", i, *world, ctx.node("splineFollow", i));
    if (!hook) return hook.status();
    if (Status s = ctx.publish_hook(i, *hook); !s) return s;
    if (ctx.component().guides[i].joint.empty()) continue;
    Result<NodeId> joint = ctx.guide_joint(i);
    if (!joint) return joint.status();
    if (Status s = ctx.drive(*hook, *joint); !s) return s;
  }
  return Status::ok();
}

Status need_guides(BuildContext& ctx, int count) {
  if (ctx.guide_count() >= count) return Status::ok();
  return error(ErrorCode::kInvalidArgument, ctx.full_name() + ": a " + ctx.component().type + " needs " +
                                                std::to_string(count) + " or more guides, it has " +
                                                std::to_string(ctx.guide_count()));
}

// FK controls, one per guide, each the child of the one before; published as
// hooks when `publish`.
Status fk_controls(BuildContext& ctx, std::string_view role, int count, bool publish) {
  NodeId parent = ctx.attach_node();
  for (int i = 0; i < count; ++i) {
    Result<Mat4> world = ctx.guide_world(i);
    if (!world) return world.status();
    Result<NodeId> c = ctx.create_control(role, i, i, *world, parent);
    if (!c) return c.status();
    if (publish)
      if (Status s = ctx.publish_hook(i, *c); !s) return s;
    parent = *c;
  }
  return Status::ok();
}

Status drive_joint(BuildContext& ctx, int guide, NodeId driver) {
  if (ctx.component().guides[guide].joint.empty()) return Status::ok();
  Result<NodeId> joint = ctx.guide_joint(guide);
  if (!joint) return joint.status();
  return ctx.drive(driver, *joint);
}

// ---- spine -------------------------------------------------------------------

// kinematicType fk: one FK control per joint (fkChain). splineIK: FK
// controls, a shoulder control under the last of them (FK layered under the
// IK, seed 002), a middle control whose space follows halfway between the
// attach node and the shoulder, and the spline setup; control points in the
// first quarter of the chain hang under the attach node (the base), those in
// the last quarter under the shoulder, the rest under the middle control.
// stretchySplineIK: the same with the ikSpline's stretch on (feature
// "stretch").
class Spine : public ComponentClass {
 public:
  std::string_view type() const override { return "spine"; }
  std::vector<Step> steps(const Component&) const override {
    return {
        Step{"controls", "", "",
             [](BuildContext& ctx) -> Status {
               if (Status s = need_guides(ctx, 3); !s) return s;
               const bool fk = ctx.param_string("kinematicType") == "fk";
               return fk_controls(ctx, "fk", ctx.guide_count(), fk);
             }},
        Step{"spline", "", "",
             [](BuildContext& ctx) -> Status {
               if (ctx.param_string("kinematicType") == "fk") return Status::ok();
               Result<std::vector<Mat4>> worlds = guide_worlds(ctx);
               if (!worlds) return worlds.status();
               const int n = ctx.guide_count();
               const NodeId attach = ctx.attach_node();
               if (!attach.is_valid()) return error(ErrorCode::kInvalidArgument, ctx.full_name() + ": no attach node");
               Result<NodeId> shoulder = ctx.create_control("shoulder", -1, n - 1, worlds->back(), ctx.node("fk", n - 1));
               if (!shoulder) return shoulder.status();
               int mid_guide = 0;
               const Mat4 mid_world = frame_along(*worlds, 0.5, &mid_guide);
               Result<NodeId> mid_space = ctx.create_group("midSpace", -1, mid_world, attach);
               if (!mid_space) return mid_space.status();
               ConstraintSpec follow;
               follow.role = "midFollow";
               follow.targets = {attach, *shoulder};
               follow.weights = {0.5, 0.5};
               follow.channels = {"translate", "rotate", "scale"};
               if (Result<NodeId> c = ctx.constrain(follow, *mid_space, -1); !c) return c.status();
               Result<NodeId> mid = ctx.create_control("mid", -1, mid_guide, mid_world, *mid_space);
               if (!mid) return mid.status();
               std::vector<NodeId> parents;
               for (int j = 0; j < n; ++j) {
                 const double t = double(j) / double(n - 1);
                 parents.push_back(t <= 0.25 ? attach : t >= 0.75 ? *shoulder : *mid);
               }
               return build_spline(ctx, *worlds, parents);
             }},
        Step{"stretch", "stretch", "",
             [](BuildContext& ctx) -> Status {
               if (ctx.param_string("kinematicType") != "stretchySplineIK") return Status::ok();
               return enable_spline_stretch(ctx);
             }},
        Step{"drive", "", "",
             [](BuildContext& ctx) -> Status {
               if (ctx.param_string("kinematicType") != "fk") return drive_from_spline(ctx);
               for (int i = 0; i < ctx.guide_count(); ++i)
                 if (Status s = drive_joint(ctx, i, ctx.node("fk", i)); !s) return s;
               return Status::ok();
             }},
    };
  }
};

// ---- neck --------------------------------------------------------------------

// FK controls for the neck joints, a head control under the last. With
// headOrient=world the head control hangs under a "headSpace" group (a child
// of the last neck control, so its position follows the neck) whose
// rotation an orient constraint takes from the rig's controls group (world
// space, moved only by the rig's own root), keeping the offset of the rest.
class Neck : public ComponentClass {
 public:
  std::string_view type() const override { return "neck"; }
  std::vector<Step> steps(const Component&) const override {
    return {
        Step{"controls", "", "",
             [](BuildContext& ctx) -> Status {
               if (Status s = need_guides(ctx, 2); !s) return s;
               const int n = ctx.guide_count();
               if (Status s = fk_controls(ctx, "neck", n - 1, true); !s) return s;
               Result<Mat4> head_world = ctx.guide_world(n - 1);
               if (!head_world) return head_world.status();
               NodeId parent = ctx.node("neck", n - 2);
               if (ctx.param_string("headOrient") == "world") {
                 const NodeId world = ctx.rig_group("controls");
                 if (!world.is_valid())
                   return error(ErrorCode::kNotFound, ctx.full_name() + ": the rig has no controls group");
                 Result<NodeId> space = ctx.create_group("headSpace", -1, *head_world, parent);
                 if (!space) return space.status();
                 ConstraintSpec orient;
                 orient.type = ops::constraints::kOrientConstraintType;
                 orient.role = "headOrient";
                 orient.targets = {world};
                 orient.channels = {"rotate"};
                 if (Result<NodeId> c = ctx.constrain(orient, *space, -1); !c) return c.status();
                 parent = *space;
               }
               Result<NodeId> head = ctx.create_control("head", -1, n - 1, *head_world, parent);
               if (!head) return head.status();
               return ctx.publish_hook(n - 1, *head);
             }},
        Step{"drive", "", "",
             [](BuildContext& ctx) -> Status {
               const int n = ctx.guide_count();
               for (int i = 0; i + 1 < n; ++i)
                 if (Status s = drive_joint(ctx, i, ctx.node("neck", i)); !s) return s;
               return drive_joint(ctx, n - 1, ctx.node("head"));
             }},
    };
  }
};

// ---- tail --------------------------------------------------------------------

// controlCount "main" controls spread evenly along the chain (by length),
// each the child of the one before (FK over the spline); control point j
// hangs under the control nearest joint j along the chain. stretch (param,
// under feature "stretch"): the joints stretch with the curve.
class Tail : public ComponentClass {
 public:
  std::string_view type() const override { return "tail"; }
  std::vector<Step> steps(const Component&) const override {
    return {
        Step{"controls", "", "",
             [](BuildContext& ctx) -> Status {
               if (Status s = need_guides(ctx, 3); !s) return s;
               Result<std::vector<Mat4>> worlds = guide_worlds(ctx);
               if (!worlds) return worlds.status();
               const std::int64_t count = ctx.param_int("controlCount");
               if (count < 2 || count > 32)
                 return error(ErrorCode::kInvalidArgument,
                              ctx.full_name() + ": controlCount " + std::to_string(count) + " is outside 2..32");
               NodeId parent = ctx.attach_node();
               for (int k = 0; k < count; ++k) {
                 int guide = 0;
                 const Mat4 world = frame_along(*worlds, double(k) / double(count - 1), &guide);
                 Result<NodeId> c = ctx.create_control("main", k, guide, world, parent);
                 if (!c) return c.status();
                 parent = *c;
               }
               return Status::ok();
             }},
        Step{"spline", "", "",
             [](BuildContext& ctx) -> Status {
               Result<std::vector<Mat4>> worlds = guide_worlds(ctx);
               if (!worlds) return worlds.status();
               std::vector<Vec3> p;
               for (const Mat4& w : *worlds) p.push_back(position_of(w));
               const std::vector<double> f = chord_fractions(p);
               const std::vector<NodeId> controls = ctx.nodes("main");
               const int count = static_cast<int>(controls.size());
               std::vector<NodeId> parents;
               for (double t : f) parents.push_back(controls[static_cast<std::size_t>(std::lround(t * (count - 1)))]);
               return build_spline(ctx, *worlds, parents);
             }},
        Step{"stretch", "stretch", "",
             [](BuildContext& ctx) -> Status {
               if (!ctx.param_bool("stretch")) return Status::ok();
               return enable_spline_stretch(ctx);
             }},
        Step{"drive", "", "", [](BuildContext& ctx) -> Status { return drive_from_spline(ctx); }},
    };
  }
};

// ---- eye ---------------------------------------------------------------------

Result<Vec3> axis_vector(BuildContext& ctx, const std::string& name) {
  if (const std::optional<Vec3> axis = axis_named(name)) return *axis;
  return error(ErrorCode::kInvalidArgument, ctx.full_name() + ": aimAxis '" + name + "' is not one of x y z -x -y -z");
}

// One "aim" control per eye, aimDistance along the eye's aimAxis (in the
// world, from the eye's rest orientation), under a "master" control at
// their mean (both oriented as the attach node). Each eye joint gets an aim
// constraint at its control whose up vector follows the master's rotation
// (objectRotation), set so that at rest the constraint gives the joint's
// own rotation. The constraint turns a "hook" group at the eye (under the
// attach node; the published hook) and the eye joint follows that group
// (BuildContext::drive, keeping the offset): an aim constraint writes a
// rotation only, and a joint whose rest matrix is not a pure rotation times
// its scale (imported glTF quaternions a little off unit length scale the
// matrix by |q|^2) would otherwise move at rest by that much (~1e-8).
class Eye : public ComponentClass {
 public:
  std::string_view type() const override { return "eye"; }
  std::vector<Step> steps(const Component&) const override {
    return {
        Step{"controls", "", "",
             [](BuildContext& ctx) -> Status {
               if (Status s = need_guides(ctx, 1); !s) return s;
               Result<Vec3> axis = axis_vector(ctx, ctx.param_string("aimAxis"));
               if (!axis) return axis.status();
               Result<std::vector<Mat4>> worlds = guide_worlds(ctx);
               if (!worlds) return worlds.status();
               const double distance = ctx.param_double("aimDistance");
               const NodeId attach = ctx.attach_node();
               const Mat3 orient = attach.is_valid() ? rotation_of(ctx.scene().world_matrix(attach)) : Mat3::Identity();
               std::vector<Vec3> aims;
               Vec3 mean = Vec3::Zero();
               for (const Mat4& w : *worlds) {
                 aims.push_back(position_of(w) + distance * (rotation_of(w) * *axis));
                 mean += aims.back();
               }
               mean /= double(aims.size());
               Result<NodeId> master = ctx.create_control("master", -1, -1, frame(orient, mean), attach);
               if (!master) return master.status();
               for (int i = 0; i < ctx.guide_count(); ++i) {
                 Result<NodeId> aim = ctx.create_control("aim", i, i, frame(orient, aims[i]), *master);
                 if (!aim) return aim.status();
                 Result<NodeId> hook = ctx.create_group("hook", i, (*worlds)[i], attach);
                 if (!hook) return hook.status();
                 if (Status s = ctx.publish_hook(i, *hook); !s) return s;
               }
               return Status::ok();
             }},
        Step{"constrain", "", "",
             [](BuildContext& ctx) -> Status {
               Result<Vec3> axis = axis_vector(ctx, ctx.param_string("aimAxis"));
               if (!axis) return axis.status();
               // The up: a joint axis across the aim.
               const Vec3 up_local = std::abs(axis->y()) > 0.5 ? Vec3(Vec3::UnitZ()) : Vec3(Vec3::UnitY());
               const NodeId master = ctx.node("master");
               const Mat3 master_rotation = rotation_of(ctx.scene().world_matrix(master));
               for (int i = 0; i < ctx.guide_count(); ++i) {
                 Result<Mat4> world = ctx.guide_world(i);
                 if (!world) return world.status();
                 // The eye's up in the master's space: at rest the world up is the eye's own.
                 const Vec3 world_up = master_rotation.transpose() * (rotation_of(*world) * up_local);
                 const NodeId hook = ctx.node("hook", i);
                 if (Status s = aim_constraint(ctx, hook, ctx.node("aim", i), *axis, up_local, world_up, master, i); !s)
                   return s;
                 if (Status s = drive_joint(ctx, i, hook); !s)
                   return s.with_context(ctx.full_name() + ": aim " + std::to_string(i));
               }
               return Status::ok();
             }},
    };
  }
};

// ---- simple ------------------------------------------------------------------

// For each guide's node: a `control` already is adopted as it is. The build
// may not tag or link a node it did not make, so the adopted control is not
// a member of the component; its hook is a "hook" group made under it at its
// place (zero offset), which follows it exactly. Addresses therefore reach
// the hook group, not the control itself (a limitation of adoption). Any
// other transform gets a "main" control at the guide, published as the hook,
// that drives it by `constrain`: parent (BuildContext::drive), point, orient
// (constraints keeping the offset) or none (control only).
class Simple : public ComponentClass {
 public:
  std::string_view type() const override { return "simple"; }
  std::vector<Step> steps(const Component&) const override {
    return {
        Step{"controls", "", "",
             [](BuildContext& ctx) -> Status {
               if (Status s = need_guides(ctx, 1); !s) return s;
               for (int i = 0; i < ctx.guide_count(); ++i) {
                 Result<NodeId> node = ctx.guide_joint(i);
                 if (!node) return node.status();
                 if (!ctx.scene().is_transform(*node))
                   return error(ErrorCode::kInvalidArgument, ctx.full_name() + ": guide " + std::to_string(i) + ": '" +
                                                                 ctx.component().guides[i].joint +
                                                                 "' is not a transform");
                 const Mat4 world = ctx.scene().world_matrix(*node);
                 if (ctx.graph().node(*node)->type().name() == scene::kControlType) {
                   Result<NodeId> hook = ctx.create_group("hook", i, world, *node);
                   if (!hook) return hook.status();
                   if (Status s = ctx.publish_hook(i, *hook); !s) return s;
                   continue;
                 }
                 // At the guide (the node's place, or off it by the guide's offset).
                 Result<Mat4> place = ctx.guide_world(i);
                 if (!place) return place.status();
                 Result<NodeId> c = ctx.create_control("main", i, i, *place, ctx.attach_node());
                 if (!c) return c.status();
                 if (Status s = ctx.publish_hook(i, *c); !s) return s;
               }
               return Status::ok();
             }},
        Step{"drive", "", "",
             [](BuildContext& ctx) -> Status {
               const std::string mode = ctx.param_string("constrain");
               if (mode == "none") return Status::ok();
               const std::vector<NodeId> controls = ctx.nodes("main");
               for (NodeId c : controls) {
                 const std::string* guide = ctx.graph().node(c)->tag_find(kTagGuide);
                 const int i = guide ? std::stoi(*guide) : -1;
                 Result<NodeId> node = ctx.guide_joint(i);
                 if (!node) return node.status();
                 if (mode == "parent") {
                   if (Status s = ctx.drive(c, *node); !s) return s;
                   continue;
                 }
                 ConstraintSpec spec;
                 spec.type = mode == "point" ? ops::constraints::kPointConstraintType
                                             : ops::constraints::kOrientConstraintType;
                 spec.role = mode == "point" ? "pointConstraint" : "orientConstraint";
                 if (mode != "point" && mode != "orient")
                   return error(ErrorCode::kInvalidArgument, ctx.full_name() + ": constrain '" + mode + "' is unknown");
                 spec.targets = {c};
                 spec.channels = {mode == "point" ? "translate" : "rotate"};
                 if (Result<NodeId> k = ctx.constrain(spec, *node, i); !k) return k.status();
               }
               return Status::ok();
             }},
    };
  }
};

}  // namespace

Status add_body_components(ComponentFactory& factory) {
  if (Status s = factory.add(std::make_shared<Spine>()); !s) return s;
  if (Status s = factory.add(std::make_shared<Neck>()); !s) return s;
  if (Status s = factory.add(std::make_shared<Tail>()); !s) return s;
  if (Status s = factory.add(std::make_shared<Eye>()); !s) return s;
  return factory.add(std::make_shared<Simple>());
}

}  // namespace rigel::rig::components
