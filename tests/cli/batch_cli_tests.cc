// `rigel batch update|bake|export|validate` over 50 generated shots (the
// biped with different keys; batch_shots.h) on 2 jobs: every output as
// running the command by hand gives, a report listing every shot, a broken
// shot failed with its log while the others succeed, --retry-failed
// running only that one once it is fixed.
#include <atomic>
#include <filesystem>
#include <thread>

#include "batch_shots.h"
#include "cli_test_util.h"

namespace rigel::cli::testing {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

// Runs `rigel COMMAND` for each command, two at a time (as the batch runs
// them with --jobs 2); the runs in the order of the commands.
std::vector<CliRun> run_two_at_a_time(const std::vector<std::vector<std::string>>& commands) {
  std::vector<CliRun> runs(commands.size());
  std::atomic<std::size_t> next{0};
  auto work = [&] {
    for (std::size_t i; (i = next.fetch_add(1)) < commands.size();) runs[i] = rigel(commands[i]);
  };
  std::thread other(work);
  work();
  other.join();
  return runs;
}

class CliBatch : public ::testing::Test {
 protected:
  void SetUp() override {
    hero_ = build_hero(dir_.path());
    ASSERT_FALSE(hero_.empty());
    shots_ = write_shots(hero_, at("shots"));
    ASSERT_FALSE(HasFailure()) << "the shots could not be made";
  }
  fs::path at(const std::string& name) { return dir_.path() / name; }
  Json eval(const fs::path& scene, int frame) {
    const CliRun r = rigel({"eval", scene.string(), "--frame", std::to_string(frame), "--json"});
    EXPECT_TRUE(exited_with(r, 0)) << r;
    return Json::parse(r.out)["nodes"];
  }
  // `rigel batch OP SHOTS... OPTIONS -o OUT --jobs 2` over the shots and a
  // broken one (expect_report_with_broken_shot); every output as
  // `rigel OP SHOT OPTIONS -o X` by hand writes it; the broken shot fixed
  // (shot kShotCount's keys) and retried alone, its output as by hand too.
  void batch_equals_by_hand_and_retries_the_broken_shot_alone(const std::string& op, const std::vector<std::string>& options) {
    io::testing::write_text(at("shots/broken.rigel"), kBrokenShotText);
    const std::vector<std::string> all = with_broken(shots_, at("shots/broken.rigel").string());
    // Siblings: the paths a scene file holds are relative to its folder.
    const fs::path out = at(op), hand = at("by_hand");
    fs::create_directories(hand);  // (`rigel bake -o` makes no folder)
    std::vector<std::string> args = {"batch", op};
    args.insert(args.end(), all.begin(), all.end());
    args.insert(args.end(), options.begin(), options.end());
    args.insert(args.end(), {"-o", out.string(), "--jobs", "2", "--json"});
    const CliRun r = rigel(args);
    expect_report_with_broken_shot(r, op, all, out, 2);
    if (HasFatalFailure()) return;

    // Every shot by hand.
    auto by_hand = [&](const std::string& shot) {
      std::vector<std::string> a = {op, shot};
      a.insert(a.end(), options.begin(), options.end());
      a.insert(a.end(), {"-o", output_of(hand, shot).string()});
      return a;
    };
    std::vector<std::vector<std::string>> commands;
    for (const std::string& shot : shots_) commands.push_back(by_hand(shot));
    const std::vector<CliRun> runs = run_two_at_a_time(commands);
    for (std::size_t i = 0; i < shots_.size(); ++i) {
      ASSERT_TRUE(exited_with(runs[i], 0)) << shots_[i] << ": " << runs[i];
      EXPECT_TRUE(same_output(output_of(out, shots_[i]), output_of(hand, shots_[i]), shots_[i]));
    }
    EXPECT_FALSE(same_output(output_of(out, shots_[0]), output_of(out, shots_[1]), shots_[0]))
        << "two shots' outputs differ, and the comparison sees it";

    // Fixed and retried: only it runs.
    const BeforeRetry before = before_retry(all, out);
    write_shot(hero_, kShotCount, at("shots/broken.rigel"));
    std::vector<std::string> retry = {"batch", op};
    retry.insert(retry.end(), options.begin(), options.end());
    retry.insert(retry.end(), {"-o", out.string(), "--retry-failed", (out / "batch-report.json").string(), "--json"});
    expect_retried_alone(rigel(retry), op, all, out, before);
    const CliRun fixed = rigel(by_hand(at("shots/broken.rigel").string()));
    ASSERT_TRUE(exited_with(fixed, 0)) << fixed;
    EXPECT_TRUE(same_output(output_of(out, "broken.rigel"), output_of(hand, "broken.rigel"), at("shots/broken.rigel")));
  }
  TempDir dir_;
  fs::path hero_;
  std::vector<std::string> shots_;
};

TEST_F(CliBatch, bake_of_50_shots_on_two_jobs_equals_by_hand_and_a_broken_shot_is_retried_alone) {
  batch_equals_by_hand_and_retries_the_broken_shot_alone("bake", {"--frames", kBakeFrames});
}

TEST_F(CliBatch, update_of_50_shots_on_two_jobs_equals_by_hand_and_a_broken_shot_is_retried_alone) {
  bump_left_arm(dir_.path());  // every shot's rig out of date: each update rebuilds the left arm
  batch_equals_by_hand_and_retries_the_broken_shot_alone("update", {});
  for (const std::string& shot : shots_) {
    const std::string log = read_text(at("update/logs") / (fs::path(shot).stem().string() + ".log"));
    EXPECT_TRUE(contains(log, ": rebuilt ") && contains(log, "arm_L")) << shot << " was updated: " << log;
  }
}

TEST_F(CliBatch, update_export_and_validate) {
  std::vector<std::string> args = {"batch", "update"};
  args.insert(args.end(), shots_.begin(), shots_.begin() + 3);
  args.insert(args.end(), {"-o", at("updated").string(), "--jobs", "2"});
  CliRun r = rigel(args);
  ASSERT_TRUE(exited_with(r, 0)) << r;
  EXPECT_EQ(eval(at("updated/s02.rigel"), 4), eval(fs::path(shots_[2]), 4)) << "an update of an up-to-date rig changes nothing";
  args = {"batch", "export", shots_[0], shots_[1], "-o", at("glb").string()};
  r = rigel(args);
  ASSERT_TRUE(exited_with(r, 0)) << r;
  EXPECT_TRUE(fs::exists(at("glb/s01.glb")));
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
