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
  const Json toe_json = Json::parse(toe_keys.out);
  for (const Json& c : toe_json["channels"]) {
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

namespace rigel::cli::testing {
namespace {

// `rigel mirror`: the biped's left arm posed, mirrored onto the right and
// flipped; pairs without names; bad input refused writing nothing.
TEST(CliMirror, mirror_flip_and_refusals) {
  TempDir dir;
  auto out = [&](const std::string& name) { return (dir.path() / name).string(); };
  const std::string example = (fs::path(RIGEL_SOURCE_DIR) / "examples/biped.rig.xml").string();
  ASSERT_TRUE(exited_with(rigel({"build", example, "-o", out("hero.rigel")}), 0));
  // Pose the left arm's FK (a key at frame 0 with the posed value).
  ASSERT_TRUE(exited_with(rigel({"pose", out("hero.rigel"), "--control", "hero_arm_L_fk0", "--mode", "forward", "--rotate",
                                 "20,0,30", "-o", out("posed.rigel")}),
                          0));
  const CliRun m = rigel({"mirror", out("posed.rigel"), "--controls", "hero:arm_L/fk[0]", "-o", out("mirrored.rigel"),
                          "--json"});
  ASSERT_TRUE(exited_with(m, 0)) << m;
  const Json j = Json::parse(m.out);
  EXPECT_EQ(j["set"], Json::array({"hero_arm_R_fk0"})) << m.out;
  EXPECT_EQ(j["frames"], 1);
  const CliRun f = rigel({"mirror", out("mirrored.rigel"), "--all", "--flip", "-o", out("flipped.rigel"), "--json"});
  ASSERT_TRUE(exited_with(f, 0)) << f;
  EXPECT_GT(Json::parse(f.out)["set"].size(), 40u) << "every control of the rig and the switches";

  // Bind pose: the posed control back at rest, keyed at frame 3.
  const CliRun bp = rigel({"bind-pose", out("posed.rigel"), "--controls", "hero:arm_L", "--frame", "3", "--key", "-o",
                           out("rest.rigel"), "--json"});
  ASSERT_TRUE(exited_with(bp, 0)) << bp;
  EXPECT_GE(Json::parse(bp.out)["set"].size(), 6u) << bp.out;
  const CliRun keys = rigel({"keys", out("rest.rigel"), "--control", "hero_arm_L_fk0", "--attr", "rotate", "--json"});
  ASSERT_TRUE(exited_with(keys, 0)) << keys;
  const Json keys_json = Json::parse(keys.out);
  for (const Json& c : keys_json["channels"]) {
    ASSERT_FALSE(c["frames"].empty()) << keys.out;
    EXPECT_EQ(c["frames"].back(), 3.0) << keys.out;
    EXPECT_EQ(c["values"].back(), 0.0) << keys.out;
  }
  const CliRun bad_bind = rigel({"bind-pose", out("posed.rigel"), "--controls", "hand.L", "-o", out("never.rigel")});
  EXPECT_TRUE(exited_with(bad_bind, 1)) << bad_bind;
  EXPECT_NE(bad_bind.err.find("not a built rig's control, component or rig"), std::string::npos) << bad_bind;

  struct Bad {
    std::vector<std::string> args;
    int code;
    const char* says;
  };
  for (const Bad& b : std::vector<Bad>{{{"--controls", "hand.L"}, 1, "is not a built rig's control"},
                                       {{"--controls", "nobody"}, 1, "no node named 'nobody'"},
                                       {{"--controls", "hero_global_main"}, 1, "nothing to mirror"},
                                       {{}, 2, "--controls"},
                                       {{"--all", "--from", "X"}, 2, "--from"},
                                       {{"--all", "--plane", "ab"}, 2, "--plane"},
                                       {{"--all", "--frames", "9:2"}, 1, "--frames"}}) {
    std::vector<std::string> args = {"mirror", out("posed.rigel")};
    args.insert(args.end(), b.args.begin(), b.args.end());
    args.insert(args.end(), {"-o", out("never.rigel")});
    const CliRun r = rigel(args);
    EXPECT_TRUE(exited_with(r, b.code)) << r;
    EXPECT_NE(r.err.find(b.says), std::string::npos) << r;
    EXPECT_FALSE(fs::exists(out("never.rigel")));
  }
}

}  // namespace
}  // namespace rigel::cli::testing
