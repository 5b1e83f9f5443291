#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "rigel/graph/graph.h"
#include "rigel/math/transform.h"
#include "rigel/ops/deform/nodes.h"
#include "rigel/scene/scene.h"
#include "rigel/scene/transform_types.h"

namespace rigel::ops {
namespace {

using graph::NodeId;
using graph::Plug;
using graph::Value;
using math::Mat4;
using math::Vec3;
namespace sc = skin_cluster_attr;
namespace bs = blend_shape_attr;

std::shared_ptr<const graph::Registry> deform_registry() {
  auto registry = std::make_shared<graph::Registry>();
  EXPECT_TRUE(scene::register_scene_types(*registry).is_ok());
  const Status s = register_deform_types(*registry);
  EXPECT_TRUE(s.is_ok()) << s.message();
  return registry;
}

::testing::AssertionResult points_near(const std::vector<Vec3>& actual, const std::vector<Vec3>& expected,
                                       double tolerance) {
  if (actual.size() != expected.size()) {
    return ::testing::AssertionFailure() << "sizes differ: " << actual.size() << " vs " << expected.size();
  }
  for (std::size_t i = 0; i < actual.size(); ++i) {
    const double diff = (actual[i] - expected[i]).cwiseAbs().maxCoeff();
    if (!(diff <= tolerance)) {
      return ::testing::AssertionFailure() << "point " << i << ": " << actual[i].transpose() << " vs "
                                           << expected[i].transpose() << " (difference " << diff << ")";
    }
  }
  return ::testing::AssertionSuccess();
}

TEST(DeformNodes, register_deform_types__adds_both_types_once) {
  graph::Registry registry;
  ASSERT_TRUE(register_deform_types(registry).is_ok());
  const graph::NodeType* skin = registry.find(kSkinClusterType);
  const graph::NodeType* blend = registry.find(kBlendShapeType);
  ASSERT_NE(skin, nullptr);
  ASSERT_NE(blend, nullptr);
  EXPECT_EQ(skin->attr_count(), std::size_t{sc::kCount} + 1) << "+ metaParent" << "the attribute enum matches the type";
  EXPECT_EQ(blend->attr_count(), std::size_t{bs::kCount} + 1);
  EXPECT_EQ(skin->attr_find("jointMatrices"), sc::kJointMatrices);
  EXPECT_EQ(skin->attr_find("outPoints"), sc::kOutPoints);
  EXPECT_EQ(blend->attr_find("weights"), bs::kWeights);
  EXPECT_NE(blend->attr(bs::kWeights).flags & graph::kKeyable, 0u) << "blend shape weights are keyable";
  EXPECT_EQ(skin->attr(sc::kMethod).enum_names, (std::vector<std::string>{"linear", "dualQuaternion"}));
  EXPECT_FALSE(register_deform_types(registry).is_ok()) << "registering twice should fail: the names are taken";
}

// Two joints: root j0 at the origin, j1 its child at (2, 0, 0). Points:
// 0 follows j0, 1 follows j1, 2 is half and half, 3 (the elbow) too.
struct TwoJointRig {
  scene::Scene scene{deform_registry()};
  graph::Graph& g = scene.graph();
  NodeId j0, j1, skin;
  std::vector<Vec3> bind = {Vec3(1, 0, 0), Vec3(3, 0, 0), Vec3(2.5, 0, 0), Vec3(2, 0, 1)};

  TwoJointRig() {
    j0 = scene.create(scene::kJointType, "j0").value();
    j1 = scene.create(scene::kJointType, "j1", j0).value();
    EXPECT_TRUE(g.set_value({j1, scene::xform::kTranslate}, Vec3(2, 0, 0)).is_ok());
    skin = g.create_node(kSkinClusterType, "skin").value();
    const Mat4 j1_bind = scene.world_matrix(j1);
    EXPECT_TRUE(g.set_value({skin, sc::kBindPoints}, bind).is_ok());
    EXPECT_TRUE(
        g.set_value({skin, sc::kBindPreMatrices}, std::vector<Mat4>{Mat4::Identity(), math::affine_inverse(j1_bind)})
            .is_ok());
    EXPECT_TRUE(g.set_value({skin, sc::kInfluenceOffsets}, std::vector<std::int64_t>{0, 1, 2, 4, 6}).is_ok());
    EXPECT_TRUE(g.set_value({skin, sc::kInfluenceJoints}, std::vector<std::int64_t>{0, 1, 0, 1, 0, 1}).is_ok());
    EXPECT_TRUE(g.set_value({skin, sc::kInfluenceWeights}, std::vector<double>{1, 1, 0.5, 0.5, 0.5, 0.5}).is_ok());
    EXPECT_TRUE(g.connect({j0, scene::xform::kWorldMatrix}, {skin, sc::kJointMatrices, 0}).is_ok());
    EXPECT_TRUE(g.connect({j1, scene::xform::kWorldMatrix}, {skin, sc::kJointMatrices, 1}).is_ok());
  }

