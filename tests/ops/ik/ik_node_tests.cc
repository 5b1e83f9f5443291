// IK node types in a scene: chains set up by the helpers, targets moved,
// joints' evaluated world matrices against hand-computed answers and against
// the kernels run directly; every validate() failure in `error` with the
// joints at their rest pose; undo of the setup; swept targets without pops.

#include "rigel/ops/ik/nodes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "ik_test_util.h"
#include "rigel/graph/graph.h"
#include "rigel/math/transform.h"
#include "rigel/ops/ik/spline_ik.h"
#include "rigel/ops/ik/two_bone_ik.h"
#include "rigel/ops/registry.h"
#include "rigel/scene/scene.h"
#include "rigel/scene/transform_types.h"

namespace rigel::ops::ik {
namespace {

using graph::NodeId;
using graph::Plug;
using graph::Value;
using scene::Scene;
using testing::kPi;
using testing::position_of;
using testing::vec_near;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// ---- scene helpers -------------------------------------------------------------

Plug plug(const Scene& s, NodeId node, const char* attr, std::int32_t element = -1) {
  Result<Plug> p = s.graph().plug_find(node, attr, element);
  EXPECT_TRUE(p.is_ok()) << attr << ": " << p.status().message();
  return p.is_ok() ? *p : Plug{};
}

void set(Scene& s, NodeId node, const char* attr, Value v, std::int32_t element = -1) {
  const Status st = s.graph().set_value(plug(s, node, attr, element), std::move(v));
  ASSERT_TRUE(st.is_ok()) << attr << ": " << st.message();
}

Value get(Scene& s, NodeId node, const char* attr) {
  Result<Value> v = s.graph().evaluate(plug(s, node, attr));
  EXPECT_TRUE(v.is_ok()) << attr;
  return v.is_ok() ? *v : Value{};
}

std::string error_of(Scene& s, NodeId ik) { return std::get<std::string>(get(s, ik, "error")); }

NodeId make(Scene& s, const char* type, const char* name, NodeId parent = NodeId{}) {
  Result<NodeId> id = s.create(type, name, parent);
  EXPECT_TRUE(id.is_ok()) << id.status().message();
  return id.is_ok() ? *id : NodeId{};
}

Vec3 apply(const Mat4& m, const Vec3& p) { return m.topLeftCorner<3, 3>() * p + m.topRightCorner<3, 1>(); }

struct JointSpec {
  Vec3 position;  // in `space`
  Vec3 orient = Vec3::Zero();
  Vec3 rotate = Vec3::Zero();
  Vec3 rotate_axis = Vec3::Zero();
};

// Joints under `parent`, each placed (through its translate) at
// space * position, with the given orient / rotate / rotateAxis (degrees).
std::vector<NodeId> build_chain(Scene& s, NodeId parent, const Mat4& space, const std::vector<JointSpec>& specs,
                                const std::string& prefix) {
  std::vector<NodeId> joints;
  NodeId up = parent;
  for (std::size_t i = 0; i < specs.size(); ++i) {
    const std::string name = prefix + std::to_string(i);
    const NodeId j = make(s, scene::kJointType, name.c_str(), up);
    set(s, j, "jointOrient", specs[i].orient);
    set(s, j, "rotate", specs[i].rotate);
    set(s, j, "rotateAxis", specs[i].rotate_axis);
    const Mat4 parent_world = up.is_valid() ? s.world_matrix(up) : Mat4(Mat4::Identity());
    set(s, j, "translate", apply(math::affine_inverse(parent_world), apply(space, specs[i].position)));
    joints.push_back(j);
    up = j;
  }
  return joints;
}

std::vector<Mat4> worlds(Scene& s, const std::vector<NodeId>& joints) {
  std::vector<Mat4> out;
  for (NodeId j : joints) out.push_back(s.world_matrix(j));
  return out;
}

::testing::AssertionResult near_mats(const std::vector<Mat4>& a, const std::vector<Mat4>& b, double tol) {
  if (a.size() != b.size()) return ::testing::AssertionFailure() << "sizes " << a.size() << " and " << b.size();
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (!math::is_near(a[i], b[i], tol)) {
      return ::testing::AssertionFailure() << "joint " << i << ":\n" << a[i] << "\n!=\n" << b[i];
    }
  }
  return ::testing::AssertionSuccess();
}

std::vector<Mat4> out_worlds(Scene& s, NodeId ik) { return std::get<std::vector<Mat4>>(get(s, ik, "outWorldMatrices")); }

// ---- registration -----------------------------------------------------------------

TEST(IkNodes, register_ik_types__adds_four_types_with_documented_layout) {
  graph::Registry registry;
  ASSERT_TRUE(register_ik_types(registry).is_ok());
  EXPECT_FALSE(register_ik_types(registry).is_ok()) << "registering twice should fail: names taken";
  const std::vector<std::pair<const char*, graph::AttrIndex>> shared = {
      {"parentMatrix", ik_attr::kParentMatrix},   {"restMatrix", ik_attr::kRestMatrix},
      {"restOffsetParentMatrix", ik_attr::kRestOffsetParentMatrix},
      {"restJointOrient", ik_attr::kRestJointOrient}, {"restRotateAxis", ik_attr::kRestRotateAxis},
      {"weight", ik_attr::kWeight},               {"error", ik_attr::kError},
      {"outRotations", ik_attr::kOutRotations},   {"outTranslations", ik_attr::kOutTranslations},
      {"outScales", ik_attr::kOutScales},         {"outShears", ik_attr::kOutShears},
      {"outWorldMatrices", ik_attr::kOutWorldMatrices}};
  for (const char* type : {kIkTwoBoneType, kIkFabrikType, kIkCcdType, kIkSplineType}) {
    const graph::NodeType* t = registry.find(type);
    ASSERT_NE(t, nullptr) << type;
    for (const auto& [name, index] : shared) EXPECT_EQ(t->attr_find(name), index) << type << "." << name;
    EXPECT_NE(t->attr(ik_attr::kWeight).flags & graph::kKeyable, 0u) << "weight is keyable";
    EXPECT_NE(t->attr(ik_attr::kError).flags & graph::kHidden, 0u) << "error is a hidden output";
  }
  const graph::NodeType& two = *registry.find(kIkTwoBoneType);
  EXPECT_EQ(two.attr_count(), two_bone_attr::kCount + 1u) << "+ metaParent";
  for (const auto& [name, index] :
       std::vector<std::pair<const char*, graph::AttrIndex>>{{"targetMatrix", two_bone_attr::kTargetMatrix},
                                                             {"poleMode", two_bone_attr::kPoleMode},
                                                             {"poleVector", two_bone_attr::kPoleVector},
                                                             {"usePoleMatrix", two_bone_attr::kUsePoleMatrix},
                                                             {"poleMatrix", two_bone_attr::kPoleMatrix},
                                                             {"midAxis", two_bone_attr::kMidAxis},
                                                             {"twist", two_bone_attr::kTwist},
                                                             {"soft", two_bone_attr::kSoft},
                                                             {"stretch", two_bone_attr::kStretch},
                                                             {"maxStretch", two_bone_attr::kMaxStretch},
                                                             {"outStretch", two_bone_attr::kOutStretch},
                                                             {"reached", two_bone_attr::kReached}}) {
    EXPECT_EQ(two.attr_find(name), index) << name;
  }
  for (const char* keyable : {"twist", "soft", "stretch", "maxStretch", "poleVector"}) {
    EXPECT_NE(two.attr(two.attr_find(keyable)).flags & graph::kKeyable, 0u) << keyable << " is keyable";
  }
  for (const char* type : {kIkFabrikType, kIkCcdType}) {
    const graph::NodeType& t = *registry.find(type);
    EXPECT_EQ(t.attr_count(), chain_attr::kCount + 1u);
    for (const auto& [name, index] :
         std::vector<std::pair<const char*, graph::AttrIndex>>{{"targetMatrix", chain_attr::kTargetMatrix},
                                                               {"tolerance", chain_attr::kTolerance},
                                                               {"maxIterations", chain_attr::kMaxIterations},
                                                               {"limitType", chain_attr::kLimitType},
                                                               {"limitAxis", chain_attr::kLimitAxis},
                                                               {"limitReference", chain_attr::kLimitReference},
                                                               {"limitMinAngle", chain_attr::kLimitMinAngle},
                                                               {"limitMaxAngle", chain_attr::kLimitMaxAngle},
                                                               {"limitHalfAngle", chain_attr::kLimitHalfAngle},
                                                               {"iterations", chain_attr::kIterations},
                                                               {"endDistance", chain_attr::kEndDistance},
                                                               {"reached", chain_attr::kReached}}) {
      EXPECT_EQ(t.attr_find(name), index) << type << "." << name;
    }
  }
  const graph::NodeType& spline = *registry.find(kIkSplineType);
  EXPECT_EQ(spline.attr_count(), spline_attr::kCount + 1u);
  for (const auto& [name, index] :
       std::vector<std::pair<const char*, graph::AttrIndex>>{{"controlMatrix", spline_attr::kControlMatrix},
                                                             {"aimAxis", spline_attr::kAimAxis},
                                                             {"upAxis", spline_attr::kUpAxis},
                                                             {"worldUpVector", spline_attr::kWorldUpVector},
                                                             {"startTwist", spline_attr::kStartTwist},
                                                             {"endTwist", spline_attr::kEndTwist},
                                                             {"stretch", spline_attr::kStretch},
                                                             {"squash", spline_attr::kSquash},
                                                             {"arcLengthSamples", spline_attr::kArcLengthSamples},
                                                             {"curveLength", spline_attr::kCurveLength},
                                                             {"chainLength", spline_attr::kChainLength},
                                                             {"overran", spline_attr::kOverran}}) {
    EXPECT_EQ(spline.attr_find(name), index) << name;
  }
  for (const char* type : {kIkTwoBoneType, kIkFabrikType, kIkCcdType, kIkSplineType}) {
    EXPECT_NE(ops::default_registry()->find(type), nullptr) << type << " is in the default registry";
  }
}

// ---- ikTwoBone -----------------------------------------------------------------------

// A leg of bones 1 and 1 under a group at (1, 2, 3) turned 90 degrees about
// z, so group space (x, y, z) is world (1 - y, 2 + x, 3 + z). In group space
// the rest pose is start (0, 0, 0), mid (0.8, -0.6, 0), end (1.6, 0, 0): bent
// in the z = 0 plane, knee toward -y. The joints carry joint orients, rotates
// and a rotate axis, so the outputs must account for them.
struct TwoBoneRig {
  Scene s{ops::default_registry()};
  NodeId group, target, pole, ik;
  std::vector<NodeId> chain;
  Mat4 space;
  std::vector<Mat4> rest;

