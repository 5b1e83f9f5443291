// `rigel shape`, `rigel align`, `rigel locator`, `rigel mirror-joints` and
// `rigel driven-key` on the biped (examples/biped.rig.xml on Rigify's human
// metarig): a shape shown, pasted from a control and from the JSON it
// printed, mirrored onto the other side; a locator made and an IK control
// matched onto it; joints mirrored; driven poses keyed, listed, exported
// and imported onto a rebuilt rig byte for byte; bad input refused with the
// option named and nothing written.
#include <filesystem>

#include "cli_test_util.h"

namespace rigel::cli::testing {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

class CliRigging : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string example = (fs::path(RIGEL_SOURCE_DIR) / "examples/biped.rig.xml").string();
    const CliRun b = rigel({"build", example, "-o", out("a.rigel")});
    ASSERT_TRUE(exited_with(b, 0)) << b;
  }
  std::string out(const std::string& name) { return (dir_.path() / name).string(); }
  Json shape(const std::string& scene, const std::string& control) {
    const CliRun r = rigel({"shape", scene, "--control", control, "--json"});
    EXPECT_TRUE(exited_with(r, 0)) << r;
    return Json::parse(r.out)["controls"][0]["shape"];
  }
  TempDir dir_;
};

TEST_F(CliRigging, shapes_pasted_from_a_control_and_a_file_and_mirrored_to_the_other_side) {
  const Json arm = shape(out("a.rigel"), "hero_arm_L_ik");
  const Json leg = shape(out("a.rigel"), "hero_leg_L_ik");
  ASSERT_NE(arm["points"], leg["points"]);
  CliRun r = rigel({"shape", out("a.rigel"), "--control", "hero_leg_L_ik", "--like", "hero:arm_L/ik", "--shape-only", "-o", out("b.rigel")});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  EXPECT_EQ(shape(out("b.rigel"), "hero_leg_L_ik")["points"], arm["points"]);
  EXPECT_EQ(shape(out("b.rigel"), "hero_leg_L_ik")["color"], leg["color"]);
  // The JSON the command printed, pasted back from a file.
  r = rigel({"shape", out("a.rigel"), "--control", "hero_leg_L_ik", "--json"});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  io::testing::write_text(dir_.path() / "leg.json", r.out);
  r = rigel({"shape", out("b.rigel"), "--control", "hero_leg_L_ik", "--from", out("leg.json"), "-o", out("c.rigel")});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  EXPECT_EQ(shape(out("c.rigel"), "hero_leg_L_ik"), leg);
  r = rigel({"shape", out("a.rigel"), "--control", "hero_arm_L_ik", "--mirror", "-o", out("d.rigel")});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  EXPECT_EQ(shape(out("d.rigel"), "hero_arm_L_ik")["points"][0][0].get<double>(), -arm["points"][0][0].get<double>());
  r = rigel({"shape", out("a.rigel"), "--control", "hero_arm_L_pole", "--to-opposite", "-o", out("e.rigel"), "--json"});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  EXPECT_EQ(Json::parse(r.out)["pairs"][0]["to"], "hero_arm_R_pole");
  for (const std::vector<std::string>& bad :
       {std::vector<std::string>{"shape", out("a.rigel"), "--control", "hero_hip_main", "--to-opposite", "-o", out("x.rigel")},
        std::vector<std::string>{"shape", out("a.rigel"), "--control", "hand.L", "--mirror", "-o", out("x.rigel")},
        std::vector<std::string>{"shape", out("a.rigel"), "--control", "hero_arm_L_ik", "--like", "nobody", "-o", out("x.rigel")},
        std::vector<std::string>{"shape", out("a.rigel"), "--control", "hero_arm_L_ik", "--from", out("none.json"), "-o", out("x.rigel")},
        std::vector<std::string>{"shape", out("a.rigel"), "--control", "hero_arm_L_ik", "--mirror"},
        std::vector<std::string>{"shape", out("a.rigel"), "--control", "hero_arm_L_ik", "--mirror", "--flip", "-o", out("x.rigel")}}) {
    const CliRun b = rigel(bad);
    EXPECT_FALSE(exited_with(b, 0)) << b;
    EXPECT_FALSE(b.err.empty()) << b;
    EXPECT_FALSE(fs::exists(out("x.rigel"))) << b;
  }
}

