// `rigel check` and `rigel check record` (rig regression tests,
// tools/rig_tests.h): every shipped example rig holds its recorded poses;
// a deliberate change to one component's parameter fails naming the poses
// and joints; a shot's rig is recorded and checked at frames as it plays;
// bad input is refused with the option named and nothing written.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_test_util.h"

namespace rigel::cli {
namespace {

using namespace rigel::cli::testing;  // NOLINT: the CLI runner
using Json = nlohmann::ordered_json;
namespace fs = std::filesystem;

const fs::path kExamples = fs::path(RIGEL_SOURCE_DIR) / "examples";
const std::string kMetarig = (fs::path(RIGEL_SOURCE_DIR) / "tests/data/gltf/rigify_human_metarig.glb").string();

std::string read(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(CliCheck, every_example_rig_holds_its_recorded_poses) {
  int checked = 0;
  for (const auto& entry : fs::directory_iterator(kExamples)) {
    const std::string name = entry.path().filename().string();
    if (!name.ends_with(".rig.xml") && !name.ends_with(".rig.json")) continue;
    const fs::path tests = kExamples / (name.substr(0, name.size() - 8) + ".rigtest.json");
    ASSERT_TRUE(fs::exists(tests)) << name << " has no regression poses (rigel check record " << name << ")";
    const CliRun run = rigel({"check", entry.path().string(), "--json"});
    ASSERT_TRUE(exited_with(run, 0)) << run;
    const Json report = Json::parse(run.out);
    EXPECT_EQ(report["ok"], true) << run;
    EXPECT_GT(report["poses"].get<int>(), 1) << name;
    EXPECT_LT(report["maxError"].get<double>(), 1e-9) << name;
    ++checked;
  }
  EXPECT_GE(checked, 2);
}

TEST(CliCheck, the_biped_converted_to_a_build_graph_holds_the_definitions_poses) {
  TempDir dir;
  const fs::path graph = dir.path() / "biped.build.json";
  ASSERT_TRUE(exited_with(rigel({"graph", "convert", (kExamples / "biped.rig.xml").string(), "-o", graph.string()}), 0));
  const CliRun run = rigel({"check", graph.string(), "--tests", (kExamples / "biped.rigtest.json").string(), "--json"});
  ASSERT_TRUE(exited_with(run, 0)) << run;
  EXPECT_LT(Json::parse(run.out)["maxError"].get<double>(), 1e-9) << run;
}

TEST(CliCheck, a_changed_parameter_fails_naming_the_poses_and_joints) {
  TempDir dir;
  // The biped with its eyes' aim distance changed, checked against the
  // biped's poses (its character found from the tests file).
  std::string text = read(kExamples / "biped.rig.xml");
  const std::string from = R"(<param name="aimDistance" value="0.4"/>)";
  ASSERT_NE(text.find(from), std::string::npos);
  text.replace(text.find(from), from.size(), R"(<param name="aimDistance" value="0.6"/>)");
  const fs::path changed = dir.path() / "changed.rig.xml";
  std::ofstream(changed, std::ios::binary) << text;
  const std::string tests = (kExamples / "biped.rigtest.json").string();
  const CliRun run = rigel({"check", changed.string(), "--tests", tests, "--json"});
  EXPECT_TRUE(exited_with(run, 1)) << run;
  const Json report = Json::parse(run.out);
  EXPECT_EQ(report["ok"], false);
  std::set<std::string> poses, joints;
  for (const Json& m : report["mismatches"]) {
    poses.insert(m["pose"].get<std::string>());
    joints.insert(m["joint"].get<std::string>());
    EXPECT_GT(m["error"].get<double>(), 1e-6);
  }
  EXPECT_TRUE(poses.count("eyes") && poses.count("all")) << run;
  EXPECT_TRUE(joints.count("eye.L") && joints.count("eye.R")) << run;
  EXPECT_EQ(joints.size(), 2u) << "only the eyes move differently: " << run;
  // Without --json: each mismatch on a line of its own, naming the pose and joint.
  const CliRun plain = rigel({"check", changed.string(), "--tests", tests});
  EXPECT_TRUE(exited_with(plain, 1));
  EXPECT_TRUE(contains(plain.err, "pose 'eyes', joint 'eye.L': off by")) << plain;
  // A looser tolerance than the change passes.
  EXPECT_TRUE(exited_with(rigel({"check", changed.string(), "--tests", tests, "--tolerance", "1"}), 0));
}

TEST(CliCheck, a_shot_is_recorded_and_checked_at_frames_as_it_plays) {
  TempDir dir;
  const fs::path shot = dir.path() / "shot.rigel";
  ASSERT_TRUE(exited_with(rigel({"build", (kExamples / "biped.rig.xml").string(), "-o", shot.string()}), 0));
  // The left arm keyed at rest at 0 and turned at 24.
  ASSERT_TRUE(exited_with(rigel({"key", shot.string(), "--control", "hero_arm_L_fk0", "--frame", "0", "-o", shot.string()}), 0));
  const CliRun posed = rigel({"pose", shot.string(), "--control", "hero_arm_L_fk0", "--mode", "forward", "--rotate", "0,0,40",
                              "--frame", "24", "--auto-key", "-o", shot.string()});
  ASSERT_TRUE(exited_with(posed, 0)) << posed;
  const fs::path tests = dir.path() / "shot.rigtest.json";
  const CliRun record = rigel({"check", "record", shot.string(), "--frames", "0-24:12", "-o", tests.string(), "--json"});
  ASSERT_TRUE(exited_with(record, 0)) << record;
  const Json recorded = Json::parse(record.out);
  ASSERT_EQ(recorded["poses"].size(), 3u);
  EXPECT_EQ(recorded["poses"][2]["name"], "frame_24");
  EXPECT_EQ(recorded["poses"][2]["frame"], 24.0);
  EXPECT_EQ(recorded["poses"][0]["moved"], 0);
  EXPECT_GT(recorded["poses"][1]["moved"].get<int>(), 0) << "the arm moves between the keys";
  const CliRun check = rigel({"check", shot.string(), "--tests", tests.string()});
  EXPECT_TRUE(exited_with(check, 0)) << check;
  EXPECT_TRUE(contains(check.err, "3 poses")) << check;
  // The file reads back to the same bytes when recorded again.
  const std::string first = read(tests);
  ASSERT_TRUE(exited_with(rigel({"check", "record", shot.string(), "--frames", "0-24:12", "-o", tests.string()}), 0));
  EXPECT_EQ(read(tests), first);
}

TEST(CliCheck, bad_input_is_refused_naming_the_option_and_nothing_is_written) {
  TempDir dir;
  const fs::path shot = dir.path() / "shot.rigel";
  ASSERT_TRUE(exited_with(rigel({"build", (kExamples / "puppet.rig.xml").string(), "-o", shot.string()}), 0));
  // A scene needs a tests file to check against and one to record into.
  const CliRun no_tests = rigel({"check", shot.string()});
  EXPECT_TRUE(exited_with(no_tests, 2)) << no_tests;
  EXPECT_TRUE(contains(no_tests.err, "--tests")) << no_tests;
  const CliRun no_output = rigel({"check", "record", shot.string()});
  EXPECT_TRUE(exited_with(no_output, 2)) << no_output;
  const CliRun frames = rigel({"check", "record", shot.string(), "--frames", "5-1", "-o", (dir.path() / "t.rigtest.json").string()});
  EXPECT_TRUE(exited_with(frames, 2)) << frames;
  EXPECT_TRUE(contains(frames.err, "--frames")) << frames;
  EXPECT_FALSE(fs::exists(dir.path() / "t.rigtest.json"));
  // A tests file that is not one: its place named.
  const fs::path bad = dir.path() / "bad.rigtest.json";
  std::ofstream(bad, std::ios::binary) << "{\"format\": \"rigel rig tests\", \"version\": 1, \"rig\": 3}";
  const CliRun broken = rigel({"check", shot.string(), "--tests", bad.string()});
  EXPECT_TRUE(exited_with(broken, 1)) << broken;
  EXPECT_TRUE(contains(broken.err, "bad.rigtest.json: rig: expected a string")) << broken;
  const CliRun missing = rigel({"check", shot.string(), "--tests", (dir.path() / "none.rigtest.json").string()});
  EXPECT_TRUE(exited_with(missing, 1)) << missing;
  EXPECT_TRUE(contains(missing.err, "no such rig tests file")) << missing;
  // A rig the scene does not have.
  const fs::path tests = (kExamples / "puppet.rigtest.json");
  const CliRun other = rigel({"check", shot.string(), "--tests", tests.string(), "--rig", "nobody"});
  EXPECT_TRUE(exited_with(other, 1)) << other;
  EXPECT_TRUE(contains(other.err, "no rig named 'nobody'")) << other;
  EXPECT_TRUE(exited_with(rigel({"check", shot.string(), "--tests", tests.string(), "--tolerance", "-1"}), 2));
  EXPECT_TRUE(exited_with(rigel({"check"}), 2));
}

}  // namespace
}  // namespace rigel::cli
