// A definition's <data> (rig/definition.h) imported by the build's last
// step through tools::components()'s importer (tools/data_files.h): the
// biped on the bundled body, with a painted weight and a hand-drawn
// control exported as data and named by the definition, built from
// scratch gives them back; stepping back over the data step, removing the
// rig and an update are exact; a bad data file fails the step naming it;
// the dispatcher refuses kinds it cannot read yet; a publish imports a file
// a definition names once.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "rigel/io/scene_file.h"
#include "rigel/rig/build.h"
#include "rigel/rig/definition_io.h"
#include "rigel/rig/manager.h"
#include "rigel/rig/meta.h"
#include "rigel/tools/data_files.h"
#include "rigel/tools/publish.h"
#include "rigel/tools/shape_data.h"
#include "rigel/tools/skin_weights.h"
#include "../io/io_test_util.h"
#include "tools_test_util.h"

namespace rigel::tools {
namespace {

namespace fs = std::filesystem;
using graph::NodeId;
using io::testing::read_text;
using io::testing::write_text;

std::unique_ptr<scene::Scene> body() { return testing::import_character(testing::source("tests/data/gltf/rigify_human_body.glb")); }

const ControlLook kDrawn{{math::Vec3(0, 0, 0), math::Vec3(0.1, 0.1, 0), math::Vec3(0, 0.2, 0)}, false, math::Vec3(1, 0.5, 0)};

// The biped's definition with `data` lines after its <rig> line.
std::string biped_with(const std::string& data) {
  std::string text = read_text(testing::source("examples/biped.rig.xml"));
  const std::size_t rig = text.find("<rig ");
  const std::size_t end = text.find('\n', rig) + 1;
  return text.substr(0, end) + data + text.substr(end);
}

// A folder with the biped's hand-made work on the body exported as data
// (a weight painted on vertex 42, arm_L's ik control drawn) and the biped's
// definition naming it.
struct Fixture {
  io::testing::TempDir dir;
  fs::path definition, weights, shapes;
  std::vector<SkinWeights> painted;
};

std::unique_ptr<Fixture> fixture() {
  auto f = std::make_unique<Fixture>();
  auto s = body();
  EXPECT_TRUE(rig::add_rig(*s, testing::source("examples/biped.rig.xml"), components()).is_ok());
  graph::Graph& g = s->graph();
  EXPECT_TRUE(paste_control_look(g, {testing::at(g, "hero:arm_L/ik")}, kDrawn).is_ok());
  f->painted = *capture_skin_weights(*s);
  SkinWeights& skin = f->painted.back();
  for (std::int64_t k = skin.offsets[42]; k < skin.offsets[43]; ++k)
    skin.weights[static_cast<std::size_t>(k)] = k == skin.offsets[42] ? 1.0 : 0.0;
  f->weights = f->dir.path() / "data" / "body.weights.json";
  f->shapes = f->dir.path() / "data" / "hero.shapes.json";
  fs::create_directories(f->weights.parent_path());
  write_text(f->weights, skin_weights_to_json(f->painted));
  write_text(f->shapes, control_shapes_to_json(*capture_control_shapes(g, rig::find_rig(g, "hero"))));
  f->definition = f->dir.path() / "build" / "hero.rig.xml";
  fs::create_directories(f->definition.parent_path());
  write_text(f->definition, biped_with("  <data kind=\"weights\" file=\"../data/body.weights.json\"/>\n"
                                       "  <data kind=\"shapes\" file=\"../data/hero.shapes.json\"/>\n"));
  return f;
}

rig::Definition load(const fs::path& path) {
  rig::ParseResult r = rig::load_definition(path, components().schemas());
  EXPECT_TRUE(r.ok()) << (r.errors.empty() ? "" : r.errors.front().str());
  return r.definition;
}

// The scene's weights and shapes are the fixture's files'.
void expect_data_of(scene::Scene& s, const Fixture& f) {
  // The weights are the file's (each import of the body makes its joints'
  // uuids afresh: the influences compare by name).
  const auto file = *skin_weights_from_json(read_text(f.weights), f.weights.string());
  const auto now = *capture_skin_weights(s);
  ASSERT_EQ(now.size(), file.size());
  for (std::size_t i = 0; i < now.size(); ++i) {
    ASSERT_EQ(now[i].influences.size(), file[i].influences.size());
    for (std::size_t k = 0; k < now[i].influences.size(); ++k) EXPECT_EQ(now[i].influences[k].joint, file[i].influences[k].joint);
    EXPECT_EQ(now[i].offsets, file[i].offsets);
    EXPECT_EQ(now[i].joints, file[i].joints);
    EXPECT_EQ(now[i].weights, file[i].weights) << "the weights are the file's";
  }
  graph::Graph& g = s.graph();
  EXPECT_EQ(control_shapes_to_json(*capture_control_shapes(g, rig::find_rig(g, "hero"))), read_text(f.shapes))
      << "the shapes are the file's";
  const ControlLook got = *control_look(g, testing::at(g, "hero:arm_L/ik"));
  EXPECT_EQ(got.points, kDrawn.points);
  EXPECT_EQ(got.color, kDrawn.color);
}

TEST(DataStep, a_build_imports_the_data_its_definition_names_and_steps_back_exactly) {
  auto f = fixture();
  auto s = body();
  const std::string bare = io::write_scene(*s);
  auto b = rig::Build::open(*s, load(f->definition), components());
  ASSERT_TRUE(b.is_ok()) << b.status().message();
  const auto& plan = (*b)->plan();
  ASSERT_FALSE(plan.empty());
  EXPECT_EQ(plan.back().component, -1);
  EXPECT_EQ(plan.back().step, "data") << "the data step comes last";
  ASSERT_TRUE((*b)->go_to(static_cast<int>(plan.size()) - 1).is_ok());
  const std::string before_data = io::write_scene(*s);
  EXPECT_NE(capture_skin_weights(*s)->back().weights, f->painted.back().weights) << "not imported yet";

  ASSERT_TRUE((*b)->forward().is_ok());
  expect_data_of(*s, *f);

  ASSERT_TRUE((*b)->back().is_ok());
  EXPECT_EQ(io::write_scene(*s), before_data) << "stepping back over the data step gives the scene back byte for byte";
  ASSERT_TRUE((*b)->build_all().is_ok());
  expect_data_of(*s, *f);
  ASSERT_TRUE((*b)->remove().is_ok());
  EXPECT_EQ(io::write_scene(*s), bare) << "build then remove gives the scene back byte for byte";
}

TEST(DataStep, the_data_step_works_in_a_later_process_and_an_update_reimports_the_data) {
  auto f = fixture();
  auto s = body();
  auto added = rig::add_rig(*s, f->definition, components());
  ASSERT_TRUE(added.is_ok()) << added.status().message();
  expect_data_of(*s, *f);

  // Saved and loaded: the record of the data step travels with the scene.
  auto loaded = io::parse_scene(io::write_scene(*s), "hero.rigel", ephemeral::default_registry());
  ASSERT_TRUE(loaded.is_ok()) << loaded.status().message();
  scene::Scene& again = **loaded;
  graph::Graph& g = again.graph();

  // Hand edits after the build; an update gives the files' data back.
  const ControlLook other{{math::Vec3(0, 0, 0), math::Vec3(0, 0, 0.3)}, false, math::Vec3(0, 0, 1)};
  ASSERT_TRUE(paste_control_look(g, {testing::at(g, "hero:arm_L/ik")}, other).is_ok());
  ASSERT_TRUE(apply_skin_weights(again, *capture_skin_weights(*body())).is_ok());
  auto updated = rig::update_rig(again, "hero", components(), f->definition, /*force=*/true);
  ASSERT_TRUE(updated.is_ok()) << updated.status().message();
  EXPECT_TRUE(updated->updated);
  expect_data_of(again, *f);

  // A changed data file comes in with an update that rebuilds nothing.
  ControlLook drawn_again = kDrawn;
  drawn_again.color = math::Vec3(0, 1, 0);
  ASSERT_TRUE(paste_control_look(g, {testing::at(g, "hero:arm_L/ik")}, drawn_again).is_ok());
  const std::string changed = control_shapes_to_json(*capture_control_shapes(g, rig::find_rig(g, "hero")));
  ASSERT_TRUE(paste_control_look(g, {testing::at(g, "hero:arm_L/ik")}, other).is_ok());
  write_text(f->shapes, changed);
  auto b = rig::Build::reopen(again, "hero", components());
  ASSERT_TRUE(b.is_ok()) << b.status().message();
  auto rebuilt = (*b)->rebuild_changed(load(f->definition));
  ASSERT_TRUE(rebuilt.is_ok()) << rebuilt.status().message();
  EXPECT_TRUE(rebuilt->empty()) << "no component changed";
  EXPECT_EQ(control_look(g, testing::at(g, "hero:arm_L/ik"))->color, math::Vec3(0, 1, 0)) << "the new file's colour";

  ASSERT_TRUE((*b)->remove().is_ok());
  EXPECT_TRUE(rig::list_rigs(g).empty());
}

TEST(DataStep, a_bad_data_file_fails_the_step_naming_it_and_changes_nothing) {
  auto f = fixture();
  write_text(f->weights, "{\"rigelWeights\": 1, \"skins\": [");
  auto s = body();
  auto b = rig::Build::open(*s, load(f->definition), components());
  ASSERT_TRUE(b.is_ok()) << b.status().message();
  const int last = static_cast<int>((*b)->plan().size()) - 1;
  ASSERT_TRUE((*b)->go_to(last).is_ok());
  const std::string before = io::write_scene(*s);
  const Status st = (*b)->forward();
  ASSERT_FALSE(st.is_ok());
  EXPECT_NE(st.message().find("body.weights.json"), std::string::npos) << st.message();
  EXPECT_NE(st.message().find("hero.rig.xml:"), std::string::npos) << "the definition's place: " << st.message();
  EXPECT_EQ((*b)->position(), last);
  EXPECT_EQ(io::write_scene(*s), before) << "rolled back";

  // Without a data importer the step says what is missing.
  write_text(f->weights, skin_weights_to_json(f->painted));
  auto plain = rig::Build::open(*s, load(f->definition), ephemeral::components());
  ASSERT_TRUE(plain.is_ok());
  const Status none = (*plain)->forward();
  ASSERT_FALSE(none.is_ok());
  EXPECT_NE(none.message().find("no data importer"), std::string::npos) << none.message();
}

TEST(DataStep, validation_reports_unknown_kinds_and_missing_files_at_their_line) {
  auto f = fixture();
  write_text(f->definition, biped_with("  <data kind=\"weights\" file=\"../data/nosuch.weights.json\"/>\n"
                                       "  <data kind=\"paint\" file=\"../data/body.weights.json\"/>\n"));
  const std::vector<rig::Diagnostic> problems = rig::check_definition(f->definition, components().schemas());
  ASSERT_EQ(problems.size(), 2u);
  EXPECT_EQ(problems[0].where.line, 7);
  EXPECT_NE(problems[0].str().find("hero.rig.xml:7:"), std::string::npos) << problems[0].str();
  EXPECT_NE(problems[0].message.find("nosuch.weights.json' does not exist"), std::string::npos) << problems[0].message;
  EXPECT_EQ(problems[1].where.line, 8);
  EXPECT_NE(problems[1].message.find("unknown kind 'paint'"), std::string::npos) << problems[1].message;
  auto s = body();
  EXPECT_FALSE(rig::add_rig(*s, f->definition, components()).is_ok()) << "an invalid definition builds nothing";
  EXPECT_TRUE(rig::list_rigs(s->graph()).empty());
}

TEST(DataFiles, the_dispatcher_imports_by_kind_and_refuses_kinds_it_cannot_read) {
  auto f = fixture();
  auto s = body();
  ASSERT_TRUE(rig::add_rig(*s, testing::source("examples/biped.rig.xml"), components()).is_ok());
  auto w = import_data_file(*s, NodeId{}, "weights", f->weights);
  ASSERT_TRUE(w.is_ok()) << w.status().message();
  EXPECT_EQ(w->kind, "weights");
  EXPECT_GT(w->weights_vertices, 10000u);
  auto sh = import_data_file(*s, NodeId{}, "shapes", f->shapes);  // onto the rig the file names
  ASSERT_TRUE(sh.is_ok()) << sh.status().message();
  EXPECT_GT(sh->shapes_set, 50u);
  expect_data_of(*s, *f);
  // A weights file is not a file of another kind: refused naming it.
  for (const char* kind : {"blendshapes", "driven_poses", "correctives"}) {
    EXPECT_TRUE(data_kind_importable(kind));
    auto r = import_data_file(*s, NodeId{}, kind, f->weights);
    ASSERT_FALSE(r.is_ok()) << kind;
    EXPECT_EQ(r.status().code(), ErrorCode::kParseError);
    EXPECT_NE(r.status().message().find(f->weights.string()), std::string::npos) << r.status().message();
  }
  auto unknown = import_data_file(*s, NodeId{}, "paint", f->weights);
  ASSERT_FALSE(unknown.is_ok());
  EXPECT_EQ(unknown.status().code(), ErrorCode::kInvalidArgument);
  auto missing = import_data_file(*s, NodeId{}, "weights", f->dir.path() / "nosuch.weights.json");
  ASSERT_FALSE(missing.is_ok());
  EXPECT_EQ(missing.status().code(), ErrorCode::kNotFound);
  EXPECT_NE(missing.status().message().find("nosuch.weights.json"), std::string::npos);
}

TEST(DataFiles, a_publish_imports_a_file_its_definition_names_once) {
  io::testing::TempDir dir;
  auto project = create_project(dir.path() / "show");
  ASSERT_TRUE(project.is_ok());
  auto asset = create_asset(*project, "hero", "character", testing::source("tests/data/gltf/rigify_human_body.glb"));
  ASSERT_TRUE(asset.is_ok()) << asset.status().message();
  auto f = fixture();
  fs::create_directories(asset->dir / "data" / "weights");
  fs::create_directories(asset->dir / "data" / "shapes");
  fs::copy_file(f->weights, asset->dir / "data" / "weights" / "body.weights.json");
  fs::copy_file(f->shapes, asset->dir / "data" / "shapes" / "hero.shapes.json");
  EXPECT_EQ(asset_data_files(*asset).size(), 2u);
  std::size_t w_count = 0;
  for (const SkinWeights& skin : f->painted) w_count += skin.vertex_count();
  // The definition names the weights; the shapes come from the folder.
  write_text(asset->dir / "build" / "hero.rig.xml", biped_with("  <data kind=\"weights\" file=\"../data/weights/body.weights.json\"/>\n"));
  auto v1 = publish_asset(*asset, ephemeral::components(), {"", true, "test"});
  ASSERT_TRUE(v1.is_ok()) << v1.status().message();
  EXPECT_EQ(v1->weights_vertices, w_count) << "the weights imported once";
  EXPECT_GT(v1->shapes_set, 50u);
  const auto manifest = nlohmann::json::parse(read_text(v1->manifest));
  ASSERT_EQ(manifest["data"].size(), 2u);
  EXPECT_EQ(manifest["data"][0]["file"], "data/weights/body.weights.json");
  EXPECT_EQ(manifest["data"][1]["file"], "data/shapes/hero.shapes.json");
  auto published = io::load_scene(v1->scene, ephemeral::default_registry());
  ASSERT_TRUE(published.is_ok());
  expect_data_of(**published, *f);
}

}  // namespace
}  // namespace rigel::tools
