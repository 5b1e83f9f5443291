// Keys set with `rigel key` on a built rig's controls (the biped of
// examples/biped.rig.xml on Rigify's metarig) survive what a rig goes
// through: a save and a load, `rigel update` rebuilding the keyed
// component with `--keep-keys local` and with `--keep-keys world`, and an
// update to a definition without an unrelated component; and `rigel
// transfer` copies them onto the other arm.
#include <filesystem>
#include <fstream>
#include <string>

#include "cli_test_util.h"

namespace rigel::cli::testing {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

class CliBuiltKeys : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir();
    const std::string example = (fs::path(RIGEL_SOURCE_DIR) / "examples/biped.rig.xml").string();
    ok_ = exited_with(rigel({"build", example, "-o", out("hero.rigel")}), 0);
    // The left arm keyed: fk1 turned at frames 0 and 10, the switch 0 then 1.
    ok_ = ok_ && exited_with(rigel({"pose", out("hero.rigel"), "--control", "hero_arm_L_fk1", "--mode", "forward",
                                    "--rotate", "0,25,10", "--frame", "10", "-o", out("posed.rigel")}),
                             0);
    ok_ = ok_ && exited_with(rigel({"key", out("posed.rigel"), "--control", "hero_arm_L_fk1", "--attr", "rotate",
                                    "--frame", "10", "-o", out("k1.rigel")}),
                             0);
    ok_ = ok_ && exited_with(rigel({"key", out("k1.rigel"), "--control", "hero_arm_L_fk1", "--attr", "rotate", "--frame",
                                    "0", "-o", out("k2.rigel")}),
                             0);
    ok_ = ok_ && exited_with(rigel({"key", out("k2.rigel"), "--control", "hero:arm_L/fkIkSwitch", "--attr", "fkIk",
                                    "--value", "0", "--frame", "0", "-o", out("k3.rigel")}),
                             0);
    ok_ = ok_ && exited_with(rigel({"key", out("k3.rigel"), "--control", "hero:arm_L/fkIkSwitch", "--attr", "fkIk",
                                    "--value", "1", "--frame", "24", "--tangent", "step", "-o", out("keyed.rigel")}),
                             0);
  }
  static void TearDownTestSuite() { delete dir_; }
  void SetUp() override { ASSERT_TRUE(ok_) << "building and keying the biped failed"; }
  static std::string out(const std::string& name) { return (dir_->path() / name).string(); }

  // `rigel keys` of the keyed nodes, by address (names may change).
  static Json keys(const std::string& scene) {
    Json all = Json::object();
    for (const char* node : {"hero:arm_L/fk[1]", "hero:arm_L/fkIkSwitch"}) {
      const CliRun k = rigel({"keys", scene, "--control", node, "--json"});
      EXPECT_TRUE(exited_with(k, 0)) << k;
      if (k.exit_code == 0) all[node] = Json::parse(k.out)["channels"];
    }
    return all;
  }
  // A definition beside the scenes: the example with `edit` applied.
  static std::string definition(const std::string& name, const std::string& from, const std::string& to) {
    std::string text = read_text(fs::path(RIGEL_SOURCE_DIR) / "examples/biped.rig.xml");
    text.replace(text.find("<rig name=\"hero\" version=\"1.0\">"), 31, "<rig name=\"hero\" version=\"1.1\">");
    const std::size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
    const std::string path = out(name);
    std::ofstream(path) << text;
    return path;
  }

  static TempDir* dir_;
  static bool ok_;
};
TempDir* CliBuiltKeys::dir_ = nullptr;
bool CliBuiltKeys::ok_ = false;

// Every plug's frames and values equal within `tolerance`.
void expect_same_keys(const Json& a, const Json& b, double tolerance, const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (const auto& [node, channels] : a.items()) {
    ASSERT_EQ(channels.size(), b[node].size()) << what << ": " << node;
    for (std::size_t i = 0; i < channels.size(); ++i) {
      const Json& x = channels[i];
      const Json& y = b[node][i];
      EXPECT_EQ(x["frames"], y["frames"]) << what << ": " << x["plug"];
      ASSERT_EQ(x["values"].size(), y["values"].size()) << what;
      for (std::size_t k = 0; k < x["values"].size(); ++k)
        EXPECT_NEAR(x["values"][k].get<double>(), y["values"][k].get<double>(), tolerance) << what << ": " << x["plug"];
      EXPECT_EQ(x.value("outTangents", Json()), y.value("outTangents", Json())) << what << ": " << x["plug"];
    }
  }
}

TEST_F(CliBuiltKeys, keys_survive_save_and_load) {
  const Json before = keys(out("keyed.rigel"));
  ASSERT_EQ(before["hero:arm_L/fk[1]"].size(), 3u) << before.dump() << ": rotateX, Y and Z";
  EXPECT_EQ(before["hero:arm_L/fk[1]"][1]["frames"], Json::array({0.0, 10.0}));
  EXPECT_NE(before["hero:arm_L/fk[1]"][1]["values"][1].get<double>(), 0.0) << "the posed turn is keyed";
  // A command that loads and saves without changing the keys.
  ASSERT_TRUE(exited_with(rigel({"key", out("keyed.rigel"), "--control", "hero_global_main", "--attr", "translate",
                                 "--frame", "5", "-o", out("resaved.rigel")}),
                          0));
  expect_same_keys(before, keys(out("resaved.rigel")), 0, "saved and loaded");
}

