// `rigel poses save|apply|list|remove`: a pose saved from one built biped
// (examples/biped.rig.xml on Rigify's human metarig) applies to a second
// one, which then saves the same pose; mirrored, blended and keyed applies;
// list and remove; bad input refused with the option named and nothing
// written.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <cmath>

#include "cli_test_util.h"

namespace rigel::cli::testing {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

std::string text_of(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream b;
  b << in.rdbuf();
  return b.str();
}

class CliPoses : public ::testing::Test {
 protected:
  // Two bipeds; the first posed (an FK arm turned, a leg's IK moved, the
  // arm's switch keyed half way).
  static void SetUpTestSuite() {
    dir_ = new TempDir();
    const std::string example = (fs::path(RIGEL_SOURCE_DIR) / "examples/biped.rig.xml").string();
    runs_ = new std::vector<CliRun>{
        rigel({"build", example, "-o", out("a.rigel")}),
        rigel({"build", example, "-o", out("b.rigel")}),
        rigel({"pose", out("a.rigel"), "--control", "hero_arm_L_fk0", "--mode", "forward", "--rotate", "0,25,10", "-o", out("p1.rigel")}),
        rigel({"pose", out("p1.rigel"), "--control", "hero_leg_L_ik", "--mode", "forward", "--translate", "0.05,0.1,0", "-o", out("p2.rigel")}),
        rigel({"key", out("p2.rigel"), "--control", "hero:arm_L/fkIkSwitch", "--attr", "fkIk", "--value", "0.5", "-o",
               posed()}),
    };
  }
  static void TearDownTestSuite() {
    delete runs_;
    delete dir_;
  }
  void SetUp() override {
    for (const CliRun& r : *runs_) ASSERT_TRUE(exited_with(r, 0)) << r;
  }
  static std::string posed() { return out("posed.rigel"); }
  static std::string out(const std::string& name) { return (dir_->path() / name).string(); }
  static std::string library() { return out("poses"); }

