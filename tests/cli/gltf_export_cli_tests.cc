// `rigel export SCENE.rigel -o OUT.glb|.gltf [--frames A:B] [--bake]`: the
// glTF exporter behind the CLI contract (exit 0 on success, 1 on invalid
// input with "rigel: ..." naming the problem, 2 on usage errors).

#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "../io/io_test_util.h"
#include "cli_test_util.h"
#include "rigel/io/scene_file.h"
#include "rigel/ops/anim/nodes.h"
#include "rigel/ops/registry.h"
#include "rigel/scene/transform_types.h"

namespace rigel::cli {
namespace {

using namespace rigel::cli::testing;  // NOLINT: the CLI runner
namespace fs = std::filesystem;
using math::Vec3;

fs::path character(const std::string& name) { return rigel::io::testing::source_dir() / "tests" / "data" / "gltf" / name; }

tinygltf::Model load_glb_or_gltf(const fs::path& path) {
  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string err, warn;
  const bool ok = path.extension() == ".glb" ? loader.LoadBinaryFromFile(&model, &err, &warn, path.string())
                                             : loader.LoadASCIIFromFile(&model, &err, &warn, path.string());
  EXPECT_TRUE(ok) << path << ": " << err;
  return model;
}

// A joint swinging with Euler angles (an animCurveVec3 on rotate): 3 keys
// over 1 s at 24 fps, saved as a .rigel file.
std::string euler_scene(const TempDir& dir) {
  scene::Scene s(ops::default_registry());
  rigel::io::testing::Builder b(s);
  const graph::NodeId arm = b.node(scene::kJointType, "arm", 1);
  const graph::NodeId curve = b.node(ops::anim::kAnimCurveVec3Type, "arm_rotate", 2);
  b.set(arm, "translate", Vec3(0, 1, 0));
  b.set(curve, "keyTimes", std::vector<double>{0, 0.5, 1});
  b.set(curve, "keyValues", std::vector<Vec3>{{0, 0, 0}, {0, 0, 45}, {0, 0, 90}});
  b.connect("arm_rotate.output", "arm.rotate");
  const std::string path = (dir.path() / "euler.rigel").string();
  EXPECT_TRUE(rigel::io::save_scene(s, path).is_ok());
  return path;
}

TEST(CliExportGltf, euler_tracks__bake_with_a_note_saying_why) {
  TempDir dir;
  const std::string scene = euler_scene(dir);
  const fs::path out = dir.path() / "arm.glb";
  const CliRun r = rigel({"export", scene, "-o", out.string()});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  EXPECT_TRUE(r.out.empty()) << "nothing on stdout";
  EXPECT_TRUE(contains(r.err, "rigel: note: baked frames 0 to 24")) << "the keys' range, in frames: " << r;
  EXPECT_TRUE(contains(r.err, "arm.rotate is animated with Euler angles")) << "and why: " << r;
  EXPECT_TRUE(contains(r.err, "rigel: exported 1 nodes")) << r;
  EXPECT_FALSE(contains(r.err, "\r")) << "no progress line when stderr is not a terminal";
  EXPECT_VALID_GLTF(out);
  tinygltf::Model model = load_glb_or_gltf(out);
  ASSERT_EQ(model.animations.size(), 1u);
  ASSERT_EQ(model.animations[0].channels.size(), 1u) << "only the rotation changes";
  EXPECT_EQ(model.animations[0].channels[0].target_path, "rotation");
  EXPECT_EQ(model.accessors.at(static_cast<std::size_t>(model.animations[0].samplers[0].input)).count, 25u);
}

TEST(CliExportGltf, frames_option__bakes_that_range) {
  TempDir dir;
  const std::string scene = euler_scene(dir);
  const fs::path out = dir.path() / "arm.gltf";
  const CliRun r = rigel({"export", scene, "-o", out.string(), "--frames", "6:12"});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  EXPECT_TRUE(contains(r.err, "baked frames 6 to 12")) << r;
  EXPECT_VALID_GLTF(out);
  tinygltf::Model model = load_glb_or_gltf(out);
  const auto& input = model.accessors.at(static_cast<std::size_t>(model.animations.at(0).samplers.at(0).input));
  EXPECT_EQ(input.count, 7u) << "frames 6..12";
  EXPECT_NEAR(input.minValues.at(0), 0.25, 1e-7);
  EXPECT_NEAR(input.maxValues.at(0), 0.5, 1e-7);
}

TEST(CliExportGltf, imported_character__round_trips_without_baking) {
  TempDir dir;
  const std::string scene = (dir.path() / "cesium.rigel").string();
  ASSERT_TRUE(exited_with(rigel({"import", character("CesiumMan.glb").string(), "-o", scene}), 0));
  for (const char* name : {"cesium.glb", "cesium.gltf"}) {
    const fs::path out = dir.path() / name;
    const CliRun r = rigel({"export", scene, "-o", out.string()});
    ASSERT_TRUE(exited_with(r, 0)) << r;
    EXPECT_FALSE(contains(r.err, "baked")) << "glTF tracks are written as they are: " << r;
    EXPECT_VALID_GLTF(out);
    tinygltf::Model model = load_glb_or_gltf(out);
    EXPECT_EQ(model.skins.size(), 1u);
    EXPECT_EQ(model.meshes.size(), 1u);
    ASSERT_EQ(model.animations.size(), 1u);
    EXPECT_GT(model.animations[0].channels.size(), 10u);
  }
}

// The validator sweep over every kind of export the CLI writes (each
// bundled character, the biped, a BVH; direct and baked; .glb and .gltf) is
// tests/export/validate_exports.py, run by ctest in the optimised build.

// --deform-only: the biped's skin joints and its mesh, baked; no control,
// rig group or helper joint in the file.
TEST(CliExportGltf, deform_only_writes_the_skinned_skeleton_and_the_mesh) {
  TempDir dir;
  const std::string hero = (dir.path() / "hero.rigel").string();
  ASSERT_TRUE(exited_with(rigel({"build", (rigel::io::testing::source_dir() / "examples/biped.rig.xml").string(), "-o", hero}), 0));
  const fs::path out = dir.path() / "game.glb";
  const CliRun r = rigel({"export", hero, "-o", out.string(), "--deform-only", "--frames", "0:5", "--json"});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_TRUE(j["baked"].get<bool>());
  EXPECT_EQ(j["bakeReason"], "requested (frames 0:5)");
  EXPECT_EQ(j["skins"], 1);
  EXPECT_VALID_GLTF(out);
  const tinygltf::Model model = load_glb_or_gltf(out);
  ASSERT_EQ(model.skins.size(), 1u);
  // Every node is a skin joint or holds the mesh (or the skin's common root).
  std::size_t others = 0;
  for (std::size_t i = 0; i < model.nodes.size(); ++i) {
    const bool joint = std::find(model.skins[0].joints.begin(), model.skins[0].joints.end(), static_cast<int>(i)) !=
                       model.skins[0].joints.end();
    if (!joint && model.nodes[i].mesh < 0) ++others;
    EXPECT_EQ(model.nodes[i].name.find("hero_"), std::string::npos) << model.nodes[i].name << " is a rig node";
  }
  EXPECT_LE(others, 1u);
  const CliRun full = rigel({"export", hero, "-o", (dir.path() / "all.glb").string(), "--json"});
  ASSERT_TRUE(exited_with(full, 0)) << full;
  EXPECT_GT(nlohmann::json::parse(full.out)["nodes"].get<int>(), static_cast<int>(model.nodes.size()) + 100)
      << "the full export holds the rig too";
}

TEST(CliExportGltf, bad_input__exits_1_naming_the_problem) {
  TempDir dir;
  const std::string scene = euler_scene(dir);
  const std::string out = (dir.path() / "x.glb").string();
  for (const char* frames : {"a:b", "3", "1:2:3", ":4", "1:inf"}) {
    const CliRun r = rigel({"export", scene, "-o", out, "--frames", frames});
    EXPECT_TRUE(exited_with(r, 1)) << frames << ": " << r;
    EXPECT_TRUE(contains(r.err, "--frames")) << r;
  }
  const CliRun reversed = rigel({"export", scene, "-o", out, "--frames", "12:6"});
  EXPECT_TRUE(exited_with(reversed, 1)) << reversed;
  EXPECT_TRUE(contains(reversed.err, "after the last")) << reversed;
  const CliRun ext = rigel({"export", scene, "-o", (dir.path() / "x.obj").string()});
  EXPECT_TRUE(exited_with(ext, 1)) << ext;
  EXPECT_TRUE(contains(ext.err, "'.obj'")) << ext;
  const CliRun missing = rigel({"export", (dir.path() / "missing.rigel").string(), "-o", out});
  EXPECT_TRUE(exited_with(missing, 1)) << missing;
  EXPECT_TRUE(contains(missing.err, "missing.rigel")) << missing;
  EXPECT_FALSE(fs::exists(out)) << "nothing written on failure";
}

TEST(CliExportGltf, usage_errors__exit_2) {
  TempDir dir;
  const std::string scene = euler_scene(dir);
  EXPECT_TRUE(exited_with(rigel({"export", scene}), 2)) << "-o is required";
  EXPECT_TRUE(exited_with(rigel({"export", "-o", "x.glb"}), 2)) << "the scene is required";
  EXPECT_TRUE(exited_with(rigel({"export", scene, "-o", "x.glb", "--no-such-option"}), 2));
}

}  // namespace
}  // namespace rigel::cli
