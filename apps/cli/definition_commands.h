#pragma once
// The rig-definition commands of `rigel`: `validate`, `components`, `schema`
// and `diff` (docs/RIG.md). Thin: parsing, checks and diffs live in the rig
// library (rig/definition_io.h, rig/diff.h); these print. main.cc registers
// them with add_definition_commands() and runs the chosen one with
// run_definition_commands().

#include <memory>
#include <optional>

#include <CLI/CLI.hpp>

namespace rigel::cli {

// What the definition commands' options parse into, and their subcommands.
// Stays in place (options hold references into it) for as long as the app.
class DefinitionCommands {
 public:
  DefinitionCommands();
  ~DefinitionCommands();
  DefinitionCommands(const DefinitionCommands&) = delete;
  DefinitionCommands& operator=(const DefinitionCommands&) = delete;

  struct State;
  State& state() { return *state_; }
  const State& state() const { return *state_; }

 private:
  std::unique_ptr<State> state_;
};

// Adds `validate`, `components`, `schema` and `diff` to `app`, parsing into
// `commands`.
void add_definition_commands(CLI::App& app, DefinitionCommands& commands);

// After app.parse(): the exit status of the chosen command when it is one of
// the commands added by add_definition_commands(); nullopt otherwise.
std::optional<int> run_definition_commands(const DefinitionCommands& commands);

}  // namespace rigel::cli
