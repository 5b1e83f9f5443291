// The JSON API's rigger actions (GET/POST /api/shape, POST /api/align,
// /api/locators, /api/mirror-joints, GET/POST /api/driven-keys; docs/SERVER.md)
// on the biped built on the bundled metarig, and its data managers (POST
// /api/data/export and import; blend shapes on Khronos' SimpleMorph): the
// same results as the library's calls, each one undo step, refusals naming
// the field.

#include <gtest/gtest.h>

#include <string>

#include "server_test_util.h"
#include "workspace.h"

namespace rigel::server {
namespace {

TEST(ServerApi, ShapesCopiedPastedMirroredFlippedAndMirroredToTheOtherSide) {
  Served s = served_biped();
  ASSERT_TRUE(s.workspace);
  const Json arm = s.get("/api/shape?control=hero:arm_L/ik");
  const Json leg = s.get("/api/shape?control=hero_leg_L_ik");
  EXPECT_EQ(arm["name"], "hero_arm_L_ik");
  ASSERT_NE(arm["points"], leg["points"]);
  // Paste the arm's shape onto the leg's control (the colour stays).
  Json r = s.post("/api/shape", {{"op", "paste"}, {"controls", {"hero_leg_L_ik"}}, {"shape", arm}, {"parts", {"shape"}}});
  EXPECT_EQ(r["controls"][0]["name"], "hero_leg_L_ik");
  Json pasted = s.get("/api/shape?control=hero_leg_L_ik");
  EXPECT_EQ(pasted["points"], arm["points"]);
  EXPECT_EQ(pasted["color"], leg["color"]);
  s.post("/api/undo", Json::object());
  EXPECT_EQ(s.get("/api/shape?control=hero_leg_L_ik")["points"], leg["points"]);
  // Mirror in place on the selection; twice gives it back.
  s.post("/api/select", {{"controls", {s.uuid("hero_arm_L_ik")}}});
  s.post("/api/shape", {{"op", "mirror"}});
  const Json once = s.get("/api/shape?control=hero_arm_L_ik");
  EXPECT_EQ(once["points"][0][0].get<double>(), -arm["points"][0][0].get<double>());
  s.post("/api/shape", {{"op", "mirror"}});
  EXPECT_EQ(s.get("/api/shape?control=hero_arm_L_ik")["points"], arm["points"]);
  s.post("/api/shape", {{"op", "flip"}});
  EXPECT_EQ(s.get("/api/shape?control=hero_arm_L_ik")["points"][0][2].get<double>(), -arm["points"][0][2].get<double>());
  // Onto the other side.
  r = s.post("/api/shape", {{"op", "opposite"}, {"controls", {"hero_arm_L_ik"}}});
  ASSERT_EQ(r["pairs"].size(), 1u);
  EXPECT_EQ(r["pairs"][0]["to"], s.uuid("hero_arm_R_ik"));
  for (auto [body, field] :
       {std::pair{R"({"op":"paste","controls":["hero_arm_L_ik"]})", "shape"},
        std::pair{R"({"op":"paste","controls":["hero_arm_L_ik"],"shape":{"points":[[0,0]]}})", "shape.points[0]"},
        std::pair{R"({"op":"paste","controls":["hero_arm_L_ik"],"shape":{"points":[],"color":[3,0,0]}})", "shape.color"},
        std::pair{R"({"op":"paste","controls":["hero_arm_L_ik"],"shape":{"points":[]},"parts":["size"]})", "parts"},
        std::pair{R"({"op":"opposite","controls":["hero_hip_main"]})", "controls"},
        std::pair{R"({"op":"mirror","controls":["hand.L"]})", "controls"},
        std::pair{R"({"op":"grow"})", "op"}}) {
    Response resp = s.request("POST", "/api/shape", body);
    EXPECT_EQ(resp.status, 400) << body << ": " << resp.body;
    EXPECT_EQ(Json::parse(resp.body)["field"], field) << body;
  }
  EXPECT_EQ(s.request("GET", "/api/shape?control=nobody", "").status, 404);
  EXPECT_EQ(s.request("GET", "/api/shape", "").status, 400);
}

TEST(ServerApi, LocatorsAlignAndMirrorJoints) {
  Served s = served_biped();
  ASSERT_TRUE(s.workspace);
  Json r = s.post("/api/locators", {{"nodes", {"hand.L"}}, {"size", 0.05}});
  ASSERT_EQ(r["locators"].size(), 1u);
  EXPECT_EQ(r["locators"][0]["name"], "hand.L_loc");
  const Json controls = s.get("/api/nodes")["controls"];
  bool drawn = false;
  for (const Json& c : controls) drawn = drawn || c["name"] == "hand.L_loc";
  EXPECT_TRUE(drawn) << "a locator is a control the page draws";
  // The arm's IK control onto the locator moved away: position and rotation.
  s.post("/api/channel-values", {{"controls", {"hand.L_loc"}}, {"attrs", {"translateY"}}, {"value", 1.3}});
  r = s.post("/api/align", {{"nodes", {"hero:arm_L/ik"}}, {"target", "hand.L_loc"}});
  EXPECT_EQ(r["moved"][0]["name"], "hero_arm_L_ik");
  const Json pose = s.get("/api/pose?space=world")["nodes"];
  EXPECT_LT(std::abs(pose[s.uuid("hero_arm_L_ik")][1].get<double>() - 1.3), 1e-9);
  s.post("/api/undo", Json::object());
  EXPECT_GT(std::abs(s.get("/api/pose?space=world")["nodes"][s.uuid("hero_arm_L_ik")][1].get<double>() - 1.3), 1e-3);
  // Joints: a centre one is refused; the left arm updates the right.
  Response centre = s.request("POST", "/api/mirror-joints", R"({"joints":["spine"]})");
  EXPECT_EQ(centre.status, 400) << centre.body;
  EXPECT_EQ(Json::parse(centre.body)["field"], "joints");
  Response exists = s.request("POST", "/api/mirror-joints", R"({"joints":["f_pinky.01.L"]})");
  EXPECT_EQ(exists.status, 400) << exists.body;
  // The built rig drives the right hand's joints: a conflict naming what feeds them.
  Response driven = s.request("POST", "/api/mirror-joints", R"({"joints":["f_pinky.01.L"],"update":true})");
  EXPECT_EQ(driven.status, 409) << driven.body;
  EXPECT_NE(driven.body.find("hero_hand_R_drive"), std::string::npos) << driven.body;
  Served bare = served_character();
  r = bare.post("/api/mirror-joints", {{"joints", {"f_pinky.01.L"}}, {"update", true}});
  EXPECT_EQ(r["updated"].size(), 3u);
  EXPECT_TRUE(r["created"].empty());
  for (auto [body, field] : {std::pair{R"({"nodes":["hero_arm_L_ik"]})", "target"},
                             std::pair{R"({"nodes":["hero_arm_L_ik"],"target":"hand.L_loc","position":false,"rotation":false})", "match"},
                             std::pair{R"({"nodes":["hero_arm_L_ik"],"target":"hand.L_loc","position":1})", "position"}}) {
    Response resp = s.request("POST", "/api/align", body);
    EXPECT_EQ(resp.status, 400) << body << ": " << resp.body;
    EXPECT_EQ(Json::parse(resp.body)["field"], field) << body;
  }
  EXPECT_EQ(Json::parse(s.request("POST", "/api/locators", R"({"nodes":["hand.L"],"size":-1})").body)["field"], "size");
}

TEST(ServerApi, DataExportedAndImportedInsideTheRoot) {
  Served s = served_biped();
  ASSERT_TRUE(s.workspace);
  Json r = s.post("/api/data/export", {{"kind", "shapes"}, {"file", "data/hero.shapes.json"}});
  EXPECT_EQ(r["file"], "data/hero.shapes.json");
  ASSERT_TRUE(fs::exists(s.root / "data" / "hero.shapes.json"));
  s.post("/api/shape", {{"op", "mirror"}, {"controls", {"hero_arm_L_ik"}}});
  const Json mirrored = s.get("/api/shape?control=hero_arm_L_ik");
  r = s.post("/api/data/import", {{"kind", "shapes"}, {"file", "data/hero.shapes.json"}});
  EXPECT_GT(r["set"].get<int>(), 50);
  EXPECT_NE(s.get("/api/shape?control=hero_arm_L_ik")["points"], mirrored["points"]) << "the file's shape back";
  s.post("/api/undo", Json::object());
  EXPECT_EQ(s.get("/api/shape?control=hero_arm_L_ik")["points"], mirrored["points"]);
  r = s.post("/api/data/export", {{"kind", "weights"}, {"file", "data/w.weights.json"}});
  r = s.post("/api/data/import", {{"kind", "weights"}, {"file", "data/w.weights.json"}, {"mirror", true}});
  EXPECT_GE(r["skins"].get<int>(), 1);
  EXPECT_FALSE(r["remapped"].empty()) << "the left joints onto the right";
  // The arrays in a side file beside it, inside the root; read back.
  r = s.post("/api/data/export", {{"kind", "weights"}, {"file", "data/b.weights.json"}, {"format", "binary"}});
  const Json b = Json::parse(read_text(s.root / "data" / "b.weights.json"));
  ASSERT_TRUE(b.contains("binary"));
  EXPECT_TRUE(fs::is_regular_file(s.root / "data" / b["binary"]["file"].get<std::string>()));
  EXPECT_GE(s.post("/api/data/import", {{"kind", "weights"}, {"file", "data/b.weights.json"}})["skins"].get<int>(), 1);
  for (auto [body, field] : {std::pair{R"({"kind":"weights","file":"data/c.weights.json","format":"xml"})", "format"},
                             std::pair{R"({"kind":"shapes","file":"data/c.shapes.json","format":"binary"})", "format"}}) {
    Response resp = s.request("POST", "/api/data/export", body);
    EXPECT_EQ(resp.status, 400) << body << ": " << resp.body;
    EXPECT_EQ(Json::parse(resp.body)["field"], field) << body;
  }
  for (auto [body, status, field] :
       {std::tuple{R"({"kind":"colours","file":"x.json"})", 400, "kind"},
        std::tuple{R"({"kind":"shapes","file":"../outside.json"})", 400, "file"},
        std::tuple{R"({"kind":"shapes","file":"data/none.json"})", 404, "file"},
        std::tuple{R"({"kind":"shapes","file":"data/w.weights.json"})", 400, "file"},
        std::tuple{R"({"kind":"shapes","file":"data/hero.shapes.json","mirror":true})", 400, "mirror"},
        std::tuple{R"({"kind":"weights","file":"data/w.weights.json","rename":[1]})", 400, "rename"}}) {
    Response resp = s.request("POST", "/api/data/import", body);
    EXPECT_EQ(resp.status, status) << body << ": " << resp.body;
    EXPECT_EQ(Json::parse(resp.body)["field"], field) << body;
  }
  EXPECT_FALSE(fs::exists(s.dir->path() / "outside.json"));
}

TEST(ServerApi, DrivenKeysSetListedRemovedExportedAndImported) {
  Served s = served_biped();
  ASSERT_TRUE(s.workspace);
  Json r = s.post("/api/driven-keys", {{"op", "set"}, {"driver", "hero_arm_L_fk0.rotateX"}, {"at", 0},
                                        {"driven", {{"hero_arm_L_fk1.rotateZ", 0}, {"hero_arm_R_fk1.rotateZ", nullptr}}}});
  EXPECT_EQ(r["created"], 2);
  r = s.post("/api/driven-keys", {{"op", "set"}, {"driver", "hero_arm_L_fk0.rotateX"}, {"at", 90}, {"tangent", "linear"},
                                   {"driven", {{"hero_arm_L_fk1.rotateZ", -45}, {"hero_arm_R_fk1.rotateZ", 30}}}});
  EXPECT_EQ(r["at"], 90);
  EXPECT_EQ(r["curves"].size(), 2u);
  Json listed = s.get("/api/driven-keys");
  ASSERT_EQ(listed["drivenPoses"]["drivers"].size(), 1u);
  EXPECT_EQ(listed["drivenPoses"]["drivers"][0]["curves"][0]["values"], Json::array({0, -45}));
  EXPECT_TRUE(listed["correctives"]["drivers"].empty());
  // Exported, removed, imported back; one undo step each.
  r = s.post("/api/data/export", {{"kind", "driven_poses"}, {"file", "data/hero.drivenposes.json"}});
  EXPECT_EQ(r["file"], "data/hero.drivenposes.json");
  const std::string file = read_text(s.root / "data" / "hero.drivenposes.json");
  s.post("/api/driven-keys", {{"op", "remove"}, {"driven", {"hero_arm_L_fk1.rotateZ", "hero_arm_R_fk1.rotateZ"}}});
  EXPECT_TRUE(s.get("/api/driven-keys")["drivenPoses"]["drivers"].empty());
  r = s.post("/api/data/import", {{"kind", "driven_poses"}, {"file", "data/hero.drivenposes.json"}});
  EXPECT_EQ(r["curves"], 2);
  EXPECT_EQ(r["created"], 2);
  s.post("/api/data/export", {{"kind", "driven_poses"}, {"file", "data/again.json"}});
  EXPECT_EQ(read_text(s.root / "data" / "again.json"), file);
  s.post("/api/undo", Json::object());
  EXPECT_TRUE(s.get("/api/driven-keys")["drivenPoses"]["drivers"].empty());
  for (auto [body, status, field] :
       {std::tuple{R"({"op":"set","driver":"nobody.rotateX","driven":{"hero_arm_L_fk1.rotateZ":1}})", 400, "driver"},
        std::tuple{R"({"op":"set","driver":"hero_arm_L_fk0.rotateX","driven":{"forearm.L.translateX":1}})", 400, "driven"},
        std::tuple{R"({"op":"set","driver":"hero_arm_L_fk0.rotateX","driven":[1]})", 400, "driven"},
        std::tuple{R"({"op":"set","driver":"hero_arm_L_fk0.rotateX","driven":{"hero_arm_L_fk1.rotateZ":"x"}})", 400, "driven.hero_arm_L_fk1.rotateZ"},
        std::tuple{R"({"op":"set","driver":"hero_arm_L_fk0.rotateX","tangent":"wobbly","driven":{"hero_arm_L_fk1.rotateZ":1}})", 400, "tangent"},
        std::tuple{R"({"op":"dance"})", 400, "op"},
        std::tuple{R"({"op":"remove","driven":["hero_arm_L_fk1.rotateZ"]})", 400, "driven"}}) {
    Response resp = s.request("POST", "/api/driven-keys", body);
    EXPECT_EQ(resp.status, status) << body << ": " << resp.body;
    EXPECT_EQ(Json::parse(resp.body)["field"], field) << body;
  }
  Response resp = s.request("POST", "/api/data/import", R"({"kind":"correctives","file":"data/hero.drivenposes.json"})");
  EXPECT_EQ(resp.status, 400) << resp.body;
  EXPECT_EQ(Json::parse(resp.body)["field"], "file");
}

TEST(ServerApi, BlendShapesExportedEditedAndImportedBack) {
  Served s;
  s.root = s.dir->path() / "root";
  fs::create_directories(s.root);
  io::GltfImportOptions options;
  options.registry = ephemeral::default_registry();
  auto scene = io::import_gltf(source_path("tests/data/gltf/SimpleMorph.gltf"), options);
  ASSERT_TRUE(scene.is_ok()) << scene.status().message();
  s.workspace = std::make_unique<Workspace>(std::move(*scene), fs::path(), s.root, ephemeral::components());
  graph::Graph& g = s.workspace->scene().graph();
  graph::NodeId mesh;
  for (graph::NodeId id : g.nodes())
    if (g.node(id)->type().name() == scene::kMeshType) mesh = id;
  auto points = [&] { return std::get<std::vector<math::Vec3>>(g.evaluate(mesh, scene::mesh_attr::kPoints)); };
  g.set_time(2.0);  // weights (1, 1)
  const auto before = points();

  Json r = s.post("/api/data/export", {{"kind", "blendshapes"}, {"file", "data/tri.blendshapes.json"}});
  EXPECT_EQ(r["file"], "data/tri.blendshapes.json");
  const fs::path file = s.root / "data" / "tri.blendshapes.json";
  std::string text = io::testing::read_text(file);
  const std::string line = "[2, 1.0, 1.0, 0.0]";
  ASSERT_NE(text.find(line), std::string::npos) << text;
  text.replace(text.find(line), line.size(), "[2, 1.0, 2.0, 0.0]");
  io::testing::write_text(file, text);
  r = s.post("/api/data/import", {{"kind", "blendshapes"}, {"file", "data/tri.blendshapes.json"}});
  EXPECT_EQ(r["blendShapes"], 1);
  EXPECT_EQ(r["targets"], 2);
  EXPECT_TRUE(r["driven"].empty()) << "the animated weights are the file's";
  EXPECT_NEAR(points()[2].y(), before[2].y() + 1, 1e-6) << "target 1 moves vertex 2 one more in y";
  s.post("/api/undo", Json::object());
  EXPECT_NEAR(points()[2].y(), before[2].y(), 1e-12);

  io::testing::write_text(s.root / "data" / "bad.blendshapes.json", "{\"rigelBlendShapes\": 1,\n \"blendShapes\": [}");
  std::string other = text;
  other.replace(other.find("_blendShape\""), 12, "_nose\"");
  other.replace(other.find("\"mesh\": \""), 9, "\"mesh\": \"no");
  io::testing::write_text(s.root / "data" / "other.blendshapes.json", other);
  for (auto [body, status, field] :
       {std::tuple{R"({"kind":"blendshapes","file":"data/bad.blendshapes.json"})", 400, "file"},
        std::tuple{R"({"kind":"blendshapes","file":"data/other.blendshapes.json"})", 400, "blendShape"},
        std::tuple{R"({"kind":"blendshapes","file":"data/tri.blendshapes.json","nearest":true})", 400, "nearest"},
        std::tuple{R"({"kind":"blendshapes","file":"../outside.json"})", 400, "file"}}) {
    Response resp = s.request("POST", "/api/data/import", body);
    EXPECT_EQ(resp.status, status) << body << ": " << resp.body;
    EXPECT_EQ(Json::parse(resp.body)["field"], field) << body;
  }
  EXPECT_NE(s.request("POST", "/api/data/import", R"({"kind":"blendshapes","file":"data/bad.blendshapes.json"})").body.find("bad.blendshapes.json:2:"),
            std::string::npos);
  Served biped = served_biped();
  Response none = biped.request("POST", "/api/data/export", R"({"kind":"blendshapes","file":"data/x.blendshapes.json"})");
  EXPECT_EQ(none.status, 409) << none.body;
  EXPECT_FALSE(fs::exists(biped.root / "data" / "x.blendshapes.json"));
}

}  // namespace
}  // namespace rigel::server
