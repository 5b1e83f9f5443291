// Constraint node types in a scene: targets' worldMatrix in, driven
// channels out.

#include "rigel/ops/constraints/nodes.h"

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "rigel/graph/graph.h"
#include "rigel/math/transform.h"
#include "rigel/ops/constraints/constraints.h"
#include "rigel/scene/scene.h"
#include "rigel/scene/transform_types.h"

namespace rigel::ops::constraints {
namespace {

using graph::NodeId;
using graph::Plug;

std::shared_ptr<const graph::Registry> constraint_registry() {
  auto r = std::make_shared<graph::Registry>();
  EXPECT_TRUE(scene::register_scene_types(*r).is_ok());
  const Status s = register_constraint_types(*r);
  EXPECT_TRUE(s.is_ok()) << s.message();
  return r;
}

Plug plug(const scene::Scene& s, NodeId node, const char* attr, std::int32_t element = -1) {
  Result<Plug> p = s.graph().plug_find(node, attr, element);
  EXPECT_TRUE(p.is_ok()) << attr << ": " << p.status().message();
  return p.is_ok() ? *p : Plug{};
}

void set(scene::Scene& s, NodeId node, const char* attr, graph::Value v, std::int32_t element = -1) {
  const Status st = s.graph().set_value(plug(s, node, attr, element), std::move(v));
  ASSERT_TRUE(st.is_ok()) << attr << ": " << st.message();
}

void connect(scene::Scene& s, NodeId src, const char* src_attr, NodeId dst, const char* dst_attr,
             std::int32_t element = -1) {
  const Status st = s.graph().connect(plug(s, src, src_attr), plug(s, dst, dst_attr, element));
  ASSERT_TRUE(st.is_ok()) << src_attr << " -> " << dst_attr << ": " << st.message();
}

NodeId make(scene::Scene& s, const char* type, const char* name, NodeId parent = NodeId{}) {
  Result<NodeId> id = s.create(type, name, parent);
  EXPECT_TRUE(id.is_ok()) << id.status().message();
  return id.is_ok() ? *id : NodeId{};
}

::testing::AssertionResult near_mat(const Mat4& a, const Mat4& b, double tol = 1e-9) {
  if (math::is_near(a, b, tol)) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "\n" << a << "\n!=\n" << b;
}

TEST(ConstraintNodes, register_constraint_types__adds_six_types_once) {
  graph::Registry registry;
  ASSERT_TRUE(register_constraint_types(registry).is_ok());
  for (const char* name : {kParentConstraintType, kPointConstraintType, kOrientConstraintType,
                           kScaleConstraintType, kAimConstraintType, kPoleVectorConstraintType}) {
    const graph::NodeType* type = registry.find(name);
    ASSERT_NE(type, nullptr) << name;
    EXPECT_NE(type->attr_find("targetWorldMatrix"), graph::kNoAttr) << name;
    const graph::AttrIndex weight = type->attr_find("targetWeight");
    ASSERT_NE(weight, graph::kNoAttr);
    EXPECT_NE(type->attr(weight).flags & graph::kKeyable, 0u) << "target weights are keyable";
  }
  EXPECT_NE(registry.find(kParentConstraintType)->attr_find("rigid"), graph::kNoAttr);
  EXPECT_FALSE(register_constraint_types(registry).is_ok()) << "registering twice should fail: names taken";
}

// Two target joints, a driven joint under a moved group, a parentConstraint
// between them.
struct ParentRig {
  scene::Scene s{constraint_registry()};
  NodeId a, b, group, driven, constraint;
  Mat4 group_world;
  ParentRig() {
    a = make(s, scene::kJointType, "targetA");
    b = make(s, scene::kJointType, "targetB");
    group = make(s, scene::kTransformType, "group");
    driven = make(s, scene::kJointType, "driven", group);
    constraint = make(s, kParentConstraintType, "driven_parentConstraint");
    set(s, group, "translate", Vec3(0, 0, 2));
    set(s, group, "rotate", Vec3(0, 30, 0));
    group_world = s.world_matrix(group);
    // The driven's parent is static here, so its inverse is set once.
    set(s, constraint, "parentInverseMatrix", math::affine_inverse(group_world));
    set(s, driven, "rotateOrder", std::int64_t{2});
    set(s, constraint, "rotateOrder", std::int64_t{2});
    set(s, driven, "jointOrient", Vec3(10, 0, 0));
    set(s, constraint, "jointOrient", Vec3(10, 0, 0));
    connect(s, a, "worldMatrix", constraint, "targetWorldMatrix", 0);
    connect(s, b, "worldMatrix", constraint, "targetWorldMatrix", 1);
    set(s, constraint, "targetWeight", 1.0, 0);
    set(s, constraint, "targetWeight", 0.0, 1);
    connect(s, constraint, "translate", driven, "translate");
    connect(s, constraint, "rotate", driven, "rotate");
    connect(s, constraint, "scale", driven, "scale");
  }
};

TEST(ConstraintNodes, parent_constraint__driven_follows_target) {
  ParentRig rig;
  scene::Scene& s = rig.s;
  set(s, rig.a, "translate", Vec3(1, 2, 3));
  set(s, rig.a, "rotate", Vec3(20, -40, 70));
  EXPECT_TRUE(near_mat(s.world_matrix(rig.driven), s.world_matrix(rig.a)))
      << "weight 1 on A: the driven sits on A (through its parent, joint orient and rotate order)";
  set(s, rig.a, "translate", Vec3(-5, 0, 1));
  set(s, rig.a, "rotate", Vec3(0, 90, 0));
  EXPECT_TRUE(near_mat(s.world_matrix(rig.driven), s.world_matrix(rig.a))) << "and follows when A moves";

  set(s, rig.b, "translate", Vec3(5, 2, 1));
  set(s, rig.b, "rotate", Vec3(0, 90, 0));
  set(s, rig.constraint, "targetWeight", 1.0, 1);
  const Mat4 world = s.world_matrix(rig.driven);
  EXPECT_TRUE(near_mat(world, math::trs_matrix(Vec3(0, 1, 1), math::euler_to_quat(Vec3(0, math::kPi / 2, 0),
                                                                                     math::RotateOrder::kXYZ),
                                                 Vec3::Ones())))
      << "weights 1:1 with the same rotation: the midpoint";
  const graph::Value error = *s.graph().evaluate(plug(s, rig.constraint, "error"));
  EXPECT_TRUE(std::get<std::string>(error).empty()) << "no error while the inputs are valid";
}

TEST(ConstraintNodes, parent_constraint__maintain_offset_and_no_cycle) {
  ParentRig rig;
  scene::Scene& s = rig.s;
  set(s, rig.a, "translate", Vec3(1, 2, 3));
  // Where the driven would be without the constraint: its world at creation.
  const Mat4 driven_world = rig.group_world * math::trs_matrix(Vec3(4, 0, 0), math::Quat::Identity(), Vec3::Ones());
  set(s, rig.constraint, "targetOffset", compute_offset(s.world_matrix(rig.a), driven_world), 0);
  EXPECT_TRUE(near_mat(s.world_matrix(rig.driven), driven_world)) << "maintain offset: in place at creation";
  set(s, rig.a, "translate", Vec3(1, 7, 3));
  EXPECT_TRUE(near_mat(s.world_matrix(rig.driven),
                       math::trs_matrix(Vec3(0, 5, 0), math::Quat::Identity(), Vec3::Ones()) * driven_world))
      << "then follows the target";
  // Feeding the driven's worldMatrix back into the constraint would be a cycle.
  EXPECT_FALSE(s.graph().connect(plug(s, rig.driven, "worldMatrix"), plug(s, rig.constraint, "targetWorldMatrix", 2)).is_ok())
      << "the graph refuses a constraint that reads its own driven";
}

TEST(ConstraintNodes, parent_constraint__bad_weight_reports_error_and_keeps_rest) {
  ParentRig rig;
  scene::Scene& s = rig.s;
  set(s, rig.constraint, "targetWeight", -1.0, 1);
  set(s, rig.constraint, "restTranslate", Vec3(3, 0, 0));
  const std::string error = std::get<std::string>(*s.graph().evaluate(plug(s, rig.constraint, "error")));
  EXPECT_NE(error.find("targetWeight[1]"), std::string::npos) << error;
  const Vec3 t = std::get<Vec3>(*s.graph().evaluate(plug(s, rig.constraint, "translate")));
  EXPECT_TRUE(t.isApprox(Vec3(3, 0, 0))) << "invalid inputs: the rest value, no crash";
}

TEST(ConstraintNodes, point_orient_scale__each_drives_its_channel) {
  scene::Scene s(constraint_registry());
  const NodeId target = make(s, scene::kTransformType, "target");
  const NodeId driven = make(s, scene::kTransformType, "driven");
  const NodeId point = make(s, kPointConstraintType, "point");
  const NodeId orient = make(s, kOrientConstraintType, "orient");
  const NodeId scale = make(s, kScaleConstraintType, "scale");
  for (NodeId c : {point, orient, scale}) connect(s, target, "worldMatrix", c, "targetWorldMatrix", 0);
  connect(s, point, "translate", driven, "translate");
  connect(s, orient, "rotate", driven, "rotate");
  connect(s, scale, "scale", driven, "scale");
  set(s, target, "translate", Vec3(1, -2, 3));
  set(s, target, "rotate", Vec3(15, 25, 35));
  set(s, target, "scale", Vec3(2, 3, 4));
  EXPECT_TRUE(near_mat(s.world_matrix(driven), s.world_matrix(target)))
      << "point + orient + scale on one target reproduce it (missing weights count as 1)";
}

TEST(ConstraintNodes, aim_constraint__points_axis_at_target) {
  scene::Scene s(constraint_registry());
  const NodeId target = make(s, scene::kLocatorType, "target");
  const NodeId driven = make(s, scene::kJointType, "driven");
  const NodeId aim = make(s, kAimConstraintType, "aim");
  connect(s, target, "worldMatrix", aim, "targetWorldMatrix", 0);
  set(s, driven, "translate", Vec3(1, 0, 0));
  set(s, aim, "constraintTranslate", Vec3(1, 0, 0));
  set(s, aim, "worldUpType", std::int64_t{3});
  set(s, aim, "worldUpVector", Vec3(0, 0, 1));
  connect(s, aim, "rotate", driven, "rotate");
  set(s, target, "translate", Vec3(1, 5, 0));
  Mat4 world = s.world_matrix(driven);
  EXPECT_TRUE(Vec3(world.col(0).head<3>()).isApprox(Vec3::UnitY(), 1e-9)) << "x aims at the target (+y)";
  EXPECT_TRUE(Vec3(world.col(1).head<3>()).isApprox(Vec3::UnitZ(), 1e-9)) << "y is the world up (+z)";
  set(s, target, "translate", Vec3(1, 0, 7));  // straight along the world up: no NaN
  world = s.world_matrix(driven);
  EXPECT_TRUE(world.allFinite());
  EXPECT_TRUE(Vec3(world.col(0).head<3>()).isApprox(Vec3::UnitZ(), 1e-9));
}

TEST(ConstraintNodes, pole_vector_constraint__offset_from_line) {
  scene::Scene s(constraint_registry());
  const NodeId pole = make(s, scene::kLocatorType, "pole");
  const NodeId c = make(s, kPoleVectorConstraintType, "poleVector");
  connect(s, pole, "worldMatrix", c, "targetWorldMatrix", 0);
  set(s, pole, "translate", Vec3(1, 2, 3));
  set(s, c, "handlePosition", Vec3(4, 0, 0));
  const Vec3 v = std::get<Vec3>(*s.graph().evaluate(plug(s, c, "poleVector")));
  EXPECT_TRUE(v.isApprox(Vec3(0, 2, 3), 1e-12)) << v.transpose();
}

}  // namespace
}  // namespace rigel::ops::constraints
