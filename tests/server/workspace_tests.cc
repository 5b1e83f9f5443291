// The JSON API of `rigel serve`, driven in-process (no sockets): every route
// on the bundled character, and every kind of bad request.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "rigel/ephemeral/component.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/io/gltf_import.h"
#include "rigel/io/scene_file.h"
#include "rigel/rig/definition_io.h"
#include "rigel/rig/meta.h"
#include "server_test_util.h"
#include "workspace.h"

namespace rigel::server {
namespace {

namespace fs = std::filesystem;

TEST(ServerApi, SceneRevisionAndSelection) {
  Served s = served_puppet();
  Json scene = s.get("/api/scene");
  EXPECT_EQ(scene["mode"], "forward");
  EXPECT_EQ(scene["modes"].size(), 8u);
  EXPECT_EQ(scene["fps"], 24.0);
  EXPECT_FALSE(scene["canUndo"].get<bool>());
  const auto rev = s.get("/api/revision")["revision"].get<std::uint64_t>();
  Json sel = s.post("/api/select", {{"controls", {"hand.L"}}});  // a joint stands for its control
  ASSERT_EQ(sel["selection"].size(), 1u);
  EXPECT_EQ(sel["selection"][0], s.control("hand.L"));
  EXPECT_EQ(s.get("/api/revision")["revision"].get<std::uint64_t>(), rev + 1);
  s.post("/api/select", {{"controls", {s.control("hand.R")}}, {"add", true}});
  EXPECT_EQ(s.get("/api/scene")["selection"].size(), 2u);
}

TEST(ServerApi, NodesListControlsWithShapes) {
  Served s = served_puppet();
  Json nodes = s.get("/api/nodes");
  std::size_t joints = 0, ephemeral_controls = 0;
  for (const Json& n : nodes["nodes"]) joints += n["type"] == "joint";
  for (const Json& c : nodes["controls"]) {
    ephemeral_controls += c["ephemeral"].get<bool>();
    EXPECT_FALSE(c["shape"]["points"].empty()) << c["name"];
    EXPECT_EQ(c["shape"]["color"].size(), 3u);
  }
  EXPECT_EQ(joints, 159u);
  EXPECT_EQ(ephemeral_controls, 159u);
  EXPECT_EQ(nodes["controls"].size(), 160u);  // and the global control
}

TEST(ServerApi, InverseDragMovesTheArmOnlyAndUndoRestoresIt) {
  Served s = served_puppet();
  const Json before = s.get("/api/pose?space=world")["nodes"];
  s.post("/api/mode", {{"mode", "inverse"}});
  s.post("/api/options", {{"maxChain", 3}});
  s.post("/api/select", {{"controls", {"hand.L"}}});
  for (int i = 1; i <= 5; ++i) {
    // Each answer lists just what the drag moved: the arm's controls and
    // joints, not the other arm.
    const Json answer = s.post("/api/drag", {{"translate", {0.0, 0.02, 0.01}}});
    EXPECT_TRUE(answer["partial"].get<bool>());
    EXPECT_TRUE(answer["nodes"].contains(s.control("hand.L")));
    EXPECT_TRUE(answer["nodes"].contains(s.uuid("forearm.L")));
    EXPECT_FALSE(answer["nodes"].contains(s.uuid("hand.R")));
    EXPECT_LT(answer["nodes"].size(), 20u);
    EXPECT_EQ(answer["revision"], s.get("/api/revision")["revision"]);
  }
  s.post("/api/release", Json::object());
  const Json after = s.get("/api/pose?space=world")["nodes"];
  for (const char* moved : {"forearm.L", "hand.L"}) EXPECT_GT(s.distance(before, after, moved), 1e-3) << moved;
  // The chain's top keeps its place (it turns); the rest of the body does not move.
  EXPECT_LT(s.position_distance(before, after, "upper_arm.L"), 1e-9);
  for (const char* still : {"upper_arm.R", "hand.R", "spine.003", "thigh.L", "foot.R", "shoulder.L"})
    EXPECT_LT(s.distance(before, after, still), 1e-9) << still;
  // The gesture is one undo step.
  Json undo = s.post("/api/undo", Json::object());
  EXPECT_NE(undo["label"].get<std::string>().find("ephemeral drag"), std::string::npos) << undo;
  const Json undone = s.get("/api/pose?space=world")["nodes"];
  for (const auto& [uuid, v] : before.items()) EXPECT_EQ(undone[uuid], v) << uuid;
  s.post("/api/redo", Json::object());
  EXPECT_LT(s.distance(after, s.get("/api/pose?space=world")["nodes"], "hand.L"), 1e-12);
}

TEST(ServerApi, ADragThatCannotDoAllSaysWhyInNotes) {
  Served s = served_puppet();
  s.post("/api/mode", {{"mode", "inverse"}});
  s.post("/api/select", {{"controls", {"hand.L"}}});
  // A chain of reach 3 moves without a note.
  s.post("/api/options", {{"maxChain", 3}});
  EXPECT_FALSE(s.post("/api/drag", {{"translate", {0.0, 0.01, 0.0}}}).contains("notes"));
  s.post("/api/release", Json::object());
  // A chain of one control would stretch its bone: it keeps its place and says so.
  s.post("/api/options", {{"maxChain", 1}});
  const Json answer = s.post("/api/drag", {{"translate", {0.0, 0.1, 0.0}}});
  ASSERT_TRUE(answer.contains("notes")) << answer;
  ASSERT_FALSE(answer["notes"].empty());
  EXPECT_NE(answer["notes"][0].get<std::string>().find("hand.L"), std::string::npos) << answer["notes"];
}

TEST(ServerApi, DragToAWorldTargetAndMultiSelection) {
  Served s = served_puppet();
  const Json before = s.get("/api/pose?space=world")["nodes"];
  s.post("/api/select", {{"controls", {"hand.L", "hand.R"}}});
  const Json& h = before[s.control("hand.L")];
  // Forward: both grabbed controls get the same delta, nothing else moves.
  s.post("/api/drag", {{"control", "hand.L"},
                       {"to", {{"t", {h[0].get<double>(), h[1].get<double>() + 0.1, h[2].get<double>()}}}}});
  const Json after = s.get("/api/pose?space=world")["nodes"];
  EXPECT_NEAR(after[s.control("hand.L")][1].get<double>(), h[1].get<double>() + 0.1, 1e-9);
  EXPECT_NEAR(s.position_distance(before, after, "hand.R"), 0.1, 1e-9);
  EXPECT_LT(s.distance(before, after, "forearm.L"), 1e-9);
}

TEST(ServerApi, KeysOnTwoFramesAndTime) {
  Served s = served_puppet();
  s.post("/api/select", {{"controls", {"spine.003"}}});
  s.post("/api/time", {{"frame", 0}});
  s.post("/api/key", Json::object());
  s.post("/api/time", {{"frame", 10}});
  Json keys = s.post("/api/key", Json::object());
  // On a key, a drag changes the key.
  s.post("/api/drag", {{"rotate", {{"euler", {0, 30, 0}}}}});
  EXPECT_EQ(keys["frames"], Json::array({0.0, 10.0}));
  EXPECT_EQ(keys["scope"], "character");
  // Between the keys the pose is between the poses.
  const double y10 = s.get("/api/pose?space=world")["nodes"][s.uuid("spine.006")][0].get<double>();
  s.post("/api/time", {{"frame", 0}});
  const double y0 = s.get("/api/pose?space=world")["nodes"][s.uuid("spine.006")][0].get<double>();
  Json t = s.post("/api/time", {{"frame", 5}});
  EXPECT_EQ(t["frame"], 5.0);
  const double y5 = s.get("/api/pose?space=world")["nodes"][s.uuid("spine.006")][0].get<double>();
  EXPECT_GT(std::abs(y10 - y0), 1e-3);
  EXPECT_GT(y5, std::min(y0, y10));
  EXPECT_LT(y5, std::max(y0, y10));
  EXPECT_EQ(s.get("/api/keys?controls=spine.003")["frames"].size(), 2u);
  // A drag off a key with auto-key off is refused: 409 with the reason.
  s.post("/api/time", {{"frame", 3}});
  Response r = s.request("POST", "/api/drag", R"({"translate": [0, 0.1, 0]})");
  EXPECT_EQ(r.status, 409) << r.body;
  s.post("/api/options", {{"autoKey", true}});
  s.post("/api/drag", {{"translate", {0, 0.01, 0}}});
  EXPECT_EQ(s.get("/api/keys")["frames"].size(), 3u);
  // Nothing selected: no scope and no frames.
  s.post("/api/select", {{"controls", Json::array()}});
  const Json none = s.get("/api/keys");
  EXPECT_TRUE(none["scope"].is_null());
  EXPECT_TRUE(none["frames"].empty());
}

TEST(ServerApi, BadRequestsNameTheFieldAndTheServerGoesOn) {
  Served s = served_puppet();
  struct Case {
    const char* method;
    const char* path;
    std::string body;
    int status;
    const char* field;  // expected "field" of the answer ("" = none)
    const char* says;   // part of the message
  };
  const std::vector<Case> cases = {
      {"POST", "/api/select", "{\"controls\": [", 400, "body", "line 1"},
      {"POST", "/api/select", "[1, 2]", 400, "body", "JSON object"},
      {"POST", "/api/select", "{}", 400, "controls", "missing field"},
      {"POST", "/api/select", R"({"controls": "hand.L"})", 400, "controls", "array"},
      {"POST", "/api/select", R"({"controls": [3]})", 400, "controls[0]", "string"},
      {"POST", "/api/select", R"({"controls": ["hand.L", "nobody"]})", 404, "controls[1]", "no node 'nobody'"},
      {"POST", "/api/select", R"({"controls": ["puppet_meta"]})", 400, "controls[0]", "not a control"},
      {"POST", "/api/mode", R"({"mode": "sideways"})", 400, "mode", "unknown mode"},
      {"POST", "/api/drag", R"({"control": "hand.L", "to": {"t": [0, "up", 0]}})", 400, "to.t[1]", "number"},
      {"POST", "/api/drag", R"({"control": "hand.L", "to": {"q": [0, 0, 0, 0]}})", 400, "to.q", "zero length"},
      {"POST", "/api/drag", R"({"translate": [1, 2]})", 400, "translate", "3 numbers"},
      {"POST", "/api/time", R"({"frame": "ten"})", 400, "frame", "number"},
      {"POST", "/api/time", "{}", 400, "frame", "missing"},
      // A number no double holds is malformed JSON, not a server fault.
      {"POST", "/api/time", R"({"frame": 1e999999})", 400, "body", "overflow"},
      {"POST", "/api/select", R"({"controls": [-1e999999]})", 400, "body", "overflow"},
      {"POST", "/api/save", R"({"path": "."})", 400, "path", "folder"},
      {"POST", "/api/options", R"({"maxChain": 2.5})", 400, "maxChain", "whole number"},
      {"POST", "/api/undo", "{}", 409, "", "nothing to undo"},
      {"POST", "/api/rigs/remove", R"({"rig": "nobody"})", 404, "rig", "no rig 'nobody'"},
      {"POST", "/api/rigs/add", R"({"definition": "../../etc/passwd"})", 400, "definition", "outside"},
      {"POST", "/api/rigs/add", R"({"definition": "/etc/passwd"})", 400, "definition", "absolute"},
      {"POST", "/api/definition/save", R"({"definition": {}, "path": "../x.rig.xml"})", 400, "path", "outside"},
      {"GET", "/api/pose?space=up", "", 400, "space", "local or world"},
      {"GET", "/api/nothing", "", 404, "", "no such route"},
      {"DELETE", "/api/scene", "", 405, "", "not allowed"},
      {"POST", "/api/select", std::string(kMaxBody + 1, ' '), 413, "", "bytes"},
  };
  for (const Case& c : cases) {
    std::string path = c.path, query;
    if (auto q = path.find('?'); q != std::string::npos) {
      query = path.substr(q + 1);
      path = path.substr(0, q);
    }
    Request req{c.method, path, {}, c.body};
    if (!query.empty()) req.query[query.substr(0, query.find('='))] = query.substr(query.find('=') + 1);
    Response r = s.workspace->handle(req);
    SCOPED_TRACE(std::string(c.method) + " " + c.path + " " + c.body.substr(0, 60));
    EXPECT_EQ(r.status, c.status) << r.body;
    const Json body = Json::parse(r.body);
    ASSERT_TRUE(body.contains("error")) << r.body;
    EXPECT_NE(body["error"].get<std::string>().find(c.says), std::string::npos) << r.body;
    if (*c.field) {
      EXPECT_EQ(body.value("field", ""), c.field) << r.body;
    }
  }
  // Nothing above changed the scene, and it still answers.
  EXPECT_FALSE(s.get("/api/scene")["canUndo"].get<bool>());
  EXPECT_EQ(s.post("/api/select", {{"controls", {"hand.L"}}})["selection"].size(), 1u);
}

TEST(ServerApi, ConfinedPathsStayInTheRoot) {
  TempDir dir;
  fs::create_directories(dir.path() / "root/defs");
  fs::create_directories(dir.path() / "outside");
  fs::create_directory_symlink(dir.path() / "outside", dir.path() / "root/link");
  const fs::path root = dir.path() / "root";
  EXPECT_TRUE(confined_path(root, "defs/a.rig.xml", "p").is_ok());
  EXPECT_TRUE(confined_path(root, "defs/../b.rig.xml", "p").is_ok());
  EXPECT_TRUE(confined_path(root, "new/c.rig.xml", "p").is_ok());
  for (const char* bad : {"", "../x", "defs/../../x", "/etc/passwd", "link/x", "link/../../x"}) {
    auto r = confined_path(root, bad, "path");
    EXPECT_FALSE(r.is_ok()) << bad;
    if (!r.is_ok()) {
      EXPECT_EQ(r.status().message().rfind("path: ", 0), 0u) << r.status().message();
    }
  }
}

TEST(ServerApi, CharacterGlbCarriesUuids) {
  Served s = served_puppet();
  Response r = s.request("GET", "/api/character.glb", "");
  ASSERT_EQ(r.status, 200);
  EXPECT_EQ(r.content_type, "model/gltf-binary");
  ASSERT_GT(r.body.size(), 20u);
  EXPECT_EQ(r.body.substr(0, 4), "glTF");
  EXPECT_NE(r.body.find(s.control("hand.L")), std::string::npos);
  const fs::path file = s.root / "served.glb";
  io::testing::write_text(file, r.body);
  EXPECT_VALID_GLTF(file);
}

// The Rig Manager: add a rig from a definition, see it out of date when the
// file on disk gets a newer version, update it, step its build, remove it.
TEST(ServerApi, RigManagerAddUpdateStepRemove) {
  Served s = served_character();
  fs::create_directories(s.root / "defs");
  std::string def = read_text(fs::path(RIGEL_SOURCE_DIR) / "examples/biped.rig.xml");
  const std::string geo = "../tests/data/gltf/rigify_human_metarig.glb";
  def.replace(def.find(geo), geo.size(), (fs::path(RIGEL_SOURCE_DIR) / "tests/data/gltf/rigify_human_metarig.glb").string());
  write_text(s.root / "defs/hero.rig.xml", def);
  Json added = s.post("/api/rigs/add", {{"definition", "defs/hero.rig.xml"}});
  EXPECT_EQ(added["rig"], "hero");
  EXPECT_EQ(added["components"].size(), 21u);
  Json rigs = s.get("/api/rigs")["rigs"];
  ASSERT_EQ(rigs.size(), 1u);
  EXPECT_FALSE(rigs[0]["outOfDate"].get<bool>());
  EXPECT_EQ(rigs[0]["buildPosition"], rigs[0]["steps"]);
  EXPECT_EQ(s.request("POST", "/api/rigs/add", R"({"definition": "defs/hero.rig.xml"})").status, 409);

  // A newer hip on disk: the rig is out of date until updated.
  const std::string hip = R"(name="hip" side="C" version="1.0")";
  def.replace(def.find(hip), hip.size(), R"(name="hip" side="C" version="1.1")");
  const std::string rig = R"(<rig name="hero" version="1.0">)";
  def.replace(def.find(rig), rig.size(), R"(<rig name="hero" version="1.1">)");
  write_text(s.root / "defs/hero.rig.xml", def);
  rigs = s.get("/api/rigs")["rigs"];
  EXPECT_TRUE(rigs[0]["outOfDate"].get<bool>());
  EXPECT_EQ(rigs[0]["definitionVersion"], "1.1");
  Json updated = s.post("/api/rigs/update", {{"rig", "hero"}, {"keepKeys", "world"}});
  EXPECT_TRUE(updated["updated"].get<bool>());
  EXPECT_EQ(updated["to"], "1.1");
  EXPECT_FALSE(updated["rebuilt"].empty());
  EXPECT_FALSE(s.get("/api/rigs")["rigs"][0]["outOfDate"].get<bool>());

  // Stepping back and forth through the build.
  const int steps = s.get("/api/rigs")["rigs"][0]["steps"].get<int>();
  Json step = s.post("/api/rigs/step", {{"rig", "hero"}, {"by", -1}});
  EXPECT_EQ(step["position"], steps - 1);
  step = s.post("/api/rigs/step", {{"rig", "hero"}, {"to", 3}});
  EXPECT_EQ(step["position"], 3);
  EXPECT_EQ(s.request("POST", "/api/rigs/step", R"({"rig": "hero", "to": 100000})").status, 400);
  s.post("/api/rigs/step", {{"rig", "hero"}, {"to", steps}});

  // Features: the biped's limbs name "ik" and "stretch"; turning one off
  // redoes the build without its steps, turning it on again brings them back.
  Json features = s.get("/api/rigs")["rigs"][0]["features"];
  EXPECT_NE(features.dump().find("\"stretch\""), std::string::npos) << features;
  const std::string with_stretch = io::write_scene(s.workspace->scene());
  Json off = s.post("/api/rigs/feature", {{"rig", "hero"}, {"feature", "stretch"}, {"enabled", false}});
  EXPECT_EQ(off["position"], steps);
  for (const Json& f : off["features"]) {
    if (f["feature"] == "stretch") {
      EXPECT_FALSE(f["enabled"].get<bool>());
    }
  }
  EXPECT_NE(io::write_scene(s.workspace->scene()), with_stretch);  // the stretch steps' work is undone
  EXPECT_EQ(s.request("POST", "/api/rigs/feature", R"({"rig": "hero", "feature": "wings", "enabled": true})").status, 404);
  Json on = s.post("/api/rigs/feature", {{"rig", "hero"}, {"feature", "stretch"}, {"enabled", true}});
  for (const Json& f : on["features"]) EXPECT_TRUE(f["enabled"].get<bool>()) << f;

  // Rig edit mode on the built rig, and back; the editor can read the
  // definition it was built from.
  Json edit = s.post("/api/rigs/edit-mode", {{"rig", "hero"}, {"on", true}});
  EXPECT_TRUE(edit["editMode"].get<bool>());
  EXPECT_TRUE(s.get("/api/rigs")["rigs"][0]["editMode"].get<bool>());
  EXPECT_EQ(s.get("/api/rigs")["rigs"][0]["buildPosition"], steps);
  s.post("/api/rigs/edit-mode", {{"rig", "hero"}, {"on", false}});
  EXPECT_FALSE(s.get("/api/rigs")["rigs"][0]["editMode"].get<bool>());
  // Committing edit mode with moved guides saves the definition where asked,
  // leaves edit mode and leaves the rig up to date with the new file.
  s.post("/api/rigs/edit-mode", {{"rig", "hero"}, {"on", true}});
  s.post("/api/select", {{"controls", {"hero_chest_main0"}}});
  s.post("/api/drag", {{"translate", {0.0, 0.05, 0.0}}});
  Json committed = s.post("/api/rigs/edit", {{"rig", "hero"}, {"definitionOut", "defs/moved.rig.xml"}});
  ASSERT_FALSE(committed["changed"].empty()) << committed;
  EXPECT_TRUE(fs::exists(s.root / "defs/moved.rig.xml"));
  EXPECT_FALSE(committed["editMode"].get<bool>());
  rigs = s.get("/api/rigs")["rigs"];
  EXPECT_FALSE(rigs[0]["editMode"].get<bool>());
  EXPECT_FALSE(rigs[0]["outOfDate"].get<bool>()) << rigs[0];
  s.post("/api/rigs/edit-mode", {{"rig", "hero"}, {"on", true}});
  committed = s.post("/api/rigs/edit", {{"rig", "hero"}, {"keepEditing", true}});
  EXPECT_TRUE(committed["editMode"].get<bool>());
  s.post("/api/rigs/edit-mode", {{"rig", "hero"}, {"on", false}});

  Json def_back = s.get("/api/definition?rig=hero");
  EXPECT_EQ(def_back["definition"]["rig"]["name"], "hero");
  EXPECT_EQ(def_back["definition"]["rig"]["version"], "1.2");  // the edit bumped it
  EXPECT_EQ(fs::path(def_back["path"].get<std::string>()).filename(), "moved.rig.xml");
  EXPECT_EQ(s.request("GET", "/api/definition?rig=villain", "").status, 404);

  s.post("/api/rigs/remove", {{"rig", "hero"}});
  EXPECT_TRUE(s.get("/api/rigs")["rigs"].empty());
  // A removal is one undo step: one undo gives the whole rig back.
  s.post("/api/undo", Json::object());
  const Json back = s.get("/api/rigs")["rigs"];
  ASSERT_EQ(back.size(), 1u);
  EXPECT_EQ(back[0]["buildPosition"], steps);
}

// The definition editor: a two-component rig validated, built live,
// changed and rebuilt, saved (version bumped on a changed file).
TEST(ServerApi, DefinitionEditorBuildsAndSaves) {
  Served s = served_character();
  Json def = two_component_definition();
  Json v = s.post("/api/definition/validate", {{"definition", def}});
  EXPECT_TRUE(v["ok"].get<bool>()) << v;
  Json bad = def;
  bad["rig"]["components"][0]["type"] = "tentacle";
  v = s.post("/api/definition/validate", {{"definition", bad}});
  EXPECT_FALSE(v["ok"].get<bool>());
  EXPECT_NE(v["problems"].dump().find("tentacle"), std::string::npos) << v;
  EXPECT_EQ(s.request("POST", "/api/definition/build", Json{{"definition", bad}}.dump()).status, 400);

  Json built = s.post("/api/definition/build", {{"definition", def}});
  EXPECT_EQ(built["rebuilt"].size(), 2u);
  EXPECT_EQ(s.get("/api/rigs")["rigs"][0]["components"].size(), 2u);
  // Live: a change rebuilds only the changed component.
  def["rig"]["components"][0]["children"][0]["controls"][0]["size"] = 0.2;
  built = s.post("/api/definition/build", {{"definition", def}});
  EXPECT_EQ(built["rebuilt"].size(), 1u) << built;

  Json saved = s.post("/api/definition/save", {{"definition", def}, {"path", "defs/arm.rig.xml"}});
  EXPECT_EQ(saved["version"], "1.0");
  EXPECT_TRUE(rig::check_definition(s.root / "defs/arm.rig.xml").empty());
  // The same content again keeps the version; another content bumps it.
  saved = s.post("/api/definition/save", {{"definition", def}, {"path", "defs/arm.rig.xml"}});
  EXPECT_EQ(saved["version"], "1.0");
  def["rig"]["components"][0]["children"][0]["controls"][0]["size"] = 0.3;
  saved = s.post("/api/definition/save", {{"definition", def}, {"path", "defs/arm.rig.xml"}});
  EXPECT_EQ(saved["version"], "1.1");
  EXPECT_EQ(rig::load_definition(s.root / "defs/arm.rig.xml").definition.version, "1.1");
  EXPECT_EQ(s.request("POST", "/api/definition/save", Json{{"definition", def}, {"path", "defs/arm.txt"}}.dump()).status,
            400);
}

// A built rig's controls (not ephemeral) are dragged directly: their
// channels take the world target, what they drive follows, one undo step.
TEST(ServerApi, DraggingABuiltRigControlWritesItsChannels) {
  Served s = served_character();
  s.post("/api/definition/build", {{"definition", two_component_definition()}});
  std::string fk;
  const Json nodes = s.get("/api/nodes");
  for (const Json& c : nodes["controls"]) {
    if (c["name"] == "arm_arm_L_fk0") {
      EXPECT_EQ(c["rig"], "arm");
      EXPECT_FALSE(c["ephemeral"].get<bool>());
      fk = c["uuid"];
    }
  }
  ASSERT_FALSE(fk.empty());
  const Json before = s.get("/api/pose?space=world")["nodes"];
  const Json& w = before[fk];
  const double half = std::sqrt(0.5);
  // A quarter turn about Y of the first FK control, in place.
  Eigen::Quaterniond q0(w[6].get<double>(), w[3].get<double>(), w[4].get<double>(), w[5].get<double>());
  Eigen::Quaterniond q = Eigen::Quaterniond(half, 0, half, 0) * q0;
  for (int i = 0; i < 3; ++i)  // several drags of one gesture
    s.post("/api/drag", {{"control", fk}, {"to", {{"q", {q.x(), q.y(), q.z(), q.w()}}}}});
  s.post("/api/release", Json::object());
  const Json after = s.get("/api/pose?space=world")["nodes"];
  EXPECT_NEAR(std::abs(after[fk][3].get<double>() * q.x() + after[fk][4].get<double>() * q.y() +
                       after[fk][5].get<double>() * q.z() + after[fk][6].get<double>() * q.w()),
              1.0, 1e-9);
  EXPECT_GT(s.position_distance(before, after, "hand.L"), 0.05);
  EXPECT_LT(s.distance(before, after, "hand.R"), 1e-12);
  s.post("/api/undo", Json::object());
  EXPECT_LT(s.position_distance(before, s.get("/api/pose?space=world")["nodes"], "hand.L"), 1e-12);
}

// Keys on a built rig's channels: a control's key keys its character (a
// pose), `attrs` keys only those channels; bad names and values are 400s,
// a delete with no key there a 404.
TEST(ServerApi, ChannelKeysOnABuiltRig) {
  Served s = served_character();
  s.post("/api/definition/build", {{"definition", two_component_definition()}});
  s.post("/api/time", {{"frame", 0}});
  Json k = s.post("/api/channel-keys", {{"controls", {"arm_arm_L_fk0"}}});
  ASSERT_TRUE(k["keys"].is_array());
  // The global control and the FK controls, each translate, rotate, scale.
  EXPECT_GE(k["keys"].size(), 18u);
  EXPECT_EQ(k["keys"].size() % 9, 0u) << k;
  bool global = false;
  for (const Json& p : k["keys"]) {
    EXPECT_EQ(p["frames"], Json::array({0.0})) << p;
    global = global || p["plug"] == "arm_global_main.translateX";
  }
  EXPECT_TRUE(global) << k;
  s.post("/api/time", {{"frame", 12}});
  Json r = s.post("/api/channel-keys", {{"controls", {"arm_arm_L_fk0"}}, {"attrs", {"rotate"}}});
  ASSERT_EQ(r["keys"].size(), 3u) << r;
  EXPECT_EQ(r["keys"][2]["plug"], "arm_arm_L_fk0.rotateZ");
  EXPECT_EQ(r["keys"][2]["frames"], Json::array({0.0, 12.0}));
  EXPECT_GT(r["revision"].get<std::uint64_t>(), k["revision"].get<std::uint64_t>());

  Response bad = s.request("POST", "/api/channel-keys", Json{{"controls", {"arm_arm_L_fk0"}}, {"attrs", {"fkIk"}}}.dump());
  EXPECT_EQ(bad.status, 400) << bad.body;
  EXPECT_EQ(Json::parse(bad.body)["field"], "attrs") << bad.body;
  Response value = s.request("POST", "/api/channel-keys",
                             Json{{"controls", {"arm_arm_L_fk0"}}, {"attrs", {"rotate"}}, {"value", 2}}.dump());
  EXPECT_EQ(value.status, 400) << value.body;
  EXPECT_EQ(Json::parse(value.body)["field"], "value") << value.body;
  Json stepped = s.post("/api/channel-keys", {{"controls", {"arm_arm_L_fk0"}}, {"attrs", {"rotate"}}, {"tangent", "step"}});
  EXPECT_EQ(stepped["keys"][2]["outTangents"], Json::array({"auto", "step"})) << stepped;
  Response curly = s.request("POST", "/api/channel-keys", Json{{"controls", {"arm_arm_L_fk0"}}, {"tangent", "curly"}}.dump());
  EXPECT_EQ(curly.status, 400) << curly.body;
  EXPECT_EQ(Json::parse(curly.body)["field"], "tangent") << curly.body;
  s.post("/api/time", {{"frame", 6}});
  Response none = s.request("POST", "/api/channel-keys",
                            Json{{"controls", {"arm_arm_L_fk0"}}, {"attrs", {"rotate"}}, {"delete", true}}.dump());
  EXPECT_EQ(none.status, 404) << none.body;
  s.post("/api/time", {{"frame", 12}});
  Json d = s.post("/api/channel-keys", {{"controls", {"arm_arm_L_fk0"}}, {"attrs", {"rotate"}}, {"delete", true}});
  EXPECT_EQ(d["keys"][2]["frames"], Json::array({0.0}));
}

// FK/IK match and bake of the biped's left leg through the API: the leg in
// IK with a rolling foot, keyed to FK over frames 0..10.
TEST(ServerApi, MatchBakesTheBipedsLegToFk) {
  Served s = served_character();
  fs::create_directories(s.root / "defs");
  std::string def = read_text(fs::path(RIGEL_SOURCE_DIR) / "examples/biped.rig.xml");
  const std::string geo = "../tests/data/gltf/rigify_human_metarig.glb";
  def.replace(def.find(geo), geo.size(), (fs::path(RIGEL_SOURCE_DIR) / "tests/data/gltf/rigify_human_metarig.glb").string());
  write_text(s.root / "defs/hero.rig.xml", def);
  s.post("/api/rigs/add", {{"definition", "defs/hero.rig.xml"}});
  s.post("/api/time", {{"frame", 0}});
  s.post("/api/channel-keys", {{"controls", {"hero:leg_L/fkIkSwitch"}}, {"attrs", {"fkIk"}}, {"value", 1}});
  s.post("/api/channel-keys", {{"controls", {"hero:foot_L/reverseFoot"}}, {"attrs", {"roll"}}, {"value", 0}});
  s.post("/api/time", {{"frame", 10}});
  s.post("/api/channel-keys", {{"controls", {"hero:foot_L/reverseFoot"}}, {"attrs", {"roll"}}, {"value", 30}});
  Json m = s.post("/api/match", {{"rig", "hero"}, {"component", "leg_L"}, {"to", "fk"}, {"frames", {0, 10}}});
  EXPECT_EQ(m["frames"], 11);
  EXPECT_LT(m["maxError"].get<double>(), 1e-6) << m;
  EXPECT_GE(m["controls"].size(), 4u) << "fk0..fk2 and the FK toe: " << m;
  EXPECT_EQ(s.get("/api/revision")["revision"], m["revision"]);
  Json sw = s.get("/api/channel-keys?controls=hero:leg_L/fkIkSwitch&attrs=fkIk");
  ASSERT_EQ(sw["keys"].size(), 1u) << sw;
  EXPECT_EQ(sw["keys"][0]["frames"], Json::array({0.0, 10.0})) << sw;
  EXPECT_EQ(sw["keys"][0]["values"], Json::array({0.0, 0.0})) << sw;
  EXPECT_EQ(sw["revision"], m["revision"]) << "listing changes nothing";
  EXPECT_EQ(s.request("GET", "/api/channel-keys", "").status, 400);
  EXPECT_EQ(s.request("GET", "/api/channel-keys?controls=nobody", "").status, 404);
  // One undo step takes it back.
  EXPECT_EQ(s.post("/api/undo", Json::object())["label"], "match FK to IK");
  sw = s.get("/api/channel-keys?controls=hero:leg_L/fkIkSwitch&attrs=fkIk");
  EXPECT_EQ(sw["keys"][0]["frames"], Json::array({0.0})) << sw;

  struct Bad {
    Json body;
    int status;
    const char* field;
  };
  for (const Bad& b : {Bad{{{"rig", "hero"}, {"component", "spine"}, {"to", "fk"}}, 400, "component"},
                       Bad{{{"rig", "hero"}, {"component", "leg_X"}, {"to", "fk"}}, 404, "component"},
                       Bad{{{"rig", "nobody"}, {"component", "leg_L"}, {"to", "fk"}}, 404, "rig"},
                       Bad{{{"rig", "hero"}, {"component", "leg_L"}, {"to", "up"}}, 400, "to"},
                       Bad{{{"rig", "hero"}, {"component", "leg_L"}, {"to", "fk"}, {"frames", {10, 0}}}, 400, "frames"},
                       Bad{{{"rig", "hero"}, {"component", "leg_L"}, {"to", "fk"}, {"frames", {0, 500}}}, 400, "frames"},
                       Bad{{{"rig", "hero"}, {"component", "leg_L"}, {"to", "fk"}, {"frames", {-1e9, 0}}}, 400, "frames"},
                       Bad{{{"rig", "hero"}, {"component", "leg_L"}, {"to", "fk"}, {"frames", {0}}}, 400, "frames"}}) {
    Response r = s.request("POST", "/api/match", b.body.dump());
    EXPECT_EQ(r.status, b.status) << b.body << ": " << r.body;
    EXPECT_EQ(Json::parse(r.body)["field"], b.field) << r.body;
  }
}

// POST /api/transfer, /api/channel-values and /api/channel-keys's moveTo on
// the biped: the left arm's switch keys onto the right arm with an offset,
// a switch set through its limb's control, keys moved.
TEST(ServerApi, TransferMoveKeysAndChannelValuesOnTheBiped) {
  Served s = served_character();
  fs::create_directories(s.root / "defs");
  std::string def = read_text(fs::path(RIGEL_SOURCE_DIR) / "examples/biped.rig.xml");
  const std::string geo = "../tests/data/gltf/rigify_human_metarig.glb";
  def.replace(def.find(geo), geo.size(), (fs::path(RIGEL_SOURCE_DIR) / "tests/data/gltf/rigify_human_metarig.glb").string());
  write_text(s.root / "defs/hero.rig.xml", def);
  s.post("/api/rigs/add", {{"definition", "defs/hero.rig.xml"}});
  s.post("/api/time", {{"frame", 0}});
  Json set = s.post("/api/channel-values", {{"controls", {"hero_arm_L_ik"}}, {"attrs", {"fkIk"}}, {"value", 0}});
  ASSERT_EQ(set["channels"].size(), 1u) << set;
  EXPECT_EQ(set["channels"][0]["value"], 0.0);
  EXPECT_TRUE(set["keys"].empty()) << "free, auto-key off: set only";
  s.post("/api/channel-keys", {{"controls", {"hero:arm_L/fkIkSwitch"}}, {"attrs", {"fkIk"}}});
  s.post("/api/time", {{"frame", 12}});
  set = s.post("/api/channel-values", {{"controls", {"hero:arm_L/fkIkSwitch"}}, {"attrs", {"fkIk"}}, {"value", {1}}});
  EXPECT_EQ(set["keys"][0]["frames"], Json::array({0.0, 12.0})) << "keyed: the value is a key";

  Json t = s.post("/api/transfer", {{"from", "hero:arm_L"}, {"to", "hero:arm_R"}, {"offset", 6}});
  EXPECT_EQ(t["keys"], 2) << t;
  EXPECT_EQ(t["frames"], Json::array({0.0, 12.0})) << t;
  Json right = s.get("/api/channel-keys?controls=hero:arm_R/fkIkSwitch&attrs=fkIk");
  EXPECT_EQ(right["keys"][0]["frames"], Json::array({6.0, 18.0})) << right;
  EXPECT_EQ(right["keys"][0]["values"], Json::array({0.0, 1.0})) << right;

  Json moved = s.post("/api/channel-keys", {{"controls", {"hero:arm_L/fkIkSwitch"}}, {"attrs", {"fkIk"}}, {"moveTo", 20}});
  EXPECT_EQ(moved["keys"][0]["frames"], Json::array({0.0, 20.0})) << moved;

  struct Bad {
    const char* route;
    Json body;
    int status;
    const char* field;
  };
  for (const Bad& b : {Bad{"/api/transfer", {{"from", "hero:arm_L"}, {"to", "hero:hand_L"}}, 400, "to"},
                       Bad{"/api/transfer", {{"from", "nobody:arm_L"}, {"to", "hero:arm_R"}}, 404, "from"},
                       Bad{"/api/transfer", {{"from", "hero:arm_L"}, {"to", "hero:arm_R"}, {"frames", {5, 1}}}, 400, "frames"},
                       Bad{"/api/transfer", {{"from", "hero:arm_L"}}, 400, "to"},
                       Bad{"/api/channel-values", {{"controls", {"hero_arm_L_ik"}}, {"attrs", {"fkIk"}}}, 400, "value"},
                       Bad{"/api/channel-values", {{"controls", {"hero_arm_L_fk0"}}, {"attrs", {"rotate"}}, {"value", 1}}, 400, "attrs"},
                       Bad{"/api/channel-keys", {{"controls", {"hero:arm_L/fkIkSwitch"}}, {"moveTo", 3}, {"value", 1}}, 400, "moveTo"},
                       Bad{"/api/channel-keys", {{"controls", {"hero:arm_L/fkIkSwitch"}}, {"attrs", {"fkIk"}}, {"moveTo", 3}}, 404, "controls"}}) {
    Response r = s.request("POST", b.route, b.body.dump());
    EXPECT_EQ(r.status, b.status) << b.route << " " << b.body << ": " << r.body;
    EXPECT_EQ(Json::parse(r.body)["field"], b.field) << r.body;
  }
}

// POST /api/mirror: the selection (or the named controls) onto the other
// side, and a flip of everything; refusals name the field.
TEST(ServerApi, MirrorAndFlipTheBuiltRig) {
  Served s = served_character();
  s.post("/api/definition/build", {{"definition", two_component_definition()}});
  Response none = s.request("POST", "/api/mirror", Json{{"controls", {"arm_arm_L_fk0"}}}.dump());
  EXPECT_EQ(none.status, 400) << none.body;
  EXPECT_EQ(Json::parse(none.body)["field"], "controls");
  EXPECT_NE(none.body.find("has no pair"), std::string::npos) << none.body;
  EXPECT_EQ(s.request("POST", "/api/mirror", Json{{"all", true}, {"from", "Q"}}.dump()).status, 400);
  EXPECT_EQ(s.request("POST", "/api/mirror", Json{{"all", true}, {"plane", "zz"}}.dump()).status, 400);
  EXPECT_EQ(s.request("POST", "/api/mirror", Json{{"controls", {"nobody"}}}.dump()).status, 404);
  // The global control alone: a centre control mirrors only with flip.
  Json flipped = s.post("/api/mirror", {{"controls", {"arm_global_main"}}, {"flip", true}});
  EXPECT_EQ(flipped["set"], Json::array({"arm_global_main"})) << flipped;
  EXPECT_EQ(flipped["frames"], 1);
  // Bind pose of the whole rig by its root address.
  Json bind = s.post("/api/bind-pose", {{"controls", {"arm:"}}});
  EXPECT_GE(bind["set"].size(), 4u) << bind;
  EXPECT_EQ(bind["revision"], s.get("/api/revision")["revision"]);
  Response bad = s.request("POST", "/api/bind-pose", Json{{"controls", {"hand.L"}}}.dump());
  EXPECT_EQ(bad.status, 400) << bad.body;
  EXPECT_EQ(Json::parse(bad.body)["field"], "controls");
}

// GET /api/spaces and POST /api/space: a space added to an FK control, a
// switch at a frame that keeps it in place, a bake, and refusals naming the
// field.
TEST(ServerApi, SpacesAddSwitchAndBake) {
  Served s = served_character();
  s.post("/api/definition/build", {{"definition", two_component_definition()}});
  Json none = s.get("/api/spaces?control=arm_arm_L_fk1");
  EXPECT_TRUE(none["spaces"].empty()) << none;
  EXPECT_EQ(none["current"], nullptr);
  Json added = s.post("/api/space", {{"control", "arm_arm_L_fk1"}, {"add", "world"}, {"target", nullptr}});
  EXPECT_EQ(added["index"], 1) << added;
  EXPECT_EQ(added["spaces"][0]["name"], "parent");
  Json global = s.post("/api/space", {{"control", "arm_arm_L_fk1"}, {"add", "global"}, {"target", "arm_global_main"}});
  EXPECT_EQ(global["spaces"][2]["target"], "arm_global_main") << global;
  Json listed = s.get("/api/spaces?control=arm:arm_L/fk[1]");
  EXPECT_EQ(listed["spaces"].size(), 3u) << listed;
  Json switched = s.post("/api/space", {{"control", "arm_arm_L_fk1"}, {"switch", "world"}, {"frame", 0}});
  EXPECT_EQ(switched["from"], "parent") << switched;
  EXPECT_LT(switched["maxError"].get<double>(), 1e-9) << switched;
  EXPECT_EQ(s.get("/api/spaces?control=arm_arm_L_fk1")["current"], "world");
  s.post("/api/time", {{"frame", 3}});
  s.post("/api/channel-keys", {{"controls", {"arm_arm_L_fk1"}}, {"attrs", {"rotate"}}});
  Json baked = s.post("/api/space", {{"control", "arm_arm_L_fk1"}, {"switch", "global"}, {"frames", {0, 3}}});
  EXPECT_EQ(baked["frames"], 4) << baked;
  const auto refused = [&](const Json& body, int status, const char* field) {
    Response r = s.request("POST", "/api/space", body.dump());
    EXPECT_EQ(r.status, status) << body << ": " << r.body;
    if (r.status < 500 && Json::accept(r.body)) {
      EXPECT_EQ(Json::parse(r.body)["field"], field) << r.body;
    }
  };
  refused({{"control", "arm_arm_L_fk1"}, {"switch", "moon"}}, 400, "space");
  refused({{"control", "arm_arm_L_fk0"}, {"switch", "world"}}, 400, "control");
  refused({{"control", "arm_arm_L_fk1"}, {"add", "world"}}, 400, "space");
  refused({{"control", "arm_arm_L_fk1"}, {"add", "x"}, {"switch", "world"}}, 400, "add");
  refused({{"control", "arm_arm_L_fk1"}, {"add", "child"}, {"target", "arm_arm_L_fk2"}}, 400, "target");
  refused({{"control", "arm_arm_L_fk1"}, {"switch", "world"}, {"frame", 1}, {"frames", {0, 2}}}, 400, "frames");
  refused({{"control", "nobody"}, {"switch", "world"}}, 404, "control");
  EXPECT_EQ(s.request("GET", "/api/spaces", "").status, 400);
}

// POST /api/export: a glTF inside the root, the deform skeleton only when
// asked; paths outside the root and other extensions refused.
TEST(ServerApi, ExportWritesGltfInsideTheRoot) {
  Served s = served_character();
  s.post("/api/definition/build", {{"definition", two_component_definition()}});
  Json all = s.post("/api/export", {{"path", "out/all.glb"}});
  EXPECT_TRUE(fs::exists(s.root / "out/all.glb")) << all;
  Json game = s.post("/api/export", {{"path", "out/game.glb"}, {"deformOnly", true}, {"frames", {0, 3}}});
  EXPECT_TRUE(game["baked"].get<bool>()) << game;
  EXPECT_LT(game["nodes"].get<int>(), all["nodes"].get<int>()) << game;
  EXPECT_VALID_GLTF(s.root / "out/game.glb");
  for (const Json& bad : {Json{{"path", "../escape.glb"}}, Json{{"path", "out/x.obj"}}, Json{{"path", "/tmp/abs.glb"}},
                          Json{{"path", "out/y.glb"}, {"frames", {3, 1}}}, Json{{"path", "out/z.glb"}, {"deformOnly", 2}}}) {
    Response r = s.request("POST", "/api/export", bad.dump());
    EXPECT_EQ(r.status, 400) << bad << ": " << r.body;
  }
  EXPECT_FALSE(fs::exists(s.root / "out/x.obj"));
  EXPECT_FALSE(fs::exists(s.root / "out/y.glb"));
}

TEST(ServerApi, SaveIsAtomicAndConfined) {
  Served s = served_puppet();
  s.post("/api/select", {{"controls", {"hand.L"}}});
  s.post("/api/drag", {{"translate", {0, 0.1, 0}}});
  Json saved = s.post("/api/save", {{"path", "shots/a.rigel"}});
  EXPECT_TRUE(fs::exists(s.root / "shots/a.rigel") || fs::exists(fs::path(saved["path"].get<std::string>())));
  EXPECT_EQ(s.request("POST", "/api/save", R"({"path": "../a.rigel"})").status, 400);
  for (const auto& e : fs::directory_iterator(s.root / "shots"))
    EXPECT_EQ(e.path().extension(), ".rigel") << "left a temporary file: " << e.path();
}

// Step 0 is the rig with no step built: still listed, steppable forward,
// and the history takes it back and forth (as Build::go_to(0) in Python).
TEST(ServerApi, SteppingToZeroKeepsTheRigListedAndSteppable) {
  Served s = served_puppet();
  const Json rigs = s.get("/api/rigs")["rigs"];
  ASSERT_EQ(rigs.size(), 1u);
  const int steps = rigs[0]["steps"].get<int>();
  const Json features = rigs[0]["features"];
  ASSERT_GT(steps, 2);
  const auto listed = [&]() -> Json {
    const Json list = s.get("/api/rigs")["rigs"];
    EXPECT_EQ(list.size(), 1u) << list;
    return list.empty() ? Json() : list[0];
  };

  for (const Json& request : {Json{{"rig", "puppet"}, {"to", 0}}, Json{{"rig", "puppet"}, {"by", -steps - 5}}}) {
    SCOPED_TRACE(request.dump());
    if (listed()["buildPosition"] != 0) {
      Json step = s.post("/api/rigs/step", request);
      EXPECT_EQ(step["position"], 0);
      EXPECT_EQ(step["steps"], steps);
      EXPECT_EQ(step["step"], "");
    }
    // Nothing of the rig is in the scene; the list still has it, at 0.
    EXPECT_FALSE(rig::find_rig(s.workspace->scene().graph(), "puppet").is_valid());
    Json r = listed();
    EXPECT_EQ(r["name"], "puppet");
    EXPECT_EQ(r["buildPosition"], 0);
    EXPECT_EQ(r["steps"], steps);
    EXPECT_EQ(r["features"], features);
    EXPECT_TRUE(r["components"].empty());
    EXPECT_EQ(s.get("/api/definition?rig=puppet")["definition"]["rig"]["name"], "puppet");
    // Other rig operations need something built.
    EXPECT_EQ(s.request("POST", "/api/rigs/update", R"({"rig": "puppet"})").status, 409);
    // Forward again: one step, then the rest.
    EXPECT_EQ(s.post("/api/rigs/step", {{"rig", "puppet"}, {"by", 1}})["position"], 1);
    EXPECT_TRUE(rig::find_rig(s.workspace->scene().graph(), "puppet").is_valid());
    EXPECT_EQ(listed()["buildPosition"], 1);
    EXPECT_EQ(s.post("/api/rigs/step", {{"rig", "puppet"}, {"to", steps}})["position"], steps);
    r = listed();
    EXPECT_EQ(r["buildPosition"], steps);
    EXPECT_FALSE(r["components"].empty());
    // Back to 0 for the next request form.
    EXPECT_EQ(s.post("/api/rigs/step", request)["position"], 0);
  }

  // Undo and redo carry the rig through step 0: forward to 3, undo (at 0,
  // listed), undo (built again, listed once), redo, redo.
  EXPECT_EQ(s.post("/api/rigs/step", {{"rig", "puppet"}, {"to", 3}})["position"], 3);
  s.post("/api/undo", Json::object());
  EXPECT_EQ(listed()["buildPosition"], 0);
  s.post("/api/undo", Json::object());
  EXPECT_EQ(listed()["buildPosition"], steps);
  s.post("/api/redo", Json::object());
  EXPECT_EQ(listed()["buildPosition"], 0);
  s.post("/api/redo", Json::object());
  EXPECT_EQ(listed()["buildPosition"], 3);

  // Removing it at step 0 takes it off the list.
  s.post("/api/rigs/step", {{"rig", "puppet"}, {"to", 0}});
  s.post("/api/rigs/remove", {{"rig", "puppet"}});
  EXPECT_TRUE(s.get("/api/rigs")["rigs"].empty());
  EXPECT_EQ(s.request("POST", "/api/rigs/step", R"({"rig": "puppet", "by": 1})").status, 404);
}

// A rig stepped to 0, that step undone and then the rig's adding undone: a
// new edit from there forgets the step to 0, however far the history grows.
TEST(ServerApi, ANewEditAfterUndoingAStepToZeroForgetsIt) {
  Served s = served_character();
  fs::copy_file(source_path("examples/puppet.rig.xml"), s.root / "puppet.rig.xml");
  s.post("/api/rigs/add", {{"definition", "puppet.rig.xml"}});
  s.post("/api/rigs/step", {{"rig", "puppet"}, {"to", 0}});
  s.post("/api/undo", Json::object());  // the step to 0
  s.post("/api/undo", Json::object());  // the add
  EXPECT_TRUE(s.get("/api/rigs")["rigs"].empty());
  // Two new undo steps: another rig built, stepped back one.
  s.post("/api/definition/build", {{"definition", two_component_definition()}});
  s.post("/api/rigs/step", {{"rig", "arm"}, {"by", -1}});
  const Json rigs = s.get("/api/rigs")["rigs"];
  ASSERT_EQ(rigs.size(), 1u) << rigs;
  EXPECT_EQ(rigs[0]["name"], "arm");
}

TEST(ServerApi, TimeIsRefusedOutsideTheFrameRange) {
  Served s = served_puppet();
  s.post("/api/time", {{"frame", 7}});
  const double fps = s.get("/api/scene")["fps"].get<double>();
  for (const Json& bad : {Json{{"frame", -1e9}}, Json{{"frame", 1e308}}, Json{{"frame", -1e308}},
                          Json{{"frame", kMaxFrame + 0.5}}, Json{{"frame", -kMaxFrame - 1}},
                          Json{{"time", 1e308}}, Json{{"time", -1e9 / fps}}, Json{{"time", (kMaxFrame + 1) / fps}}}) {
    Response r = s.request("POST", "/api/time", bad.dump());
    EXPECT_EQ(r.status, 400) << bad << " " << r.body;
    EXPECT_NE(r.body.find("out of range"), std::string::npos) << r.body;
    EXPECT_EQ(Json::parse(r.body)["field"], bad.begin().key()) << r.body;
  }
  EXPECT_EQ(s.get("/api/scene")["frame"], 7);
  // The edges are in range.
  EXPECT_EQ(s.post("/api/time", {{"frame", kMaxFrame}})["frame"], kMaxFrame);
  EXPECT_EQ(s.post("/api/time", {{"frame", -kMaxFrame}})["frame"], -kMaxFrame);
  EXPECT_NEAR(s.post("/api/time", {{"time", kMaxFrame / fps}})["frame"].get<double>(), kMaxFrame, 1e-6);
}

// Bad input is a 4xx, never a 5xx: every route, with malformed bodies and
// each of its fields given values of every kind, alone and beside a real
// rig and control; the server still answers afterwards.
TEST(ServerApi, NoRequestIsAnsweredWithA5xx) {
  Served s = served_puppet();
  fs::create_directories(s.root / "folder.rig.json");
  fs::create_directories(s.root / "folder.rigel");
  // Each POST route and the fields it reads (rigs/remove last: it takes the
  // rig away from the routes after it).
  const std::vector<std::pair<std::string, std::vector<std::string>>> routes = {
      {"/api/save", {"path"}},
      {"/api/select", {"controls", "add"}},
      {"/api/mode", {"mode"}},
      {"/api/options", {"autoKey", "magnetFraction", "magnetRadius", "maxChain"}},
      {"/api/drag", {"control", "to", "translate", "rotate", "scale"}},
      {"/api/release", {}},
      {"/api/time", {"frame", "time"}},
      {"/api/key", {"controls", "delete"}},
      {"/api/channel-keys", {"controls", "attrs", "value", "delete", "tangent", "inTangent", "outTangent"}},
      {"/api/match", {"rig", "component", "to", "frames", "key"}},
      {"/api/space", {"control", "add", "target", "switch", "frame", "frames"}},
      {"/api/export", {"path", "frames", "bake", "deformOnly"}},
      {"/api/mirror", {"controls", "all", "flip", "from", "plane", "frames", "key"}},
      {"/api/bind-pose", {"controls", "key"}},
      {"/api/tween", {"controls", "attrs", "fraction", "key"}},
      {"/api/poses/save", {"library", "name", "rig", "controls"}},
      {"/api/poses/apply", {"library", "name", "rig", "controls", "mirror", "plane", "fraction", "key"}},
      {"/api/poses/remove", {"library", "name"}},
      {"/api/undo", {}},
      {"/api/redo", {}},
      {"/api/rigs/add", {"definition", "editMode"}},
      {"/api/rigs/update", {"rig", "keepKeys", "force"}},
      {"/api/rigs/edit", {"rig", "definitionOut", "keepEditing"}},
      {"/api/rigs/edit-mode", {"rig", "on"}},
      {"/api/rigs/feature", {"rig", "feature", "enabled", "switch"}},
      {"/api/rigs/step", {"rig", "to", "by"}},
      {"/api/definition/validate", {"definition"}},
      {"/api/definition/build", {"definition"}},
      {"/api/definition/save", {"definition", "path"}},
      {"/api/rigs/remove", {"rig"}},
  };
  const std::vector<Json> values = {
      nullptr, true, false, 0, -1, 3, 0.5, -0.0, 1e308, -1e308, 2147483648.0, -2147483649.0,
      "", "x", ".", "..", "/etc/passwd", "../../x.rigel", "folder.rig.json", "folder.rigel", "hand.L", "puppet",
      std::string(5000, 'a'), Json::array(), Json::array({1}), Json::array({"hand.L"}),
      Json::array({1e308, -1e308, 1e308}), Json::array({0, 0, 0, 0}), Json::array({1e308, 0, 0, 1}),
      Json::object(), Json{{"t", {1e308, 0, 0}}}, Json{{"q", {0, 0, 0, 0}}}, Json{{"euler", {1e308, 0, 0}}},
      Json{{"rig", 3}}, Json{{"rig", Json{{"name", "x"}, {"components", 1}}}},
  };
  const std::vector<std::string> raw = {
      "",       "not json", "[]",   "1e999999", R"({"frame": 1e999999})", R"({"a":)", "null", "\"text\"",
      "{\"controls\": [\"\\ud800\"]}", std::string("{\"rig\": \"\xff\xfe\"}"), "{\"unknown\": 1}",
  };
  int requests = 0;
  const auto expect_below_500 = [&](const std::string& method, const std::string& target, const std::string& body) {
    const Response r = s.request(method, target, body);
    ++requests;
    EXPECT_LT(r.status, 500) << method << " " << target << " " << body.substr(0, 200) << ": " << r.body;
    EXPECT_GE(r.status, 200);
    EXPECT_TRUE(Json::accept(r.body) || r.content_type != "application/json") << r.body;
  };
  const Json beside{{"rig", "puppet"}, {"controls", {"hand.L"}}, {"control", "hand.L"}};
  for (const auto& [route, fields] : routes) {
    SCOPED_TRACE(route);
    for (const std::string& body : raw) expect_below_500("POST", route, body);
    for (const std::string& field : fields) {
      for (const Json& v : values) {
        expect_below_500("POST", route, Json{{field, v}}.dump());
        Json both = beside;
        both[field] = v;
        expect_below_500("POST", route, both.dump());
      }
    }
  }
  for (const char* get : {"/api/pose?space=", "/api/keys?controls=", "/api/definition?rig=", "/api/poses?library="}) {
    for (const Json& v : values)
      if (v.is_string()) expect_below_500("GET", get + v.get<std::string>(), "");
  }
  for (const char* get : {"/api/scene", "/api/nodes", "/api/pose", "/api/keys", "/api/rigs", "/api/revision",
                          "/api/components", "/api/definition", "/api/character.glb"})
    expect_below_500("GET", get, "");
  EXPECT_GT(requests, 2000);
  EXPECT_EQ(s.get("/api/scene").value("fps", 0.0), 24.0);
}

}  // namespace
}  // namespace rigel::server
