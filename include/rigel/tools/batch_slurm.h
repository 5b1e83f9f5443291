#pragma once
// Batch runs on Slurm (batch.h's jobs as one job array): a script per job
// and an array script in a work folder, submitted with `sbatch --array`;
// each task runs its job with the output in the job's log and writes its
// exit status; the submitter polls those (and `squeue`) for progress and
// the report, so the report and the retries are the local run's. Tasks
// that vanish from the queue without a status are reported "crashed".
// Slurm is Debian's slurm-wlm: without `sbatch` on the PATH the run is
// refused saying how to get it.

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/tools/batch.h"

namespace rigel::tools {

struct SlurmOptions {
  std::string partition;              // "" : the cluster's default
  std::filesystem::path work;         // the scripts and status files (made as needed)
  double poll_seconds = 0.25;         // how often the statuses are read
  std::string job_name = "rigel-batch";
};

// kFailedPrecondition when sbatch is missing; kIoError when the work folder
// cannot be written; kInternal... never: a failed submission is reported
// with sbatch's own message (kFailedPrecondition).
Result<BatchReport> run_batch_slurm(std::string operation, const std::vector<BatchJob>& jobs, const SlurmOptions& options,
                                    const std::function<void(const BatchProgress&)>& progress = {});

// `word` quoted for a POSIX shell ('...', with ' written as '\'').
std::string shell_quote(const std::string& word);

}  // namespace rigel::tools
