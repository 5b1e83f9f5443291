// `rigel validate`, `rigel components`, `rigel schema`, `rigel diff` (rig
// definitions; docs/RIG.md): exit codes, error places, --json shapes.

#include <gtest/gtest.h>

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

std::string fixture(const std::string& name) {
  return (fs::path(RIGEL_SOURCE_DIR) / "tests" / "data" / "rig" / name).string();
}

TEST(CliDefinition, validate_accepts_valid_files_in_both_syntaxes) {
  const CliRun r = rigel({"validate", fixture("all_types.rig.xml"), fixture("all_types.rig.json")});
  EXPECT_TRUE(exited_with(r, 0)) << r;
  EXPECT_TRUE(contains(r.err, "all_types.rig.xml: valid")) << r;
  EXPECT_TRUE(contains(r.err, "all_types.rig.json: valid")) << r;
}

TEST(CliDefinition, validate_prints_every_problem_with_its_place_and_exits_1) {
  const std::string file = fixture("invalid_semantic.rig.xml");
  const CliRun r = rigel({"validate", fixture("all_types.rig.xml"), file});
  EXPECT_TRUE(exited_with(r, 1)) << r;
  EXPECT_TRUE(contains(r.err, file + ":5:5: component 'wing' (wing, L): unknown component type 'wing'")) << r;
  EXPECT_TRUE(contains(r.err, file + ":12:9: component 'arm' (limb, L): parameter 'stretch' must be a bool")) << r;
  EXPECT_TRUE(contains(r.err, file + ":22:7: component 'inner' (global): a global component must be a root")) << r;
  EXPECT_TRUE(contains(r.err, file + ": 15 errors")) << r;
  const CliRun syntax = rigel({"validate", fixture("syntax_error.rig.json")});
  EXPECT_TRUE(exited_with(syntax, 1)) << syntax;
  EXPECT_TRUE(contains(syntax.err, fixture("syntax_error.rig.json") + ":4:20: JSON syntax error")) << syntax;
  const CliRun missing = rigel({"validate", fixture("missing.rig.xml")});
  EXPECT_TRUE(exited_with(missing, 1)) << missing;
  EXPECT_TRUE(exited_with(rigel({"validate"}), 2)) << "no file is a usage error";
}

TEST(CliDefinition, validate_json_lists_files_and_errors) {
  const CliRun r = rigel({"validate", "--json", fixture("all_types.rig.json"), fixture("cycle.rig.json")});
  EXPECT_TRUE(exited_with(r, 1)) << r;
  const Json out = Json::parse(r.out);
  ASSERT_EQ(out["files"].size(), 2u);
  EXPECT_EQ(out["files"][0]["valid"], true);
  EXPECT_EQ(out["files"][0]["errors"], Json::array());
  const Json& cycle = out["files"][1];
  EXPECT_EQ(cycle["file"], fixture("cycle.rig.json"));
  EXPECT_EQ(cycle["valid"], false);
  ASSERT_EQ(cycle["errors"].size(), 2u);
  EXPECT_EQ(cycle["errors"][0]["line"], 11);
  EXPECT_EQ(cycle["errors"][0]["column"], 11);
  EXPECT_TRUE(contains(cycle["errors"][0]["message"].get<std::string>(), "'a' -> 'c' -> 'b' -> 'a'"));
}

TEST(CliDefinition, components_lists_types_with_parameters_guides_controls_and_hooks) {
  const CliRun all = rigel({"components"});
  EXPECT_TRUE(exited_with(all, 0)) << all;
  for (const char* type : {"global:", "limb:", "ephemeral:", "twist:"}) EXPECT_TRUE(contains(all.out, type)) << type;
  const CliRun limb = rigel({"components", "limb"});
  EXPECT_TRUE(exited_with(limb, 0)) << limb;
  EXPECT_TRUE(contains(limb.out, "maxStretch (double >= 1, default 1.5): Largest stretch factor.")) << limb;
  EXPECT_TRUE(contains(limb.out, "guides: exactly 3 (upper, lower, end)")) << limb;
  EXPECT_TRUE(contains(limb.out, "hooks: upper, lower, end")) << limb;
  EXPECT_FALSE(contains(limb.out, "global:")) << "one type only";
  const CliRun json = rigel({"components", "twist", "--json"});
  EXPECT_TRUE(exited_with(json, 0)) << json;
  const Json twist = Json::parse(json.out)["components"][0];
  EXPECT_EQ(twist["type"], "twist");
  EXPECT_EQ(twist["params"][0], (Json{{"name", "count"}, {"type", "int"}, {"default", 3}, {"min", 1.0}, {"max", 16.0},
                                      {"help", "Number of twist joints."}}));
  EXPECT_EQ(twist["params"][1]["choices"], (Json{"x", "y", "z"}));
  EXPECT_EQ(twist["guides"]["names"], (Json{"start", "end"}));
  EXPECT_EQ(twist["hooks"], (Json{"start", "end"}));
  const CliRun unknown = rigel({"components", "wing"});
  EXPECT_TRUE(exited_with(unknown, 1)) << unknown;
  EXPECT_TRUE(contains(unknown.err, "unknown component type 'wing'")) << unknown;
}

