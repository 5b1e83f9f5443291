// `rigel space`: the biped's left IK hand (examples/biped.rig.xml on
// Rigify's human metarig) listed with its default spaces, given a custom
// space, switched at a frame (its world matrix kept there, earlier frames
// unchanged, the switch keys stepped) and baked over a range (keys on the
// range's frames only); bad input refused with the option named and
// nothing written.
#include <filesystem>

#include "cli_test_util.h"

namespace rigel::cli::testing {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

class CliSpace : public ::testing::Test {
 protected:
  // The biped with its chest turning and its left IK hand keyed over 0..20.
  static void SetUpTestSuite() {
    dir_ = new TempDir();
    const std::string example = (fs::path(RIGEL_SOURCE_DIR) / "examples/biped.rig.xml").string();
    const std::string a = out("a.rigel"), b = out("b.rigel");
    runs_ = new std::vector<CliRun>{
        rigel({"build", example, "-o", a}),
        rigel({"key", a, "--control", "hero:chest/main", "--attr", "rotate", "--frame", "0", "-o", b}),
        rigel({"pose", b, "--control", "hero_chest_main0", "--mode", "forward", "--rotate", "0,40,10", "--frame", "20",
               "--auto-key", "-o", a}),
        rigel({"key", a, "--control", "hero:arm_L/ik", "--attr", "translate", "--frame", "0", "-o", b}),
        rigel({"pose", b, "--control", "hero_arm_L_ik", "--mode", "forward", "--translate", "0.1,0.15,0", "--frame", "20",
               "--auto-key", "-o", shot()}),
    };
  }
  static void TearDownTestSuite() {
    delete runs_;
    delete dir_;
  }
  void SetUp() override {
    for (const CliRun& r : *runs_) ASSERT_TRUE(exited_with(r, 0)) << r;
  }
  static std::string shot() { return out("shot.rigel"); }
  static std::string out(const std::string& name) { return (dir_->path() / name).string(); }
  // Every node's world translation at `frame` (rigel eval).
  static Json world_at(const std::string& scene, double frame) {
    const CliRun p = rigel({"eval", scene, "--frame", std::to_string(frame), "--json"});
    EXPECT_TRUE(exited_with(p, 0)) << p;
    return exited_with(p, 0) ? Json::parse(p.out)["nodes"] : Json();
  }

