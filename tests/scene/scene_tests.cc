#include "rigel/scene/scene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "rigel/math/transform.h"
#include "rigel/scene/transform_types.h"
#include "scene_test_util.h"
#include "../support/slow_build.h"

namespace rigel::scene {
namespace {

using graph::Plug;
using graph::Value;
using math::Quat;
using math::Vec3;
using testing::matrix_near;
using testing::rows;
using testing::set;

NodeId make(Scene& scene, std::string_view type, std::string_view name, NodeId parent = NodeId{}) {
  Result<NodeId> id = scene.create(type, name, parent);
  EXPECT_TRUE(id.is_ok()) << "creating " << name << ": " << id.status().message();
  return id.is_ok() ? *id : NodeId{};
}

// ---- types -------------------------------------------------------------------

TEST(SceneTypes, every_type_shares_the_transform_prefix) {
  auto registry = default_registry();
  static const char* kNames[] = {"translate", "rotate", "rotateOrder", "rotateMode", "rotateQuaternion",
                                 "scale", "shear", "rotateAxis", "rotatePivot", "rotatePivotTranslate",
                                 "scalePivot", "scalePivotTranslate", "offsetParentMatrix", "parentMatrix",
                                 "visibility", "matrix", "worldMatrix"};
  static_assert(sizeof(kNames) / sizeof(kNames[0]) == xform::kCount, "one name per shared attribute");
  for (const char* type : {kTransformType, kJointType, kControlType, kLocatorType, kMeshType}) {
    const graph::NodeType* t = registry->find(type);
    ASSERT_NE(t, nullptr) << type << " is registered";
    EXPECT_TRUE(is_transform_type(*t)) << type << " is a transform type";
    for (AttrIndex i = 0; i < xform::kCount; ++i)
      EXPECT_EQ(t->attr(i).name, kNames[i]) << type << ": shared attribute " << i << " is at its constant index";
    EXPECT_EQ(t->parent_input(), xform::kParentMatrix) << type << " is parented through parentMatrix";
    EXPECT_EQ(t->world_output(), xform::kWorldMatrix) << type << " parents through worldMatrix";
  }
  EXPECT_EQ(registry->find(kJointType)->attr(joint_attr::kJointOrient).name, "jointOrient") << "joint constants";
  EXPECT_EQ(registry->find(kControlType)->attr(control_attr::kShapeColor).name, "shapeColor") << "control constants";
  EXPECT_EQ(registry->find(kLocatorType)->attr(locator_attr::kLocalScale).name, "localScale") << "locator constants";
  EXPECT_EQ(registry->find(kMeshType)->attr(mesh_attr::kTriangles).name, "triangles") << "mesh constants";
  EXPECT_EQ(std::get<Vec3>(registry->find(kJointType)->default_value(xform::kScale)), Vec3::Ones())
      << "scale defaults to 1 1 1";
  graph::Registry again;
  ASSERT_TRUE(register_scene_types(again).is_ok()) << "the scene types register in a fresh registry";
  EXPECT_FALSE(register_scene_types(again).is_ok()) << "but not twice";
}

// ---- hierarchy ---------------------------------------------------------------

TEST(Scene, create__with_parent_is_one_undo_step) {
  Scene scene;
  NodeId root = make(scene, kJointType, "root");
  NodeId child = make(scene, kJointType, "child", root);
  EXPECT_EQ(scene.graph().parent(child), root) << "created under its parent";
  EXPECT_EQ(scene.graph().undo_count(), 2u) << "each create (with its parenting) is one step";
  ASSERT_TRUE(scene.graph().undo()) << "undo";
  EXPECT_FALSE(scene.graph().find("child").is_valid()) << "undo removes the node and its parenting together";
  EXPECT_TRUE(scene.graph().children(root).empty()) << "the parent has no child left";

  Result<NodeId> bad_type = scene.create("nope", "x");
  EXPECT_FALSE(bad_type.is_ok()) << "an unknown type is refused";
  NodeId gone = make(scene, kJointType, "gone");
  ASSERT_TRUE(scene.graph().delete_node(gone).is_ok()) << "delete";
  const std::size_t count = scene.graph().node_count();
  Result<NodeId> stale_parent = scene.create(kJointType, "orphan", gone);
  EXPECT_FALSE(stale_parent.is_ok()) << "a stale parent is refused";
  EXPECT_EQ(scene.graph().node_count(), count) << "and the node is not left behind";
  EXPECT_FALSE(scene.graph().find("orphan").is_valid()) << "the refused create was rolled back";
}

TEST(Scene, roots_hierarchy_and_depth) {
  Scene scene;
  NodeId a = make(scene, kJointType, "a");
  NodeId b = make(scene, kTransformType, "b");
  NodeId a2 = make(scene, kJointType, "a2", a);
  NodeId a1 = make(scene, kJointType, "a1", a);
  NodeId a21 = make(scene, kControlType, "a21", a2);
  NodeId b1 = make(scene, kLocatorType, "b1", b);
  NodeId a11 = make(scene, kMeshType, "a11", a1);
  EXPECT_EQ(scene.roots(), (std::vector<NodeId>{a, b})) << "roots in creation order";
  EXPECT_EQ(scene.hierarchy(), (std::vector<NodeId>{a, a2, a21, a1, a11, b, b1}))
      << "depth first, parents before children, siblings in creation order";
  EXPECT_EQ(scene.depth(a), 0) << "a root is at depth 0";
  EXPECT_EQ(scene.depth(a2), 1) << "a child is at depth 1";
  EXPECT_EQ(scene.depth(a21), 2) << "a grandchild is at depth 2";
  EXPECT_TRUE(scene.is_transform(a11)) << "a mesh is a transform";
  EXPECT_FALSE(scene.is_transform(NodeId{})) << "an invalid id is not";

  ASSERT_TRUE(scene.reparent(a2, b1, false).is_ok()) << "move a2's subtree under b1";
  EXPECT_EQ(scene.hierarchy(), (std::vector<NodeId>{a, a1, a11, b, b1, a2, a21})) << "the subtree moved";
  EXPECT_EQ(scene.depth(a21), 3) << "and got deeper";
  ASSERT_TRUE(scene.reparent(a, NodeId{}, false).is_ok()) << "unparenting a root is a no-op";
  ASSERT_TRUE(scene.reparent(a1, NodeId{}, false).is_ok()) << "unparent a1";
  EXPECT_EQ(scene.roots(), (std::vector<NodeId>{a, b, a1})) << "roots stay in creation order";
}

// ---- world matrices ------------------------------------------------------------

TEST(Scene, matrices_of_a_node_that_is_not_a_transform_are_the_identity) {
  Scene scene;
  EXPECT_TRUE(scene.world_matrix(NodeId{}).isIdentity(0.0)) << "no such node: no exception, the identity";
  EXPECT_TRUE(scene.local_matrix(NodeId{}).isIdentity(0.0));
}

TEST(Scene, world_matrix__three_joint_chain_matches_hand_computation) {
  Scene scene;
  NodeId j0 = make(scene, kJointType, "j0");
  NodeId j1 = make(scene, kJointType, "j1", j0);
  NodeId j2 = make(scene, kJointType, "j2", j1);
  ASSERT_TRUE(testing::succeeded(set(scene, j0, xform::kTranslate, Vec3(1, 0, 0)))) << "test setup";
  ASSERT_TRUE(testing::succeeded(set(scene, j0, xform::kRotate, Vec3(0, 0, 90)))) << "test setup";
  ASSERT_TRUE(testing::succeeded(set(scene, j1, xform::kTranslate, Vec3(2, 0, 0)))) << "test setup";
  ASSERT_TRUE(testing::succeeded(set(scene, j1, xform::kRotate, Vec3(90, 0, 0)))) << "test setup";
  ASSERT_TRUE(testing::succeeded(set(scene, j2, xform::kTranslate, Vec3(0, 3, 0)))) << "test setup";
  ASSERT_TRUE(testing::succeeded(set(scene, j2, xform::kScale, Vec3(2, 2, 2)))) << "test setup";

  // j0 = T(1,0,0) Rz(90); j1 = j0 T(2,0,0) Rx(90); j2 = j1 T(0,3,0) S(2).
  const Mat4 w0 = rows({0, -1, 0, 1, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1});
  const Mat4 w1 = rows({0, 0, 1, 1, 1, 0, 0, 2, 0, 1, 0, 0, 0, 0, 0, 1});
  const Mat4 w2 = rows({0, 0, 2, 1, 2, 0, 0, 2, 0, 2, 0, 3, 0, 0, 0, 1});
  EXPECT_TRUE(matrix_near(scene.world_matrix(j0), w0, 1e-14)) << "root world = its local";
  EXPECT_TRUE(matrix_near(scene.world_matrix(j1), w1, 1e-14)) << "child world = parent world * local";
  EXPECT_TRUE(matrix_near(scene.world_matrix(j2), w2, 1e-14)) << "grandchild, with scale";
  EXPECT_TRUE(matrix_near(scene.local_matrix(j2), rows({2, 0, 0, 0, 0, 2, 0, 3, 0, 0, 2, 0, 0, 0, 0, 1}), 1e-15))
      << "local_matrix is the node's own channels only";

  ASSERT_TRUE(set(scene, j0, xform::kTranslate, Vec3(0, 0, 0)).is_ok()) << "move the root";
  Mat4 moved = w2;
  moved(0, 3) -= 1.0;
  EXPECT_TRUE(matrix_near(scene.world_matrix(j2), moved, 1e-14)) << "a root edit reaches the grandchild";
}

TEST(Scene, world_matrix__rotate_order_is_applied) {
  Scene scene;
  NodeId j = make(scene, kJointType, "j");
  ASSERT_TRUE(testing::succeeded(set(scene, j, xform::kRotate, Vec3(90, 0, 90)))) << "test setup";
  EXPECT_TRUE(matrix_near(scene.world_matrix(j), rows({0, 0, 1, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 1}), 1e-15))
      << "xyz: rotate about X first, then Z: Rz(90) Rx(90)";
  ASSERT_TRUE(set(scene, j, xform::kRotateOrder, std::int64_t{5}).is_ok()) << "zyx";
  EXPECT_TRUE(matrix_near(scene.world_matrix(j), rows({0, -1, 0, 0, 0, 0, -1, 0, 1, 0, 0, 0, 0, 0, 0, 1}), 1e-15))
      << "zyx: rotate about Z first, then X: Rx(90) Rz(90)";
  ASSERT_TRUE(set(scene, j, xform::kRotateMode, std::int64_t{1}).is_ok()) << "quaternion mode";
  EXPECT_TRUE(matrix_near(scene.world_matrix(j), Mat4::Identity(), 1e-15))
      << "quaternion mode ignores the euler angles and uses rotateQuaternion (identity)";
  ASSERT_TRUE(testing::succeeded(set(scene, j, xform::kRotateQuaternion, Quat(Eigen::AngleAxisd(math::kPi / 2, Vec3::UnitX()))))) << "test setup";
  EXPECT_TRUE(matrix_near(scene.world_matrix(j), rows({1, 0, 0, 0, 0, 0, -1, 0, 0, 1, 0, 0, 0, 0, 0, 1}), 1e-15))
      << "a quaternion of 90 degrees about X";
}

TEST(Scene, world_matrix__joint_orient_is_applied) {
  Scene scene;
  NodeId j = make(scene, kJointType, "j");
  const AttrIndex jo = joint_attr::kJointOrient;
  ASSERT_TRUE(set(scene, j, jo, Vec3(0, 0, 90)).is_ok()) << "orient only";
  EXPECT_TRUE(matrix_near(scene.world_matrix(j), rows({0, -1, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}), 1e-15))
      << "a joint orient of 90 about Z rotates like rotate (0,0,90)";
  ASSERT_TRUE(set(scene, j, xform::kRotate, Vec3(90, 0, 0)).is_ok()) << "orient and rotate";
  ASSERT_TRUE(set(scene, j, xform::kTranslate, Vec3(1, 2, 3)).is_ok()) << "and translate";
  EXPECT_TRUE(matrix_near(scene.world_matrix(j), rows({0, 0, 1, 1, 1, 0, 0, 2, 0, 1, 0, 3, 0, 0, 0, 1}), 1e-15))
      << "local = T * JO * R: the orient applies after (outside) the rotation";
  ASSERT_TRUE(testing::succeeded(set(scene, j, xform::kRotate, Vec3(0, 0, 0)))) << "test setup";
  ASSERT_TRUE(set(scene, j, jo, Vec3(90, 0, 90)).is_ok()) << "orient in two axes";
  EXPECT_TRUE(matrix_near(scene.world_matrix(j), rows({0, 0, 1, 1, 1, 0, 0, 2, 0, 1, 0, 3, 0, 0, 0, 1}), 1e-15))
      << "the joint orient is Euler XYZ: Rz(90) Rx(90)";

  NodeId t = make(scene, kTransformType, "t");
  EXPECT_EQ(scene.graph().node(t)->type().attr_find("jointOrient"), graph::kNoAttr)
      << "only joints have a joint orient";
}

TEST(Scene, world_matrix__offset_parent_matrix_sits_between_parent_and_local) {
  Scene scene;
  NodeId p = make(scene, kTransformType, "p");
  NodeId c = make(scene, kJointType, "c", p);
  ASSERT_TRUE(testing::succeeded(set(scene, p, xform::kTranslate, Vec3(1, 0, 0)))) << "test setup";
  Mat4 offset = rows({0, -1, 0, 0, 1, 0, 0, 5, 0, 0, 1, 0, 0, 0, 0, 1});  // T(0,5,0) Rz(90)
  ASSERT_TRUE(testing::succeeded(set(scene, c, xform::kOffsetParentMatrix, offset))) << "test setup";
  ASSERT_TRUE(testing::succeeded(set(scene, c, xform::kTranslate, Vec3(1, 0, 0)))) << "test setup";
  // world = T(1,0,0) * T(0,5,0) Rz(90) * T(1,0,0)
  EXPECT_TRUE(matrix_near(scene.world_matrix(c), rows({0, -1, 0, 1, 1, 0, 0, 6, 0, 0, 1, 0, 0, 0, 0, 1}), 1e-15))
      << "world = parent * offsetParent * local";
  EXPECT_TRUE(matrix_near(scene.local_matrix(c), rows({1, 0, 0, 1, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}), 1e-15))
      << "the local matrix leaves the offset parent matrix out";
  ASSERT_TRUE(set(scene, p, xform::kOffsetParentMatrix, offset).is_ok()) << "offset on the root too";
  EXPECT_TRUE(matrix_near(scene.world_matrix(p), rows({0, -1, 0, 0, 1, 0, 0, 6, 0, 0, 1, 0, 0, 0, 0, 1}), 1e-15))
      << "a root's offset parent matrix applies outside its local: T(0,5,0) Rz(90) T(1,0,0)";
  EXPECT_TRUE(matrix_near(scene.world_matrix(c), rows({-1, 0, 0, -6, 0, -1, 0, 6, 0, 0, 1, 0, 0, 0, 0, 1}), 1e-14))
      << "and the child follows: Pworld * offset * local";
}

TEST(Scene, frame__converts_with_fps) {
  Scene scene;
  scene.set_frame(48.0);
  EXPECT_EQ(scene.graph().time(), 2.0) << "frame 48 at 24 fps is 2 s";
  EXPECT_EQ(scene.frame(), 48.0) << "and back";
  ASSERT_TRUE(scene.graph().set_fps(30.0).is_ok()) << "30 fps";
  EXPECT_EQ(scene.frame(), 60.0) << "the time stays, the frame follows the rate";
}

// ---- reparent -------------------------------------------------------------------

TEST(Scene, reparent__keep_world_keeps_the_world_matrix) {
  for (std::uint32_t seed = 1; seed <= 40; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    Scene scene;
    testing::ChannelOptions options;
    options.pivots = false;  // keep_world refuses pivots on the child; parents may have them below
    std::vector<NodeId> ids = testing::random_forest(scene, seed, 30, options);
    std::mt19937 rng(seed);
    // Give some nodes pivots: they may be parents, never a moved child.
    std::vector<bool> has_pivots(ids.size(), false);
    for (std::size_t i = 0; i < ids.size(); i += 5) {
      ASSERT_TRUE(testing::succeeded(set(scene, ids[i], xform::kRotatePivot, Vec3(0.5, -0.25, 1)))) << "test setup";
      has_pivots[i] = true;
    }
    for (int move = 0; move < 20; ++move) {
      const std::size_t ci = std::uniform_int_distribution<std::size_t>(0, ids.size() - 1)(rng);
      if (has_pivots[ci]) continue;
      NodeId child = ids[ci];
      NodeId parent;
      if (std::bernoulli_distribution(0.85)(rng)) parent = ids[std::uniform_int_distribution<std::size_t>(0, ids.size() - 1)(rng)];
      // Skip parents inside the child's subtree: refused as cycles (tested below).
      bool inside = false;
      for (NodeId p = parent; p.is_valid(); p = scene.graph().parent(p)) inside |= p == child;
      if (inside) continue;
      const Mat4 before = scene.world_matrix(child);
      const graph::Value orient_before =
          scene.graph().node(child)->type().attr_find("jointOrient") == graph::kNoAttr
              ? graph::Value()
              : scene.graph().node(child)->value(joint_attr::kJointOrient);
      Status s = scene.reparent(child, parent, true);
      ASSERT_TRUE(s.is_ok()) << s.message();
      EXPECT_EQ(scene.graph().parent(child), parent) << "the child moved under its new parent";
      EXPECT_TRUE(matrix_near(scene.world_matrix(child), before, 1e-9))
          << "keep_world leaves the world matrix where it was (move " << move << ")";
      if (!std::holds_alternative<std::monostate>(orient_before)) {
        EXPECT_TRUE(graph::values_identical(scene.graph().node(child)->value(joint_attr::kJointOrient), orient_before))
            << "a joint keeps its joint orient; the rotation absorbs the difference";
      }
    }
  }
}

TEST(Scene, reparent__keep_world_is_one_undo_step) {
  Scene scene;
  NodeId p = make(scene, kTransformType, "p");
  NodeId c = make(scene, kJointType, "c");
  ASSERT_TRUE(testing::succeeded(set(scene, p, xform::kTranslate, Vec3(1, 2, 3)))) << "test setup";
  ASSERT_TRUE(testing::succeeded(set(scene, p, xform::kRotate, Vec3(10, 20, 30)))) << "test setup";
  ASSERT_TRUE(testing::succeeded(set(scene, c, xform::kTranslate, Vec3(-1, 0, 4)))) << "test setup";
  const Mat4 world = scene.world_matrix(c);
  const std::size_t steps = scene.graph().undo_count();
  ASSERT_TRUE(scene.reparent(c, p, true).is_ok()) << "reparent";
  EXPECT_EQ(scene.graph().undo_count(), steps + 1) << "parenting and the channel edits are one step";
  EXPECT_FALSE(std::get<Vec3>(scene.graph().node(c)->value(xform::kTranslate)).isApprox(Vec3(-1, 0, 4)))
      << "the local channels were rewritten";
  ASSERT_TRUE(scene.graph().undo()) << "undo";
  EXPECT_FALSE(scene.graph().parent(c).is_valid()) << "undo unparents";
  EXPECT_EQ(std::get<Vec3>(scene.graph().node(c)->value(xform::kTranslate)), Vec3(-1, 0, 4))
      << "and restores the channels exactly";
  EXPECT_TRUE(matrix_near(scene.world_matrix(c), world, 1e-15)) << "back where it was";
}

TEST(Scene, reparent__under_the_current_parent_changes_nothing) {
  Scene scene;
  NodeId p = make(scene, kTransformType, "p");
  NodeId c = make(scene, kJointType, "c", p);
  ASSERT_TRUE(testing::succeeded(set(scene, p, xform::kRotate, Vec3(10, 20, 30)))) << "test setup";
  ASSERT_TRUE(testing::succeeded(set(scene, p, xform::kScale, Vec3(1, 2, 3)))) << "test setup";
  ASSERT_TRUE(testing::succeeded(set(scene, c, xform::kTranslate, Vec3(0.1, 0.2, 0.3)))) << "test setup";
  ASSERT_TRUE(testing::succeeded(set(scene, c, xform::kRotate, Vec3(33, 44, 55)))) << "test setup";
  const graph::Value translate = scene.graph().node(c)->value(xform::kTranslate);
  const graph::Value rotate = scene.graph().node(c)->value(xform::kRotate);
  const std::size_t steps = scene.graph().undo_count();
  for (int i = 0; i < 3; ++i) {
    ASSERT_TRUE(scene.reparent(c, p, true).is_ok()) << "reparenting under the current parent is fine";
    ASSERT_TRUE(scene.reparent(p, NodeId{}, true).is_ok()) << "and so is keeping a root a root";
  }
  EXPECT_TRUE(graph::values_identical(scene.graph().node(c)->value(xform::kTranslate), translate))
      << "the channels are not rewritten (no rounding drift from decomposing a matrix that did not move)";
  EXPECT_TRUE(graph::values_identical(scene.graph().node(c)->value(xform::kRotate), rotate))
      << "the rotation is not rewritten either";
  EXPECT_EQ(scene.graph().undo_count(), steps) << "and no undo step is recorded for a no-op";
}

TEST(Scene, reparent__keep_world_refuses_pivots_and_rotate_axis) {
  Scene scene;
  NodeId p = make(scene, kTransformType, "p");
  NodeId c = make(scene, kJointType, "c");
  ASSERT_TRUE(testing::succeeded(set(scene, p, xform::kTranslate, Vec3(1, 0, 0)))) << "test setup";
  for (AttrIndex a : {xform::kRotateAxis, xform::kRotatePivot, xform::kRotatePivotTranslate, xform::kScalePivot,
                      xform::kScalePivotTranslate}) {
    const std::string name = scene.graph().node(c)->type().attr(a).name;
    SCOPED_TRACE(name);
    ASSERT_TRUE(testing::succeeded(set(scene, c, a, Vec3(0, 0.5, 0)))) << "test setup";
    const std::size_t steps = scene.graph().undo_count();
    Status s = scene.reparent(c, p, true);
    EXPECT_EQ(s.code(), ErrorCode::kInvalidArgument) << "keep_world with a non-zero " << name << " is refused";
    EXPECT_NE(s.message().find(name), std::string::npos) << "the message names " << name << ": " << s.message();
    EXPECT_FALSE(scene.graph().parent(c).is_valid()) << "the refused reparent changed nothing";
    EXPECT_EQ(scene.graph().undo_count(), steps) << "and recorded nothing";
    ASSERT_TRUE(testing::succeeded(set(scene, c, a, Vec3(0, 0, 0)))) << "test setup";
  }
  ASSERT_TRUE(testing::succeeded(set(scene, c, xform::kRotatePivot, Vec3(1, 1, 1)))) << "test setup";
  EXPECT_TRUE(scene.reparent(c, p, false).is_ok()) << "without keep_world, pivots are no obstacle";
  EXPECT_EQ(scene.graph().parent(c), p) << "parented";
}

TEST(Scene, reparent__refuses_cycles_and_non_transforms) {
  Scene scene;
  NodeId a = make(scene, kJointType, "a");
  NodeId b = make(scene, kJointType, "b", a);
  NodeId c = make(scene, kJointType, "c", b);
  ASSERT_TRUE(testing::succeeded(set(scene, a, xform::kTranslate, Vec3(1, 0, 0)))) << "test setup";
  const Vec3 translate = std::get<Vec3>(scene.graph().node(a)->value(xform::kTranslate));
  for (bool keep : {false, true}) {
    Status s = scene.reparent(a, c, keep);
    EXPECT_EQ(s.code(), ErrorCode::kCycle) << "a node cannot go under its grandchild: " << s.message();
    EXPECT_FALSE(scene.graph().parent(a).is_valid()) << "still a root";
    EXPECT_EQ(std::get<Vec3>(scene.graph().node(a)->value(xform::kTranslate)), translate) << "channels untouched";
  }
  // A driven channel cannot be rewritten: the whole reparent is rolled back.
  NodeId driver = make(scene, kLocatorType, "driver");
  ASSERT_TRUE(scene.graph()
                  .connect(graph::Plug{driver, xform::kTranslate, -1}, graph::Plug{c, xform::kTranslate, -1})
                  .is_ok())
      << "drive c.translate";
  ASSERT_TRUE(set(scene, driver, xform::kTranslate, Vec3(0, 1, 0)).is_ok()) << "move the driver";
  const std::size_t steps = scene.graph().undo_count();
  Status driven = scene.reparent(c, NodeId{}, true);
  EXPECT_FALSE(driven.is_ok()) << "keep_world cannot rewrite a connected translate";
  EXPECT_EQ(scene.graph().parent(c), b) << "and the parenting is rolled back with it";
  EXPECT_EQ(scene.graph().undo_count(), steps) << "leaving no undo step";
  EXPECT_TRUE(scene.reparent(c, NodeId{}, false).is_ok()) << "without keep_world the driven node can move";

  EXPECT_EQ(scene.reparent(NodeId{}, a, true).code(), ErrorCode::kInvalidArgument) << "no child";
  EXPECT_EQ(scene.reparent(b, NodeId{7, 0}, true).code(), ErrorCode::kInvalidArgument) << "no such parent";
}

// ---- channels for a world matrix ------------------------------------------------

TEST(Scene, channels_for_world__translate_only_gives_the_whole_fits_translate_bit_for_bit) {
  // A moved world matrix under a moved parent: translate_only must give the
  // translate the whole fit gives (posing relies on it for body motions),
  // keep the rotation as it is, and fall back to the whole fit with pivots.
  for (std::uint32_t seed = 1; seed <= 10; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    Scene scene;
    std::vector<NodeId> ids = testing::random_forest(scene, seed, 25);
    Scene::ChannelFit whole;
    whole.keep_scale_shear = true;
    whole.nearest_rotation = true;
    for (NodeId id : ids) {
      const graph::Node& n = *scene.graph().node(id);
      Mat4 world = scene.world_matrix(id);
      world.block<3, 1>(0, 3) += Vec3(0.3, -0.2, 0.1 * seed);
      whole.parent_world = std::get<Mat4>(scene.graph().evaluate(id, xform::kParentMatrix));
      Scene::ChannelFit only = whole;
      only.translate_only = true;
      Result<Scene::LocalChannels> a = scene.channels_for_world(id, world, whole);
      Result<Scene::LocalChannels> b = scene.channels_for_world(id, world, only);
      ASSERT_EQ(a.is_ok(), b.is_ok()) << n.name();
      if (!a) continue;
      EXPECT_EQ(a->translate, b->translate) << n.name();
      const bool pivots = !std::get<Vec3>(n.value(xform::kRotatePivot)).isZero() ||
                          !std::get<Vec3>(n.value(xform::kRotatePivotTranslate)).isZero() ||
                          !std::get<Vec3>(n.value(xform::kScalePivot)).isZero() ||
                          !std::get<Vec3>(n.value(xform::kScalePivotTranslate)).isZero();
      if (!pivots) {
        EXPECT_EQ(b->rotation, n.value(xform::rotation_channel(n))) << n.name() << ": the rotation is kept";
      }
    }
  }
}

TEST(Scene, channels_for_world__keep_scale_shear_recovers_every_channel_set) {
  // Pivots, rotate axis, shear, joint orient, offset parent, quaternion mode
  // and every rotate order: the fit that keeps scale, shear and rotate axis
  // finds the translate and rotation the node has.
  for (std::uint32_t seed = 1; seed <= 20; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    Scene scene;
    std::vector<NodeId> ids = testing::random_forest(scene, seed, 25);
    Scene::ChannelFit fit;
    fit.keep_scale_shear = true;
    fit.nearest_rotation = true;
    for (NodeId id : ids) {
      const graph::Node& n = *scene.graph().node(id);
      Result<Scene::LocalChannels> ch = scene.channels_for_world(id, scene.world_matrix(id), fit);
      ASSERT_TRUE(ch.is_ok()) << ch.status().message();
      EXPECT_TRUE(ch->exact) << "the world matrix is the kept scale and shear turned";
      const Vec3& t0 = std::get<Vec3>(n.value(xform::kTranslate));
      EXPECT_LE((ch->translate - t0).norm(), 1e-9 * std::max(1.0, t0.norm())) << n.name() << ": translate";
      EXPECT_EQ(ch->scale, std::get<Vec3>(n.value(xform::kScale))) << "scale is kept as it is";
      EXPECT_EQ(ch->shear, std::get<Vec3>(n.value(xform::kShear))) << "shear is kept as it is";
      EXPECT_EQ(ch->rotation_attr, xform::rotation_channel(n)) << "the channel the rotate mode uses";
      if (ch->rotation_attr == xform::kRotateQuaternion) {
        const Quat q0 = std::get<Quat>(n.value(xform::kRotateQuaternion)).normalized();
        const Quat q = std::get<Quat>(ch->rotation);
        EXPECT_LE((q.coeffs() - q0.coeffs()).norm(), 1e-9) << n.name() << ": the same quaternion, same sign";
      } else {
        const Vec3& r0 = std::get<Vec3>(n.value(xform::kRotate));
        EXPECT_LE((std::get<Vec3>(ch->rotation) - r0).cwiseAbs().maxCoeff(), 1e-7)
            << n.name() << ": the Euler angles nearest the current ones are the current ones";
      }
    }
  }
}

TEST(Scene, channels_for_world__under_a_given_parent_world_puts_the_node_there) {
  Scene scene;
  NodeId p = make(scene, kTransformType, "p");
  NodeId c = make(scene, kControlType, "c", p);
  ASSERT_TRUE(testing::succeeded(set(scene, p, xform::kTranslate, Vec3(1, 2, 3)))) << "test setup";
  ASSERT_TRUE(testing::succeeded(set(scene, c, xform::kRotateAxis, Vec3(10, 0, 20)))) << "test setup";
  ASSERT_TRUE(testing::succeeded(set(scene, c, xform::kRotatePivot, Vec3(0.5, 0, 0)))) << "test setup";
  ASSERT_TRUE(testing::succeeded(set(scene, c, xform::kScale, Vec3(2, 2, 2)))) << "test setup";
  // The parent about to move (a solver places it first, then the child).
  Mat4 parent_new = Mat4::Identity();
  parent_new.topLeftCorner<3, 3>() = Eigen::AngleAxisd(0.7, Vec3(1, 1, 0).normalized()).toRotationMatrix();
  parent_new.topRightCorner<3, 1>() = Vec3(-1, 0, 4);
  Mat4 target = Mat4::Identity();
  target.topLeftCorner<3, 3>() = Eigen::AngleAxisd(1.1, Vec3(0, 1, 1).normalized()).toRotationMatrix() *
                                 math::compose([] {
                                   math::TransformParts kept;
                                   kept.scale = Vec3(2, 2, 2);
                                   kept.rotate_axis = math::to_radians(Vec3(10, 0, 20));
                                   return kept;
                                 }()).topLeftCorner<3, 3>();
  target.topRightCorner<3, 1>() = Vec3(3, -2, 1);
  Scene::ChannelFit fit;
  fit.parent_world = parent_new;
  fit.keep_scale_shear = true;
  Result<Scene::LocalChannels> ch = scene.channels_for_world(c, target, fit);
  ASSERT_TRUE(ch.is_ok()) << ch.status().message();
  ASSERT_TRUE(testing::succeeded(set(scene, c, xform::kTranslate, ch->translate))) << "write";
  ASSERT_TRUE(testing::succeeded(set(scene, c, ch->rotation_attr, ch->rotation))) << "write";
  EXPECT_TRUE(matrix_near(parent_new * scene.local_matrix(c), target, 1e-12))
      << "under the given parent world, the channels put the node at the target (pivots and rotate axis included)";
  EXPECT_FALSE(scene.channels_for_world(c, target).is_ok())
      << "the full decomposition still refuses pivots and rotate axis";
}

TEST(Scene, channels_for_world__nearest_rotation_and_exactness) {
  Scene scene;
  NodeId e = make(scene, kControlType, "e");
  NodeId q = make(scene, kControlType, "q");
  ASSERT_TRUE(testing::succeeded(set(scene, e, xform::kRotate, Vec3(0, 0, 350)))) << "test setup";
  ASSERT_TRUE(testing::succeeded(set(scene, q, xform::kRotateMode, xform::kQuaternionMode))) << "test setup";
  ASSERT_TRUE(testing::succeeded(set(scene, q, xform::kRotateQuaternion, Quat(-1, 0, 0, 0)))) << "test setup";
  Mat4 turned = Mat4::Identity();
  turned.topLeftCorner<3, 3>() = Eigen::AngleAxisd(math::to_radians(340.0), Vec3::UnitZ()).toRotationMatrix();
  Scene::ChannelFit nearest;
  nearest.nearest_rotation = true;
  for (bool keep : {false, true}) {
    SCOPED_TRACE(keep ? "keeping scale and shear" : "full decomposition");
    Scene::ChannelFit plain;
    plain.keep_scale_shear = keep;
    nearest.keep_scale_shear = keep;
    EXPECT_NEAR(std::get<Vec3>(scene.channels_for_world(e, turned, plain)->rotation).z(), -20, 1e-9)
        << "the principal angles";
    EXPECT_NEAR(std::get<Vec3>(scene.channels_for_world(e, turned, nearest)->rotation).z(), 340, 1e-9)
        << "the angles nearest rotate (350) are 340, not -20";
    const Quat near_q = std::get<Quat>(scene.channels_for_world(q, turned, nearest)->rotation);
    EXPECT_LT(near_q.w(), 0) << "the quaternion on the current one's side (w = -1)";
  }
  // A world with a scale the node does not have: no rotation fits exactly.
  Mat4 scaled = turned;
  scaled.col(0) *= 3;
  Scene::ChannelFit keep;
  keep.keep_scale_shear = true;
  Result<Scene::LocalChannels> ch = scene.channels_for_world(e, scaled, keep);
  ASSERT_TRUE(ch.is_ok()) << ch.status().message();
  EXPECT_FALSE(ch->exact) << "the kept scale cannot reproduce a scaled world";
  EXPECT_TRUE(scene.channels_for_world(e, scaled)->exact) << "the full decomposition reproduces any world";
  ASSERT_TRUE(testing::succeeded(set(scene, e, xform::kScale, Vec3(0, 1, 1)))) << "test setup";
  EXPECT_FALSE(scene.channels_for_world(e, turned, keep).is_ok()) << "a zero scale leaves no rotation to fit";
}

// ---- serial and parallel evaluation agree bit for bit ----------------------------

std::vector<Mat4> evaluated_worlds(const Scene& scene, const std::vector<NodeId>& ids, AttrIndex attr) {
  std::vector<Mat4> out;
  out.reserve(ids.size());
  for (NodeId id : ids) out.push_back(std::get<Mat4>(scene.graph().node(id)->value(attr)));
  return out;
}

::testing::AssertionResult bitwise_equal(const std::vector<Mat4>& a, const std::vector<Mat4>& b, const char* what) {
  if (a.size() != b.size()) return ::testing::AssertionFailure() << what << ": sizes differ";
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (std::memcmp(a[i].data(), b[i].data(), sizeof(double) * 16) != 0)
      return ::testing::AssertionFailure() << what << " of node " << i << " differs:\n" << a[i] << "\n  vs\n" << b[i];
  }
  return ::testing::AssertionSuccess();
}

TEST(Scene, evaluate_all__parallel_matches_serial_bit_for_bit_on_large_random_hierarchies) {
  // 20,000 joints (4,000 in the sanitizer build: still levels wide enough).
  constexpr int kJoints = 20000 / rigel::testing::kSlowBuildDivisor;
  for (std::uint32_t seed : {11u, 12u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    Scene serial, parallel;
    const std::vector<NodeId> ids = testing::random_forest(serial, seed, kJoints);
    ASSERT_EQ(testing::random_forest(parallel, seed, kJoints), ids) << "the same seed builds the same scene";
    EXPECT_LT(parallel.graph().schedule_level_count(), static_cast<std::size_t>(kJoints / 64))
        << "some level is wide enough for the parallel path";

    serial.graph().evaluate_all(graph::Execution::kSerial);
    parallel.graph().evaluate_all(graph::Execution::kParallel);
    EXPECT_TRUE(bitwise_equal(evaluated_worlds(serial, ids, xform::kWorldMatrix),
                              evaluated_worlds(parallel, ids, xform::kWorldMatrix), "worldMatrix"))
        << "parallel and serial evaluation must agree bit for bit";
    EXPECT_TRUE(bitwise_equal(evaluated_worlds(serial, ids, xform::kMatrix),
                              evaluated_worlds(parallel, ids, xform::kMatrix), "matrix"))
        << "local matrices too";

    // Edit a few hundred channels in both, then: serial scene by pull (world
    // matrices read one by one), parallel scene by evaluate_all.
    std::mt19937 a(seed * 7), b(seed * 7);
    for (int i = 0; i < 300; ++i) {
      const std::size_t k = std::uniform_int_distribution<std::size_t>(0, ids.size() - 1)(a);
      (void)std::uniform_int_distribution<std::size_t>(0, ids.size() - 1)(b);
      testing::random_channels(serial, ids[k], a);
      testing::random_channels(parallel, ids[k], b);
    }
    std::vector<Mat4> pulled;
    pulled.reserve(ids.size());
    for (auto it = ids.rbegin(); it != ids.rend(); ++it) pulled.push_back(serial.world_matrix(*it));
    std::reverse(pulled.begin(), pulled.end());
    parallel.graph().evaluate_all(graph::Execution::kParallel);
    EXPECT_TRUE(bitwise_equal(pulled, evaluated_worlds(parallel, ids, xform::kWorldMatrix), "worldMatrix"))
        << "pull evaluation (children first) and parallel evaluate_all agree bit for bit after edits";
  }
}

}  // namespace
}  // namespace rigel::scene