  explicit TwoBoneRig(bool with_pole = false, const Vec3& group_scale = Vec3::Ones()) {
    group = make(s, scene::kTransformType, "group");
    set(s, group, "translate", Vec3(1, 2, 3));
    set(s, group, "rotate", Vec3(0, 0, 90));
    set(s, group, "scale", group_scale);
    space = s.world_matrix(group);
    chain = build_chain(s, group, space,
                        {{Vec3(0, 0, 0), Vec3(0, 0, -36.87), Vec3(10, 0, 0)},
                         {Vec3(0.8, -0.6, 0), Vec3(0, 0, 73.74), Vec3(0, 0, 5), Vec3(0, 20, 0)},
                         {Vec3(1.6, 0, 0), Vec3(5, 5, 5)}},
                        "leg");
    target = make(s, scene::kLocatorType, "target");
    move_target(Vec3(1.6, 0, 0));
    if (with_pole) {
      pole = make(s, scene::kLocatorType, "pole");
      set(s, pole, "translate", world(Vec3(0.8, -2, 0)));
    }
    rest = worlds(s, chain);
    Result<NodeId> id = setup_two_bone_ik(s, chain, target, pole);
    EXPECT_TRUE(id.is_ok()) << id.status().message();
    ik = id.is_ok() ? *id : NodeId{};
  }
  Vec3 world(const Vec3& local) const { return apply(space, local); }
  void move_target(const Vec3& local) { set(s, target, "translate", world(local)); }
  Vec3 joint(std::size_t i) { return position_of(s.world_matrix(chain[i])); }
};

TEST(IkTwoBoneNode, setup__at_rest_target_keeps_rest_pose) {
  TwoBoneRig rig;
  EXPECT_EQ(error_of(rig.s, rig.ik), "");
  EXPECT_TRUE(near_mats(worlds(rig.s, rig.chain), rig.rest, 1e-9))
      << "with the target on the end joint, the solve is the rest pose";
  for (NodeId j : rig.chain) {
    EXPECT_EQ(std::get<std::int64_t>(rig.s.graph().node(j)->value(scene::xform::kRotateMode)), j == rig.chain[2] ? 0 : 1)
        << "start and mid switch to quaternion mode; the end's rotation is left alone";
  }
}

TEST(IkTwoBoneNode, reach__target_at_sqrt2_puts_elbow_at_right_angle) {
  TwoBoneRig rig;
  rig.move_target(Vec3(1, 1, 0));
  // |start - target| = sqrt(2) with bones 1 and 1: the elbow is at a right
  // angle, at (1, 0, 0) or (0, 1, 0); the pole (the rest bend, -y side of
  // the start-target line) picks (1, 0, 0).
  EXPECT_TRUE(vec_near(rig.joint(0), rig.world(Vec3(0, 0, 0)), 1e-12)) << "the start joint does not move";
  EXPECT_TRUE(vec_near(rig.joint(1), rig.world(Vec3(1, 0, 0)), 1e-9));
  EXPECT_TRUE(vec_near(rig.joint(2), rig.world(Vec3(1, 1, 0)), 1e-9));
  EXPECT_TRUE(vec_near(rig.joint(2), Vec3(0, 3, 3), 1e-9)) << "world (0, 3, 3) by hand";
  EXPECT_TRUE(std::get<bool>(get(rig.s, rig.ik, "reached")));
  const std::vector<Mat4> now = worlds(rig.s, rig.chain);
  EXPECT_LE(testing::bone_length_error(rig.rest, now), 1e-9) << "bone lengths are kept";
  EXPECT_TRUE(near_mats(now, out_worlds(rig.s, rig.ik), 1e-12)) << "outWorldMatrices is what the joints evaluate to";
}

// Under a non-uniformly scaled parent the solve turns the joints in world
// space, so the bones stay rigid and the end lands on the target (the
// joints take the shear that needs); turning them in their own frames
// instead missed by the parent's non-uniformity, ~1e-6 on joints from
// single-precision files, 5e-2 here.
TEST(IkTwoBoneNode, under_a_non_uniformly_scaled_parent_the_bones_stay_rigid_and_reach) {
  TwoBoneRig rig(true, Vec3(1.0, 1.25, 0.8));
  for (const Vec3& at : {Vec3(1.2, 0.5, 0.3), Vec3(0.4, 1.0, -0.6), Vec3(1.5, -0.2, 0.1)}) {
    rig.move_target(at);
    const std::vector<Mat4> now = worlds(rig.s, rig.chain);
    EXPECT_TRUE(vec_near(rig.joint(2), rig.world(at), 1e-12)) << "the end on the target";
    EXPECT_LE(testing::bone_length_error(rig.rest, now), 1e-12) << "bone lengths are kept";
    EXPECT_TRUE(near_mats(now, out_worlds(rig.s, rig.ik), 1e-12)) << "outWorldMatrices is what the joints evaluate to";
    // The joints' orientations are the rest ones turned rigidly: the
    // start's by one rotation, the mid's and the end's by another.
    for (std::size_t i = 0; i < 3; ++i) {
      const math::Mat3 turn = now[i].topLeftCorner<3, 3>() * rig.rest[i].topLeftCorner<3, 3>().inverse();
      EXPECT_LE((turn * turn.transpose() - math::Mat3::Identity()).cwiseAbs().maxCoeff(), 1e-12) << "joint " << i;
    }
  }
}

TEST(IkTwoBoneNode, joints_match_the_kernel_solved_directly) {
  TwoBoneRig rig;
  rig.move_target(Vec3(0.7, 0.9, 0.4));
  set(rig.s, rig.ik, "twist", 25.0);
  set(rig.s, rig.ik, "soft", 0.1);
  // The kernel on the rest world matrices, through the one correction path.
  TwoBoneIkJob job;
  TwoBoneIkOutput out;
  job.start_world = &rig.rest[0];
  job.mid_world = &rig.rest[1];
  job.end_world = &rig.rest[2];
  job.target = rig.world(Vec3(0.7, 0.9, 0.4));
  job.pole_vector = std::get<Vec3>(get(rig.s, rig.ik, "poleVector"));
  job.mid_axis = std::get<Vec3>(get(rig.s, rig.ik, "midAxis"));
  job.twist_angle = 25.0 * math::kDegToRad;
  job.soft = 0.1;
  job.output = &out;
  ASSERT_TRUE(job.run());
  const std::vector<Mat4> expected = testing::apply_corrections(
      rig.rest, {out.start_correction, out.mid_correction, Quat::Identity()}, {1, out.stretch, out.stretch}, rig.space);
  EXPECT_TRUE(near_mats(worlds(rig.s, rig.chain), expected, 1e-9))
      << "rotateQuaternion outputs reproduce the kernel's pose through joint orient, rotate axis and the parent";
}

// At full extension the law of cosines gives cos(gamma) a few ulps below 1;
// the kernel snaps that to 1 (two_bone_ik.cc), otherwise sqrt(1 - c^2) would
// put the knee ~1.5e-8 off the line. Straight chains are checked tightly.
constexpr double kStraight = 1e-12;

TEST(IkTwoBoneNode, out_of_reach__points_straight_at_target) {
  TwoBoneRig rig;
  rig.move_target(Vec3(3, 0, 0));
  EXPECT_TRUE(vec_near(rig.joint(1), rig.world(Vec3(1, 0, 0)), kStraight));
  EXPECT_TRUE(vec_near(rig.joint(2), rig.world(Vec3(2, 0, 0)), 1e-9)) << "the end on the line, 2 from the start";
  EXPECT_FALSE(std::get<bool>(get(rig.s, rig.ik, "reached")));
  EXPECT_LE(testing::bone_length_error(rig.rest, worlds(rig.s, rig.chain)), 1e-9);
  rig.move_target(Vec3(0, 0, -5));
  EXPECT_TRUE(vec_near(rig.joint(1), rig.world(Vec3(0, 0, -1)), kStraight));
  EXPECT_TRUE(vec_near(rig.joint(2), rig.world(Vec3(0, 0, -2)), 1e-9));
}

TEST(IkTwoBoneNode, stretch__lengthens_bones_up_to_max_stretch) {
  TwoBoneRig rig;
  rig.move_target(Vec3(3, 0, 0));
  set(rig.s, rig.ik, "stretch", true);
  EXPECT_TRUE(vec_near(rig.joint(1), rig.world(Vec3(1.5, 0, 0)), kStraight)) << "both bones x 1.5";
  EXPECT_TRUE(vec_near(rig.joint(2), rig.world(Vec3(3, 0, 0)), 1e-9)) << "the end reaches the target";
  EXPECT_NEAR(std::get<double>(get(rig.s, rig.ik, "outStretch")), 1.5, 1e-12);
  set(rig.s, rig.ik, "maxStretch", 1.25);
  EXPECT_TRUE(vec_near(rig.joint(1), rig.world(Vec3(1.25, 0, 0)), kStraight));
  EXPECT_TRUE(vec_near(rig.joint(2), rig.world(Vec3(2.5, 0, 0)), 1e-9)) << "limited to 1.25";
  rig.move_target(Vec3(1, 1, 0));
  EXPECT_TRUE(vec_near(rig.joint(2), rig.world(Vec3(1, 1, 0)), 1e-9)) << "within reach: no stretch";
  EXPECT_NEAR(std::get<double>(get(rig.s, rig.ik, "outStretch")), 1.0, 0.0);
}

TEST(IkTwoBoneNode, soft__eases_reach_near_full_extension) {
  TwoBoneRig rig;
  set(rig.s, rig.ik, "soft", 0.2);
  rig.move_target(Vec3(2, 0, 0));
  // L = 2, ds = 0.4, da = 1.6, d = 2: reach = 1.6 + 0.4 (1 - e^-1).
  const double reach = 1.6 + 0.4 * (1.0 - std::exp(-1.0));
  EXPECT_TRUE(vec_near(rig.joint(2), rig.world(Vec3(reach, 0, 0)), 1e-9));
  EXPECT_FALSE(std::get<bool>(get(rig.s, rig.ik, "reached")));
}

TEST(IkTwoBoneNode, twist__turns_chain_about_start_to_target) {
  TwoBoneRig rig;
  rig.move_target(Vec3(1, 1, 0));
  set(rig.s, rig.ik, "twist", 90.0);
  // (1, 0, 0) turned 90 degrees about (1, 1, 0) / sqrt(2), right-handed.
  EXPECT_TRUE(vec_near(rig.joint(1), rig.world(Vec3(0.5, 0.5, -std::sqrt(0.5))), 1e-9));
  EXPECT_TRUE(vec_near(rig.joint(2), rig.world(Vec3(1, 1, 0)), 1e-9)) << "the end stays on the target";
}

TEST(IkTwoBoneNode, pole__object_and_plane_normal_choose_the_knee_side) {
  TwoBoneRig rig(/*with_pole=*/true);
  EXPECT_TRUE(std::get<bool>(get(rig.s, rig.ik, "usePoleMatrix")));
  rig.move_target(Vec3(1, 1, 0));
  EXPECT_TRUE(vec_near(rig.joint(1), rig.world(Vec3(1, 0, 0)), 1e-9)) << "pole on the -y side";
  set(rig.s, rig.pole, "translate", rig.world(Vec3(-1, 1, 0)));
  EXPECT_TRUE(vec_near(rig.joint(1), rig.world(Vec3(0, 1, 0)), 1e-9)) << "pole on the other side: the knee follows";
  EXPECT_TRUE(vec_near(rig.joint(2), rig.world(Vec3(1, 1, 0)), 1e-9));
  set(rig.s, rig.pole, "translate", Vec3(0, kNaN, 0));
  EXPECT_NE(error_of(rig.s, rig.ik).find("poleMatrix"), std::string::npos)
      << "a pole object that is not finite: " << error_of(rig.s, rig.ik);
  EXPECT_TRUE(near_mats(worlds(rig.s, rig.chain), rig.rest, 1e-9)) << "the rest pose meanwhile";

  // Plane normal: the hinge (+z in group space at rest) along poleVector,
  // the knee along cross(start-to-target, normal).
  set(rig.s, rig.ik, "usePoleMatrix", false);
  set(rig.s, rig.ik, "poleMode", std::int64_t{1});
  set(rig.s, rig.ik, "poleVector", Vec3(0, 0, 1));
  EXPECT_TRUE(vec_near(rig.joint(1), rig.world(Vec3(1, 0, 0)), 1e-9));
  set(rig.s, rig.ik, "poleVector", Vec3(0, 0, -1));
  EXPECT_TRUE(vec_near(rig.joint(1), rig.world(Vec3(0, 1, 0)), 1e-9));
  EXPECT_FALSE(rig.s.graph().set_value(plug(rig.s, rig.ik, "poleMode"), std::int64_t{2}).is_ok())
      << "poleMode stays one of its names (TwoBoneIkJob's invalid pole_mode cannot arise from a node)";
}

TEST(IkTwoBoneNode, weight__blends_from_rest) {
  TwoBoneRig rig;
  rig.move_target(Vec3(1, 1, 0));
  set(rig.s, rig.ik, "weight", 0.0);
  EXPECT_TRUE(near_mats(worlds(rig.s, rig.chain), rig.rest, 1e-9)) << "weight 0: the rest pose";
  set(rig.s, rig.ik, "weight", 1.0);
  const double full = testing::angle_between(testing::frame_of(rig.rest[0]), testing::frame_of(rig.s.world_matrix(rig.chain[0])));
  ASSERT_GT(full, 0.1) << "the solve turns the start joint";
  set(rig.s, rig.ik, "weight", 0.5);
  const double half = testing::angle_between(testing::frame_of(rig.rest[0]), testing::frame_of(rig.s.world_matrix(rig.chain[0])));
  EXPECT_NEAR(half, 0.5 * full, 1e-9) << "weight 0.5: the start joint turns half way (slerp)";
}

TEST(IkTwoBoneNode, swept_target__continuous_rotations_across_pole_plane) {
  TwoBoneRig rig;
  // A circle about the start in the group's x-z plane: it crosses the plane
  // of the pole (z = 0) twice, at x = 1.5 and x = -1.5.
  std::vector<Mat4> previous;
  std::vector<Quat> previous_q;
  double worst_turn = 0.0, worst_q = 0.0;
  const int steps = 240;
  for (int k = 0; k <= steps; ++k) {
    const double a = 2.0 * kPi * k / steps;
    rig.move_target(Vec3(1.5 * std::cos(a), 0.2, 1.5 * std::sin(a)));
    const std::vector<Mat4> now = worlds(rig.s, rig.chain);
    const auto q = std::get<std::vector<Quat>>(get(rig.s, rig.ik, "outRotations"));
    ASSERT_TRUE(vec_near(position_of(now[2]), rig.world(Vec3(1.5 * std::cos(a), 0.2, 1.5 * std::sin(a))), 1e-9));
    if (!previous.empty()) {
      worst_turn = std::max(worst_turn, testing::largest_turn(previous, now));
      for (std::size_t i = 0; i < q.size(); ++i) worst_q = std::max(worst_q, (q[i].coeffs() - previous_q[i].coeffs()).norm());
    }
    previous = now;
    previous_q = q;
  }
  // The target steps 2 pi 1.5 / 240 = 0.039 per frame at ~1.5 from the start.
  EXPECT_LT(worst_turn, 0.1) << "no joint pops (a flip would turn ~pi)";
  EXPECT_LT(worst_q, 0.1) << "outRotations are continuous, sign included";
}

TEST(IkTwoBoneNode, validate_failures__surface_in_error_and_keep_rest_pose) {
  TwoBoneRig rig;
  rig.move_target(Vec3(1, 1, 0));
  ASSERT_EQ(error_of(rig.s, rig.ik), "");
  Scene& s = rig.s;
  const NodeId ik = rig.ik;
  auto expect_failure = [&](const char* attr, const std::string& why, bool check_out_worlds = true) {
    const std::string error = error_of(s, ik);
    EXPECT_NE(error.find(attr), std::string::npos) << why << ": error was '" << error << "'";
    EXPECT_TRUE(near_mats(worlds(s, rig.chain), rig.rest, 1e-9)) << why << ": the joints fall back to the rest pose";
    if (check_out_worlds) {
      EXPECT_TRUE(near_mats(out_worlds(s, ik), rig.rest, 1e-9)) << why;
    }
    EXPECT_FALSE(std::get<bool>(get(s, ik, "reached"))) << why;
  };
  auto expect_recovered = [&](const std::string& why) {
    EXPECT_EQ(error_of(s, ik), "") << why;
    EXPECT_TRUE(vec_near(rig.joint(1), rig.world(Vec3(1, 0, 0)), 1e-9)) << why << ": solves again";
  };

  // Target not finite (the locator's translation).
  set(s, rig.target, "translate", Vec3(kNaN, 0, 0));
  expect_failure("targetMatrix", "a NaN target");
  rig.move_target(Vec3(1, 1, 0));
  expect_recovered("target fixed");

  // Pole vector not finite.
  const Vec3 pole = std::get<Vec3>(get(s, ik, "poleVector"));
  set(s, ik, "poleVector", Vec3(0, kInf, 0));
  expect_failure("poleVector", "an infinite pole vector");
  set(s, ik, "poleVector", pole);
  expect_recovered("pole fixed");

  // mid_axis not a unit vector.
  const Vec3 axis = std::get<Vec3>(get(s, ik, "midAxis"));
  set(s, ik, "midAxis", Vec3(axis * 2.0));
  expect_failure("midAxis", "a hinge axis of length 2");
  set(s, ik, "midAxis", axis);
  expect_recovered("axis fixed");

  // Twist not finite.
  set(s, ik, "twist", kInf);
  expect_failure("twist", "an infinite twist");
  set(s, ik, "twist", 0.0);

  // Soft and weight outside [0, 1], NaN included.
  for (double bad : {-0.1, 1.5, kNaN}) {
    set(s, ik, "soft", bad);
    expect_failure("soft", "soft " + std::to_string(bad));
  }
  set(s, ik, "soft", 0.0);
  for (double bad : {-0.1, 1.5, kNaN}) {
    set(s, ik, "weight", bad);
    expect_failure("weight", "weight " + std::to_string(bad));
  }
  set(s, ik, "weight", 1.0);
  expect_recovered("soft and weight fixed");

  // Stretch on with max_stretch below 1 (or NaN); off, it is not looked at.
  set(s, ik, "maxStretch", 0.5);
  expect_recovered("max stretch is ignored while stretch is off");
  set(s, ik, "stretch", true);
  expect_failure("maxStretch", "max stretch 0.5");
  set(s, ik, "maxStretch", kNaN);
  expect_failure("maxStretch", "max stretch NaN");
  set(s, ik, "maxStretch", kInf);
  expect_recovered("infinite max stretch: no limit");
  set(s, ik, "stretch", false);

  // World matrices not affine: the rest data and the parent space.
  const auto rest = std::get<std::vector<Mat4>>(get(s, ik, "restMatrix"));
  Mat4 projective = rest[1];
  projective(3, 0) = 0.5;
  set(s, ik, "restMatrix", projective, 1);
  expect_failure("restMatrix[1]", "a projective rest matrix");
  set(s, ik, "restMatrix", rest);
  expect_recovered("rest fixed");
  ASSERT_TRUE(s.graph().disconnect_input(plug(s, ik, "parentMatrix")).is_ok());
  Mat4 parent = rig.space;
  parent(3, 2) = 1.0;
  set(s, ik, "parentMatrix", parent);
  expect_failure("parentMatrix", "a projective parent matrix", /*check_out_worlds=*/false);
  set(s, ik, "parentMatrix", rig.space);
  expect_recovered("parent fixed");

  // Node-level checks: a singular offset parent matrix, the wrong joint count.
  Mat4 flat = Mat4::Identity();
  flat(2, 2) = 0.0;
  set(s, ik, "restOffsetParentMatrix", flat, 2);
  expect_failure("restOffsetParentMatrix[2]", "a singular offset parent matrix", /*check_out_worlds=*/false);
  set(s, ik, "restOffsetParentMatrix", std::vector<Mat4>{});
  expect_recovered("offset parent matrices missing: identity");
  std::vector<Mat4> four = rest;
  four.push_back(Mat4::Identity());
  set(s, ik, "restMatrix", four);
  EXPECT_NE(error_of(s, ik).find("exactly 3"), std::string::npos) << error_of(s, ik);
  EXPECT_TRUE(near_mats(worlds(s, rig.chain), rig.rest, 1e-9)) << "four joints: the three driven keep their rest";
  set(s, ik, "restMatrix", rest);
  expect_recovered("three joints again");
}

// ---- helpers: refusals, undo ------------------------------------------------------

TEST(IkSetup, refuses_bad_chains_and_leaves_scene_unchanged) {
  Scene s(ops::default_registry());
  const std::vector<NodeId> chain =
      build_chain(s, NodeId{}, Mat4::Identity(), {{Vec3(0, 0, 0)}, {Vec3(1, 0, 0)}, {Vec3(2, 0, 0)}}, "j");
  const NodeId target = make(s, scene::kLocatorType, "target");
  const NodeId below = make(s, scene::kLocatorType, "below", chain[2]);
  const NodeId other = make(s, scene::kJointType, "other");
  const std::size_t nodes = s.graph().node_count();
  const std::size_t steps = s.graph().undo_count();
  auto unchanged = [&](const char* why) {
    EXPECT_EQ(s.graph().node_count(), nodes) << why;
    EXPECT_EQ(s.graph().undo_count(), steps) << why << ": a failed setup leaves no undo step";
    for (NodeId j : chain) EXPECT_EQ(std::get<std::int64_t>(s.graph().node(j)->value(scene::xform::kRotateMode)), 0) << why;
  };

  Result<NodeId> r = setup_two_bone_ik(s, chain, target);
  EXPECT_FALSE(r.is_ok()) << "a straight chain with no pole has no bend plane";
  EXPECT_NE(r.status().message().find("straight"), std::string::npos) << r.status().message();
  unchanged("straight chain");

  TwoBoneIkOptions with_pole;
  with_pole.pole_vector = Vec3(0, 1, 0);
  r = setup_two_bone_ik(s, chain, below, NodeId{}, with_pole);
  EXPECT_FALSE(r.is_ok()) << "a target below the chain would close a cycle";
  EXPECT_EQ(r.status().code(), ErrorCode::kCycle) << r.status().message();
  unchanged("cycle");

  const std::vector<NodeId> broken = {chain[0], other, chain[2]};
  r = setup_fabrik_ik(s, broken, target);
  EXPECT_FALSE(r.is_ok()) << "joints that are not parent and child";
  unchanged("not a chain");

  r = setup_ccd_ik(s, std::vector<NodeId>{chain[0]}, target);
  EXPECT_FALSE(r.is_ok()) << "one joint is no chain";
  unchanged("one joint");

  set(s, chain[1], "rotatePivot", Vec3(0.1, 0, 0));
  const std::size_t steps_after_pivot = s.graph().undo_count();
  r = setup_ccd_ik(s, chain, target);
  EXPECT_FALSE(r.is_ok()) << "pivots are refused";
  EXPECT_NE(r.status().message().find("rotatePivot"), std::string::npos) << r.status().message();
  EXPECT_EQ(s.graph().undo_count(), steps_after_pivot);
}

TEST(IkSetup, undo_removes_everything_and_redo_restores_it) {
  TwoBoneRig rig;
  rig.move_target(Vec3(1, 1, 0));
  Scene& s = rig.s;
  graph::Graph& g = s.graph();
  const std::vector<Mat4> solved = worlds(s, rig.chain);
  const std::size_t nodes = g.node_count();
  const std::size_t connections = g.connections().size();
  // Undo the target move, then the setup.
  ASSERT_TRUE(g.undo());
  ASSERT_EQ(g.undo_label(), std::string("setup ") + kIkTwoBoneType) << "the setup is one undo step";
  ASSERT_TRUE(g.undo());
  EXPECT_EQ(g.node_count(), nodes - 1) << "the IK node is gone";
  EXPECT_EQ(g.connections().size(), connections - 10)
      << "its 10 connections are gone (parent, target, 2 rotations, 2 translations, 2 scales, 2 shears)";
  for (NodeId j : rig.chain) {
    EXPECT_EQ(std::get<std::int64_t>(g.node(j)->value(scene::xform::kRotateMode)), 0) << "back to euler";
  }
  EXPECT_TRUE(near_mats(worlds(s, rig.chain), rig.rest, 1e-12)) << "the joints are where they were";
  ASSERT_TRUE(g.redo());
  ASSERT_TRUE(g.redo());
  EXPECT_EQ(g.node_count(), nodes);
  EXPECT_TRUE(near_mats(worlds(s, rig.chain), solved, 1e-12)) << "redo: the IK solves again";
}

TEST(IkSetup, solver_cannot_read_its_own_joints) {
  TwoBoneRig rig;
  EXPECT_FALSE(rig.s.graph().connect(plug(rig.s, rig.chain[2], "worldMatrix"), plug(rig.s, rig.ik, "poleMatrix")).is_ok())
      << "the graph refuses a node-level cycle";
}

// ---- ikFabrik / ikCcd -------------------------------------------------------------------

// Bones of length 1 under a group at (0, 0, 5) turned 90 degrees about y, so
// group space (x, y, z) is world (z, y, 5 - x). Rest in group space: a
// zig-zag in z = 0 (knees toward -y).
struct ChainRig {
  // Converged far below the tests' tolerances.
  static ChainIkOptions tight() {
    ChainIkOptions o;
    o.tolerance = 1e-12;
    o.max_iterations = 1000;
    return o;
  }
  Scene s{ops::default_registry()};
  NodeId group, target, ik;
  std::vector<NodeId> chain;
  Mat4 space;
  std::vector<Mat4> rest;

