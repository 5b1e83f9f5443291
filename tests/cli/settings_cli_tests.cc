// `rigel playback` and `rigel sets` on the biped (examples/biped.rig.xml on
// Rigify's human metarig): the playback range and selection sets set,
// saved with the scene and listed; `rigel key --move-to --copy` keeping
// the keys it copies; bad input refused with the option named and nothing
// written; `rigel picker` listing the groups.
#include <filesystem>

#include "cli_test_util.h"

namespace rigel::cli::testing {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

class CliSettings : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string example = (fs::path(RIGEL_SOURCE_DIR) / "examples/biped.rig.xml").string();
    const CliRun b = rigel({"build", example, "-o", out("a.rigel")});
    ASSERT_TRUE(exited_with(b, 0)) << b;
  }
  std::string out(const std::string& name) { return (dir_.path() / name).string(); }
  TempDir dir_;
};

TEST_F(CliSettings, playback_range_set_saved_and_shown) {
  CliRun p = rigel({"playback", out("a.rigel"), "--json"});
  ASSERT_TRUE(exited_with(p, 0)) << p;
  EXPECT_TRUE(Json::parse(p.out)["playbackRange"].is_null());
  p = rigel({"playback", out("a.rigel"), "--range", "12:96", "-o", out("b.rigel")});
  ASSERT_TRUE(exited_with(p, 0)) << p;
  p = rigel({"playback", out("b.rigel"), "--json"});
  ASSERT_TRUE(exited_with(p, 0)) << p;
  EXPECT_EQ(Json::parse(p.out)["playbackRange"], Json::array({12.0, 96.0}));
  for (const std::vector<std::string>& bad :
       {std::vector<std::string>{"playback", out("a.rigel"), "--range", "9:3", "-o", out("c.rigel")},
        std::vector<std::string>{"playback", out("a.rigel"), "--range", "nine", "-o", out("c.rigel")},
        std::vector<std::string>{"playback", out("a.rigel"), "--range", "1:3"}}) {
    const CliRun r = rigel(bad);
    EXPECT_FALSE(exited_with(r, 0)) << r;
    EXPECT_NE(r.err.find("--range"), std::string::npos) << r;
    EXPECT_FALSE(fs::exists(out("c.rigel")));
  }
}

TEST_F(CliSettings, selection_sets_saved_listed_and_removed) {
  CliRun r = rigel({"sets", out("a.rigel"), "--save", "left_arm", "--control", "hero_arm_L_ik,hero:arm_L/fk[0]", "-o",
                    out("b.rigel")});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  r = rigel({"sets", out("b.rigel"), "--json"});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  Json j = Json::parse(r.out);
  ASSERT_EQ(j["sets"].size(), 1u) << j;
  EXPECT_EQ(j["sets"][0]["name"], "left_arm");
  EXPECT_EQ(j["sets"][0]["members"], Json::array({"hero_arm_L_ik", "hero_arm_L_fk0"}));
  r = rigel({"sets", out("b.rigel"), "--remove", "left_arm", "-o", out("c.rigel"), "--json"});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  EXPECT_TRUE(Json::parse(r.out)["sets"].empty());
  for (const std::vector<std::string>& bad :
       {std::vector<std::string>{"sets", out("b.rigel"), "--remove", "nosuch", "-o", out("d.rigel")},
        std::vector<std::string>{"sets", out("b.rigel"), "--save", "x", "--control", "nobody", "-o", out("d.rigel")},
        std::vector<std::string>{"sets", out("b.rigel"), "--save", "bad name", "--control", "hero_arm_L_ik", "-o",
                                 out("d.rigel")},
        std::vector<std::string>{"sets", out("b.rigel"), "--save", "x", "-o", out("d.rigel")}}) {
    const CliRun e = rigel(bad);
    EXPECT_FALSE(exited_with(e, 0)) << e;
    EXPECT_TRUE(e.err.find("--remove") != std::string::npos || e.err.find("--save") != std::string::npos ||
                e.err.find("--control") != std::string::npos)
        << e;
    EXPECT_FALSE(fs::exists(out("d.rigel")));
  }
}

TEST_F(CliSettings, key_copy_keeps_the_keys_it_copies) {
  const std::string sw = "hero:arm_L/fkIkSwitch";
  CliRun r = rigel({"key", out("a.rigel"), "--control", sw, "--attr", "fkIk", "--frame", "4", "--value", "1", "-o",
                    out("b.rigel")});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  r = rigel({"key", out("b.rigel"), "--control", sw, "--attr", "fkIk", "--frame", "4", "--move-to", "9", "--copy",
             "-o", out("c.rigel"), "--json"});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  EXPECT_EQ(Json::parse(r.out)["copiedTo"], 9.0);
  r = rigel({"keys", out("c.rigel"), "--control", sw, "--json"});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  EXPECT_NE(r.out.find("[4.0,9.0]"), std::string::npos) << r;
  r = rigel({"key", out("b.rigel"), "--control", sw, "--attr", "fkIk", "--frame", "4", "--copy", "-o", out("d.rigel")});
  EXPECT_FALSE(exited_with(r, 0)) << r;
  EXPECT_NE(r.err.find("--copy"), std::string::npos) << r;
  EXPECT_FALSE(fs::exists(out("d.rigel")));
}

TEST_F(CliSettings, picker_lists_the_groups_by_part_and_side) {
  const CliRun r = rigel({"picker", out("a.rigel"), "--json"});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  const Json j = Json::parse(r.out);
  bool arm = false;
  for (const Json& g : j["groups"])
    if (g["name"] == "arm_L") {
      arm = true;
      EXPECT_EQ(g["part"], "arm");
      EXPECT_EQ(g["side"], "L");
    }
  EXPECT_TRUE(arm) << j;
  const CliRun bad = rigel({"picker", out("nosuch.rigel")});
  EXPECT_EQ(bad.exit_code, 1) << bad;
  EXPECT_NE(bad.err.find("nosuch.rigel"), std::string::npos) << bad;
}

TEST_F(CliSettings, trail_samples_a_control_over_a_range_with_its_keys) {
  const std::string ik = "hero:arm_L/ik";
  CliRun r = rigel({"key", out("a.rigel"), "--control", ik, "--attr", "translate", "--frame", "3", "-o", out("b.rigel")});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  r = rigel({"trail", out("b.rigel"), "--control", ik, "--frames", "0:8", "--step", "4", "--json"});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  const Json j = Json::parse(r.out);
  ASSERT_EQ(j["trails"].size(), 1u);
  EXPECT_EQ(j["trails"][0]["frames"], Json::array({0.0, 3.0, 4.0, 8.0}));
  EXPECT_EQ(j["trails"][0]["keys"], Json::array({3.0}));
  for (const std::vector<std::string>& bad :
       {std::vector<std::string>{"trail", out("b.rigel"), "--control", ik, "--frames", "8:0"},
        std::vector<std::string>{"trail", out("b.rigel"), "--control", "nobody", "--frames", "0:8"},
        std::vector<std::string>{"trail", out("b.rigel"), "--control", ik, "--frames", "0:8", "--step", "0"}}) {
    const CliRun e = rigel(bad);
    EXPECT_FALSE(exited_with(e, 0)) << e;
    EXPECT_TRUE(e.err.find("--frames") != std::string::npos || e.err.find("--control") != std::string::npos ||
                e.err.find("--step") != std::string::npos)
        << e;
  }
}

}  // namespace
}  // namespace rigel::cli::testing