  std::vector<Vec3> out_points() { return std::get<std::vector<Vec3>>(g.evaluate(skin, sc::kOutPoints)); }
};

TEST(SkinClusterNode, the_bind_pose_gives_the_bind_points) {
  TwoJointRig rig;
  EXPECT_TRUE(points_near(rig.out_points(), rig.bind, 1e-6));
}

TEST(SkinClusterNode, rotating_a_joint_moves_its_points) {
  TwoJointRig rig;
  ASSERT_TRUE(rig.g.set_value({rig.j1, scene::xform::kRotate}, Vec3(0, 0, 90)).is_ok());  // degrees
  // j1 turns 90 degrees about z at (2, 0, 0): (3, 0, 0) -> (2, 1, 0);
  // (2.5, 0, 0) half way: 0.5 (2.5, 0, 0) + 0.5 (2, 0.5, 0).
  EXPECT_TRUE(points_near(rig.out_points(), {Vec3(1, 0, 0), Vec3(2, 1, 0), Vec3(2.25, 0.25, 0), Vec3(2, 0, 1)}, 1e-6))
      << "points on j1 follow it, points on j0 stay";
  ASSERT_TRUE(rig.g.set_value({rig.j0, scene::xform::kTranslate}, Vec3(0, 0, 10)).is_ok());
  EXPECT_TRUE(
      points_near(rig.out_points(), {Vec3(1, 0, 10), Vec3(2, 1, 10), Vec3(2.25, 0.25, 10), Vec3(2, 0, 11)}, 1e-6))
      << "moving the root carries everything (j1's world matrix follows its parent)";
}

TEST(SkinClusterNode, dual_quaternion_keeps_the_radius_that_linear_loses) {
  TwoJointRig rig;
  ASSERT_TRUE(rig.g.set_value({rig.j1, scene::xform::kRotate}, Vec3(180, 0, 0)).is_ok());
  const std::vector<Vec3> linear = rig.out_points();
  EXPECT_NEAR(std::hypot(linear[3].y(), linear[3].z()), 0.0, 1e-6) << "linear: the elbow point collapses onto the axis";
  ASSERT_TRUE(rig.g.set_value({rig.skin, sc::kMethod}, std::int64_t{1}).is_ok());
  const std::vector<Vec3> dual = rig.out_points();
  EXPECT_NEAR(std::hypot(dual[3].y(), dual[3].z()), 1.0, 1e-6) << "dual quaternion: it keeps radius 1";
  EXPECT_TRUE(points_near({dual[0], dual[1]}, {linear[0], linear[1]}, 1e-6)) << "single influences agree";
}

TEST(SkinClusterNode, geom_matrix_puts_the_points_in_the_mesh_space) {
  TwoJointRig rig;
  ASSERT_TRUE(rig.g.set_value({rig.skin, sc::kGeomMatrix}, math::translation_matrix(Vec3(0, 0, 5))).is_ok());
  std::vector<Vec3> expected = rig.bind;
  for (Vec3& p : expected) p.z() -= 5.0;
  EXPECT_TRUE(points_near(rig.out_points(), expected, 1e-6))
      << "the inverse of the mesh's world matrix is applied last";
}

TEST(SkinClusterNode, normals_are_skinned_when_given) {
  TwoJointRig rig;
  EXPECT_TRUE(std::get<std::vector<Vec3>>(rig.g.evaluate(rig.skin, sc::kOutNormals)).empty())
      << "no bind normals, no normals";
  ASSERT_TRUE(rig.g.set_value({rig.skin, sc::kBindNormals}, std::vector<Vec3>(4, Vec3(1, 0, 0))).is_ok());
  ASSERT_TRUE(rig.g.set_value({rig.j1, scene::xform::kRotate}, Vec3(0, 0, 90)).is_ok());
  const auto& normals = std::get<std::vector<Vec3>>(rig.g.evaluate(rig.skin, sc::kOutNormals));
  ASSERT_EQ(normals.size(), 4u);
  EXPECT_TRUE(points_near({normals[0], normals[1]}, {Vec3(1, 0, 0), Vec3(0, 1, 0)}, 1e-6));
  EXPECT_NEAR(normals[2].norm(), 1.0, 1e-6) << "a blended normal is normalised";
}

TEST(SkinClusterNode, passes_points_through_when_the_weights_do_not_validate) {
  TwoJointRig rig;
  ASSERT_TRUE(rig.g.set_value({rig.j1, scene::xform::kRotate}, Vec3(0, 0, 90)).is_ok());
  ASSERT_TRUE(rig.g.set_value({rig.skin, sc::kInfluenceJoints}, std::vector<std::int64_t>{0, 7, 0, 1, 0, 1}).is_ok());
  EXPECT_TRUE(points_near(rig.out_points(), rig.bind, 0.0)) << "joint 7 does not exist: the rest shape shows";
  ASSERT_TRUE(rig.g.set_value({rig.skin, sc::kInfluenceJoints}, std::vector<std::int64_t>{0, 1, 0, 1, 0, 1}).is_ok());
  ASSERT_TRUE(rig.g.set_value({rig.skin, sc::kBindPoints}, std::vector<Vec3>(3, Vec3::Zero())).is_ok());
  EXPECT_EQ(rig.out_points().size(), 3u) << "3 points for 4 influence lists: passed through";
}

TEST(SkinClusterNode, a_new_skin_cluster_outputs_nothing) {
  scene::Scene scene(deform_registry());
  const NodeId skin = scene.graph().create_node(kSkinClusterType, "skin").value();
  EXPECT_TRUE(std::get<std::vector<Vec3>>(scene.graph().evaluate(skin, sc::kOutPoints)).empty());
}

// The node keeps its compiled skin and bind points between evaluations: every
// way its inputs can change after a first evaluation (a set, an undo, a redo,
// a connection feeding them) must show in the next result.
TEST(SkinClusterNode, edits_after_an_evaluation_rebuild_what_the_node_keeps) {
  TwoJointRig rig;
  ASSERT_TRUE(rig.g.set_value({rig.j1, scene::xform::kRotate}, Vec3(0, 0, 90)).is_ok());
  const std::vector<Vec3> posed = {Vec3(1, 0, 0), Vec3(2, 1, 0), Vec3(2.25, 0.25, 0), Vec3(2, 0, 1)};
  ASSERT_TRUE(points_near(rig.out_points(), posed, 1e-6));

  // Point 0 moves from j0 to j1: (1, 0, 0) is (-1, 0, 0) from j1, turned to (2, -1, 0).
  ASSERT_TRUE(rig.g.set_value({rig.skin, sc::kInfluenceJoints}, std::vector<std::int64_t>{1, 1, 0, 1, 0, 1}).is_ok());
  std::vector<Vec3> moved = posed;
  moved[0] = Vec3(2, -1, 0);
  EXPECT_TRUE(points_near(rig.out_points(), moved, 1e-6)) << "new influence joints";
  ASSERT_TRUE(rig.g.undo());
  EXPECT_TRUE(points_near(rig.out_points(), posed, 1e-6)) << "undo of the joints";
  ASSERT_TRUE(rig.g.redo());
  EXPECT_TRUE(points_near(rig.out_points(), moved, 1e-6)) << "redo of the joints";
  ASSERT_TRUE(rig.g.undo());

  ASSERT_TRUE(rig.g.set_value({rig.skin, sc::kInfluenceWeights}, std::vector<double>{1, 1, 1, 0, 0.5, 0.5}).is_ok());
  std::vector<Vec3> reweighted = posed;
  reweighted[2] = Vec3(2.5, 0, 0);
  EXPECT_TRUE(points_near(rig.out_points(), reweighted, 1e-6)) << "new weights";
  // Point 1 half on each joint, point 2 on j1 alone.
  ASSERT_TRUE(rig.g.set_value({rig.skin, sc::kInfluenceOffsets}, std::vector<std::int64_t>{0, 1, 3, 4, 5}).is_ok());
  ASSERT_TRUE(rig.g.set_value({rig.skin, sc::kInfluenceJoints}, std::vector<std::int64_t>{0, 0, 1, 1, 0}).is_ok());
  ASSERT_TRUE(rig.g.set_value({rig.skin, sc::kInfluenceWeights}, std::vector<double>{1, 0.5, 0.5, 1, 1}).is_ok());
  const std::vector<Vec3> reshaped = {Vec3(1, 0, 0), Vec3(2.5, 0.5, 0), Vec3(2, 0.5, 0), Vec3(2, 0, 1)};
  EXPECT_TRUE(points_near(rig.out_points(), reshaped, 1e-6)) << "new offsets";

  ASSERT_TRUE(rig.g.set_value({rig.skin, sc::kBindPoints}, std::vector<Vec3>{Vec3(1, 0, 0), Vec3(4, 0, 0),
                                                                              Vec3(2.5, 0, 0), Vec3(2, 0, 1)})
                  .is_ok());
  std::vector<Vec3> rebound = reshaped;
  rebound[1] = Vec3(3, 1, 0);  // half (4, 0, 0), half (2, 2, 0)
  EXPECT_TRUE(points_near(rig.out_points(), rebound, 1e-6)) << "new bind points";
  ASSERT_TRUE(rig.g.undo());
  EXPECT_TRUE(points_near(rig.out_points(), reshaped, 1e-6)) << "undo of the bind points";
}

TEST(SkinClusterNode, bind_points_fed_by_a_blend_shape_follow_its_weights) {
  TwoJointRig rig;
  const NodeId blend = rig.g.create_node(kBlendShapeType, "shapes").value();
  ASSERT_TRUE(rig.g.set_value({blend, bs::kBasePoints}, rig.bind).is_ok());
  ASSERT_TRUE(rig.g.set_value({blend, bs::kTargetDeltas}, std::vector<Vec3>{Vec3(0, 0, 1)}).is_ok());
  ASSERT_TRUE(rig.g.set_value({blend, bs::kTargetOffsets}, std::vector<std::int64_t>{0, 1}).is_ok());
  ASSERT_TRUE(rig.g.set_value({blend, bs::kTargetIndices}, std::vector<std::int64_t>{1}).is_ok());
  ASSERT_TRUE(rig.g.connect({blend, bs::kOutPoints}, {rig.skin, sc::kBindPoints}).is_ok());
  ASSERT_TRUE(rig.g.set_value({rig.j1, scene::xform::kRotate}, Vec3(0, 0, 90)).is_ok());
  const std::vector<Vec3> posed = {Vec3(1, 0, 0), Vec3(2, 1, 0), Vec3(2.25, 0.25, 0), Vec3(2, 0, 1)};
  EXPECT_TRUE(points_near(rig.out_points(), posed, 1e-6)) << "weight 0: the base";
  ASSERT_TRUE(rig.g.set_value({blend, bs::kWeights}, std::vector<double>{2.0}).is_ok());
  std::vector<Vec3> lifted = posed;
  lifted[1] = Vec3(2, 1, 2);  // (3, 0, 2) on j1, turned about z at (2, 0, 0)
  EXPECT_TRUE(points_near(rig.out_points(), lifted, 1e-6)) << "the shape moves the skinned point";
  ASSERT_TRUE(rig.g.undo());
  EXPECT_TRUE(points_near(rig.out_points(), posed, 1e-6)) << "undo of the weight";
}

struct BlendShapeRig {
  scene::Scene scene{deform_registry()};
  graph::Graph& g = scene.graph();
  NodeId node = g.create_node(kBlendShapeType, "face").value();

