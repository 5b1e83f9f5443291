// Clips: curves holding several clips' keys (clipOffsets), the animClips
// node that picks one, and the helpers the CLI and the exporter use.
#include "rigel/ops/anim/clips.h"

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "anim_test_util.h"
#include "rigel/graph/graph.h"
#include "rigel/ops/anim/nodes.h"
#include "rigel/ops/anim/track.h"
#include "rigel/scene/scene.h"
#include "rigel/scene/transform_types.h"

namespace rigel::ops::anim {
namespace {

using graph::Graph;
using graph::NodeId;
using graph::Plug;
using graph::Value;
using math::Quat;
using math::Vec3;
using testing::succeeded;

std::shared_ptr<const graph::Registry> registry() {
  static const std::shared_ptr<const graph::Registry> r = [] {
    auto reg = std::make_shared<graph::Registry>();
    EXPECT_TRUE(succeeded(scene::register_scene_types(*reg)));
    EXPECT_TRUE(succeeded(register_anim_types(*reg)));
    return reg;
  }();
  return r;
}

std::string message_of(const Status& s) { return s.message(); }

class Clips : public ::testing::Test {
 protected:
  Clips() : scene_(registry()) {}

  NodeId create(const char* type, const char* name) {
    Result<NodeId> id = scene_.create(type, name);
    EXPECT_TRUE(succeeded(id.status()));
    return id ? *id : NodeId{};
  }
  void set(NodeId node, graph::AttrIndex attr, Value value) {
    ASSERT_TRUE(succeeded(graph().set_value(Plug{node, attr, -1}, std::move(value))));
  }
  void connect(NodeId src, graph::AttrIndex src_attr, NodeId dst, graph::AttrIndex dst_attr) {
    ASSERT_TRUE(succeeded(graph().connect(Plug{src, src_attr, -1}, Plug{dst, dst_attr, -1})));
  }
  template <typename T>
  T value(NodeId node, graph::AttrIndex attr) {
    return std::get<T>(graph().evaluate(node, attr));
  }
  Graph& graph() { return scene_.graph(); }

  // "walk" (0..1 s) and "jump" (0..2 s).
  NodeId make_clips() {
    const NodeId clips = create(kAnimClipsType, "clips");
    set(clips, clips_attr::kClipNames, std::vector<std::string>{"walk", "jump"});
    set(clips, clips_attr::kClipStarts, std::vector<double>{0, 0});
    set(clips, clips_attr::kClipEnds, std::vector<double>{1, 2});
    return clips;
  }

