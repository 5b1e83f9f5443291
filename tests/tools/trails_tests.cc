// Motion trails and ghosts (tools/trails.h) on the biped built on the
// metarig with its left IK hand keyed: each trail point is the control's
// world position evaluated at that frame, its keys are marked and are
// points of the trail, the graph's time is put back and nothing is undoable;
// bad ranges name the field.

#include "rigel/tools/trails.h"

#include <gtest/gtest.h>

#include <memory>

#include "rigel/tools/keys.h"
#include "tools_test_util.h"

namespace rigel::tools {
namespace {

using graph::NodeId;
using testing::at;

TEST(Trails, points_are_the_evaluated_world_positions_and_keys_are_marked) {
  auto scene = testing::built_rig();
  ASSERT_TRUE(scene);
  graph::Graph& g = scene->graph();
  const NodeId ik = at(g, "hero:arm_L/ik");
  const NodeId hand = g.find("hand.L");
  ASSERT_TRUE(hand.is_valid());
  auto ch = channels_of(g, {ik}, {"translate"});
  ASSERT_TRUE(ch.is_ok());
  Channel y = ch->front();
  y.component = 1;
  for (double f : {2.0, 9.5}) {
    scene->set_frame(f);
    ASSERT_TRUE(set_values(g, {y}, {f * 0.02}, true).is_ok());
  }
  g.clear_history();
  scene->set_frame(4);
  auto trails = motion_trails(*scene, {ik, hand}, 0, 12, 2);
  ASSERT_TRUE(trails.is_ok()) << trails.status().message();
  ASSERT_EQ(trails->size(), 2u);
  const MotionTrail& t = (*trails)[0];
  EXPECT_EQ(t.key_frames, (std::vector<double>{2.0, 9.5}));
  EXPECT_EQ(t.frames, (std::vector<double>{0, 2, 4, 6, 8, 9.5, 10, 12})) << "every step, and the keys";
  EXPECT_EQ((*trails)[1].frames, t.frames) << "one pass: the same frames for each";
  EXPECT_TRUE((*trails)[1].key_frames.empty()) << "the joint has no keys of its own";
  EXPECT_EQ(scene->frame(), 4) << "the time is put back";
  EXPECT_FALSE(g.can_undo());
  for (std::size_t i = 0; i < t.frames.size(); ++i) {
    scene->set_frame(t.frames[i]);
    const math::Vec3 want = scene->world_matrix(ik).block<3, 1>(0, 3);
    const math::Vec3 joint = scene->world_matrix(hand).block<3, 1>(0, 3);
    EXPECT_LT((t.points[i] - want).norm(), 1e-12) << t.frames[i];
    EXPECT_LT(((*trails)[1].points[i] - joint).norm(), 1e-12) << t.frames[i];
  }
  EXPECT_GT((t.points[3] - t.points[0]).norm(), 1e-3) << "the trail moves with the keys";
  EXPECT_EQ(motion_trails(*scene, {ik}, 5, 1).status().field(), "frames");
  EXPECT_EQ(motion_trails(*scene, {ik}, 0, 10, 0).status().field(), "step");
  EXPECT_EQ(world_positions(*scene, {ik}, {std::nan("")}).status().field(), "frames");
}

}  // namespace
}  // namespace rigel::tools
