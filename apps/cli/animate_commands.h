#pragma once
// The animator tools' commands (issue "Animate a shot"): `rigel match`
// (FK/IK match and bake, tools/match.h) and `rigel mirror` (tools/mirror.h),
// through app::Workspace. main.cc
// registers them with add_animate_commands() and runs the chosen one with
// run_animate_commands().

#include <memory>
#include <optional>

#include <CLI/CLI.hpp>

namespace rigel::cli {

class AnimateCommands {
 public:
  AnimateCommands();
  ~AnimateCommands();
  AnimateCommands(const AnimateCommands&) = delete;
  AnimateCommands& operator=(const AnimateCommands&) = delete;

  struct State;
  State& state() { return *state_; }
  const State& state() const { return *state_; }

 private:
  std::unique_ptr<State> state_;
};

void add_animate_commands(CLI::App& app, AnimateCommands& commands);
std::optional<int> run_animate_commands(const AnimateCommands& commands);

}  // namespace rigel::cli