  BlendShapeRig() {
    EXPECT_TRUE(g.set_value({node, bs::kBasePoints}, std::vector<Vec3>{Vec3(1, 1, 1), Vec3(1, 1, 1)}).is_ok());
    // Dense: target 0 = (2,0,0) (0,0,0); target 1 = (0,0,8) (0,4,0).
    EXPECT_TRUE(g.set_value({node, bs::kTargetDeltas},
                            std::vector<Vec3>{Vec3(2, 0, 0), Vec3(0, 0, 0), Vec3(0, 0, 8), Vec3(0, 4, 0)})
                    .is_ok());
    EXPECT_TRUE(g.set_value({node, bs::kTargetOffsets}, std::vector<std::int64_t>{0, 2, 4}).is_ok());
  }
  std::vector<Vec3> out() { return std::get<std::vector<Vec3>>(g.evaluate(node, bs::kOutPoints)); }
};

TEST(BlendShapeNode, weights_0_1_and_half_blend_two_targets) {
  BlendShapeRig rig;
  EXPECT_TRUE(points_near(rig.out(), {Vec3(1, 1, 1), Vec3(1, 1, 1)}, 0.0)) << "no weights: every target at 0";
  ASSERT_TRUE(rig.g.set_value({rig.node, bs::kWeights}, std::vector<double>{1.0, 0.0}).is_ok());
  EXPECT_TRUE(points_near(rig.out(), {Vec3(3, 1, 1), Vec3(1, 1, 1)}, 0.0)) << "target 0 at 1";
  ASSERT_TRUE(rig.g.set_value({rig.node, bs::kWeights}, std::vector<double>{0.5, 0.5}).is_ok());
  EXPECT_TRUE(points_near(rig.out(), {Vec3(2, 1, 5), Vec3(1, 3, 1)}, 0.0)) << "both at 0.5";
  ASSERT_TRUE(rig.g.set_value({rig.node, bs::kWeights, 1}, Value(1.0)).is_ok());
  EXPECT_TRUE(points_near(rig.out(), {Vec3(2, 1, 9), Vec3(1, 5, 1)}, 0.0)) << "one element set on its own";
}

TEST(BlendShapeNode, sparse_targets_give_the_dense_result) {
  BlendShapeRig rig;
  ASSERT_TRUE(
      rig.g.set_value({rig.node, bs::kTargetDeltas}, std::vector<Vec3>{Vec3(2, 0, 0), Vec3(0, 4, 0), Vec3(0, 0, 8)})
          .is_ok());
  ASSERT_TRUE(rig.g.set_value({rig.node, bs::kTargetOffsets}, std::vector<std::int64_t>{0, 1, 3}).is_ok());
  ASSERT_TRUE(rig.g.set_value({rig.node, bs::kTargetIndices}, std::vector<std::int64_t>{0, 1, 0}).is_ok());
  ASSERT_TRUE(rig.g.set_value({rig.node, bs::kWeights}, std::vector<double>{0.5, 0.5}).is_ok());
  EXPECT_TRUE(points_near(rig.out(), {Vec3(2, 1, 5), Vec3(1, 3, 1)}, 0.0));
}

TEST(BlendShapeNode, passes_points_through_on_bad_targets) {
  BlendShapeRig rig;
  ASSERT_TRUE(rig.g.set_value({rig.node, bs::kWeights}, std::vector<double>{1.0, 1.0}).is_ok());
  ASSERT_TRUE(rig.g.set_value({rig.node, bs::kTargetOffsets}, std::vector<std::int64_t>{0, 3, 4}).is_ok());
  EXPECT_TRUE(points_near(rig.out(), {Vec3(1, 1, 1), Vec3(1, 1, 1)}, 0.0))
      << "a dense target of 3 deltas for 2 points does not build: the base shows";
  ASSERT_TRUE(rig.g.set_value({rig.node, bs::kTargetOffsets}, std::vector<std::int64_t>{0, 2, 5}).is_ok());
  EXPECT_TRUE(points_near(rig.out(), {Vec3(1, 1, 1), Vec3(1, 1, 1)}, 0.0)) << "offsets past the deltas";
}

// The node keeps its compiled targets: changing them after a first
// evaluation (a set, an undo, a new base size) must show in the next result.
TEST(BlendShapeNode, edits_after_an_evaluation_rebuild_the_targets) {
  BlendShapeRig rig;
  ASSERT_TRUE(rig.g.set_value({rig.node, bs::kWeights}, std::vector<double>{1.0, 0.5}).is_ok());
  EXPECT_TRUE(points_near(rig.out(), {Vec3(3, 1, 5), Vec3(1, 3, 1)}, 0.0));
  ASSERT_TRUE(rig.g.set_value({rig.node, bs::kTargetDeltas},
                              std::vector<Vec3>{Vec3(4, 0, 0), Vec3(0, 0, 0), Vec3(0, 0, 8), Vec3(0, 4, 0)})
                  .is_ok());
  EXPECT_TRUE(points_near(rig.out(), {Vec3(5, 1, 5), Vec3(1, 3, 1)}, 0.0)) << "new deltas";
  ASSERT_TRUE(rig.g.undo());
  EXPECT_TRUE(points_near(rig.out(), {Vec3(3, 1, 5), Vec3(1, 3, 1)}, 0.0)) << "undo of the deltas";
  ASSERT_TRUE(rig.g.set_value({rig.node, bs::kTargetOffsets}, std::vector<std::int64_t>{0, 4}).is_ok());
  EXPECT_TRUE(points_near(rig.out(), {Vec3(1, 1, 1), Vec3(1, 1, 1)}, 0.0))
      << "offsets that no longer fit the base: passed through";
  ASSERT_TRUE(rig.g.set_value({rig.node, bs::kBasePoints},
                              std::vector<Vec3>{Vec3(1, 1, 1), Vec3(1, 1, 1), Vec3(0, 0, 0), Vec3(0, 0, 0)})
                  .is_ok());
  EXPECT_TRUE(points_near(rig.out(), {Vec3(3, 1, 1), Vec3(1, 1, 1), Vec3(0, 0, 8), Vec3(0, 4, 0)}, 0.0))
      << "a base of 4 points: the one 4-delta target now fits (weight 1)";
}

}  // namespace
}  // namespace rigel::ops
