#pragma once
// Runs the built `rigel` binary (RIGEL_CLI_PATH) for the CLI tests: stdout,
// stderr and the exit status, with crashes told apart from failures.

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <ostream>
#include <string>
#include <vector>

#include "../io/io_test_util.h"

extern char** environ;

namespace rigel::cli::testing {

using rigel::io::testing::read_text;
using rigel::io::testing::TempDir;

// Every run reads the settings of a folder that does not exist, so a user's
// own settings (~/.config/rigel/config.json) never reach the tests; a test
// of settings sets RIGEL_CONFIG_HOME itself.
inline const bool kNoUserSettings = (setenv("RIGEL_CONFIG_HOME", "/nonexistent/rigel-tests-config", 1), true);

// What one run of the binary did.
struct CliRun {
  bool exited = false;  // false: killed by a signal (a crash)
  int exit_code = -1;
  int signal = 0;
  std::string out, err;
};

inline std::ostream& operator<<(std::ostream& os, const CliRun& r) {
  os << (r.exited ? "exit " + std::to_string(r.exit_code) : "signal " + std::to_string(r.signal))
     << "\n--- stdout ---\n" << r.out.substr(0, 2000) << "\n--- stderr ---\n" << r.err.substr(0, 2000);
  return os;
}

// Runs `rigel ARGS...` with stdin from /dev/null and stdout/stderr captured
// in files (no pipes to drain, so large outputs cannot deadlock); in folder
// `cwd` when given (for tests where the current directory matters).
inline CliRun rigel(const std::vector<std::string>& args, const std::filesystem::path& cwd = {}) {
  CliRun run;
  TempDir dir;
  const std::string out = (dir.path() / "stdout").string(), err = (dir.path() / "stderr").string();
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (!cwd.empty()) posix_spawn_file_actions_addchdir_np(&actions, cwd.c_str());
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&actions, 2, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  std::vector<std::string> words = {RIGEL_CLI_PATH};
  words.insert(words.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, RIGEL_CLI_PATH, &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  EXPECT_EQ(spawned, 0) << "the rigel binary should start: " << RIGEL_CLI_PATH << ": " << std::strerror(spawned);
  if (spawned != 0) return run;
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  run.exited = WIFEXITED(status);
  run.exit_code = run.exited ? WEXITSTATUS(status) : -1;
  run.signal = WIFSIGNALED(status) ? WTERMSIG(status) : 0;
  run.out = read_text(out);
  run.err = read_text(err);
  return run;
}

inline bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// A run that exited with `code` (not a crash).
inline bool exited_with(const CliRun& run, int code) { return run.exited && run.exit_code == code; }

// A point read from --json output ([x, y, z]) and its comparisons.
struct V3 {
  double x, y, z;
};
inline V3 v3(const nlohmann::ordered_json& a) { return {a[0].get<double>(), a[1].get<double>(), a[2].get<double>()}; }
inline double dist(V3 a, V3 b) { return std::hypot(a.x - b.x, a.y - b.y, a.z - b.z); }
#define EXPECT_V3_NEAR(actual, ex, ey, ez, tol) \
  do {                                          \
    const V3 v_ = (actual);                     \
    EXPECT_NEAR(v_.x, (ex), (tol));             \
    EXPECT_NEAR(v_.y, (ey), (tol));             \
    EXPECT_NEAR(v_.z, (ez), (tol));             \
  } while (0)

}  // namespace rigel::cli::testing
