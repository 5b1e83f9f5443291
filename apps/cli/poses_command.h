#pragma once
// `rigel poses save|apply|list|remove LIBRARY ...` (issue "Animate a shot":
// the pose library, tools/poses.h), through app::Workspace. main.cc
// registers it with add_poses_command() and runs it with run_poses_command().

#include <memory>
#include <optional>

#include <CLI/CLI.hpp>

namespace rigel::cli {

class PosesCommand {
 public:
  PosesCommand();
  ~PosesCommand();
  PosesCommand(const PosesCommand&) = delete;
  PosesCommand& operator=(const PosesCommand&) = delete;

  struct State;
  State& state() { return *state_; }
  const State& state() const { return *state_; }

 private:
  std::unique_ptr<State> state_;
};

void add_poses_command(CLI::App& app, PosesCommand& command);
std::optional<int> run_poses_command(const PosesCommand& command);

}  // namespace rigel::cli
