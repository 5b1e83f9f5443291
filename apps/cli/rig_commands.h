#pragma once
// The rig commands of `rigel` (docs/RIG.md, "Building and updating"):
// `build` (a definition onto a character), `update` (rebuild what changed,
// keeping animation), `rigs` (the Rig Manager's list), `remove` and
// `address` (nameless addresses), `edit` (rig edit mode), `meta` (metadata queries). main.cc registers them with
// add_rig_commands() and runs the chosen one with run_rig_commands().

#include <memory>
#include <optional>

#include <CLI/CLI.hpp>

namespace rigel::cli {

class RigCommands {
 public:
  RigCommands();
  ~RigCommands();
  RigCommands(const RigCommands&) = delete;
  RigCommands& operator=(const RigCommands&) = delete;

  struct State;
  State& state() { return *state_; }
  const State& state() const { return *state_; }

 private:
  std::unique_ptr<State> state_;
};

void add_rig_commands(CLI::App& app, RigCommands& commands);
std::optional<int> run_rig_commands(const RigCommands& commands);

}  // namespace rigel::cli
