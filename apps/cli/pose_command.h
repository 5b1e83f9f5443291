#pragma once
// `rigel pose`: grabs controls of an ephemeral rig (moved in a mode) or of a
// built rig (moved as they are), moves them once and writes the scene; the
// drag is app::Workspace's, as the server's and Python's are.

#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace rigel::cli {

struct PoseArgs {
  CLI::App* command = nullptr;  // set by add_pose_command
  std::string scene;
  std::string output;
  std::string control;
  std::string mode;
  std::optional<std::string> translate, rotate, scale, pivot;
  std::vector<std::string> select;
  std::optional<double> frame;
  std::optional<double> time;
  std::optional<double> magnet_fraction;
  std::optional<double> magnet_radius;
  std::optional<int> max_chain;
  bool auto_key = false;
  bool key = false;
  bool json = false;
};

void add_pose_command(CLI::App& app, PoseArgs& args);
int run_pose(const PoseArgs& args);

}  // namespace rigel::cli
