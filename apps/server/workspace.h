#pragma once
// What `rigel serve` holds and answers: an app::Workspace (one scene, its
// posing session and its rigs) behind the JSON API of docs/SERVER.md. This
// file only turns JSON into app calls and app answers into JSON: every rule
// is the app layer's. The HTTP side (http_server.h) only moves bytes, so
// tests drive the API without sockets and the server adds nothing to it.
//
// Requests are served one at a time (a mutex), so every answer is a
// consistent state, whatever the number of tabs and scripts. Every change
// increments `revision`, which clients poll to notice the others' edits.

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include <nlohmann/json.hpp>

#include "rigel/app/workspace.h"
#include "rigel/base/status.h"
#include "rigel/rig/component.h"
#include "rigel/scene/scene.h"

namespace rigel::server {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

struct Request {
  std::string method;  // "GET", "POST", ...
  std::string path;    // "/api/pose" (no query)
  std::map<std::string, std::string> query;
  std::string body;
};

struct Response {
  int status = 200;
  std::string body;
  std::string content_type = "application/json";
};

// The largest request body the API takes (413 above it).
inline constexpr std::size_t kMaxBody = 4u << 20;
// The farthest a request may move the current time from 0, in frames
// (POST /api/time; 400 beyond it).
inline constexpr double kMaxFrame = app::kMaxFrame;

class Workspace {
 public:
  // `scene_path`: where "save" without a path writes (may be empty: then a
  // save needs a path). `root`: the folder request paths are relative to and
  // confined in. `factory`: the component classes builds use.
  Workspace(std::unique_ptr<scene::Scene> scene, fs::path scene_path, fs::path root,
            const rig::ComponentFactory& factory);
  ~Workspace();
  Workspace(const Workspace&) = delete;
  Workspace& operator=(const Workspace&) = delete;

  // Answers one API request (any path under /api). Never throws.
  Response handle(const Request& request);

  std::uint64_t revision() const;
  // The character file the scene was opened from (GET /api/scene's
  // `character`: the geometry of a definition the editor starts).
  void set_character(fs::path file);
  // For tests and the CLI: the workspace and its scene, under the caller's
  // care (no request must be running).
  app::Workspace& workspace() { return *app_; }
  scene::Scene& scene() { return app_->scene(); }

 private:
  struct Impl;
  std::unique_ptr<app::Workspace> app_;
  std::unique_ptr<Impl> impl_;
  mutable std::mutex mutex_;
};

// `path` (relative, from a request) resolved inside `root` (app::confined_path).
using app::confined_path;

}  // namespace rigel::server
