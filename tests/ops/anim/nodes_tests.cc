#include "rigel/ops/anim/nodes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "anim_test_util.h"
#include "rigel/graph/graph.h"
#include "rigel/ops/anim/curve.h"
#include "rigel/ops/anim/track.h"
#include "rigel/scene/scene.h"
#include "rigel/scene/transform_types.h"

namespace rigel::ops::anim {
namespace {

using graph::Graph;
using graph::NodeId;
using graph::Plug;
using graph::Value;
using math::Mat4;
using math::Quat;
using math::Vec3;
using testing::succeeded;

constexpr double kTight = 1e-12;

// Scene types plus the anim types (ops::default_registry() gains them when
// the ops registry calls register_anim_types).
std::shared_ptr<const graph::Registry> registry() {
  static const std::shared_ptr<const graph::Registry> r = [] {
    auto reg = std::make_shared<graph::Registry>();
    EXPECT_TRUE(succeeded(scene::register_scene_types(*reg)));
    EXPECT_TRUE(succeeded(register_anim_types(*reg)));
    return reg;
  }();
  return r;
}

template <typename T>
Track<T> make_or_die(std::vector<double> times, std::vector<T> values, Interpolation interpolation) {
  Result<Track<T>> track = Track<T>::build(std::move(times), std::move(values), interpolation);
  EXPECT_TRUE(succeeded(track.status()));
  return track ? std::move(track).value() : Track<T>();
}

class AnimNodes : public ::testing::Test {
 protected:
  AnimNodes() : scene_(registry()) {}

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
  // Every per-key array of an animCurve or drivenKey.
  void set_keys(NodeId curve, const testing::KeyColumns& k) {
    set(curve, curve_attr::kKeyTimes, k.times);
    set(curve, curve_attr::kKeyValues, k.values);
    set(curve, curve_attr::kInTangentType, k.in_types);
    set(curve, curve_attr::kOutTangentType, k.out_types);
    set(curve, curve_attr::kInSlope, k.in_slopes);
    set(curve, curve_attr::kOutSlope, k.out_slopes);
    set(curve, curve_attr::kInWeight, k.in_weights);
    set(curve, curve_attr::kOutWeight, k.out_weights);
  }
  template <typename T>
  T value(NodeId node, graph::AttrIndex attr) {
    return std::get<T>(graph().evaluate(node, attr));
  }
  Graph& graph() { return scene_.graph(); }

