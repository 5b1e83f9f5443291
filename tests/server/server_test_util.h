#pragma once
// Shared by the server tests: a Workspace on the bundled character (with
// the web app's default rig, examples/puppet.rig.xml, or bare), in a
// temporary root folder, and JSON helpers over its API.

#include <gtest/gtest.h>

#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

#include "rigel/ephemeral/component.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/io/gltf_import.h"
#include "rigel/io/scene_file.h"
#include "rigel/rig/manager.h"
#include "../io/io_test_util.h"
#include "workspace.h"

namespace rigel::server {

namespace fs = std::filesystem;

using io::testing::read_text;
using io::testing::TempDir;
using io::testing::write_text;

inline fs::path source_path(const std::string& relative) { return fs::path(RIGEL_SOURCE_DIR) / relative; }

struct Served {
  std::unique_ptr<TempDir> dir = std::make_unique<TempDir>();
  fs::path root;
  std::unique_ptr<Workspace> workspace;

  Response request(const std::string& method, const std::string& target, const std::string& body) {
    Request r{method, target, {}, body};
    if (auto q = target.find('?'); q != std::string::npos) {
      r.path = target.substr(0, q);
      std::stringstream ss(target.substr(q + 1));
      for (std::string kv; std::getline(ss, kv, '&');) r.query[kv.substr(0, kv.find('='))] = kv.substr(kv.find('=') + 1);
    }
    return workspace->handle(r);
  }
  Json get(const std::string& target) {
    Response r = request("GET", target, "");
    EXPECT_EQ(r.status, 200) << "GET " << target << ": " << r.body;
    return Json::parse(r.body);
  }
  Json post(const std::string& target, const Json& body) {
    Response r = request("POST", target, body.dump());
    EXPECT_EQ(r.status, 200) << "POST " << target << " " << body.dump() << ": " << r.body;
    return Json::parse(r.body);
  }
  std::string uuid(const std::string& name) {
    const graph::Graph& g = workspace->scene().graph();
    const graph::NodeId id = g.find(name);
    EXPECT_TRUE(id.is_valid()) << name;
    return id.is_valid() ? g.node(id)->uuid().str() : std::string();
  }
  // The uuid of the ephemeral control standing for a joint.
  std::string control(const std::string& joint) {
    const graph::Graph& g = workspace->scene().graph();
    const graph::NodeId c = ephemeral::control_of(g, g.find(joint));
    EXPECT_TRUE(c.is_valid()) << joint;
    return c.is_valid() ? g.node(c)->uuid().str() : std::string();
  }
  // Largest difference of the pose numbers (t, q, s) of node `name`.
  double distance(const Json& a, const Json& b, const std::string& name) {
    const std::string id = uuid(name);
    double d = 0;
    for (std::size_t i = 0; i < 10; ++i) d = std::max(d, std::abs(a[id][i].get<double>() - b[id][i].get<double>()));
    return d;
  }
  double position_distance(const Json& a, const Json& b, const std::string& name) {
    const std::string id = uuid(name);
    double d = 0;
    for (std::size_t i = 0; i < 3; ++i) d += std::pow(a[id][i].get<double>() - b[id][i].get<double>(), 2);
    return std::sqrt(d);
  }
};

inline std::unique_ptr<scene::Scene> bundled_character() {
  // Over the registry with the rig and ephemeral types (as `rigel serve`).
  io::GltfImportOptions options;
  options.registry = ephemeral::default_registry();
  auto imported = io::import_gltf(source_path("tests/data/gltf/rigify_human_metarig.glb"), options);
  EXPECT_TRUE(imported.is_ok()) << imported.status().message();
  return std::move(*imported);
}

// The character without a rig.
inline Served served_character() {
  Served s;
  s.root = s.dir->path() / "root";
  fs::create_directories(s.root);
  s.workspace = std::make_unique<Workspace>(bundled_character(), fs::path(), s.root, ephemeral::components());
  return s;
}

// The character with examples/puppet.rig.xml built (160 controls), history cleared.
// The bundled character with the biped (examples/biped.rig.xml) built on
// it, served from a root folder of its own, history cleared.
inline Served served_biped() {
  Served s;
  s.root = s.dir->path() / "root";
  fs::create_directories(s.root);
  auto scene = bundled_character();
  EXPECT_TRUE(rig::add_rig(*scene, source_path("examples/biped.rig.xml"), ephemeral::components()).is_ok());
  scene->graph().clear_history();
  s.workspace = std::make_unique<Workspace>(std::move(scene), fs::path(), s.root, ephemeral::components());
  return s;
}

inline Served served_puppet() {
  Served s;
  s.root = s.dir->path() / "root";
  fs::create_directories(s.root);
  auto scene = bundled_character();
  auto added = rig::add_rig(*scene, source_path("examples/puppet.rig.xml"), ephemeral::components());
  EXPECT_TRUE(added.is_ok()) << added.status().message();
  scene->graph().clear_history();
  s.workspace = std::make_unique<Workspace>(std::move(scene), fs::path(), s.root, ephemeral::components());
  return s;
}

// A global control and an FK chain on the left arm, as the definition
// editor sends it (.rig.json form).
inline Json two_component_definition() {
  return Json::parse(R"({
    "rig": {
      "name": "arm",
      "version": "1.0",
      "components": [{
        "type": "global", "name": "global", "side": "C", "version": "1.0",
        "rigId": "0b9f1e36-5a1e-4d8c-9a55-2f3c1d7e8a01",
        "guides": [{"name": "main"}],
        "controls": [{"role": "main", "shape": "fourArrowCircle", "color": "yellow", "size": 0.8}],
        "children": [{
          "type": "fkChain", "name": "arm", "side": "L", "version": "1.0",
          "rigId": "7c2d4b9e-3f1a-4e6b-8d0c-5a9b2e1f3c02",
          "guides": [{"joint": "upper_arm.L"}, {"joint": "forearm.L"}, {"joint": "hand.L"}],
          "controls": [{"role": "fk", "shape": "circle", "color": "blue", "size": 0.1}]
        }]
      }]
    }
  })");
}

}  // namespace rigel::server
