// FK/IK matching of a built limb and its child foot (components/limbs.h).
// Everything is found through the metadata network by role: the limb's fk
// controls, ik, pole, ikSolver and fkIkSwitch; a child foot's toeFk,
// reverseFoot and fkIkSwitch. Each side's joint poses are read where the
// switch reads them (its fkMatrix / ikMatrix / ikEndMatrix inputs), so a
// match is exact for whatever drives either side.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "rigel/math/rotation.h"
#include "rigel/math/transform.h"
#include "rigel/ops/ik/nodes.h"
#include "rigel/ops/ik/two_bone_ik.h"
#include "rigel/ops/util/blend.h"
#include "rigel/ops/util/fk_ik_blend.h"
#include "rigel/ops/util/foot.h"
#include "rigel/ops/util/reverse_foot.h"
#include "rigel/rig/components/limbs.h"
#include "rigel/rig/meta.h"
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
namespace rf = ops::util::reverse_foot_attr;

Vec3 position_of(const Mat4& m) { return m.topRightCorner<3, 1>(); }

struct FootNodes {
  NodeId toe_fk, reverse_foot, blend;  // toe_fk invalid when the foot has no FK side
  Mat4 toe_to_joint = Mat4::Identity();  // the offsetParentMatrix of its toeFkJoint group, if any
};

struct LimbNodes {
  std::vector<NodeId> fk;  // 3 (limb) or 4 (quadLeg)
  NodeId ik, pole, solver, blend;
  NodeId hock;  // a pinned quadLeg's hock control (else invalid)
  Mat4 hock_to_joint = Mat4::Identity();  // the offsetParentMatrix of its hockTarget group
  int solved_end = 2;  // the joint the solver's two-bone chain ends at (a spring quadLeg: 3, the foot)
  // From each control to the joint it drives: identity, or the
  // offsetParentMatrix of its fkJoint / ikEnd group (an offset guide, or a
  // joint whose frame is not rigid: limbs.cc, control_at_guide).
  std::vector<Mat4> fk_to_joint;
  std::optional<FootNodes> foot;  // a child foot component with a reverse foot
};

std::string component_name(const graph::Graph& g, NodeId meta) {
  return "component '" + meta_string(g, meta, "componentName") + "' (" + meta_string(g, meta, "metaType") + ")";
}

Result<LimbNodes> limb_nodes(const graph::Graph& g, NodeId meta) {
  const graph::Node* n = g.node(meta);
  if (!n || n->type().name() != kMetaComponentType)
    return error(ErrorCode::kInvalidArgument, "match: not a component of a built rig");
  const std::string type = meta_string(g, meta, "metaType");
  if (type != "limb" && type != "quadLeg")
    return Status(ErrorCode::kInvalidArgument,
                  "match: " + component_name(g, meta) + " has no FK/IK switch (limbs and quadLegs have one)")
        .with_field("component");
  LimbNodes out;
  const int count = type == "quadLeg" ? 4 : 3;
  out.fk.resize(static_cast<std::size_t>(count));
  out.fk_to_joint.assign(static_cast<std::size_t>(count), Mat4::Identity());
  auto find = [&](NodeId m, const char* role, int index, NodeId& into) -> Status {
    Result<NodeId> r = get_meta_connection(g, m, role, index);
    if (!r) return r.status().with_context("match " + component_name(g, m));
    into = *r;
    return Status::ok();
  };
  for (const char* role : {"ik", "pole", "ikSolver"})
    if (!get_meta_connection(g, meta, role).is_ok())
      return Status(ErrorCode::kInvalidArgument,
                    "match: " + component_name(g, meta) + " has no IK side (its feature \"ik\" is off)")
          .with_field("component");
  for (int i = 0; i < count; ++i)
    if (Status s = find(meta, "fk", i, out.fk[static_cast<std::size_t>(i)]); !s) return s;
  for (auto [role, into] : {std::pair<const char*, NodeId*>{"ik", &out.ik}, {"pole", &out.pole},
                            {"ikSolver", &out.solver}, {"fkIkSwitch", &out.blend}})
    if (Status s = find(meta, role, 0, *into); !s) return s;
  for (NodeId m : meta_members(g, meta)) {
    const std::string* role = g.node(m)->tag_find(kTagRole);
    if (!role || *role != "fkJoint") continue;
    const std::string* index = g.node(m)->tag_find(kTagIndex);
    if (index && index->size() == 1 && (*index)[0] >= '0' && (*index)[0] < '0' + count)
      out.fk_to_joint[static_cast<std::size_t>((*index)[0] - '0')] =
          std::get<Mat4>(g.node(m)->value(xform::kOffsetParentMatrix));
  }
  if (type == "quadLeg") {
    const bool pinned = std::get<std::int64_t>(g.node(out.solver)->value(ik::three_bone_attr::kHockMode)) == 1;
    out.solved_end = pinned ? 2 : 3;
    if (pinned) {
      if (Status s = find(meta, "hock", 0, out.hock); !s) return s;
      NodeId group;
      if (Status s = find(meta, "hockTarget", 0, group); !s) return s;
      out.hock_to_joint = std::get<Mat4>(g.node(group)->value(xform::kOffsetParentMatrix));
    }
    return out;  // a quadLeg's foot is its own fourth joint
  }
  for (NodeId child : meta_children(g, meta)) {
    if (meta_string(g, child, "metaType") != "foot") continue;
    Result<NodeId> reverse = get_meta_connection(g, child, "reverseFoot");
    Result<NodeId> blend = get_meta_connection(g, child, "fkIkSwitch");
    if (!reverse || !blend) continue;
    Result<NodeId> toe = get_meta_connection(g, child, "toeFk");
    out.foot = FootNodes{toe ? *toe : NodeId{}, *reverse, *blend};
    if (Result<NodeId> group = get_meta_connection(g, child, "toeFkJoint"); group)
      out.foot->toe_to_joint = std::get<Mat4>(g.node(*group)->value(xform::kOffsetParentMatrix));
    break;
  }
  return out;
}

