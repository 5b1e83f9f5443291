// Set-driven keys and driven poses / correctives as data
// (tools/driven_poses.h) on the biped built on the Rigify metarig: poses
// keyed at driver values drive their channels between and beyond the
// keys; the file comes back on a rebuild from scratch and is written again
// byte for byte; correctives (a joint's angle driving a blend shape
// weight) are told apart from driven poses; bad requests and files are
// refused naming the plug or place, with nothing changed.

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "rigel/ops/anim/nodes.h"
#include "rigel/ops/deform/nodes.h"
#include "rigel/tools/driven_poses.h"
#include "tools_test_util.h"

namespace rigel::tools {
namespace {

using graph::NodeId;

std::string channel(const graph::Graph& g, const std::string& address, const std::string& attr) {
  return g.node(testing::at(g, address))->name() + "." + attr;
}

double value_of(graph::Graph& g, const std::string& plug) {
  auto p = g.plug_find(plug);
  EXPECT_TRUE(p.is_ok()) << plug;
  return std::get<double>(*g.evaluate(*p));
}

void set(graph::Graph& g, const std::string& plug, double v) {
  auto p = g.plug_find(plug);
  ASSERT_TRUE(p.is_ok()) << plug;
  ASSERT_TRUE(g.set_value(*p, graph::Value(v)).is_ok()) << plug;
}

std::size_t driven_key_count(const graph::Graph& g) {
  std::size_t n = 0;
  for (NodeId id : g.nodes()) n += g.node(id)->type().name() == ops::anim::kDrivenKeyType;
  return n;
}

struct Keyed {
  std::string driver, a, b;
};

// Two poses and an in-between on the left arm: fk[0].rotateX drives the
// elbow's and the other arm's fk[1].rotateZ.
Keyed key_poses(graph::Graph& g) {
  Keyed k{channel(g, "hero:arm_L/fk[0]", "rotateX"), channel(g, "hero:arm_L/fk[1]", "rotateZ"),
          channel(g, "hero:arm_R/fk[1]", "rotateZ")};
  auto r = set_driven_key(g, DrivenKeyRequest{k.driver, 0.0, {{k.a, 0.0}, {k.b, std::nullopt}}});
  EXPECT_TRUE(r.is_ok()) << r.status().message();
  EXPECT_EQ(r->created, 2u);
  r = set_driven_key(g, DrivenKeyRequest{k.driver, 90.0, {{k.a, -45.0}, {k.b, 30.0}}});
  EXPECT_TRUE(r.is_ok()) << r.status().message();
  EXPECT_EQ(r->created, 0u);
  r = set_driven_key(g, DrivenKeyRequest{k.driver, 45.0, {{k.a, -10.0}}, ops::anim::TangentType::kLinear});
  EXPECT_TRUE(r.is_ok()) << r.status().message();
  return k;
}

TEST(DrivenKeys, poses_drive_their_channels_at_between_and_beyond_the_keys) {
  auto s = testing::built_rig();
  ASSERT_TRUE(s);
  graph::Graph& g = s->graph();
  const double rest_b = value_of(g, channel(g, "hero:arm_R/fk[1]", "rotateZ"));
  const std::size_t before = driven_key_count(g);
  const Keyed k = key_poses(g);
  EXPECT_EQ(driven_key_count(g), before + 2);
  set(g, k.driver, 90.0);
  EXPECT_NEAR(value_of(g, k.a), -45.0, 1e-12);
  EXPECT_NEAR(value_of(g, k.b), 30.0, 1e-12);
  set(g, k.driver, 45.0);
  EXPECT_NEAR(value_of(g, k.a), -10.0, 1e-12);
  set(g, k.driver, 0.0);
  EXPECT_NEAR(value_of(g, k.b), rest_b, 1e-12) << "a channel keyed at its value now";
  set(g, k.driver, 200.0);
  EXPECT_NEAR(value_of(g, k.a), -45.0, 1e-12) << "constant beyond the last pose";
  // The same driver value again replaces the key.
  auto r = set_driven_key(g, DrivenKeyRequest{k.driver, 90.0 + 1e-12, {{k.a, -50.0}}});
  ASSERT_TRUE(r.is_ok()) << r.status().message();
  auto poses = capture_driven_poses(g, DrivenData::kPoses);
  ASSERT_TRUE(poses.is_ok());
  ASSERT_EQ(poses->drivers.size(), 1u);
  EXPECT_EQ(poses->drivers[0].driver, k.driver);
  ASSERT_EQ(poses->drivers[0].curves.size(), 2u);
  EXPECT_EQ(poses->drivers[0].curves[0].driven, k.a);
  EXPECT_EQ(poses->drivers[0].curves[0].times, (std::vector<double>{0, 45, 90}));
  EXPECT_EQ(poses->drivers[0].curves[0].values, (std::vector<double>{0, -10, -50}));
  EXPECT_EQ(poses->drivers[0].curves[0].in_types, (std::vector<std::string>{"auto", "linear", "auto"}));
  EXPECT_TRUE(capture_driven_poses(g, DrivenData::kCorrectives)->drivers.empty());
  // One undo step per pose.
  ASSERT_TRUE(g.undo());
  set(g, k.driver, 90.0);
  EXPECT_NEAR(value_of(g, k.a), -45.0, 1e-12);
  // Removed, each channel keeps its value now.
  ASSERT_TRUE(remove_driven_keys(g, {k.b}).is_ok());
  EXPECT_NEAR(value_of(g, k.b), 30.0, 1e-12);
  set(g, k.driver, 0.0);
  EXPECT_NEAR(value_of(g, k.b), 30.0, 1e-12);
  EXPECT_EQ(capture_driven_poses(g, DrivenData::kPoses)->drivers[0].curves.size(), 1u);
}

TEST(DrivenKeys, bad_requests_are_refused_naming_the_plug_and_change_nothing) {
  auto s = testing::built_rig();
  ASSERT_TRUE(s);
  graph::Graph& g = s->graph();
  const Keyed k = key_poses(g);
  const std::size_t count = driven_key_count(g);
  auto refused = [&](DrivenKeyRequest request, const std::string& part) {
    auto r = set_driven_key(g, request);
    ASSERT_FALSE(r.is_ok()) << part;
    EXPECT_NE(r.status().message().find(part), std::string::npos) << r.status().message();
    EXPECT_EQ(driven_key_count(g), count);
  };
  refused({"nobody.rotateX", 1.0, {{k.a, 1.0}}}, "nobody");
  refused({k.driver, 1.0, {}}, "no driven channel");
  refused({k.driver, 1.0, {{k.a, 1.0}, {k.a, 2.0}}}, "named twice");
  refused({k.driver, 1.0, {{channel(g, "hero:arm_L/fk[2]", "translate"), 1.0}}}, "double3, not a number");
  refused({k.driver, 1.0, {{k.driver, 1.0}}}, "is the driver");
  refused({channel(g, "hero:arm_R/fk[0]", "rotateX"), 1.0, {{k.a, 1.0}}}, "not from");
  // A joint the rig drives: its channel is fed by the rig, not a driven key.
  refused({k.driver, 1.0, {{"forearm.L.translateX", 1.0}}}, "not by a driven key");
  EXPECT_FALSE(remove_driven_keys(g, {"forearm.L.translateX"}).is_ok());
}

TEST(DrivenPosesData, driven_poses_come_back_on_a_rebuild_from_scratch_byte_for_byte) {
  auto s = testing::built_rig();
  ASSERT_TRUE(s);
  const Keyed k = key_poses(s->graph());
  const std::string file = driven_poses_to_json(*capture_driven_poses(s->graph(), DrivenData::kPoses));
  EXPECT_NE(file.find("\"rigelDrivenPoses\": 1"), std::string::npos);
  EXPECT_NE(file.find("\"kind\": \"drivenPoses\""), std::string::npos);

  auto fresh = testing::built_rig();
  graph::Graph& g = fresh->graph();
  auto back = driven_poses_from_json(file, "hero.drivenposes.json", DrivenData::kPoses);
  ASSERT_TRUE(back.is_ok()) << back.status().message();
  auto r = apply_driven_poses(g, *back);
  ASSERT_TRUE(r.is_ok()) << r.status().message();
  EXPECT_EQ(r->curves, 2u);
  EXPECT_EQ(r->created, 2u);
  EXPECT_EQ(r->keys, 5u);
  EXPECT_EQ(driven_poses_to_json(*capture_driven_poses(g, DrivenData::kPoses)), file) << "byte for byte";
  for (double at : {-20.0, 0.0, 30.0, 45.0, 60.0, 90.0, 120.0}) {
    set(s->graph(), k.driver, at);
    set(g, k.driver, at);
    EXPECT_EQ(value_of(g, k.a), value_of(s->graph(), k.a)) << at;
    EXPECT_EQ(value_of(g, k.b), value_of(s->graph(), k.b)) << at;
  }
  // Imported again onto the same channels: their curves take the file's keys.
  r = apply_driven_poses(g, *back);
  ASSERT_TRUE(r.is_ok());
  EXPECT_EQ(r->created, 0u);
  EXPECT_EQ(driven_poses_to_json(*capture_driven_poses(g, DrivenData::kPoses)), file);
  // A file naming a channel this scene lacks: refused, nothing changed.
  auto broken = *back;
  broken.drivers[0].curves[1].driven = "hero_nothing.rotateZ";
  broken.drivers[0].curves[0].values[2] = 7.0;
  const std::size_t count = driven_key_count(g);
  auto failed = apply_driven_poses(g, broken);
  ASSERT_FALSE(failed.is_ok());
  EXPECT_NE(failed.status().message().find("hero_nothing"), std::string::npos);
  EXPECT_EQ(driven_key_count(g), count);
  EXPECT_EQ(driven_poses_to_json(*capture_driven_poses(g, DrivenData::kPoses)), file) << "rolled back";
}

TEST(DrivenPosesData, correctives_are_a_joint_angle_driving_blend_shape_weights) {
  auto s = testing::built_rig();
  ASSERT_TRUE(s);
  graph::Graph& g = s->graph();
  auto shape = g.create_node(ops::kBlendShapeType, "body_fix");
  ASSERT_TRUE(shape.is_ok());
  ASSERT_TRUE(g.set_value({*shape, ops::blend_shape_attr::kWeights, -1}, graph::Value(std::vector<double>{0, 0})).is_ok());
  key_poses(g);
  // A pose reader on the elbow: 0 at rest, the swing of the forearm's axis as the rig bends it.
  auto reader = create_pose_reader(g, g.find("forearm.L"), math::Vec3(0, 1, 0));
  ASSERT_TRUE(reader.is_ok()) << reader.status().message();
  const std::string elbow = g.node(*reader)->name() + ".angle";
  EXPECT_EQ(elbow, "forearm.L_poseReader.angle");
  EXPECT_NEAR(value_of(g, elbow), 0.0, 1e-9);
  auto r = set_driven_key(g, DrivenKeyRequest{elbow, 0.0, {{"body_fix.weights[1]", 0.0}}, ops::anim::TangentType::kLinear});
  ASSERT_TRUE(r.is_ok()) << r.status().message();
  r = set_driven_key(g, DrivenKeyRequest{elbow, 90.0, {{"body_fix.weights[1]", 1.0}}, ops::anim::TangentType::kLinear});
  ASSERT_TRUE(r.is_ok()) << r.status().message();
  auto correctives = capture_driven_poses(g, DrivenData::kCorrectives);
  ASSERT_EQ(correctives->drivers.size(), 1u);
  EXPECT_EQ(correctives->drivers[0].driver, elbow);
  EXPECT_EQ(correctives->drivers[0].curves[0].driven, "body_fix.weights[1]");
  EXPECT_EQ(capture_driven_poses(g, DrivenData::kPoses)->drivers.size(), 1u) << "the arm's poses only";
  // The weight follows the elbow as the arm's FK control bends it.
  EXPECT_NEAR(value_of(g, "body_fix.weights[1]"), 0.0, 1e-9);
  const std::string fk = g.node(testing::at(g, "hero:arm_L/fk[1]"))->name();
  for (const char* axis : {"rotateX", "rotateY"}) set(g, fk + "." + axis, 40.0);  // rotateZ: a driven pose
  const double bent = value_of(g, elbow);
  EXPECT_GT(bent, 1.0) << "the elbow turned";
  EXPECT_NEAR(value_of(g, "body_fix.weights[1]"), std::clamp(bent / 90.0, 0.0, 1.0), 1e-12);
  const std::string file = driven_poses_to_json(*correctives);
  EXPECT_NE(file.find("\"kind\": \"correctives\""), std::string::npos);
  // A correctives file is not a driven-poses file.
  auto wrong = driven_poses_from_json(file, "x.drivenposes.json", DrivenData::kPoses);
  ASSERT_FALSE(wrong.is_ok());
  EXPECT_NE(wrong.status().message().find("x.drivenposes.json: kind: a file of correctives"), std::string::npos);
  // Pose readers refuse what is not a joint's frame or an axis.
  EXPECT_EQ(create_pose_reader(g, *shape, math::Vec3(1, 0, 0)).status().field(), "joint");
  EXPECT_EQ(create_pose_reader(g, g.find("forearm.L"), math::Vec3(0, 0, 0)).status().field(), "axis");
}

TEST(DrivenPosesData, malformed_files_are_refused_naming_the_place) {
  auto place = [](const std::string& text) {
    auto r = driven_poses_from_json(text, "p.json", DrivenData::kPoses);
    EXPECT_FALSE(r.is_ok()) << text;
    EXPECT_EQ(r.status().code(), ErrorCode::kParseError);
    return r.status().message();
  };
  EXPECT_NE(place("{\"rigelDrivenPoses\": 1,\n \"kind\": }").find("p.json:2:"), std::string::npos);
  EXPECT_NE(place("{\"rigelDrivenPoses\": 2, \"kind\": \"drivenPoses\", \"drivers\": []}").find("newer rigel"), std::string::npos);
  const std::string head = "{\"rigelDrivenPoses\": 1, \"kind\": \"drivenPoses\", \"drivers\": [{\"driver\": \"a.x\", \"curves\": [";
  EXPECT_NE(place(head + "{\"node\": \"k\", \"driven\": \"b.y\", \"keys\": [[0, 1], [1]]}]}]}").find("drivers[0].curves[0].keys[1]"),
            std::string::npos);
  EXPECT_NE(place(head + "{\"node\": \"k\", \"driven\": \"b.y\", \"keys\": [[1, 1], [0, 2]]}]}]}").find("drivers[0].curves[0]"),
            std::string::npos)
      << "driver values out of order";
  EXPECT_NE(place(head + "{\"node\": \"k\", \"driven\": \"b.y\", \"keys\": [[0, 1]], \"inTangents\": [\"wobbly\"]}]}]}").find("wobbly"),
            std::string::npos);
  EXPECT_NE(place(head + "{\"node\": \"k\", \"driven\": \"b.y\", \"keys\": [[0, 1]], \"colour\": 1}]}]}").find("colour"),
            std::string::npos);
  EXPECT_NE(place(head + "{\"node\": \"k\", \"driven\": \"b.y\", \"keys\": [[0, 1]]}, {\"node\": \"j\", \"driven\": \"b.y\", \"keys\": [[0, 1]]}]}]}")
                .find("driven twice"),
            std::string::npos);
}

}  // namespace
}  // namespace rigel::tools
