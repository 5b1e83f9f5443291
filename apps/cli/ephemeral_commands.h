#pragma once
// The ephemeral-rig commands of `rigel`: `ephemeral setup|relations|key|keys|
// scope|merge|unmerge` (docs/EPHEMERAL.md, README "Posing with ephemeral
// rigs"; `pose` is pose_command.h). main.cc registers them with add_ephemeral_commands() and
// runs the chosen one with run_ephemeral_commands().

#include <memory>
#include <optional>

#include <CLI/CLI.hpp>

namespace rigel::cli {

// What the ephemeral commands' options parse into, and their subcommands.
// Stays in place (options hold references into it) for as long as the app.
class EphemeralCommands {
 public:
  EphemeralCommands();
  ~EphemeralCommands();
  EphemeralCommands(const EphemeralCommands&) = delete;
  EphemeralCommands& operator=(const EphemeralCommands&) = delete;

  struct State;
  State& state() { return *state_; }
  const State& state() const { return *state_; }

 private:
  std::unique_ptr<State> state_;
};

// Adds the `ephemeral` command (with its subcommands) and `pose` to `app`,
// parsing into `commands`.
void add_ephemeral_commands(CLI::App& app, EphemeralCommands& commands);

// After app.parse(): the exit status of the chosen command when it is one of
// the commands added by add_ephemeral_commands(); nullopt otherwise.
std::optional<int> run_ephemeral_commands(const EphemeralCommands& commands);

}  // namespace rigel::cli
