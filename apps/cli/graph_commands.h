#pragma once
// `rigel graph run|convert|validate`: build graphs (docs/BUILD_GRAPH.md).
// main.cc registers them with add_graph_commands() and runs the chosen one
// with run_graph_commands().

#include <memory>
#include <optional>

#include <CLI/CLI.hpp>

namespace rigel::cli {

class GraphCommands {
 public:
  GraphCommands();
  ~GraphCommands();
  GraphCommands(const GraphCommands&) = delete;
  GraphCommands& operator=(const GraphCommands&) = delete;

  struct State;
  State& state() { return *state_; }
  const State& state() const { return *state_; }

 private:
  std::unique_ptr<State> state_;
};

void add_graph_commands(CLI::App& app, GraphCommands& commands);
std::optional<int> run_graph_commands(const GraphCommands& commands);

}  // namespace rigel::cli
