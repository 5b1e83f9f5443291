#pragma once
// `rigel project new|info`, `rigel asset new|info`, `rigel config
// get|set|unset|list` and `rigel data export|import weights|shapes`: the
// rigging pipeline's projects, assets, settings and data managers
// (tools/project.h, tools/config.h, tools/skin_weights.h,
// tools/shape_data.h); and the log level every command takes
// (`--log-level`, else the settings' log.level).

#include <memory>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "rigel/tools/config.h"
#include "rigel/tools/project.h"

namespace rigel::cli {

class PipelineCommands {
 public:
  PipelineCommands();
  ~PipelineCommands();
  PipelineCommands(const PipelineCommands&) = delete;
  PipelineCommands& operator=(const PipelineCommands&) = delete;

  struct State;
  State& state() { return *state_; }
  const State& state() const { return *state_; }

 private:
  std::unique_ptr<State> state_;
};

void add_pipeline_commands(CLI::App& app, PipelineCommands& commands);
std::optional<int> run_pipeline_commands(const PipelineCommands& commands);

// `--log-level LEVEL` on the main command (and, falling through, after any
// subcommand).
void add_log_level_option(CLI::App& app, std::string& level);
// Sets the log level: `given` when set (a usage error for an unknown
// level), else the settings' log.level (the user's and the current
// project's; a malformed settings file is reported as a warning and left
// out). nullopt when fine, else the exit code.
std::optional<int> apply_log_level(const std::string& given);
// A file a command was given, resolved against the asset the current
// folder is in (tools::resolve_in_asset: a bare name looked up in the
// asset's folder for that kind); as given outside an asset or when nothing
// there matches (the command then reports it missing).
std::string in_current_asset(const std::string& given, tools::AssetFile kind);
// The skeleton of the asset the current folder is in ("" outside one).
std::string current_asset_skeleton();

// The settings apply_log_level read (the user's and the current project's;
// the defaults before it ran or when a file was malformed).
const tools::Config& settings();

}  // namespace rigel::cli
