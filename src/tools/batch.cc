// Batch runs over many shots (batch.h): local processes and the report.

#include "rigel/tools/batch.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <thread>

#include <nlohmann/json.hpp>

#include "rigel/base/log.h"
#include "rigel/io/diffable_json.h"
#include "rigel/io/json_depth.h"

extern char** environ;

namespace rigel::tools {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;
using Clock = std::chrono::steady_clock;

namespace {

double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// Starts one job with its output in its log; -1 when it cannot start.
pid_t start(const BatchJob& job) {
  std::error_code ec;
  if (job.log.has_parent_path()) fs::create_directories(job.log.parent_path(), ec);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, job.log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  std::vector<std::string> words = job.argv;
  std::vector<char*> argv;
  for (std::string& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  pid_t pid = -1;
  const int r = words.empty() ? EINVAL : posix_spawnp(&pid, words[0].c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  return r == 0 ? pid : -1;
}

}  // namespace

std::size_t BatchReport::failed() const {
  return static_cast<std::size_t>(std::count_if(shots.begin(), shots.end(), [](const BatchResult& r) { return r.status != "ok"; }));
}

BatchReport run_batch_local(std::string operation, const std::vector<BatchJob>& jobs, std::size_t parallel,
                            const std::function<void(const BatchProgress&)>& progress) {
  if (parallel == 0) parallel = std::max(1u, std::thread::hardware_concurrency());
  BatchReport report;
  report.operation = std::move(operation);
  report.jobs = parallel;
  report.shots.resize(jobs.size());
  const Clock::time_point t0 = Clock::now();
  std::map<pid_t, std::pair<std::size_t, Clock::time_point>> running;
  std::size_t next = 0, done = 0, failed = 0;
  double busy = 0;
  auto tell = [&] {
    if (!progress) return;
    BatchProgress p{done, failed, running.size(), jobs.size(), since(t0), 0};
    if (done > 0) p.left = busy / static_cast<double>(done) * static_cast<double>(jobs.size() - done) / static_cast<double>(parallel);
    progress(p);
  };
  while (done < jobs.size()) {
    while (running.size() < parallel && next < jobs.size()) {
      const std::size_t i = next++;
      BatchResult& r = report.shots[i];
      r.shot = jobs[i].shot;
      r.log = jobs[i].log;
      r.output = jobs[i].output;
      const pid_t pid = start(jobs[i]);
      if (pid < 0) {
        r.status = "not run";
        ++done;
        ++failed;
        log::warn(jobs[i].shot + ": the job could not start");
        continue;
      }
      running[pid] = {i, Clock::now()};
      log::debug(jobs[i].shot + ": started (pid " + std::to_string(pid) + ")");
      tell();
    }
    if (running.empty()) continue;
    // Wait for a child to end without reaping it, then reap it only when it
    // is one of ours: a program that runs batches (a TD's Python script)
    // may have children of its own, whose exit status is theirs to collect.
    siginfo_t info{};
    if (waitid(P_ALL, 0, &info, WEXITED | WNOWAIT) != 0) {
      if (errno == EINTR) continue;
      break;  // no children left (should not happen)
    }
    int status = 0;
    pid_t pid = info.si_pid;
    if (running.count(pid)) {
      if (waitpid(pid, &status, 0) != pid) continue;
    } else {
      // Another child ended and stays unreaped (waitid would see it again):
      // poll ours until one ends.
      pid = 0;
      for (const auto& entry : running)
        if (waitpid(entry.first, &status, WNOHANG) == entry.first) {
          pid = entry.first;
          break;
        }
      if (pid == 0) {
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
        continue;
      }
    }
    auto it = running.find(pid);
    BatchResult& r = report.shots[it->second.first];
    r.seconds = since(it->second.second);
    busy += r.seconds;
    if (WIFEXITED(status)) {
      r.exit = WEXITSTATUS(status);
      r.status = r.exit == 0 ? "ok" : "failed";
    } else {
      r.exit = -1;
      r.status = "crashed";
    }
    if (r.status != "ok") {
      ++failed;
      log::info(r.shot + ": " + r.status + (r.exit >= 0 ? " (exit " + std::to_string(r.exit) + ")" : std::string()) +
                "; its log: " + r.log.string());
    }
    running.erase(it);
    ++done;
    tell();
  }
  report.seconds = since(t0);
  return report;
}

std::string progress_line(const BatchProgress& p) {
  char left[32] = "";
  if (p.done > 0 && p.done < p.total) {
    const long s = std::lround(p.left);
    std::snprintf(left, sizeof left, ", %ld:%02ld left", s / 60, s % 60);
  }
  return std::to_string(p.done) + "/" + std::to_string(p.total) + " done, " + std::to_string(p.failed) + " failed, " +
         std::to_string(p.running) + " running" + left;
}

std::string batch_report_to_json(const BatchReport& report) {
  Json shots = Json::array();
  for (const BatchResult& r : report.shots)
    shots.push_back(Json{{"shot", r.shot},
                         {"status", r.status},
                         {"exit", r.exit},
                         {"seconds", std::round(r.seconds * 1000) / 1000},
                         {"log", r.log.string()},
                         {"output", r.output.string()}});
  io::DiffableJsonOptions o;
  o.inline_flat_objects_in_arrays = true;
  return io::diffable_json(Json{{"rigelBatch", kBatchFormat},
                                {"operation", report.operation},
                                {"jobs", report.jobs},
                                {"seconds", std::round(report.seconds * 1000) / 1000},
                                {"shots", shots}},
                           o);
}

Result<BatchReport> batch_report_from_json(std::string_view text, const std::string& source) {
  Result<Json> parsed = io::parse_json(text, source, 8);
  if (!parsed) return parsed.status();
  Json j = std::move(*parsed);
  auto bad = [&](const std::string& where, const std::string& what) {
    return Status(ErrorCode::kParseError, source + ": " + where + ": " + what);
  };
  if (!j.is_object() || !j.contains("rigelBatch")) return bad("rigelBatch", "not a rigel batch report");
  if (!j["rigelBatch"].is_number_integer() || j["rigelBatch"].get<std::int64_t>() > kBatchFormat)
    return bad("rigelBatch", "a format this rigel does not read");
  if (!j.contains("operation") || !j["operation"].is_string()) return bad("operation", "expected text");
  if (!j.contains("shots") || !j["shots"].is_array()) return bad("shots", "expected an array");
  BatchReport r;
  r.operation = j["operation"].get<std::string>();
  // What a retry's merged report keeps: the first run's jobs, and its time
  // that the retry's adds to.
  if (j.contains("jobs") && j["jobs"].is_number_unsigned()) r.jobs = j["jobs"].get<std::size_t>();
  if (j.contains("seconds") && j["seconds"].is_number()) r.seconds = j["seconds"].get<double>();
  for (std::size_t i = 0; i < j["shots"].size(); ++i) {
    const Json& s = j["shots"][i];
    const std::string at = "shots[" + std::to_string(i) + "]";
    if (!s.is_object() || !s.contains("shot") || !s["shot"].is_string() || !s.contains("status") || !s["status"].is_string())
      return bad(at, "expected {\"shot\", \"status\", ...}");
    BatchResult x;
    x.shot = s["shot"].get<std::string>();
    x.status = s["status"].get<std::string>();
    if (s.contains("exit") && s["exit"].is_number_integer()) x.exit = s["exit"].get<int>();
    if (s.contains("seconds") && s["seconds"].is_number()) x.seconds = s["seconds"].get<double>();
    if (s.contains("log") && s["log"].is_string()) x.log = s["log"].get<std::string>();
    if (s.contains("output") && s["output"].is_string()) x.output = s["output"].get<std::string>();
    r.shots.push_back(std::move(x));
  }
  return r;
}

std::vector<std::string> failed_shots(const BatchReport& report) {
  std::vector<std::string> out;
  for (const BatchResult& r : report.shots)
    if (r.status != "ok") out.push_back(r.shot);
  return out;
}

BatchReport merge_reports(const BatchReport& earlier, const BatchReport& rerun) {
  BatchReport out = earlier;
  out.seconds += rerun.seconds;
  for (const BatchResult& r : rerun.shots)
    for (BatchResult& e : out.shots)
      if (e.shot == r.shot) e = r;
  return out;
}

}  // namespace rigel::tools
