// The utility node types of ops/util: fkIkSwitch (blend.h) and twistShare
// (twist.h), against hand-computed poses.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "rigel/graph/graph.h"
#include "rigel/math/rotation.h"
#include "rigel/math/transform.h"
#include "rigel/ops/registry.h"
#include "rigel/ops/util/blend.h"
#include "rigel/ops/util/twist.h"

namespace rigel::ops::util {
namespace {

using graph::NodeId;
using graph::Plug;
using graph::Value;
using math::Mat4;
using math::Quat;
using math::Vec3;

Mat4 trs(const Vec3& t, const Quat& r, const Vec3& s = Vec3::Ones()) { return math::trs_matrix(t, r, s); }
Quat about(const Vec3& axis, double degrees) { return Quat(Eigen::AngleAxisd(math::to_radians(degrees), axis.normalized())); }
Vec3 pos(const Mat4& m) { return m.topRightCorner<3, 1>(); }

struct SwitchFixture {
  graph::Graph g{ops::default_registry()};
  NodeId node;
  SwitchFixture() {
    node = *g.create_node(kFkIkSwitchType, "switch");
  }
  void set(graph::AttrIndex attr, Value v) { ASSERT_TRUE(g.set_value(Plug{node, attr, -1}, std::move(v)).is_ok()); }
  template <typename T>
  T get(graph::AttrIndex attr) {
    return std::get<T>(g.evaluate(node, attr));
  }
};

// A two-joint chain (bone of length 2 along x) under a turned, moved parent.
TEST(FkIkSwitch, blends_local_poses_keeping_bone_lengths_and_ends_exactly_on_each_side) {
  namespace a = fk_ik_attr;
  SwitchFixture f;
  const Mat4 parent = trs(Vec3(1, 2, 3), about(Vec3(0, 0, 1), 30));
  const Mat4 offset1 = trs(Vec3(2, 0, 0), Quat::Identity());
  f.set(a::kParentMatrix, parent);
  f.set(a::kRestOffsetParentMatrix, std::vector<Mat4>{Mat4::Identity(), offset1});
  const std::vector<Mat4> fk = {parent * trs(Vec3::Zero(), about(Vec3(0, 0, 1), 40)),
                                parent * trs(Vec3::Zero(), about(Vec3(0, 0, 1), 40)) * offset1};
  const std::vector<Mat4> ik = {parent * trs(Vec3::Zero(), about(Vec3(0, 0, 1), -40)),
                                parent * trs(Vec3::Zero(), about(Vec3(0, 0, 1), -40)) * offset1 *
                                    trs(Vec3::Zero(), about(Vec3(0, 1, 0), 60))};
  f.set(a::kFkMatrix, fk);
  f.set(a::kIkMatrix, ik);
  for (double w : {0.0, 1.0}) {
    f.set(a::kFkIk, w);
    const auto worlds = f.get<std::vector<Mat4>>(a::kOutWorldMatrices);
    ASSERT_EQ(worlds.size(), 2u);
    for (int i = 0; i < 2; ++i)
      EXPECT_LT((worlds[i] - (w == 0 ? fk : ik)[i]).norm(), 1e-12) << "fkIk " << w << " joint " << i;
  }
  f.set(a::kFkIk, 0.5);
  const auto worlds = f.get<std::vector<Mat4>>(a::kOutWorldMatrices);
  // Halfway: the root turned 0 degrees about z in the parent, the bone still 2 long.
  const Quat root = math::decompose(math::affine_inverse(parent) * worlds[0]).rotation;
  EXPECT_NEAR(root.angularDistance(Quat::Identity()), 0.0, 1e-12);
  EXPECT_NEAR((pos(worlds[1]) - pos(worlds[0])).norm(), 2.0, 1e-12) << "local blending keeps the bone's length";
  const Quat tip = math::decompose(math::affine_inverse(worlds[0] * offset1) * worlds[1]).rotation;
  EXPECT_NEAR(tip.angularDistance(about(Vec3(0, 1, 0), 30)), 0.0, 1e-12) << "the tip's local turn is slerped";
  // The channels give the world matrices through the joint's orient.
  f.set(a::kRestJointOrient, std::vector<Vec3>{Vec3(0, 0, 90), Vec3(10, 0, 0)});
  const auto rotations = f.get<std::vector<Quat>>(a::kOutRotations);
  const auto translations = f.get<std::vector<Vec3>>(a::kOutTranslations);
  math::TransformParts p;
  p.rotate_mode = math::RotateMode::kQuaternion;
  p.rotate_quaternion = rotations[1];
  p.translate = translations[1];
  p.joint_orient = math::to_radians(Vec3(10, 0, 0));
  EXPECT_LT((worlds[0] * offset1 * math::compose(p) - f.get<std::vector<Mat4>>(a::kOutWorldMatrices)[1]).norm(), 1e-12);
  EXPECT_EQ(f.get<std::string>(a::kError), "");
}

TEST(FkIkSwitch, takes_the_ik_end_orientation_from_the_control_and_reports_bad_input) {
  namespace a = fk_ik_attr;
  SwitchFixture f;
  f.set(a::kRestOffsetParentMatrix, std::vector<Mat4>{Mat4::Identity()});
  f.set(a::kIkMatrix, std::vector<Mat4>{trs(Vec3(1, 0, 0), Quat::Identity())});
  f.set(a::kFkIk, 1.0);
  f.set(a::kUseIkEndMatrix, true);
  f.set(a::kIkEndMatrix, trs(Vec3(5, 5, 5), about(Vec3(1, 0, 0), 90)));
  Mat4 w = f.get<std::vector<Mat4>>(a::kOutWorldMatrices)[0];
  EXPECT_LT((w - trs(Vec3(1, 0, 0), about(Vec3(1, 0, 0), 90))).norm(), 1e-12)
      << "translation from the solver, orientation from the control";
  f.set(a::kFkIk, 7.0);
  w = f.get<std::vector<Mat4>>(a::kOutWorldMatrices)[0];
  EXPECT_LT((w - trs(Vec3(1, 0, 0), about(Vec3(1, 0, 0), 90))).norm(), 1e-12) << "fkIk is clamped to 1";
  Mat4 singular = Mat4::Identity();
  singular(0, 0) = 0;
  f.set(a::kParentMatrix, singular);
  EXPECT_NE(f.get<std::string>(a::kError), "");
  EXPECT_TRUE(f.get<std::vector<Quat>>(a::kOutRotations)[0].coeffs().allFinite()) << "never NaN channels";
}

TEST(TwistShare, shares_the_twist_about_the_axis_and_ignores_swing) {
  namespace t = twist_attr;
  graph::Graph g{ops::default_registry()};
  const NodeId n = *g.create_node(kTwistShareType, "share");
  auto set = [&](graph::AttrIndex attr, Value v) { ASSERT_TRUE(g.set_value(Plug{n, attr, -1}, std::move(v)).is_ok()); };
  const Quat rest = about(Vec3(0, 0, 1), 20);  // the end's rest turn relative to the start
  const Mat4 start = trs(Vec3(1, 0, 0), about(Vec3(1, 1, 0), 50), Vec3(2, 2, 2));
  set(t::kStartMatrix, start);
  set(t::kRestRelative, rest);
  set(t::kCount, std::int64_t{3});
  set(t::kAxis, std::int64_t{1});  // y
  // The end at rest: no twist.
  set(t::kEndMatrix, Mat4(start * trs(Vec3(0, 3, 0), rest)));
  EXPECT_NEAR(std::get<double>(g.evaluate(n, t::kTwist)), 0.0, 1e-9);
  // 80 degrees of twist about y, then a swing about x: the twist is 80.
  const Quat turned = about(Vec3(1, 0, 0), 35) * about(Vec3(0, 1, 0), 80) * rest;
  set(t::kEndMatrix, Mat4(start * trs(Vec3(0, 3, 0), turned)));
  EXPECT_NEAR(std::get<double>(g.evaluate(n, t::kTwist)), 80.0, 1e-9);
  const auto out = std::get<std::vector<Quat>>(g.evaluate(n, t::kOutRotations));
  ASSERT_EQ(out.size(), 3u);
  for (int i = 0; i < 3; ++i)
    EXPECT_NEAR(out[i].angularDistance(about(Vec3(0, 1, 0), 20.0 * (i + 1))), 0.0, 1e-12) << i;
  EXPECT_NEAR(math::to_degrees(twist_angle(about(Vec3(0, 0, 1), -170), Vec3(0, 0, 1))), -170.0, 1e-9);
  Mat4 bad = start;
  bad(0, 0) = std::nan("");
  set(t::kEndMatrix, bad);
  EXPECT_NE(std::get<std::string>(g.evaluate(n, t::kError)), "");
  EXPECT_EQ(std::get<std::vector<Quat>>(g.evaluate(n, t::kOutRotations))[0].coeffs(), Quat::Identity().coeffs());
}

}  // namespace
}  // namespace rigel::ops::util
