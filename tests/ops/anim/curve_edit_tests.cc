// One time curve edited key by key (curve_edit.h): moves keep values and
// tangents and reorder, moves onto a key replace it, inserted keys lie on
// the curve, slopes make fixed tangents, clips other than the active one
// are left alone, rotations refuse values, every edit is one undo step and
// refused edits change nothing. Samples equal the node's own evaluation.

#include "rigel/ops/anim/curve_edit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "anim_test_util.h"
#include "rigel/graph/graph.h"
#include "rigel/ops/anim/nodes.h"
#include "rigel/ops/registry.h"
#include "rigel/scene/transform_types.h"

namespace rigel::ops::anim {
namespace {

using graph::Graph;
using graph::NodeId;
using graph::Plug;
using math::Quat;
using math::Vec3;
using testing::fails_with;
using testing::succeeded;
namespace xform = scene::xform;

struct ScalarFixture {
  ScalarFixture() : g(default_registry()) {
    t = *g.create_node(scene::kTransformType, "t");
    c = *g.create_node(kAnimCurveType, "c");
    EXPECT_TRUE(succeeded(g.set_value(Plug{c, curve_attr::kKeyTimes, -1}, std::vector<double>{0, 1, 2})));
    EXPECT_TRUE(succeeded(g.set_value(Plug{c, curve_attr::kKeyValues, -1}, std::vector<double>{0, 10, 0})));
    EXPECT_TRUE(succeeded(g.connect(Plug{c, curve_attr::kOutput, -1}, Plug{t, xform::kTranslate, -1, 0})));
    g.clear_history();
  }
  double at(double time) {
    g.set_time(time);
    return std::get<double>(*g.evaluate(Plug{c, curve_attr::kOutput, -1}));
  }
  Graph g;
  NodeId t, c;
};

KeyChange move(std::size_t key, double time) {
  KeyChange k;
  k.key = key;
  k.time = time;
  return k;
}

TEST(CurveEdit, MovingAKeyKeepsItsValueAndTangentsAndUndoesInOneStep) {
  ScalarFixture f;
  KeyChange linear;
  linear.key = 0;
  linear.out_type = TangentType::kLinear;
  ASSERT_TRUE(succeeded(edit_curve(f.g, f.c, std::vector{linear})));
  f.g.clear_history();
  // Key 0 (linear out) moves past key 1; key 1 takes value 5.
  KeyChange value;
  value.key = 1;
  value.value = 5;
  ASSERT_TRUE(succeeded(edit_curve(f.g, f.c, std::vector{move(0, 1.5), value})));
  const CurveKeys k = curve_keys(f.g, f.c);
  EXPECT_EQ(k.times, (std::vector<double>{1, 1.5, 2}));
  EXPECT_EQ(k.values, (std::vector<std::vector<double>>{{5}, {0}, {0}}));
  EXPECT_EQ(k.out_types[1], TangentType::kLinear);
  EXPECT_EQ(k.out_types[0], TangentType::kAuto);
  EXPECT_EQ(f.g.undo_count(), 1u);
  ASSERT_TRUE(f.g.undo());
  const CurveKeys back = curve_keys(f.g, f.c);
  EXPECT_EQ(back.times, (std::vector<double>{0, 1, 2}));
  EXPECT_EQ(back.values, (std::vector<std::vector<double>>{{0}, {10}, {0}}));
  EXPECT_EQ(back.out_types[0], TangentType::kLinear);
}

TEST(CurveEdit, AMoveOntoAKeyThatStaysReplacesItTwoOntoOneTimeAreRefused) {
  ScalarFixture f;
  ASSERT_TRUE(succeeded(edit_curve(f.g, f.c, std::vector{move(1, 2.0)})));
  EXPECT_EQ(curve_keys(f.g, f.c).times, (std::vector<double>{0, 2}));
  EXPECT_EQ(curve_keys(f.g, f.c).values, (std::vector<std::vector<double>>{{0}, {10}}));
  ASSERT_TRUE(f.g.undo());
  const std::size_t undo = f.g.undo_count();
  EXPECT_TRUE(fails_with(edit_curve(f.g, f.c, std::vector{move(0, 1.5), move(2, 1.5)}), "two keys changed to one time"));
  EXPECT_EQ(curve_keys(f.g, f.c).times, (std::vector<double>{0, 1, 2}));
  EXPECT_EQ(f.g.undo_count(), undo);
  // Shifting every key by the same offset is no collision.
  ASSERT_TRUE(succeeded(edit_curve(f.g, f.c, std::vector{move(0, 1), move(1, 2), move(2, 3)})));
  EXPECT_EQ(curve_keys(f.g, f.c).times, (std::vector<double>{1, 2, 3}));
}

TEST(CurveEdit, BadChangesNameTheChangeAndChangeNothing) {
  ScalarFixture f;
  EXPECT_TRUE(fails_with(edit_curve(f.g, f.c, std::vector{move(3, 1.0)}), "changes[0]: key 3 is out of range"));
  EXPECT_TRUE(fails_with(edit_curve(f.g, f.c, std::vector{move(0, std::nan(""))}), "changes[0]: the time is not finite"));
  KeyChange fresh;  // a new key with no time
  EXPECT_TRUE(fails_with(edit_curve(f.g, f.c, std::vector{fresh}), "a new key needs a time"));
  EXPECT_TRUE(fails_with(edit_curve(f.g, f.t, std::vector{move(0, 1.0)}), "not a time curve"));
  EXPECT_EQ(f.g.undo_count(), 0u);
  EXPECT_EQ(curve_keys(f.g, f.c).times, (std::vector<double>{0, 1, 2}));
}

TEST(CurveEdit, AnInsertedKeyLiesOnTheCurve) {
  ScalarFixture f;
  const double before = f.at(0.37);
  KeyChange fresh;
  fresh.time = 0.37;
  ASSERT_TRUE(succeeded(edit_curve(f.g, f.c, std::vector{fresh})));
  const CurveKeys k = curve_keys(f.g, f.c);
  ASSERT_EQ(k.times.size(), 4u);
  EXPECT_EQ(k.times[1], 0.37);
  EXPECT_DOUBLE_EQ(k.values[1][0], before);
  EXPECT_DOUBLE_EQ(f.at(0.37), before);
}

TEST(CurveEdit, ASlopeMakesAFixedTangentTheCurveFollows) {
  ScalarFixture f;
  KeyChange slope;
  slope.key = 1;
  slope.out_slope = 4.0;
  slope.in_slope = 4.0;
  ASSERT_TRUE(succeeded(edit_curve(f.g, f.c, std::vector{slope})));
  const CurveKeys k = curve_keys(f.g, f.c);
  EXPECT_EQ(k.in_types[1], TangentType::kFixed);
  EXPECT_EQ(k.out_types[1], TangentType::kFixed);
  EXPECT_DOUBLE_EQ(k.out_slopes[1], 4.0);
  const double h = 1e-6;
  EXPECT_NEAR((f.at(1 + h) - f.at(1 - h)) / (2 * h), 4.0, 1e-4);
  // The other keys keep auto (the array was empty: every key the default).
  EXPECT_EQ(k.out_types[0], TangentType::kAuto);
  EXPECT_EQ(k.out_types[2], TangentType::kAuto);
}

TEST(CurveEdit, SamplesAreTheNodesEvaluation) {
  ScalarFixture f;
  const std::vector<double> times{-1, 0, 0.25, 0.5, 1, 1.7, 2, 3};
  const auto samples = sample_curve(f.g, f.c, times);
  ASSERT_EQ(samples.size(), times.size());
  for (std::size_t i = 0; i < times.size(); ++i) EXPECT_EQ(samples[i][0], f.at(times[i])) << times[i];
}

TEST(CurveEdit, EditsTouchOnlyTheActiveClip) {
  Graph g(default_registry());
  const NodeId t = *g.create_node(scene::kTransformType, "t");
  const NodeId v = *g.create_node(kAnimCurveVec3Type, "v");
  const std::vector<double> times = {0, 0.5, 1, 0, 0.5, 0, 1, 2};
  std::vector<Vec3> values;
  for (std::size_t i = 0; i < times.size(); ++i) values.push_back(Vec3(static_cast<double>(i), 0, 0));
  ASSERT_TRUE(succeeded(g.set_value(Plug{v, track_attr::kKeyTimes, -1}, times)));
  ASSERT_TRUE(succeeded(g.set_value(Plug{v, track_attr::kKeyValues, -1}, values)));
  ASSERT_TRUE(succeeded(g.set_value(Plug{v, track_attr::kClipOffsets, -1}, std::vector<std::int64_t>{0, 3, 5, 8})));
  ASSERT_TRUE(succeeded(g.set_value(Plug{v, track_attr::kClip, -1}, std::int64_t{1})));
  ASSERT_TRUE(succeeded(g.connect(Plug{v, track_attr::kOutput, -1}, Plug{t, xform::kTranslate, -1})));
  // Clip 1 is keys 3 and 4 (times 0, 0.5): move the first to 0.75, set y of
  // the second, insert one at 0.25.
  KeyChange y;
  y.key = 1;
  y.value = 7;
  y.component = 1;
  KeyChange fresh;
  fresh.time = 0.25;
  ASSERT_TRUE(succeeded(edit_curve(g, v, std::vector{move(0, 0.75), y, fresh})));
  const graph::Node& n = *g.node(v);
  EXPECT_EQ(std::get<std::vector<double>>(n.value(track_attr::kKeyTimes)),
            (std::vector<double>{0, 0.5, 1, 0.25, 0.5, 0.75, 0, 1, 2}));
  EXPECT_EQ(std::get<std::vector<std::int64_t>>(n.value(track_attr::kClipOffsets)), (std::vector<std::int64_t>{0, 3, 6, 9}));
  const auto& vs = std::get<std::vector<Vec3>>(n.value(track_attr::kKeyValues));
  EXPECT_EQ(vs[4], Vec3(4, 7, 0));
  EXPECT_EQ(vs[5], Vec3(3, 0, 0));
  EXPECT_EQ(vs[0], Vec3(0, 0, 0));
  EXPECT_EQ(vs[8], Vec3(7, 0, 0));
  // A track takes no tangent types; a component out of range is refused.
  KeyChange tangent;
  tangent.key = 0;
  tangent.in_type = TangentType::kFlat;
  EXPECT_TRUE(fails_with(edit_curve(g, v, std::vector{tangent}), "tangents apply to curves"));
  y.component = 3;
  EXPECT_TRUE(fails_with(edit_curve(g, v, std::vector{y}), "component 0, 1 or 2"));
}

TEST(CurveEdit, RotationKeysMoveButRefuseComponentValuesAndStaySignContinuous) {
  Graph g(default_registry());
  const NodeId t = *g.create_node(scene::kTransformType, "t");
  const NodeId q = *g.create_node(kAnimCurveQuatType, "q");
  const Quat a = Quat::Identity();
  const Quat b(Eigen::AngleAxisd(1.0, Vec3::UnitY()));
  const Quat c(Eigen::AngleAxisd(2.0, Vec3::UnitY()));
  ASSERT_TRUE(succeeded(g.set_value(Plug{q, track_attr::kKeyTimes, -1}, std::vector<double>{0, 1, 2})));
  ASSERT_TRUE(succeeded(g.set_value(Plug{q, track_attr::kKeyValues, -1}, std::vector<Quat>{a, b, c})));
  ASSERT_TRUE(succeeded(g.connect(Plug{q, track_attr::kOutput, -1}, Plug{t, xform::kRotateQuaternion, -1})));
  KeyChange value;
  value.key = 1;
  value.value = 0.5;
  value.component = 0;
  EXPECT_TRUE(fails_with(edit_curve(g, q, std::vector{value}), "rotation track"));
  // c moves first: b follows it, and keeps the sign nearest c.
  ASSERT_TRUE(succeeded(edit_curve(g, q, std::vector{move(2, -1.0)})));
  const CurveKeys k = curve_keys(g, q);
  EXPECT_EQ(k.times, (std::vector<double>{-1, 0, 1}));
  for (std::size_t i = 1; i < 3; ++i) {
    const Quat p(k.values[i - 1][3], k.values[i - 1][0], k.values[i - 1][1], k.values[i - 1][2]);
    const Quat n(k.values[i][3], k.values[i][0], k.values[i][1], k.values[i][2]);
    EXPECT_GE(p.dot(n), 0.0) << i;
  }
}

}  // namespace
}  // namespace rigel::ops::anim
