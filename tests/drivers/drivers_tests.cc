// The CLI and the server over the same app layer: for each operation both
// offer, the same input gives the same answer (the same scene afterwards,
// or the same refusal). One table: a case runs `rigel` on a scene file and
// the JSON API on the same file, and compares what each left.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "../cli/cli_test_util.h"
#include "rigel/ephemeral/component.h"
#include "rigel/ephemeral/keying.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/io/scene_file.h"
#include "rigel/rig/meta.h"
#include "rigel/scene/transform_types.h"
#include "workspace.h"

namespace rigel {
namespace {

namespace fs = std::filesystem;
using cli::testing::CliRun;
using cli::testing::contains;
using cli::testing::exited_with;
using cli::testing::TempDir;
using Json = nlohmann::ordered_json;

fs::path source(const std::string& relative) { return fs::path(RIGEL_SOURCE_DIR) / relative; }

// What a scene holds after an operation, for comparison: every control's
// world translation (1e-9), the key frames of the controls' keying sets
// and the rigs.
struct Outcome {
  std::map<std::string, math::Vec3> controls;
  std::vector<double> key_frames;
  std::vector<std::string> rigs;
};

Outcome outcome_of(scene::Scene& s) {
  Outcome o;
  graph::Graph& g = s.graph();
  std::vector<graph::NodeId> controls;
  for (graph::NodeId id : s.hierarchy()) {
    if (g.node(id)->type().name() != scene::kControlType) continue;
    controls.push_back(id);
    o.controls[g.node(id)->name()] = s.world_matrix(id).block<3, 1>(0, 3);
  }
  for (double t : ephemeral::key_times(g, controls)) o.key_frames.push_back(std::round(t * g.fps() * 1e6) / 1e6);
  for (graph::NodeId r : rig::list_rigs(g)) o.rigs.push_back(rig::meta_string(g, r, "rigName"));
  return o;
}

void expect_same(const Outcome& cli, const Outcome& api, const std::string& what) {
  EXPECT_EQ(cli.rigs, api.rigs) << what;
  EXPECT_EQ(cli.key_frames, api.key_frames) << what;
  ASSERT_EQ(cli.controls.size(), api.controls.size()) << what;
  double worst = 0;
  std::string where;
  for (const auto& [name, t] : cli.controls) {
    auto it = api.controls.find(name);
    ASSERT_NE(it, api.controls.end()) << what << ": " << name;
    const double d = (t - it->second).norm();
    if (d > worst) worst = d, where = name;
  }
  EXPECT_LT(worst, 1e-9) << what << ": " << where;
}

std::unique_ptr<scene::Scene> load(const fs::path& file) {
  auto s = io::load_scene(file, ephemeral::default_registry());
  EXPECT_TRUE(s.is_ok()) << s.status().message();
  return std::move(*s);
}

// One operation through both drivers. `cli` is the command's words, SCENE
// standing for the scene file (the output file is added); `api` the requests in order
// (method, route, body); a refusal must come from both, with the same
// reason (`refusal`, a part of both messages), exit 2 or 1 and a 4xx.
struct Case {
  std::string name;
  std::string scene;  // "ephemeral" (the character with an ephemeral rig) or "biped" (examples/biped.rig.xml built)
  std::vector<std::string> cli;
  std::vector<std::tuple<std::string, std::string, Json>> api;
  std::string refusal;  // empty: both succeed
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

class Drivers : public ::testing::TestWithParam<Case> {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir();
    const std::string glb = source("tests/data/gltf/rigify_human_metarig.glb").string();
    const std::string ephemeral = (dir_->path() / "ephemeral.rigel").string();
    const std::string biped = (dir_->path() / "biped.rigel").string();
    CliRun r = cli::testing::rigel({"ephemeral", "setup", glb, "-o", ephemeral});
    ASSERT_TRUE(exited_with(r, 0)) << r.err;
    r = cli::testing::rigel({"build", source("examples/biped.rig.xml").string(), "--character", glb, "-o", biped});
    ASSERT_TRUE(exited_with(r, 0)) << r.err;
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static TempDir* dir_;
};
TempDir* Drivers::dir_ = nullptr;

TEST_P(Drivers, same_input_same_answer) {
  const Case& c = GetParam();
  const fs::path scene = dir_->path() / (c.scene + ".rigel");
  const fs::path out = dir_->path() / (c.name + "_cli.rigel");
  std::vector<std::string> words = c.cli;
  for (std::string& w : words)
    if (w == "SCENE") w = scene.string();
  words.insert(words.end(), {"-o", out.string()});
  const CliRun run = cli::testing::rigel(words);

  const fs::path root = dir_->path() / (c.name + "_root");
  fs::create_directories(root);
  server::Workspace api(load(scene), fs::path(), root, ephemeral::components());
  int status = 200;
  std::string message;
  for (const auto& [method, route, body] : c.api) {
    const auto q = route.find('?');
    server::Request request{method, route.substr(0, q), {}, method == "POST" ? body.dump() : ""};
    if (q != std::string::npos) {
      const std::string kv = route.substr(q + 1);
      request.query[kv.substr(0, kv.find('='))] = kv.substr(kv.find('=') + 1);
    }
    const server::Response r = api.handle(request);
    if (r.status != 200) {
      status = r.status;
      message = Json::parse(r.body)["error"];
      break;
    }
  }

  if (!c.refusal.empty()) {
    EXPECT_TRUE(exited_with(run, 1) || exited_with(run, 2)) << run.err;
    EXPECT_TRUE(contains(run.err, c.refusal)) << run.err;
    EXPECT_GE(status, 400);
    EXPECT_LT(status, 500);
    EXPECT_TRUE(contains(message, c.refusal)) << message;
    EXPECT_FALSE(fs::exists(out)) << "a refused command writes nothing";
    return;
  }
  ASSERT_TRUE(exited_with(run, 0)) << run.err;
  ASSERT_EQ(status, 200) << message;
  expect_same(outcome_of(*load(out)), outcome_of(api.scene()), c.name);
}

Json sel(const std::string& control) { return Json{{"controls", {control}}}; }

INSTANTIATE_TEST_SUITE_P(
    Operations, Drivers,
    ::testing::Values(
        Case{"pose_forward",
             "ephemeral",
             {"pose", "SCENE", "--control", "forearm.L", "--mode", "forward", "--rotate", "0,0,30"},
             {{"POST", "/api/select", sel("forearm.L")},
              {"POST", "/api/mode", {{"mode", "forward"}}},
              {"POST", "/api/drag", {{"rotate", {{"euler", {0, 0, 30}}}}}}},
             ""},
        Case{"pose_inverse_max_chain",
             "ephemeral",
             {"pose", "SCENE", "--control", "hand.L", "--mode", "inverse", "--max-chain", "3", "--translate", "0,0.1,0.05"},
             {{"POST", "/api/options", {{"maxChain", 3}}},
              {"POST", "/api/select", sel("hand.L")},
              {"POST", "/api/mode", {{"mode", "inverse"}}},
              {"POST", "/api/drag", {{"translate", {0, 0.1, 0.05}}}}},
             ""},
        Case{"pose_magnet_fraction",
             "ephemeral",
             {"pose", "SCENE", "--control", "spine.003", "--mode", "magnet", "--magnet-fraction", "0.5", "--translate", "0.1,0,0"},
             {{"POST", "/api/options", {{"magnetFraction", 0.5}}},
              {"POST", "/api/select", sel("spine.003")},
              {"POST", "/api/mode", {{"mode", "magnet"}}},
              {"POST", "/api/drag", {{"translate", {0.1, 0, 0}}}}},
             ""},
        Case{"pose_built_rig_control",
             "biped",
             {"pose", "SCENE", "--control", "hero_arm_L_fk1", "--mode", "forward", "--rotate", "0,20,0"},
             {{"POST", "/api/select", sel("hero_arm_L_fk1")},
              {"POST", "/api/mode", {{"mode", "forward"}}},
              {"POST", "/api/drag", {{"rotate", {{"euler", {0, 20, 0}}}}}}},
             ""},
        Case{"pose_and_key",
             "ephemeral",
             {"pose", "SCENE", "--control", "hand.L", "--mode", "forward", "--frame", "7", "--translate", "0,0.05,0", "--key"},
             {{"POST", "/api/time", {{"frame", 7}}},
              {"POST", "/api/select", sel("hand.L")},
              {"POST", "/api/mode", {{"mode", "forward"}}},
              {"POST", "/api/drag", {{"translate", {0, 0.05, 0}}}},
              {"POST", "/api/release", Json::object()},
              {"POST", "/api/key", Json::object()}},
             ""},
        Case{"key_at_a_frame",
             "ephemeral",
             {"ephemeral", "key", "SCENE", "--control", "hand.L", "--frame", "12"},
             {{"POST", "/api/time", {{"frame", 12}}}, {"POST", "/api/key", sel("hand.L")}},
             ""},
        Case{"key_a_built_rigs_character",
             "biped",
             {"key", "SCENE", "--control", "hero_arm_L_fk1", "--frame", "12"},
             {{"POST", "/api/time", {{"frame", 12}}}, {"POST", "/api/channel-keys", sel("hero_arm_L_fk1")}},
             ""},
        Case{"key_a_switch_by_address_with_a_value",
             "biped",
             {"key", "SCENE", "--control", "hero:arm_L/fkIkSwitch", "--attr", "fkIk", "--value", "1", "--frame", "5"},
             {{"POST", "/api/time", {{"frame", 5}}},
              {"POST", "/api/channel-keys", {{"controls", {"hero:arm_L/fkIkSwitch"}}, {"attrs", {"fkIk"}}, {"value", 1}}}},
             ""},
        Case{"match_a_limb_to_fk_at_a_frame",
             "biped",
             {"match", "SCENE", "--rig", "hero", "--component", "arm_L", "--to", "fk", "--frame", "4"},
             {{"POST", "/api/time", {{"frame", 4}}},
              {"POST", "/api/match", {{"rig", "hero"}, {"component", "arm_L"}, {"to", "fk"}}}},
             ""},
        Case{"mirror_a_control_onto_its_pair",
             "biped",
             {"mirror", "SCENE", "--controls", "hero_arm_L_fk1"},
             {{"POST", "/api/mirror", {{"controls", {"hero_arm_L_fk1"}}}}},
             ""},
        Case{"flip_the_whole_character",
             "biped",
             {"mirror", "SCENE", "--all", "--flip"},
             {{"POST", "/api/mirror", {{"all", true}, {"flip", true}}}},
             ""},
        Case{"bind_pose_of_a_component",
             "biped",
             {"bind-pose", "SCENE", "--controls", "hero:arm_L"},
             {{"POST", "/api/bind-pose", {{"controls", {"hero:arm_L"}}}}},
             ""},
        Case{"refuse_a_match_on_a_component_without_a_switch",
             "biped",
             {"match", "SCENE", "--rig", "hero", "--component", "spine", "--to", "ik"},
             {{"POST", "/api/match", {{"rig", "hero"}, {"component", "spine"}, {"to", "ik"}}}},
             "has no FK/IK switch"},
        Case{"refuse_a_channel_the_control_lacks",
             "biped",
             {"key", "SCENE", "--control", "hero_arm_L_fk1", "--attr", "fkIk"},
             {{"POST", "/api/channel-keys", {{"controls", {"hero_arm_L_fk1"}}, {"attrs", {"fkIk"}}}}},
             "has no keyable channel 'fkIk'"},
        Case{"remove_rig", "biped", {"remove", "SCENE", "--rig", "hero"}, {{"POST", "/api/rigs/remove", {{"rig", "hero"}}}}, ""},
        Case{"update_unchanged_rig", "biped", {"update", "SCENE", "--rig", "hero"}, {{"POST", "/api/rigs/update", {{"rig", "hero"}}}}, ""},
        Case{"refuse_magnet_fraction_out_of_range",
             "ephemeral",
             {"pose", "SCENE", "--control", "hand.L", "--mode", "magnet", "--magnet-fraction", "2"},
             {{"POST", "/api/options", {{"magnetFraction", 2}}}},
             "must be a number in (0, 1]"},
        Case{"refuse_max_chain_out_of_range",
             "ephemeral",
             {"pose", "SCENE", "--control", "hand.L", "--mode", "inverse", "--max-chain", "5000"},
             {{"POST", "/api/options", {{"maxChain", 5000}}}},
             "from 0 (no limit) to 1000"},
        Case{"refuse_frame_out_of_range",
             "ephemeral",
             {"ephemeral", "key", "SCENE", "--control", "hand.L", "--frame", "2000000"},
             {{"POST", "/api/time", {{"frame", 2000000}}}},
             "is out of range (at most 1000000 frames either side of 0)"},
        Case{"refuse_a_node_that_is_no_control",
             "biped",
             {"pose", "SCENE", "--control", "hero_meta", "--mode", "forward", "--translate", "0,1,0"},
             {{"POST", "/api/select", sel("hero_meta")}},
             "is not a control"},
        Case{"refuse_an_unknown_rig", "biped", {"remove", "SCENE", "--rig", "villain"}, {{"POST", "/api/rigs/remove", {{"rig", "villain"}}}},
             "no rig 'villain'"}),
    [](const ::testing::TestParamInfo<Case>& info) { return info.param.name; });

}  // namespace
}  // namespace rigel
