// A batch run as a user asks for it (batch_run.h): plan, run, report.

#include "rigel/tools/batch_run.h"

#include <cmath>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>

#include "rigel/io/scene_file.h"
#include "rigel/tools/batch_slurm.h"

namespace rigel::tools {

namespace fs = std::filesystem;

namespace {

Status bad(const std::string& field, const std::string& message) {
  return Status(ErrorCode::kInvalidArgument, message).with_field(field);
}

// FIRST:LAST, two finite frame numbers.
bool frames_ok(const std::string& text) {
  const std::size_t colon = text.find(':');
  if (colon == std::string::npos) return false;
  for (const std::string& part : {text.substr(0, colon), text.substr(colon + 1)}) {
    std::istringstream in(part);
    double d = 0;
    if (part.empty() || !(in >> d) || !in.eof() || !std::isfinite(d)) return false;
  }
  return true;
}

}  // namespace

Result<std::vector<BatchJob>> plan_batch(const BatchRequest& r) {
  const std::string& op = r.operation;
  if (op != "update" && op != "bake" && op != "export" && op != "validate")
    return bad("operation", "operation '" + op + "': expected update, bake, export or validate");
  if (op != "validate" && r.output.empty()) return bad("output", "batch " + op + " writes a file per shot: give an output folder");
  if (op == "bake" && r.frames.empty()) return bad("frames", "batch bake: give the frames FIRST:LAST");
  if (!r.frames.empty() && !frames_ok(r.frames))
    return bad("frames", "frames '" + r.frames + "': expected FIRST:LAST, two frame numbers such as 0:120");
  if (r.program.empty()) return bad("program", "the rigel command line each job runs is not known");
  const fs::path logs = r.output.empty() ? report_path_of(r).parent_path() / "batch-logs" : r.output / "logs";
  std::vector<BatchJob> jobs;
  std::map<std::string, std::string> taken;  // output name -> shot, so two shots never write one file
  for (const std::string& shot : r.shots) {
    const std::string stem = fs::path(shot).stem().string();
    if (auto [it, fresh] = taken.emplace(stem, shot); !fresh)
      return bad("shots", "shots " + it->second + " and " + shot + " would write the same " + stem + " output");
    BatchJob j;
    j.shot = shot;
    j.log = logs / (stem + ".log");
    if (op == "update") j.output = r.output / (stem + ".rigel"), j.argv = {r.program, "update", shot, "-o", j.output.string()};
    if (op == "bake")
      j.output = r.output / (stem + ".rigel"), j.argv = {r.program, "bake", shot, "--frames", r.frames, "-o", j.output.string()};
    if (op == "export") {
      j.output = r.output / (stem + ".glb");
      j.argv = {r.program, "export", shot, "-o", j.output.string()};
      if (!r.frames.empty()) j.argv.insert(j.argv.end(), {"--frames", r.frames});
    }
    if (op == "validate") j.argv = {r.program, "rigs", shot, "--check"};
    j.argv.insert(j.argv.end(), {"--log-level", r.log_level});
    jobs.push_back(std::move(j));
  }
  return jobs;
}

fs::path report_path_of(const BatchRequest& r) {
  return !r.report.empty()         ? r.report
         : !r.retry_failed.empty() ? r.retry_failed
         : r.output.empty()        ? fs::path("batch-report.json")
                                   : r.output / "batch-report.json";
}

Result<BatchOutcome> run_batch(const BatchRequest& request, const std::function<void(const BatchProgress&)>& progress) {
  BatchRequest r = request;
  std::optional<BatchReport> earlier;
  if (!r.retry_failed.empty()) {
    const std::string source = r.retry_failed.string();
    std::ifstream in(r.retry_failed, std::ios::binary);
    if (!in) return Status(ErrorCode::kNotFound, "retry_failed: " + source + ": cannot be read").with_field("retry_failed");
    std::stringstream text;
    text << in.rdbuf();
    auto old = batch_report_from_json(text.str(), source);
    if (!old) return Status(old.status()).with_field("retry_failed");
    if (old->operation != r.operation)
      return bad("retry_failed", source + " is a report of batch " + old->operation + ", not " + r.operation);
    if (!r.shots.empty()) return bad("retry_failed", "a retry reruns the report's failed shots: give no shots");
    r.shots = failed_shots(*old);
    earlier = std::move(*old);
  }
  if (!r.slurm && !r.partition.empty()) return bad("partition", "a partition goes with Slurm");
  BatchOutcome out;
  out.report_path = report_path_of(r);
  // (a retry of a report with nothing failed runs nothing)
  if (r.shots.empty() && !earlier) return bad("shots", "give the shots (scene files) or a report to retry the failed shots of");
  auto jobs = plan_batch(r);
  if (!jobs) return jobs.status();
  std::error_code ec;
  if (!r.output.empty()) {
    fs::create_directories(r.output, ec);
    if (ec || !fs::is_directory(r.output))
      return Status(ErrorCode::kFailedPrecondition, "output: " + r.output.string() + ": not a folder").with_field("output");
  }
  if (r.slurm) {
    SlurmOptions so;
    so.partition = r.partition;
    so.work = (r.output.empty() ? out.report_path.parent_path() : r.output) / "slurm";
    auto run = run_batch_slurm(r.operation, *jobs, so, progress);
    if (!run) return run.status();
    out.run = std::move(*run);
  } else {
    out.run = run_batch_local(r.operation, *jobs, r.parallel, progress);
  }
  out.report = earlier ? merge_reports(*earlier, out.run) : out.run;
  if (out.report_path.has_parent_path()) fs::create_directories(out.report_path.parent_path(), ec);
  if (Status s = io::write_file_atomic(out.report_path, batch_report_to_json(out.report)); !s) return s.with_field("report");
  return out;
}

}  // namespace rigel::tools