template <typename T>
T eval(graph::Graph& g, NodeId node, AttrIndex attr) {
  return std::get<T>(g.evaluate(node, attr));
}

// The joint worlds a switch reads on one side (its last joint's IK pose as
// it takes it: the solver's position, the end matrix's orientation).
std::vector<Mat4> switch_side(graph::Graph& g, NodeId blend, MatchSide side) {
  std::vector<Mat4> worlds = eval<std::vector<Mat4>>(g, blend, side == MatchSide::kFk ? sw::kFkMatrix : sw::kIkMatrix);
  if (side == MatchSide::kIk && !worlds.empty() && eval<bool>(g, blend, sw::kUseIkEndMatrix))
    worlds.back() = ops::util::ik_end_world(worlds.back(), eval<Mat4>(g, blend, sw::kIkEndMatrix));
  return worlds;
}

// The joint a switch drives at `index` (the destination of its outRotations).
NodeId driven_joint(const graph::Graph& g, NodeId blend, int index) {
  for (const graph::Connection& c : g.node(blend)->outputs())
    if (c.src.attr == sw::kOutRotations && c.src.element == index) return c.dst.node;
  return {};
}

// The toe tap that turns a reverse foot's toes from its ankle pose `ankle`
// onto `ball` (world matrices): the ball branch is control * H T B P *
// rest_ball and the ankle's control * H T B L * rest_ankle
// (ops/util/reverse_foot.h), so P = L * rest_ankle * ankle^-1 * ball *
// rest_ball^-1, a turn by -toeTap about the roll axis through the ball
// pivot. Its part about that axis is the answer; exact when the turn is
// about that axis only.
double toe_tap_for(graph::Graph& g, NodeId reverse, const Mat4& ankle, const Mat4& ball) {
  ops::util::ReverseFootPivots pivots;
  pivots.heel = eval<Vec3>(g, reverse, rf::kHeelPivot);
  pivots.toe = eval<Vec3>(g, reverse, rf::kToePivot);
  pivots.ball = eval<Vec3>(g, reverse, rf::kBallPivot);
  pivots.inner = eval<Vec3>(g, reverse, rf::kInnerPivot);
  pivots.outer = eval<Vec3>(g, reverse, rf::kOuterPivot);
  pivots.roll_axis = eval<Vec3>(g, reverse, rf::kRollAxis).normalized();
  pivots.bank_axis = eval<Vec3>(g, reverse, rf::kBankAxis).normalized();
  pivots.twist_axis = eval<Vec3>(g, reverse, rf::kTwistAxis).normalized();
  ops::util::ReverseFootValues values;
  values.roll = eval<double>(g, reverse, rf::kRoll);
  values.roll_break = eval<double>(g, reverse, rf::kRollBreak);
  values.bank = eval<double>(g, reverse, rf::kBank);
  values.heel_twist = eval<double>(g, reverse, rf::kHeelTwist);
  values.toe_twist = eval<double>(g, reverse, rf::kToeTwist);
  values.ball_twist = eval<double>(g, reverse, rf::kBallTwist);
  values.toe_tap = 0;
  const ops::util::ReverseFootChain chain = ops::util::reverse_foot_chain(pivots, values);
  const Mat4 l = math::affine_inverse(chain.ball) * chain.ankle;  // P is the identity at toe tap 0
  const Mat4 p = l * eval<Mat4>(g, reverse, rf::kRestAnkleMatrix) * math::affine_inverse(ankle) * ball *
                 math::affine_inverse(eval<Mat4>(g, reverse, rf::kRestBallMatrix));
  const Quat q(math::decompose(p).rotation);
  double turn = 2.0 * std::atan2(q.vec().dot(pivots.roll_axis), q.w());  // radians about the roll axis
  turn = std::remainder(turn, 2.0 * std::numbers::pi);
  return -turn * 180.0 / std::numbers::pi;
}

