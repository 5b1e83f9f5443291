#pragma once
// `rigel serve`: holds a scene and serves the web app and the JSON API
// (apps/server, docs/SERVER.md) until interrupted.

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace rigel::cli {

struct ServeArgs {
  std::string scene;  // .rigel or a character (.glb, .gltf, .bvh); "" = an empty scene
  std::string host = "127.0.0.1";
  int port = 8080;
  std::string root = ".";
  std::string web;  // "" = the web app this build made
  std::string token;
  std::vector<std::string> rigs;  // definitions to build on load
  bool setup_ephemeral = false;
  double shape_radius = 0.03;
  bool fixed_shape_size = false;
  std::string port_file;
  bool log = false;
  bool json = false;
};

CLI::App* add_serve_command(CLI::App& app, ServeArgs& args);
int run_serve(const ServeArgs& args);

}  // namespace rigel::cli
