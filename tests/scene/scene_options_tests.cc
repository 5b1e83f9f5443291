// Scene settings kept as nodes (scene/scene_options.h): the playback range
// set, changed and undone; selection sets saved, replaced, reported with a
// member deleted (missing) and brought back by undo, removed; bad input
// refused naming the field, changing nothing.

#include "rigel/scene/scene_options.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "rigel/scene/scene.h"
#include "rigel/scene/transform_types.h"

namespace rigel::scene {
namespace {

using graph::NodeId;

TEST(PlaybackRange, set_changed_and_undone_one_step_each) {
  Scene s;
  graph::Graph& g = s.graph();
  EXPECT_FALSE(playback_range(g));
  ASSERT_TRUE(set_playback_range(g, 10, 250).is_ok());
  ASSERT_TRUE(playback_range(g));
  EXPECT_EQ(*playback_range(g), (std::array<double, 2>{10, 250}));
  ASSERT_TRUE(set_playback_range(g, -5.5, 7).is_ok());
  EXPECT_EQ(*playback_range(g), (std::array<double, 2>{-5.5, 7}));
  std::size_t nodes = 0;
  for (NodeId id : g.nodes()) nodes += g.node(id)->type().name() == kPlaybackOptionsType;
  EXPECT_EQ(nodes, 1u) << "one playbackOptions node, reused";
  ASSERT_TRUE(g.undo());
  EXPECT_EQ(*playback_range(g), (std::array<double, 2>{10, 250}));
  ASSERT_TRUE(g.undo());
  EXPECT_FALSE(playback_range(g));
  for (auto [a, b] : {std::pair{5.0, 4.0}, std::pair{0.0, 2e6}, std::pair{std::nan(""), 1.0}}) {
    const Status st = set_playback_range(g, a, b);
    EXPECT_EQ(st.field(), "range") << a << " " << b;
  }
  EXPECT_FALSE(playback_range(g)) << "refusals change nothing";
}

TEST(SelectionSets, saved_replaced_missing_members_and_removed) {
  Scene s;
  graph::Graph& g = s.graph();
  auto a = g.create_node(kControlType, "a");
  auto b = g.create_node(kControlType, "b");
  auto c = g.create_node(kControlType, "c");
  ASSERT_TRUE(a && b && c);
  auto id = save_selection_set(g, "left_arm", {*a, *b, *a});
  ASSERT_TRUE(id.is_ok()) << id.status().message();
  ASSERT_TRUE(save_selection_set(g, "all", {*c, *b, *a}).is_ok());
  std::vector<SelectionSet> sets = selection_sets(g);
  ASSERT_EQ(sets.size(), 2u);
  EXPECT_EQ(sets[0].name, "all") << "by name";
  EXPECT_EQ(sets[0].members, (std::vector<NodeId>{*c, *b, *a})) << "in set order";
  EXPECT_EQ(sets[1].members, (std::vector<NodeId>{*a, *b})) << "once each";
  // Replace the members of a set.
  ASSERT_TRUE(save_selection_set(g, "left_arm", {*c}).is_ok());
  EXPECT_EQ(selection_sets(g)[1].members, (std::vector<NodeId>{*c}));
  ASSERT_TRUE(g.undo());
  EXPECT_EQ(selection_sets(g)[1].members, (std::vector<NodeId>{*a, *b}));
  // A member deleted is missing; undo brings it back as a member.
  const std::string b_uuid = g.node(*b)->uuid().str();
  ASSERT_TRUE(g.delete_node(*b).is_ok());
  sets = selection_sets(g);
  EXPECT_EQ(sets[1].members, (std::vector<NodeId>{*a}));
  EXPECT_EQ(sets[1].missing, (std::vector<std::string>{b_uuid}));
  ASSERT_TRUE(g.undo());
  sets = selection_sets(g);
  ASSERT_EQ(sets[1].members.size(), 2u);
  EXPECT_EQ(g.node(sets[1].members[1])->uuid().str(), b_uuid);
  EXPECT_TRUE(sets[1].missing.empty());
  // Bad input.
  EXPECT_EQ(save_selection_set(g, "bad name", {*a}).status().field(), "name");
  EXPECT_EQ(save_selection_set(g, "a.b", {*a}).status().field(), "name");
  EXPECT_EQ(save_selection_set(g, "a", {*c}).status().field(), "name") << "a control's name";
  EXPECT_EQ(save_selection_set(g, "empty", {}).status().field(), "members");
  EXPECT_EQ(remove_selection_set(g, "a").code(), ErrorCode::kNotFound) << "not a set";
  EXPECT_EQ(selection_sets(g).size(), 2u);
  ASSERT_TRUE(remove_selection_set(g, "all").is_ok());
  ASSERT_EQ(selection_sets(g).size(), 1u);
  ASSERT_TRUE(g.undo());
  EXPECT_EQ(selection_sets(g).size(), 2u);
}

}  // namespace
}  // namespace rigel::scene