  static TempDir* dir_;
  static std::vector<CliRun>* runs_;
};
TempDir* CliPoses::dir_ = nullptr;
std::vector<CliRun>* CliPoses::runs_ = nullptr;

// The pose file's entries (the part that depends on the scene's values).
Json entries_of(const fs::path& file) { return Json::parse(text_of(file))["entries"]; }

// Equal JSON, numbers within 1e-12 (an Euler channel's rotation goes
// through a quaternion and back).
bool near(const Json& a, const Json& b) {
  if (a.is_number() && b.is_number()) return std::abs(a.get<double>() - b.get<double>()) <= 1e-12;
  if (a.type() != b.type() || a.size() != b.size()) return false;
  if (a.is_array()) {
    for (std::size_t i = 0; i < a.size(); ++i)
      if (!near(a[i], b[i])) return false;
    return true;
  }
  if (a.is_object()) {
    for (auto it = a.begin(); it != a.end(); ++it)
      if (!b.contains(it.key()) || !near(it.value(), b[it.key()])) return false;
    return true;
  }
  return a == b;
}

TEST_F(CliPoses, a_pose_saved_on_one_biped_applies_to_another) {
  const CliRun s = rigel({"poses", "save", library(), posed(), "--rig", "hero", "--name", "wave", "--json"});
  ASSERT_TRUE(exited_with(s, 0)) << s;
  EXPECT_TRUE(fs::exists(fs::path(library()) / "wave.pose.json"));
  EXPECT_GT(Json::parse(s.out)["entries"].get<int>(), 50) << s.out;
  const CliRun a = rigel({"poses", "apply", library(), out("b.rigel"), "--name", "wave", "-o", out("b_wave.rigel"), "--json"});
  ASSERT_TRUE(exited_with(a, 0)) << a;
  const Json j = Json::parse(a.out);
  EXPECT_GT(j["set"].size(), 50u) << a.out;
  // The second biped now holds the first one's pose: saved again, the same entries.
  const CliRun again = rigel({"poses", "save", library(), out("b_wave.rigel"), "--name", "copy"});
  ASSERT_TRUE(exited_with(again, 0)) << again;
  const Json first = entries_of(fs::path(library()) / "wave.pose.json"), second = entries_of(fs::path(library()) / "copy.pose.json");
  ASSERT_EQ(first.size(), second.size());
  for (std::size_t i = 0; i < first.size(); ++i)
    ASSERT_TRUE(near(first[i], second[i])) << "entry " << i << ": " << first[i] << " vs " << second[i];
  bool posed_arm = false;
  for (const Json& e : first)
    if (e["node"] == "hero_arm_L_fk0") posed_arm = e["channels"]["rotation"][3].get<double>() < 0.99;
  EXPECT_TRUE(posed_arm) << "the turned arm is in the pose";

  const CliRun list = rigel({"poses", "list", library(), "--json"});
  ASSERT_TRUE(exited_with(list, 0)) << list;
  const Json l = Json::parse(list.out);
  ASSERT_EQ(l["poses"].size(), 2u) << list.out;
  EXPECT_EQ(l["poses"][0]["name"], "copy");
  EXPECT_EQ(l["poses"][1]["name"], "wave");
  EXPECT_EQ(l["poses"][1]["rig"], "hero");
  const CliRun rm = rigel({"poses", "remove", library(), "--name", "copy"});
  ASSERT_TRUE(exited_with(rm, 0)) << rm;
  EXPECT_FALSE(fs::exists(fs::path(library()) / "copy.pose.json"));
  const CliRun plain = rigel({"poses", "list", library()});
  ASSERT_TRUE(exited_with(plain, 0)) << plain;
  EXPECT_TRUE(contains(plain.out, "wave\thero\t")) << plain.out;
  EXPECT_FALSE(contains(plain.out, "copy")) << plain.out;
}

TEST_F(CliPoses, mirrored_blended_and_keyed_on_a_selection) {
  const std::string lib = out("lib2");
  ASSERT_TRUE(exited_with(rigel({"poses", "save", lib, posed(), "--name", "arm", "--controls", "hero:arm_L/fk[0],hero:arm_L/fkIkSwitch"}), 0));
  const CliRun a = rigel({"poses", "apply", lib, out("b.rigel"), "--name", "arm", "--mirror", "--fraction", "0.5", "--frame",
                          "3", "--key", "-o", out("b_arm.rigel"), "--json"});
  ASSERT_TRUE(exited_with(a, 0)) << a;
  const Json j = Json::parse(a.out);
  EXPECT_EQ(j["set"], Json::array({"hero_arm_R_fk0", "hero_arm_R_fkIkSwitch"})) << a.out;
  EXPECT_EQ(j["keyed"], j["channels"]);
  const CliRun keys = rigel({"keys", out("b_arm.rigel"), "--control", "hero:arm_R/fkIkSwitch", "--json"});
  ASSERT_TRUE(exited_with(keys, 0)) << keys;
  EXPECT_TRUE(contains(keys.out, "\"values\":[0.25]")) << "half way from 0 (FK, as built) to 0.5: " << keys.out;
  // A selection the mirrored pose does not set.
  const CliRun miss = rigel({"poses", "apply", lib, out("b.rigel"), "--name", "arm", "--mirror", "--controls",
                             "hero:arm_L/fk[0]", "-o", out("miss.rigel")});
  EXPECT_TRUE(exited_with(miss, 1)) << miss;
  EXPECT_TRUE(contains(miss.err, "--controls")) << miss.err;
  EXPECT_TRUE(contains(miss.err, "hero_arm_L_fk0")) << miss.err;
  EXPECT_FALSE(fs::exists(out("miss.rigel")));
}

TEST_F(CliPoses, bad_input_is_refused_naming_it_and_nothing_is_written) {
  const std::string lib = out("lib3");
  ASSERT_TRUE(exited_with(rigel({"poses", "save", lib, posed(), "--name", "wave"}), 0));
  // A pose of another rig: the same names, another rigId.
  const fs::path other_def = dir_->path() / "other.rig.xml";
  std::ofstream(other_def) << "<rig name=\"hero\" version=\"1.0\">\n  <geo file=\""
                           << (fs::path(RIGEL_SOURCE_DIR) / "tests/data/gltf/rigify_human_metarig.glb").string()
                           << "\"/>\n"
                              R"(  <component type="global" name="global" side="C" version="1.0" rigId="1513270e-269e-4d37-b2a7-4de452e6b438">
    <guide name="main"/>
  </component>
</rig>)";
  ASSERT_TRUE(exited_with(rigel({"build", other_def.string(), "-o", out("other.rigel")}), 0));
  const CliRun other = rigel({"poses", "apply", lib, out("other.rigel"), "--name", "wave", "-o", out("x.rigel")});
  EXPECT_TRUE(exited_with(other, 1)) << other;
  EXPECT_TRUE(contains(other.err, "--rig")) << other.err;
  EXPECT_TRUE(contains(other.err, "6513270e-269e-4d37-b2a7-4de452e6b438")) << other.err;
  EXPECT_TRUE(contains(other.err, "main")) << "the role: " << other.err;
  // Unknown pose, unsafe name, unknown control, bad fraction.
  const CliRun unknown = rigel({"poses", "apply", lib, out("b.rigel"), "--name", "nope", "-o", out("x.rigel")});
  EXPECT_TRUE(exited_with(unknown, 1)) << unknown;
  EXPECT_TRUE(contains(unknown.err, "--name")) << unknown.err;
  EXPECT_TRUE(contains(unknown.err, "'nope'")) << unknown.err;
  const CliRun unsafe = rigel({"poses", "save", lib, posed(), "--name", "../escape"});
  EXPECT_TRUE(exited_with(unsafe, 1)) << unsafe;
  EXPECT_TRUE(contains(unsafe.err, "--name")) << unsafe.err;
  EXPECT_FALSE(fs::exists(dir_->path() / "escape.pose.json"));
  const CliRun control = rigel({"poses", "apply", lib, out("b.rigel"), "--name", "wave", "--controls", "banana", "-o", out("x.rigel")});
  EXPECT_TRUE(exited_with(control, 1)) << control;
  EXPECT_TRUE(contains(control.err, "'banana'")) << control.err;
  EXPECT_TRUE(exited_with(rigel({"poses", "apply", lib, out("b.rigel"), "--name", "wave", "--fraction", "2", "-o", out("x.rigel")}), 2));
  EXPECT_FALSE(fs::exists(out("x.rigel")));
  // A malformed file names itself and the place; remove and list of what is not there.
  std::ofstream(fs::path(lib) / "broken.pose.json") << "{\n  \"format\": \"rigel pose\",\n  oops\n}\n";
  const CliRun broken = rigel({"poses", "apply", lib, out("b.rigel"), "--name", "broken", "-o", out("x.rigel")});
  EXPECT_TRUE(exited_with(broken, 1)) << broken;
  EXPECT_TRUE(contains(broken.err, "broken.pose.json:3:")) << broken.err;
  EXPECT_TRUE(exited_with(rigel({"poses", "remove", lib, "--name", "nope"}), 1));
  const CliRun missing = rigel({"poses", "list", out("no_such_library")});
  EXPECT_TRUE(exited_with(missing, 1)) << missing;
  EXPECT_TRUE(contains(missing.err, "no_such_library")) << missing.err;
  EXPECT_FALSE(fs::exists(out("x.rigel")));
}

}  // namespace
}  // namespace rigel::cli::testing
