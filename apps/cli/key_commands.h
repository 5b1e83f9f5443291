#pragma once
// `rigel key`, `rigel keys` and `rigel tween`: keys on any keyable channel of any rig's
// controls and switches (built and ephemeral rigs alike), through
// app::Workspace's channel keys (tools/keys.h). main.cc registers them
// with add_key_commands() and runs the chosen one with run_key_commands().

#include <memory>
#include <optional>

#include <CLI/CLI.hpp>

namespace rigel::cli {

class KeyCommands {
 public:
  KeyCommands();
  ~KeyCommands();
  KeyCommands(const KeyCommands&) = delete;
  KeyCommands& operator=(const KeyCommands&) = delete;

  struct State;
  State& state() { return *state_; }
  const State& state() const { return *state_; }

 private:
  std::unique_ptr<State> state_;
};

void add_key_commands(CLI::App& app, KeyCommands& commands);
std::optional<int> run_key_commands(const KeyCommands& commands);

}  // namespace rigel::cli
