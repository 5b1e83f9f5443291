#pragma once
// `rigel check [record] FILE ...`: rig regression tests (app/rig_checks.h,
// tools/rig_tests.h). main.cc registers it with add_check_command() and
// runs it with run_check_command().

#include <memory>
#include <optional>

#include <CLI/CLI.hpp>

namespace rigel::cli {

class CheckCommand {
 public:
  CheckCommand();
  ~CheckCommand();
  CheckCommand(const CheckCommand&) = delete;
  CheckCommand& operator=(const CheckCommand&) = delete;

  struct State;
  State& state() { return *state_; }
  const State& state() const { return *state_; }

 private:
  std::unique_ptr<State> state_;
};

void add_check_command(CLI::App& app, CheckCommand& command);
std::optional<int> run_check_command(const CheckCommand& command);

}  // namespace rigel::cli
