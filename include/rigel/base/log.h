#pragma once
// Logging (seed 004 §4.2's Logger): one process-wide logger over spdlog
// (Debian's libspdlog-dev), with levels, writing to stderr as
// "rigel: LEVEL: message", and log files for single jobs (a build, a
// publish, a batch shot) that take every message at or above their own
// level while they are open and keep the job's warnings. spdlog stays in
// log.cc, so no other file compiles against it. Thread safe.

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "rigel/base/status.h"

namespace rigel::log {

enum class Level : int { kTrace = 0, kDebug, kInfo, kWarn, kError, kOff };

// "trace", "debug", "info", "warn" (or "warning"), "error", "off"; nullopt
// for anything else.
std::optional<Level> level_from_name(std::string_view name);
const char* level_name(Level level);
// "trace, debug, info, warn, error, off", for messages.
const char* level_names();

// What reaches stderr (default kWarn). Files keep their own levels.
void set_level(Level level);
Level level();
// Whether a message at `level` goes anywhere (stderr or an open job log).
bool enabled(Level level);

void write(Level level, std::string_view message);
inline void trace(std::string_view m) { write(Level::kTrace, m); }
inline void debug(std::string_view m) { write(Level::kDebug, m); }
inline void info(std::string_view m) { write(Level::kInfo, m); }
inline void warn(std::string_view m) { write(Level::kWarn, m); }
inline void error(std::string_view m) { write(Level::kError, m); }

// A log file for one job: while it lives, every message at or above
// `level` also goes to `path` (one line each: ISO time, level, message;
// the file is truncated when opened), and the warnings and errors logged
// are kept. kIoError when the file cannot be opened.
class JobLog {
 public:
  static Result<std::unique_ptr<JobLog>> open(const std::filesystem::path& path, Level level = Level::kDebug);
  ~JobLog();
  JobLog(const JobLog&) = delete;
  JobLog& operator=(const JobLog&) = delete;

  const std::filesystem::path& path() const;
  // The warnings and errors logged while it was open ("warn: ..."), in order.
  std::vector<std::string> warnings() const;
  // Writes what is buffered to the file.
  void flush();

  struct Impl;

 private:
  explicit JobLog(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace rigel::log
