#pragma once
// A batch run as a user asks for it (`rigel batch`, Python's rigel.batch):
// the operation over shots, or the failed shots of an earlier report; each
// shot's job planned as a `rigel` command line writing OUTDIR/STEM.rigel
// (.glb for export) with its log in OUTDIR/logs/STEM.log; run locally
// (batch.h) or as a Slurm job array (batch_slurm.h); the report written
// atomically (a retry's merged into the report it retried).

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/tools/batch.h"

namespace rigel::tools {

struct BatchRequest {
  std::string operation;                 // update, bake, export or validate
  std::vector<std::string> shots;        // scene files (none with retry_failed)
  std::filesystem::path output;          // OUTDIR (required but for validate)
  std::string frames;                    // FIRST:LAST (bake: required; export: optional)
  std::filesystem::path report;          // "": OUTDIR/batch-report.json, the retried report, or ./batch-report.json
  std::filesystem::path retry_failed;    // rerun this report's failed shots
  std::size_t parallel = 0;              // local shots at once (0: one per core)
  bool slurm = false;                    // one Slurm job array instead of local processes
  std::string partition;                 // with slurm ("": the cluster's default)
  std::string program;                   // the `rigel` executable each job runs
  std::string log_level = "info";        // each job's --log-level (its log file)
};

struct BatchOutcome {
  BatchReport run;                       // this run's shots
  BatchReport report;                    // what was written (a retry: merged)
  std::filesystem::path report_path;
};

// The jobs of a request (no retry): kInvalidArgument naming the field
// ("operation", "output", "frames", "shots") for a request that cannot run.
Result<std::vector<BatchJob>> plan_batch(const BatchRequest& request);

// Where the report goes: `report`, else the retried report, else
// OUTDIR/batch-report.json, else ./batch-report.json.
std::filesystem::path report_path_of(const BatchRequest& request);

// Plans, runs and writes the report. kInvalidArgument naming the field for
// a bad request (also "retry_failed": a report of another operation, or
// shots given with it; "partition" without slurm); kNotFound / kParseError
// for a retried report that cannot be read; run_batch_slurm's errors.
// Shots that fail are in the report, not an error.
Result<BatchOutcome> run_batch(const BatchRequest& request, const std::function<void(const BatchProgress&)>& progress = {});

}  // namespace rigel::tools
