// `rigel key` and `rigel keys`: keys on the channels of a built rig's
// controls and of its fkIk switch (the biped of examples/biped.rig.xml on
// Rigify's human metarig), saved, listed and deleted; bad input refused.
#include <filesystem>

#include "cli_test_util.h"

namespace rigel::cli::testing {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

class CliKey : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir();
    const std::string example = (fs::path(RIGEL_SOURCE_DIR) / "examples/biped.rig.xml").string();
    built_run_ = new CliRun(rigel({"build", example, "-o", hero()}));
  }
  static void TearDownTestSuite() {
    delete built_run_;
    delete dir_;
  }
  void SetUp() override { ASSERT_TRUE(exited_with(*built_run_, 0)) << *built_run_; }
  static std::string hero() { return (dir_->path() / "hero.rigel").string(); }
  static std::string out(const std::string& name) { return (dir_->path() / name).string(); }

  static TempDir* dir_;
  static CliRun* built_run_;
};
TempDir* CliKey::dir_ = nullptr;
CliRun* CliKey::built_run_ = nullptr;

TEST_F(CliKey, a_controls_key_keys_the_whole_built_character) {
  const CliRun k = rigel({"key", hero(), "--control", "hero_arm_L_fk1", "--frame", "10", "-o", out("pose.rigel"), "--json"});
  ASSERT_TRUE(exited_with(k, 0)) << k;
  const Json j = Json::parse(k.out);
  EXPECT_EQ(j["frame"].get<double>(), 10.0);
  EXPECT_GT(j["channels"].size(), 30u) << "every channel of every control of the rig";
  bool global = false;
  for (const Json& c : j["channels"]) global = global || c.get<std::string>() == "hero_global_main.translate";
  EXPECT_TRUE(global) << k.out;
  for (const Json& p : j["keys"]) EXPECT_EQ(p["frames"], Json::array({10.0})) << p;

  const CliRun listed = rigel({"keys", out("pose.rigel"), "--control", "hero_global_main", "--json"});
  ASSERT_TRUE(exited_with(listed, 0)) << listed;
  const Json l = Json::parse(listed.out);
  EXPECT_EQ(l["control"], "hero_global_main");
  ASSERT_EQ(l["channels"].size(), 9u) << listed.out;
  EXPECT_EQ(l["channels"][0]["plug"], "hero_global_main.translateX");
}

TEST_F(CliKey, the_fk_ik_switch_is_keyed_by_address_with_values_and_deleted) {
  const std::string a = out("switch_a.rigel"), b = out("switch_b.rigel"), c = out("switch_c.rigel");
  ASSERT_TRUE(exited_with(rigel({"key", hero(), "--control", "hero:arm_L/fkIkSwitch", "--attr", "fkIk", "--value", "0",
                                 "--frame", "0", "-o", a}),
                          0));
  const CliRun k = rigel({"key", a, "--control", "hero:arm_L/fkIkSwitch", "--attr", "fkIk", "--value", "1", "--frame",
                          "24", "-o", b, "--json"});
  ASSERT_TRUE(exited_with(k, 0)) << k;
  const Json j = Json::parse(k.out);
  ASSERT_EQ(j["keys"].size(), 1u) << k.out;
  EXPECT_EQ(j["keys"][0]["frames"], Json::array({0.0, 24.0}));
  EXPECT_EQ(j["keys"][0]["values"], Json::array({0.0, 1.0}));

  EXPECT_EQ(j["keys"][0]["outTangents"], Json::array({"auto", "auto"})) << k.out;
  // A step key: the switch holds until the next key.
  const CliRun step = rigel({"key", b, "--control", "hero:arm_L/fkIkSwitch", "--attr", "fkIk", "--value", "0",
                             "--frame", "12", "--tangent", "step", "-o", out("switch_step.rigel"), "--json"});
  ASSERT_TRUE(exited_with(step, 0)) << step;
  const Json sj = Json::parse(step.out);
  EXPECT_EQ(sj["keys"][0]["outTangents"], Json::array({"auto", "step", "auto"})) << step.out;
  EXPECT_EQ(sj["keys"][0]["inTangents"], Json::array({"auto", "step", "auto"})) << step.out;
  const CliRun out_only = rigel({"key", b, "--control", "hero:arm_L/fkIkSwitch", "--attr", "fkIk", "--frame", "24",
                                 "--out-tangent", "linear", "-o", out("switch_lin.rigel"), "--json"});
  ASSERT_TRUE(exited_with(out_only, 0)) << out_only;
  EXPECT_EQ(Json::parse(out_only.out)["keys"][0]["outTangents"], Json::array({"auto", "linear"})) << out_only.out;
  const CliRun bad_type = rigel({"key", b, "--control", "hero:arm_L/fkIkSwitch", "--attr", "fkIk", "--tangent", "curly",
                                 "-o", out("never_t.rigel")});
  EXPECT_TRUE(exited_with(bad_type, 2)) << bad_type;
  EXPECT_TRUE(contains(bad_type.err, "--tangent 'curly'")) << bad_type;
  EXPECT_FALSE(fs::exists(out("never_t.rigel")));

  // Halfway, the switch blends: the evaluated scene says so.
  const CliRun text = rigel({"keys", b, "--control", "hero:arm_L/fkIkSwitch"});
  ASSERT_TRUE(exited_with(text, 0)) << text;
  EXPECT_TRUE(contains(text.out, ".fkIk: frame 0 = 0, frame 24 = 1")) << text;

  const CliRun del = rigel({"key", b, "--control", "hero:arm_L/fkIkSwitch", "--attr", "fkIk", "--frame", "24",
                            "--delete", "-o", c, "--json"});
  ASSERT_TRUE(exited_with(del, 0)) << del;
  EXPECT_EQ(Json::parse(del.out)["keys"][0]["frames"], Json::array({0.0}));
  const CliRun again = rigel({"key", c, "--control", "hero:arm_L/fkIkSwitch", "--attr", "fkIk", "--frame", "24",
                              "--delete", "-o", out("switch_d.rigel")});
  EXPECT_TRUE(exited_with(again, 1)) << "no key there: " << again;
  EXPECT_TRUE(contains(again.err, "no key at frame 24")) << again;
  EXPECT_FALSE(fs::exists(out("switch_d.rigel")));
}