  static TempDir* dir_;
  static std::vector<CliRun>* runs_;
};
TempDir* CliSpace::dir_ = nullptr;
std::vector<CliRun>* CliSpace::runs_ = nullptr;

TEST_F(CliSpace, list_add_and_the_default_spaces) {
  const CliRun l = rigel({"space", shot(), "--control", "hero:arm_L/ik", "--list", "--json"});
  ASSERT_TRUE(exited_with(l, 0)) << l;
  const Json j = Json::parse(l.out);
  EXPECT_EQ(j["current"], "parent");
  std::vector<std::string> names;
  for (const Json& s : j["spaces"]) names.push_back(s["name"]);
  EXPECT_EQ(names, (std::vector<std::string>{"parent", "world", "global", "chest", "head"})) << l.out;
  EXPECT_EQ(j["spaces"][1]["target"], nullptr);

  const std::string added = out("added.rigel");
  const CliRun a = rigel({"space", shot(), "--control", "hero:arm_L/ik", "--add", "prop", "--target", "hand.R", "-o",
                          added, "--json"});
  ASSERT_TRUE(exited_with(a, 0)) << a;
  EXPECT_EQ(Json::parse(a.out)["spaces"].size(), 6u) << a.out;
  const CliRun text = rigel({"space", added, "--control", "hero_arm_L_ik", "--list"});
  ASSERT_TRUE(exited_with(text, 0)) << text;
  EXPECT_NE(text.out.find("* 0 parent"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("5 prop  hand.R"), std::string::npos) << text.out;
}

TEST_F(CliSpace, switch_at_a_frame_keeps_the_hand_there_and_earlier_frames_as_they_were) {
  const std::string switched = out("switched.rigel");
  const CliRun sw = rigel({"space", shot(), "--control", "hero:arm_L/ik", "--switch", "world", "--frame", "10", "-o",
                           switched, "--json"});
  ASSERT_TRUE(exited_with(sw, 0)) << sw;
  const Json j = Json::parse(sw.out);
  EXPECT_EQ(j["from"], "parent");
  EXPECT_LT(j["maxError"].get<double>(), 1e-9) << sw.out;
  for (double f : {0.0, 5.0, 9.0, 10.0}) {
    const Json a = world_at(shot(), f), b = world_at(switched, f);
    for (const auto& [name, node] : a.items()) {
      if (!b.contains(name)) continue;  // the switch's compensation transform is new
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(node["t"][k].get<double>(), b[name]["t"][k].get<double>(), 1e-9) << name << " at frame " << f;
    }
  }
  const CliRun keys = rigel({"keys", switched, "--control", "hero:arm_L/ikSpaceSwitch", "--attr", "space", "--json"});
  ASSERT_TRUE(exited_with(keys, 0)) << keys;
  const Json k = Json::parse(keys.out);
  ASSERT_EQ(k["channels"].size(), 1u) << keys.out;
  EXPECT_EQ(k["channels"][0]["frames"], Json::array({0.0, 10.0})) << keys.out;
  EXPECT_EQ(k["channels"][0]["values"], Json::array({0.0, 1.0})) << keys.out;
  EXPECT_EQ(k["channels"][0]["outTangents"], Json::array({"step", "step"})) << keys.out;
}

TEST_F(CliSpace, bake_a_range_keys_its_frames_only) {
  const std::string baked = out("baked.rigel");
  const CliRun b = rigel({"space", shot(), "--control", "hero:arm_L/ik", "--switch", "chest", "--frames", "4:16", "-o",
                          baked, "--json"});
  ASSERT_TRUE(exited_with(b, 0)) << b;
  const Json j = Json::parse(b.out);
  EXPECT_EQ(j["frames"], 13);
  EXPECT_LT(j["maxError"].get<double>(), 1e-6) << b.out;
  const CliRun keys = rigel({"keys", baked, "--control", "hero:arm_L/ik", "--attr", "translate", "--json"});
  ASSERT_TRUE(exited_with(keys, 0)) << keys;
  const Json listed = Json::parse(keys.out);
  for (const Json& c : listed["channels"]) {
    ASSERT_EQ(c["frames"].size(), 15u) << c;  // 0, 4..16, 20
    EXPECT_EQ(c["frames"][0], 0.0);
    EXPECT_EQ(c["frames"][1], 4.0);
    EXPECT_EQ(c["frames"][13], 16.0);
    EXPECT_EQ(c["frames"][14], 20.0);
  }
}

TEST_F(CliSpace, bad_input_names_the_option_and_writes_nothing) {
  const std::string o = out("never.rigel");
  struct Bad {
    std::vector<std::string> args;
    int code;
    const char* says;
  };
  const std::vector<Bad> cases = {
      {{"--control", "nobody", "--switch", "world", "-o", o}, 1, "--control"},
      {{"--control", "hero:arm_L/ik", "--switch", "moon", "-o", o}, 1, "--switch"},
      {{"--control", "hero:arm_L/fk[0]", "--switch", "world", "-o", o}, 1, "has no spaces"},
      {{"--control", "hero:arm_L/ik", "--add", "hand", "--target", "hand.L", "-o", o}, 1, "--target"},
      {{"--control", "hero:arm_L/ik", "--add", "chest", "-o", o}, 1, "has a space 'chest'"},
      {{"--control", "hero:arm_L/ik", "--switch", "world", "--frames", "100:200", "-o", o}, 1, "outside the clip"},
      {{"--control", "hero:arm_L/ik", "--switch", "world", "--frames", "9:3", "-o", o}, 1, "--frames"},
      {{"--control", "hero:arm_L/ik", "--switch", "world", "--frames", "x", "-o", o}, 2, "--frames"},
      {{"--control", "hero:arm_L/ik", "--switch", "world"}, 2, "-o"},
      {{"--control", "hero:arm_L/ik", "--list", "--add", "x", "-o", o}, 2, "one of"},
      {{"--control", "hero:arm_L/ik", "--switch", "world", "--frame", "3", "--frames", "0:4", "-o", o}, 2, "excludes"},
  };
  for (const Bad& c : cases) {
    std::vector<std::string> args = {"space", shot()};
    args.insert(args.end(), c.args.begin(), c.args.end());
    const CliRun r = rigel(args);
    EXPECT_TRUE(exited_with(r, c.code)) << r;
    EXPECT_NE(r.err.find(c.says), std::string::npos) << r;
    EXPECT_FALSE(fs::exists(o)) << "nothing written";
  }
}

}  // namespace
}  // namespace rigel::cli::testing
