#pragma once
// Batch runs over many shots (the pipeline's farm work): one job per shot,
// each a process of its own (a command line), run locally N at a time, with
// every job's output in its log file, live progress, and a report of every
// shot (status, time, log, output). A job's output file is written by the
// job (rigel's saves are atomic), so a failed shot leaves its input and any
// earlier output as they were. Slurm runs (sbatch job arrays) go through
// the same jobs and report (batch_slurm.h).
//
// The report, diffable JSON:
//
//   {
//     "rigelBatch": 1,
//     "operation": "bake",
//     "jobs": 2,
//     "seconds": 12.5,
//     "shots": [
//       {"shot": "shots/s01.rigel", "status": "ok", "exit": 0, "seconds": 0.4,
//        "log": "out/logs/s01.log", "output": "out/s01.rigel"},
//       ...
//     ]
//   }

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "rigel/base/status.h"

namespace rigel::tools {

inline constexpr int kBatchFormat = 1;

struct BatchJob {
  std::string shot;                 // the input, as the report names it
  std::vector<std::string> argv;    // the command line (argv[0]: the program)
  std::filesystem::path log;        // stdout and stderr go here
  std::filesystem::path output;     // what the job writes ("" for none)
};

struct BatchResult {
  std::string shot;
  std::string status;  // "ok", "failed" (non-zero exit), "crashed" (a signal), "not run" (could not start)
  int exit = -1;
  double seconds = 0;
  std::filesystem::path log, output;
};

struct BatchProgress {
  std::size_t done = 0, failed = 0, running = 0, total = 0;
  double elapsed = 0, left = 0;  // seconds; `left` estimated from the mean so far (0 before any is done)
};

struct BatchReport {
  std::string operation;
  std::size_t jobs = 0;
  double seconds = 0;
  std::vector<BatchResult> shots;
  std::size_t failed() const;
};

// Runs the jobs, at most `parallel` at a time (0: one per core), in order
// of the list; `progress` is called as each starts and ends. Each log's
// folder is made. Jobs run with the current environment and folder.
BatchReport run_batch_local(std::string operation, const std::vector<BatchJob>& jobs, std::size_t parallel,
                            const std::function<void(const BatchProgress&)>& progress = {});

// "12/50 done, 1 failed, 2 running, 0:35 left".
std::string progress_line(const BatchProgress& p);

std::string batch_report_to_json(const BatchReport& report);
// kParseError naming `source` and the place for text that is not a report.
Result<BatchReport> batch_report_from_json(std::string_view text, const std::string& source);

// The shots of `report` that did not succeed, in its order.
std::vector<std::string> failed_shots(const BatchReport& report);
// `earlier` with `rerun`'s results in place of the same shots' (a retry).
BatchReport merge_reports(const BatchReport& earlier, const BatchReport& rerun);

}  // namespace rigel::tools
