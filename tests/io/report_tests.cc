// Tests of the JSON reports (include/rigel/io/report.h) that `rigel inspect
// --json` and `rigel eval --json` print. The eval report's shape is a
// contract (DESIGN.md, CLI contract).

#include "rigel/io/report.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "io_test_util.h"

namespace rigel::io {
namespace {

using namespace rigel::io::testing;  // NOLINT: test helpers
using Json = nlohmann::ordered_json;

constexpr double kTolerance = 1e-12;

NodeId create(Scene& scene, std::string_view type, std::string_view name, NodeId parent = NodeId{}) {
  Result<NodeId> id = scene.create(type, name, parent);
  EXPECT_TRUE(id.is_ok()) << "creating '" << name << "' should succeed: " << id.status().message();
  return id.is_ok() ? *id : NodeId{};
}

void set(Scene& scene, NodeId node, std::string_view attr, Value value) {
  Result<Plug> plug = scene.graph().plug_find(node, attr);
  ASSERT_TRUE(plug.is_ok()) << "the attribute should exist: " << plug.status().message();
  Status s = scene.graph().set_value(*plug, std::move(value));
  EXPECT_TRUE(s.is_ok()) << "setting " << attr << " should succeed: " << s.message();
}

// Expected values within kTolerance; a quaternion also matches when negated
// (q and -q are the same rotation).
::testing::AssertionResult near(const Json& actual, const std::vector<double>& expected, bool quaternion = false) {
  if (!actual.is_array() || actual.size() != expected.size())
    return ::testing::AssertionFailure() << actual.dump() << " should have " << expected.size() << " numbers";
  for (double sign : {1.0, -1.0}) {
    if (!quaternion && sign < 0) break;
    bool all = true;
    for (std::size_t i = 0; i < expected.size(); ++i)
      all = all && std::abs(actual[i].get<double>() - sign * expected[i]) <= kTolerance;
    if (all) return ::testing::AssertionSuccess();
  }
  Json want = expected;
  return ::testing::AssertionFailure() << actual.dump() << " vs expected " << want.dump();
}

// ---- inspect ---------------------------------------------------------------

TEST(InspectReport, fields_describe_nodes_hierarchy_tags_and_connections) {
  Scene scene;
  Graph& g = scene.graph();
  NodeId root = create(scene, "transform", "root");
  NodeId hip = create(scene, "joint", "hip", root);
  create(scene, "joint", "knee", hip);
  NodeId ctrl = create(scene, "control", "ctrl");
  NodeId loc = create(scene, "locator", "loc", ctrl);
  create(scene, "mesh", "geo");
  ASSERT_TRUE(g.set_tag(ctrl, "side", "L").is_ok()) << "tagging should succeed";
  ASSERT_TRUE(g.connect(*g.plug_find("hip.worldMatrix"), *g.plug_find("loc.offsetParentMatrix")).is_ok())
      << "a matrix connection should succeed";
  scene.set_frame(12.0);

  const Json report = inspect_report(scene);
  EXPECT_EQ(report["fps"], 24.0) << "the default frame rate";
  EXPECT_EQ(report["time"], 0.5) << "frame 12 at 24 fps is 0.5 s";
  EXPECT_EQ(report["frame"], 12.0) << "the current frame";
  EXPECT_EQ(report["node_count"], 6) << "every node is counted";
  EXPECT_EQ(report["types"], Json::parse(R"({"control": 1, "joint": 2, "locator": 1, "mesh": 1, "transform": 1})"))
      << "nodes are counted by type";
  EXPECT_EQ(report["roots"], Json::parse(R"(["root", "ctrl", "geo"])")) << "roots are listed in creation order";
  ASSERT_EQ(report["nodes"].size(), 6u) << "every node is listed";

  const Json& hip_json = report["nodes"][1];
  EXPECT_EQ(hip_json["name"], "hip") << "nodes are listed in creation order";
  EXPECT_EQ(hip_json["type"], "joint") << "the node's type";
  EXPECT_EQ(hip_json["uuid"], g.node(hip)->uuid().str()) << "the node's uuid";
  EXPECT_EQ(hip_json["parent"], "root") << "the parent by name";
  EXPECT_EQ(hip_json["children"], Json::array({"knee"})) << "the children by name";
  EXPECT_EQ(hip_json["tags"], Json::object()) << "an untagged node has an empty tags object";
  EXPECT_FALSE(report["nodes"][0].contains("parent")) << "a root has no parent member";
  EXPECT_EQ(report["nodes"][3]["tags"], Json::parse(R"({"side": "L"})")) << "tags are listed";
  EXPECT_EQ(report["nodes"][3]["children"], Json::array({"loc"})) << "ctrl's child";
  EXPECT_EQ(report["nodes"][4]["parent"], "ctrl") << "loc's parent";
  (void)loc;
  EXPECT_EQ(report["connections"], Json::parse(R"([{"src": "hip.worldMatrix", "dst": "loc.offsetParentMatrix"}])"))
      << "connections exclude the hierarchy, which parent/children describe";
}

// ---- eval --------------------------------------------------------------------

// root: translate (1, 2, 3), rotate (0, 0, 90) degrees, scale 2.
// tip, its child: translate (1, 0, 0), rotate (90, 0, 0).
// aim: a locator at (0, 1, 0) under tip's world matrix through its offset
// parent matrix (a connection, not the hierarchy).
//
// By hand: root world = T(1,2,3) Rz(90) S(2).
//   tip world = root world T(1,0,0) Rx(90): position (1,2,3) + Rz(90)(2,0,0)
//   = (1,4,3); rotation Rz(90) Rx(90), the quaternion (0.5, 0.5, 0.5, 0.5)
//   (120 degrees about (1,1,1): x -> y -> z -> x); scale 2.
//   aim world = tip world T(0,1,0): (1,4,3) + 2 R(0,1,0) = (1,4,3) + (0,0,2).
TEST(EvalReport, two_joint_chain_matches_hand_computed_world_transforms) {
  Scene scene;
  NodeId root = create(scene, "joint", "root");
  NodeId tip = create(scene, "joint", "tip", root);
  NodeId aim = create(scene, "locator", "aim");
  set(scene, root, "translate", Vec3(1, 2, 3));
  set(scene, root, "rotate", Vec3(0, 0, 90));
  set(scene, root, "scale", Vec3(2, 2, 2));
  set(scene, tip, "translate", Vec3(1, 0, 0));
  set(scene, tip, "rotate", Vec3(90, 0, 0));
  set(scene, aim, "translate", Vec3(0, 1, 0));
  Graph& g = scene.graph();
  ASSERT_TRUE(g.connect(*g.plug_find("tip.worldMatrix"), *g.plug_find("aim.offsetParentMatrix")).is_ok())
      << "a matrix connection should succeed";

  const Json report = eval_report(scene);
  const double h = std::sqrt(0.5);
  const Json& nodes = report["nodes"];
  EXPECT_TRUE(near(nodes["root"]["t"], {1, 2, 3})) << "root's world translation is its translate";
  EXPECT_TRUE(near(nodes["root"]["q"], {0, 0, h, h}, true)) << "root's world rotation is 90 degrees about z";
  EXPECT_TRUE(near(nodes["root"]["s"], {2, 2, 2})) << "root's world scale is its scale";
  EXPECT_TRUE(near(nodes["tip"]["t"], {1, 4, 3})) << "tip sits 1 unit along root's rotated, scaled x";
  EXPECT_TRUE(near(nodes["tip"]["q"], {0.5, 0.5, 0.5, 0.5}, true)) << "tip's rotation is Rz(90) Rx(90)";
  EXPECT_TRUE(near(nodes["tip"]["s"], {2, 2, 2})) << "tip inherits root's scale";
  EXPECT_TRUE(near(nodes["aim"]["t"], {1, 4, 5})) << "aim is offset by tip's world matrix";
  EXPECT_TRUE(near(nodes["aim"]["q"], {0.5, 0.5, 0.5, 0.5}, true)) << "aim inherits tip's rotation";
  EXPECT_TRUE(near(nodes["aim"]["s"], {2, 2, 2})) << "aim inherits tip's scale";
}

TEST(EvalReport, has_the_contract_shape_for_every_transform_node_of_every_type) {
  Scene scene;
  NodeId group = create(scene, "transform", "group");
  NodeId joint = create(scene, "joint", "joint", group);
  create(scene, "control", "control", joint);
  create(scene, "locator", "locator", group);
  create(scene, "mesh", "mesh");
  set(scene, joint, "rotate", Vec3(12, 34, 56));
  const Json report = eval_report(scene);
  std::vector<std::string> keys;
  for (auto it = report.begin(); it != report.end(); ++it) keys.push_back(it.key());
  EXPECT_EQ(keys, (std::vector<std::string>{"frame", "time", "nodes"})) << "exactly frame, time and nodes, in order";
  std::vector<std::string> names;
  for (auto it = report["nodes"].begin(); it != report["nodes"].end(); ++it) {
    names.push_back(it.key());
    const Json& n = it.value();
    std::vector<std::string> members;
    for (auto m = n.begin(); m != n.end(); ++m) members.push_back(m.key());
    EXPECT_EQ(members, (std::vector<std::string>{"t", "q", "s"})) << it.key() << " has exactly t, q, s";
    ASSERT_EQ(n["q"].size(), 4u) << it.key() << ": q is [x, y, z, w]";
    double norm = 0;
    for (const Json& c : n["q"]) norm += c.get<double>() * c.get<double>();
    EXPECT_NEAR(norm, 1.0, 1e-12) << it.key() << ": q is a unit quaternion";
    EXPECT_EQ(n["t"].size(), 3u) << it.key() << ": t is [x, y, z]";
    EXPECT_EQ(n["s"].size(), 3u) << it.key() << ": s is [x, y, z]";
  }
  EXPECT_EQ(names, (std::vector<std::string>{"group", "joint", "control", "locator", "mesh"}))
      << "every transform node, depth first from the roots";
}

TEST(EvalReport, frame_and_time_follow_the_scene_time) {
  Scene scene;
  create(scene, "joint", "j");
  scene.graph().set_time(0.25);
  Json report = eval_report(scene);
  EXPECT_EQ(report["time"], 0.25) << "the scene's time in seconds";
  EXPECT_EQ(report["frame"], 6.0) << "0.25 s at 24 fps is frame 6";
  ASSERT_TRUE(scene.graph().set_fps(30.0).is_ok()) << "30 fps is valid";
  scene.set_frame(15.0);
  report = eval_report(scene);
  EXPECT_EQ(report["time"], 0.5) << "frame 15 at 30 fps is 0.5 s";
  EXPECT_EQ(report["frame"], 15.0) << "the frame set";
}

TEST(EvalReport, empty_scene_has_an_empty_nodes_object) {
  Scene scene;
  const Json report = eval_report(scene);
  EXPECT_TRUE(report["nodes"].is_object() && report["nodes"].empty()) << "no transform nodes, an empty object";
}

}  // namespace
}  // namespace rigel::io
