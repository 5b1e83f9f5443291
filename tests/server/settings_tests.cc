// The JSON API's scene settings (POST /api/playback-range, GET/POST
// /api/selection-sets, docs/SERVER.md) and the timeline's retime and copy
// of keys (POST /api/channel-keys with moveTo, from and copy) on the biped
// built on the bundled metarig: each one undo step, refusals naming the
// field.

#include <gtest/gtest.h>

#include <map>
#include <string>

#include "server_test_util.h"
#include "workspace.h"

namespace rigel::server {
namespace {

TEST(ServerApi, PlaybackRangeIsInTheSceneAndUndoes) {
  Served s = served_biped();
  ASSERT_TRUE(s.workspace);
  EXPECT_TRUE(s.get("/api/scene")["playbackRange"].is_null());
  Json r = s.post("/api/playback-range", {{"first", 5}, {"last", 120}});
  EXPECT_EQ(r["playbackRange"], Json::array({5.0, 120.0}));
  EXPECT_EQ(s.get("/api/scene")["playbackRange"], Json::array({5.0, 120.0}));
  s.post("/api/undo", Json::object());
  EXPECT_TRUE(s.get("/api/scene")["playbackRange"].is_null());
  for (auto [body, field] : {std::pair{R"({"first":9,"last":3})", "range"}, std::pair{R"({"first":1})", "last"},
                             std::pair{R"({"first":"a","last":3})", "first"}}) {
    Response resp = s.request("POST", "/api/playback-range", body);
    EXPECT_EQ(resp.status, 400) << body << ": " << resp.body;
    EXPECT_EQ(Json::parse(resp.body)["field"], field) << body;
  }
}

TEST(ServerApi, SelectionSetsSaveSelectReplaceAndRemove) {
  Served s = served_biped();
  ASSERT_TRUE(s.workspace);
  Json r = s.post("/api/selection-sets",
                  {{"op", "save"}, {"name", "left_arm"}, {"controls", {"hero_arm_L_ik", "hero_arm_L_fk1"}}});
  ASSERT_EQ(r["sets"].size(), 1u) << r;
  EXPECT_EQ(r["sets"][0]["name"], "left_arm");
  EXPECT_EQ(r["sets"][0]["members"][1]["name"], "hero_arm_L_fk1");
  // Without controls: the selection.
  s.post("/api/select", {{"controls", {s.uuid("hero_leg_R_ik")}}});
  s.post("/api/selection-sets", {{"op", "save"}, {"name", "right_leg"}});
  Json sets = s.get("/api/selection-sets");
  ASSERT_EQ(sets["sets"].size(), 2u);
  EXPECT_EQ(sets["sets"][1]["members"][0]["name"], "hero_leg_R_ik");
  // Select a set (replacing the selection), then add another.
  r = s.post("/api/selection-sets", {{"op", "select"}, {"name", "left_arm"}});
  EXPECT_EQ(r["selection"], Json::array({s.uuid("hero_arm_L_ik"), s.uuid("hero_arm_L_fk1")}));
  r = s.post("/api/selection-sets", {{"op", "select"}, {"name", "right_leg"}, {"add", true}});
  EXPECT_EQ(r["selection"].size(), 3u);
  EXPECT_EQ(s.get("/api/scene")["selection"].size(), 3u);
  // Remove, undone.
  s.post("/api/selection-sets", {{"op", "remove"}, {"name", "left_arm"}});
  EXPECT_EQ(s.get("/api/selection-sets")["sets"].size(), 1u);
  s.post("/api/undo", Json::object());
  EXPECT_EQ(s.get("/api/selection-sets")["sets"].size(), 2u);
  for (auto [body, status, field] :
       {std::tuple{R"({"op":"select","name":"nosuch"})", 404, "name"},
        std::tuple{R"({"op":"remove","name":"nosuch"})", 404, "name"},
        std::tuple{R"({"op":"save","name":"has space","controls":["hero_arm_L_ik"]})", 400, "name"},
        std::tuple{R"({"op":"save","name":"hero_arm_L_ik","controls":["hero_arm_L_ik"]})", 400, "name"},
        std::tuple{R"({"op":"save","name":"x","controls":["nobody"]})", 404, "controls[0]"},
        std::tuple{R"({"op":"rename","name":"x"})", 400, "op"}}) {
    Response resp = s.request("POST", "/api/selection-sets", body);
    EXPECT_EQ(resp.status, status) << body << ": " << resp.body;
    EXPECT_EQ(Json::parse(resp.body)["field"], field) << body;
  }
  s.post("/api/select", {{"controls", Json::array()}});
  Response none = s.request("POST", "/api/selection-sets", R"({"op":"save","name":"empty"})");
  EXPECT_EQ(none.status, 400) << none.body;
  EXPECT_EQ(Json::parse(none.body)["field"], "members");
}

TEST(ServerApi, KeysRetimedAndCopiedFromAFrameThatIsNotTheCurrentOne) {
  Served s = served_biped();
  ASSERT_TRUE(s.workspace);
  for (int f : {0, 10}) {
    s.post("/api/time", {{"frame", f}});
    s.post("/api/channel-keys", {{"controls", {"hero_arm_L_fkIkSwitch"}}, {"attrs", {"fkIk"}}, {"value", f / 10.0}});
  }
  s.post("/api/time", {{"frame", 3}});
  Json r = s.post("/api/channel-keys",
                  {{"controls", {"hero_arm_L_fkIkSwitch"}}, {"attrs", {"fkIk"}}, {"moveTo", 14}, {"from", 10}});
  EXPECT_EQ(r["keys"][0]["frames"], Json::array({0.0, 14.0}));
  r = s.post("/api/channel-keys", {{"controls", {"hero_arm_L_fkIkSwitch"}},
                                   {"attrs", {"fkIk"}},
                                   {"moveTo", 20},
                                   {"from", 14},
                                   {"copy", true}});
  EXPECT_EQ(r["keys"][0]["frames"], Json::array({0.0, 14.0, 20.0}));
  EXPECT_EQ(r["keys"][0]["values"], Json::array({0.0, 1.0, 1.0}));
  EXPECT_EQ(s.get("/api/scene")["frame"], 3.0) << "the current frame stays";
  s.post("/api/undo", Json::object());
  EXPECT_EQ(s.get("/api/channel-keys?controls=hero_arm_L_fkIkSwitch&attrs=fkIk")["keys"][0]["frames"],
            Json::array({0.0, 14.0}));
  for (auto [body, status, field] : {
           std::tuple{R"({"controls":["hero_arm_L_fkIkSwitch"],"attrs":["fkIk"],"moveTo":5,"from":7})", 404, "controls"},
           std::tuple{R"({"controls":["hero_arm_L_fkIkSwitch"],"attrs":["fkIk"],"moveTo":5,"from":"x"})", 400, "from"},
           std::tuple{R"({"controls":["hero_arm_L_fkIkSwitch"],"attrs":["fkIk"],"copy":true})", 400, "copy"},
       }) {
    Response resp = s.request("POST", "/api/channel-keys", body);
    EXPECT_EQ(resp.status, status) << body << ": " << resp.body;
    EXPECT_EQ(Json::parse(resp.body)["field"], field) << body;
  }
}

TEST(ServerApi, PickerGroupsTheBipedsControlsByPartAndSide) {
  Served s = served_biped();
  ASSERT_TRUE(s.workspace);
  const Json p = s.get("/api/picker");
  std::map<std::string, Json> groups;
  std::size_t controls = 0;
  for (const Json& g : p["groups"]) {
    groups[g["name"].get<std::string>()] = g;
    controls += g["controls"].size();
  }
  ASSERT_TRUE(groups.count("arm_L") && groups.count("leg_R") && groups.count("hand_L")) << p;
  EXPECT_EQ(groups["arm_L"]["side"], "L");
  EXPECT_EQ(groups["arm_L"]["part"], "arm");
  EXPECT_EQ(groups["leg_R"]["side"], "R");
  EXPECT_EQ(groups["leg_R"]["part"], "leg");
  EXPECT_EQ(groups["hand_L"]["part"], "hand");
  bool ik = false;
  for (const Json& c : groups["arm_L"]["controls"]) ik |= c["name"] == "hero_arm_L_ik";
  EXPECT_TRUE(ik) << groups["arm_L"];
  // Every control once.
  EXPECT_EQ(controls, s.workspace->workspace().controls().size());
}

}  // namespace
}  // namespace rigel::server
