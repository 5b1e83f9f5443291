#pragma once
// `rigel space`: a control's spaces (rig/spaces.h) listed, added, switched
// at a frame or baked over a range (tools/spaces.h), through
// app::Workspace. main.cc registers it with add_space_command() and runs it
// with run_space_command().

#include <memory>
#include <optional>

#include <CLI/CLI.hpp>

namespace rigel::cli {

class SpaceCommand {
 public:
  SpaceCommand();
  ~SpaceCommand();
  SpaceCommand(const SpaceCommand&) = delete;
  SpaceCommand& operator=(const SpaceCommand&) = delete;

  struct State;
  State& state() { return *state_; }
  const State& state() const { return *state_; }

 private:
  std::unique_ptr<State> state_;
};

void add_space_command(CLI::App& app, SpaceCommand& command);
std::optional<int> run_space_command(const SpaceCommand& command);

}  // namespace rigel::cli
