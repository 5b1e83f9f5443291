#pragma once
// The rig commands of `rigel` (docs/RIG.md, "Building and updating"):
// `build` (a definition onto a character), `update` (rebuild what changed,
// keeping animation), `rigs` (the Rig Manager's list), `remove` and
// `address` (nameless addresses), `edit` (rig edit mode), `meta` (metadata queries). main.cc registers them with
// add_rig_commands() and runs the chosen one with run_rig_commands().

#include <memory>
#include <optional>
#include <string>

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

// `rigel build`, which `rigel graph run` runs too.
struct BuildArgs {
  std::string definition;  // a definition or a build graph
  std::string character;   // "" = the definition's first geometry file
  std::string output;
  int steps = -1;  // -1 = all
  bool edit_mode = false;
  bool json = false;
};
int run_build(const BuildArgs& args);
std::optional<int> run_rig_commands(const RigCommands& commands);

}  // namespace rigel::cli
