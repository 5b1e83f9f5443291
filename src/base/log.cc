// Logging (log.h) over spdlog: one logger named "rigel" with a stderr sink
// at the process's level, and a file sink plus a warnings-keeping sink per
// open JobLog.

#include "rigel/base/log.h"

#include <algorithm>
#include <mutex>

#include <spdlog/sinks/base_sink.h>
#include <spdlog/sinks/basic_file_sink.h>
#include <spdlog/sinks/stdout_sinks.h>
#include <spdlog/spdlog.h>

namespace rigel::log {

namespace {

constexpr std::pair<const char*, Level> kNames[] = {{"trace", Level::kTrace}, {"debug", Level::kDebug},
                                                     {"info", Level::kInfo},   {"warn", Level::kWarn},
                                                     {"warning", Level::kWarn}, {"error", Level::kError},
                                                     {"off", Level::kOff}};

spdlog::level::level_enum to_spd(Level l) {
  switch (l) {
    case Level::kTrace: return spdlog::level::trace;
    case Level::kDebug: return spdlog::level::debug;
    case Level::kInfo: return spdlog::level::info;
    case Level::kWarn: return spdlog::level::warn;
    case Level::kError: return spdlog::level::err;
    case Level::kOff: return spdlog::level::off;
  }
  return spdlog::level::off;
}

// The logger and its stderr sink; job sinks are added and removed under
// `mutex` (spdlog's sink list itself is not guarded).
struct State {
  std::mutex mutex;
  std::shared_ptr<spdlog::sinks::stderr_sink_mt> console = std::make_shared<spdlog::sinks::stderr_sink_mt>();
  std::shared_ptr<spdlog::logger> logger;
  Level console_level = Level::kWarn;
  std::vector<Level> job_levels;

  State() {
    console->set_pattern("rigel: %l: %v");
    console->set_level(to_spd(console_level));
    logger = std::make_shared<spdlog::logger>("rigel", console);
    update();
  }
  // The logger passes what any sink wants.
  void update() {
    Level lowest = console_level;
    for (Level l : job_levels) lowest = std::min(lowest, l);
    logger->set_level(to_spd(lowest));
  }
};

State& state() {
  static State s;
  return s;
}

// Keeps the warnings and errors of one job.
class WarningSink final : public spdlog::sinks::base_sink<std::mutex> {
 public:
  std::vector<std::string> warnings() {
    std::lock_guard lock(mutex_);
    return kept_;
  }

 protected:
  void sink_it_(const spdlog::details::log_msg& msg) override {
    if (msg.level < spdlog::level::warn) return;
    kept_.push_back(std::string(msg.level == spdlog::level::warn ? "warn: " : "error: ") +
                    std::string(msg.payload.data(), msg.payload.size()));
  }
  void flush_() override {}

 private:
  std::vector<std::string> kept_;
};

}  // namespace

std::optional<Level> level_from_name(std::string_view name) {
  for (const auto& [n, l] : kNames)
    if (name == n) return l;
  return std::nullopt;
}

const char* level_name(Level level) {
  for (const auto& [n, l] : kNames)
    if (l == level) return n;
  return "off";
}

const char* level_names() { return "trace, debug, info, warn, error, off"; }

void set_level(Level level) {
  State& s = state();
  std::lock_guard lock(s.mutex);
  s.console_level = level;
  s.console->set_level(to_spd(level));
  s.update();
}

Level level() {
  State& s = state();
  std::lock_guard lock(s.mutex);
  return s.console_level;
}

bool enabled(Level level) { return level != Level::kOff && state().logger->should_log(to_spd(level)); }

void write(Level level, std::string_view message) {
  if (!enabled(level)) return;
  State& s = state();
  std::lock_guard lock(s.mutex);
  s.logger->log(to_spd(level), "{}", message);
}

struct JobLog::Impl {
  std::filesystem::path path;
  Level level = Level::kDebug;
  std::shared_ptr<spdlog::sinks::basic_file_sink_mt> file;
  std::shared_ptr<WarningSink> warnings = std::make_shared<WarningSink>();
};

Result<std::unique_ptr<JobLog>> JobLog::open(const std::filesystem::path& path, Level level) {
  auto impl = std::make_unique<Impl>();
  impl->path = path;
  impl->level = level;
  try {
    impl->file = std::make_shared<spdlog::sinks::basic_file_sink_mt>(path.string(), true);
  } catch (const spdlog::spdlog_ex& e) {
    return Status(ErrorCode::kIoError, path.string() + ": the log file cannot be opened: " + e.what());
  }
  impl->file->set_pattern("%Y-%m-%dT%H:%M:%S.%e %l: %v");
  impl->file->set_level(to_spd(level));
  impl->warnings->set_level(spdlog::level::warn);
  State& s = state();
  {
    std::lock_guard lock(s.mutex);
    s.logger->sinks().push_back(impl->file);
    s.logger->sinks().push_back(impl->warnings);
    s.job_levels.push_back(std::min(level, Level::kWarn));
    s.update();
  }
  return std::unique_ptr<JobLog>(new JobLog(std::move(impl)));
}

JobLog::JobLog(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

JobLog::~JobLog() {
  State& s = state();
  std::lock_guard lock(s.mutex);
  auto& sinks = s.logger->sinks();
  sinks.erase(std::remove_if(sinks.begin(), sinks.end(),
                             [&](const spdlog::sink_ptr& p) { return p == impl_->file || p == impl_->warnings; }),
              sinks.end());
  const Level mine = std::min(impl_->level, Level::kWarn);
  if (auto it = std::find(s.job_levels.begin(), s.job_levels.end(), mine); it != s.job_levels.end()) s.job_levels.erase(it);
  s.update();
  impl_->file->flush();
}

const std::filesystem::path& JobLog::path() const { return impl_->path; }

std::vector<std::string> JobLog::warnings() const { return impl_->warnings->warnings(); }

void JobLog::flush() { impl_->file->flush(); }

}  // namespace rigel::log
