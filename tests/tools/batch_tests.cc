// Local batch runs (tools/batch.h) on small shell jobs: each job's status,
// exit, log and output in the report, in the jobs' order whatever order
// they end in; progress to the end; and a child the calling program
// started itself left for it to collect (a TD's script that runs a batch
// beside its own subprocesses).

#include "rigel/tools/batch.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <string>
#include <vector>

#include "../io/io_test_util.h"

namespace rigel::tools {
namespace {

namespace fs = std::filesystem;

BatchJob shell_job(const fs::path& dir, const std::string& shot, const std::string& script) {
  BatchJob j;
  j.shot = shot;
  j.argv = {"/bin/sh", "-c", script};
  j.log = dir / "logs" / (shot + ".log");
  return j;
}

TEST(BatchLocal, each_job_reported_in_order_and_a_foreign_child_left_to_its_parent) {
  io::testing::TempDir dir;
  // The caller's own child, ended before the batch starts and not yet collected.
  const pid_t own = fork();
  ASSERT_GE(own, 0);
  if (own == 0) _exit(7);
  const std::vector<BatchJob> jobs = {shell_job(dir.path(), "slow", "sleep 0.3; echo slow done"),
                                      shell_job(dir.path(), "fails", "echo broken >&2; exit 3"),
                                      shell_job(dir.path(), "killed", "kill -9 $$"),
                                      shell_job(dir.path(), "quick", "echo quick done")};
  std::vector<BatchProgress> seen;
  const BatchReport r = run_batch_local("bake", jobs, 2, [&](const BatchProgress& p) { seen.push_back(p); });
  ASSERT_EQ(r.shots.size(), 4u);
  EXPECT_EQ(r.jobs, 2u);
  EXPECT_EQ(r.shots[0].shot, "slow");
  EXPECT_EQ(r.shots[0].status, "ok");
  EXPECT_EQ(r.shots[1].status, "failed");
  EXPECT_EQ(r.shots[1].exit, 3);
  EXPECT_EQ(r.shots[2].status, "crashed");
  EXPECT_EQ(r.shots[3].status, "ok");
  EXPECT_EQ(r.failed(), 2u);
  EXPECT_EQ(io::testing::read_text(r.shots[0].log), "slow done\n");
  EXPECT_EQ(io::testing::read_text(r.shots[1].log), "broken\n");
  ASSERT_FALSE(seen.empty());
  EXPECT_EQ(seen.back().done, 4u);
  EXPECT_EQ(seen.back().failed, 2u);
  EXPECT_EQ(seen.back().running, 0u);
  // The caller's child is still the caller's to collect, with its status.
  int status = 0;
  ASSERT_EQ(waitpid(own, &status, WNOHANG), own) << "the batch reaped a child that was not its own";
  EXPECT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 7);
}

TEST(BatchLocal, a_job_that_cannot_start_is_reported_not_run) {
  io::testing::TempDir dir;
  BatchJob missing;
  missing.shot = "missing";
  missing.argv = {(dir.path() / "no-such-program").string()};
  missing.log = dir.path() / "logs" / "missing.log";
  const BatchReport r = run_batch_local("update", {missing, shell_job(dir.path(), "fine", "true")}, 1);
  ASSERT_EQ(r.shots.size(), 2u);
  EXPECT_NE(r.shots[0].status, "ok");
  EXPECT_EQ(r.shots[1].status, "ok");
}

}  // namespace
}  // namespace rigel::tools