  ChainRig(const char* type, std::size_t joints, const ChainIkOptions& options = tight()) {
    group = make(s, scene::kTransformType, "group");
    set(s, group, "translate", Vec3(0, 0, 5));
    set(s, group, "rotate", Vec3(0, 90, 0));
    space = s.world_matrix(group);
    std::vector<JointSpec> specs;
    for (std::size_t i = 0; i < joints; ++i) {
      specs.push_back({Vec3(0.8 * static_cast<double>(i), i % 2 ? -0.6 : 0.0, 0), Vec3(0, 0, 7.0 * i), Vec3(3, 0, 0)});
    }
    chain = build_chain(s, group, space, specs, "j");
    target = make(s, scene::kLocatorType, "target");
    move_target(specs.back().position);
    rest = worlds(s, chain);
    Result<NodeId> id = std::string(type) == kIkFabrikType ? setup_fabrik_ik(s, chain, target, options)
                                                           : setup_ccd_ik(s, chain, target, options);
    EXPECT_TRUE(id.is_ok()) << id.status().message();
    ik = id.is_ok() ? *id : NodeId{};
  }
  Vec3 world(const Vec3& local) const { return apply(space, local); }
  void move_target(const Vec3& local) { set(s, target, "translate", world(local)); }
  Vec3 joint(std::size_t i) { return position_of(s.world_matrix(chain[i])); }
};

class IkChainNode : public ::testing::TestWithParam<const char*> {};

TEST_P(IkChainNode, reach__two_bones_to_sqrt2_elbow_at_right_angle) {
  ChainRig rig(GetParam(), 3);
  rig.move_target(Vec3(1, 1, 0));
  // As for the two-bone node: the rest bend (-y side) picks elbow (1, 0, 0).
  EXPECT_TRUE(vec_near(rig.joint(0), rig.world(Vec3::Zero()), 1e-12));
  EXPECT_TRUE(vec_near(rig.joint(1), rig.world(Vec3(1, 0, 0)), 1e-6));
  EXPECT_TRUE(vec_near(rig.joint(2), rig.world(Vec3(1, 1, 0)), 1e-9));
  EXPECT_TRUE(std::get<bool>(get(rig.s, rig.ik, "reached")));
  EXPECT_LE(std::get<double>(get(rig.s, rig.ik, "endDistance")), 1e-12);
  EXPECT_GT(std::get<std::int64_t>(get(rig.s, rig.ik, "iterations")), 0);
  EXPECT_LE(testing::bone_length_error(rig.rest, worlds(rig.s, rig.chain)), 1e-9);
  EXPECT_TRUE(near_mats(worlds(rig.s, rig.chain), out_worlds(rig.s, rig.ik), 1e-12));
}

TEST_P(IkChainNode, out_of_reach__chain_lies_straight_at_target) {
  ChainRig rig(GetParam(), 4);
  rig.move_target(Vec3(0, 4, 3));  // distance 5, chain length 3
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_TRUE(vec_near(rig.joint(i), rig.world(Vec3(0, 0.8, 0.6) * static_cast<double>(i)), 1e-9)) << "joint " << i;
  }
  EXPECT_FALSE(std::get<bool>(get(rig.s, rig.ik, "reached")));
  EXPECT_NEAR(std::get<double>(get(rig.s, rig.ik, "endDistance")), 2.0, 1e-9);
  EXPECT_EQ(std::get<std::int64_t>(get(rig.s, rig.ik, "iterations")), 0) << "closed form";
}

