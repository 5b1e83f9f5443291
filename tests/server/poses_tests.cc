// The JSON API's pose library (docs/SERVER.md), driven in-process on the
// biped of examples/biped.rig.xml built on the bundled metarig: save, list,
// apply and remove inside the served root, and every refusal naming its
// field. (The routes' fuzzing is workspace_tests.cc's, with the others.)

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "rigel/ephemeral/component.h"
#include "rigel/rig/manager.h"
#include "rigel/scene/transform_types.h"
#include "server_test_util.h"
#include "workspace.h"

namespace rigel::server {
namespace {

namespace fs = std::filesystem;

// The pose library: POST /api/poses/save, GET /api/poses, POST
// /api/poses/apply and /api/poses/remove, libraries inside the root;
// refusals name the field.
TEST(ServerApi, PoseLibrarySavesAppliesListsAndRemovesInsideTheRoot) {
  Served s = served_biped();
  ASSERT_TRUE(s.workspace);
  graph::Graph& g = s.workspace->scene().graph();
  const graph::NodeId fk0 = g.find("hero_arm_L_fk0");
  const graph::Plug rotate{fk0, scene::xform::kRotate, -1};
  ASSERT_TRUE(g.set_value(rotate, graph::Value(math::Vec3(10, 20, 30))).is_ok());
  Json saved = s.post("/api/poses/save", {{"library", "poses"}, {"name", "wave"}, {"rig", "hero"}});
  EXPECT_GT(saved["entries"].get<int>(), 50) << saved;
  ASSERT_TRUE(fs::exists(s.root / "poses" / "wave.pose.json"));
  Json list = s.get("/api/poses?library=poses");
  ASSERT_EQ(list["poses"].size(), 1u) << list;
  EXPECT_EQ(list["poses"][0]["name"], "wave");
  EXPECT_EQ(list["poses"][0]["rig"], "hero");
  EXPECT_EQ(list["poses"][0]["thumbnail"], true);
  const Response thumb = s.request("GET", "/api/poses/thumbnail?library=poses&name=wave", "");
  EXPECT_EQ(thumb.status, 200) << thumb.body;
  EXPECT_EQ(thumb.content_type, "image/svg+xml");
  EXPECT_EQ(thumb.body, io::testing::read_text(s.root / "poses" / "wave.pose.svg"));
  EXPECT_NE(thumb.body.find("<line "), std::string::npos);
  EXPECT_EQ(s.request("GET", "/api/poses/thumbnail?library=poses&name=nope", "").status, 404);
  EXPECT_EQ(s.request("GET", "/api/poses/thumbnail?library=poses", "").status, 400);
  EXPECT_EQ(s.request("GET", "/api/poses/thumbnail?library=../up&name=wave", "").status, 400);
  s.post("/api/bind-pose", {{"controls", {"hero:"}}});
  EXPECT_EQ(std::get<math::Vec3>(g.evaluate(fk0, scene::xform::kRotate)), math::Vec3::Zero());
  Json applied = s.post("/api/poses/apply", {{"library", "poses"}, {"name", "wave"}, {"controls", {"hero:arm_L/fk[0]"}}});
  EXPECT_EQ(applied["set"], Json::array({"hero_arm_L_fk0"})) << applied;
  EXPECT_LT((std::get<math::Vec3>(g.evaluate(fk0, scene::xform::kRotate)) - math::Vec3(10, 20, 30)).norm(), 1e-9);
  EXPECT_EQ(applied["revision"], s.get("/api/revision")["revision"]);
  // A pose of another rig: its rigIds are not this rig's.
  std::string text = io::testing::read_text(s.root / "poses" / "wave.pose.json");
  for (std::size_t at = text.find("\"rigId\": \""); at != std::string::npos; at = text.find("\"rigId\": \"", at + 1))
    text[at + 10] = text[at + 10] == 'f' ? '0' : 'f';
  write_text(s.root / "poses" / "other.pose.json", text);
  struct Bad {
    const char* route;
    Json body;
    int status;
    const char* field;
  };
  for (const Bad& b : {Bad{"/api/poses/apply", {{"library", "poses"}, {"name", "other"}}, 400, "rig"},
                       Bad{"/api/poses/apply", {{"library", "poses"}, {"name", "nope"}}, 404, "name"},
                       Bad{"/api/poses/apply", {{"library", "poses"}, {"name", "wave"}, {"controls", {"nobody"}}}, 404, "controls[0]"},
                       Bad{"/api/poses/apply", {{"library", "poses"}, {"name", "wave"}, {"fraction", 2}}, 400, "fraction"},
                       Bad{"/api/poses/apply", {{"library", "poses"}, {"name", "wave"}, {"rig", "nobody"}}, 404, "rig"},
                       Bad{"/api/poses/save", {{"library", "poses"}, {"name", "../x"}}, 400, "name"},
                       Bad{"/api/poses/save", {{"library", "/tmp"}, {"name", "x"}}, 400, "library"},
                       Bad{"/api/poses/save", {{"library", "../outside"}, {"name", "x"}}, 400, "library"},
                       Bad{"/api/poses/save", {{"library", "poses"}, {"name", "x"}, {"controls", {"hand.L"}}}, 400, "controls"},
                       Bad{"/api/poses/remove", {{"library", "poses"}, {"name", "nope"}}, 404, "name"}}) {
    const Response r = s.request("POST", b.route, b.body.dump());
    EXPECT_EQ(r.status, b.status) << b.route << " " << b.body << ": " << r.body;
    EXPECT_EQ(Json::parse(r.body)["field"], b.field) << r.body;
  }
  const Response wrong = s.request("POST", "/api/poses/apply", Json{{"library", "poses"}, {"name", "other"}}.dump());
  EXPECT_NE(wrong.body.find("rigId f"), std::string::npos) << "the missing rigId: " << wrong.body;
  EXPECT_FALSE(fs::exists(s.dir->path() / "outside"));
  EXPECT_FALSE(fs::exists(s.root / "x.pose.json"));
  EXPECT_EQ(s.request("GET", "/api/poses?library=missing", "").status, 404);
  s.post("/api/poses/remove", {{"library", "poses"}, {"name", "other"}});
  EXPECT_EQ(s.get("/api/poses?library=poses")["poses"].size(), 1u);
}

}  // namespace
}  // namespace rigel::server
