// `rigel match`: FK/IK match and bake of the biped's leg (examples/
// biped.rig.xml on Rigify's human metarig) with a rolled reverse foot, keys
// on the frames asked for only, the switch stepped; bad input refused with
// the option named and nothing written.
#include <filesystem>

#include "cli_test_util.h"

namespace rigel::cli::testing {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

class CliMatch : public ::testing::Test {
 protected:
  // The biped with its left leg in IK and the foot rolling from 0 to 40
  // degrees over frames 0..20.
  static void SetUpTestSuite() {
    dir_ = new TempDir();
    const std::string example = (fs::path(RIGEL_SOURCE_DIR) / "examples/biped.rig.xml").string();
    const std::string a = out("a.rigel"), b = out("b.rigel");
    runs_ = new std::vector<CliRun>{
        rigel({"build", example, "-o", a}),
        rigel({"key", a, "--control", "hero:leg_L/fkIkSwitch", "--attr", "fkIk", "--value", "1", "--frame", "0", "-o", b}),
        rigel({"key", b, "--control", "hero:foot_L/reverseFoot", "--attr", "roll", "--value", "0", "--frame", "0", "-o", a}),
        rigel({"key", a, "--control", "hero:foot_L/reverseFoot", "--attr", "roll", "--value", "40", "--frame", "20", "-o",
               shot()}),
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

  static TempDir* dir_;
  static std::vector<CliRun>* runs_;
};
TempDir* CliMatch::dir_ = nullptr;
std::vector<CliRun>* CliMatch::runs_ = nullptr;

TEST_F(CliMatch, fk_keyed_to_the_rolling_ik_leg_over_a_range_and_the_switch_stepped) {
  const std::string matched = out("matched.rigel");
  const CliRun m = rigel({"match", shot(), "--rig", "hero", "--component", "leg_L", "--to", "fk", "--frames", "0:20",
                          "-o", matched, "--json"});
  ASSERT_TRUE(exited_with(m, 0)) << m;
  const Json j = Json::parse(m.out);
  EXPECT_EQ(j["framesKeyed"], 21);
  EXPECT_LT(j["maxError"].get<double>(), 1e-6) << m.out;
  EXPECT_EQ(j["to"], "fk");
  bool toe = false;
  for (const Json& c : j["controls"]) toe = toe || c.get<std::string>() == "hero_foot_L_toeFk";
  EXPECT_TRUE(toe) << "the reverse foot's roll goes to the FK toe: " << m.out;
  EXPECT_NE(m.err.find("matched leg_L to FK at 21 frames"), std::string::npos) << m.err;

  const CliRun sw = rigel({"keys", matched, "--control", "hero:leg_L/fkIkSwitch", "--attr", "fkIk", "--json"});
  ASSERT_TRUE(exited_with(sw, 0)) << sw;
  const Json s = Json::parse(sw.out);
  ASSERT_EQ(s["channels"].size(), 1u) << sw.out;
  EXPECT_EQ(s["channels"][0]["frames"], Json::array({0.0, 20.0}));
  EXPECT_EQ(s["channels"][0]["values"], Json::array({0.0, 0.0}));
  const CliRun toe_keys = rigel({"keys", matched, "--control", "hero:foot_L/toeFk", "--attr", "rotate", "--json"});
  ASSERT_TRUE(exited_with(toe_keys, 0)) << toe_keys;
  for (const Json& c : Json::parse(toe_keys.out)["channels"]) {
    EXPECT_EQ(c["frames"].size(), 21u) << c;
    EXPECT_EQ(c["frames"].front(), 0.0);
    EXPECT_EQ(c["frames"].back(), 20.0);
  }
}

TEST_F(CliMatch, one_frame_and_back_to_ik) {
  const std::string a = out("one.rigel"), b = out("back.rigel");
  const CliRun m = rigel({"match", shot(), "--rig", "hero", "--component", "leg_L", "--to", "fk", "--frame", "10", "-o", a});
  ASSERT_TRUE(exited_with(m, 0)) << m;
  EXPECT_NE(m.err.find("at 1 frame"), std::string::npos) << m.err;
  const CliRun back = rigel({"match", a, "--rig", "hero", "--component", "7f150524-34b9-45df-9e77-69b10f4205b4", "--to",
                             "ik", "--frame", "10", "-o", b, "--json"});
  ASSERT_TRUE(exited_with(back, 0)) << back << " (the leg by rigId)";
  EXPECT_LT(Json::parse(back.out)["maxError"].get<double>(), 1e-5) << back.out;
}

TEST_F(CliMatch, bad_input_names_the_option_and_writes_nothing) {
  const std::string o = out("never.rigel");
  struct Bad {
    std::vector<std::string> args;
    int code;
    const char* says;
  };
  const std::vector<Bad> cases = {
      {{"--rig", "hero", "--component", "leg_X", "--to", "fk"}, 1, "--component"},
      {{"--rig", "villain", "--component", "leg_L", "--to", "fk"}, 1, "--rig"},
      {{"--rig", "hero", "--component", "spine", "--to", "fk"}, 1, "no FK/IK switch"},
      {{"--rig", "hero", "--component", "leg_L", "--to", "fk", "--frames", "20:5"}, 1, "--frames"},
      {{"--rig", "hero", "--component", "leg_L", "--to", "fk", "--frames", "100:200"}, 1, "outside the clip"},
      {{"--rig", "hero", "--component", "leg_L", "--to", "fk", "--frames", "a:b"}, 2, "--frames"},
      {{"--rig", "hero", "--component", "leg_L", "--to", "sideways"}, 2, "--to"},
      {{"--rig", "hero", "--component", "leg_L", "--to", "fk", "--frame", "3", "--frames", "0:4"}, 2, "excludes"},
  };
  for (const Bad& c : cases) {
    std::vector<std::string> args = {"match", shot()};
    args.insert(args.end(), c.args.begin(), c.args.end());
    args.insert(args.end(), {"-o", o});
    const CliRun r = rigel(args);
    EXPECT_TRUE(exited_with(r, c.code)) << r;
    EXPECT_NE(r.err.find(c.says), std::string::npos) << r;
    EXPECT_FALSE(fs::exists(o)) << "nothing written";
  }
  const CliRun missing = rigel({"match", out("missing.rigel"), "--rig", "hero", "--component", "leg_L", "--to", "fk", "-o", o});
  EXPECT_TRUE(exited_with(missing, 1)) << missing;
  EXPECT_NE(missing.err.find("missing.rigel"), std::string::npos) << missing;
}

}  // namespace
}  // namespace rigel::cli::testing