  scene::Scene scene_;
};

TEST_F(Clips, track__evaluates_the_active_clips_keys) {
  const NodeId clips = make_clips();
  const NodeId track = create(kAnimCurveVec3Type, "hip_translate");
  const NodeId hip = create(scene::kJointType, "hip");
  // walk: x 0 -> 2 over 1 s; jump: x 10 -> 14 over 2 s.
  set(track, track_attr::kKeyTimes, std::vector<double>{0, 1, 0, 2});
  set(track, track_attr::kKeyValues, std::vector<Vec3>{Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(10, 0, 0), Vec3(14, 0, 0)});
  set(track, track_attr::kClipOffsets, std::vector<std::int64_t>{0, 2, 4});
  connect(clips, clips_attr::kActiveClip, track, track_attr::kClip);
  connect(track, track_attr::kOutput, hip, scene::xform::kTranslate);
  graph().set_time(0.5);
  EXPECT_DOUBLE_EQ(scene_.world_matrix(hip)(0, 3), 1.0) << "walk is active by default";
  ASSERT_TRUE(succeeded(set_active_clip(graph(), clips, 1)));
  EXPECT_DOUBLE_EQ(scene_.world_matrix(hip)(0, 3), 11.0) << "jump at 0.5 s: 10 + 4 * 0.25";
  ASSERT_TRUE(graph().undo());
  EXPECT_DOUBLE_EQ(scene_.world_matrix(hip)(0, 3), 1.0) << "switching clips is undoable";
  EXPECT_TRUE(value<std::string>(track, track_attr::kError).empty());
}

TEST_F(Clips, track__clip_without_keys_gives_the_rest_value) {
  const NodeId clips = make_clips();
  const NodeId track = create(kAnimCurveQuatType, "arm_rotate");
  const Quat rest(Eigen::AngleAxisd(0.3, Vec3::UnitX()));
  const Quat key(Eigen::AngleAxisd(1.0, Vec3::UnitY()));
  // Only walk animates the arm.
  set(track, track_attr::kKeyTimes, std::vector<double>{0});
  set(track, track_attr::kKeyValues, std::vector<Quat>{key});
  set(track, track_attr::kClipOffsets, std::vector<std::int64_t>{0, 1, 1});
  set(track, track_attr::kRestValue, rest);
  connect(clips, clips_attr::kActiveClip, track, track_attr::kClip);
  EXPECT_TRUE(value<Quat>(track, track_attr::kOutput).isApprox(key, 1e-15));
  ASSERT_TRUE(succeeded(set_active_clip(graph(), clips, 1)));
  EXPECT_TRUE(value<Quat>(track, track_attr::kOutput).isApprox(rest, 1e-15)) << "jump does not animate the arm";
  ASSERT_TRUE(succeeded(graph().disconnect_input(Plug{track, track_attr::kClip, -1})));
  set(track, track_attr::kClip, std::int64_t{7});
  EXPECT_TRUE(value<Quat>(track, track_attr::kOutput).isApprox(rest, 1e-15)) << "a clip out of range is the rest";
}

TEST_F(Clips, track__each_clip_is_validated_on_its_own) {
  const NodeId track = create(kAnimCurveVec3Type, "t");
  // Times restart at each clip: valid.
  set(track, track_attr::kKeyTimes, std::vector<double>{0, 1, 0, 3});
  set(track, track_attr::kKeyValues, std::vector<Vec3>(4, Vec3(1, 2, 3)));
  set(track, track_attr::kClipOffsets, std::vector<std::int64_t>{0, 2, 4});
  EXPECT_TRUE(value<std::string>(track, track_attr::kError).empty()) << value<std::string>(track, track_attr::kError);
  // An inactive clip's bad keys are still reported.
  set(track, track_attr::kKeyTimes, std::vector<double>{0, 1, 3, 2});
  EXPECT_NE(value<std::string>(track, track_attr::kError).find("clip 1 (keys from 2): keys[1].time"), std::string::npos)
      << value<std::string>(track, track_attr::kError);
  EXPECT_TRUE(value<Vec3>(track, track_attr::kOutput) == Vec3::Zero()) << "bad keys give the fallback, no crash";
}

TEST_F(Clips, track__bad_clip_offsets_are_named) {
  const NodeId track = create(kAnimCurveVec3Type, "t");
  set(track, track_attr::kKeyTimes, std::vector<double>{0, 1, 2});
  set(track, track_attr::kKeyValues, std::vector<Vec3>(3, Vec3(1, 2, 3)));
  const auto error_with = [&](std::vector<std::int64_t> offsets) {
    set(track, track_attr::kClipOffsets, std::move(offsets));
    return value<std::string>(track, track_attr::kError);
  };
  EXPECT_NE(error_with({0}).find("clipOffsets: needs at least 2 entries"), std::string::npos);
  EXPECT_NE(error_with({1, 3}).find("clipOffsets[0]: must be 0, not 1"), std::string::npos);
  EXPECT_NE(error_with({0, 2, 1, 3}).find("clipOffsets[2]: 1 is less than clipOffsets[1]"), std::string::npos);
  EXPECT_NE(error_with({0, 2, 5}).find("clipOffsets[2]: must be the key count 3, not 5"), std::string::npos);
  EXPECT_TRUE(error_with({0, 3}).empty());
  set(track, track_attr::kClipOffsets, std::vector<std::int64_t>{0, 1, 3});
  set(track, track_attr::kKeyValues, std::vector<Vec3>(2, Vec3(1, 2, 3)));
  EXPECT_NE(value<std::string>(track, track_attr::kError).find("keyValues: 2 entries for 3 keys"), std::string::npos)
      << "per-key arrays are checked before they are cut into clips";
}

TEST_F(Clips, anim_curve__clips_keep_their_tangents) {
  const NodeId clips = make_clips();
  const NodeId curve = create(kAnimCurveType, "weight");
  namespace a = curve_attr;
  // walk: linear 0 -> 1 over 1 s; jump: step 5, then 7 at 1 s.
  set(curve, a::kKeyTimes, std::vector<double>{0, 1, 0, 1});
  set(curve, a::kKeyValues, std::vector<double>{0, 1, 5, 7});
  const std::int64_t linear = static_cast<std::int64_t>(TangentType::kLinear);
  const std::int64_t step = static_cast<std::int64_t>(TangentType::kStep);
  set(curve, a::kInTangentType, std::vector<std::int64_t>{linear, linear, step, step});
  set(curve, a::kOutTangentType, std::vector<std::int64_t>{linear, linear, step, step});
  set(curve, anim_curve_attr::kClipOffsets, std::vector<std::int64_t>{0, 2, 4});
  set(curve, anim_curve_attr::kRestValue, 0.25);
  connect(clips, clips_attr::kActiveClip, curve, anim_curve_attr::kClip);
  graph().set_time(0.5);
  EXPECT_DOUBLE_EQ(value<double>(curve, a::kOutput), 0.5);
  ASSERT_TRUE(succeeded(set_active_clip(graph(), clips, 1)));
  EXPECT_DOUBLE_EQ(value<double>(curve, a::kOutput), 5.0) << "step holds the first key";
  set(curve, anim_curve_attr::kClipOffsets, std::vector<std::int64_t>{0, 4, 4});
  EXPECT_NE(value<std::string>(curve, a::kError).find("clip 0 (keys from 0): keys[2].time"), std::string::npos)
      << value<std::string>(curve, a::kError);
  set(curve, anim_curve_attr::kClipOffsets, std::vector<std::int64_t>{0, 2, 2});
  set(curve, a::kKeyTimes, std::vector<double>{0, 1});
  set(curve, a::kKeyValues, std::vector<double>{0, 1});
  set(curve, a::kInTangentType, std::vector<std::int64_t>{linear, linear});
  set(curve, a::kOutTangentType, std::vector<std::int64_t>{linear, linear});
  EXPECT_DOUBLE_EQ(value<double>(curve, a::kOutput), 0.25) << "jump has no keys here: the rest value";
}

TEST_F(Clips, clips_node__lists_resolves_and_clamps) {
  const NodeId clips = make_clips();
  EXPECT_EQ(find_clips_node(graph()), clips);
  Result<std::vector<Clip>> list = clips_of(graph(), clips);
  ASSERT_TRUE(succeeded(list.status()));
  ASSERT_EQ(list->size(), 2u);
  EXPECT_EQ((*list)[1].name, "jump");
  EXPECT_EQ((*list)[1].end, 2.0);
  EXPECT_EQ(*resolve_clip(graph(), clips, "jump"), 1);
  EXPECT_EQ(*resolve_clip(graph(), clips, "0"), 0);
  Result<int> missing = resolve_clip(graph(), clips, "run");
  ASSERT_FALSE(missing.is_ok());
  EXPECT_EQ(message_of(missing.status()), "no clip 'run'; clips: 0 'walk', 1 'jump'");
  EXPECT_FALSE(resolve_clip(graph(), clips, "2").is_ok());
  EXPECT_FALSE(resolve_clip(graph(), clips, "-1").is_ok());
  EXPECT_FALSE(set_active_clip(graph(), clips, 2).is_ok());
  set(clips, clips_attr::kActive, std::int64_t{9});
  EXPECT_EQ(value<std::int64_t>(clips, clips_attr::kActiveClip), 1) << "activeClip is clamped";
  const NodeId hip = create(scene::kJointType, "hip");
  EXPECT_FALSE(clips_of(graph(), hip).is_ok()) << "not an animClips node";
}

TEST_F(Clips, clips_node__bad_lists_are_named) {
  const NodeId clips = make_clips();
  set(clips, clips_attr::kClipNames, std::vector<std::string>{"walk", "walk"});
  EXPECT_EQ(message_of(clips_of(graph(), clips).status()), "clips: clipNames[1]: 'walk' is also clipNames[0]");
  EXPECT_EQ(value<std::string>(clips, clips_attr::kError), "clipNames[1]: 'walk' is also clipNames[0]");
  set(clips, clips_attr::kClipNames, std::vector<std::string>{"walk", ""});
  EXPECT_EQ(message_of(clips_of(graph(), clips).status()), "clips: clipNames[1]: empty name");
  set(clips, clips_attr::kClipNames, std::vector<std::string>{"walk"});
  EXPECT_EQ(message_of(clips_of(graph(), clips).status()), "clips: clipNames: 1 names for 2 starts and 2 ends");
  set(clips, clips_attr::kClipNames, std::vector<std::string>{"walk", "jump"});
  set(clips, clips_attr::kClipEnds, std::vector<double>{1, -1});
  EXPECT_NE(message_of(clips_of(graph(), clips).status()).find("clipEnds[1]: -1.000000 is before clipStarts[1]"),
            std::string::npos);
}

TEST_F(Clips, find_clips_node__none_in_a_scene_without_clips) {
  create(scene::kJointType, "hip");
  EXPECT_FALSE(find_clips_node(graph()).is_valid());
}

}  // namespace
}  // namespace rigel::ops::anim