TEST(CliDefinition, schema_prints_the_shipped_files) {
  const CliRun json = rigel({"schema", "--json"});
  EXPECT_TRUE(exited_with(json, 0)) << json;
  EXPECT_EQ(json.out, read_text(fs::path(RIGEL_SOURCE_DIR) / "schemas" / "rig.schema.json"));
  const CliRun xsd = rigel({"schema", "--xsd"});
  EXPECT_TRUE(exited_with(xsd, 0)) << xsd;
  EXPECT_EQ(xsd.out, read_text(fs::path(RIGEL_SOURCE_DIR) / "schemas" / "rig.xsd"));
  EXPECT_TRUE(exited_with(rigel({"schema"}), 2)) << "one of --json or --xsd is needed";
  EXPECT_TRUE(exited_with(rigel({"schema", "--json", "--xsd"}), 2));
}

TEST(CliDefinition, diff_exits_0_when_equal_1_when_different_2_on_trouble) {
  const CliRun same = rigel({"diff", fixture("all_types.rig.xml"), fixture("all_types.rig.json")});
  EXPECT_TRUE(exited_with(same, 0)) << same;
  EXPECT_EQ(same.out, "");
  TempDir dir;
  std::string text = read_text(fixture("all_types.rig.json"));
  text.replace(text.find("\"maxStretch\": 1.25"), 18, "\"maxStretch\": 1.5");
  const std::string changed = (dir.path() / "changed.rig.json").string();
  rigel::io::testing::write_text(changed, text);
  const CliRun r = rigel({"diff", fixture("all_types.rig.xml"), changed});
  EXPECT_TRUE(exited_with(r, 1)) << r;
  EXPECT_EQ(r.out, "component 'arm' [056085bd]: parameter 'maxStretch': 1.25 -> 1.5\n");
  const CliRun json = rigel({"diff", "--json", fixture("all_types.rig.xml"), changed});
  EXPECT_TRUE(exited_with(json, 1)) << json;
  const Json out = Json::parse(json.out);
  EXPECT_EQ(out["equal"], false);
  ASSERT_EQ(out["differences"].size(), 1u);
  EXPECT_EQ(out["differences"][0]["kind"], "paramChanged");
  EXPECT_EQ(out["differences"][0]["rigId"], "056085bd-f7e6-45bb-8505-54f724ac83a7");
  EXPECT_EQ(out["differences"][0]["item"], "maxStretch");
  EXPECT_EQ(out["differences"][0]["old"], "1.25");
  EXPECT_EQ(out["differences"][0]["new"], "1.5");
  const CliRun broken = rigel({"diff", fixture("all_types.rig.xml"), fixture("syntax_error.rig.xml")});
  EXPECT_TRUE(exited_with(broken, 2)) << broken;
  EXPECT_TRUE(contains(broken.err, "syntax_error.rig.xml:4:3: XML syntax error")) << broken;
}

TEST(CliDefinition, deep_nesting_is_refused_with_the_place_not_a_crash) {
  TempDir dir;
  std::string open, close;
  for (int i = 0; i < 10000; ++i) {
    open += "<component type=\"fkChain\" name=\"c" + std::to_string(i) + "\" version=\"1.0\">\n";
    close += "</component>\n";
  }
  const std::string xml = (dir.path() / "deep.rig.xml").string();
  std::ofstream(xml) << "<?xml version=\"1.0\"?>\n<rig name=\"r\" version=\"1.0\">\n" << open << close << "</rig>\n";
  const std::string json = (dir.path() / "deep.rig.json").string();
  std::ofstream(json) << "{\"rig\": " << std::string(10000, '[') << std::string(10000, ']') << "}";
  for (const std::string& file : {xml, json}) {
    const CliRun v = rigel({"validate", file});
    EXPECT_TRUE(exited_with(v, 1)) << v;
    EXPECT_TRUE(contains(v.err, "nest deeper than 1024 levels")) << v;
    EXPECT_TRUE(contains(v.err, file + ":")) << v;
    const CliRun d = rigel({"diff", file, file});
    EXPECT_TRUE(exited_with(d, 2)) << d;
    const CliRun b = rigel({"build", file, "--character", (fs::path(RIGEL_SOURCE_DIR) / "tests/data/gltf/rigify_human_metarig.glb").string(),
                            "-o", (dir.path() / "x.rigel").string()});
    EXPECT_TRUE(exited_with(b, 1)) << b;
  }
  // The shipped examples are well-formed XML (puppet's comment held "--").
  const CliRun examples = rigel({"validate", (fs::path(RIGEL_SOURCE_DIR) / "examples/puppet.rig.xml").string(),
                                 (fs::path(RIGEL_SOURCE_DIR) / "examples/biped.rig.xml").string()});
  EXPECT_TRUE(exited_with(examples, 0)) << examples;
  const std::string comment = (dir.path() / "comment.rig.xml").string();
  std::ofstream(comment) << "<?xml version=\"1.0\"?>\n<!-- a -- b -->\n<rig name=\"r\" version=\"1.0\"/>\n";
  const CliRun c = rigel({"validate", comment});
  EXPECT_TRUE(exited_with(c, 1)) << c;
  EXPECT_TRUE(contains(c.err, "comment.rig.xml:2:8: XML syntax error: '--' is not allowed inside a comment")) << c;
}

TEST(CliDefinition, help_shows_an_example_for_each_command) {
  for (const char* command : {"validate", "components", "schema", "diff"}) {
    const CliRun r = rigel({command, "--help"});
    EXPECT_TRUE(exited_with(r, 0)) << r;
    EXPECT_TRUE(contains(r.out, std::string("rigel ") + command)) << command << " --help should show an example: " << r;
  }
}

}  // namespace
}  // namespace rigel::cli