TEST_F(CliRigging, a_locator_and_an_ik_control_matched_onto_it_and_joints_mirrored) {
  CliRun r = rigel({"locator", out("a.rigel"), "--at", "hand.L", "--size", "0.05", "-o", out("b.rigel"), "--json"});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  EXPECT_EQ(Json::parse(r.out)["locators"], Json::array({"hand.L_loc"}));
  r = rigel({"align", out("b.rigel"), "--node", "hero_arm_R_ik", "--to", "hand.L_loc", "--position", "-o", out("c.rigel"), "--json"});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  EXPECT_EQ(Json::parse(r.out)["moved"], Json::array({"hero_arm_R_ik"}));
  r = rigel({"eval", out("c.rigel"), "--json"});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  const Json nodes = Json::parse(r.out)["nodes"];
  for (int i = 0; i < 3; ++i)
    EXPECT_NEAR(nodes["hero_arm_R_ik"]["t"][i].get<double>(), nodes["hand.L_loc"]["t"][i].get<double>(), 1e-9);
  r = rigel({"mirror-joints", out("a.rigel"), "--joint", "spine", "-o", out("x.rigel")});
  EXPECT_FALSE(exited_with(r, 0)) << r;
  EXPECT_NE(r.err.find("--joint"), std::string::npos) << r;
  EXPECT_NE(r.err.find("names no side"), std::string::npos) << r;
  r = rigel({"locator", out("a.rigel"), "--at", "nobody", "-o", out("x.rigel")});
  EXPECT_FALSE(exited_with(r, 0)) << r;
  EXPECT_NE(r.err.find("--at"), std::string::npos) << r;
  r = rigel({"align", out("a.rigel"), "--node", "hero_arm_R_ik", "--to", "hero_arm_R_ik", "-o", out("x.rigel")});
  EXPECT_FALSE(exited_with(r, 0)) << r;
  EXPECT_FALSE(fs::exists(out("x.rigel")));
}

TEST_F(CliRigging, a_bare_skeleton_s_arm_mirrored_onto_the_other_side) {
  const std::string metarig = (fs::path(RIGEL_SOURCE_DIR) / "tests/data/gltf/rigify_human_metarig.glb").string();
  CliRun r = rigel({"import", metarig, "-o", out("bare.rigel")});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  r = rigel({"mirror-joints", out("bare.rigel"), "--joint", "upper_arm.L", "-o", out("x.rigel")});
  EXPECT_FALSE(exited_with(r, 0)) << r;
  EXPECT_NE(r.err.find("upper_arm.R"), std::string::npos) << r;
  r = rigel({"mirror-joints", out("bare.rigel"), "--joint", "upper_arm.L", "--update", "-o", out("m.rigel"), "--json"});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  const Json j = Json::parse(r.out);
  EXPECT_TRUE(j["created"].empty());
  EXPECT_EQ(j["updated"][0], "upper_arm.R");
}