TEST_P(IkChainNode, reach__four_joints_keep_lengths_and_hit_target) {
  ChainRig rig(GetParam(), 4);
  for (const Vec3& t : {Vec3(1, 1.5, 0.5), Vec3(-0.5, 1, 1), Vec3(2, -1, 0.3)}) {
    rig.move_target(t);
    EXPECT_TRUE(vec_near(rig.joint(3), rig.world(t), 1e-9)) << "reached within tolerance";
    EXPECT_LE(testing::bone_length_error(rig.rest, worlds(rig.s, rig.chain)), 1e-9);
    EXPECT_TRUE(vec_near(rig.joint(0), rig.world(Vec3::Zero()), 1e-12));
  }
}

TEST_P(IkChainNode, hinge_limit__locks_root_bone_and_second_bone_reaches) {
  ChainIkOptions options = ChainRig::tight();
  JointLimit locked;  // the root bone along the group's +x: hinge about z, range [0, 0]
  locked.kind = LimitKind::kHinge;
  locked.min_angle = 0.0;
  locked.max_angle = 0.0;
  options.limits = {locked, JointLimit{}, JointLimit{}};
  ChainRig rig(GetParam(), 3, options);
  EXPECT_EQ(std::get<std::vector<std::int64_t>>(get(rig.s, rig.ik, "limitType")),
            (std::vector<std::int64_t>{1, 0, 0}));
  rig.move_target(Vec3(1, 0.6, 0.8));
  EXPECT_EQ(error_of(rig.s, rig.ik), "");
  EXPECT_TRUE(vec_near(rig.joint(1), rig.world(Vec3(1, 0, 0)), 1e-9)) << "the root bone stays on +x";
  EXPECT_TRUE(vec_near(rig.joint(2), rig.world(Vec3(1, 0.6, 0.8)), 1e-9)) << "the free bone reaches the target";
}

