// Batch runs on Slurm (batch_slurm.h).

#include "rigel/tools/batch_slurm.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <thread>

#include "rigel/base/log.h"
#include "rigel/io/scene_file.h"

extern char** environ;

namespace rigel::tools {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

// Runs a program, its stdout and stderr into `out`; the exit status (-1 when it cannot start).
int run_program(const std::vector<std::string>& argv, const fs::path& out) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  std::vector<std::string> words = argv;
  std::vector<char*> args;
  for (std::string& w : words) args.push_back(w.data());
  args.push_back(nullptr);
  pid_t pid = -1;
  const int r = posix_spawnp(&pid, words[0].c_str(), &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (r != 0) return -1;
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

bool on_path(const std::string& program) {
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "");
  for (std::string d; std::getline(dirs, d, ':');)
    if (!d.empty() && ::access((fs::path(d) / program).c_str(), X_OK) == 0) return true;
  return false;
}

}  // namespace

std::string shell_quote(const std::string& word) {
  std::string out = "'";
  for (char c : word) {
    if (c == '\'') out += "'\\''";
    else out += c;
  }
  return out + "'";
}

Result<BatchReport> run_batch_slurm(std::string operation, const std::vector<BatchJob>& jobs, const SlurmOptions& options,
                                    const std::function<void(const BatchProgress&)>& progress) {
  if (!on_path("sbatch") || !on_path("squeue"))
    return Status(ErrorCode::kFailedPrecondition,
                  "--slurm: sbatch is not installed (Debian: apt-get install slurm-wlm, and a cluster to submit to)");
  BatchReport report;
  report.operation = std::move(operation);
  report.shots.resize(jobs.size());
  if (jobs.empty()) return report;
  std::error_code ec;
  const fs::path work = fs::absolute(options.work).lexically_normal();
  fs::create_directories(work, ec);
  if (ec) return Status(ErrorCode::kIoError, work.string() + ": " + ec.message());
  // One script per job: its command with the output in its log, then its
  // exit status and time, written atomically.
  for (std::size_t i = 0; i < jobs.size(); ++i) {
    const BatchJob& j = jobs[i];
    if (j.log.has_parent_path()) fs::create_directories(j.log.parent_path(), ec);
    const std::string n = std::to_string(i);
    const fs::path status = work / ("status-" + n), pending = work / ("status-" + n + ".tmp");
    fs::remove(status, ec);
    // Written piece by piece (GCC 12 warns falsely on long chains of + here, -Wstringop-overflow).
    std::string script = "#!/bin/sh\ncd ";
    script += shell_quote(fs::current_path().string());
    script += " || exit 127\nstart=$(date +%s.%N)\n";
    for (std::size_t w = 0; w < j.argv.size(); ++w) {
      if (w) script += ' ';
      script += shell_quote(j.argv[w]);
    }
    script += " < /dev/null > ";
    script += shell_quote(fs::absolute(j.log).string());
    script += " 2>&1\ncode=$?\necho \"$code $start $(date +%s.%N)\" > ";
    script += shell_quote(pending.string());
    script += "\nmv ";
    script += shell_quote(pending.string());
    script += ' ';
    script += shell_quote(status.string());
    script += "\nexit $code\n";
    if (Status s = io::write_file_atomic(work / ("job-" + n + ".sh"), script); !s) return s;
    report.shots[i] = BatchResult{j.shot, "not run", -1, 0, j.log, j.output};
  }
  const std::string array = "#!/bin/sh\nexec /bin/sh " + shell_quote(work.string()) + "/job-\"$SLURM_ARRAY_TASK_ID\".sh\n";
  if (Status s = io::write_file_atomic(work / "array.sh", array); !s) return s;
  std::string range = "--array=0-";  // (not "lit" + std::string: GCC 12 warns falsely, -Wstringop-overflow)
  range += std::to_string(jobs.size() - 1);
  std::vector<std::string> sbatch = {"sbatch", "--parsable", range,
                                     "--job-name=" + options.job_name, "--output=/dev/null", "--chdir=" + fs::current_path().string()};
  if (!options.partition.empty()) sbatch.push_back("--partition=" + options.partition);
  sbatch.push_back((work / "array.sh").string());
  const Clock::time_point t0 = Clock::now();
  const int submitted = run_program(sbatch, work / "sbatch.out");
  const std::string answer = read_text(work / "sbatch.out");
  if (submitted != 0) return Status(ErrorCode::kFailedPrecondition, "--slurm: sbatch failed: " + answer);
  const std::string job_id = answer.substr(0, answer.find_first_of(";\n"));
  log::info("submitted Slurm job array " + job_id + " (" + std::to_string(jobs.size()) + " tasks)");
  std::vector<bool> done(jobs.size(), false);
  std::size_t n_done = 0, n_failed = 0;
  double busy = 0;
  for (;;) {
    for (std::size_t i = 0; i < jobs.size(); ++i) {
      if (done[i]) continue;
      const fs::path status = work / ("status-" + std::to_string(i));
      if (!fs::exists(status, ec)) continue;
      std::istringstream in(read_text(status));
      int code = -1;
      double start = 0, end = 0;
      in >> code >> start >> end;
      BatchResult& r = report.shots[i];
      r.exit = code;
      r.seconds = end > start ? end - start : 0;
      r.status = code == 0 ? "ok" : code > 128 ? "crashed" : "failed";
      busy += r.seconds;
      done[i] = true;
      ++n_done;
      if (code != 0) ++n_failed;
    }
    if (progress) {
      BatchProgress p{n_done, n_failed, 0, jobs.size(), std::chrono::duration<double>(Clock::now() - t0).count(), 0};
      if (n_done) p.left = busy / static_cast<double>(n_done) * static_cast<double>(jobs.size() - n_done);
      progress(p);
    }
    if (n_done == jobs.size()) break;
    // Tasks gone from the queue without a status did not finish.
    const int q = run_program({"squeue", "-h", "-j", job_id, "-o", "%i"}, work / "squeue.out");
    if (q == 0 && read_text(work / "squeue.out").find_first_not_of(" \n") == std::string::npos) {
      std::this_thread::sleep_for(std::chrono::milliseconds(200));  // a status written as the task left the queue
      bool any = false;
      for (std::size_t i = 0; i < jobs.size(); ++i) any |= !done[i] && fs::exists(work / ("status-" + std::to_string(i)), ec);
      if (!any) {
        for (std::size_t i = 0; i < jobs.size(); ++i)
          if (!done[i]) report.shots[i].status = "crashed";
        break;
      }
      continue;
    }
    std::this_thread::sleep_for(std::chrono::duration<double>(options.poll_seconds));
  }
  report.jobs = jobs.size();
  report.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return report;
}

}  // namespace rigel::tools
