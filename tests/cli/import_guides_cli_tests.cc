// `rigel import-guides FILE.sgt [-o OUT.rig.xml] [--skeleton OUT.glb]`
// (app/guide_import.h): mGear's biped template becomes a definition that
// validates and builds on the skeleton written beside it, every component
// mapped; an unknown type is reported by name (exit 1, files written);
// a malformed template or a bad file name is refused and writes nothing.

#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_test_util.h"

namespace rigel::cli {
namespace {

using namespace rigel::cli::testing;  // NOLINT: the CLI runner
using Json = nlohmann::ordered_json;
namespace fs = std::filesystem;

const std::string kBiped = (fs::path(RIGEL_SOURCE_DIR) / "tests/data/mgear/biped.sgt").string();

TEST(CliImportGuides, the_mgear_biped_imports_validates_and_builds_on_its_skeleton) {
  TempDir dir;
  const fs::path def = dir.path() / "rigs" / "biped.rig.json";
  fs::create_directories(def.parent_path());
  const CliRun run = rigel({"import-guides", kBiped, "-o", def.string(), "--json"});
  ASSERT_TRUE(exited_with(run, 0)) << run;
  const Json report = Json::parse(run.out);
  EXPECT_TRUE(report["unmapped"].empty()) << run;
  EXPECT_EQ(report["components"].size(), 38u);
  const fs::path skeleton = dir.path() / "rigs" / "biped.glb";
  EXPECT_EQ(fs::path(report["skeleton"].get<std::string>()), skeleton);
  ASSERT_TRUE(fs::exists(def) && fs::exists(skeleton));

  // The skeleton is one glTF skin of every joint, so readers keep them as joints.
  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string err, warn;
  ASSERT_TRUE(loader.LoadBinaryFromFile(&model, &err, &warn, skeleton.string())) << err;
  ASSERT_EQ(model.skins.size(), 1u);
  EXPECT_EQ(model.skins[0].joints.size(), report["joints"].get<std::size_t>());

  const CliRun valid = rigel({"validate", def.string()});
  EXPECT_TRUE(exited_with(valid, 0)) << valid;
  // The definition names its skeleton: it builds as it is, and on the skeleton given.
  const CliRun built = rigel({"build", def.string(), "-o", (dir.path() / "built.rigel").string(), "--json"});
  ASSERT_TRUE(exited_with(built, 0)) << built;
  const CliRun given = rigel({"build", def.string(), "--character", skeleton.string(), "-o",
                              (dir.path() / "given.rigel").string()});
  EXPECT_TRUE(exited_with(given, 0)) << given;

  // Without -o: NAME.rig.xml and NAME.glb in the current folder; the text
  // report names every component.
  const CliRun plain = rigel({"import-guides", kBiped}, dir.path());
  ASSERT_TRUE(exited_with(plain, 0)) << plain;
  EXPECT_TRUE(fs::exists(dir.path() / "biped.rig.xml") && fs::exists(dir.path() / "biped.glb"));
  EXPECT_TRUE(contains(plain.err, "arm_L0 (arm_2jnt_01) -> arm_L (limb)")) << plain;
  EXPECT_TRUE(contains(plain.err, "38 of 38 components imported")) << plain;
  EXPECT_TRUE(contains(plain.err, "guides without a counterpart: tan0, tan1")) << plain;
}

TEST(CliImportGuides, an_unknown_type_is_named_and_a_malformed_template_writes_nothing) {
  TempDir dir;
  std::ifstream in(kBiped, std::ios::binary);
  Json doc = Json::parse(in);
  doc["components_dict"]["mouth_C0"]["param_values"]["comp_type"] = "lips_99";
  const fs::path odd = dir.path() / "odd.sgt";
  std::ofstream(odd, std::ios::binary) << doc.dump();
  const fs::path out = dir.path() / "odd.rig.xml";
  const CliRun run = rigel({"import-guides", odd.string(), "-o", out.string()});
  EXPECT_TRUE(exited_with(run, 1)) << run;
  EXPECT_TRUE(contains(run.err, "mouth_C0 (lips_99): not imported")) << run;
  EXPECT_TRUE(contains(run.err, "37 of 38 components")) << run;
  EXPECT_TRUE(fs::exists(out)) << "what could be imported is written";
  // The tongue, the mouth's child, hangs from the neck now: the rest still builds.
  const CliRun built = rigel({"build", out.string(), "-o", (dir.path() / "odd.rigel").string()});
  EXPECT_TRUE(exited_with(built, 0)) << built;

  doc["components_dict"]["arm_L0"]["tra"].erase("elbow");
  doc["components_dict"]["mouth_C0"]["param_values"]["comp_type"] = "mouth_01";
  const fs::path bad = dir.path() / "bad.sgt";
  std::ofstream(bad, std::ios::binary) << doc.dump();
  const fs::path bad_out = dir.path() / "bad.rig.xml";
  const CliRun refused = rigel({"import-guides", bad.string(), "-o", bad_out.string()});
  EXPECT_TRUE(exited_with(refused, 1)) << refused;
  EXPECT_TRUE(contains(refused.err, "component 'arm_L0' (arm_2jnt_01): guide locator 'elbow'")) << refused;
  EXPECT_FALSE(fs::exists(bad_out));
  EXPECT_FALSE(fs::exists(dir.path() / "bad.glb"));

  const CliRun wrong = rigel({"import-guides", kBiped, "-o", (dir.path() / "x.xml").string()});
  EXPECT_TRUE(exited_with(wrong, 2)) << wrong;
  EXPECT_TRUE(contains(wrong.err, "NAME.rig.xml")) << wrong;
  const CliRun missing = rigel({"import-guides", (dir.path() / "none.sgt").string(), "-o", out.string()});
  EXPECT_TRUE(exited_with(missing, 1)) << missing;
  EXPECT_TRUE(contains(missing.err, "none.sgt")) << missing;
}

}  // namespace
}  // namespace rigel::cli
