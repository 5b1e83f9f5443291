// IK node graphs (include/rigel/ops/ik/nodes.h) through the .rigel scene
// file: every IK type, set up by its helper, saves, loads and saves again to
// the same text, and the loaded scene poses its joints exactly as the
// original and keeps solving when the targets move. (Here rather than in
// tests/ops: the file format is the io layer, above ops.)

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "io_test_util.h"
#include "rigel/io/scene_file.h"
#include "rigel/math/transform.h"
#include "rigel/ops/ik/nodes.h"
#include "rigel/ops/registry.h"
#include "rigel/scene/transform_types.h"

namespace rigel::io {
namespace {

using namespace rigel::io::testing;  // NOLINT: test helpers
namespace ik = rigel::ops::ik;

NodeId make(Scene& s, const char* type, const std::string& name, NodeId parent = NodeId{}) {
  Result<NodeId> id = s.create(type, name, parent);
  EXPECT_TRUE(id.is_ok()) << id.status().message();
  return id.is_ok() ? *id : NodeId{};
}

void set(Scene& s, NodeId node, const char* attr, Value v) {
  Result<Plug> p = s.graph().plug_find(node, attr);
  ASSERT_TRUE(p.is_ok()) << attr;
  const Status st = s.graph().set_value(*p, std::move(v));
  ASSERT_TRUE(st.is_ok()) << attr << ": " << st.message();
}

Value get(Scene& s, const std::string& plug) {
  Result<Plug> p = s.graph().plug_find(plug);
  EXPECT_TRUE(p.is_ok()) << plug;
  if (!p.is_ok()) return Value{};
  Result<Value> v = s.graph().evaluate(*p);
  return v.is_ok() ? *v : Value{};
}

// Joints named <prefix>0.. under `parent`, each `step` from the last (in the
// parent joint's space), with a joint orient so the outputs must account for it.
std::vector<NodeId> chain(Scene& s, NodeId parent, const std::string& prefix, const std::vector<Vec3>& steps) {
  std::vector<NodeId> joints;
  for (std::size_t i = 0; i < steps.size(); ++i) {
    const NodeId j = make(s, scene::kJointType, prefix + std::to_string(i), joints.empty() ? parent : joints.back());
    set(s, j, "translate", steps[i]);
    set(s, j, "jointOrient", Vec3(0, 0, 5.0 * static_cast<double>(i)));
    joints.push_back(j);
  }
  return joints;
}

NodeId locator(Scene& s, const std::string& name, const Vec3& at) {
  const NodeId id = make(s, scene::kLocatorType, name);
  set(s, id, "translate", at);
  return id;
}

// One scene holding an ikTwoBone (with a pole object), an ikFabrik (with a
// hinge limit), an ikCcd and an ikSpline, each moved off its rest pose.
struct IkScene {
  Scene s{ops::default_registry()};
  std::vector<NodeId> joints;

