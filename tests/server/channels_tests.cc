// The JSON API's channel box (GET /api/channels, docs/SERVER.md) on the
// biped of examples/biped.rig.xml built on the bundled metarig: a control's
// channels as components with their values and keyed state, its
// component's switches beside them, a component set through
// /api/channel-values, and refusals naming the field.

#include <gtest/gtest.h>

#include <string>

#include "rigel/ephemeral/component.h"
#include "rigel/rig/manager.h"
#include "rigel/scene/transform_types.h"
#include "server_test_util.h"
#include "workspace.h"

namespace rigel::server {
namespace {

namespace fs = std::filesystem;

const Json* row(const Json& box, const std::string& plug) {
  for (const Json& r : box["channels"])
    if (r["plug"] == plug) return &r;
  return nullptr;
}

TEST(ServerApi, ChannelBoxListsValuesKeyedStateAndTheComponentsSwitches) {
  Served s = served_biped();
  ASSERT_TRUE(s.workspace);
  s.post("/api/time", {{"frame", 0}});

  Json box = s.get("/api/channels?controls=hero_arm_L_ik,hero_arm_L_fk1");
  ASSERT_EQ(box["controls"].size(), 2u) << box;
  const Json& ik = box["controls"][0];
  EXPECT_EQ(ik["control"], "hero_arm_L_ik");
  for (const char* plug : {"hero_arm_L_ik.translateX", "hero_arm_L_ik.rotateZ", "hero_arm_L_ik.scaleY"}) {
    const Json* r = row(ik, plug);
    ASSERT_NE(r, nullptr) << plug << " in " << ik;
    EXPECT_EQ((*r)["keyed"], "none") << plug;
  }
  const Json* fk_ik = row(ik, "hero_arm_L_fkIkSwitch.fkIk");
  ASSERT_NE(fk_ik, nullptr) << "the limb's switch beside its control's channels: " << ik;
  EXPECT_EQ((*fk_ik)["node"], "hero_arm_L_fkIkSwitch");
  EXPECT_EQ((*fk_ik)["attr"], "fkIk");
  EXPECT_EQ((*fk_ik)["keyAttr"], "fkIk");
  EXPECT_EQ((*fk_ik)["value"], std::get<double>(s.workspace->scene().graph().evaluate(
                                   s.workspace->scene().graph().find("hero_arm_L_fkIkSwitch"),
                                   s.workspace->scene().graph().node(s.workspace->scene().graph().find("hero_arm_L_fkIkSwitch"))->type().attr_find("fkIk"))));

  // One component set (the others keep theirs), keyed, then seen keyed here
  // and, at another frame, elsewhere.
  Json set = s.post("/api/channel-values", {{"controls", {"hero_arm_L_ik"}}, {"attrs", {"translateY"}}, {"value", 0.125}});
  ASSERT_EQ(set["channels"].size(), 1u) << set;
  EXPECT_EQ(set["channels"][0]["plug"], "hero_arm_L_ik.translateY");
  EXPECT_EQ(set["channels"][0]["value"], 0.125);
  s.post("/api/channel-keys", {{"controls", {"hero_arm_L_ik"}}, {"attrs", {"translate"}}});
  box = s.get("/api/channels?controls=hero_arm_L_ik");
  EXPECT_EQ((*row(box["controls"][0], "hero_arm_L_ik.translateY"))["value"], 0.125);
  EXPECT_EQ((*row(box["controls"][0], "hero_arm_L_ik.translateX"))["value"], 0.0);
  EXPECT_EQ((*row(box["controls"][0], "hero_arm_L_ik.translateY"))["keyed"], "here");
  EXPECT_EQ((*row(box["controls"][0], "hero_arm_L_ik.rotateX"))["keyed"], "none");
  s.post("/api/time", {{"frame", 10}});
  box = s.get("/api/channels?controls=hero_arm_L_ik");
  EXPECT_EQ((*row(box["controls"][0], "hero_arm_L_ik.translateY"))["keyed"], "elsewhere");
  EXPECT_EQ(box["frame"], 10.0);
  // A keyed component set at another frame keys it there.
  set = s.post("/api/channel-values", {{"controls", {"hero_arm_L_ik"}}, {"attrs", {"translateY"}}, {"value", -0.25}});
  EXPECT_EQ(set["keys"][1]["frames"], Json::array({0.0, 10.0})) << set;

  // The selection without `controls`.
  s.post("/api/select", {{"controls", {"hero_leg_L_ik"}}});
  box = s.get("/api/channels");
  ASSERT_EQ(box["controls"].size(), 1u) << box;
  EXPECT_EQ(box["controls"][0]["control"], "hero_leg_L_ik");

  for (auto [bad, field] : {std::pair{"/api/channels?controls=nobody", "controls[0]"},
                            std::pair{"/api/channels?controls=hero_arm_L_ik,", "controls[1]"}}) {
    Response r = s.request("GET", bad, "");
    EXPECT_EQ(r.status / 100, 4) << bad << ": " << r.body;
    EXPECT_EQ(Json::parse(r.body)["field"], field) << bad << ": " << r.body;
  }
  Response r = s.request("POST", "/api/channel-values",
                         Json{{"controls", {"hero_arm_L_ik"}}, {"attrs", {"translateW"}}, {"value", 1}}.dump());
  EXPECT_EQ(r.status, 400) << r.body;
  EXPECT_EQ(Json::parse(r.body)["field"], "attrs") << r.body;
}

}  // namespace
}  // namespace rigel::server