TEST_F(CliRigging, driven_poses_keyed_listed_exported_and_imported_onto_a_rebuilt_rig) {
  CliRun r = rigel({"driven-key", out("a.rigel"), "--driver", "hero_arm_L_fk0.rotateX", "--at", "0", "--set",
                    "hero_arm_L_fk1.rotateZ=0", "--set", "hero_arm_R_fk1.rotateZ", "-o", out("p.rigel"), "--json"});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  EXPECT_EQ(Json::parse(r.out)["created"], 2);
  r = rigel({"driven-key", out("p.rigel"), "--driver", "hero_arm_L_fk0.rotateX", "--at", "90", "--set", "hero_arm_L_fk1.rotateZ=-45",
             "--set", "hero_arm_R_fk1.rotateZ=30", "--tangent", "linear", "-o", out("p.rigel")});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  r = rigel({"driven-key", out("p.rigel"), "--list", "--json"});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  const Json listed = Json::parse(r.out);
  ASSERT_EQ(listed["drivenPoses"]["drivers"].size(), 1u);
  EXPECT_EQ(listed["drivenPoses"]["drivers"][0]["curves"][0]["at"], Json::array({0, 90}));
  EXPECT_EQ(listed["drivenPoses"]["drivers"][0]["curves"][0]["values"], Json::array({0, -45}));
  EXPECT_TRUE(listed["correctives"]["drivers"].empty());
  // Exported, imported onto a rig built again: the same file.
  r = rigel({"data", "export", "driven_poses", out("p.rigel"), "-o", out("hero.drivenposes.json")});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  const std::string file = io::testing::read_text(out("hero.drivenposes.json"));
  EXPECT_NE(file.find("\"driven\": \"hero_arm_R_fk1.rotateZ\""), std::string::npos);
  const std::string example = (fs::path(RIGEL_SOURCE_DIR) / "examples/biped.rig.xml").string();
  ASSERT_TRUE(exited_with(rigel({"build", example, "-o", out("fresh.rigel")}), 0));
  r = rigel({"data", "import", "driven_poses", out("fresh.rigel"), out("hero.drivenposes.json"), "-o", out("fresh2.rigel"), "--json"});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  EXPECT_EQ(Json::parse(r.out)["curves"], 2);
  r = rigel({"data", "export", "driven_poses", out("fresh2.rigel"), "-o", out("again.json")});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  EXPECT_EQ(io::testing::read_text(out("again.json")), file) << "export after import: the same bytes";
  // Removed: the channel keeps its value.
  r = rigel({"driven-key", out("p.rigel"), "--remove", "hero_arm_R_fk1.rotateZ", "-o", out("r.rigel")});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  r = rigel({"driven-key", out("r.rigel"), "--list", "--json"});
  EXPECT_EQ(Json::parse(r.out)["drivenPoses"]["drivers"][0]["curves"].size(), 1u);

  // Bad input: usage errors exit 2, refused edits 1, nothing written.
  for (const std::vector<std::string>& usage :
       {std::vector<std::string>{"driven-key", out("a.rigel"), "--set", "hero_arm_L_fk1.rotateZ=1", "-o", out("x.rigel")},
        std::vector<std::string>{"driven-key", out("a.rigel"), "--driver", "hero_arm_L_fk0.rotateX", "--set", "hero_arm_L_fk1.rotateZ=abc", "-o", out("x.rigel")},
        std::vector<std::string>{"driven-key", out("a.rigel"), "--driver", "hero_arm_L_fk0.rotateX", "--set", "hero_arm_L_fk1.rotateZ=1"},
        std::vector<std::string>{"driven-key", out("a.rigel"), "--list", "--remove", "hero_arm_L_fk1.rotateZ"},
        std::vector<std::string>{"driven-key", out("a.rigel"), "--driver", "hero_arm_L_fk0.rotateX", "--set", "hero_arm_L_fk1.rotateZ=1", "--tangent", "wobbly", "-o", out("x.rigel")}}) {
    const CliRun b = rigel(usage);
    EXPECT_TRUE(exited_with(b, 2)) << b;
  }
  for (const std::vector<std::string>& refused :
       {std::vector<std::string>{"driven-key", out("a.rigel"), "--driver", "nobody.rotateX", "--set", "hero_arm_L_fk1.rotateZ=1", "-o", out("x.rigel")},
        std::vector<std::string>{"driven-key", out("a.rigel"), "--driver", "hero_arm_L_fk0.rotateX", "--set", "forearm.L.translateX=1", "-o", out("x.rigel")},
        std::vector<std::string>{"driven-key", out("a.rigel"), "--remove", "hero_arm_L_fk1.rotateZ", "-o", out("x.rigel")},
        std::vector<std::string>{"data", "import", "correctives", out("a.rigel"), out("hero.drivenposes.json"), "-o", out("x.rigel")}}) {
    const CliRun b = rigel(refused);
    EXPECT_TRUE(exited_with(b, 1)) << b;
    EXPECT_FALSE(b.err.empty());
  }
  EXPECT_FALSE(fs::exists(out("x.rigel")));
}

}  // namespace
}  // namespace rigel::cli::testing
