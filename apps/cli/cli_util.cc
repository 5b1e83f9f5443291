#include "cli_util.h"

#include <unistd.h>

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "rigel/app/scene_files.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/io/scene_file.h"

namespace rigel::cli {

using graph::NodeId;

int fail(const Status& status) {
  std::cerr << "rigel: " << status.message() << "\n";
  return kExitInvalidInput;
}

int usage_error(const std::string& message) {
  std::cerr << "rigel: " << message << "\n";
  return kExitUsage;
}

Result<std::unique_ptr<scene::Scene>> load(const std::string& path) {
  return io::load_scene(path, ephemeral::default_registry());
}

Result<std::unique_ptr<scene::Scene>> load_rigged(const std::string& path) {
  auto scene = load(path);
  if (!scene) return scene.status();
  if (ephemeral::rigs_find((*scene)->graph()).empty()) {
    return Status(ErrorCode::kNotFound,
                  path + ": the scene has no ephemeral rig; run `rigel ephemeral setup " + path + " -o OUT.rigel` first");
  }
  return scene;
}

Result<std::unique_ptr<scene::Scene>> load_or_import(const std::string& path) { return app::open_scene(path); }

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

std::optional<double> parse_number(const char* begin, const char* end) {
  double value = 0.0;
  const auto [ptr, ec] = std::from_chars(begin, end, value);
  if (ec != std::errc() || ptr != end || begin == end || !std::isfinite(value)) return std::nullopt;
  return value;
}

std::optional<math::Vec3> parse_vec3(const std::string& text) {
  math::Vec3 v;
  std::size_t start = 0;
  for (int i = 0; i < 3; ++i) {
    const std::size_t comma = i < 2 ? text.find(',', start) : text.size();
    if (comma == std::string::npos) return std::nullopt;
    const auto number = parse_number(text.data() + start, text.data() + comma);
    if (!number) return std::nullopt;
    v[i] = *number;
    start = comma + 1;
  }
  return v;
}

std::optional<std::pair<double, double>> parse_frames(const std::string& text) {
  const std::size_t colon = text.find(':');
  if (colon == std::string::npos) return std::nullopt;
  const auto first = parse_number(text.data(), text.data() + colon);
  const auto last = parse_number(text.data() + colon + 1, text.data() + text.size());
  if (!first || !last) return std::nullopt;
  return std::pair{*first, *last};
}

std::function<void(double)> TerminalProgress::callback() {
  if (!isatty(STDERR_FILENO)) return {};
  return [this](double fraction) {
    const int percent = static_cast<int>(fraction * 100.0);
    if (percent == last_) return;
    last_ = percent;
    shown_ = true;
    std::fprintf(stderr, "\rrigel: %s %3d%%", what_.c_str(), percent);
    std::fflush(stderr);
  };
}

void TerminalProgress::finish() {
  if (shown_) std::fputc('\n', stderr);
  shown_ = false;
}

std::string number_text(double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%g", value);
  return buffer;
}

Result<NodeId> resolve_control(const graph::Graph& g, const std::string& scene, const std::string& option,
                               const std::string& name) {
  const NodeId id = g.find(name);
  if (!id.is_valid()) return Status(ErrorCode::kNotFound, scene + ": " + option + ": no node named '" + name + "'");
  const NodeId control = ephemeral::control_of(g, id);
  if (!control.is_valid()) {
    return Status(ErrorCode::kInvalidArgument, scene + ": " + option + ": '" + name +
                                                   "' is not a control of an ephemeral rig (nor a joint driven by one)");
  }
  return control;
}

Result<NodeId> resolve_rig(const graph::Graph& g, const std::string& scene, const std::string& option,
                           const std::string& name) {
  const NodeId id = g.find(name);
  std::string rigs;
  for (NodeId r : ephemeral::rigs_find(g)) rigs += (rigs.empty() ? "" : ", ") + g.node(r)->name();
  const std::string known = rigs.empty() ? "the scene has no ephemeral rig" : "rigs: " + rigs;
  if (!id.is_valid())
    return Status(ErrorCode::kNotFound, scene + ": " + option + ": no ephemeral rig named '" + name + "' (" + known + ")");
  if (g.node(id)->type().name() != ephemeral::kRigType) {
    return Status(ErrorCode::kInvalidArgument,
                  scene + ": " + option + ": '" + name + "' is not an ephemeralRig node (" + known + ")");
  }
  return id;
}

}  // namespace rigel::cli
