// `rigel batch --slurm` on a real single-node Slurm cluster the test starts
// (tests/support/slurm_cluster.sh: munge, slurmctld and slurmd of its own in
// a temporary folder, stopped at the end): the shots as one job array, every
// output as the local run's, a broken shot failed with its log, the report
// listing every shot, --retry-failed through Slurm running only that one.
// Skipped, saying why, where Slurm cannot run (not installed, not root).
#include <cstdlib>
#include <filesystem>

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
    const std::string example = (fs::path(RIGEL_SOURCE_DIR) / "examples/biped.rig.xml").string();
    ASSERT_TRUE(exited_with(rigel({"build", example, "-o", at("hero.rigel").string()}), 0));
    for (int i = 0; i < 6; ++i) {
      const std::string shot = at("shots/s" + std::to_string(i) + ".rigel").string();
      fs::create_directories(at("shots"));
      const CliRun r = rigel({"key", at("hero.rigel").string(), "--control", "hero_arm_L_fkIkSwitch", "--attr", "fkIk",
                              "--frame", std::to_string(2 + i), "--value", "0." + std::to_string(i), "-o", shot});
      ASSERT_TRUE(exited_with(r, 0)) << r;
      shots_.push_back(shot);
    }
  }
  void TearDown() override {
    if (!started_) return;
    const std::string cmd = (fs::path(RIGEL_SOURCE_DIR) / "tests/support/slurm_cluster.sh").string() + " stop " +
                            (dir_.path() / "cluster").string();
    EXPECT_EQ(std::system(cmd.c_str()), 0);
    unsetenv("SLURM_CONF");
  }
  fs::path at(const std::string& name) { return dir_.path() / name; }
  TempDir dir_;
  bool started_ = false;
  std::vector<std::string> shots_;
};

TEST_F(CliBatchSlurm, a_job_array_gives_the_local_outputs_and_retries_the_broken_shot) {
  io::testing::write_text(at("shots/broken.rigel"), "not a scene");
  std::vector<std::string> shots = shots_;
  shots.push_back(at("shots/broken.rigel").string());
  std::vector<std::string> args = {"batch", "bake"};
  args.insert(args.end(), shots.begin(), shots.end());
  for (const char* where : {"local", "slurm"}) {
    std::vector<std::string> a = args;
    a.insert(a.end(), {"--frames", "0:10", "-o", at(where).string(), "--json"});
    if (std::string(where) == "slurm") a.push_back("--slurm");
    const CliRun r = rigel(a);
    EXPECT_TRUE(exited_with(r, 1)) << where << ": the broken shot fails: " << r;
    const Json report = Json::parse(r.out);
    ASSERT_EQ(report["shots"].size(), shots.size()) << where;
    for (const Json& s : report["shots"]) {
      const bool broken = s["shot"].get<std::string>().find("broken") != std::string::npos;
      EXPECT_EQ(s["status"], broken ? "failed" : "ok") << where << " " << s;
      EXPECT_TRUE(fs::exists(s["log"].get<std::string>())) << s;
    }
  }
  EXPECT_NE(read_text(at("slurm/logs/broken.log")).find("broken.rigel"), std::string::npos) << "its log says why";
  for (std::size_t i = 0; i < shots_.size(); ++i) {
    std::string name = "s";
    name += std::to_string(i);
    name += ".rigel";
    for (int f : {0, 6, 10}) {
      const CliRun a = rigel({"eval", at("local/" + name).string(), "--frame", std::to_string(f), "--json"});
      const CliRun b = rigel({"eval", at("slurm/" + name).string(), "--frame", std::to_string(f), "--json"});
      ASSERT_TRUE(exited_with(a, 0) && exited_with(b, 0)) << a << b;
      EXPECT_EQ(a.out, b.out) << name << " at " << f;
    }
  }
  fs::copy_file(shots_[0], at("shots/broken.rigel"), fs::copy_options::overwrite_existing);
  const auto before = fs::last_write_time(at("slurm/s1.rigel"));
  const CliRun r = rigel({"batch", "bake", "--frames", "0:10", "-o", at("slurm").string(), "--slurm", "--retry-failed",
                          at("slurm/batch-report.json").string()});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  const Json merged = Json::parse(read_text(at("slurm/batch-report.json")));
  for (const Json& s : merged["shots"]) EXPECT_EQ(s["status"], "ok") << s;
  EXPECT_EQ(fs::last_write_time(at("slurm/s1.rigel")), before) << "only the failed shot ran again";
}

}  // namespace
}  // namespace rigel::cli::testing
