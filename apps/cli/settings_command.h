#pragma once
// `rigel playback`, `rigel sets` and `rigel picker`: the scene's playback
// range and named selection sets (scene/scene_options.h), shown or changed,
// the picker's layout of the controls (app::Workspace::picker), and
// `rigel trail`: motion trails (app::Workspace::motion_trails), through
// app::Workspace. main.cc registers them with add_settings_commands() and
// runs them with run_settings_commands().

#include <memory>
#include <optional>

#include <CLI/CLI.hpp>

namespace rigel::cli {

class SettingsCommands {
 public:
  SettingsCommands();
  ~SettingsCommands();
  SettingsCommands(const SettingsCommands&) = delete;
  SettingsCommands& operator=(const SettingsCommands&) = delete;

  struct State;
  State& state() { return *state_; }
  const State& state() const { return *state_; }

 private:
  std::unique_ptr<State> state_;
};

void add_settings_commands(CLI::App& app, SettingsCommands& commands);
std::optional<int> run_settings_commands(const SettingsCommands& commands);

}  // namespace rigel::cli