TEST_P(IkChainNode, weight__zero_is_rest_half_is_half_turn) {
  ChainRig rig(GetParam(), 4);
  rig.move_target(Vec3(1, 1.5, 0.5));
  const double full = testing::angle_between(testing::frame_of(rig.rest[0]), testing::frame_of(rig.s.world_matrix(rig.chain[0])));
  ASSERT_GT(full, 0.1) << "the solve turns the start joint";
  set(rig.s, rig.ik, "weight", 0.5);
  const double half = testing::angle_between(testing::frame_of(rig.rest[0]), testing::frame_of(rig.s.world_matrix(rig.chain[0])));
  EXPECT_NEAR(half, 0.5 * full, 1e-9);
  set(rig.s, rig.ik, "weight", 0.0);
  EXPECT_TRUE(near_mats(worlds(rig.s, rig.chain), rig.rest, 1e-9));
}

TEST_P(IkChainNode, validate_failures__surface_in_error_and_keep_rest_pose) {
  ChainRig rig(GetParam(), 4);
  rig.move_target(Vec3(1, 1.5, 0.5));
  Scene& s = rig.s;
  const NodeId ik = rig.ik;
  ASSERT_EQ(error_of(s, ik), "");
  auto expect_failure = [&](const std::string& attr, const std::string& why) {
    const std::string error = error_of(s, ik);
    EXPECT_NE(error.find(attr), std::string::npos) << why << ": error was '" << error << "'";
    EXPECT_TRUE(near_mats(worlds(s, rig.chain), rig.rest, 1e-9)) << why << ": rest pose";
    EXPECT_EQ(std::get<std::int64_t>(get(s, ik, "iterations")), 0) << why;
  };
  auto expect_ok = [&](const std::string& why) {
    EXPECT_EQ(error_of(s, ik), "") << why;
    EXPECT_TRUE(vec_near(rig.joint(3), rig.world(Vec3(1, 1.5, 0.5)), 1e-9)) << why;
  };
  auto expect_no_error = [&](const std::string& why) { EXPECT_EQ(error_of(s, ik), "") << why; };

  // Fewer than 2 joints.
  const auto rest = std::get<std::vector<Mat4>>(get(s, ik, "restMatrix"));
  set(s, ik, "restMatrix", std::vector<Mat4>{rest[0]});
  EXPECT_NE(error_of(s, ik).find("restMatrix"), std::string::npos) << "one joint";
  set(s, ik, "restMatrix", rest);
  expect_ok("four joints again");

  // A world matrix not affine.
  Mat4 projective = rest[2];
  projective(3, 1) = 0.25;
  set(s, ik, "restMatrix", projective, 2);
  expect_failure("restMatrix[2]", "projective rest");
  set(s, ik, "restMatrix", rest);

  // Target not finite.
  set(s, rig.target, "translate", Vec3(0, kInf, 0));
  expect_failure("targetMatrix", "infinite target");
  rig.move_target(Vec3(1, 1.5, 0.5));

  // Tolerance negative or not finite; max_iterations negative.
  for (double bad : {-1e-6, kNaN, kInf}) {
    set(s, ik, "tolerance", bad);
    expect_failure("tolerance", "tolerance " + std::to_string(bad));
  }
  set(s, ik, "tolerance", 1e-12);
  set(s, ik, "maxIterations", std::int64_t{-1});
  expect_failure("maxIterations", "negative iterations");
  set(s, ik, "maxIterations", std::int64_t{1000});
  expect_ok("tolerance and iterations fixed");

  // Weight outside [0, 1].
  set(s, ik, "weight", 1.01);
  expect_failure("weight", "weight 1.01");
  set(s, ik, "weight", 1.0);

  // Each joint_limit_error() failure, on joint 1 (hinge or cone), and on the
  // last joint (ignored by the solve, but validate() checks every limit).
  set(s, ik, "limitType", std::vector<std::int64_t>{0, 1, 0, 0});
  expect_no_error("a valid default hinge on joint 1 (full range)");
  set(s, ik, "limitAxis", std::vector<Vec3>{Vec3::UnitZ(), Vec3(0, 0, 1.1)});
  expect_failure("limitAxis[1]", "hinge axis not unit");
  set(s, ik, "limitAxis", std::vector<Vec3>{});
  set(s, ik, "limitReference", std::vector<Vec3>{Vec3::UnitX(), Vec3(0.5, 0, 0)});
  expect_failure("limitReference[1]", "hinge reference not unit");
  set(s, ik, "limitReference", std::vector<Vec3>{Vec3::UnitX(), Vec3(0.6, 0, 0.8)});
  expect_failure("limitReference[1]", "hinge reference not perpendicular to the axis");
  set(s, ik, "limitReference", std::vector<Vec3>{});
  set(s, ik, "limitMinAngle", std::vector<double>{0, 30});
  set(s, ik, "limitMaxAngle", std::vector<double>{0, 10});
  expect_failure("limitMinAngle[1]", "min > max");
  set(s, ik, "limitMinAngle", std::vector<double>{0, -190});
  set(s, ik, "limitMaxAngle", std::vector<double>{0, 10});
  expect_failure("limitMinAngle[1]", "min < -180");
  set(s, ik, "limitMinAngle", std::vector<double>{0, -180});
  set(s, ik, "limitMaxAngle", std::vector<double>{0, 180});
  expect_no_error("the full range in degrees maps into [-pi, pi] exactly");
  set(s, ik, "limitType", std::vector<std::int64_t>{0, 2, 0, 0});
  set(s, ik, "limitAxis", std::vector<Vec3>{Vec3::UnitZ(), Vec3(0, 0, 0)});
  expect_failure("limitAxis[1]", "cone axis zero");
  set(s, ik, "limitAxis", std::vector<Vec3>{});
  set(s, ik, "limitHalfAngle", std::vector<double>{0, 181});
  expect_failure("limitHalfAngle[1]", "cone half angle > 180");
  set(s, ik, "limitHalfAngle", std::vector<double>{0, kNaN});
  expect_failure("limitHalfAngle[1]", "cone half angle NaN");
  set(s, ik, "limitHalfAngle", std::vector<double>{});
  set(s, ik, "limitType", std::vector<std::int64_t>{0, 0, 0, 2});
  set(s, ik, "limitHalfAngle", std::vector<double>{0, 0, 0, -5});
  expect_failure("limitHalfAngle[3]", "an invalid limit on the end joint");
  set(s, ik, "limitType", std::vector<std::int64_t>{});
  expect_ok("no limits");
  EXPECT_FALSE(s.graph().set_value(plug(s, ik, "limitType"), std::vector<std::int64_t>{0, 3}).is_ok())
      << "limitType stays one of its names (an unknown LimitKind cannot arise from a node)";
}

