// `rigel serve` (issue 6's target): the API round trip of one drag on the
// web app's default character (Rigify's human metarig with
// examples/puppet.rig.xml: 160 controls) over loopback, from the client's
// send to the parsed JSON answer (the pose of every node). Target: p50 at
// most 2 ms. The in-process variant (Workspace::handle, no sockets) shows
// what the HTTP layer adds; the pose variant is a GET of the pose alone.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <thread>
#include <vector>

#include "http_server.h"
#include "rigel/ephemeral/component.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/io/gltf_import.h"
#include "rigel/io/scene_file.h"
#include "rigel/rig/manager.h"
#include "workspace.h"

// After Eigen: <resolv.h>, which httplib includes, defines a macro `_res`.
#include <httplib.h>

namespace rigel::bench {
namespace {

namespace fs = std::filesystem;

std::unique_ptr<server::Workspace> puppet_workspace() {
  auto imported = io::import_gltf(fs::path(RIGEL_SOURCE_DIR) / "tests/data/gltf/rigify_human_metarig.glb");
  if (!imported) throw std::runtime_error(imported.status().message());
  auto scene = io::parse_scene(io::write_scene(**imported), "metarig", ephemeral::default_registry());
  if (!scene) throw std::runtime_error(scene.status().message());
  auto added = rig::add_rig(**scene, fs::path(RIGEL_SOURCE_DIR) / "examples/puppet.rig.xml", ephemeral::components());
  if (!added) throw std::runtime_error(added.status().message());
  (*scene)->graph().clear_history();
  return std::make_unique<server::Workspace>(std::move(*scene), fs::path(), fs::temp_directory_path(),
                                             ephemeral::components());
}

// p50 / p99 of per-iteration times, as counters (milliseconds).
void report(benchmark::State& state, std::vector<double>& ms) {
  if (ms.empty()) return;
  std::sort(ms.begin(), ms.end());
  state.counters["p50_ms"] = ms[ms.size() / 2];
  state.counters["p99_ms"] = ms[std::min(ms.size() - 1, ms.size() * 99 / 100)];
}

const char* kModes[] = {"forward", "pseudo-inverse", "inverse", "magnet", "body"};

// One drag, answered with the pose (the web app's request while dragging).
void BM_ServerDragRoundTrip(benchmark::State& state) {
  auto workspace = puppet_workspace();
  server::ServeOptions options;
  options.port = 0;
  server::HttpServer http(*workspace, options);
  auto port = http.bind();
  if (!port) {
    state.SkipWithError(port.status().message().c_str());
    return;
  }
  std::thread serving([&http] { (void)http.run(); });
  httplib::Client client("127.0.0.1", *port);
  client.set_keep_alive(true);
  client.set_tcp_nodelay(true);
  while (!client.Get("/api/revision")) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  client.Post("/api/select", R"({"controls": ["hand.L"]})", "application/json");
  const std::string mode = std::string("{\"mode\": \"") + kModes[state.range(0)] + "\"}";
  client.Post("/api/mode", mode, "application/json");
  std::vector<double> ms;
  int i = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    const std::string body = std::string("{\"translate\": [0, ") + (i++ % 2 ? "0.002" : "-0.002") + ", 0]}";
    auto res = client.Post("/api/drag", body, "application/json");
    if (!res || res->status != 200) {
      state.SkipWithError(res ? res->body.c_str() : "no answer");
      break;
    }
    auto pose = nlohmann::json::parse(res->body);  // the client's side of "including the JSON"
    benchmark::DoNotOptimize(pose);
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  report(state, ms);
  state.SetLabel(kModes[state.range(0)]);
  http.stop();
  serving.join();
}
BENCHMARK(BM_ServerDragRoundTrip)->DenseRange(0, 4)->Unit(benchmark::kMillisecond)->Iterations(400);

// The same drag answered in-process: the API without HTTP.
void BM_ServerDragInProcess(benchmark::State& state) {
  auto workspace = puppet_workspace();
  workspace->handle({"POST", "/api/select", {}, R"({"controls": ["hand.L"]})"});
  workspace->handle({"POST", "/api/mode", {}, R"({"mode": "pseudo-inverse"})"});
  std::vector<double> ms;
  int i = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    auto r = workspace->handle(
        {"POST", "/api/drag", {}, std::string("{\"translate\": [0, ") + (i++ % 2 ? "0.002" : "-0.002") + ", 0]}"});
    benchmark::DoNotOptimize(r);
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  report(state, ms);
}
BENCHMARK(BM_ServerDragInProcess)->Unit(benchmark::kMillisecond)->Iterations(400);

// The pose alone (what a tab fetches when another one changed the scene).
void BM_ServerPoseInProcess(benchmark::State& state) {
  auto workspace = puppet_workspace();
  for (auto _ : state) {
    auto r = workspace->handle({"GET", "/api/pose", {}, ""});
    benchmark::DoNotOptimize(r);
  }
}
BENCHMARK(BM_ServerPoseInProcess)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace rigel::bench
