// `rigel project`, `rigel asset`, `rigel config` and `--log-level`: a
// project made with two assets and listed; settings set in the user's and
// the project's files, the project's winning inside the project; a build
// inside the project naming its nodes by the project's naming.template;
// the log level from the settings and from --log-level (which wins); bad
// input refused with exit codes and nothing written.
#include <cstdlib>
#include <filesystem>

#include "cli_test_util.h"

namespace rigel::cli::testing {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

class CliPipeline : public ::testing::Test {
 protected:
  void SetUp() override { setenv("RIGEL_CONFIG_HOME", (dir_.path() / "user").c_str(), 1); }
  void TearDown() override { setenv("RIGEL_CONFIG_HOME", "/nonexistent/rigel-tests-config", 1); }
  fs::path at(const std::string& name) { return dir_.path() / name; }
  // A project "show" with the character "hero" on the bundled body, which
  // is imported into the asset as body.rigel; returns the asset's folder.
  fs::path hero_on_the_body() {
    EXPECT_TRUE(exited_with(rigel({"project", "new", at("show").string()}), 0));
    EXPECT_TRUE(exited_with(rigel({"asset", "new", "hero", "--skeleton", body()}, at("show")), 0));
    const fs::path asset = at("show/characters/hero");
    EXPECT_TRUE(exited_with(rigel({"import", body(), "-o", (asset / "body.rigel").string()}), 0));
    return asset;
  }
  static std::string body() { return (fs::path(RIGEL_SOURCE_DIR) / "tests/data/gltf/rigify_human_body.glb").string(); }
  TempDir dir_;
};

TEST_F(CliPipeline, a_project_with_two_assets_listed) {
  CliRun r = rigel({"project", "new", at("show").string(), "--json"});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  EXPECT_EQ(Json::parse(r.out)["name"], "show");
  const std::string body = (fs::path(RIGEL_SOURCE_DIR) / "tests/data/gltf/rigify_human_body.glb").string();
  r = rigel({"asset", "new", "hero", "--skeleton", body}, at("show"));
  ASSERT_TRUE(exited_with(r, 0)) << r;
  r = rigel({"asset", "new", "sword", "--type", "prop", "--project", at("show").string()});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  EXPECT_TRUE(fs::exists(at("show/characters/hero/skeleton/rigify_human_body.glb")));
  EXPECT_TRUE(fs::is_directory(at("show/props/sword/data/driven_poses")));
  r = rigel({"project", "info", "--json"}, at("show/characters/hero/data"));
  ASSERT_TRUE(exited_with(r, 0)) << r;
  const Json info = Json::parse(r.out);
  ASSERT_EQ(info["assets"].size(), 2u) << info;
  EXPECT_EQ(info["assets"][0]["name"], "hero");
  EXPECT_EQ(info["assets"][1]["type"], "prop");
  r = rigel({"asset", "info", "--json"}, at("show/characters/hero/build"));
  ASSERT_TRUE(exited_with(r, 0)) << r;
  EXPECT_EQ(Json::parse(r.out)["skeleton"], "skeleton/rigify_human_body.glb");

  for (const auto& [args, cwd] : {std::pair{std::vector<std::string>{"project", "new", at("show").string()}, fs::path()},
                                  std::pair{std::vector<std::string>{"asset", "new", "hero"}, at("show")},
                                  std::pair{std::vector<std::string>{"asset", "new", "lamp", "--type", "car"}, at("show")},
                                  std::pair{std::vector<std::string>{"asset", "new", "lamp"}, dir_.path()},
                                  std::pair{std::vector<std::string>{"project", "info"}, dir_.path()}}) {
    const CliRun b = rigel(args, cwd);
    EXPECT_TRUE(exited_with(b, 1)) << b;
    EXPECT_FALSE(b.err.empty());
  }
  EXPECT_FALSE(fs::exists(at("show/characters/lamp")));
  EXPECT_FALSE(fs::exists(at("lamp")));
}

TEST_F(CliPipeline, settings_layered_and_used_by_builds_and_the_log) {
  ASSERT_TRUE(exited_with(rigel({"project", "new", at("show").string()}), 0));
  CliRun r = rigel({"config", "set", "log.level", "error", "--user"});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  r = rigel({"config", "set", "naming.template", "{side}_{name}_{role}{index}"}, at("show"));
  ASSERT_TRUE(exited_with(r, 0)) << r;
  EXPECT_TRUE(fs::exists(at("show/rigel.config.json")));
  r = rigel({"config", "get", "naming.template", "--json"}, at("show"));
  ASSERT_TRUE(exited_with(r, 0)) << r;
  EXPECT_EQ(Json::parse(r.out)["source"], "project");
  r = rigel({"config", "get", "naming.template", "--json"});
  EXPECT_EQ(Json::parse(r.out)["source"], "default") << "outside the project";
  r = rigel({"config", "list", "--json"}, at("show"));
  ASSERT_TRUE(exited_with(r, 0)) << r;
  EXPECT_EQ(Json::parse(r.out)["settings"][0]["source"], "user");

  // A build inside the project names its nodes by the project's template.
  const std::string biped = (fs::path(RIGEL_SOURCE_DIR) / "examples/biped.rig.xml").string();
  r = rigel({"build", biped, "-o", at("show/hero.rigel").string()}, at("show"));
  ASSERT_TRUE(exited_with(r, 0)) << r;
  r = rigel({"address", at("show/hero.rigel").string(), "hero:arm_L/ik", "--json"});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  EXPECT_NE(r.out.find("L_arm_ik"), std::string::npos) << r;

  // The log: the project's level (debug) says where the settings came from;
  // --log-level wins over it.
  ASSERT_TRUE(exited_with(rigel({"config", "set", "log.level", "debug"}, at("show")), 0));
  r = rigel({"config", "get", "log.level"}, at("show"));
  ASSERT_TRUE(exited_with(r, 0)) << r;
  EXPECT_EQ(r.out, "debug\n");
  EXPECT_NE(r.err.find("debug: settings from"), std::string::npos) << r;
  r = rigel({"config", "get", "log.level", "--log-level", "warn"}, at("show"));
  EXPECT_EQ(r.err.find("debug:"), std::string::npos) << r;
  r = rigel({"--log-level", "loud", "config", "list"});
  EXPECT_TRUE(exited_with(r, 2)) << r;

  // Bad values and files: refused, the file as it was.
  const std::string before = io::testing::read_text(at("show/rigel.config.json"));
  for (const std::vector<std::string>& bad : {std::vector<std::string>{"config", "set", "log.level", "loud"},
                                              std::vector<std::string>{"config", "set", "no.such", "1"},
                                              std::vector<std::string>{"config", "get", "no.such"}}) {
    const CliRun b = rigel(bad, at("show"));
    EXPECT_TRUE(exited_with(b, 1)) << b;
  }
  EXPECT_EQ(io::testing::read_text(at("show/rigel.config.json")), before);
  io::testing::write_text(at("show/rigel.config.json"), "{\"rigelConfig\": 1,\n \"settings\": {\"log.level\": }}");
  r = rigel({"config", "list"}, at("show"));
  EXPECT_TRUE(exited_with(r, 1)) << r;
  EXPECT_NE(r.err.find("rigel.config.json:2:"), std::string::npos) << r;
  r = rigel({"project", "info"}, at("show"));
  EXPECT_TRUE(exited_with(r, 0)) << "other commands go on, warning: " << r;
  EXPECT_NE(r.err.find("settings left out"), std::string::npos) << r;
}

TEST_F(CliPipeline, weights_and_shapes_exported_into_the_asset_and_imported_back) {
  const fs::path asset = hero_on_the_body();
  ASSERT_FALSE(HasFailure());
  const std::string body = CliPipeline::body();
  // A bare name goes to the asset's data folder.
  CliRun r = rigel({"data", "export", "weights", "body.rigel", "-o", "body", "--json"}, asset);
  ASSERT_TRUE(exited_with(r, 0)) << r;
  const fs::path file = asset / "data/weights/body.weights.json";
  EXPECT_EQ(Json::parse(r.out)["file"], file.string());
  const std::string exported = io::testing::read_text(file);
  // Onto a fresh import (other uuids): by name; mirrored; each written.
  ASSERT_TRUE(exited_with(rigel({"import", body, "-o", at("fresh.rigel").string()}), 0));
  r = rigel({"data", "import", "weights", at("fresh.rigel").string(), file.string(), "-o", at("fresh2.rigel").string(), "--json"});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  EXPECT_EQ(Json::parse(r.out)["vertices"], 10027);
  r = rigel({"data", "import", "weights", (asset / "body.rigel").string(), file.string(), "-o", at("same.rigel").string()});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  r = rigel({"data", "export", "weights", at("same.rigel").string(), "-o", at("again.weights.json").string()});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  EXPECT_EQ(io::testing::read_text(at("again.weights.json")), exported) << "export after import: the same bytes";
  r = rigel({"data", "import", "weights", at("fresh.rigel").string(), file.string(), "--mirror", "-o", at("mirrored.rigel").string()});
  ASSERT_TRUE(exited_with(r, 0)) << r;

  // Shapes of the biped, exported and imported back.
  const std::string biped = (fs::path(RIGEL_SOURCE_DIR) / "examples/biped.rig.xml").string();
  ASSERT_TRUE(exited_with(rigel({"build", biped, "-o", at("hero.rigel").string()}), 0));
  r = rigel({"data", "export", "shapes", at("hero.rigel").string(), "-o", at("hero.shapes.json").string()});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  r = rigel({"data", "import", "shapes", at("hero.rigel").string(), at("hero.shapes.json").string(), "-o", at("hero2.rigel").string(), "--json"});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  EXPECT_GT(Json::parse(r.out)["set"].get<int>(), 50);

  for (const std::vector<std::string>& bad :
       {std::vector<std::string>{"data", "import", "weights", at("hero.rigel").string(), at("hero.shapes.json").string(), "-o", at("x.rigel").string()},
        std::vector<std::string>{"data", "import", "shapes", at("hero.rigel").string(), at("none.json").string(), "-o", at("x.rigel").string()},
        std::vector<std::string>{"data", "export", "weights", at("hero.rigel").string(), "-o", at("show").string()},
        std::vector<std::string>{"data", "import", "weights", at("fresh.rigel").string(), file.string(), "--rename", at("none.json").string(), "-o", at("x.rigel").string()}}) {
    const CliRun b = rigel(bad);
    EXPECT_TRUE(exited_with(b, 1)) << b;
  }
  EXPECT_TRUE(exited_with(rigel({"data", "export", "colours", at("hero.rigel").string(), "-o", at("x.json").string()}), 2));
  EXPECT_FALSE(fs::exists(at("x.rigel")));
}

// The project's data.weights = binary: exports put the arrays in a side
// file beside the weights file (the same weights back, byte for byte on a
// second export); --format json overrides the setting; --format on another
// kind, or an unknown format, is a usage error.
TEST_F(CliPipeline, weights_in_a_binary_side_file_by_the_project_setting) {
  const fs::path asset = hero_on_the_body();
  ASSERT_FALSE(HasFailure());
  const std::string body = CliPipeline::body();
  ASSERT_TRUE(exited_with(rigel({"data", "export", "weights", "body.rigel", "-o", "plain"}, asset), 0));
  const std::string plain = io::testing::read_text(asset / "data/weights/plain.weights.json");
  ASSERT_TRUE(exited_with(rigel({"config", "set", "data.weights", "binary"}, at("show")), 0));
  CliRun r = rigel({"data", "export", "weights", "body.rigel", "-o", "body"}, asset);
  ASSERT_TRUE(exited_with(r, 0)) << r;
  const fs::path file = asset / "data/weights/body.weights.json";
  const Json j = Json::parse(io::testing::read_text(file));
  ASSERT_TRUE(j.contains("binary")) << "the setting made it binary";
  const fs::path side = file.parent_path() / j["binary"]["file"].get<std::string>();
  ASSERT_TRUE(fs::is_regular_file(side));
  EXPECT_EQ(fs::file_size(side), j["binary"]["bytes"].get<std::uintmax_t>());
  // Imported onto a fresh import and exported as JSON: the weights the plain export has.
  ASSERT_TRUE(exited_with(rigel({"import", body, "-o", at("fresh.rigel").string()}), 0));
  r = rigel({"data", "import", "weights", at("fresh.rigel").string(), file.string(), "-o", at("fresh2.rigel").string(), "--json"});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  EXPECT_EQ(Json::parse(r.out)["vertices"], 10027);
  r = rigel({"data", "import", "weights", (asset / "body.rigel").string(), file.string(), "-o", at("same.rigel").string()});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  r = rigel({"data", "export", "weights", at("same.rigel").string(), "-o", at("again.weights.json").string(), "--format", "json"}, asset);
  ASSERT_TRUE(exited_with(r, 0)) << r;
  EXPECT_EQ(io::testing::read_text(at("again.weights.json")), plain) << "--format json over the setting; the same weights";
  const std::string before = io::testing::read_text(file);
  ASSERT_TRUE(exited_with(rigel({"data", "export", "weights", at("same.rigel").string(), "-o", file.string()}, asset), 0));
  EXPECT_EQ(io::testing::read_text(file), before) << "export after import: the same bytes";
  EXPECT_TRUE(fs::is_regular_file(side)) << "the same side file";
  for (const std::vector<std::string>& bad :
       {std::vector<std::string>{"data", "export", "weights", "body.rigel", "-o", "x", "--format", "xml"},
        std::vector<std::string>{"data", "export", "shapes", "body.rigel", "-o", "x", "--format", "binary"}}) {
    const CliRun b = rigel(bad, asset);
    EXPECT_TRUE(exited_with(b, 2)) << b;
  }
  // A side file that is not the one written: refused, naming the member.
  std::string bytes = io::testing::read_text(side);
  bytes[bytes.size() - 3] ^= 0x01;
  io::testing::write_text(side, bytes);
  r = rigel({"data", "import", "weights", at("fresh.rigel").string(), file.string(), "-o", at("x.rigel").string()});
  EXPECT_TRUE(exited_with(r, 1)) << r;
  EXPECT_NE(r.err.find("binary.checksum"), std::string::npos) << r;
  EXPECT_FALSE(fs::exists(at("x.rigel")));
}

TEST_F(CliPipeline, blend_shapes_exported_into_the_asset_edited_and_imported_onto_a_fresh_import) {
  ASSERT_TRUE(exited_with(rigel({"project", "new", at("show").string()}), 0));
  const std::string morph = (fs::path(RIGEL_SOURCE_DIR) / "tests/data/gltf/SimpleMorph.gltf").string();
  ASSERT_TRUE(exited_with(rigel({"asset", "new", "tri", "--skeleton", morph}, at("show")), 0));
  const fs::path asset = at("show/characters/tri");
  ASSERT_TRUE(exited_with(rigel({"import", morph, "-o", (asset / "tri.rigel").string()}), 0));
  // A bare name goes to the asset's data folder.
  CliRun r = rigel({"data", "export", "blendshapes", "tri.rigel", "-o", "tri", "--json"}, asset);
  ASSERT_TRUE(exited_with(r, 0)) << r;
  const fs::path file = asset / "data/blendshapes/tri.blendshapes.json";
  EXPECT_EQ(Json::parse(r.out)["file"], file.string());
  // Sculpted by hand in the file: target 0 moves vertex 2 further.
  std::string text = io::testing::read_text(file);
  const std::string line = "[2, -1.0, 1.0, 0.0]";
  ASSERT_NE(text.find(line), std::string::npos) << text;
  text.replace(text.find(line), line.size(), "[2, -1.0, 1.5, 0.25]");
  io::testing::write_text(file, text);
  // A rebuild: the glTF again, then the file (by bare name inside the asset).
  ASSERT_TRUE(exited_with(rigel({"import", morph, "-o", at("fresh.rigel").string()}), 0));
  r = rigel({"data", "import", "blendshapes", at("fresh.rigel").string(), "tri", "-o", at("fresh2.rigel").string(), "--json"}, asset);
  ASSERT_TRUE(exited_with(r, 0)) << r;
  const Json report = Json::parse(r.out);
  EXPECT_EQ(report["blendShapes"], 1);
  EXPECT_EQ(report["targets"], 2);
  EXPECT_TRUE(report["driven"].empty()) << "the animated weights are the file's";
  r = rigel({"data", "export", "blendshapes", at("fresh2.rigel").string(), "-o", at("again.blendshapes.json").string()});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  EXPECT_EQ(io::testing::read_text(at("again.blendshapes.json")), text) << "export after import: the same bytes";

  // Refused: a file that is not JSON (file:line:column), a blendShape the
  // scene lacks (named), a scene without blend shapes, weights' options.
  io::testing::write_text(at("broken.blendshapes.json"), "{\"rigelBlendShapes\": 1,\n  \"blendShapes\": [}");
  r = rigel({"data", "import", "blendshapes", at("fresh.rigel").string(), at("broken.blendshapes.json").string(), "-o", at("x.rigel").string()});
  EXPECT_TRUE(exited_with(r, 1)) << r;
  EXPECT_NE(r.err.find("broken.blendshapes.json:2:"), std::string::npos) << r;
  std::string other = text;
  other.replace(other.find("_blendShape\""), 12, "_nose\"");
  other.replace(other.find("\"mesh\": \""), 9, "\"mesh\": \"no");
  io::testing::write_text(at("other.blendshapes.json"), other);
  r = rigel({"data", "import", "blendshapes", at("fresh.rigel").string(), at("other.blendshapes.json").string(), "-o", at("x.rigel").string()});
  EXPECT_TRUE(exited_with(r, 1)) << r;
  EXPECT_NE(r.err.find("_nose': the scene has no such blendShape"), std::string::npos) << r;
  const std::string body = (fs::path(RIGEL_SOURCE_DIR) / "tests/data/gltf/rigify_human_body.glb").string();
  ASSERT_TRUE(exited_with(rigel({"import", body, "-o", at("body.rigel").string()}), 0));
  r = rigel({"data", "export", "blendshapes", at("body.rigel").string(), "-o", at("x.blendshapes.json").string()});
  EXPECT_TRUE(exited_with(r, 1)) << r;
  EXPECT_NE(r.err.find("no blend shapes"), std::string::npos) << r;
  r = rigel({"data", "import", "blendshapes", at("fresh.rigel").string(), file.string(), "--mirror", "-o", at("x.rigel").string()});
  EXPECT_TRUE(exited_with(r, 2)) << r;
  EXPECT_FALSE(fs::exists(at("x.rigel")));
  EXPECT_FALSE(fs::exists(at("x.blendshapes.json")));
}

TEST_F(CliPipeline, publish_twice_and_a_shot_of_version_1_is_out_of_date) {
  ASSERT_TRUE(exited_with(rigel({"project", "new", at("show").string()}), 0));
  const std::string body = (fs::path(RIGEL_SOURCE_DIR) / "tests/data/gltf/rigify_human_body.glb").string();
  ASSERT_TRUE(exited_with(rigel({"asset", "new", "hero", "--skeleton", body}, at("show")), 0));
  const fs::path asset = at("show/characters/hero");
  CliRun r = rigel({"publish"}, asset);
  EXPECT_TRUE(exited_with(r, 1)) << "no definition yet: " << r;
  fs::copy_file(fs::path(RIGEL_SOURCE_DIR) / "examples/biped.rig.xml", asset / "build/biped.rig.xml");
  r = rigel({"publish", "--json"}, asset);
  ASSERT_TRUE(exited_with(r, 0)) << r;
  EXPECT_EQ(Json::parse(r.out)["version"], 1);
  // Inside the asset, bare names are its files and its skeleton the default character.
  r = rigel({"validate", "biped"}, asset);
  EXPECT_TRUE(exited_with(r, 0)) << r;
  r = rigel({"build", "biped", "-o", at("inasset.rigel").string()}, asset);
  ASSERT_TRUE(exited_with(r, 0)) << r;
  EXPECT_NE(r.err.find(" on " + (asset / "skeleton/rigify_human_body.glb").string()), std::string::npos) << r;
  // A shot made from version 1 (written by rigel, so its paths follow it).
  r = rigel({"playback", (asset / "rig/v001/rig.rigel").string(), "--range", "1:24", "-o", at("shots/s01.rigel").string()});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  // A hand edit kept as data, then version 2.
  r = rigel({"shape", (asset / "rig/v001/rig.rigel").string(), "--control", "hero_arm_L_ik", "--flip", "-o", at("edit.rigel").string()});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  r = rigel({"data", "export", "shapes", at("edit.rigel").string(), "-o", "hero"}, asset);
  ASSERT_TRUE(exited_with(r, 0)) << r;
  r = rigel({"publish", "hero", "--project", at("show").string(), "--json"});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  EXPECT_EQ(Json::parse(r.out)["version"], 2);
  EXPECT_GT(Json::parse(r.out)["shapesSet"].get<int>(), 50);
  r = rigel({"shape", (asset / "rig/v002/rig.rigel").string(), "--control", "hero_arm_L_ik", "--json"});
  const CliRun edited = rigel({"shape", at("edit.rigel").string(), "--control", "hero_arm_L_ik", "--json"});
  EXPECT_EQ(Json::parse(r.out)["controls"][0]["shape"], Json::parse(edited.out)["controls"][0]["shape"]);
  r = rigel({"rigs", at("shots/s01.rigel").string(), (asset / "rig/v002/rig.rigel").string(), "--json"});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  const Json scenes = Json::parse(r.out)["scenes"];
  EXPECT_EQ(scenes[0]["rigs"][0]["published"]["version"], 1);
  EXPECT_EQ(scenes[0]["rigs"][0]["published"]["newest"], 2);
  EXPECT_EQ(scenes[0]["rigs"][0]["published"]["outOfDate"], true);
  EXPECT_EQ(scenes[1]["rigs"][0]["published"]["outOfDate"], false);
  r = rigel({"rigs", at("shots/s01.rigel").string()});
  EXPECT_NE(r.out.find("out of date: the newest is v2"), std::string::npos) << r;
}

}  // namespace
}  // namespace rigel::cli::testing
