// `rigel batch update|bake|export|validate` over generated shots (the biped
// with different keys) on 2 jobs: every output as running the command by
// hand gives, a report listing every shot, a broken shot failed with its
// log while the others succeed, --retry-failed running only that one;
// `rigel rigs --check` failing a shot whose rig is out of date.
#include <filesystem>

#include "cli_test_util.h"

namespace rigel::cli::testing {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

class CliBatch : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string example = (fs::path(RIGEL_SOURCE_DIR) / "examples/biped.rig.xml").string();
    ASSERT_TRUE(exited_with(rigel({"build", example, "-o", at("hero.rigel").string()}), 0));
    fs::create_directories(at("shots"));
    for (int i = 0; i < 8; ++i) {
      const std::string shot = at("shots/s" + std::to_string(i) + ".rigel").string();
      const CliRun r = rigel({"key", at("hero.rigel").string(), "--control", "hero_arm_L_fkIkSwitch", "--attr", "fkIk",
                              "--frame", std::to_string(3 + i), "--value", "0." + std::to_string(i), "-o", shot});
      ASSERT_TRUE(exited_with(r, 0)) << r;
      shots_.push_back(shot);
    }
  }
  fs::path at(const std::string& name) { return dir_.path() / name; }
  Json eval(const fs::path& scene, int frame) {
    const CliRun r = rigel({"eval", scene.string(), "--frame", std::to_string(frame), "--json"});
    EXPECT_TRUE(exited_with(r, 0)) << r;
    return Json::parse(r.out)["nodes"];
  }
  TempDir dir_;
  std::vector<std::string> shots_;
};

TEST_F(CliBatch, bake_on_two_jobs_equals_by_hand_and_a_broken_shot_is_retried_alone) {
  io::testing::write_text(at("shots/broken.rigel"), "{\"rigelScene\": 1, \"nodes\": [\n");
  std::vector<std::string> args = {"batch", "bake"};
  args.insert(args.end(), shots_.begin(), shots_.end());
  args.push_back(at("shots/broken.rigel").string());
  args.insert(args.end(), {"--frames", "0:12", "-o", at("baked").string(), "--jobs", "2", "--json"});
  CliRun r = rigel(args);
  EXPECT_TRUE(exited_with(r, 1)) << "one shot failed: " << r;
  const Json report = Json::parse(r.out);
  ASSERT_EQ(report["shots"].size(), shots_.size() + 1);
  EXPECT_EQ(report["jobs"], 2);
  for (const Json& s : report["shots"]) {
    const bool broken = s["shot"].get<std::string>().find("broken") != std::string::npos;
    EXPECT_EQ(s["status"], broken ? "failed" : "ok") << s;
    EXPECT_TRUE(fs::exists(s["log"].get<std::string>())) << s;
    if (broken) {
      EXPECT_NE(io::testing::read_text(s["log"].get<std::string>()).find("broken.rigel:2:"), std::string::npos);
    }
  }
  EXPECT_FALSE(fs::exists(at("baked/broken.rigel"))) << "a failed shot writes nothing";
  EXPECT_EQ(io::testing::read_text(at("baked/batch-report.json")), r.out);
  // Each output as the command by hand.
  for (int i : {0, 5}) {
    const CliRun by_hand = rigel({"bake", shots_[static_cast<std::size_t>(i)], "--frames", "0:12", "-o", at("hand.rigel").string()});
    ASSERT_TRUE(exited_with(by_hand, 0)) << by_hand;
    for (int f : {0, 7, 12}) EXPECT_EQ(eval(at("baked/s" + std::to_string(i) + ".rigel"), f), eval(at("hand.rigel"), f)) << i << " " << f;
  }
  // Fixed, retried: only it runs, and the report lists every shot ok.
  fs::copy_file(shots_[0], at("shots/broken.rigel"), fs::copy_options::overwrite_existing);
  const auto before = fs::last_write_time(at("baked/s1.rigel"));
  r = rigel({"batch", "bake", "--frames", "0:12", "-o", at("baked").string(), "--retry-failed", at("baked/batch-report.json").string(), "--json"});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  const Json merged = Json::parse(io::testing::read_text(at("baked/batch-report.json")));
  ASSERT_EQ(merged["shots"].size(), shots_.size() + 1);
  for (const Json& s : merged["shots"]) EXPECT_EQ(s["status"], "ok") << s;
  EXPECT_TRUE(fs::exists(at("baked/broken.rigel")));
  EXPECT_EQ(fs::last_write_time(at("baked/s1.rigel")), before) << "only the failed shot ran again";
}

TEST_F(CliBatch, update_export_and_validate) {
  std::vector<std::string> args = {"batch", "update"};
  args.insert(args.end(), shots_.begin(), shots_.begin() + 3);
  args.insert(args.end(), {"-o", at("updated").string(), "--jobs", "2"});
  CliRun r = rigel(args);
  ASSERT_TRUE(exited_with(r, 0)) << r;
  EXPECT_EQ(eval(at("updated/s2.rigel"), 4), eval(fs::path(shots_[2]), 4)) << "an update of an up-to-date rig changes nothing";
  args = {"batch", "export", shots_[0], shots_[1], "-o", at("glb").string()};
  r = rigel(args);
  ASSERT_TRUE(exited_with(r, 0)) << r;
  EXPECT_TRUE(fs::exists(at("glb/s1.glb")));
  r = rigel({"batch", "validate", shots_[0], shots_[1], "--report", at("validate.json").string()});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  // Usage errors.
  EXPECT_TRUE(exited_with(rigel({"batch", "bake", shots_[0], "-o", at("x").string()}), 2)) << "bake needs --frames";
  EXPECT_TRUE(exited_with(rigel({"batch", "bake", shots_[0], "--frames", "0:3"}), 2)) << "needs -o";
  EXPECT_TRUE(exited_with(rigel({"batch", "dance", shots_[0]}), 2));
  EXPECT_TRUE(exited_with(rigel({"batch", "update", shots_[0], shots_[0], "-o", at("x").string()}), 2)) << "one output twice";
  EXPECT_TRUE(exited_with(rigel({"batch", "bake", "--frames", "0:3", "-o", at("x").string(), "--retry-failed", at("validate.json").string()}), 2))
      << "a report of another operation";
}

}  // namespace
}  // namespace rigel::cli::testing