TEST_F(CliKey, tween_puts_the_switch_between_its_keys) {
  const std::string a = out("tw_a.rigel"), b = out("tw_b.rigel"), c = out("tw_c.rigel");
  ASSERT_TRUE(exited_with(rigel({"key", hero(), "--control", "hero:arm_L/fkIkSwitch", "--attr", "fkIk", "--value", "0",
                                 "--frame", "0", "-o", a}),
                          0));
  ASSERT_TRUE(exited_with(rigel({"key", a, "--control", "hero:arm_L/fkIkSwitch", "--attr", "fkIk", "--value", "1",
                                 "--frame", "20", "-o", b}),
                          0));
  const CliRun t = rigel({"tween", b, "--control", "hero:arm_L/fkIkSwitch", "--attr", "fkIk", "--frame", "5",
                          "--fraction", "0.8", "-o", c, "--json"});
  ASSERT_TRUE(exited_with(t, 0)) << t;
  const Json j = Json::parse(t.out);
  ASSERT_EQ(j["keys"].size(), 1u) << t.out;
  EXPECT_EQ(j["keys"][0]["frames"], Json::array({0.0, 5.0, 20.0}));
  EXPECT_NEAR(j["keys"][0]["values"][1].get<double>(), 0.8, 1e-12);
  const CliRun outside = rigel({"tween", b, "--control", "hero:arm_L/fkIkSwitch", "--attr", "fkIk", "--frame", "30",
                                "-o", out("tw_never.rigel")});
  EXPECT_TRUE(exited_with(outside, 1)) << outside;
  EXPECT_TRUE(contains(outside.err, "no channel has a key both before and after frame 30")) << outside;
  EXPECT_FALSE(fs::exists(out("tw_never.rigel")));
  EXPECT_TRUE(exited_with(rigel({"tween", b, "--control", "hero:arm_L/fkIkSwitch", "--fraction", "x", "-o", c}), 2));
}

TEST_F(CliKey, bad_input_names_the_thing_and_writes_nothing) {
  const std::string o = out("bad.rigel");
  const CliRun unknown = rigel({"key", hero(), "--control", "nobody", "--frame", "1", "-o", o});
  EXPECT_TRUE(exited_with(unknown, 1)) << unknown;
  EXPECT_TRUE(contains(unknown.err, "--control: no node named 'nobody'")) << unknown;
  const CliRun attr = rigel({"key", hero(), "--control", "hero_arm_L_fk1", "--attr", "fkIk", "-o", o});
  EXPECT_TRUE(exited_with(attr, 1)) << attr;
  EXPECT_TRUE(contains(attr.err, "--attr: 'hero_arm_L_fk1' has no keyable channel 'fkIk'")) << attr;
  const CliRun value = rigel({"key", hero(), "--control", "hero_arm_L_fk1", "--attr", "rotate", "--value", "2", "-o", o});
  EXPECT_TRUE(exited_with(value, 1)) << value;
  EXPECT_TRUE(contains(value.err, "--value")) << value;
  const CliRun nan = rigel({"key", hero(), "--control", "hero_arm_L_fk1", "--value", "nan", "-o", o});
  EXPECT_TRUE(exited_with(nan, 2)) << nan;
  const CliRun both = rigel({"key", hero(), "--control", "hero_arm_L_fk1", "--value", "1", "--delete", "-o", o});
  EXPECT_TRUE(exited_with(both, 2)) << both;
  const CliRun far = rigel({"key", hero(), "--control", "hero_arm_L_fk1", "--frame", "1e9", "-o", o});
  EXPECT_TRUE(exited_with(far, 2)) << far;
  EXPECT_FALSE(fs::exists(o)) << "nothing written";
  const CliRun keys = rigel({"keys", hero(), "--control", "nobody"});
  EXPECT_TRUE(exited_with(keys, 1)) << keys;
}

