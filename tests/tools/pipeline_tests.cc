// The pipeline's settings, projects and assets (tools/config.h,
// tools/project.h) and logging (base/log.h): settings layered project over
// user over defaults, set and unset keeping the rest, malformed and newer
// files refused naming the file and place; projects and assets made with
// their folders, listed, found from inside them, names resolved against an
// asset; job logs taking their level and keeping the warnings.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "rigel/base/log.h"
#include "rigel/tools/config.h"
#include "rigel/tools/project.h"
#include "rigel/rig/manager.h"
#include "rigel/rig/meta.h"
#include "../io/io_test_util.h"
#include "tools_test_util.h"

namespace rigel::tools {
namespace {

namespace fs = std::filesystem;
using io::testing::read_text;
using io::testing::TempDir;
using io::testing::write_text;

TEST(Config, defaults_then_user_then_project) {
  TempDir dir;
  const fs::path user = dir.path() / "user" / "config.json", project = dir.path() / "project" / kProjectConfigFile;
  auto c = Config::load(user, project);
  ASSERT_TRUE(c.is_ok()) << c.status().message();
  EXPECT_EQ(c->string("log.level"), "warn");
  EXPECT_EQ(c->get("log.level")->source, ConfigSource::kDefault);
  ASSERT_TRUE(Config::set(user, "log.level", "info").is_ok());
  ASSERT_TRUE(Config::set(user, "batch.jobs", "3").is_ok());
  ASSERT_TRUE(Config::set(project, "log.level", "debug").is_ok());
  c = Config::load(user, project);
  ASSERT_TRUE(c.is_ok()) << c.status().message();
  EXPECT_EQ(c->string("log.level"), "debug");
  EXPECT_EQ(c->get("log.level")->source, ConfigSource::kProject);
  EXPECT_EQ(c->integer("batch.jobs"), 3);
  EXPECT_EQ(c->get("batch.jobs")->source, ConfigSource::kUser);
  EXPECT_TRUE(c->flag("publish.checks"));
  // Unset the project's: the user's shows through; the file keeps its format.
  ASSERT_TRUE(Config::set(project, "log.level", std::nullopt).is_ok());
  c = Config::load(user, project);
  EXPECT_EQ(c->string("log.level"), "info");
  EXPECT_EQ(read_text(user), "{\n  \"rigelConfig\": 1,\n  \"settings\": {\n    \"log.level\": \"info\",\n    \"batch.jobs\": 3\n  }\n}\n");
}

TEST(Config, bad_values_and_files_are_refused_naming_the_place) {
  TempDir dir;
  const fs::path file = dir.path() / "config.json";
  EXPECT_EQ(Config::set(file, "log.level", "loud").field(), "value");
  EXPECT_EQ(Config::set(file, "batch.jobs", "two").field(), "value");
  EXPECT_EQ(Config::set(file, "batch.jobs", "-1").field(), "value");
  EXPECT_EQ(Config::set(file, "viewport.controlLineWidth", "nan").field(), "value");
  EXPECT_EQ(Config::set(file, "naming.template", "{rig}_{role}").field(), "value") << "no {index}";
  EXPECT_EQ(Config::set(file, "naming.template", "{rig}_{role}{index}_{colour}").field(), "value");
  EXPECT_TRUE(Config::set(file, "naming.template", "{side}_{name}_{role}{index}").is_ok());
  EXPECT_EQ(Config::set(file, "no.such", "1").field(), "key");
  EXPECT_FALSE(fs::exists(dir.path() / "other.json"));

  write_text(file, "{\n  \"rigelConfig\": 1,\n  \"settings\": {\n    \"log.level\": \"info\",,\n  }\n}\n");
  auto bad = Config::load(file, {});
  ASSERT_FALSE(bad.is_ok());
  EXPECT_EQ(bad.status().code(), ErrorCode::kParseError);
  EXPECT_NE(bad.status().message().find(file.string() + ":4:"), std::string::npos) << bad.status().message();
  write_text(file, R"({"rigelConfig": 1, "settings": {"log.level": 3}})");
  EXPECT_NE(Config::load(file, {}).status().message().find("log.level takes one of"), std::string::npos);
  write_text(file, R"({"rigelConfig": 1, "settings": {"colour": "red"}})");
  EXPECT_NE(Config::load(file, {}).status().message().find("unknown setting 'colour'"), std::string::npos);
  write_text(file, R"({"rigelConfig": 7, "settings": {}})");
  EXPECT_NE(Config::load(file, {}).status().message().find("made by a newer rigel"), std::string::npos);
  const std::string before = read_text(file);
  EXPECT_FALSE(Config::set(file, "log.level", "info").is_ok()) << "a file it cannot read is not overwritten";
  EXPECT_EQ(read_text(file), before);
}

TEST(Projects, a_project_with_assets_found_from_inside_and_names_resolved) {
  TempDir dir;
  const fs::path root = dir.path() / "show";
  auto p = create_project(root);
  ASSERT_TRUE(p.is_ok()) << p.status().message();
  EXPECT_EQ(p->name, "show");
  EXPECT_EQ(create_project(root).status().field(), "dir") << "already a project";
  const fs::path skeleton = fs::path(RIGEL_SOURCE_DIR) / "tests/data/gltf/rigify_human_metarig.glb";
  auto hero = create_asset(*p, "hero", "character", skeleton);
  ASSERT_TRUE(hero.is_ok()) << hero.status().message();
  EXPECT_EQ(hero->dir, root / "characters" / "hero");
  EXPECT_EQ(hero->skeleton, "skeleton/rigify_human_metarig.glb");
  for (const char* sub : {"build", "skeleton", "poses", "rig", "data/weights", "data/shapes", "data/blendshapes",
                          "data/driven_poses", "data/correctives"})
    EXPECT_TRUE(fs::is_directory(hero->dir / sub)) << sub;
  EXPECT_TRUE(fs::exists(hero->dir / "skeleton/rigify_human_metarig.glb"));
  auto sword = create_asset(*p, "sword", "prop");
  ASSERT_TRUE(sword.is_ok());
  EXPECT_EQ(sword->dir, root / "props" / "sword");
  EXPECT_EQ(create_asset(*p, "hero").status().field(), "name") << "taken";
  EXPECT_EQ(create_asset(*p, "a/b").status().field(), "name");
  EXPECT_EQ(create_asset(*p, "lamp", "vehicle").status().field(), "type");
  EXPECT_EQ(create_asset(*p, "lamp", "prop", dir.path() / "nope.glb").status().field(), "skeleton");
  EXPECT_FALSE(fs::exists(root / "props" / "lamp"));

  auto assets = list_assets(*p);
  ASSERT_TRUE(assets.is_ok());
  ASSERT_EQ(assets->size(), 2u);
  EXPECT_EQ((*assets)[0].name, "hero");
  EXPECT_EQ((*assets)[1].type, "prop");
  EXPECT_EQ(find_project(hero->dir / "data" / "weights")->dir, root);
  EXPECT_EQ(find_asset(hero->dir / "data" / "weights")->name, "hero");
  EXPECT_FALSE(find_asset(root).is_ok());
  EXPECT_FALSE(find_project(dir.path()).is_ok());
  EXPECT_EQ(open_asset(*p, "nobody").status().field(), "asset");

  write_text(hero->dir / "build" / "biped.rig.xml", "<Rig/>");
  EXPECT_EQ(*resolve_in_asset(*hero, "biped", AssetFile::kDefinition, "definition"), hero->dir / "build" / "biped.rig.xml");
  EXPECT_EQ(*resolve_in_asset(*hero, "rigify_human_metarig", AssetFile::kCharacter, "character"),
            hero->dir / "skeleton" / "rigify_human_metarig.glb");
  EXPECT_EQ(*resolve_in_asset(*hero, "poses", AssetFile::kPoseLibrary, "library"), hero->dir / "poses");
  EXPECT_EQ(resolve_in_asset(*hero, "nothing", AssetFile::kDefinition, "definition").status().field(), "definition");
  EXPECT_EQ(*resolve_in_asset(*hero, skeleton.string(), AssetFile::kCharacter, "character"), skeleton) << "a path as it is";
  EXPECT_TRUE(published_versions(*hero).empty());
  fs::create_directories(hero->dir / "rig" / "v002");
  fs::create_directories(hero->dir / "rig" / "v001");
  EXPECT_EQ(published_versions(*hero), (std::vector<int>{1, 2}));
}

TEST(Projects, newer_and_malformed_files_are_refused) {
  TempDir dir;
  write_text(dir.path() / kProjectFile, R"({"rigelProject": 2, "name": "future"})");
  auto p = open_project(dir.path());
  ASSERT_FALSE(p.is_ok());
  EXPECT_EQ(p.status().code(), ErrorCode::kFailedPrecondition);
  EXPECT_NE(p.status().message().find("made by a newer rigel (project format 2; this rigel reads 1)"), std::string::npos);
  write_text(dir.path() / kProjectFile, "{\"rigelProject\": 1,\n \"name\": }");
  EXPECT_NE(open_project(dir.path()).status().message().find(":2:"), std::string::npos) << open_project(dir.path()).status().message();
  write_text(dir.path() / kProjectFile, R"({"name": "x"})");
  EXPECT_EQ(open_project(dir.path()).status().code(), ErrorCode::kParseError);
}

TEST(Logging, job_logs_take_their_level_and_keep_the_warnings) {
  TempDir dir;
  EXPECT_EQ(*log::level_from_name("warning"), log::Level::kWarn);
  EXPECT_FALSE(log::level_from_name("loud"));
  const log::Level before = log::level();
  log::set_level(log::Level::kError);
  {
    auto job = log::JobLog::open(dir.path() / "build.log", log::Level::kInfo);
    ASSERT_TRUE(job.is_ok()) << job.status().message();
    log::debug("left out");
    log::info("step 1 built");
    log::warn("guide 3 is far from its joint");
    (*job)->flush();
    const std::string text = read_text(dir.path() / "build.log");
    EXPECT_EQ(text.find("left out"), std::string::npos);
    EXPECT_NE(text.find("info: step 1 built"), std::string::npos) << text;
    EXPECT_NE(text.find("warning: guide 3 is far from its joint"), std::string::npos) << text;
    EXPECT_EQ((*job)->warnings(), std::vector<std::string>{"warn: guide 3 is far from its joint"});
  }
  log::warn("after the job");
  EXPECT_EQ(read_text(dir.path() / "build.log").find("after the job"), std::string::npos) << "closed with the job";
  EXPECT_FALSE(log::enabled(log::Level::kInfo));
  write_text(dir.path() / "a_file", "");
  EXPECT_EQ(log::JobLog::open(dir.path() / "a_file" / "x.log").status().code(), ErrorCode::kIoError) << "under a file";
  log::set_level(before);
}

TEST(NamingTemplate, a_template_names_every_built_node_and_updates_keep_it) {
  auto scene = testing::import_character(testing::source("tests/data/gltf/rigify_human_metarig.glb"));
  ASSERT_TRUE(scene);
  rig::BuildOptions options;
  options.naming_template = "{side}_{name}_{role}{index}";
  const auto path = std::filesystem::path(RIGEL_SOURCE_DIR) / "examples/biped.rig.xml";
  auto added = rig::add_rig(*scene, path, ephemeral::components(), options);
  ASSERT_TRUE(added.is_ok()) << added.status().message();
  graph::Graph& g = scene->graph();
  EXPECT_TRUE(g.find("L_arm_ik").is_valid());
  EXPECT_TRUE(g.find("R_leg_ik").is_valid());
  EXPECT_FALSE(g.find("hero_arm_L_ik").is_valid());
  auto ik = rig::resolve_address(g, "hero:arm_L/ik");
  ASSERT_TRUE(ik.is_ok()) << ik.status().message();
  EXPECT_EQ(g.node(*ik)->name(), "L_arm_ik");
  auto updated = rig::update_rig(*scene, "hero", ephemeral::components(), {}, true);
  ASSERT_TRUE(updated.is_ok()) << updated.status().message();
  EXPECT_TRUE(updated->updated);
  EXPECT_TRUE(g.find("L_arm_ik").is_valid()) << "rebuilt with the rig's own template";
  EXPECT_FALSE(g.find("hero_arm_L_ik").is_valid());
}

}  // namespace
}  // namespace rigel::tools
