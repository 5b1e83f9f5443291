// blendShapeSliders and corrective (components/shapes.h): sliders drive a
// blendShape's weights from the weights it had (Khronos' SimpleMorph, two
// targets), a corrective takes a joint to its offset and a target to its
// weight as the driver swings (Rigify's metarig and SimpleMorph); rest kept,
// removal exact, stepping equal to the straight build, bad names refused.
#include <gtest/gtest.h>

#include <filesystem>

#include "rig_test_util.h"
#include "rigel/io/gltf_import.h"
#include "rigel/io/scene_file.h"
#include "rigel/ops/deform/nodes.h"
#include "rigel/rig/build.h"
#include "rigel/rig/meta.h"
#include "rigel/scene/transform_types.h"

namespace rigel::rig {
namespace {

using graph::Plug;
using graph::Value;
using math::Vec3;
using testing::at_joint;
namespace xform = scene::xform;
namespace bs = ops::blend_shape_attr;

NodeId shape_of(graph::Graph& g) {
  for (NodeId id : g.nodes())
    if (g.node(id)->type().name() == ops::kBlendShapeType) return id;
  return {};
}

// SimpleMorph (two targets); `animated`: with its weight animation, else
// with the weights its animation holds at 0 s, free to be driven.
std::unique_ptr<scene::Scene> morph(bool animated = false) {
  io::GltfImportOptions options;
  options.registry = default_registry();
  auto imported = io::import_gltf(std::filesystem::path(RIGEL_SOURCE_DIR) / "tests/data/gltf/SimpleMorph.gltf", options);
  EXPECT_TRUE(imported.is_ok()) << imported.status().message();
  if (!imported) return nullptr;
  graph::Graph& g = (*imported)->graph();
  const NodeId shape = shape_of(g);
  if (!animated && shape.is_valid()) {
    const std::vector<double> now = std::get<std::vector<double>>(g.evaluate(shape, bs::kWeights));
    for (std::int32_t t = 0; t < 2; ++t) {
      if (g.source(Plug{shape, bs::kWeights, t})) {
        EXPECT_TRUE(g.disconnect_input(Plug{shape, bs::kWeights, t}).is_ok());
      }
    }
    EXPECT_TRUE(g.set_value(Plug{shape, bs::kWeights, -1}, Value(now)).is_ok());
    g.clear_history();
  }
  return std::move(*imported);
}

Component sliders(std::vector<Param> params = {}) {
  Guide panel;
  panel.name = "panel";
  panel.translate = Vec3(1, 0.5, 0);
  return testing::make_component("blendShapeSliders", "face", {panel}, std::move(params));
}

Definition with(std::vector<Component> under_global) {
  Definition d;
  d.name = "shapes";
  Component global = testing::make_component("global", "global", {Guide{}});
  global.children = std::move(under_global);
  d.components = {global};
  return d;
}

struct Built {
  std::unique_ptr<scene::Scene> scene;
  std::unique_ptr<Build> build;
  std::string before;
};

Built build_on(std::unique_ptr<scene::Scene> scene, Definition d) {
  Built b;
  b.scene = std::move(scene);
  if (!b.scene) return b;
  b.before = io::write_scene(*b.scene);
  auto opened = Build::open(*b.scene, std::move(d), builtin_components());
  EXPECT_TRUE(opened.is_ok()) << opened.status().message();
  if (!opened) return b;
  b.build = std::move(*opened);
  const Status s = b.build->build_all();
  EXPECT_TRUE(s.is_ok()) << s.message();
  if (!s) b.build.reset();
  return b;
}

std::vector<Vec3> points(graph::Graph& g, NodeId shape) {
  return std::get<std::vector<Vec3>>(g.evaluate(shape, bs::kOutPoints));
}

double weight(graph::Graph& g, NodeId shape, int t) {
  return std::get<std::vector<double>>(g.evaluate(shape, bs::kWeights))[static_cast<std::size_t>(t)];
}

TEST(BlendShapeSliders, each_slider_adds_to_its_weight_from_the_weight_it_had) {
  auto scene = morph();
  ASSERT_TRUE(scene);
  graph::Graph& g0 = scene->graph();
  const NodeId shape0 = shape_of(g0);
  ASSERT_TRUE(shape0.is_valid());
  const std::vector<Vec3> rest = points(g0, shape0);
  const double w0 = weight(g0, shape0, 0), w1 = weight(g0, shape0, 1);
  Built b = build_on(std::move(scene), with({sliders()}));
  ASSERT_TRUE(b.build);
  graph::Graph& g = b.scene->graph();
  const NodeId shape = shape_of(g);
  EXPECT_EQ(points(g, shape), rest) << "nothing moves at rest";
  const NodeId s0 = testing::at(*b.scene, "shapes:face/slider[0]");
  const NodeId s1 = testing::at(*b.scene, "shapes:face/slider[1]");
  // The panel's column: slider 1 `spacing` below slider 0.
  EXPECT_NEAR((b.scene->world_matrix(s0).topRightCorner<3, 1>() - b.scene->world_matrix(s1).topRightCorner<3, 1>()).norm(),
              0.05, 1e-12);
  ASSERT_TRUE(g.set_value(Plug{s0, xform::kTranslate, -1}, Value(Vec3(0, 0.25, 0))).is_ok());
  EXPECT_NEAR(weight(g, shape, 0), std::min(1.0, w0 + 0.25), 1e-12);
  EXPECT_NEAR(weight(g, shape, 1), w1, 1e-12);
  ASSERT_TRUE(g.set_value(Plug{s1, xform::kTranslate, -1}, Value(Vec3(0, 5, 0))).is_ok());
  EXPECT_NEAR(weight(g, shape, 1), 1.0, 1e-12) << "clamped at max";
  ASSERT_TRUE(g.set_value(Plug{s1, xform::kTranslate, -1}, Value(Vec3(0, -5, 0))).is_ok());
  EXPECT_NEAR(weight(g, shape, 1), 0.0, 1e-12) << "clamped at min";
  EXPECT_NE(points(g, shape), rest) << "the mesh takes the weights";
  ASSERT_TRUE(b.build->remove().is_ok());
  EXPECT_EQ(io::write_scene(*b.scene), b.before) << "removed byte for byte";
}

TEST(BlendShapeSliders, stepping_equals_the_straight_build_and_bad_names_are_refused) {
  Built b = build_on(morph(), with({sliders({testing::make_param("targets", std::string("1"))})}));
  ASSERT_TRUE(b.build);
  EXPECT_EQ(static_cast<int>(b.build->plan().size()), b.build->position());
  testing::expect_stepping_gives_the_straight_build(*b.build, *b.scene);
  EXPECT_FALSE(get_meta_connection(b.scene->graph(), find_component(b.scene->graph(), find_rig(b.scene->graph(), "shapes"), "face"),
                                   "slider", 1)
                   .is_ok())
      << "one slider: target 1 only";
  for (const auto& [param, value, expected] :
       {std::tuple{"targets", "7", "has no target '7' (2 targets)"},
        std::tuple{"blendShape", "nope", "no blendShape node 'nope'"},
        std::tuple{"targets", "0", "is already connected from"}}) {
    auto scene = morph(std::string(value) == "0");  // an animated weight is not taken over
    auto opened = Build::open(*scene, with({sliders({testing::make_param(param, std::string(value))})}), builtin_components());
    ASSERT_TRUE(opened.is_ok());
    const Status s = (*opened)->build_all();
    ASSERT_FALSE(s.is_ok());
    EXPECT_NE(s.message().find(expected), std::string::npos) << s.message();
    EXPECT_NE(s.message().find("build face/"), std::string::npos) << s.message();
  }
}

TEST(Corrective, the_drivers_swing_takes_the_joint_to_its_offset_and_the_target_to_its_weight) {
  // On the metarig: the forearm's bend moves a corrective joint.
  Component fix = testing::make_component("corrective", "elbowFix", {at_joint("forearm.L"), at_joint("palm.01.L")},
                                          {testing::make_param("offset", Vec3(0, 0.02, 0.01)),
                                           testing::make_param("startAngle", 0.0), testing::make_param("endAngle", 90.0)});
  testing::BuiltRig r = testing::built_rig(with({fix}));
  ASSERT_TRUE(r.build);
  graph::Graph& g = r.g();
  std::string worst;
  EXPECT_LT(testing::pose_error(*r.scene, r.rest, &worst), 1e-12) << "nothing moves at rest: " << worst;
  const NodeId forearm = g.find("forearm.L"), palm = g.find("palm.01.L");
  const Vec3 rest = std::get<Vec3>(g.evaluate(palm, xform::kTranslate));
  // Bend the forearm 45 degrees about its x: its y axis swings 45 degrees.
  const math::Quat q = std::get<math::Quat>(g.evaluate(forearm, xform::kRotateQuaternion));
  ASSERT_TRUE(g.set_value(Plug{forearm, xform::kRotateMode, -1}, Value(xform::kQuaternionMode)).is_ok());
  ASSERT_TRUE(g.set_value(Plug{forearm, xform::kRotateQuaternion, -1},
                          Value(math::Quat(q * math::Quat(Eigen::AngleAxisd(M_PI / 4, Vec3::UnitX())))))
                  .is_ok());
  EXPECT_LT((std::get<Vec3>(g.evaluate(palm, xform::kTranslate)) - (rest + Vec3(0, 0.01, 0.005))).norm(), 1e-9)
      << "half way: half the offset";
  ASSERT_TRUE(r.build->remove().is_ok());

  // On SimpleMorph: a driver transform's swing weights target 0.
  auto scene = morph();
  ASSERT_TRUE(scene);
  Result<NodeId> driver = scene->create(scene::kTransformType, "driver");
  ASSERT_TRUE(driver.is_ok());
  Component shape = testing::make_component("corrective", "shapeFix", {at_joint("driver")},
                                            {testing::make_param("target", std::string("0")),
                                             testing::make_param("endAngle", 60.0)});
  Built b = build_on(std::move(scene), with({shape}));
  ASSERT_TRUE(b.build);
  graph::Graph& gm = b.scene->graph();
  const NodeId blend = shape_of(gm);
  EXPECT_NEAR(weight(gm, blend, 0), 0.0, 1e-12);
  ASSERT_TRUE(gm.set_value(Plug{*driver, xform::kRotate, -1}, Value(Vec3(30, 0, 0))).is_ok());
  EXPECT_NEAR(weight(gm, blend, 0), 0.5, 1e-9);
  ASSERT_TRUE(gm.set_value(Plug{*driver, xform::kRotate, -1}, Value(Vec3(90, 0, 0))).is_ok());
  EXPECT_NEAR(weight(gm, blend, 0), 1.0, 1e-12) << "held past endAngle";
  ASSERT_TRUE(gm.set_value(Plug{*driver, xform::kRotate, -1}, Value(Vec3(0, 0, 0))).is_ok());
  ASSERT_TRUE(b.build->remove().is_ok());
  EXPECT_EQ(io::write_scene(*b.scene), b.before);
}

TEST(Corrective, with_nothing_to_correct_or_backward_angles_it_fails_naming_the_component) {
  for (const auto& [params, expected] :
       {std::pair{std::vector<Param>{}, "nothing to correct"},
        std::pair{std::vector<Param>{testing::make_param("startAngle", 50.0), testing::make_param("endAngle", 40.0),
                                     testing::make_param("target", std::string("0"))},
                  "startAngle must be below endAngle"}}) {
    testing::BuiltRig r;
    r.scene = testing::metarig();
    auto opened = Build::open(*r.scene, with({testing::make_component("corrective", "fix", {at_joint("forearm.L")}, params)}),
                              builtin_components());
    ASSERT_TRUE(opened.is_ok());
    const Status s = (*opened)->build_all();
    ASSERT_FALSE(s.is_ok());
    EXPECT_NE(s.message().find(std::string("fix (corrective): ") + expected), std::string::npos) << s.message();
  }
}

}  // namespace
}  // namespace rigel::rig