  scene::Scene scene_;
};

TEST_F(AnimNodes, register__declares_four_types_once) {
  for (const char* name : {kAnimCurveType, kDrivenKeyType, kAnimCurveVec3Type, kAnimCurveQuatType}) {
    const graph::NodeType* type = registry()->find(name);
    ASSERT_NE(type, nullptr) << name;
  }
  EXPECT_TRUE(registry()->find(kAnimCurveType)->time_dependent()) << "animCurve reads the graph's time";
  EXPECT_FALSE(registry()->find(kDrivenKeyType)->time_dependent()) << "a driven key depends on its input only";
  EXPECT_EQ(registry()->find(kAnimCurveType)->attr_count(), anim_curve_attr::kCount + 1u) << "+ metaParent";
  EXPECT_EQ(registry()->find(kDrivenKeyType)->attr_count(), driven_key_attr::kCount + 1u);
  EXPECT_EQ(registry()->find(kAnimCurveVec3Type)->attr_find("restValue"), track_attr::kRestValue);
  EXPECT_EQ(registry()->find(kDrivenKeyType)->attr_find("input"), driven_key_attr::kInput);
  EXPECT_EQ(registry()->find(kAnimCurveQuatType)->attr_find("output"), track_attr::kOutput);
  EXPECT_EQ(registry()->find(kAnimCurveType)->attr_find("postInfinity"), curve_attr::kPostInfinity);
  graph::Registry again;
  ASSERT_TRUE(succeeded(register_anim_types(again)));
  EXPECT_FALSE(register_anim_types(again).is_ok()) << "registering the names twice should fail";
}

TEST_F(AnimNodes, anim_curve__drives_joint_channel_with_set_time) {
  const NodeId curve = create(kAnimCurveType, "radius_curve");
  const NodeId joint = create(scene::kJointType, "hip");
  set(curve, curve_attr::kKeyTimes, std::vector<double>{0, 1});
  set(curve, curve_attr::kKeyValues, std::vector<double>{1, 3});
  set(curve, curve_attr::kInTangentType, std::vector<std::int64_t>{1, 1});   // linear
  set(curve, curve_attr::kOutTangentType, std::vector<std::int64_t>{1, 1});
  connect(curve, curve_attr::kOutput, joint, scene::joint_attr::kRadius);
  graph().set_time(0.5);
  EXPECT_DOUBLE_EQ(value<double>(joint, scene::joint_attr::kRadius), 2.0);
  graph().set_time(0.25);
  EXPECT_DOUBLE_EQ(value<double>(joint, scene::joint_attr::kRadius), 1.5) << "set_time dirties the curve";
  graph().set_time(5.0);
  EXPECT_DOUBLE_EQ(value<double>(joint, scene::joint_attr::kRadius), 3.0) << "constant post-infinity";
  set(curve, curve_attr::kPostInfinity, std::int64_t{static_cast<int>(Infinity::kLinear)});
  EXPECT_DOUBLE_EQ(value<double>(joint, scene::joint_attr::kRadius), 3.0)
      << "linear infinity of a linear end key is level (Maya)";
  EXPECT_TRUE(value<std::string>(curve, curve_attr::kError).empty()) << "valid keys report no error";
}

TEST_F(AnimNodes, anim_curve_vec3__drives_joint_translate_with_set_time) {
  const NodeId track = create(kAnimCurveVec3Type, "hip_translate");
  const NodeId joint = create(scene::kJointType, "hip");
  set(track, track_attr::kKeyTimes, std::vector<double>{0, 2});
  set(track, track_attr::kKeyValues, std::vector<Vec3>{Vec3(0, 1, 0), Vec3(4, 1, -2)});
  connect(track, track_attr::kOutput, joint, scene::xform::kTranslate);
  for (double t : {0.0, 0.5, 1.0, 2.0, 3.0}) {
    graph().set_time(t);
    const Mat4 world = scene_.world_matrix(joint);
    const double s = std::min(t, 2.0) / 2.0;
    EXPECT_NEAR((world.topRightCorner<3, 1>() - Vec3(4 * s, 1, -2 * s)).norm(), 0.0, kTight) << "t = " << t;
  }
}

TEST_F(AnimNodes, anim_curve_quat__drives_joint_rotation_with_set_time) {
  const NodeId track = create(kAnimCurveQuatType, "hip_rotate");
  const NodeId joint = create(scene::kJointType, "hip");
  const Quat q0 = Quat::Identity(), q1(Eigen::AngleAxisd(math::kPi / 2, Vec3::UnitZ()));
  set(track, track_attr::kKeyTimes, std::vector<double>{0, 1});
  set(track, track_attr::kKeyValues, std::vector<Quat>{q0, q1});
  set(joint, scene::xform::kRotateMode, std::int64_t{1});  // quaternion
  connect(track, track_attr::kOutput, joint, scene::xform::kRotateQuaternion);
  graph().set_time(0.5);
  const Mat4 world = scene_.world_matrix(joint);
  const Eigen::Matrix3d expected = Eigen::AngleAxisd(math::kPi / 4, Vec3::UnitZ()).toRotationMatrix();
  EXPECT_NEAR((world.topLeftCorner<3, 3>() - expected).norm(), 0.0, 1e-12) << "slerp midpoint: 45 degrees about Z";
}

// An animCurveQuat keeps its keys built into a Track with a cursor: forward
// and backward playback and jumps give the track's values bit for bit, and
// an edit of the keys, the interpolation or the clip is followed at once.
TEST_F(AnimNodes, anim_curve_quat__plays_its_track_bit_for_bit_and_follows_edits) {
  testing::Random random(31);
  std::vector<double> times;
  std::vector<Quat> values;
  for (int i = 0; i < 40; ++i) {
    times.push_back(i / 24.0);
    values.push_back(Quat(Eigen::Vector4d(random.uniform(-1, 1), random.uniform(-1, 1), random.uniform(-1, 1),
                                          random.uniform(-1, 1)))
                         .normalized());
  }
  const NodeId node = create(kAnimCurveQuatType, "rot");
  set(node, track_attr::kKeyTimes, times);
  set(node, track_attr::kKeyValues, values);
  auto check = [&](const QuatTrack& track, const std::string& what) {
    std::vector<double> samples;
    for (int f = -5; f < 45 * 2; ++f) samples.push_back(f / 48.0);
    for (int f = 45 * 2; f > -5; --f) samples.push_back(f / 48.0);
    for (int i = 0; i < 50; ++i) samples.push_back(random.uniform(-0.5, 2.0));
    for (double t : samples) {
      graph().set_time(t);
      ASSERT_EQ(value<Quat>(node, track_attr::kOutput).coeffs(), track.evaluate(t).coeffs()) << what << ", t " << t;
    }
  };
  check(make_or_die<Quat>(times, values, Interpolation::kLinear), "linear");
  values[7] = Quat(Eigen::AngleAxisd(1.0, Vec3::UnitY()));
  set(node, track_attr::kKeyValues, values);
  check(make_or_die<Quat>(times, values, Interpolation::kLinear), "a key edited");
  set(node, track_attr::kInterpolation, std::int64_t{static_cast<int>(Interpolation::kStep)});
  check(make_or_die<Quat>(times, values, Interpolation::kStep), "step");
  // Two clips: keys 0-19 and 20-39; clip 1 plays the second half's keys.
  set(node, track_attr::kInterpolation, std::int64_t{static_cast<int>(Interpolation::kLinear)});
  set(node, track_attr::kClipOffsets, std::vector<std::int64_t>{0, 20, 40});
  set(node, track_attr::kClip, std::int64_t{1});
  check(make_or_die<Quat>(std::vector<double>(times.begin() + 20, times.end()),
                          std::vector<Quat>(values.begin() + 20, values.end()), Interpolation::kLinear),
        "clip 1");
  EXPECT_TRUE(value<std::string>(node, track_attr::kError).empty());
}

TEST_F(AnimNodes, driven_key__follows_its_input_attribute) {
  const NodeId driver = create(scene::kJointType, "driver");
  const NodeId driven = create(scene::kJointType, "driven");
  const NodeId sdk = create(kDrivenKeyType, "sdk");
  // Set-driven key: driver radius 0 -> 10 maps to driven radius 1 -> 2, linear.
  set(sdk, curve_attr::kKeyTimes, std::vector<double>{0, 10});
  set(sdk, curve_attr::kKeyValues, std::vector<double>{1, 2});
  set(sdk, curve_attr::kInTangentType, std::vector<std::int64_t>{1, 1});
  set(sdk, curve_attr::kOutTangentType, std::vector<std::int64_t>{1, 1});
  connect(driver, scene::joint_attr::kRadius, sdk, driven_key_attr::kInput);
  connect(sdk, curve_attr::kOutput, driven, scene::joint_attr::kRadius);
  for (double x : {0.0, 2.5, 5.0, 10.0, 20.0}) {
    set(driver, scene::joint_attr::kRadius, x);
    EXPECT_DOUBLE_EQ(value<double>(driven, scene::joint_attr::kRadius), 1.0 + std::min(x, 10.0) / 10.0) << "input " << x;
  }
  graph().set_time(3.0);
  set(driver, scene::joint_attr::kRadius, 5.0);
  EXPECT_DOUBLE_EQ(value<double>(driven, scene::joint_attr::kRadius), 1.5) << "time plays no part in a driven key";
}

TEST_F(AnimNodes, anim_curve__equals_compiled_curve) {
  testing::Random random(17);
  const std::vector<Key> keys = random.keys(12);
  const CurveSettings settings{.weighted = true, .pre_infinity = Infinity::kOscillate, .post_infinity = Infinity::kCycleOffset};
  Result<AnimCurve> compiled = AnimCurve::build(keys, settings);
  ASSERT_TRUE(succeeded(compiled.status()));
  const NodeId curve = create(kAnimCurveType, "curve");
  testing::KeyColumns columns;
  columns.append(keys);
  set_keys(curve, columns);
  set(curve, curve_attr::kWeighted, true);
  set(curve, curve_attr::kPreInfinity, std::int64_t{static_cast<int>(settings.pre_infinity)});
  set(curve, curve_attr::kPostInfinity, std::int64_t{static_cast<int>(settings.post_infinity)});
  for (int frame = -48; frame < 400; frame += 7) {
    graph().set_time(frame / 24.0);
    EXPECT_EQ(value<double>(curve, curve_attr::kOutput), compiled->evaluate(frame / 24.0)) << "frame " << frame;
  }
}

TEST_F(AnimNodes, anim_curve__bad_keys_give_zero_and_an_error_naming_the_key) {
  const NodeId curve = create(kAnimCurveType, "curve");
  set(curve, curve_attr::kKeyTimes, std::vector<double>{0, 2, 1});
  set(curve, curve_attr::kKeyValues, std::vector<double>{5, 5, 5});
  graph().set_time(0.5);
  EXPECT_EQ(value<double>(curve, curve_attr::kOutput), 0.0) << "invalid keys evaluate to 0, never crash";
  EXPECT_NE(value<std::string>(curve, curve_attr::kError).find("keys[2].time: 1 is before keys[1].time 2"), std::string::npos)
      << value<std::string>(curve, curve_attr::kError);
  set(curve, curve_attr::kKeyTimes, std::vector<double>{0, 1, 2});
  EXPECT_EQ(value<double>(curve, curve_attr::kOutput), 5.0);
  EXPECT_TRUE(value<std::string>(curve, curve_attr::kError).empty()) << "fixing the keys clears the error";
  set(curve, curve_attr::kKeyValues, std::vector<double>{5, 5});
  EXPECT_EQ(value<double>(curve, curve_attr::kOutput), 0.0);
  EXPECT_NE(value<std::string>(curve, curve_attr::kError).find("keyValues has 2 entries but keyTimes has 3"), std::string::npos);
}

TEST_F(AnimNodes, anim_curve_quat__bad_keys_give_identity_and_an_error) {
  const NodeId track = create(kAnimCurveQuatType, "rot");
  set(track, track_attr::kKeyTimes, std::vector<double>{0, 1});
  set(track, track_attr::kKeyValues, std::vector<Quat>{Quat::Identity(), Quat(0, 0, 0, 0)});
  EXPECT_TRUE(value<Quat>(track, track_attr::kOutput).coeffs() == Quat::Identity().coeffs());
  EXPECT_NE(value<std::string>(track, track_attr::kError).find("keyValues[1]"), std::string::npos);
  set(track, track_attr::kInterpolation, std::int64_t{static_cast<int>(Interpolation::kCubicSpline)});
  set(track, track_attr::kKeyValues, std::vector<Quat>{Quat::Identity(), Quat::Identity()});
  EXPECT_NE(value<std::string>(track, track_attr::kError).find("inTangents has 0 entries"), std::string::npos)
      << "cubic tracks need tangents";
}

TEST_F(AnimNodes, anim_curve__empty_curve_outputs_zero) {
  const NodeId curve = create(kAnimCurveType, "curve");
  graph().set_time(1.0);
  EXPECT_EQ(value<double>(curve, curve_attr::kOutput), 0.0);
  EXPECT_TRUE(value<std::string>(curve, curve_attr::kError).empty()) << "no keys is valid";
  const NodeId track = create(kAnimCurveVec3Type, "track");
  EXPECT_TRUE(value<Vec3>(track, track_attr::kOutput) == Vec3::Zero());
}

// The check of the keys (O(keys)) is done when the keys change, not at
// every time: `error` is time-invariant, so a time change leaves it clean
// and a compute keeps its message. Playback of N frames of an N-key curve
// was O(N^2) while every frame's compute re-checked every key.
TEST_F(AnimNodes, keys_are_checked_when_they_change_not_when_the_time_does) {
  const NodeId curve = create(kAnimCurveType, "c");
  const NodeId track = create(kAnimCurveVec3Type, "v");
  const NodeId clips = create(kAnimCurveQuatType, "q");
  set(curve, curve_attr::kKeyTimes, std::vector<double>{0, 1});
  set(curve, curve_attr::kKeyValues, std::vector<double>{1, 3});
  set(track, track_attr::kKeyTimes, std::vector<double>{0, 2});
  set(track, track_attr::kKeyValues, std::vector<Vec3>{Vec3(0, 0, 0), Vec3(2, 0, 0)});
  const Quat z90(Eigen::AngleAxisd(math::kPi / 2, Vec3::UnitZ()));
  set(clips, track_attr::kKeyTimes, std::vector<double>{0, 1, 0, 1});
  set(clips, track_attr::kKeyValues, std::vector<Quat>{Quat::Identity(), z90, z90, Quat::Identity()});
  set(clips, track_attr::kClipOffsets, std::vector<std::int64_t>{0, 2, 4});
  set(clips, track_attr::kClip, std::int64_t{1});
  const std::vector<std::pair<NodeId, graph::AttrIndex>> errors = {
      {curve, curve_attr::kError}, {track, track_attr::kError}, {clips, track_attr::kError}};
  const std::vector<std::pair<NodeId, graph::AttrIndex>> outputs = {
      {curve, curve_attr::kOutput}, {track, track_attr::kOutput}, {clips, track_attr::kOutput}};
  for (const auto& [n, a] : errors) EXPECT_TRUE(value<std::string>(n, a).empty());
  for (double t : {0.25, 0.5, 0.75}) {
    graph().set_time(t);
    for (std::size_t i = 0; i < errors.size(); ++i) {
      EXPECT_TRUE(graph().node(outputs[i].first)->is_dirty(outputs[i].second)) << "t " << t;
      EXPECT_FALSE(graph().node(errors[i].first)->is_dirty(errors[i].second)) << "t " << t << ": error dirtied by time";
    }
    EXPECT_DOUBLE_EQ(value<double>(curve, curve_attr::kOutput), 1 + 2 * (3 * t * t - 2 * t * t * t))
        << "flat auto tangents at both ends";
    EXPECT_NEAR((value<Vec3>(track, track_attr::kOutput) - Vec3(t, 0, 0)).norm(), 0.0, kTight);
    const Quat q = value<Quat>(clips, track_attr::kOutput);
    EXPECT_NEAR(q.angularDistance(Quat(Eigen::AngleAxisd(math::kPi / 2 * (1 - t), Vec3::UnitZ()))), 0.0, 1e-12);
  }
  // Bad keys: checked at once, and the error stays while only time changes.
  set(curve, curve_attr::kKeyTimes, std::vector<double>{1, 0});
  set(track, track_attr::kKeyValues, std::vector<Vec3>{Vec3(0, 0, 0), Vec3(NAN, 0, 0)});
  set(clips, track_attr::kKeyTimes, std::vector<double>{0, 1, 1, 0});
  for (double t : {0.5, 0.25}) {
    graph().set_time(t);
    EXPECT_EQ(value<double>(curve, curve_attr::kOutput), 0.0);
    EXPECT_EQ(value<Vec3>(track, track_attr::kOutput), Vec3::Zero());
    EXPECT_TRUE(value<Quat>(clips, track_attr::kOutput).isApprox(Quat::Identity()));
    EXPECT_NE(value<std::string>(curve, curve_attr::kError).find("keys[1].time"), std::string::npos);
    EXPECT_NE(value<std::string>(track, track_attr::kError).find("keyValues[1]"), std::string::npos);
    EXPECT_NE(value<std::string>(clips, track_attr::kError).find("clip 1"), std::string::npos);
  }
  // Undone, the keys are valid again and are checked again.
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(graph().undo());
  graph().set_time(0.5);
  for (const auto& [n, a] : errors) EXPECT_TRUE(value<std::string>(n, a).empty());
  EXPECT_NEAR((value<Vec3>(track, track_attr::kOutput) - Vec3(0.5, 0, 0)).norm(), 0.0, kTight);
  // Switching clips re-checks (the clip picks the keys).
  set(clips, track_attr::kClip, std::int64_t{0});
  EXPECT_TRUE(graph().node(clips)->is_dirty(track_attr::kError));
  EXPECT_NEAR(value<Quat>(clips, track_attr::kOutput).angularDistance(Quat(Eigen::AngleAxisd(math::kPi / 4, Vec3::UnitZ()))),
              0.0, 1e-12);
}

// A driven key's input moves its output only: the keys are not re-checked.
TEST_F(AnimNodes, driven_key__input_leaves_the_check_clean) {
  const NodeId sdk = create(kDrivenKeyType, "sdk");
  set(sdk, curve_attr::kKeyTimes, std::vector<double>{0, 10});
  set(sdk, curve_attr::kKeyValues, std::vector<double>{1, 2});
  set(sdk, curve_attr::kInTangentType, std::vector<std::int64_t>{1, 1});
  set(sdk, curve_attr::kOutTangentType, std::vector<std::int64_t>{1, 1});
  EXPECT_DOUBLE_EQ(value<double>(sdk, curve_attr::kOutput), 1.0);
  set(sdk, driven_key_attr::kInput, 5.0);
  EXPECT_FALSE(graph().node(sdk)->is_dirty(curve_attr::kError));
  EXPECT_DOUBLE_EQ(value<double>(sdk, curve_attr::kOutput), 1.5);
  set(sdk, curve_attr::kKeyValues, std::vector<double>{1});
  EXPECT_NE(value<std::string>(sdk, curve_attr::kError).find("keyValues"), std::string::npos);
  set(sdk, driven_key_attr::kInput, 7.0);
  EXPECT_EQ(value<double>(sdk, curve_attr::kOutput), 0.0);
  EXPECT_FALSE(value<std::string>(sdk, curve_attr::kError).empty());
}


// An animCurve keeps its keys compiled (and a playback cursor) between
// evaluations: whatever the edits (new keys, one value changed, clips cut
// and switched, the rest value, undo and redo) and however time moves
// (forward, backward, jumps), its output is exactly the curve its current
// keys make.
TEST_F(AnimNodes, anim_curve__compiled_keys_follow_every_edit_undo_and_time) {
  struct State {
    std::vector<std::vector<Key>> clips;  // one clip without offsets when `cut` is false
    bool cut = false;
    std::int64_t clip = 0;
    double rest = 0.0;
    CurveSettings settings;
  };
  testing::Random random(29);
  const NodeId curve = create(kAnimCurveType, "curve");
  const auto write = [&](const State& st) {
    testing::KeyColumns columns;
    std::vector<std::int64_t> offsets{0};
    for (const std::vector<Key>& keys : st.clips) {
      columns.append(keys);
      offsets.push_back(static_cast<std::int64_t>(columns.times.size()));
    }
    if (!st.cut) offsets.clear();
    graph::Transaction step(graph(), "keys");
    set_keys(curve, columns);
    set(curve, curve_attr::kWeighted, st.settings.weighted);
    set(curve, curve_attr::kPreInfinity, std::int64_t{static_cast<int>(st.settings.pre_infinity)});
    set(curve, curve_attr::kPostInfinity, std::int64_t{static_cast<int>(st.settings.post_infinity)});
    set(curve, anim_curve_attr::kClipOffsets, offsets);
    set(curve, anim_curve_attr::kClip, st.clip);
    set(curve, anim_curve_attr::kRestValue, st.rest);
  };
  const auto expected = [](const State& st, double t) {
    if (st.clip < 0 || static_cast<std::size_t>(st.clip) >= st.clips.size()) return st.cut ? st.rest : 0.0;
    const std::vector<Key>& keys = st.clips[static_cast<std::size_t>(st.clip)];
    if (keys.empty() && st.cut) return st.rest;
    return testing::make_curve(keys, st.settings).evaluate(t);
  };
  std::vector<State> done{State{{{}}, false, 0, 0.0, {}}};
  std::vector<State> undone;
  double t = 0.0;
  for (int round = 0; round < 300; ++round) {
    SCOPED_TRACE("round " + std::to_string(round));
    const int action = random.index(8);
    if (action == 0 && done.size() > 1) {
      ASSERT_TRUE(graph().undo());
      undone.push_back(done.back());
      done.pop_back();
    } else if (action == 1 && !undone.empty()) {
      ASSERT_TRUE(graph().redo());
      done.push_back(undone.back());
      undone.pop_back();
    } else {
      State st = done.back();
      if (action <= 3) {  // new keys: one clip, or several cut by offsets
        st.cut = random.index(2) == 1;
        st.clips.assign(st.cut ? 1 + random.index(3) : 1, {});
        for (std::vector<Key>& keys : st.clips) keys = random.keys(random.index(6), random.uniform(-1, 1));
        st.settings = random.settings(random.index(2) == 1);
        st.clip = st.cut ? random.index(4) - 1 : 0;
      } else if (action == 4 && !st.clips[0].empty()) {  // one key's value
        st.clips[0][static_cast<std::size_t>(random.index(static_cast<int>(st.clips[0].size())))].value = random.uniform(-5, 5);
      } else if (action == 5 && st.cut) {
        st.clip = random.index(static_cast<int>(st.clips.size()) + 2) - 1;
      } else {
        st.rest = random.uniform(-3, 3);
      }
      write(st);
      done.push_back(st);
      undone.clear();
    }
    for (int k = 0; k < 6; ++k) {
      // Mostly frame steps either way (the cursor's sequential case), sometimes a jump.
      t = random.index(5) == 0 ? random.uniform(-2, 6) : t + random.uniform(-0.1, 0.1) * (random.index(3) == 0 ? -1 : 1);
      graph().set_time(t);
      const double v = value<double>(curve, curve_attr::kOutput);
      const double want = expected(done.back(), t);
      if (std::isnan(want)) EXPECT_TRUE(std::isnan(v)) << "t " << t;
      else EXPECT_EQ(v, want) << "t " << t;
      ASSERT_TRUE(value<std::string>(curve, curve_attr::kError).empty()) << value<std::string>(curve, curve_attr::kError);
    }
  }
}

}  // namespace
}  // namespace rigel::ops::anim
