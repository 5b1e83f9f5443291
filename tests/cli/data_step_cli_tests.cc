// `rigel build DEF --character FILE` with <data> entries: the biped on the
// bundled body, its shapes and weights exported, edited and named by the
// definition, come back in the built scene; `rigel remove` takes them out
// with the rig; a data file that is not there is refused at its line.
#include <filesystem>
#include <fstream>

#include "cli_test_util.h"

namespace rigel::cli::testing {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

std::string biped() { return (fs::path(RIGEL_SOURCE_DIR) / "examples/biped.rig.xml").string(); }
std::string body() { return (fs::path(RIGEL_SOURCE_DIR) / "tests/data/gltf/rigify_human_body.glb").string(); }

// The biped's definition with `data` lines after its <rig> line (line 7 on).
std::string biped_with(const std::string& data) {
  std::string text = read_text(biped());
  const std::size_t end = text.find('\n', text.find("<rig ")) + 1;
  return text.substr(0, end) + data + text.substr(end);
}

TEST(CliDataStep, build_imports_the_data_the_definition_names) {
  TempDir dir;
  auto at = [&](const std::string& name) { return (dir.path() / name).string(); };
  ASSERT_EQ(rigel({"import", body(), "-o", at("body.rigel")}).exit_code, 0);
  ASSERT_EQ(rigel({"build", biped(), "--character", at("body.rigel"), "-o", at("first.rigel")}).exit_code, 0);
  fs::create_directories(dir.path() / "data");
  CliRun e = rigel({"data", "export", "shapes", at("first.rigel"), "-o", at("data/hero.shapes.json")});
  ASSERT_EQ(e.exit_code, 0) << e;
  e = rigel({"data", "export", "weights", at("first.rigel"), "-o", at("data/body.weights.json")});
  ASSERT_EQ(e.exit_code, 0) << e;

  // Hand-made work: a control recoloured, a vertex painted onto one joint.
  Json shapes = Json::parse(read_text(at("data/hero.shapes.json")));
  shapes["controls"][0]["color"] = Json::array({0.25, 0.5, 1.0});
  std::ofstream(at("data/hero.shapes.json")) << shapes.dump(2);
  Json weights = Json::parse(read_text(at("data/body.weights.json")));
  Json& vertex = weights["skins"][0]["vertices"][7];
  vertex = Json::array({vertex[0], 1.0});
  std::ofstream(at("data/body.weights.json")) << weights.dump(2);

  fs::create_directories(dir.path() / "build");
  std::ofstream(at("build/hero.rig.xml")) << biped_with("  <data kind=\"weights\" file=\"../data/body.weights.json\"/>\n"
                                                        "  <data kind=\"shapes\" file=\"../data/hero.shapes.json\"/>\n");
  CliRun b = rigel({"build", at("build/hero.rig.xml"), "--character", at("body.rigel"), "-o", at("hero.rigel"), "--json"});
  ASSERT_EQ(b.exit_code, 0) << b;
  const Json summary = Json::parse(b.out);
  EXPECT_EQ(summary["steps"], summary["of"]);

  ASSERT_EQ(rigel({"data", "export", "shapes", at("hero.rigel"), "-o", at("back.shapes.json")}).exit_code, 0);
  const Json shapes_back = Json::parse(read_text(at("back.shapes.json")));
  EXPECT_EQ(shapes_back["controls"][0]["color"], Json::array({0.25, 0.5, 1.0})) << "the recoloured control";
  EXPECT_EQ(shapes_back, shapes);
  ASSERT_EQ(rigel({"data", "export", "weights", at("hero.rigel"), "-o", at("back.weights.json")}).exit_code, 0);
  const Json weights_back = Json::parse(read_text(at("back.weights.json")));
  ASSERT_EQ(weights_back["skins"][0]["vertices"][7].size(), 2u);
  EXPECT_EQ(weights_back["skins"][0]["vertices"][7][1].get<double>(), 1.0) << "the painted vertex";
  EXPECT_EQ(weights_back, weights);

  // Removing the rig undoes its data step: the weights are the body's again.
  CliRun r = rigel({"remove", at("hero.rigel"), "--rig", "hero", "-o", at("removed.rigel")});
  ASSERT_EQ(r.exit_code, 0) << r;
  ASSERT_EQ(rigel({"data", "export", "weights", at("removed.rigel"), "-o", at("removed.weights.json")}).exit_code, 0);
  ASSERT_EQ(rigel({"data", "export", "weights", at("body.rigel"), "-o", at("body.weights.json")}).exit_code, 0);
  EXPECT_EQ(read_text(at("removed.weights.json")), read_text(at("body.weights.json")));
}

TEST(CliDataStep, a_missing_data_file_is_refused_at_its_line) {
  TempDir dir;
  const fs::path def = dir.path() / "hero.rig.xml";
  std::ofstream(def) << biped_with("  <data kind=\"weights\" file=\"nosuch.weights.json\"/>\n");
  const std::string out = (dir.path() / "x.rigel").string();
  CliRun b = rigel({"build", def.string(), "--character", body(), "-o", out});
  EXPECT_EQ(b.exit_code, 1) << b;
  EXPECT_TRUE(contains(b.err, "hero.rig.xml:7:")) << b;
  EXPECT_TRUE(contains(b.err, "nosuch.weights.json")) << b;
  EXPECT_FALSE(fs::exists(out));
  CliRun v = rigel({"validate", def.string()});
  EXPECT_EQ(v.exit_code, 1) << v;
  EXPECT_TRUE(contains(v.err, "hero.rig.xml:7:")) << v;
}

}  // namespace
}  // namespace rigel::cli::testing