TEST_P(IkChainNode, swept_target__continuous_rotations) {
  ChainRig rig(GetParam(), 4);
  // An arc of reachable targets around the root, out of the rest plane and
  // back through it.
  std::vector<Mat4> previous;
  double worst = 0.0;
  const int steps = 120;
  for (int k = 0; k <= steps; ++k) {
    const double a = -0.8 + 1.6 * k / steps;
    const Vec3 t(2.0 * std::cos(a), 0.5, 2.0 * std::sin(a));
    rig.move_target(t);
    const std::vector<Mat4> now = worlds(rig.s, rig.chain);
    ASSERT_TRUE(vec_near(position_of(now[3]), rig.world(t), 1e-9)) << "step " << k;
    if (!previous.empty()) worst = std::max(worst, testing::largest_turn(previous, now));
    previous = now;
  }
  // The target moves 2 * 1.6 / 120 = 0.027 per step at ~2 from the root.
  EXPECT_LT(worst, 0.1) << "no joint pops along the path";
}

INSTANTIATE_TEST_SUITE_P(Solvers, IkChainNode, ::testing::Values(kIkFabrikType, kIkCcdType));

// ---- ikSpline ---------------------------------------------------------------------------

// Four joints of bones 1 along world +z from (0, 1, 0), under a group at
// (0, 1, 0); the root's joint orient turns its x axis down the chain (x = +z,
// y = +y, z = -x). Control points are locators.
struct SplineRig {
  Scene s{ops::default_registry()};
  NodeId group, ik;
  std::vector<NodeId> chain, controls;
  std::vector<Mat4> rest;

