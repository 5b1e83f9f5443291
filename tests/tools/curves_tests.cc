// The graph editor's curves (tools/curves.h): a built rig's control and its
// fkIk switch keyed, shown as curves with tangents and samples equal to
// the evaluated channel; keys moved in time and value, tangents changed,
// inserted on the curve and deleted, each one undo step; glTF rotation
// tracks (CesiumMan) shown per component and as unwrapped Euler angles.

#include "rigel/tools/curves.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "rigel/math/rotation.h"
#include "rigel/ops/anim/channel_keys.h"
#include "rigel/rig/meta.h"
#include "rigel/scene/transform_types.h"
#include "tools_test_util.h"

namespace rigel::tools {
namespace {

using graph::NodeId;
using graph::Plug;
using testing::at;
using ops::anim::TangentType;
namespace xform = scene::xform;

class Curves : public ::testing::Test {
 protected:
  void SetUp() override {
    scene_ = testing::built_rig();
    ASSERT_TRUE(scene_);
    ik_ = at(g(), "hero:arm_L/ik");
    switch_ = at(g(), "hero:arm_L/fkIkSwitch");
    // translate keyed at 0 and 10, fkIk at 0, 10, 20.
    for (double f : {0.0, 10.0}) {
      scene_->set_frame(f);
      auto ch = channels_of(g(), {ik_}, {"translate"});
      ASSERT_TRUE(ch.is_ok());
      ASSERT_EQ(ch->size(), 1u);
      Channel y = ch->front();
      y.component = 1;
      auto st = set_values(g(), {y}, {f * 0.01}, /*auto_key=*/true);
      ASSERT_TRUE(st.is_ok()) << st.message();
    }
    auto sw = channels_of(g(), {switch_}, {"fkIk"});
    ASSERT_TRUE(sw.is_ok());
    for (auto [f, v] : {std::pair{0.0, 0.0}, std::pair{10.0, 1.0}, std::pair{20.0, 0.5}}) {
      scene_->set_frame(f);
      ASSERT_TRUE(set_keys(g(), *sw, v).is_ok());
    }
    g().clear_history();
  }
  graph::Graph& g() { return scene_->graph(); }
  double fps() { return g().fps(); }
  std::vector<CurveView> views(const CurveViewOptions& o = {}) {
    auto ch = channels_of(g(), {ik_, switch_});
    EXPECT_TRUE(ch.is_ok());
    auto v = curve_views(g(), *ch, o);
    EXPECT_TRUE(v.is_ok()) << v.status().message();
    return v ? *v : std::vector<CurveView>{};
  }
  const CurveView* find(const std::vector<CurveView>& vs, const std::string& name) {
    for (const CurveView& v : vs)
      if (v.name == name) return &v;
    ADD_FAILURE() << "no curve " << name;
    return nullptr;
  }
  double value_at(const Plug& p, double frame) {
    scene_->set_frame(frame);
    auto v = g().evaluate(Plug{p.node, p.attr, -1});
    EXPECT_TRUE(v.is_ok());
    if (p.component >= 0) return std::get<math::Vec3>(*v)[p.component];
    return std::get<double>(*v);
  }
  std::unique_ptr<scene::Scene> scene_;
  NodeId ik_, switch_;
};

TEST_F(Curves, keyed_channels_show_as_curves_whose_samples_are_the_channels_values) {
  const std::vector<CurveView> vs = views();
  const CurveView* ty = find(vs, "hero_arm_L_ik.translateY");
  const CurveView* sw = find(vs, "hero_arm_L_fkIkSwitch.fkIk");
  ASSERT_TRUE(ty && sw);
  EXPECT_EQ(ty->kind, "curve");
  EXPECT_EQ(ty->label, "translateY");
  ASSERT_EQ(sw->key_times.size(), 3u);
  EXPECT_NEAR(sw->key_times[2] * fps(), 20, 1e-9);
  EXPECT_EQ(sw->key_values, (std::vector<double>{0, 1, 0.5}));
  EXPECT_EQ(sw->in_tangents.size(), 3u);
  EXPECT_EQ(sw->in_slopes.size(), 3u);
  // One sample a frame over the keys, each the value the channel evaluates to.
  EXPECT_EQ(sw->sample_times.size(), 21u);
  for (std::size_t i = 0; i < sw->sample_times.size(); i += 3)
    EXPECT_DOUBLE_EQ(sw->sample_values[i], value_at(sw->plug, sw->sample_times[i] * fps())) << i;
  CurveViewOptions wide;
  wide.first = -1;
  wide.last = 2;
  wide.step = 0.5;
  const std::vector<CurveView> wide_views = views(wide);
  const CurveView* w = find(wide_views, "hero_arm_L_fkIkSwitch.fkIk");
  ASSERT_TRUE(w);
  EXPECT_EQ(w->sample_times.front(), -1);
  EXPECT_EQ(w->sample_times.back(), 2);
  CurveViewOptions bad;
  bad.step = 0;
  auto ch = channels_of(g(), {switch_});
  EXPECT_EQ(curve_views(g(), *ch, bad).status().field(), "step");
  bad.step = 1e-9;
  EXPECT_EQ(curve_views(g(), *ch, bad).status().field(), "step") << "too many samples";
}

TEST_F(Curves, a_key_moved_in_time_and_value_changes_the_pose_at_that_frame_and_undoes) {
  const double before = value_at(Plug{switch_, g().node(switch_)->type().attr_find("fkIk"), -1}, 15);
  CurveKeyEdit e;
  e.key = {"hero_arm_L_fkIkSwitch.fkIk", (10 + 3e-4) / fps()};  // a hair off frame 10
  e.to_time = 15 / fps();
  e.value = 0.6;
  auto n = edit_curve_keys(g(), {e});
  ASSERT_TRUE(n.is_ok()) << n.status().message();
  EXPECT_EQ(*n, 1u);
  const Plug fkik{switch_, g().node(switch_)->type().attr_find("fkIk"), -1};
  EXPECT_DOUBLE_EQ(value_at(fkik, 15), 0.6);
  EXPECT_NE(before, 0.6);
  ASSERT_EQ(g().undo_count(), 1u);
  ASSERT_TRUE(g().undo());
  EXPECT_DOUBLE_EQ(value_at(fkik, 15), before);
  EXPECT_DOUBLE_EQ(value_at(fkik, 10), 1.0);
}

TEST_F(Curves, tangents_insert_and_delete) {
  CurveKeyEdit step;
  step.key = {"hero_arm_L_fkIkSwitch.fkIk", 0};
  step.out_type = TangentType::kStep;
  ASSERT_TRUE(edit_curve_keys(g(), {step}).is_ok());
  const Plug fkik{switch_, g().node(switch_)->type().attr_find("fkIk"), -1};
  EXPECT_EQ(value_at(fkik, 9.9), 0.0) << "step holds the key's value";
  const std::vector<CurveView> stepped = views();
  const CurveView* sw = find(stepped, "hero_arm_L_fkIkSwitch.fkIk");
  ASSERT_TRUE(sw);
  EXPECT_EQ(sw->out_tangents[0], "step");
  // Insert on the curve where it passes: the value there is unchanged.
  const double at5 = value_at(Plug{ik_, xform::kTranslate, -1, 1}, 5);
  auto ins = insert_curve_keys(g(), {{"hero_arm_L_ik.translateY", 5 / fps()}});
  ASSERT_TRUE(ins.is_ok()) << ins.status().message();
  EXPECT_EQ(*ins, 1u);
  EXPECT_DOUBLE_EQ(value_at(Plug{ik_, xform::kTranslate, -1, 1}, 5), at5);
  const std::vector<CurveView> inserted = views();
  const CurveView* ty = find(inserted, "hero_arm_L_ik.translateY");
  const CurveView* tx = find(inserted, "hero_arm_L_ik.translateX");
  ASSERT_TRUE(ty && tx);
  EXPECT_EQ(ty->key_times.size(), 3u);
  EXPECT_EQ(tx->key_times.size(), 2u) << "only that curve";
  // Delete: a curve left without keys goes, its channel keeps its value.
  auto del = delete_curve_keys(g(), {{"hero_arm_L_ik.translateX", 0}, {"hero_arm_L_ik.translateX", 10 / fps()}});
  ASSERT_TRUE(del.is_ok()) << del.status().message();
  EXPECT_EQ(*del, 2u);
  auto ch = channels_of(g(), {ik_}, {"translate"});
  auto left = curve_views(g(), *ch);
  ASSERT_TRUE(left.is_ok());
  for (const CurveView& v : *left) EXPECT_NE(v.name, "hero_arm_L_ik.translateX");
  // Bad references name "keys".
  CurveKeyEdit gone;
  gone.key = {"hero_arm_L_ik.translateX", 0};
  EXPECT_EQ(edit_curve_keys(g(), {gone}).status().field(), "keys");
  EXPECT_EQ(delete_curve_keys(g(), {{"nosuch.translateX", 0}}).status().field(), "keys");
  EXPECT_EQ(delete_curve_keys(g(), {{"hero_arm_L_ik.translateY", 3 / fps()}}).status().code(), ErrorCode::kNotFound);
}

TEST(CurvesGltf, rotation_tracks_show_per_component_and_as_unwrapped_euler) {
  auto s = testing::import_character(testing::source("tests/data/gltf/CesiumMan.glb"));
  ASSERT_TRUE(s);
  graph::Graph& g = s->graph();
  // A joint with a rotation track.
  std::vector<Channel> channels;
  for (NodeId id : s->hierarchy()) {
    auto ch = channels_of(g, {id}, {"rotateQuaternion"});
    if (!ch) continue;
    for (const Channel& c : *ch)
      if (!keys_of(g, {c}).empty()) channels.push_back(c);
    if (!channels.empty()) break;
  }
  ASSERT_FALSE(channels.empty());
  CurveViewOptions components;
  components.quat_as_euler = false;
  auto q = curve_views(g, channels, components);
  ASSERT_TRUE(q.is_ok()) << q.status().message();
  ASSERT_EQ(q->size(), 4u);
  EXPECT_EQ((*q)[3].label, "rotateQuaternion.w");
  EXPECT_FALSE((*q)[0].editable);
  auto e = curve_views(g, channels);
  ASSERT_TRUE(e.is_ok());
  ASSERT_EQ(e->size(), 3u);
  EXPECT_EQ((*e)[0].label, "rotate.x");
  // Each sample's angles give the sampled rotation back, and no step jumps.
  for (std::size_t i = 0; i < (*e)[0].sample_times.size(); ++i) {
    const math::Vec3 deg((*e)[0].sample_values[i], (*e)[1].sample_values[i], (*e)[2].sample_values[i]);
    const math::Quat from_euler = math::euler_to_quat(deg * (M_PI / 180), math::RotateOrder::kXYZ);
    const math::Quat sampled((*q)[3].sample_values[i], (*q)[0].sample_values[i], (*q)[1].sample_values[i],
                             (*q)[2].sample_values[i]);
    EXPECT_NEAR(std::abs(from_euler.normalized().dot(sampled.normalized())), 1.0, 1e-9) << i;
    if (i > 0) {
      for (int c = 0; c < 3; ++c) EXPECT_LT(std::abs((*e)[c].sample_values[i] - (*e)[c].sample_values[i - 1]), 90.0) << i;
    }
  }
  // Keys of a rotation track move in time but take no component value.
  CurveKeyEdit value;
  value.key = {(*e)[0].name, (*e)[0].key_times[1]};
  value.value = 10;
  EXPECT_EQ(edit_curve_keys(g, {value}).status().field(), "keys");
  CurveKeyEdit moved;
  moved.key = {(*e)[0].name, (*e)[0].key_times.back()};
  moved.to_time = (*e)[0].key_times.back() + 0.5;
  ASSERT_TRUE(edit_curve_keys(g, {moved}).is_ok());
  EXPECT_DOUBLE_EQ((*curve_views(g, channels))[0].key_times.back(), moved.to_time.value());
}

}  // namespace
}  // namespace rigel::tools