TEST_F(CliBuiltKeys, keys_survive_an_update_rebuilding_the_arm_local_and_world) {
  const Json before = keys(out("keyed.rigel"));
  const std::string v2 = definition("arm_v2.rig.xml", "name=\"arm\" side=\"L\" version=\"1.0\"",
                                    "name=\"arm\" side=\"L\" version=\"1.1\"");
  for (const char* keep : {"local", "world"}) {
    const std::string updated = out(std::string("updated_") + keep + ".rigel");
    const CliRun u = rigel({"update", out("keyed.rigel"), "--rig", "hero", "--definition", v2, "--keep-keys", keep,
                            "-o", updated, "--json"});
    ASSERT_TRUE(exited_with(u, 0)) << u;
    const Json rebuilt = Json::parse(u.out)["rigs"][0]["rebuilt"];
    EXPECT_EQ(rebuilt[0], "arm_L") << u.out;
    // World keys are rewritten from the controls' sampled world matrices
    // (the same build puts them back to rounding).
    expect_same_keys(before, keys(updated), std::string(keep) == "local" ? 0 : 1e-6, std::string("--keep-keys ") + keep);
  }
}

TEST_F(CliBuiltKeys, keys_survive_an_update_that_removes_an_unrelated_component) {
  const Json before = keys(out("keyed.rigel"));
  std::string text = read_text(fs::path(RIGEL_SOURCE_DIR) / "examples/biped.rig.xml");
  const std::size_t begin = text.find("<component type=\"tail\" name=\"ear\" side=\"R\"");
  ASSERT_NE(begin, std::string::npos);
  const std::size_t end = text.find("</component>", begin) + std::string("</component>").size();
  text.erase(begin, end - begin);
  text.replace(text.find("<rig name=\"hero\" version=\"1.0\">"), 31, "<rig name=\"hero\" version=\"1.1\">");
  const std::string v2 = out("no_ear.rig.xml");
  std::ofstream(v2) << text;
  const CliRun u = rigel({"update", out("keyed.rigel"), "--rig", "hero", "--definition", v2, "-o", out("no_ear.rigel")});
  ASSERT_TRUE(exited_with(u, 0)) << u;
  const CliRun gone = rigel({"address", out("no_ear.rigel"), "hero:ear_R"});
  EXPECT_EQ(gone.exit_code, 1) << "the right ear is gone: " << gone;
  expect_same_keys(before, keys(out("no_ear.rigel")), 0, "an unrelated component removed");
}

TEST_F(CliBuiltKeys, transfer_copies_the_left_arms_keys_onto_the_right_with_an_offset) {
  const CliRun t = rigel({"transfer", out("keyed.rigel"), "--from", "hero:arm_L", "--to", "hero:arm_R", "--offset", "30",
                          "-o", out("transferred.rigel"), "--json"});
  ASSERT_TRUE(exited_with(t, 0)) << t;
  const Json j = Json::parse(t.out);
  EXPECT_EQ(j["channels"], 4) << t.out;  // fk1's rotate X, Y, Z and the switch
  EXPECT_EQ(j["keys"], 8) << t.out;
  EXPECT_EQ(j["frames"], Json::array({0.0, 24.0}));
  const CliRun k = rigel({"keys", out("transferred.rigel"), "--control", "hero:arm_R/fkIkSwitch", "--json"});
  ASSERT_TRUE(exited_with(k, 0)) << k;
  const Json sw = Json::parse(k.out)["channels"][0];
  EXPECT_EQ(sw["frames"], Json::array({30.0, 54.0}));
  EXPECT_EQ(sw["values"], Json::array({0.0, 1.0}));
  EXPECT_EQ(sw["outTangents"], Json::array({"auto", "step"})) << "tangent types travel";

  // Only the frames asked for: 10:24 with offset 20 replaces the
  // destination range 30..44 (30's key goes, 24's lands at 44); 54 is kept.
  const CliRun again = rigel({"transfer", out("transferred.rigel"), "--from", "hero:arm_L", "--to", "hero:arm_R",
                              "--frames", "10:24", "--offset", "20", "-o", out("again.rigel")});
  ASSERT_TRUE(exited_with(again, 0)) << again;
  const Json sw2 = Json::parse(rigel({"keys", out("again.rigel"), "--control", "hero:arm_R/fkIkSwitch", "--json"}).out)["channels"][0];
  EXPECT_EQ(sw2["frames"], Json::array({44.0, 54.0})) << sw2;
}

TEST_F(CliBuiltKeys, transfer_refuses_bad_input_and_writes_nothing) {
  struct Case {
    std::vector<std::string> args;
    int code;
    std::string says;
  };
  const std::string never = out("never.rigel");
  for (const Case& c : std::vector<Case>{
           {{"--from", "hero:arm_L", "--to", "hero:hand_L"}, 1, "--to"},
           {{"--from", "villain:arm_L", "--to", "hero:arm_R"}, 1, "--from"},
           {{"--from", "hero:wing_L", "--to", "hero:arm_R"}, 1, "no component 'wing_L'"},
           {{"--from", "hero:arm_L", "--to", "hero:"}, 1, "a component for a component"},
           {{"--from", "hero:arm_L", "--to", "hero:arm_R", "--frames", "10:0"}, 1, "--frames"},
           {{"--from", "hero:arm_L", "--to", "hero:arm_R", "--frames", "ten"}, 2, "--frames"},
       }) {
    std::vector<std::string> args{"transfer", out("keyed.rigel")};
    args.insert(args.end(), c.args.begin(), c.args.end());
    args.insert(args.end(), {"-o", never});
    const CliRun r = rigel(args);
    EXPECT_TRUE(exited_with(r, c.code)) << r;
    EXPECT_TRUE(contains(r.err, c.says)) << r;
    EXPECT_FALSE(fs::exists(never)) << r;
  }
}

}  // namespace
}  // namespace rigel::cli::testing
