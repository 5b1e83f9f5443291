// foot: a reverse foot (components/foot.h).
#include "rigel/rig/components/foot.h"

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "rigel/math/transform.h"
#include "rigel/ops/ik/nodes.h"
#include "rigel/ops/util/blend.h"
#include "rigel/ops/util/foot.h"
#include "rigel/rig/component.h"
#include "rigel/rig/meta.h"
#include "rigel/scene/transform_types.h"

namespace rigel::rig::components {
namespace {

using graph::AttrIndex;
using graph::Plug;
using graph::Value;
using math::Mat4;
using math::Vec3;
namespace xform = scene::xform;
namespace sw = ops::util::fk_ik_attr;
namespace rf = ops::util::reverse_foot_attr;

enum Guide { kAnkle = 0, kBall, kToe, kHeel, kInner, kOuter };
constexpr const char* kGuideNames[] = {"ankle", "ball", "toe", "heel", "inner", "outer"};

Vec3 position_of(const Mat4& m) { return m.topRightCorner<3, 1>(); }

Plug plug(NodeId node, AttrIndex attr, std::int32_t element = -1) { return Plug{node, attr, element}; }

Status fail(BuildContext& ctx, const std::string& what) {
  return error(ErrorCode::kInvalidArgument, ctx.full_name() + " (" + ctx.component().type + "): " + what);
}

std::string guide_label(int i) { return "guide " + std::to_string(i) + " (" + kGuideNames[i] + ")"; }

// The guides at rest, in the world, and the foot's frame (foot.h).
struct Foot {
  NodeId ankle, ball;
  Mat4 ankle_world, ball_world, toe_world;
  Vec3 heel, toe, inner, outer;
  Vec3 up, forward, roll_axis, outward;
  Mat4 control_world;  // on the ground below the ankle, axes (roll, up, forward)
};

Result<NodeId> guide_joint(BuildContext& ctx, int i) {
  if (ctx.component().guides[i].joint.empty())
    return fail(ctx, guide_label(i) + " must name a joint: the foot drives it");
  Result<NodeId> j = ctx.guide_joint(i);
  if (!j) return j;
  if (!ctx.scene().is_transform(*j))
    return fail(ctx, guide_label(i) + ": '" + ctx.graph().node(*j)->name() + "' is not a transform");
  return j;
}

Result<Foot> read_foot(BuildContext& ctx) {
  if (ctx.guide_count() != 6) return fail(ctx, "needs 6 guides (ankle, ball, toe, heel, inner, outer)");
  Foot f;
  graph::Graph& g = ctx.graph();
  Result<NodeId> ankle = guide_joint(ctx, kAnkle);
  if (!ankle) return ankle.status();
  Result<NodeId> ball = guide_joint(ctx, kBall);
  if (!ball) return ball.status();
  if (g.parent(*ball) != *ankle)
    return fail(ctx, guide_label(kBall) + ": '" + g.node(*ball)->name() + "' is not a child of the ankle joint '" +
                         g.node(*ankle)->name() + "'");
  f.ankle = *ankle;
  f.ball = *ball;
  f.ankle_world = ctx.scene().world_matrix(f.ankle);
  f.ball_world = ctx.scene().world_matrix(f.ball);
  Vec3* points[] = {nullptr, nullptr, &f.toe, &f.heel, &f.inner, &f.outer};
  for (int i = kToe; i <= kOuter; ++i) {
    Result<Mat4> world = ctx.guide_world(i);
    if (!world) return world.status();
    if (!world->allFinite()) return fail(ctx, guide_label(i) + " is not finite");
    *points[i] = position_of(*world);
    if (i == kToe) f.toe_world = *world;
  }
  // Thresholds relative to the foot's size, so any unit works.
  const Vec3 ankle_at = position_of(f.ankle_world);
  const Vec3 length = f.toe - f.heel, across = f.outer - f.inner;
  const double size = length.norm();
  if (!(size > 1e-9)) return fail(ctx, "the heel and toe guides coincide");
  if (!(across.norm() > 1e-6 * size)) return fail(ctx, "the inner and outer guides coincide");
  Vec3 up = length.cross(across);
  if (!(up.norm() > 1e-3 * size * across.norm()))
    return fail(ctx, "the inner and outer guides lie on the heel-toe line: the sole spans no plane");
  up.normalize();
  const double height = up.dot(ankle_at - f.heel);
  if (height < 0) up = -up;
  if (!(std::abs(height) > 1e-3 * size))
    return fail(ctx, "the ankle lies on the sole's plane (heel, toe, inner, outer)");
  Vec3 forward = f.toe - ankle_at;
  forward -= up * up.dot(forward);
  if (!(forward.norm() > 1e-3 * size)) return fail(ctx, "the toe guide is straight below the ankle");
  forward.normalize();
  if (!(forward.dot(length) > 0)) return fail(ctx, "the toe guide is behind the heel guide");
  f.up = up;
  f.forward = forward;
  f.roll_axis = up.cross(forward);
  const double side = across.dot(f.roll_axis);
  if (!(std::abs(side) > 1e-3 * across.norm()))
    return fail(ctx, "the inner and outer guides are not on either side of the foot");
  f.outward = side > 0 ? f.roll_axis : Vec3(-f.roll_axis);
  f.control_world = Mat4::Identity();
  f.control_world.col(0).head<3>() = f.roll_axis;
  f.control_world.col(1).head<3>() = f.up;
  f.control_world.col(2).head<3>() = f.forward;
  f.control_world.topRightCorner<3, 1>() = ankle_at - up * up.dot(ankle_at - f.heel);
  return f;
}

// The chain the foot ends: the parent component's nodes when its
// fkIkSwitch drives the ankle as the last joint of its chain (a limb, an
// ikChain); all invalid for a foot on its own.
struct ParentChain {
  NodeId meta, blend, solver, ik, fk_end;
};

Result<ParentChain> parent_chain(BuildContext& ctx, NodeId ankle) {
  graph::Graph& g = ctx.graph();
  ParentChain out;
  const NodeId parent = meta_parent(g, ctx.meta());
  if (!parent.is_valid() || g.node(parent)->type().name() != kMetaComponentType) return out;
  const std::string parent_type = meta_string(g, parent, "metaType");
  const std::optional<Plug> source = g.source(plug(ankle, xform::kRotateQuaternion));
  const bool chained = source && component_of(g, source->node) == parent &&
                       g.node(source->node)->type().name() == ops::util::kFkIkSwitchType &&
                       source->attr == sw::kOutRotations;
  if (!chained) {
    if (parent_type == "limb" || parent_type == "ikChain")
      return fail(ctx, "the ankle joint '" + g.node(ankle)->name() + "' is not the end joint of " + parent_type + " '" +
                           meta_string(g, parent, "componentName") + "'");
    return out;  // another kind of parent: the foot works on its own
  }
  const auto joints = static_cast<std::int32_t>(
      std::get<std::vector<Mat4>>(g.evaluate(source->node, sw::kRestOffsetParentMatrix)).size());
  if (source->element + 1 != joints)
    return fail(ctx, "the ankle joint '" + g.node(ankle)->name() + "' is not the last joint of " + parent_type + " '" +
                         meta_string(g, parent, "componentName") + "'");
  out.meta = parent;
  out.blend = source->node;
  auto optional_node = [&](const char* role, int index) {
    Result<NodeId> r = get_meta_connection(g, parent, role, index);
    return r ? *r : NodeId{};
  };
  out.solver = optional_node("ikSolver", 0);
  out.ik = optional_node("ik", 0);
  out.fk_end = optional_node("fk", joints - 1);
  return out;
}

// Replaces whatever feeds `dst` with `src` (the recorder keeps the old
// connection, so the destruct restores it).
Status reconnect(graph::Graph& g, const Plug& src, const Plug& dst) {
  if (g.source(dst)) {
    if (Status s = g.disconnect_input(dst); !s) return s;
  }
  return g.connect(src, dst);
}

class FootComponent : public ComponentClass {
 public:
  std::string_view type() const override { return "foot"; }
  std::vector<Step> steps(const Component&) const override {
    return {
        Step{"controls", "", "",
             [](BuildContext& ctx) -> Status {
               Result<Foot> foot = read_foot(ctx);
               if (!foot) return foot.status();
               Result<ParentChain> chain = parent_chain(ctx, foot->ankle);
               if (!chain) return chain.status();
               const NodeId parent = chain->ik.is_valid() ? chain->ik : ctx.attach_node();
               Result<NodeId> control = ctx.create_control("foot", -1, kAnkle, foot->control_world, parent);
               if (!control) return control.status();
               if (!chain->fk_end.is_valid()) return Status::ok();
               // A rigid control, and a group under it at the ball joint's
               // frame when that is not rigid (see limbs.cc, control_at_guide).
               Result<NodeId> toe =
                   ctx.create_control("toeFk", -1, kBall, math::rigid_part(foot->ball_world), chain->fk_end);
               if (!toe || math::is_rigid(foot->ball_world)) return toe.status();
               return ctx.create_group("toeFkJoint", -1, foot->ball_world, *toe).status();
             }},
        Step{"reverseFoot", "", "",
             [](BuildContext& ctx) -> Status {
               Result<Foot> foot = read_foot(ctx);
               if (!foot) return foot.status();
               graph::Graph& g = ctx.graph();
               const NodeId control = ctx.node("foot");
               Result<NodeId> created = ctx.create(ops::util::kReverseFootType, "reverseFoot");
               if (!created) return created.status();
               const NodeId node = *created;
               // Everything in the control's rest space, so the chain follows
               // the control (and whatever it hangs from) as one piece.
               const Mat4 to_control = math::affine_inverse(ctx.scene().world_matrix(control));
               auto point = [&](const Vec3& p) {
                 return Vec3(to_control.topLeftCorner<3, 3>() * p + to_control.topRightCorner<3, 1>());
               };
               auto direction = [&](const Vec3& d) {
                 return Vec3((to_control.topLeftCorner<3, 3>() * d).normalized());
               };
               const Vec3 ball_at = position_of(foot->ball_world);
               const std::pair<AttrIndex, Value> values[] = {
                   {rf::kRollBreak, Value(ctx.param_double("rollBreak"))},
                   {rf::kHeelPivot, Value(point(foot->heel))},
                   {rf::kToePivot, Value(point(foot->toe))},
                   {rf::kBallPivot, Value(point(ball_at))},
                   {rf::kInnerPivot, Value(point(foot->inner))},
                   {rf::kOuterPivot, Value(point(foot->outer))},
                   {rf::kRollAxis, Value(direction(foot->roll_axis))},
                   {rf::kBankAxis, Value(direction(foot->up.cross(foot->outward)))},
                   {rf::kTwistAxis, Value(direction(foot->forward.cross(foot->outward)))},
                   {rf::kRestAnkleMatrix, Value(Mat4(to_control * foot->ankle_world))},
                   {rf::kRestBallMatrix, Value(Mat4(to_control * foot->ball_world))}};
               Status s = Status::ok();
               for (const auto& [attr, value] : values) {
                 s = g.set_value(plug(node, attr), value);
                 if (!s) break;
               }
               if (s) s = g.connect(plug(control, xform::kWorldMatrix), plug(node, rf::kControlMatrix));
               return s.is_ok() ? s : s.with_context(ctx.full_name() + " reverseFoot");
             }},
        Step{"ankle", "", "",
             [](BuildContext& ctx) -> Status {
               Result<Foot> foot = read_foot(ctx);
               if (!foot) return foot.status();
               Result<ParentChain> chain = parent_chain(ctx, foot->ankle);
               if (!chain) return chain.status();
               graph::Graph& g = ctx.graph();
               const Plug out = plug(ctx.node("reverseFoot"), rf::kOutAnkleMatrix);
               if (chain->blend.is_valid()) {
                 // The parent chain owns the ankle; the foot takes over its IK
                 // end: the solver's target and the switch's end orientation.
                 // A parent without IK (limb feature "ik" off) keeps its FK.
                 if (!chain->solver.is_valid()) return Status::ok();
                 const AttrIndex target = g.node(chain->solver)->type().attr_find("targetMatrix");
                 if (target == graph::kNoAttr) return fail(ctx, "the parent's ikSolver has no targetMatrix");
                 Status s = reconnect(g, out, plug(chain->solver, target));
                 if (s && !std::get<bool>(g.evaluate(chain->blend, sw::kUseIkEndMatrix)))
                   s = g.set_value(plug(chain->blend, sw::kUseIkEndMatrix), Value(true));
                 if (s) s = reconnect(g, out, plug(chain->blend, sw::kIkEndMatrix));
                 return s.is_ok() ? s : s.with_context(ctx.full_name() + ": take over the IK end");
               }
               Result<NodeId> driver =
                   ctx.create(scene::kTransformType, "ankleDriver", -1, kAnkle, ctx.rig_group("noTransform"));
               if (!driver) return driver.status();
               if (Status s = g.connect(out, plug(*driver, xform::kOffsetParentMatrix)); !s) return s;
               return ctx.drive(*driver, foot->ankle);
             }},
        Step{"drive", "", "",
             [](BuildContext& ctx) -> Status {
               Result<Foot> foot = read_foot(ctx);
               if (!foot) return foot.status();
               Result<ParentChain> chain = parent_chain(ctx, foot->ankle);
               if (!chain) return chain.status();
               graph::Graph& g = ctx.graph();
               // The ball joint: IK from the reverse foot, FK from toeFk, by
               // the parent's fkIk (the same switch as the leg's).
               Result<NodeId> created = ctx.create(ops::util::kFkIkSwitchType, "fkIkSwitch", -1, kBall);
               if (!created) return created.status();
               const NodeId blend = *created;
               const NodeId ball = foot->ball;
               const AttrIndex orient = g.node(ball)->type().attr_find("jointOrient");
               const Vec3 jo = orient == graph::kNoAttr ? Vec3(Vec3::Zero()) : std::get<Vec3>(g.evaluate(ball, orient));
               Status s =
                   g.set_value(plug(blend, sw::kRestOffsetParentMatrix),
                               Value(std::vector<Mat4>{std::get<Mat4>(g.evaluate(ball, xform::kOffsetParentMatrix))}));
               if (s) s = g.set_value(plug(blend, sw::kRestJointOrient), Value(std::vector<Vec3>{jo}));
               if (s)
                 s = g.set_value(plug(blend, sw::kRestRotateAxis),
                                 Value(std::vector<Vec3>{std::get<Vec3>(g.evaluate(ball, xform::kRotateAxis))}));
               if (s) s = g.connect(plug(foot->ankle, xform::kWorldMatrix), plug(blend, sw::kParentMatrix));
               if (s) s = g.connect(plug(ctx.node("reverseFoot"), rf::kOutBallMatrix), plug(blend, sw::kIkMatrix, 0));
               const NodeId toe_fk = ctx.node("toeFkJoint").is_valid() ? ctx.node("toeFkJoint") : ctx.node("toeFk");
               if (s && toe_fk.is_valid()) s = g.connect(plug(toe_fk, xform::kWorldMatrix), plug(blend, sw::kFkMatrix, 0));
               if (s && chain->blend.is_valid()) s = g.connect(plug(chain->blend, sw::kFkIk), plug(blend, sw::kFkIk));
               if (s && !chain->blend.is_valid()) s = g.set_value(plug(blend, sw::kFkIk), Value(1.0));
               if (!s) return s.with_context(ctx.full_name() + " fkIkSwitch");
               const std::pair<AttrIndex, AttrIndex> channels[] = {{sw::kOutTranslations, xform::kTranslate},
                                                                   {sw::kOutRotations, xform::kRotateQuaternion},
                                                                   {sw::kOutScales, xform::kScale},
                                                                   {sw::kOutShears, xform::kShear}};
               s = g.set_value(plug(ball, xform::kRotateMode), Value(xform::kQuaternionMode));
               for (const auto& [src, dst] : channels) {
                 if (!s) break;
                 s = reconnect(g, plug(blend, src, 0), plug(ball, dst));
               }
               if (!s) return s.with_context(ctx.full_name() + ": drive " + g.node(ball)->name());
               // Hooks: ankle and ball follow their joints; the toe tip rides
               // on the ball hook at its rest offset.
               const NodeId no_transform = ctx.rig_group("noTransform");
               NodeId ball_hook;
               for (int i = 0; i < 2; ++i) {
                 Result<NodeId> hook = ctx.create(scene::kTransformType, "hook", i, i, no_transform);
                 if (!hook) return hook.status();
                 s = g.connect(plug(i == 0 ? foot->ankle : ball, xform::kWorldMatrix),
                               plug(*hook, xform::kOffsetParentMatrix));
                 if (s) s = ctx.publish_hook(i, *hook);
                 if (!s) return s.with_context(ctx.full_name() + " hook " + std::to_string(i));
                 ball_hook = *hook;
               }
               Result<NodeId> toe = ctx.create(scene::kTransformType, "hook", 2, kToe, ball_hook);
               if (!toe) return toe.status();
               s = g.set_value(plug(*toe, xform::kOffsetParentMatrix),
                               Value(Mat4(math::affine_inverse(foot->ball_world) * foot->toe_world)));
               if (s) s = ctx.publish_hook(2, *toe);
               return s.is_ok() ? s : s.with_context(ctx.full_name() + " hook 2");
             }},
    };
  }
};

}  // namespace

Status add_foot_component(ComponentFactory& factory) { return factory.add(std::make_shared<FootComponent>()); }

}  // namespace rigel::rig::components
