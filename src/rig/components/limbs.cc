// ikChain, limb, quadLeg, springChain and twist (components/limbs.h).
#include "rigel/rig/components/limbs.h"

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "rigel/math/rotation.h"
#include "rigel/math/transform.h"
#include "rigel/ops/ik/nodes.h"
#include "rigel/ops/util/blend.h"
#include "rigel/ops/util/space.h"
#include "rigel/ops/util/spring.h"
#include "rigel/ops/util/twist.h"
#include "rigel/rig/component.h"
#include "rigel/rig/meta.h"
#include "rigel/rig/spaces.h"
#include "rigel/scene/transform_types.h"

namespace rigel::rig::components {
namespace {

using graph::AttrIndex;
using graph::Plug;
using graph::Value;
using math::Mat4;
using math::Quat;
using math::Vec3;
namespace xform = scene::xform;
namespace ik = ops::ik;
namespace sw = ops::util::fk_ik_attr;

Vec3 position_of(const Mat4& m) { return m.topRightCorner<3, 1>(); }

Plug plug(NodeId node, AttrIndex attr, std::int32_t element = -1) { return Plug{node, attr, element}; }

AttrIndex attr_of(const graph::Graph& g, NodeId node, const char* name) { return g.node(node)->type().attr_find(name); }

Status fail(BuildContext& ctx, const std::string& what) {
  return error(ErrorCode::kInvalidArgument, ctx.full_name() + " (" + ctx.component().type + "): " + what);
}

// The guide joints, each the child of the one before.
Result<std::vector<NodeId>> chain_joints(BuildContext& ctx) {
  std::vector<NodeId> joints;
  graph::Graph& g = ctx.graph();
  for (int i = 0; i < ctx.guide_count(); ++i) {
    Result<NodeId> j = ctx.guide_joint(i);
    if (!j) return j.status();
    if (!ctx.scene().is_transform(*j))
      return fail(ctx, "guide " + std::to_string(i) + ": '" + g.node(*j)->name() + "' is not a transform");
    if (i > 0 && g.parent(*j) != joints.back())
      return fail(ctx, "guide " + std::to_string(i) + ": '" + g.node(*j)->name() + "' is not a child of '" +
                           g.node(joints.back())->name() + "'");
    joints.push_back(*j);
  }
  return joints;
}

// Guide offsets (docs/RIG.md): a guide with a joint and a translate, rotate
// or scale places its control off the joint. The control stands at the
// guide (joint * offset); a group under it at the joint's own place (role
// `fkJoint`/`ikEnd`, made only for an offset guide) is what drives the
// joint, so the joint keeps its rest while the control is zeroed.
bool has_offset(const Guide& g) {
  return g.translate != Vec3::Zero() || g.rotate != Vec3::Zero() || g.scale != Vec3::Ones();
}

// The node of `role` whose index tag is `index` (invalid when none).
NodeId node_at(BuildContext& ctx, std::string_view role, int index) {
  for (NodeId n : ctx.nodes(role)) {
    const std::string* tag = ctx.graph().node(n)->tag_find(kTagIndex);
    if (tag && *tag == std::to_string(index)) return n;
    if (!tag && index < 0) return n;
  }
  return {};
}

// The control of guide `i` at the guide's place, its rigid part (scale and
// shear left out), and, for an offset guide or a joint whose frame is not
// rigid, a group `joint_role` under it at `joint`'s place (the node that
// drives it). Returns the driving node (the group, else the control).
//
// A rigid control turns the limb rigidly: a control standing in a joint's
// frame with the joint's scales (1 +- 3e-6 on rigs read from
// single-precision files) would bend the bones under it by that much as it
// turns, a pose the IK side, whose bones are rigid, cannot take, so FK/IK
// matches would miss by it.
Result<NodeId> control_at_guide(BuildContext& ctx, std::string_view role, int index, int i, NodeId joint,
                                NodeId parent, std::string_view joint_role) {
  Result<Mat4> place = ctx.guide_world(i);
  if (!place) return place.status();
  Result<NodeId> c = ctx.create_control(role, index, i, math::rigid_part(*place), parent);
  if (!c) return c;
  const Mat4 at_joint = ctx.scene().world_matrix(joint);
  if (!has_offset(ctx.component().guides[static_cast<std::size_t>(i)]) && math::is_rigid(at_joint)) return c;
  return ctx.create_group(joint_role, index, at_joint, *c);
}

// The direction from the start-end line toward `mid` (unit), or, for a
// straight chain, `fallback` made perpendicular to the line (then world x).
Vec3 bend_direction(const Vec3& start, const Vec3& mid, const Vec3& end, const Vec3& fallback) {
  Vec3 line = end - start;
  if (line.norm() < 1e-12) line = mid - start;
  line.normalize();
  const Vec3 to_mid = mid - start;
  Vec3 perp = to_mid - line * line.dot(to_mid);
  if (perp.norm() > 1e-6 * std::max(to_mid.norm(), 1e-12)) return perp.normalized();
  for (const Vec3& f : {fallback, Vec3(Vec3::UnitX()), Vec3(Vec3::UnitY())}) {
    perp = f - line * line.dot(f);
    if (perp.norm() > 1e-6) return perp.normalized();
  }
  return Vec3::UnitZ();
}

// Creates the solver (role "ikSolver") on `joints`, with the rest data copied
// and its parent space from `space`'s worldMatrix.
Result<NodeId> make_solver(BuildContext& ctx, const char* type, const std::vector<NodeId>& joints, NodeId space) {
  graph::Graph& g = ctx.graph();
  Result<NodeId> created = ctx.create(type, "ikSolver");
  if (!created) return created;
  const NodeId solver = *created;
  std::vector<Mat4> rest, offset;
  std::vector<Vec3> orient, axis;
  for (NodeId joint : joints) {
    rest.push_back(std::get<Mat4>(g.evaluate(joint, xform::kMatrix)));
    offset.push_back(std::get<Mat4>(g.evaluate(joint, xform::kOffsetParentMatrix)));
    const AttrIndex jo = attr_of(g, joint, "jointOrient");
    orient.push_back(jo == graph::kNoAttr ? Vec3(Vec3::Zero()) : std::get<Vec3>(g.evaluate(joint, jo)));
    axis.push_back(std::get<Vec3>(g.evaluate(joint, xform::kRotateAxis)));
  }
  Status s = g.set_value(plug(solver, ik::ik_attr::kRestMatrix), Value(rest));
  if (s) s = g.set_value(plug(solver, ik::ik_attr::kRestOffsetParentMatrix), Value(offset));
  if (s) s = g.set_value(plug(solver, ik::ik_attr::kRestJointOrient), Value(orient));
  if (s) s = g.set_value(plug(solver, ik::ik_attr::kRestRotateAxis), Value(axis));
  if (s) s = g.connect(plug(space, xform::kWorldMatrix), plug(solver, ik::ik_attr::kParentMatrix));
  if (!s) return s.with_context(ctx.full_name() + " ikSolver");
  return solver;
}

// The group the solver works in: under the attach point, at the world
// matrix of the root joint's parent (identity for a root joint).
Result<NodeId> make_ik_space(BuildContext& ctx, NodeId root_joint) {
  const NodeId parent = ctx.graph().parent(root_joint);
  const Mat4 world = parent.is_valid() ? ctx.scene().world_matrix(parent) : Mat4(Mat4::Identity());
  return ctx.create_group("ikSpace", -1, world, ctx.attach_node());
}

// A two-bone solver toward `target`, bending toward `pole`.
Result<NodeId> make_two_bone(BuildContext& ctx, const std::vector<NodeId>& joints, NodeId target, NodeId pole) {
  scene::Scene& scene = ctx.scene();
  const Vec3 start = position_of(scene.world_matrix(joints[0]));
  const Mat4 mid_world = scene.world_matrix(joints[1]);
  const Vec3 upper = position_of(mid_world) - start;
  const Vec3 lower = position_of(scene.world_matrix(joints[2])) - position_of(mid_world);
  Vec3 hinge = upper.cross(lower);
  if (hinge.norm() <= 1e-9 * upper.norm() * lower.norm()) hinge = (position_of(scene.world_matrix(pole)) - start).cross(upper);
  const math::Mat3 mid_linear = mid_world.topLeftCorner<3, 3>();
  if (hinge.norm() < 1e-12 || !(std::abs(mid_linear.determinant()) > 1e-300))
    return fail(ctx, "cannot find the middle joint's hinge (the chain is straight and the pole lies on it)");
  Vec3 mid_axis = (mid_linear.inverse() * hinge.normalized()).normalized();
  Result<NodeId> space = make_ik_space(ctx, joints[0]);
  if (!space) return space;
  Result<NodeId> solver = make_solver(ctx, ik::kIkTwoBoneType, joints, *space);
  if (!solver) return solver;
  graph::Graph& g = ctx.graph();
  namespace a = ik::two_bone_attr;
  Status s = g.set_value(plug(*solver, a::kMidAxis), Value(mid_axis));
  if (s) s = g.connect(plug(target, xform::kWorldMatrix), plug(*solver, a::kTargetMatrix));
  if (s) s = g.set_value(plug(*solver, a::kUsePoleMatrix), Value(true));
  if (s) s = g.connect(plug(pole, xform::kWorldMatrix), plug(*solver, a::kPoleMatrix));
  if (!s) return s.with_context(ctx.full_name() + " ikSolver");
  return solver;
}

// The fkIkSwitch (role "fkIkSwitch") for `joints`: FK from `fk` (may be
// empty), IK from `solver` (may be invalid), the last joint oriented by
// `ik_control` (may be invalid); parent space from the root's real parent.
Result<NodeId> make_switch(BuildContext& ctx, const std::vector<NodeId>& joints, const std::vector<NodeId>& fk,
                           NodeId solver, NodeId ik_control, double fk_ik) {
  graph::Graph& g = ctx.graph();
  Result<NodeId> created = ctx.create(ops::util::kFkIkSwitchType, "fkIkSwitch");
  if (!created) return created;
  const NodeId node = *created;
  std::vector<Mat4> offset;
  std::vector<Vec3> orient, axis;
  for (NodeId joint : joints) {
    offset.push_back(std::get<Mat4>(g.evaluate(joint, xform::kOffsetParentMatrix)));
    const AttrIndex jo = attr_of(g, joint, "jointOrient");
    orient.push_back(jo == graph::kNoAttr ? Vec3(Vec3::Zero()) : std::get<Vec3>(g.evaluate(joint, jo)));
    axis.push_back(std::get<Vec3>(g.evaluate(joint, xform::kRotateAxis)));
  }
  Status s = g.set_value(plug(node, sw::kRestOffsetParentMatrix), Value(offset));
  if (s) s = g.set_value(plug(node, sw::kRestJointOrient), Value(orient));
  if (s) s = g.set_value(plug(node, sw::kRestRotateAxis), Value(axis));
  if (s) s = g.set_value(plug(node, sw::kFkIk), Value(fk_ik));
  const NodeId parent = g.parent(joints[0]);
  if (s && parent.is_valid()) s = g.connect(plug(parent, xform::kWorldMatrix), plug(node, sw::kParentMatrix));
  if (s && !parent.is_valid())
    s = g.set_value(plug(node, sw::kParentMatrix), g.evaluate(joints[0], xform::kParentMatrix));
  for (std::size_t i = 0; s && i < fk.size(); ++i)
    s = g.connect(plug(fk[i], xform::kWorldMatrix), plug(node, sw::kFkMatrix, static_cast<std::int32_t>(i)));
  for (std::size_t i = 0; s && solver.is_valid() && i < joints.size(); ++i) {
    const auto e = static_cast<std::int32_t>(i);
    s = g.connect(plug(solver, ik::ik_attr::kOutWorldMatrices, e), plug(node, sw::kIkMatrix, e));
  }
  if (s && ik_control.is_valid()) {
    s = g.set_value(plug(node, sw::kUseIkEndMatrix), Value(true));
    if (s) s = g.connect(plug(ik_control, xform::kWorldMatrix), plug(node, sw::kIkEndMatrix));
  }
  if (!s) return s.with_context(ctx.full_name() + " fkIkSwitch");
  return node;
}

// Connects the switch's channels to the joints (quaternion mode) and
// publishes hook i as a group following joint i.
Status drive_joints(BuildContext& ctx, const std::vector<NodeId>& joints, NodeId node) {
  graph::Graph& g = ctx.graph();
  const std::pair<AttrIndex, AttrIndex> channels[] = {{sw::kOutTranslations, xform::kTranslate},
                                                      {sw::kOutRotations, xform::kRotateQuaternion},
                                                      {sw::kOutScales, xform::kScale},
                                                      {sw::kOutShears, xform::kShear}};
  for (std::size_t i = 0; i < joints.size(); ++i) {
    const auto e = static_cast<std::int32_t>(i);
    const NodeId joint = joints[i];
    Status s = g.set_value(plug(joint, xform::kRotateMode), Value(xform::kQuaternionMode));
    for (const auto& [src, dst] : channels) {
      if (!s) break;
      if (g.source(plug(joint, dst))) s = g.disconnect_input(plug(joint, dst));
      if (s) s = g.connect(plug(node, src, e), plug(joint, dst));
    }
    if (!s) return s.with_context(ctx.full_name() + ": drive " + g.node(joint)->name());
  }
  for (std::size_t i = 0; i < joints.size(); ++i) {
    Result<NodeId> hook = ctx.create(scene::kTransformType, "hook", static_cast<int>(i), static_cast<int>(i),
                                     ctx.rig_group("noTransform"));
    if (!hook) return hook.status();
    Status s = g.connect(plug(node, sw::kOutWorldMatrices, static_cast<std::int32_t>(i)),
                         plug(*hook, xform::kOffsetParentMatrix));
    if (s) s = ctx.publish_hook(static_cast<int>(i), *hook);
    if (!s) return s.with_context(ctx.full_name() + " hook " + std::to_string(i));
  }
  return Status::ok();
}

// ---- steps limb and quadLeg share ------------------------------------------

// `stretch` (feature stretch): the solver's stretch on, up to maxStretch.
Status stretch_step(BuildContext& ctx) {
  const NodeId solver = ctx.node("ikSolver");
  if (!solver.is_valid() || !ctx.param_bool("stretch")) return Status::ok();
  Status s = ctx.graph().set_value(plug(solver, ik::two_bone_attr::kStretch), Value(true));
  if (s) s = ctx.graph().set_value(plug(solver, ik::two_bone_attr::kMaxStretch), Value(ctx.param_double("maxStretch")));
  return s;
}

// `switch`: the switch control at `place` (guide `guide`) and the
// fkIkSwitch over the chain's `count` FK and IK poses, starting in defaultMode.
Status switch_step(BuildContext& ctx, int count, const Mat4& place, int guide) {
  Result<std::vector<NodeId>> joints = chain_joints(ctx);
  if (!joints) return joints.status();
  const NodeId solver = ctx.node("ikSolver");
  Result<NodeId> control = ctx.create_control("switch", -1, guide, place, ctx.attach_node());
  if (!control) return control.status();
  const double fk_ik = solver.is_valid() && ctx.param_string("defaultMode") == "ik" ? 1.0 : 0.0;
  std::vector<NodeId> fk;
  for (int i = 0; i < count; ++i) {
    const NodeId at_joint = node_at(ctx, "fkJoint", i);
    fk.push_back(at_joint.is_valid() ? at_joint : node_at(ctx, "fk", i));
  }
  const NodeId ik_end = ctx.node("ikEnd").is_valid() ? ctx.node("ikEnd") : ctx.node("ik");
  return make_switch(ctx, *joints, fk, solver, ik_end, fk_ik).status();
}

// `spaces` (feature ik): the ik control's spaces, `ikSpaces` or `fallback`.
Status ik_spaces_step(BuildContext& ctx, const char* fallback) {
  const NodeId ik = ctx.node("ik");
  if (!ik.is_valid()) return Status::ok();
  const std::string spec = ctx.param_string("ikSpaces");
  return add_default_spaces(ctx, ik, "ik", spec.empty() ? fallback : spec, !spec.empty());
}

// `drive`: the switch drives the joints.
Status drive_step(BuildContext& ctx) {
  Result<std::vector<NodeId>> joints = chain_joints(ctx);
  if (!joints) return joints.status();
  return drive_joints(ctx, *joints, ctx.node("fkIkSwitch"));
}

// `fk`: one FK control per guide, each under the one before.
Status fk_step(BuildContext& ctx) {
  Result<std::vector<NodeId>> joints = chain_joints(ctx);
  if (!joints) return joints.status();
  NodeId parent = ctx.attach_node();
  for (int i = 0; i < ctx.guide_count(); ++i) {
    Result<NodeId> c = control_at_guide(ctx, "fk", i, i, (*joints)[static_cast<std::size_t>(i)], parent, "fkJoint");
    if (!c) return c.status();
    parent = node_at(ctx, "fk", i);
  }
  return Status::ok();
}

// ---- ikChain ------------------------------------------------------------

Result<std::string> chain_solver(BuildContext& ctx) {
  const std::string solver = ctx.param_string("solver");
  const int n = ctx.guide_count();
  if (solver == "auto" || solver.empty()) return std::string(n == 3 ? "twoBone" : "fabrik");
  if (solver == "twoBone" && n != 3)
    return fail(ctx, "solver twoBone needs exactly 3 joints, got " + std::to_string(n));
  if (solver != "twoBone" && solver != "fabrik" && solver != "ccd") return fail(ctx, "unknown solver '" + solver + "'");
  return solver;
}

class IkChain : public ComponentClass {
 public:
  std::string_view type() const override { return "ikChain"; }
  std::vector<Step> steps(const Component&) const override {
    return {
        Step{"controls", "", "",
             [](BuildContext& ctx) -> Status {
               Result<std::string> solver = chain_solver(ctx);
               if (!solver) return solver.status();
               Result<std::vector<NodeId>> joints = chain_joints(ctx);
               if (!joints) return joints.status();
               const int n = ctx.guide_count();
               const Mat4 end = ctx.scene().world_matrix(joints->back());
               Result<NodeId> control = control_at_guide(ctx, "ik", -1, n - 1, joints->back(), ctx.attach_node(), "ikEnd");
               if (!control) return control.status();
               if (*solver != "twoBone") return Status::ok();
               const Vec3 a = position_of(ctx.scene().world_matrix((*joints)[0]));
               const Vec3 m = position_of(ctx.scene().world_matrix((*joints)[1]));
               const Vec3 dir = bend_direction(a, m, position_of(end), Vec3::UnitZ());
               Mat4 pole = Mat4::Identity();
               pole.topRightCorner<3, 1>() = m + dir * ctx.param_double("poleDistance");
               return ctx.create_control("pole", -1, 1, pole, ctx.attach_node()).status();
             }},
        Step{"ik", "", "",
             [](BuildContext& ctx) -> Status {
               Result<std::string> solver = chain_solver(ctx);
               if (!solver) return solver.status();
               Result<std::vector<NodeId>> joints = chain_joints(ctx);
               if (!joints) return joints.status();
               const NodeId target = ctx.node("ikEnd").is_valid() ? ctx.node("ikEnd") : ctx.node("ik");
               if (*solver == "twoBone") return make_two_bone(ctx, *joints, target, ctx.node("pole")).status();
               Result<NodeId> space = make_ik_space(ctx, joints->front());
               if (!space) return space.status();
               Result<NodeId> node = make_solver(ctx, *solver == "ccd" ? ik::kIkCcdType : ik::kIkFabrikType,
                                                 *joints, *space);
               if (!node) return node.status();
               return ctx.graph().connect(plug(target, xform::kWorldMatrix),
                                          plug(*node, ik::chain_attr::kTargetMatrix));
             }},
        Step{"stretch", "stretch", "",
             [](BuildContext& ctx) -> Status {
               const NodeId solver = ctx.node("ikSolver");
               if (!ctx.param_bool("stretch") || ctx.graph().node(solver)->type().name() != ik::kIkTwoBoneType)
                 return Status::ok();
               return ctx.graph().set_value(plug(solver, ik::two_bone_attr::kStretch), Value(true));
             }},
        Step{"drive", "", "",
             [](BuildContext& ctx) -> Status {
               Result<std::vector<NodeId>> joints = chain_joints(ctx);
               if (!joints) return joints.status();
               const NodeId end = ctx.node("ikEnd").is_valid() ? ctx.node("ikEnd") : ctx.node("ik");
               Result<NodeId> node = make_switch(ctx, *joints, {}, ctx.node("ikSolver"), end, 1.0);
               if (!node) return node.status();
               return drive_joints(ctx, *joints, *node);
             }},
    };
  }
};

// ---- limb ---------------------------------------------------------------

class Limb : public ComponentClass {
 public:
  std::string_view type() const override { return "limb"; }
  std::vector<Step> steps(const Component&) const override {
    return {
        Step{"fk", "", "", [](BuildContext& ctx) { return fk_step(ctx); }},
        Step{"ik", "ik", "",
             [](BuildContext& ctx) -> Status {
               Result<std::vector<NodeId>> joints = chain_joints(ctx);
               if (!joints) return joints.status();
               const Mat4 end = ctx.scene().world_matrix((*joints)[2]);
               Result<NodeId> target = control_at_guide(ctx, "ik", -1, 2, (*joints)[2], ctx.attach_node(), "ikEnd");
               if (!target) return target.status();
               const Vec3 a = position_of(ctx.scene().world_matrix((*joints)[0]));
               const Vec3 m = position_of(ctx.scene().world_matrix((*joints)[1]));
               // Straight limbs: knees forward, elbows back (glTF: +z is the character's front).
               const Vec3 front = ctx.param_string("kind") == "leg" ? Vec3(Vec3::UnitZ()) : Vec3(-Vec3::UnitZ());
               Mat4 pole_world = Mat4::Identity();
               pole_world.topRightCorner<3, 1>() =
                   m + bend_direction(a, m, position_of(end), front) * ctx.param_double("poleDistance");
               Result<NodeId> pole = ctx.create_control("pole", -1, 1, pole_world, ctx.attach_node());
               if (!pole) return pole.status();
               return make_two_bone(ctx, *joints, *target, *pole).status();
             }},
        Step{"stretch", "stretch", "", [](BuildContext& ctx) { return stretch_step(ctx); }},
        Step{"switch", "", "",
             [](BuildContext& ctx) -> Status {
               Result<std::vector<NodeId>> joints = chain_joints(ctx);
               if (!joints) return joints.status();
               // The switch control floats above the end joint by a fifth of the limb's reach.
               const Mat4 end = ctx.scene().world_matrix((*joints)[2]);
               const double reach = (position_of(ctx.scene().world_matrix((*joints)[1])) -
                                     position_of(ctx.scene().world_matrix((*joints)[0]))).norm() +
                                    (position_of(end) - position_of(ctx.scene().world_matrix((*joints)[1]))).norm();
               Mat4 place = Mat4::Identity();
               place.topRightCorner<3, 1>() = position_of(end) + Vec3(0, 0.2 * reach, 0);
               return switch_step(ctx, 3, place, 2);
             }},
        Step{"drive", "", "", [](BuildContext& ctx) { return drive_step(ctx); }},
        Step{"spaces", "ik", "",
             [](BuildContext& ctx) -> Status {
               return ik_spaces_step(ctx, ctx.param_string("kind") == "leg"
                                              ? "world,global=global/main,hip=hip/main"
                                              : "world,global=global/main,chest=chest/main,head=neck/head");
             }},
    };
  }
};

// ---- quadLeg ------------------------------------------------------------

// The two-bone chain the ikThreeBone node solves (nodes.h): start, middle
// and end positions. spring: the middle where the upper and hock bones
// meet, the end at the foot; pinned: the knee and the hock joint.
struct SolvedChain {
  Vec3 start, mid, end;
};

SolvedChain solved_chain(BuildContext& ctx, const std::vector<NodeId>& joints, bool pinned) {
  Vec3 p[4];
  for (int i = 0; i < 4; ++i) p[i] = position_of(ctx.scene().world_matrix(joints[static_cast<std::size_t>(i)]));
  if (pinned) return {p[0], p[1], p[2]};
  return {p[0], p[0] + (p[1] - p[0]) + (p[3] - p[2]), p[3]};
}

// The pole control: on the solved chain's plane (so nothing turns at rest),
// level with the knee, poleDistance off the start-end line on the bend side.
Result<NodeId> make_quad_pole(BuildContext& ctx, const std::vector<NodeId>& joints, const SolvedChain& chain) {
  const Vec3 front = ctx.param_string("kind") == "hind" ? Vec3(Vec3::UnitZ()) : Vec3(-Vec3::UnitZ());
  const Vec3 dir = bend_direction(chain.start, chain.mid, chain.end, front);
  Vec3 knee = position_of(ctx.scene().world_matrix(joints[1]));
  const Vec3 normal = (chain.end - chain.start).cross(dir);
  if (normal.norm() > 1e-12) knee -= normal.normalized() * normal.normalized().dot(knee - chain.start);
  Vec3 line = chain.end - chain.start;
  if (line.norm() > 1e-12) line.normalize();
  const Vec3 on_line = chain.start + line * line.dot(knee - chain.start);
  Mat4 place = Mat4::Identity();
  place.topRightCorner<3, 1>() = on_line + dir * ((knee - on_line).norm() + ctx.param_double("poleDistance"));
  return ctx.create_control("pole", -1, 1, place, ctx.attach_node());
}

// The ikThreeBone solver (role ikSolver) toward the ik end, the pole and,
// pinned, the hock group.
Status make_three_bone(BuildContext& ctx, const std::vector<NodeId>& joints, bool pinned) {
  const SolvedChain chain = solved_chain(ctx, joints, pinned);
  Result<NodeId> pole = make_quad_pole(ctx, joints, chain);
  if (!pole) return pole.status();
  Vec3 hinge = (chain.mid - chain.start).cross(chain.end - chain.mid);
  const Vec3 upper = chain.mid - chain.start;
  if (hinge.norm() <= 1e-9 * upper.norm() * (chain.end - chain.mid).norm())
    hinge = (position_of(ctx.scene().world_matrix(*pole)) - chain.start).cross(upper);
  const math::Mat3 mid_linear = ctx.scene().world_matrix(joints[1]).topLeftCorner<3, 3>();
  if (hinge.norm() < 1e-12 || !(std::abs(mid_linear.determinant()) > 1e-300))
    return fail(ctx, "cannot find the leg's hinge (the chain is straight and the pole lies on it)");
  Result<NodeId> space = make_ik_space(ctx, joints[0]);
  if (!space) return space.status();
  Result<NodeId> solver = make_solver(ctx, ik::kIkThreeBoneType, joints, *space);
  if (!solver) return solver.status();
  graph::Graph& g = ctx.graph();
  namespace a = ik::two_bone_attr;
  const NodeId target = ctx.node("ikEnd").is_valid() ? ctx.node("ikEnd") : ctx.node("ik");
  Status s = g.set_value(plug(*solver, a::kMidAxis), Value(Vec3((mid_linear.inverse() * hinge.normalized()).normalized())));
  if (s) s = g.connect(plug(target, xform::kWorldMatrix), plug(*solver, a::kTargetMatrix));
  if (s) s = g.set_value(plug(*solver, a::kUsePoleMatrix), Value(true));
  if (s) s = g.connect(plug(*pole, xform::kWorldMatrix), plug(*solver, a::kPoleMatrix));
  if (s) s = g.set_value(plug(*solver, ik::three_bone_attr::kHockMode), Value(std::int64_t{pinned ? 1 : 0}));
  if (s && pinned)
    s = g.connect(plug(ctx.node("hockTarget"), xform::kWorldMatrix), plug(*solver, ik::three_bone_attr::kHockMatrix));
  return s.is_ok() ? s : s.with_context(ctx.full_name() + " ikSolver");
}

class QuadLeg : public ComponentClass {
 public:
  std::string_view type() const override { return "quadLeg"; }
  std::vector<Step> steps(const Component&) const override {
    return {
        Step{"fk", "", "", [](BuildContext& ctx) { return fk_step(ctx); }},
        Step{"ik", "ik", "",
             [](BuildContext& ctx) -> Status {
               Result<std::vector<NodeId>> joints = chain_joints(ctx);
               if (!joints) return joints.status();
               Result<NodeId> ik = control_at_guide(ctx, "ik", -1, 3, (*joints)[3], ctx.attach_node(), "ikEnd");
               if (!ik) return ik.status();
               const bool pinned = ctx.param_string("hockMode") == "pinned";
               if (pinned) {
                 // The hock control turns the hock bone about the foot; the
                 // group under it, at the hock joint, is what the solver reads.
                 const Mat4 foot = math::rigid_part(ctx.scene().world_matrix((*joints)[3]));
                 Result<NodeId> hock = ctx.create_control("hock", -1, 2, foot, ctx.node("ik"));
                 if (!hock) return hock.status();
                 Result<NodeId> target =
                     ctx.create_group("hockTarget", -1, ctx.scene().world_matrix((*joints)[2]), *hock);
                 if (!target) return target.status();
               }
               return make_three_bone(ctx, *joints, pinned);
             }},
        Step{"stretch", "stretch", "", [](BuildContext& ctx) { return stretch_step(ctx); }},
        Step{"switch", "", "",
             [](BuildContext& ctx) -> Status {
               Result<std::vector<NodeId>> joints = chain_joints(ctx);
               if (!joints) return joints.status();
               const Vec3 top = position_of(ctx.scene().world_matrix((*joints)[0]));
               const Vec3 foot = position_of(ctx.scene().world_matrix((*joints)[3]));
               Mat4 place = Mat4::Identity();  // beside the foot, a fifth of the leg's height above it
               place.topRightCorner<3, 1>() = foot + Vec3(0, 0.2 * std::abs(top.y() - foot.y()), 0);
               return switch_step(ctx, 4, place, 3);
             }},
        Step{"drive", "", "", [](BuildContext& ctx) { return drive_step(ctx); }},
        Step{"spaces", "ik", "",
             [](BuildContext& ctx) -> Status {
               const NodeId ik = ctx.node("ik");
               if (Status s = ik_spaces_step(ctx, "world,global=global/main,hip=hip/main"); !s || !ik.is_valid()) return s;
               // The space the IK control starts in: the feet stay planted
               // as the body moves (world where the rig lacks the space).
               const ControlSpaces spaces = spaces_of(ctx.scene(), ik);
               if (!spaces.node.is_valid()) return Status::ok();
               Result<int> index = find_space(spaces, ctx.param_string("ikSpace"));
               if (!index) index = find_space(spaces, "world");
               if (!index) return index.status().with_context(ctx.full_name());
               return ctx.graph().set_value(plug(spaces.node, ops::util::space_attr::kSpace),
                                            Value(static_cast<double>(*index)));
             }},
    };
  }
};

// ---- springChain --------------------------------------------------------

// FK controls whose pose is the goal of a springChain node (ops/util/
// spring.h); an fkIkSwitch blends the FK pose (0) and the spring's (1).
class SpringChain : public ComponentClass {
 public:
  std::string_view type() const override { return "springChain"; }
  std::vector<Step> steps(const Component&) const override {
    return {
        Step{"fk", "", "", [](BuildContext& ctx) { return fk_step(ctx); }},
        Step{"spring", "", "",
             [](BuildContext& ctx) -> Status {
               Result<std::vector<NodeId>> joints = chain_joints(ctx);
               if (!joints) return joints.status();
               graph::Graph& g = ctx.graph();
               Result<NodeId> spring = ctx.create(ops::util::kSpringChainType, "spring");
               if (!spring) return spring.status();
               namespace a = ops::util::spring_attr;
               std::vector<NodeId> fk;
               Status s = Status::ok();
               for (int i = 0; s && i < ctx.guide_count(); ++i) {
                 const NodeId at_joint = node_at(ctx, "fkJoint", i);
                 fk.push_back(at_joint.is_valid() ? at_joint : node_at(ctx, "fk", i));
                 s = g.connect(plug(fk.back(), xform::kWorldMatrix), plug(*spring, a::kGoalMatrix, i));
               }
               const double fps = g.fps();
               if (s) s = g.set_value(plug(*spring, a::kFps), Value(fps));
               if (s) s = g.set_value(plug(*spring, a::kStartTime), Value(ctx.param_double("startFrame") / fps));
               if (s) s = g.set_value(plug(*spring, a::kStiffness), Value(ctx.param_double("stiffness")));
               if (s) s = g.set_value(plug(*spring, a::kDamping), Value(ctx.param_double("damping")));
               if (s) s = g.set_value(plug(*spring, a::kGravity), Value(Vec3(0, -ctx.param_double("gravity"), 0)));
               if (!s) return s.with_context(ctx.full_name() + " spring");
               // The switch: FK (0) to the spring (1), at `weight`.
               Result<NodeId> blend = make_switch(ctx, *joints, fk, NodeId{}, NodeId{}, ctx.param_double("weight"));
               if (!blend) return blend.status();
               for (int i = 0; s && i < ctx.guide_count(); ++i)
                 s = g.connect(plug(*spring, a::kOutWorldMatrices, i), plug(*blend, sw::kIkMatrix, i));
               return s.is_ok() ? s : s.with_context(ctx.full_name() + " fkIkSwitch");
             }},
        Step{"drive", "", "", [](BuildContext& ctx) { return drive_step(ctx); }},
    };
  }
};

// ---- twist --------------------------------------------------------------

class Twist : public ComponentClass {
 public:
  std::string_view type() const override { return "twist"; }
  std::vector<Step> steps(const Component&) const override {
    return {
        Step{"joints", "", "",
             [](BuildContext& ctx) -> Status {
               Result<NodeId> start = ctx.guide_joint(0);
               if (!start) return start.status();
               Result<NodeId> end = ctx.guide_joint(1);
               if (!end) return end.status();
               if (!ctx.scene().is_transform(*start) || !ctx.scene().is_transform(*end))
                 return fail(ctx, "the start and end guides must name transforms");
               const std::int64_t count = ctx.param_int("count");
               if (count < 1 || count > 16) return fail(ctx, "count must be 1..16, got " + std::to_string(count));
               const std::string axis_name = ctx.param_string("axis");
               const std::int64_t axis = axis_name == "x" ? 0 : axis_name == "z" ? 2 : 1;
               graph::Graph& g = ctx.graph();
               const Mat4 start_world = ctx.scene().world_matrix(*start);
               const Mat4 end_world = ctx.scene().world_matrix(*end);
               const Vec3 end_local = position_of(math::affine_inverse(start_world) * end_world);
               Result<NodeId> share = ctx.create(ops::util::kTwistShareType, "twistShare");
               if (!share) return share.status();
               namespace t = ops::util::twist_attr;
               const Quat rest = math::decompose(start_world).rotation.conjugate() * math::decompose(end_world).rotation;
               Status s = g.set_value(plug(*share, t::kRestRelative), Value(Quat(rest.normalized())));
               if (s) s = g.set_value(plug(*share, t::kAxis), Value(axis));
               if (s) s = g.set_value(plug(*share, t::kCount), Value(count));
               if (s) s = g.connect(plug(*start, xform::kWorldMatrix), plug(*share, t::kStartMatrix));
               if (s) s = g.connect(plug(*end, xform::kWorldMatrix), plug(*share, t::kEndMatrix));
               if (!s) return s.with_context(ctx.full_name() + " twistShare");
               for (std::int64_t i = 0; i < count; ++i) {
                 const int index = static_cast<int>(i);
                 Result<NodeId> joint = ctx.create(scene::kJointType, "twistJoint", index, 0, *start);
                 if (!joint) return joint.status();
                 const double f = double(i + 1) / double(count + 1);
                 s = g.set_value(plug(*joint, xform::kTranslate), Value(Vec3(end_local * f)));
                 if (s) s = g.set_value(plug(*joint, xform::kRotateMode), Value(xform::kQuaternionMode));
                 if (s) s = g.connect(plug(*share, t::kOutRotations, index), plug(*joint, xform::kRotateQuaternion));
                 if (!s) return s.with_context(ctx.full_name() + " twistJoint" + std::to_string(i));
               }
               return Status::ok();
             }},
        Step{"hooks", "", "",
             [](BuildContext& ctx) -> Status {
               for (int i = 0; i < 2; ++i) {
                 Result<NodeId> joint = ctx.guide_joint(i);
                 if (!joint) return joint.status();
                 Result<NodeId> hook = ctx.create(scene::kTransformType, "hook", i, i, ctx.rig_group("noTransform"));
                 if (!hook) return hook.status();
                 Status s = ctx.graph().connect(plug(*joint, xform::kWorldMatrix), plug(*hook, xform::kOffsetParentMatrix));
                 if (s) s = ctx.publish_hook(i, *hook);
                 if (!s) return s;
               }
               return Status::ok();
             }},
    };
  }
};

}  // namespace

Status add_limb_components(ComponentFactory& factory) {
  if (Status s = factory.add(std::make_shared<IkChain>()); !s) return s;
  if (Status s = factory.add(std::make_shared<Limb>()); !s) return s;
  if (Status s = factory.add(std::make_shared<QuadLeg>()); !s) return s;
  if (Status s = factory.add(std::make_shared<SpringChain>()); !s) return s;
  return factory.add(std::make_shared<Twist>());
}

}  // namespace rigel::rig::components
