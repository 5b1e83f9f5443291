#pragma once
// The scene-file commands of `rigel` (DESIGN.md's CLI contract): `inspect`
// (nodes, hierarchy, connections), `eval` (world transforms at a time, a
// clip chosen), `import` (a character or motion into a scene file),
// `export` (glTF 2.0) and `bake` (what the rigs make nodes do, into keys).
// Each is app/scene_files.h's operation with its options and its output.
// main.cc registers them with add_scene_commands() and runs the chosen one
// with run_scene_commands().

#include <memory>
#include <optional>

#include <CLI/CLI.hpp>

namespace rigel::cli {

class SceneCommands {
 public:
  SceneCommands();
  ~SceneCommands();
  SceneCommands(const SceneCommands&) = delete;
  SceneCommands& operator=(const SceneCommands&) = delete;

  struct State;
  State& state() { return *state_; }
  const State& state() const { return *state_; }

 private:
  std::unique_ptr<State> state_;
};

void add_scene_commands(CLI::App& app, SceneCommands& commands);
std::optional<int> run_scene_commands(const SceneCommands& commands);

}  // namespace rigel::cli
