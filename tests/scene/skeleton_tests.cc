#include "rigel/scene/skeleton.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "rigel/math/local_to_world.h"
#include "rigel/scene/scene.h"
#include "scene_test_util.h"

namespace rigel::scene {
namespace {

using math::Vec3;
using testing::matrix_near;
using testing::set;

NodeId make(Scene& scene, std::string_view type, std::string_view name, NodeId parent = NodeId{}) {
  Result<NodeId> id = scene.create(type, name, parent);
  EXPECT_TRUE(id.is_ok()) << "creating " << name << ": " << id.status().message();
  return id.is_ok() ? *id : NodeId{};
}

TEST(Skeleton, compile__lists_parents_before_children) {
  Scene scene;
  NodeId a = make(scene, kJointType, "a");
  NodeId b = make(scene, kJointType, "b");
  NodeId a1 = make(scene, kJointType, "a1", a);
  NodeId a11 = make(scene, kJointType, "a11", a1);
  NodeId b1 = make(scene, kJointType, "b1", b);
  NodeId a2 = make(scene, kJointType, "a2", a);
  Result<Skeleton> s = Skeleton::compile(scene);
  ASSERT_TRUE(s.is_ok()) << s.status().message();
  EXPECT_EQ(std::vector<NodeId>(s->nodes().begin(), s->nodes().end()), scene.hierarchy())
      << "all roots, in the order of Scene::hierarchy()";
  EXPECT_EQ(std::vector<NodeId>(s->nodes().begin(), s->nodes().end()), (std::vector<NodeId>{a, a1, a11, a2, b, b1}))
      << "depth first, siblings in creation order";
  EXPECT_EQ(std::vector<std::int32_t>(s->parents().begin(), s->parents().end()),
            (std::vector<std::int32_t>{math::kNoParent, 0, 1, 0, math::kNoParent, 4}))
      << "parent indices point backwards";
  EXPECT_EQ(s->name(2), "a11") << "names are kept";
  EXPECT_EQ(s->generation(), scene.graph().topology_generation()) << "stamped with the topology generation";

  const NodeId sub[] = {a1, b};
  Result<Skeleton> part = Skeleton::compile(scene, sub);
  ASSERT_TRUE(part.is_ok()) << part.status().message();
  EXPECT_EQ(std::vector<NodeId>(part->nodes().begin(), part->nodes().end()), (std::vector<NodeId>{a1, a11, b, b1}))
      << "only the given subtrees, in the given order";
  EXPECT_EQ(part->parents()[0], math::kNoParent) << "a subtree root has no parent in the skeleton";
}

TEST(Skeleton, compile__refuses_bad_roots) {
  // A registry with the scene types and one node type that is not a transform.
  auto registry = std::make_shared<graph::Registry>();
  ASSERT_TRUE(register_scene_types(*registry).is_ok()) << "scene types";
  graph::NodeTypeSpec note;
  note.name = "note";
  graph::AttrSpec text;
  text.name = "text";
  text.type = {graph::ValueType::kString, false};
  note.attrs = {text};
  ASSERT_TRUE(registry->add(note).is_ok()) << "a plain type";
  Scene scene(registry);
  NodeId a = make(scene, kJointType, "a");
  NodeId a1 = make(scene, kJointType, "a1", a);
  Result<NodeId> n = scene.graph().create_node("note", "n");
  ASSERT_TRUE(n.is_ok()) << n.status().message();
  EXPECT_FALSE(scene.is_transform(*n)) << "a note is not a transform";
  EXPECT_EQ(scene.roots(), (std::vector<NodeId>{a})) << "and not a root of the hierarchy";

  const NodeId not_transform[] = {*n};
  EXPECT_EQ(Skeleton::compile(scene, not_transform).status().code(), ErrorCode::kInvalidArgument)
      << "a non-transform root is refused";
  NodeId gone = make(scene, kJointType, "gone");
  ASSERT_TRUE(scene.graph().delete_node(gone).is_ok()) << "delete";
  const NodeId stale[] = {gone};
  EXPECT_EQ(Skeleton::compile(scene, stale).status().code(), ErrorCode::kInvalidArgument)
      << "a stale root is refused";
  const NodeId overlapping[] = {a, a1};
  Result<Skeleton> twice = Skeleton::compile(scene, overlapping);
  EXPECT_EQ(twice.status().code(), ErrorCode::kInvalidArgument) << "a root inside another root's subtree is refused";
  EXPECT_NE(twice.status().message().find("a1"), std::string::npos)
      << "naming the node reached twice: " << twice.status().message();
  Result<Skeleton> all = Skeleton::compile(scene);
  ASSERT_TRUE(all.is_ok()) << "the whole scene compiles, skipping the note";
  EXPECT_EQ(all->size(), 2u) << "two joints";
}

::testing::AssertionResult matches_scene(Scene& scene, const Skeleton& skeleton, double tolerance) {
  std::vector<Mat4> local(skeleton.size()), world(skeleton.size());
  Status s = skeleton.evaluate(scene, local, world);
  if (!s) return ::testing::AssertionFailure() << "evaluate failed: " << s.message();
  for (std::size_t i = 0; i < skeleton.size(); ++i) {
    const NodeId id = skeleton.nodes()[i];
    auto r = matrix_near(world[i], scene.world_matrix(id), tolerance);
    if (!r) return r << "\n(world matrix of " << skeleton.name(i) << ")";
    const std::int32_t p = skeleton.parents()[i];
    const Mat4 parent_world = p == math::kNoParent
                                  ? std::get<Mat4>(*scene.graph().evaluate(graph::Plug{id, xform::kParentMatrix, -1}))
                                  : world[static_cast<std::size_t>(p)];
    if (p != math::kNoParent) {
      r = matrix_near(parent_world * local[i], world[i], tolerance);
      if (!r) return r << "\n(local matrix of " << skeleton.name(i) << " does not link to its parent)";
    }
  }
  return ::testing::AssertionSuccess();
}

TEST(Skeleton, evaluate__agrees_with_scene_world_matrix_on_random_trees) {
  for (std::uint32_t seed = 1; seed <= 20; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    Scene scene;
    std::vector<NodeId> ids = testing::random_forest(scene, seed, 200);
    Result<Skeleton> s = Skeleton::compile(scene);
    ASSERT_TRUE(s.is_ok()) << s.status().message();
    EXPECT_EQ(s->size(), ids.size()) << "every transform is in the skeleton";
    EXPECT_TRUE(matches_scene(scene, *s, 1e-12)) << "the compiled skeleton gives the scene's world matrices";

    // Values change without recompiling.
    std::mt19937 rng(seed);
    for (int i = 0; i < 20; ++i) testing::random_channels(scene, ids[rng() % ids.size()], rng);
    EXPECT_TRUE(matches_scene(scene, *s, 1e-12)) << "after value edits, with no recompile";

    // A subtree: its root's world includes what is above it.
    const NodeId deep = ids[ids.size() / 2];
    const NodeId sub[] = {deep};
    Result<Skeleton> part = Skeleton::compile(scene, sub);
    ASSERT_TRUE(part.is_ok()) << part.status().message();
    EXPECT_TRUE(matches_scene(scene, *part, 1e-12)) << "a subtree skeleton starts from its root's parent world";
  }
}

TEST(Skeleton, evaluate__refuses_stale_generation_and_wrong_spans) {
  Scene scene;
  NodeId a = make(scene, kJointType, "a");
  make(scene, kJointType, "b", a);
  Result<Skeleton> s = Skeleton::compile(scene);
  ASSERT_TRUE(s.is_ok()) << s.status().message();
  std::vector<Mat4> local(2), world(2), short_span(1), long_span(3);
  EXPECT_TRUE(s->evaluate(scene, local, world).is_ok()) << "matching spans evaluate";
  EXPECT_EQ(s->evaluate(scene, short_span, world).code(), ErrorCode::kInvalidArgument) << "local too short";
  EXPECT_EQ(s->evaluate(scene, local, long_span).code(), ErrorCode::kInvalidArgument) << "world too long";

  ASSERT_TRUE(set(scene, a, xform::kTranslate, Vec3(1, 2, 3)).is_ok()) << "a value edit";
  EXPECT_TRUE(s->evaluate(scene, local, world).is_ok()) << "values do not invalidate a skeleton";
  make(scene, kJointType, "c", a);
  Status stale = s->evaluate(scene, local, world);
  EXPECT_EQ(stale.code(), ErrorCode::kInvalidArgument) << "a topology change (new joint) makes the skeleton stale";
  EXPECT_NE(stale.message().find("compile"), std::string::npos) << "the message says to recompile: " << stale.message();
  Result<Skeleton> again = Skeleton::compile(scene);
  ASSERT_TRUE(again.is_ok()) << "recompile";
  std::vector<Mat4> local3(3), world3(3);
  EXPECT_TRUE(again->evaluate(scene, local3, world3).is_ok()) << "the recompiled skeleton evaluates";
  EXPECT_TRUE(matrix_near(world3[1], scene.world_matrix(scene.graph().find("b")), 1e-15)) << "and is right";
}

}  // namespace
}  // namespace rigel::scene