  explicit SplineRig(const std::vector<Vec3>& points, const SplineIkOptions& options = {}) {
    group = make(s, scene::kTransformType, "group");
    set(s, group, "translate", Vec3(0, 1, 0));
    const Mat4 space = s.world_matrix(group);
    chain = build_chain(s, group, space,
                        {{Vec3(0, 0, 0), Vec3(0, -90, 0)}, {Vec3(0, 0, 1)}, {Vec3(0, 0, 2)}, {Vec3(0, 0, 3)}}, "spine");
    for (std::size_t i = 0; i < points.size(); ++i) {
      const std::string name = "cv" + std::to_string(i);
      controls.push_back(make(s, scene::kLocatorType, name.c_str()));
      set(s, controls.back(), "translate", points[i]);
    }
    rest = worlds(s, chain);
    Result<NodeId> id = setup_spline_ik(s, chain, controls, options);
    EXPECT_TRUE(id.is_ok()) << id.status().message();
    ik = id.is_ok() ? *id : NodeId{};
  }
  Vec3 joint(std::size_t i) { return position_of(s.world_matrix(chain[i])); }
};

std::vector<Vec3> line_points() { return {Vec3(0, 1, 0), Vec3(0, 1, 1.5), Vec3(0, 1, 3), Vec3(0, 1, 4)}; }

TEST(IkSplineNode, straight_curve__joints_by_bone_length_frames_down_the_curve) {
  SplineRig rig(line_points());
  EXPECT_EQ(error_of(rig.s, rig.ik), "");
  EXPECT_TRUE(vec_near(std::get<Vec3>(get(rig.s, rig.ik, "aimAxis")), Vec3::UnitX(), 1e-12)) << "derived from the rest pose";
  EXPECT_TRUE(vec_near(std::get<Vec3>(get(rig.s, rig.ik, "upAxis")), Vec3::UnitY(), 1e-12));
  EXPECT_TRUE(near_mats(worlds(rig.s, rig.chain), rig.rest, 1e-9)) << "a curve through the rest chain keeps the rest pose";
  EXPECT_NEAR(std::get<double>(get(rig.s, rig.ik, "curveLength")), 4.0, 1e-9);
  EXPECT_NEAR(std::get<double>(get(rig.s, rig.ik, "chainLength")), 3.0, 1e-12);
  EXPECT_FALSE(std::get<bool>(get(rig.s, rig.ik, "overran")));

  // Move the curve to run along world +x from (2, 0, 0): the frames follow.
  const std::vector<Vec3> along_x = {Vec3(2, 0, 0), Vec3(3, 0, 0), Vec3(4.5, 0, 0), Vec3(6, 0, 0)};
  for (std::size_t i = 0; i < 4; ++i) set(rig.s, rig.controls[i], "translate", along_x[i]);
  for (std::size_t i = 0; i < 4; ++i) {
    const Mat4 w = rig.s.world_matrix(rig.chain[i]);
    EXPECT_TRUE(vec_near(position_of(w), Vec3(2.0 + static_cast<double>(i), 0, 0), 1e-9)) << "joint " << i;
    EXPECT_TRUE(vec_near(w.col(0).head<3>(), Vec3::UnitX(), 1e-9)) << "aim down the curve";
    EXPECT_TRUE(vec_near(w.col(1).head<3>(), Vec3::UnitY(), 1e-9)) << "up toward world up";
  }
}

TEST(IkSplineNode, stretch_squash_twist__hand_computed) {
  SplineRig rig(line_points());
  set(rig.s, rig.ik, "stretch", true);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_TRUE(vec_near(rig.joint(i), Vec3(0, 1, 4.0 * static_cast<double>(i) / 3.0), 1e-9))
        << "stretch: joints divide the curve's length 4 in the bones' proportions";
  }
  Mat4 w = rig.s.world_matrix(rig.chain[0]);
  EXPECT_NEAR(w.col(0).head<3>().norm(), 4.0 / 3.0, 1e-9) << "the aim axis scales by 4/3";
  EXPECT_NEAR(w.col(1).head<3>().norm(), 1.0, 1e-9);
  set(rig.s, rig.ik, "squash", true);
  w = rig.s.world_matrix(rig.chain[1]);
  EXPECT_NEAR(w.col(0).head<3>().norm(), 4.0 / 3.0, 1e-9);
  EXPECT_NEAR(w.col(1).head<3>().norm(), 1.0 / std::sqrt(4.0 / 3.0), 1e-9) << "squash keeps the volume";
  EXPECT_NEAR(w.col(2).head<3>().norm(), 1.0 / std::sqrt(4.0 / 3.0), 1e-9);
  EXPECT_TRUE(vec_near(rig.joint(3), Vec3(0, 1, 4), 1e-9));
  set(rig.s, rig.ik, "stretch", false);
  set(rig.s, rig.ik, "squash", false);

  // Twist from 0 to 90 degrees by length: joint i's up (y) turned 30 i
  // degrees about the aim (+z): y cos + (z cross y = -x) sin.
  set(rig.s, rig.ik, "endTwist", 90.0);
  for (std::size_t i = 0; i < 4; ++i) {
    const double a = math::to_radians(30.0 * static_cast<double>(i));
    EXPECT_TRUE(vec_near(rig.s.world_matrix(rig.chain[i]).col(1).head<3>(), Vec3(-std::sin(a), std::cos(a), 0), 1e-9))
        << "joint " << i;
  }
}

