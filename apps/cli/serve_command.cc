// `rigel serve` (serve_command.h).

#include "serve_command.h"

#include <pthread.h>
#include <signal.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <thread>

#include <nlohmann/json.hpp>

#include "cli_util.h"
#include "http_server.h"
#include "rigel/app/workspace.h"
#include "rigel/ephemeral/component.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/io/scene_file.h"
#include "rigel/rig/manager.h"
#include "rigel/tools/data_files.h"
#include "workspace.h"

#ifndef RIGEL_WEB_DIR
#define RIGEL_WEB_DIR ""
#endif

namespace rigel::cli {
namespace {

namespace fs = std::filesystem;

std::string random_token() {
  std::random_device rd;
  std::string t;
  static const char* kHex = "0123456789abcdef";
  for (int i = 0; i < 32; ++i) t += kHex[rd() % 16];
  return t;
}

}  // namespace

CLI::App* add_serve_command(CLI::App& app, ServeArgs& a) {
  CLI::App* cmd = app.add_subcommand("serve", "Serve a scene to the web app and the JSON API (docs/SERVER.md)");
  cmd->footer(
      "Examples:\n"
      "  rigel serve shot.rigel                      # http://127.0.0.1:8080/\n"
      "  rigel serve tests/data/gltf/rigify_human_metarig.glb --rig examples/puppet.rig.xml --port 0\n"
      "  rigel serve shot.rigel --host 0.0.0.0 --token s3cret   # other machines: writes need the token");
  cmd->add_option("SCENE", a.scene, "Scene (.rigel) or character (.glb, .gltf, .bvh); default: an empty scene");
  cmd->add_option("--host", a.host, "Address to listen on (default 127.0.0.1; any other needs a token)");
  cmd->add_option("--port", a.port, "Port (default 8080; 0: any free port)")->check(CLI::Range(0, 65535));
  cmd->add_option("--root", a.root, "Folder that request paths (definitions, saves) are confined to (default: .)");
  cmd->add_option("--web", a.web, "The built web app (default: web/dist of this source tree)");
  cmd->add_option("--token", a.token, "Token every write must carry (generated when --host is not loopback)");
  cmd->add_option("--rig", a.rigs, "Build this rig definition on the scene first (repeatable)");
  cmd->add_flag("--setup-ephemeral", a.setup_ephemeral, "Give every joint an ephemeral control first");
  cmd->add_option("--shape-radius", a.shape_radius,
                  "Largest radius of the controls --setup-ephemeral draws, each sized from its joint's bones (default 0.03)")
      ->check(CLI::PositiveNumber);
  cmd->add_flag("--fixed-shape-size", a.fixed_shape_size, "Draw every --setup-ephemeral control at --shape-radius");
  cmd->add_option("--port-file", a.port_file, "Write the port here once listening (for scripts using --port 0)");
  cmd->add_flag("--log", a.log, "Print one line per request on stderr");
  cmd->add_flag("--json", a.json, "Print {\"url\", \"port\", \"token\"} on stdout once listening");
  return cmd;
}

int run_serve(const ServeArgs& a) {
  std::unique_ptr<scene::Scene> scene;
  fs::path scene_path;
  if (a.scene.empty()) {
    scene = std::make_unique<scene::Scene>(ephemeral::default_registry());
  } else {
    auto loaded = load_or_import(a.scene);
    if (!loaded) return fail(loaded.status().with_context(a.scene));
    scene = std::move(*loaded);
    if (app::is_scene_file(a.scene)) scene_path = fs::absolute(a.scene);
  }
  if (a.setup_ephemeral) {
    ephemeral::SetupOptions options;
    options.shape_radius = a.shape_radius;
    options.size_from_bones = !a.fixed_shape_size;
    auto r = ephemeral::setup_ephemeral(*scene, options);
    if (!r) return fail(r.status().with_context(a.scene));
  }
  for (const std::string& def : a.rigs) {
    auto r = rig::add_rig(*scene, fs::absolute(def), tools::components());
    if (!r) return fail(r.status());
    std::cerr << "rigel: built " << r->name << " " << r->version << " (" << r->components.size() << " components)\n";
  }
  // What was built before serving is where undo starts.
  scene->graph().clear_history();

  std::error_code ec;
  if (!fs::is_directory(a.root, ec)) return usage_error("--root " + a.root + ": not a folder");
  server::ServeOptions options;
  options.host = a.host;
  options.port = a.port;
  options.log = a.log;
  options.token = a.token;
  if (!server::is_loopback(a.host) && options.token.empty()) options.token = random_token();
  if (!a.web.empty()) {
    options.web_dir = a.web;
  } else if (fs::is_regular_file(fs::path(RIGEL_WEB_DIR) / "index.html", ec)) {
    options.web_dir = RIGEL_WEB_DIR;
  } else {
    std::cerr << "rigel: warning: the web app is not built (" << RIGEL_WEB_DIR
              << "); serving the API only. Build it with scripts/test or `npm ci && npm run build` in web/\n";
  }

  server::Workspace workspace(std::move(scene), scene_path, fs::absolute(a.root), tools::components());
  if (!a.scene.empty()) workspace.set_character(fs::absolute(a.scene).lexically_normal());
  server::HttpServer http(workspace, options);

  // SIGINT / SIGTERM stop the server from a thread of ours (stop() is not
  // async-signal-safe); blocked here, before the server's threads exist.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);

  auto port = http.bind();
  if (!port) return fail(port.status());
  const std::string url = "http://" + (a.host.find(':') != std::string::npos ? "[" + a.host + "]" : a.host) + ":" +
                          std::to_string(*port) + "/" + (options.token.empty() ? "" : "?token=" + options.token);
  if (!a.port_file.empty()) {
    if (Status s = io::write_file_atomic(a.port_file, std::to_string(*port) + "\n"); !s) return fail(s);
  }
  if (a.json) {
    std::cout << nlohmann::json{{"url", url}, {"port", *port}, {"token", options.token}}.dump() << std::endl;
  } else {
    std::cout << "rigel: serving " << (a.scene.empty() ? "an empty scene" : a.scene) << " at " << url << std::endl;
  }

  std::thread waiter([&http, signals] {
    int sig = 0;
    sigwait(&signals, &sig);
    http.stop();
  });
  Status s = http.run();
  // Wake the waiter if the server ended by itself.
  pthread_kill(waiter.native_handle(), SIGTERM);
  waiter.join();
  if (!s) return fail(s);
  std::cerr << "rigel: server stopped\n";
  return 0;
}

}  // namespace rigel::cli
