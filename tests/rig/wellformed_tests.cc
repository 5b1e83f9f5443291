// What the definition readers refuse: XML that is not well-formed (pugixml
// alone accepts much of it), nesting past the documented limits in either
// syntax (refused at the place, never a crash, memory linear in the text),
// and the places of syntax errors (the unclosed open tag, not the end of
// the file).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "../io/io_test_util.h"
#include "rigel/io/scene_file.h"
#include "rigel/rig/definition_io.h"
#include "rigel/rig/build.h"
#include "rigel/rig/component.h"
#include "rigel/rig/diff.h"
#include "rigel/rig/meta.h"

namespace rigel::rig {
namespace {

namespace fs = std::filesystem;

constexpr const char* kHead = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
constexpr const char* kGlobal =
    "<component type=\"global\" name=\"global\" side=\"C\" version=\"1.0\" "
    "rigId=\"6513270e-269e-4d37-b2a7-4de452e6b438\"><guide name=\"main\"/></component>";

std::string rig_xml(const std::string& inside, const std::string& before_rig = "") {
  return std::string(kHead) + before_rig + "<rig name=\"r\" version=\"1.0\">\n" + inside + "\n</rig>\n";
}

// The one error of an XML text, "line:column: message", or "" when it reads.
std::string xml_error(const std::string& text) {
  const ParseResult r = parse_definition(text, Syntax::kXml, "t.rig.xml");
  if (r.ok()) return "";
  const Diagnostic& d = r.errors.front();
  return std::to_string(d.where.line) + ":" + std::to_string(d.where.column) + ": " + d.message;
}

TEST(WellFormed, a_valid_file_reads) { EXPECT_EQ(xml_error(rig_xml(kGlobal, "<!-- a - b -->\n")), ""); }

TEST(WellFormed, xml_that_xml_refuses_is_refused_at_its_place) {
  struct Case {
    std::string text, expected;
  };
  const Case cases[] = {
      {rig_xml(kGlobal, "<!-- a -- b -->\n"), "2:8: XML syntax error: '--' is not allowed inside a comment"},
      {rig_xml(kGlobal, "<!-- a --->\n"), "2:8: XML syntax error: '--' is not allowed inside a comment"},
      {rig_xml(kGlobal, "<?xml version=\"1.0\"?>\n"), "2:1: XML syntax error: the XML declaration must come first in the file"},
      {rig_xml(kGlobal, "<!DOCTYPE rig>\n"), "2:1: XML syntax error: a DOCTYPE is not supported in rig definitions"},
      {rig_xml("<feature name=\"a<b\"/>"), "3:17: XML syntax error: '<' is not allowed in an attribute value (write &lt;)"},
      {rig_xml("<feature name=\"a&b\"/>"),
       "3:17: XML syntax error: '&' must start a reference (&amp; &lt; &gt; &quot; &apos; &#N; &#xN;)"},
      {rig_xml("<feature name=\"&nbsp;\"/>"), "3:16: XML syntax error: undefined entity '&nbsp;' (rig definitions declare none)"},
      {rig_xml("<feature name=\"&#1;\"/>"), "3:16: XML syntax error: '&#1;' refers to a character XML does not allow"},
      {rig_xml("<feature name=\"a\x01\"/>"), "3:17: XML syntax error: character U+0001 is not allowed in XML"},
      {rig_xml("<feature name=\"a\xC3\"/>"), "3:17: XML syntax error: invalid UTF-8"},
      {rig_xml("<feature name=\"a\"enabled=\"true\"/>"), "3:18: XML syntax error: attributes must be separated by white space"},
      {rig_xml("<feature name=a/>"), "3:10: XML syntax error: an attribute value must be quoted"},
      // An unclosed element is named where it opens, not at the end of the file.
      {std::string(kHead) + "<rig name=\"r\" version=\"1.0\">\n  <component type=\"global\">\n    <guide/>\n",
       "3:3: XML syntax error: <component> is not closed"},
  };
  for (const Case& c : cases) EXPECT_EQ(xml_error(c.text), c.expected) << c.text;
}

TEST(WellFormed, the_shipped_examples_are_well_formed) {
  for (const char* name : {"examples/biped.rig.xml", "examples/puppet.rig.xml", "examples/quadruped.rig.xml",
                           "tests/data/rig/all_types.rig.xml"}) {
    const ParseResult r = load_definition(fs::path(RIGEL_SOURCE_DIR) / name);
    EXPECT_TRUE(r.ok()) << name << ": " << (r.ok() ? "" : r.errors.front().str());
  }
}

// n components, each the only child of the one before.
std::string nested_xml(std::size_t n) {
  std::string open, close;
  for (std::size_t i = 0; i < n; ++i) {
    open += "<component type=\"fkChain\" name=\"c" + std::to_string(i) + "\" version=\"1.0\">\n";
    close += "</component>\n";
  }
  return rig_xml(open + close);
}

std::string nested_json(std::size_t n) {
  std::string open, close;
  for (std::size_t i = 0; i < n; ++i) {
    open += "{\"type\": \"fkChain\", \"name\": \"c" + std::to_string(i) + "\", \"version\": \"1.0\", \"children\": [\n";
    close += "]}";
  }
  return "{\"rig\": {\"name\": \"r\", \"version\": \"1.0\", \"components\": [\n" + open + close + "]}}";
}

TEST(WellFormed, components_nest_at_most_the_limit_in_either_syntax) {
  // At the limit: read (the components need rigIds, which validate reports).
  const ParseResult xml_ok = parse_definition(nested_xml(kMaxComponentDepth), Syntax::kXml, "d.rig.xml");
  EXPECT_TRUE(xml_ok.ok()) << (xml_ok.ok() ? "" : xml_ok.errors.front().str());
  const ParseResult json_ok = parse_definition(nested_json(kMaxComponentDepth), Syntax::kJson, "d.rig.json");
  EXPECT_TRUE(json_ok.ok()) << (json_ok.ok() ? "" : json_ok.errors.front().str());
  // One more: refused at the component that passes the limit.
  const ParseResult xml = parse_definition(nested_xml(kMaxComponentDepth + 1), Syntax::kXml, "d.rig.xml");
  ASSERT_EQ(xml.errors.size(), 1u);
  EXPECT_EQ(xml.errors[0].where.line, static_cast<int>(kMaxComponentDepth) + 3) << xml.errors[0].str();
  EXPECT_NE(xml.errors[0].message.find("components nest deeper than 256 levels"), std::string::npos);
  const ParseResult json = parse_definition(nested_json(kMaxComponentDepth + 1), Syntax::kJson, "d.rig.json");
  ASSERT_EQ(json.errors.size(), 1u);
  EXPECT_EQ(json.errors[0].where.line, static_cast<int>(kMaxComponentDepth) + 2) << json.errors[0].str();
}

TEST(WellFormed, deep_input_is_refused_not_a_crash) {
  // 10,000 and 100,000 levels: refused where the text passes kMaxTextDepth.
  for (std::size_t n : {std::size_t{10000}, std::size_t{100000}}) {
    const ParseResult xml = parse_definition(nested_xml(n), Syntax::kXml, "deep.rig.xml");
    ASSERT_EQ(xml.errors.size(), 1u);
    EXPECT_EQ(xml.errors[0].where.line, static_cast<int>(kMaxTextDepth) + 2) << xml.errors[0].str();
    EXPECT_NE(xml.errors[0].message.find("nest deeper than 1024 levels"), std::string::npos) << xml.errors[0].str();
    const ParseResult json = parse_definition(nested_json(n), Syntax::kJson, "deep.rig.json");
    ASSERT_EQ(json.errors.size(), 1u);
    EXPECT_NE(json.errors[0].message.find("nest deeper than 1024 levels"), std::string::npos) << json.errors[0].str();
    const std::string arrays = std::string(n, '[') + std::string(n, ']');
    const ParseResult bare = parse_definition(arrays, Syntax::kJson, "a.rig.json");
    ASSERT_EQ(bare.errors.size(), 1u);
    EXPECT_EQ(bare.errors[0].where.column, static_cast<int>(kMaxTextDepth) + 1);
  }
  // Between the component limit and the text limit: errors, no crash, for
  // validate and diff alike.
  const ParseResult mid = parse_definition(nested_json(400), Syntax::kJson, "mid.rig.json");
  EXPECT_FALSE(mid.ok());
  EXPECT_FALSE(validate(mid.definition).empty());
  EXPECT_TRUE(diff(mid.definition, mid.definition).empty());
}

TEST(WellFormed, validate_refuses_a_definition_built_deeper_than_the_limit) {
  Definition d;
  d.name = "r";
  d.version = "1.0";
  // Built from the leaf up.
  Component inner;
  inner.type = "fkChain";
  inner.name = "leaf";
  for (std::size_t i = 0; i < kMaxComponentDepth + 5; ++i) {
    Component outer;
    outer.type = "fkChain";
    outer.name = std::to_string(i);
    outer.children.push_back(std::move(inner));
    inner = std::move(outer);
  }
  d.components.push_back(std::move(inner));
  bool found = false;
  for (const Diagnostic& e : validate(d)) found = found || e.message.find("nest deeper than 256") != std::string::npos;
  EXPECT_TRUE(found);
}

TEST(WellFormed, a_rig_without_a_name_is_refused_at_its_place) {
  const ParseResult r =
      parse_definition(std::string(kHead) + "<rig version=\"1.0\">\n" + kGlobal + "\n</rig>\n", Syntax::kXml, "n.rig.xml");
  ASSERT_TRUE(r.ok());
  const std::vector<Diagnostic> problems = validate(r.definition);
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_EQ(problems[0].str(), "n.rig.xml:2:1: the rig has no name");
  scene::Scene scene(default_registry());
  auto b = Build::open(scene, r.definition, builtin_components());
  ASSERT_FALSE(b.is_ok());
  EXPECT_EQ(b.status().message(), "build: n.rig.xml:2:1: the rig has no name");
}

TEST(WellFormed, deep_scene_files_are_refused_with_the_place) {
  io::testing::TempDir dir;
  const fs::path file = dir.path() / "deep.rigel";
  std::string text = "{\"rigel\": \"scene\", \"version\": 1, \"nodes\": [{\"name\": \"a\", \"type\": \"transform\", \"tags\": ";
  text += std::string(100000, '[') + std::string(100000, ']') + "}], \"connections\": []}";
  { std::ofstream(file) << text; }
  auto loaded = io::load_scene(file, default_registry());
  ASSERT_FALSE(loaded.is_ok());
  EXPECT_NE(loaded.status().message().find("deep.rigel:1:"), std::string::npos) << loaded.status().message();
  EXPECT_NE(loaded.status().message().find("nest deeper than"), std::string::npos) << loaded.status().message();
}

}  // namespace
}  // namespace rigel::rig