TEST(IkSplineNode, short_curve__chain_overruns_straight_along_end_tangent) {
  SplineRig rig({Vec3(0, 1, 0), Vec3(0, 1, 2)});  // degree 1, length 2; the chain is 3
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_TRUE(vec_near(rig.joint(i), Vec3(0, 1, static_cast<double>(i)), 1e-9)) << "joint " << i;
  }
  EXPECT_TRUE(std::get<bool>(get(rig.s, rig.ik, "overran")));
}

TEST(IkSplineNode, bent_curve_with_squash__joints_match_the_kernel) {
  const std::vector<Vec3> points = {Vec3(0, 1, 0), Vec3(0.5, 2, 1), Vec3(-0.5, 1.5, 2.5), Vec3(1, 1, 3.5),
                                    Vec3(1.5, 2, 4)};
  SplineRig rig(points);
  set(rig.s, rig.ik, "stretch", true);
  set(rig.s, rig.ik, "squash", true);
  set(rig.s, rig.ik, "startTwist", -20.0);
  set(rig.s, rig.ik, "endTwist", 45.0);
  std::vector<double> arc(64 * 4 + 1);  // the node's automatic table size
  std::vector<Mat4> expected(4);
  SplineIkJob job;
  job.control_points = points;
  job.world = rig.rest;
  job.start_twist = math::to_radians(-20.0);
  job.end_twist = math::to_radians(45.0);
  job.stretch = true;
  job.squash = true;
  job.arc_lengths = arc;
  job.world_out = expected;
  ASSERT_TRUE(job.run());
  EXPECT_EQ(error_of(rig.s, rig.ik), "");
  EXPECT_TRUE(near_mats(worlds(rig.s, rig.chain), expected, 1e-9))
      << "translate, rotation, scale and shear outputs reproduce non-uniformly scaled parents exactly";
  EXPECT_TRUE(near_mats(out_worlds(rig.s, rig.ik), expected, 1e-9));

  set(rig.s, rig.ik, "stretch", false);
  set(rig.s, rig.ik, "squash", false);
  EXPECT_LE(testing::bone_length_error(rig.rest, worlds(rig.s, rig.chain)), 1e-9) << "no stretch: lengths kept";
  EXPECT_TRUE(vec_near(rig.joint(0), points[0], 1e-12)) << "the root on the curve's start";
  for (std::size_t i = 1; i < 4; ++i) {
    // On the curve: the nearest of many samples is within the sample spacing.
    double nearest = kInf;
    for (int k = 0; k <= 20000; ++k) nearest = std::min(nearest, (bspline_point(points, k / 20000.0) - rig.joint(i)).norm());
    EXPECT_LT(nearest, 1e-3) << "joint " << i << " lies on the curve";
  }

  set(rig.s, rig.ik, "weight", 0.0);
  EXPECT_TRUE(near_mats(worlds(rig.s, rig.chain), rig.rest, 1e-9)) << "weight 0: the rest pose";
}

TEST(IkSplineNode, validate_failures__surface_in_error_and_keep_rest_pose) {
  SplineRig rig({Vec3(0, 1, 0), Vec3(1, 1, 1.5), Vec3(0, 2, 3), Vec3(0, 1, 4)});
  Scene& s = rig.s;
  const NodeId ik = rig.ik;
  ASSERT_EQ(error_of(s, ik), "");
  ASSERT_FALSE(near_mats(worlds(s, rig.chain), rig.rest, 1e-3)) << "the solve moved the chain";
  auto expect_failure = [&](const std::string& attr, const std::string& why) {
    const std::string error = error_of(s, ik);
    EXPECT_NE(error.find(attr), std::string::npos) << why << ": error was '" << error << "'";
    EXPECT_TRUE(near_mats(worlds(s, rig.chain), rig.rest, 1e-9)) << why << ": rest pose";
  };
  auto expect_ok = [&](const std::string& why) { EXPECT_EQ(error_of(s, ik), "") << why; };

  // A control point not finite (through its locator), then fewer than 2.
  set(s, rig.controls[0], "translate", Vec3(kNaN, 0, 0));
  expect_failure("controlMatrix[0]", "a NaN control point");
  set(s, rig.controls[0], "translate", Vec3(0, 1, 0));
  expect_ok("fixed");
  const Mat4 first = s.world_matrix(rig.controls[0]);
  const Mat4 second = s.world_matrix(rig.controls[1]);
  for (std::int32_t i = 0; i < 4; ++i) ASSERT_TRUE(s.graph().disconnect_input(plug(s, ik, "controlMatrix", i)).is_ok());
  set(s, ik, "controlMatrix", std::vector<Mat4>{first});
  expect_failure("controlMatrix", "one control point");
  set(s, ik, "controlMatrix", std::vector<Mat4>{first, second});
  expect_ok("two control points: a line");

  // arc_lengths of fewer than 2 entries.
  for (std::int64_t bad : {std::int64_t{1}, std::int64_t{-4}, std::int64_t{1} << 21}) {
    set(s, ik, "arcLengthSamples", bad);
    expect_failure("arcLengthSamples", "samples " + std::to_string(bad));
  }
  set(s, ik, "arcLengthSamples", std::int64_t{2});
  expect_ok("2 samples: the smallest table");
  set(s, ik, "arcLengthSamples", std::int64_t{0});

  // aim_axis / up_axis not unit, not perpendicular.
  set(s, ik, "aimAxis", Vec3(2, 0, 0));
  expect_failure("aimAxis", "aim of length 2");
  set(s, ik, "aimAxis", Vec3(1, 0, 0));
  set(s, ik, "upAxis", Vec3(0, 0.5, 0));
  expect_failure("upAxis", "up of length 0.5");
  set(s, ik, "upAxis", Vec3(0.6, 0.8, 0));
  expect_failure("upAxis", "up not perpendicular to aim");
  set(s, ik, "upAxis", Vec3(0, 1, 0));

  // up_vector zero or not finite.
  set(s, ik, "worldUpVector", Vec3(0, 0, 0));
  expect_failure("worldUpVector", "zero up");
  set(s, ik, "worldUpVector", Vec3(0, kNaN, 0));
  expect_failure("worldUpVector", "NaN up");
  set(s, ik, "worldUpVector", Vec3(0, 3, 0));
  expect_ok("up need not be unit");

  // Twists not finite.
  set(s, ik, "startTwist", kInf);
  expect_failure("startTwist", "infinite start twist");
  set(s, ik, "startTwist", 0.0);
  set(s, ik, "endTwist", kNaN);
  expect_failure("endTwist", "NaN end twist");
  set(s, ik, "endTwist", 0.0);

  // World matrices not affine; fewer than 2 joints; weight.
  const auto rest = std::get<std::vector<Mat4>>(get(s, ik, "restMatrix"));
  Mat4 projective = rest[3];
  projective(3, 3) = 2.0;
  set(s, ik, "restMatrix", projective, 3);
  expect_failure("restMatrix[3]", "projective rest");
  set(s, ik, "restMatrix", std::vector<Mat4>{rest[0]});
  EXPECT_NE(error_of(s, ik).find("restMatrix"), std::string::npos) << "one joint";
  set(s, ik, "restMatrix", rest);
  set(s, ik, "weight", -0.5);
  expect_failure("weight", "negative weight");
  set(s, ik, "weight", 1.0);
  expect_ok("all fixed");

  // A curve of zero length with stretch: the solved chain is singular.
  set(s, ik, "controlMatrix", std::vector<Mat4>{first, first});
  set(s, ik, "stretch", true);
  expect_failure("singular", "zero-length curve with stretch");
}

}  // namespace
}  // namespace rigel::ops::ik
