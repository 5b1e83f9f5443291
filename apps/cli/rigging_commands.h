#pragma once
// `rigel shape`, `rigel align`, `rigel locator`, `rigel mirror-joints` and
// `rigel driven-key`: the rigger actions (tools/rigging.h,
// tools/driven_poses.h, app::Workspace's rigger actions) on a scene file,
// each writing the scene (-o) and reporting with --json.

#include <memory>
#include <optional>

#include <CLI/CLI.hpp>

namespace rigel::cli {

class RiggingCommands {
 public:
  RiggingCommands();
  ~RiggingCommands();
  RiggingCommands(const RiggingCommands&) = delete;
  RiggingCommands& operator=(const RiggingCommands&) = delete;

  struct State;
  State& state() { return *state_; }
  const State& state() const { return *state_; }

 private:
  std::unique_ptr<State> state_;
};

void add_rigging_commands(CLI::App& app, RiggingCommands& commands);
std::optional<int> run_rigging_commands(const RiggingCommands& commands);

}  // namespace rigel::cli
