#pragma once
// Helpers shared by the `rigel` commands (main.cc, ephemeral_commands.cc):
// exit codes, error reporting, reading scenes, parsing option values and
// resolving the names given to options.

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "rigel/base/status.h"
#include "rigel/graph/graph.h"
#include "rigel/math/types.h"
#include "rigel/scene/scene.h"

namespace rigel::cli {

// Exit status: 0 success, 1 invalid input, 2 usage error (DESIGN.md).
inline constexpr int kExitInvalidInput = 1;
inline constexpr int kExitUsage = 2;

// Prints "rigel: MESSAGE" on stderr; returns kExitInvalidInput.
int fail(const Status& status);
// Prints "rigel: MESSAGE" on stderr; returns kExitUsage.
int usage_error(const std::string& message);

// Every .rigel file is read over ephemeral::default_registry() (the ops types
// plus ephemeralRig), so scenes holding an ephemeral rig load everywhere.
Result<std::unique_ptr<scene::Scene>> load(const std::string& path);

// A .rigel scene that holds an ephemeral rig (kNotFound saying how to make one).
Result<std::unique_ptr<scene::Scene>> load_rigged(const std::string& path);

// A .rigel scene, or a character (.glb, .gltf, .bvh) imported as `rigel
// import` does (units kept); either way over ephemeral::default_registry().
Result<std::unique_ptr<scene::Scene>> load_or_import(const std::string& path);
// The extension of `path`, lower case, with its dot ("" when none).
std::string lower_extension(const std::string& path);

// One finite number filling all of [begin, end); nullopt for anything else.
std::optional<double> parse_number(const char* begin, const char* end);
// "X,Y,Z" as three finite numbers; nullopt for anything else.
std::optional<math::Vec3> parse_vec3(const std::string& text);
// "A:B" as two finite numbers; nullopt for anything else.
std::optional<std::pair<double, double>> parse_frames(const std::string& text);
// What --frames expects, for its error messages.
inline constexpr const char* kFramesExpected = "expected FIRST:LAST, two frame numbers such as 0:120";
// `value` as printf's %g writes it.
std::string number_text(double value);

// `name` given to `option` as a control (a joint stands for its control).
Result<graph::NodeId> resolve_control(const graph::Graph& g, const std::string& scene, const std::string& option,
                                      const std::string& name);
// `name` given to `option` as an ephemeralRig node.
Result<graph::NodeId> resolve_rig(const graph::Graph& g, const std::string& scene, const std::string& option,
                                  const std::string& name);

// Progress of long work as "rigel: WHAT NN%" on stderr, on a terminal only
// (callback() is empty elsewhere); finish() ends the line it started.
class TerminalProgress {
 public:
  explicit TerminalProgress(std::string what) : what_(std::move(what)) {}
  std::function<void(double)> callback();
  void finish();

 private:
  std::string what_;
  int last_ = -1;
  bool shown_ = false;
};

}  // namespace rigel::cli