// Sets a control's channels so that its world matrix is `world`.
Status set_world(scene::Scene& scene, NodeId control, const Mat4& world) {
  graph::Graph& g = scene.graph();
  const NodeId parent = g.parent(control);
  const Mat4 parent_world = parent.is_valid() ? scene.world_matrix(parent) : Mat4(Mat4::Identity());
  const Mat4 offset = std::get<Mat4>(g.evaluate(control, xform::kOffsetParentMatrix));
  const Mat4 local = math::affine_inverse(parent_world * offset) * world;
  const auto order = static_cast<math::RotateOrder>(std::get<std::int64_t>(g.evaluate(control, xform::kRotateOrder)));
  const math::TransformParts parts = math::decompose_to_parts(local, order);
  Status s = g.set_value(Plug{control, xform::kTranslate, -1}, Value(parts.translate));
  if (s && xform::is_quaternion_mode(*g.node(control)))
    s = g.set_value(Plug{control, xform::kRotateQuaternion, -1}, Value(math::euler_to_quat(parts.rotate, order)));
  else if (s)
    s = g.set_value(Plug{control, xform::kRotate, -1}, Value(Vec3(math::to_degrees(parts.rotate))));
  if (s) s = g.set_value(Plug{control, xform::kScale, -1}, Value(parts.scale));
  if (s) s = g.set_value(Plug{control, xform::kShear, -1}, Value(parts.shear));
  return s.is_ok() ? s : s.with_context("match: " + g.node(control)->name());
}

Status apply(scene::Scene& scene, NodeId limb_meta, MatchSide set, const char* label) {
  graph::Graph& g = scene.graph();
  Result<FkIkMatch> plan = plan_fk_ik_match(scene, limb_meta, set);
  if (!plan) return plan.status();
  graph::Transaction tx(g, label);
  for (const MatchControl& c : plan->controls) {
    if (Status s = set_world(scene, c.control, c.world); !s) {
      tx.rollback();
      return s;
    }
  }
  for (const MatchValue& v : plan->values) {
    if (Status s = g.set_value(v.plug, Value(v.value)); !s) {
      tx.rollback();
      return s.with_context("match");
    }
  }
  return Status::ok();
}

}  // namespace

std::vector<Mat4> fk_ik_side_worlds(scene::Scene& scene, NodeId limb_meta, MatchSide side) {
  graph::Graph& g = scene.graph();
  Result<LimbNodes> nodes = limb_nodes(g, limb_meta);
  if (!nodes) return {};
  std::vector<Mat4> worlds = switch_side(g, nodes->blend, side);
  if (nodes->foot && nodes->foot->toe_fk.is_valid()) {
    const std::vector<Mat4> ball = switch_side(g, nodes->foot->blend, side);
    worlds.insert(worlds.end(), ball.begin(), ball.end());
  }
  return worlds;
}