  // Builds the rigs (a function, not the constructor: ASSERT returns).
  void build() {
    const NodeId hips = make(s, scene::kTransformType, "hips");
    set(s, hips, "translate", Vec3(0, 1, 0));
    set(s, hips, "rotate", Vec3(0, 30, 0));

    const std::vector<NodeId> leg = chain(s, hips, "leg", {Vec3(0.2, 0, 0), Vec3(0.4, -0.3, 0), Vec3(0.4, 0.3, 0)});
    const NodeId foot = locator(s, "foot_target", Vec3(0.5, 0.3, 0.4));
    const NodeId knee = locator(s, "knee_pole", Vec3(0.5, 1, 2));
    Result<NodeId> two = ik::setup_two_bone_ik(s, leg, foot, knee);
    ASSERT_TRUE(two.is_ok()) << two.status().message();
    set(s, *two, "twist", 12.5);
    set(s, *two, "soft", 0.1);
    set(s, *two, "stretch", true);
    set(s, *two, "maxStretch", 1.3);

    const std::vector<NodeId> arm =
        chain(s, hips, "arm", {Vec3(0, 0.5, 0), Vec3(0.3, 0.1, 0), Vec3(0.3, -0.1, 0), Vec3(0.3, 0.1, 0)});
    const NodeId hand = locator(s, "hand_target", Vec3(0.4, 1.8, 0.5));
    ik::ChainIkOptions options;
    ik::JointLimit cone;
    cone.kind = ik::LimitKind::kCone;
    cone.axis = Vec3::UnitX();
    cone.half_angle = 1.0;
    options.limits = {ik::JointLimit{}, cone, ik::JointLimit{}, ik::JointLimit{}};
    Result<NodeId> fabrik = ik::setup_fabrik_ik(s, arm, hand, options);
    ASSERT_TRUE(fabrik.is_ok()) << fabrik.status().message();

    const std::vector<NodeId> tail =
        chain(s, hips, "tail", {Vec3(-0.2, 0, 0), Vec3(-0.3, 0.05, 0), Vec3(-0.3, -0.05, 0)});
    const NodeId tip = locator(s, "tail_target", Vec3(-0.6, 0.8, 0.3));
    Result<NodeId> ccd = ik::setup_ccd_ik(s, tail, tip);
    ASSERT_TRUE(ccd.is_ok()) << ccd.status().message();
    set(s, *ccd, "weight", 0.75);

    const std::vector<NodeId> spine =
        chain(s, hips, "spine", {Vec3(0, 0.1, 0), Vec3(0.25, 0, 0), Vec3(0.25, 0, 0), Vec3(0.25, 0, 0)});
    std::vector<NodeId> cvs;
    const std::vector<Vec3> points = {Vec3(0, 1.1, 0), Vec3(0.1, 1.4, 0.1), Vec3(-0.1, 1.6, 0), Vec3(0, 1.9, -0.1)};
    for (std::size_t i = 0; i < points.size(); ++i) cvs.push_back(locator(s, "spine_cv" + std::to_string(i), points[i]));
    ik::SplineIkOptions spline_options;
    spline_options.stretch = true;
    spline_options.squash = true;
    Result<NodeId> spline = ik::setup_spline_ik(s, spine, cvs, spline_options);
    ASSERT_TRUE(spline.is_ok()) << spline.status().message();
    set(s, *spline, "endTwist", 40.0);

    for (const auto* group : {&leg, &arm, &tail, &spine}) joints.insert(joints.end(), group->begin(), group->end());
  }
};

TEST(IkSceneFile, round_trip__every_ik_type_saves_loads_and_poses_the_same) {
  IkScene original;
  ASSERT_NO_FATAL_FAILURE(original.build());
  const std::string text = write_scene(original.s);
  for (const char* needle : {"\"ikTwoBone\"", "\"ikFabrik\"", "\"ikCcd\"", "\"ikSpline\"", "\"restMatrix\"",
                             "\"limitType\"", "outRotations[0]", "\"hips.worldMatrix\""}) {
    EXPECT_NE(text.find(needle), std::string::npos) << needle << " should be in the file";
  }
  for (const char* name : {"leg0_ikTwoBone", "arm0_ikFabrik", "tail0_ikCcd", "spine0_ikSpline"}) {
    EXPECT_EQ(std::get<std::string>(get(original.s, std::string(name) + ".error")), "") << name;
  }

  Result<std::unique_ptr<Scene>> loaded = parse_scene(text, "ik.rigel");
  ASSERT_TRUE(loaded.is_ok()) << loaded.status().message();
  Scene& copy = **loaded;
  EXPECT_EQ(write_scene(copy), text) << first_difference(write_scene(copy), text);
  for (NodeId j : original.joints) {
    const std::string& name = original.s.graph().node(j)->name();
    const NodeId k = copy.graph().find(name);
    ASSERT_TRUE(k.is_valid()) << name;
    EXPECT_TRUE(math::is_near(copy.world_matrix(k), original.s.world_matrix(j), 1e-12))
        << name << " is posed the same after loading";
  }

  // The loaded graph still solves: move the foot target, the leg follows.
  const NodeId foot = copy.graph().find("foot_target");
  set(copy, foot, "translate", Vec3(0.3, 0.5, 0.2));
  const Mat4 end = copy.world_matrix(copy.graph().find("leg2"));
  EXPECT_LT((Vec3(end.topRightCorner<3, 1>()) - Vec3(0.3, 0.5, 0.2)).norm(), 1e-9)
      << "the end reaches the moved target: " << end.topRightCorner<3, 1>().transpose();

  // And through a file on disk.
  TempDir dir;
  ASSERT_TRUE(save_scene(original.s, dir.path() / "ik.rigel").is_ok());
  Result<std::unique_ptr<Scene>> from_disk = load_scene(dir.path() / "ik.rigel");
  ASSERT_TRUE(from_disk.is_ok()) << from_disk.status().message();
  EXPECT_EQ(write_scene(**from_disk), text);
}

}  // namespace
}  // namespace rigel::io
