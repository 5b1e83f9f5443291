// The JSON API's graph editor (GET /api/curves, POST /api/curve-keys,
// docs/SERVER.md) on the biped of examples/biped.rig.xml built on the
// bundled metarig: keyed channels as curves in frames, a key moved in time
// and value and its tangent changed, one inserted and one deleted, each one
// undo step, and refusals naming the field.

#include <gtest/gtest.h>

#include <string>

#include "server_test_util.h"
#include "workspace.h"

namespace rigel::server {
namespace {

const Json* curve(const Json& curves, const std::string& plug) {
  for (const Json& c : curves["curves"])
    if (c["plug"] == plug) return &c;
  return nullptr;
}

// The biped's left IK arm keyed at 0 and 10 (translateY 0, 0.1), its fkIk at 0, 10, 20.
Served keyed_biped() {
  Served s = served_biped();
  for (int f : {0, 10}) {
    s.post("/api/time", {{"frame", f}});
    s.post("/api/channel-values", {{"controls", {"hero_arm_L_ik"}}, {"attrs", {"translateY"}}, {"value", f * 0.01}});
    s.post("/api/channel-keys", {{"controls", {"hero_arm_L_ik"}}, {"attrs", {"translate"}}});
  }
  for (auto [f, v] : {std::pair{0, 0.0}, std::pair{10, 1.0}, std::pair{20, 0.5}}) {
    s.post("/api/time", {{"frame", f}});
    s.post("/api/channel-keys", {{"controls", {"hero_arm_L_fkIkSwitch"}}, {"attrs", {"fkIk"}}, {"value", v}});
  }
  return s;
}

TEST(ServerApi, CurvesShowKeysTangentsAndSamplesInFrames) {
  Served s = keyed_biped();
  ASSERT_TRUE(s.workspace);
  Json cs = s.get("/api/curves?controls=hero_arm_L_ik");
  const Json* ty = curve(cs, "hero_arm_L_ik.translateY");
  const Json* sw = curve(cs, "hero_arm_L_fkIkSwitch.fkIk");
  ASSERT_TRUE(ty && sw) << cs;
  EXPECT_EQ((*ty)["kind"], "curve");
  EXPECT_EQ((*ty)["frames"], Json::array({0.0, 10.0}));
  EXPECT_NEAR((*ty)["values"][1].get<double>(), 0.1, 1e-12);
  EXPECT_EQ((*sw)["frames"], Json::array({0.0, 10.0, 20.0}));
  EXPECT_EQ((*sw)["inTangents"].size(), 3u);
  EXPECT_EQ((*sw)["samples"]["frames"].size(), 21u) << "a sample a frame over the keys";
  EXPECT_EQ(cs["fps"], s.workspace->scene().graph().fps());

  Json wide = s.get("/api/curves?controls=hero_arm_L_ik&first=-5&last=30&step=5");
  EXPECT_EQ((*curve(wide, "hero_arm_L_fkIkSwitch.fkIk"))["samples"]["frames"].front(), -5.0);
  EXPECT_EQ((*curve(wide, "hero_arm_L_fkIkSwitch.fkIk"))["samples"]["frames"].back(), 30.0);

  for (auto [bad, field] : {std::pair{"/api/curves?controls=hero_arm_L_ik&step=0", "step"},
                            std::pair{"/api/curves?controls=hero_arm_L_ik&first=x", "first"},
                            std::pair{"/api/curves?controls=nobody", "controls[0]"}}) {
    Response r = s.request("GET", bad, "");
    EXPECT_EQ(r.status / 100, 4) << bad << ": " << r.body;
    EXPECT_EQ(Json::parse(r.body)["field"], field) << bad << ": " << r.body;
  }
}

TEST(ServerApi, CurveKeysEditInsertAndDeleteEachOneUndoStep) {
  Served s = keyed_biped();
  ASSERT_TRUE(s.workspace);
  graph::Graph& g = s.workspace->scene().graph();
  const std::size_t undo_before = g.undo_count();

  // Move fkIk's key at 10 (given a hair off the frame) to 15 with value 0.75, stepped out.
  Json r = s.post("/api/curve-keys", {{"op", "edit"},
                                      {"keys", {{{"curve", "hero_arm_L_fkIkSwitch.fkIk"},
                                                 {"frame", 10.0003},
                                                 {"toFrame", 15},
                                                 {"value", 0.75},
                                                 {"outTangent", "step"}}}}});
  EXPECT_EQ(r["changed"], 1);
  EXPECT_EQ(g.undo_count(), undo_before + 1);
  Json cs = s.get("/api/curves?controls=hero_arm_L_ik");
  const Json* sw = curve(cs, "hero_arm_L_fkIkSwitch.fkIk");
  ASSERT_TRUE(sw);
  EXPECT_EQ((*sw)["frames"], Json::array({0.0, 15.0, 20.0}));
  EXPECT_EQ((*sw)["values"][1], 0.75);
  EXPECT_EQ((*sw)["outTangents"][1], "step");
  s.post("/api/time", {{"frame", 18}});
  Json box = s.get("/api/channels?controls=hero_arm_L_ik");
  bool seen = false;
  for (const Json& row : box["controls"][0]["channels"])
    if (row["plug"] == "hero_arm_L_fkIkSwitch.fkIk") {
      EXPECT_EQ(row["value"], 0.75) << "a step holds the key's value";
      seen = true;
    }
  EXPECT_TRUE(seen) << box;

  // Insert on translateX at 5; delete both of translateZ's keys (its curve goes).
  r = s.post("/api/curve-keys", {{"op", "insert"}, {"keys", {{{"curve", "hero_arm_L_ik.translateX"}, {"frame", 5}}}}});
  EXPECT_EQ(r["changed"], 1);
  r = s.post("/api/curve-keys", {{"op", "delete"},
                                 {"keys",
                                  {{{"curve", "hero_arm_L_ik.translateZ"}, {"frame", 0}},
                                   {{"curve", "hero_arm_L_ik.translateZ"}, {"frame", 10}}}}});
  EXPECT_EQ(r["changed"], 2);
  cs = s.get("/api/curves?controls=hero_arm_L_ik");
  EXPECT_EQ((*curve(cs, "hero_arm_L_ik.translateX"))["frames"], Json::array({0.0, 5.0, 10.0}));
  EXPECT_EQ(curve(cs, "hero_arm_L_ik.translateZ"), nullptr) << cs;
  EXPECT_EQ(g.undo_count(), undo_before + 3);
  s.post("/api/undo", Json::object());
  cs = s.get("/api/curves?controls=hero_arm_L_ik");
  ASSERT_NE(curve(cs, "hero_arm_L_ik.translateZ"), nullptr) << "undo brings the curve back";

  // Refusals name the field; nothing changes.
  const std::size_t undo_now = g.undo_count();
  for (const char* bad : {
           R"({"op":"move","keys":[{"curve":"hero_arm_L_ik.translateX","frame":0}]})",
           R"({"op":"edit","keys":[]})",
           R"({"op":"edit","keys":[{"curve":"hero_arm_L_ik.translateX"}]})",
           R"({"op":"edit","keys":[{"curve":"hero_arm_L_ik.translateX","frame":0,"tangent":"wobbly"}]})",
           R"({"op":"edit","keys":[{"curve":"hero_arm_L_ik.translateX","frame":3,"value":1}]})",
           R"({"op":"edit","keys":[{"curve":"nosuch.translateX","frame":0,"value":1}]})",
           R"({"op":"delete","keys":[{"curve":"hero_arm_L_ik.translateX","frame":0,"value":1}]})",
       }) {
    Response resp = s.request("POST", "/api/curve-keys", bad);
    EXPECT_EQ(resp.status / 100, 4) << bad << ": " << resp.body;
    const Json err = Json::parse(resp.body);
    EXPECT_TRUE(err.contains("field")) << bad << ": " << resp.body;
  }
  EXPECT_EQ(g.undo_count(), undo_now);
}

}  // namespace
}  // namespace rigel::server