Result<FkIkMatch> plan_fk_ik_match(scene::Scene& scene, NodeId limb_meta, MatchSide set) {
  graph::Graph& g = scene.graph();
  Result<LimbNodes> found = limb_nodes(g, limb_meta);
  if (!found) return found.status();
  const LimbNodes& nodes = *found;
  const bool toe = nodes.foot && nodes.foot->toe_fk.is_valid();
  FkIkMatch plan;
  plan.fk_ik = Plug{nodes.blend, sw::kFkIk, -1};
  const std::size_t count = nodes.fk.size();
  for (std::size_t i = 0; i < count; ++i) plan.joints.push_back(driven_joint(g, nodes.blend, static_cast<int>(i)));
  if (toe) plan.joints.push_back(driven_joint(g, nodes.foot->blend, 0));
  const MatchSide from = set == MatchSide::kFk ? MatchSide::kIk : MatchSide::kFk;
  plan.joint_worlds = fk_ik_side_worlds(scene, limb_meta, from);
  if (plan.joint_worlds.size() != plan.joints.size())
    return error(ErrorCode::kInvalidArgument, "match " + component_name(g, limb_meta) + ": its switch drives " +
                                                  std::to_string(plan.joint_worlds.size()) + " joints, expected " +
                                                  std::to_string(plan.joints.size()));
  const std::vector<Mat4>& target = plan.joint_worlds;
  if (set == MatchSide::kFk) {
    for (std::size_t i = 0; i < count; ++i)
      plan.controls.push_back({nodes.fk[i], target[i] * math::affine_inverse(nodes.fk_to_joint[i])});
    if (toe)
      plan.controls.push_back({nodes.foot->toe_fk, target[count] * math::affine_inverse(nodes.foot->toe_to_joint)});
    return plan;
  }
  // The IK end as the switch and the solver take it hangs rigidly from the
  // ik control (its end group, or the reverse foot whatever its values):
  // end = ik * q, so the ik control goes to fk_end * q^-1.
  const bool use_end = eval<bool>(g, nodes.blend, sw::kUseIkEndMatrix);
  const Mat4 end = use_end ? eval<Mat4>(g, nodes.blend, sw::kIkEndMatrix)
                           : eval<Mat4>(g, nodes.solver, ik::two_bone_attr::kTargetMatrix);
  const Mat4 q = math::affine_inverse(scene.world_matrix(nodes.ik)) * end;
  plan.controls.push_back({nodes.ik, target[count - 1] * math::affine_inverse(q)});
  // A pinned quadLeg's hock group (under the hock control, under the ik
  // control) is the hock bone's IK pose: the hock control goes where the
  // group lands on the FK hock bone.
  if (nodes.hock.is_valid()) plan.controls.push_back({nodes.hock, target[2] * math::affine_inverse(nodes.hock_to_joint)});
  // The pole. The two-bone solver turns the start joint so that its hinge
  // (midAxis in the middle joint's space), made perpendicular to
  // start-to-target, lies along pole x aim (poleVector mode) or along the
  // pole (planeNormal), then turns that by `twist` about the aim
  // (ops/ik/two_bone_ik.h). So the pole goes where the FK pose's hinge asks:
  // across the aim by aim x hinge, at its current distance from the middle
  // joint's side of the line. (Placing it in the plane of the three joints
  // instead is off by the hinge's tilt from that plane, ~1e-6 on rigs built
  // from single-precision files.)
  // The solver's chain: its middle's frame is joint 1's; a spring quadLeg's
  // chain ends at the foot (ops/ik/nodes.h, ikThreeBone).
  const Vec3 a = position_of(target[0]), m = position_of(target[1]);
  const Vec3 e = position_of(target[static_cast<std::size_t>(nodes.solved_end)]);
  Vec3 aim = e - a;
  const Vec3 mid_axis = eval<Vec3>(g, nodes.solver, ik::two_bone_attr::kMidAxis);
  Vec3 hinge = target[1].topLeftCorner<3, 3>() * mid_axis;
  if (aim.norm() > 1e-12 && hinge.norm() > 1e-12) {
    aim.normalize();
    hinge = hinge - aim * aim.dot(hinge);
    if (hinge.norm() > 1e-9) {
      hinge.normalize();
      const double twist = math::to_radians(eval<double>(g, nodes.solver, ik::two_bone_attr::kTwist));
      if (twist != 0.0) hinge = hinge * std::cos(twist) - aim.cross(hinge) * std::sin(twist);  // undo the twist
      const bool plane_normal =
          eval<std::int64_t>(g, nodes.solver, ik::two_bone_attr::kPoleMode) ==
          static_cast<std::int64_t>(ik::TwoBonePoleMode::kPlaneNormal);
      const Vec3 across = plane_normal ? hinge : Vec3(aim.cross(hinge));
      const std::vector<Mat4> ik_worlds = switch_side(g, nodes.blend, MatchSide::kIk);
      const Mat4 pole_world = scene.world_matrix(nodes.pole);
      const Vec3 ik_mid = ik_worlds.size() == count ? position_of(ik_worlds[1]) : m;
      double distance = (position_of(pole_world) - ik_mid).norm();
      if (!(distance > 1e-9)) distance = (m - a).norm();
      const Vec3 foot = a + aim * aim.dot(m - a);  // the middle joint's foot on the line
      Mat4 place = pole_world;
      place.topRightCorner<3, 1>() = foot + across * ((m - foot).norm() + distance);
      plan.controls.push_back({nodes.pole, place});
    }
  }
  // A straight FK pose has no bend plane: the pole stays (listed all the
  // same, so every frame of a bake sets the same controls).
  if (plan.controls.back().control != nodes.pole) plan.controls.push_back({nodes.pole, scene.world_matrix(nodes.pole)});
  if (toe)
    plan.values.push_back({Plug{nodes.foot->reverse_foot, rf::kToeTap, -1},
                           toe_tap_for(g, nodes.foot->reverse_foot, target[2], target[3])});
  return plan;
}

Status match_fk_to_ik(scene::Scene& scene, NodeId limb_meta) {
  return apply(scene, limb_meta, MatchSide::kFk, "match FK to IK");
}

Status match_ik_to_fk(scene::Scene& scene, NodeId limb_meta) {
  return apply(scene, limb_meta, MatchSide::kIk, "match IK to FK");
}

}  // namespace rigel::rig::components
