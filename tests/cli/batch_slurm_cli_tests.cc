// `rigel batch --slurm` on a real single-node Slurm cluster the test starts
// (tests/support/slurm_cluster.sh: munge, slurmctld and slurmd of its own in
// a temporary folder, stopped at the end), over 50 generated shots and a
// broken one (batch_shots.h), for bake and update: the shots as one job
// array, every output as the local run's (batch_cli_tests.cc shows those
// equal to running the command by hand), the broken shot failed with its
// log, the report listing every shot, --retry-failed through Slurm running
// only that one once it is fixed.
// Skipped, saying why, where Slurm cannot run (not installed, not root).
#include <cstdlib>
#include <filesystem>

#include "batch_shots.h"
#include "cli_test_util.h"

namespace rigel::cli::testing {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

class CliBatchSlurm : public ::testing::Test {
 protected:
  void SetUp() override {
    const fs::path script = fs::path(RIGEL_SOURCE_DIR) / "tests/support/slurm_cluster.sh";
    const std::string cmd = script.string() + " start " + (dir_.path() / "cluster").string() + " > " +
                            (dir_.path() / "conf").string() + " 2> " + (dir_.path() / "cluster.err").string();
    const int rc = std::system(cmd.c_str());
    if (WEXITSTATUS(rc) == 3) GTEST_SKIP() << "no Slurm here: " << read_text(dir_.path() / "cluster.err");
    ASSERT_EQ(WEXITSTATUS(rc), 0) << read_text(dir_.path() / "cluster.err");
    std::string conf = read_text(dir_.path() / "conf");
    while (!conf.empty() && (conf.back() == '\n' || conf.back() == ' ')) conf.pop_back();
    setenv("SLURM_CONF", conf.c_str(), 1);
    started_ = true;
    hero_ = build_hero(dir_.path());
    ASSERT_FALSE(hero_.empty());
    shots_ = write_shots(hero_, at("shots"));
    ASSERT_FALSE(HasFailure()) << "the shots could not be made";
  }
  void TearDown() override {
    if (!started_) return;
    const std::string cmd = (fs::path(RIGEL_SOURCE_DIR) / "tests/support/slurm_cluster.sh").string() + " stop " +
                            (dir_.path() / "cluster").string();
    EXPECT_EQ(std::system(cmd.c_str()), 0);
    unsetenv("SLURM_CONF");
  }
  fs::path at(const std::string& name) { return dir_.path() / name; }

  // `rigel batch OP SHOTS... OPTIONS` over the shots and a broken one,
  // locally on 2 jobs (into OP_local/) and as a Slurm job array (into
  // OP_slurm/), each reported as expect_report_with_broken_shot says; every
  // Slurm output the local one; the broken shot fixed and retried alone
  // through Slurm, its output as by hand.
  void slurm_equals_local_and_retries_the_broken_shot_alone(const std::string& op, const std::vector<std::string>& options) {
    io::testing::write_text(at("shots/broken.rigel"), kBrokenShotText);
    const std::vector<std::string> all = with_broken(shots_, at("shots/broken.rigel").string());
    const fs::path local = at(op + "_local"), slurm = at(op + "_slurm"), hand = at("by_hand");
    fs::create_directories(hand);  // (`rigel bake -o` makes no folder)
    for (const fs::path& out : {local, slurm}) {
      std::vector<std::string> args = {"batch", op};
      args.insert(args.end(), all.begin(), all.end());
      args.insert(args.end(), options.begin(), options.end());
      args.insert(args.end(), {"-o", out.string(), "--json"});
      if (out == local) args.insert(args.end(), {"--jobs", "2"});
      else args.push_back("--slurm");
      SCOPED_TRACE(out.filename().string());
      expect_report_with_broken_shot(rigel(args), op, all, out, out == local ? 2 : all.size());
      if (HasFatalFailure()) return;
    }
    for (const std::string& shot : shots_) EXPECT_TRUE(same_output(output_of(slurm, shot), output_of(local, shot), shot));

    const BeforeRetry before = before_retry(all, slurm);
    write_shot(hero_, kShotCount, at("shots/broken.rigel"));
    std::vector<std::string> retry = {"batch", op};
    retry.insert(retry.end(), options.begin(), options.end());
    retry.insert(retry.end(),
                 {"-o", slurm.string(), "--slurm", "--retry-failed", (slurm / "batch-report.json").string(), "--json"});
    expect_retried_alone(rigel(retry), op, all, slurm, before);
    std::vector<std::string> by_hand = {op, at("shots/broken.rigel").string()};
    by_hand.insert(by_hand.end(), options.begin(), options.end());
    by_hand.insert(by_hand.end(), {"-o", output_of(hand, "broken.rigel").string()});
    const CliRun fixed = rigel(by_hand);
    ASSERT_TRUE(exited_with(fixed, 0)) << fixed;
    EXPECT_TRUE(same_output(output_of(slurm, "broken.rigel"), output_of(hand, "broken.rigel"), at("shots/broken.rigel")));
  }

  TempDir dir_;
  bool started_ = false;
  fs::path hero_;
  std::vector<std::string> shots_;
};

TEST_F(CliBatchSlurm, bake_of_50_shots_as_a_job_array_gives_the_local_outputs_and_retries_the_broken_shot) {
  slurm_equals_local_and_retries_the_broken_shot_alone("bake", {"--frames", kBakeFrames});
}

TEST_F(CliBatchSlurm, update_of_50_shots_as_a_job_array_gives_the_local_outputs_and_retries_the_broken_shot) {
  bump_left_arm(dir_.path());
  slurm_equals_local_and_retries_the_broken_shot_alone("update", {});
}

}  // namespace
}  // namespace rigel::cli::testing
