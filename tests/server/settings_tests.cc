// The JSON API's scene settings (POST /api/playback-range, GET/POST
// /api/selection-sets, docs/SERVER.md) and the timeline's retime and copy
// of keys (POST /api/channel-keys with moveTo, from and copy) on the biped
// built on the bundled metarig: each one undo step, refusals naming the
// field.

#include <gtest/gtest.h>

#include <cmath>
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

TEST(ServerApi, TrailsAndGhostsFromTheEvaluatedGraph) {
  Served s = served_biped();
  ASSERT_TRUE(s.workspace);
  for (int f : {0, 10}) {
    s.post("/api/time", {{"frame", f}});
    s.post("/api/channel-values", {{"controls", {"hero_arm_L_ik"}}, {"attrs", {"translateY"}}, {"value", f * 0.02}});
    s.post("/api/channel-keys", {{"controls", {"hero_arm_L_ik"}}, {"attrs", {"translate"}}});
  }
  s.post("/api/time", {{"frame", 5}});
  const std::size_t undo = s.workspace->workspace().graph().undo_count();
  Json t = s.get("/api/trails?controls=hero_arm_L_ik&first=0&last=10&step=5");
  ASSERT_EQ(t["trails"].size(), 1u) << t;
  EXPECT_EQ(t["trails"][0]["frames"], Json::array({0.0, 5.0, 10.0}));
  EXPECT_EQ(t["trails"][0]["keys"], Json::array({0.0, 10.0}));
  // translateY moved by 0.2 in the control's parent space (rotated, not scaled): the trail by 0.2.
  double moved = 0;
  for (int k = 0; k < 3; ++k)
    moved += std::pow(t["trails"][0]["points"][2][k].get<double>() - t["trails"][0]["points"][0][k].get<double>(), 2);
  EXPECT_NEAR(std::sqrt(moved), 0.2, 1e-9);
  EXPECT_EQ(s.get("/api/scene")["frame"], 5.0) << "the time stays";

  Json g = s.get("/api/ghosts?before=2&after=1&step=3");
  EXPECT_GE(g["joints"].size(), 159u) << "the metarig's and the rig's joints";
  EXPECT_EQ(g["parents"].size(), g["joints"].size());
  EXPECT_EQ(g["parents"][0], -1);
  ASSERT_EQ(g["frames"].size(), 3u);
  EXPECT_EQ(g["frames"][0]["frame"], -1.0);
  EXPECT_EQ(g["frames"][2]["frame"], 8.0);
  EXPECT_EQ(g["frames"][1]["points"].size(), g["joints"].size());
  s.post("/api/select", {{"controls", {s.uuid("hero_arm_L_ik")}}});
  g = s.get("/api/ghosts?keys=1");
  ASSERT_EQ(g["frames"].size(), 2u) << "at the keys of the selection's keying group";
  g = s.get("/api/ghosts?frames=3,4.5");
  EXPECT_EQ(g["frames"][1]["frame"], 4.5);
  EXPECT_EQ(s.workspace->workspace().graph().undo_count(), undo) << "nothing changed";

  for (auto [bad, field] : {std::pair{"/api/trails?controls=hero_arm_L_ik&first=0", "last"},
                            std::pair{"/api/trails?controls=hero_arm_L_ik&first=9&last=2", "frames"},
                            std::pair{"/api/trails?controls=hero_arm_L_ik&first=0&last=9&step=0", "step"},
                            std::pair{"/api/ghosts?frames=1,x", "frames[1]"},
                            std::pair{"/api/ghosts?before=2.5", "before"},
                            std::pair{"/api/ghosts?before=-1", "before"}}) {
    Response r = s.request("GET", bad, "");
    EXPECT_EQ(r.status, 400) << bad << ": " << r.body;
    EXPECT_EQ(Json::parse(r.body)["field"], field) << bad << ": " << r.body;
  }
}

}  // namespace
}  // namespace rigel::server