TEST_F(CliKey, move_to_moves_keys_with_their_values_and_tangents) {
  const std::string a = out("move_a.rigel"), b = out("move_b.rigel"), c = out("move_c.rigel");
  ASSERT_TRUE(exited_with(rigel({"key", hero(), "--control", "hero:arm_L/fkIkSwitch", "--attr", "fkIk", "--value", "1",
                                 "--frame", "10", "--tangent", "step", "-o", a}),
                          0));
  ASSERT_TRUE(exited_with(rigel({"key", a, "--control", "hero:arm_L/fkIkSwitch", "--attr", "fkIk", "--value", "0.5",
                                 "--frame", "14", "-o", b}),
                          0));
  const CliRun m = rigel({"key", b, "--control", "hero:arm_L/fkIkSwitch", "--attr", "fkIk", "--frame", "10", "--move-to",
                          "14", "-o", c, "--json"});
  ASSERT_TRUE(exited_with(m, 0)) << m;
  const Json k = Json::parse(m.out)["keys"][0];
  EXPECT_EQ(k["frames"], Json::array({14.0})) << "the key at 14 was replaced by the moved one: " << m.out;
  EXPECT_EQ(k["values"], Json::array({1.0}));
  EXPECT_EQ(k["outTangents"], Json::array({"step"}));
  const CliRun none = rigel({"key", c, "--control", "hero:arm_L/fkIkSwitch", "--attr", "fkIk", "--frame", "3",
                             "--move-to", "5", "-o", out("never_m.rigel")});
  EXPECT_TRUE(exited_with(none, 1)) << none;
  EXPECT_TRUE(contains(none.err, "no channel given has a key at frame 3")) << none;
  EXPECT_FALSE(fs::exists(out("never_m.rigel")));
  EXPECT_EQ(rigel({"key", c, "--control", "hero_arm_L_fk1", "--frame", "3", "--move-to", "5", "--delete", "-o",
                   out("never_m.rigel")})
                .exit_code,
            2);
}

TEST_F(CliKey, set_sets_a_limbs_switch_through_its_control_and_keys_a_keyed_one) {
  const std::string a = out("set_a.rigel"), b = out("set_b.rigel"), c = out("set_c.rigel");
  const CliRun set = rigel({"set", hero(), "--control", "hero_arm_L_ik", "--attr", "fkIk", "--value", "1", "--frame",
                            "6", "-o", a, "--json"});
  ASSERT_TRUE(exited_with(set, 0)) << set;
  const Json j = Json::parse(set.out);
  ASSERT_EQ(j["channels"].size(), 1u) << set.out;
  EXPECT_NE(j["channels"][0].get<std::string>().find("fkIk"), std::string::npos) << "the limb's switch: " << set.out;
  EXPECT_TRUE(j["keys"].empty()) << "free and no --auto-key: set only";
  const CliRun keyed = rigel({"set", a, "--control", "hero_arm_L_ik", "--attr", "fkIk", "--value", "0", "--frame", "2",
                              "--auto-key", "-o", b, "--json"});
  ASSERT_TRUE(exited_with(keyed, 0)) << keyed;
  EXPECT_EQ(Json::parse(keyed.out)["keys"][0]["frames"], Json::array({2.0}));
  // Keyed now: a value at another frame is a key there, even without --auto-key.
  const CliRun again = rigel({"set", b, "--control", "hero:arm_L/fkIkSwitch", "--attr", "fkIk", "--value", "1",
                              "--frame", "8", "-o", c, "--json"});
  ASSERT_TRUE(exited_with(again, 0)) << again;
  const Json k = Json::parse(again.out)["keys"][0];
  EXPECT_EQ(k["frames"], Json::array({2.0, 8.0}));
  EXPECT_EQ(k["values"], Json::array({0.0, 1.0}));
  const CliRun bad = rigel({"set", c, "--control", "hero_arm_L_fk1", "--attr", "rotate", "--value", "1", "-o",
                            out("never_s.rigel")});
  EXPECT_TRUE(exited_with(bad, 1)) << bad;
  EXPECT_TRUE(contains(bad.err, "--attr")) << bad;
  EXPECT_FALSE(fs::exists(out("never_s.rigel")));
}

}  // namespace
}  // namespace rigel::cli::testing
