// Reading and writing rig definitions (rig/definition_io.h): golden files in
// both syntaxes, byte-identical round trips within and across syntaxes,
// every parameter type, exact doubles, the places of structural and syntax
// errors, atomic saves, and the shipped schema files.

#include <gtest/gtest.h>
#include <pugixml.hpp>

#include <cmath>
#include <limits>
#include <set>

#include <nlohmann/json.hpp>

#include "../io/io_test_util.h"
#include "rigel/rig/definition_io.h"

namespace rigel::rig {
namespace {

namespace fs = std::filesystem;
using rigel::io::testing::read_text;
using rigel::io::testing::TempDir;
using rigel::io::testing::write_text;

fs::path data(const std::string& name) { return fs::path(RIGEL_SOURCE_DIR) / "tests" / "data" / "rig" / name; }

ParseResult parse_ok(const std::string& text, Syntax syntax, const SchemaRegistry& schemas = builtin_schemas()) {
  ParseResult r = parse_definition(text, syntax, "t", schemas);
  EXPECT_TRUE(r.ok()) << (r.errors.empty() ? "" : r.errors[0].str());
  return r;
}

// "line:column: message" of every error, for comparing whole lists.
std::vector<std::string> places(const std::vector<Diagnostic>& errors) {
  std::vector<std::string> out;
  for (const Diagnostic& d : errors) out.push_back(std::to_string(d.where.line) + ":" + std::to_string(d.where.column) + ": " + d.message);
  return out;
}

// A component type with one parameter of every kind, for the tests of
// parameter typing (the shipped types have no string or vec3 parameter).
const SchemaRegistry& gadget_schemas() {
  static const SchemaRegistry r = [] {
    SchemaRegistry s;
    ComponentSchema c;
    c.type = "gadget";
    c.params = {ParamSpec{"on", ParamType::kBool, false, {}, {}, {}, ""},
                ParamSpec{"count", ParamType::kInt, std::int64_t{1}, {}, {}, {}, ""},
                ParamSpec{"gain", ParamType::kDouble, 1.0, {}, {}, {}, ""},
                ParamSpec{"label", ParamType::kString, std::string(), {}, {}, {}, ""},
                ParamSpec{"mode", ParamType::kEnum, std::string("a"), {}, {}, {"a", "b"}, ""},
                ParamSpec{"offset", ParamType::kVec3, math::Vec3::Zero(), {}, {}, {}, ""}};
    c.guides = {0, -1, {}, ""};
    c.hooks = {"guide[i]"};
    EXPECT_TRUE(s.add(c).is_ok());
    return s;
  }();
  return r;
}

Definition gadget_definition() {
  Definition d;
  d.name = "gadgets";
  Component c;
  c.type = "gadget";
  c.name = "g";
  c.rig_id = "dc1d18de-c423-42aa-915a-cfc6c3c62d32";
  c.params = {{"on", true, {}},
              {"count", std::numeric_limits<std::int64_t>::max(), {}},
              {"gain", 0.1 + 0.2, {}},
              {"label", std::string("say \"hi\" & <bye>\n\ttab"), {}},
              {"mode", std::string("b"), {}},
              {"offset", math::Vec3(1.0 / 3.0, -2.5e-300, 1e21), {}}};
  d.components.push_back(c);
  return d;
}

TEST(DefinitionIo, golden_files_round_trip_byte_for_byte_within_and_across_syntaxes) {
  const std::string xml = read_text(data("all_types.rig.xml"));
  const std::string json = read_text(data("all_types.rig.json"));
  const ParseResult from_xml = parse_ok(xml, Syntax::kXml);
  const ParseResult from_json = parse_ok(json, Syntax::kJson);
  EXPECT_EQ(write_definition(from_xml.definition, Syntax::kXml), xml) << "XML -> model -> XML must give the same text";
  EXPECT_EQ(write_definition(from_json.definition, Syntax::kJson), json) << "JSON -> model -> JSON must give the same text";
  EXPECT_EQ(write_definition(from_xml.definition, Syntax::kJson), json) << "the XML golden file written as JSON is the JSON golden file";
  EXPECT_EQ(write_definition(from_json.definition, Syntax::kXml), xml) << "the JSON golden file written as XML is the XML golden file";
  // XML -> model -> JSON -> model -> XML, and the other way, through text.
  EXPECT_EQ(write_definition(parse_ok(write_definition(from_xml.definition, Syntax::kJson), Syntax::kJson).definition, Syntax::kXml), xml);
  EXPECT_EQ(write_definition(parse_ok(write_definition(from_json.definition, Syntax::kXml), Syntax::kXml).definition, Syntax::kJson), json);
}

TEST(DefinitionIo, golden_file_holds_every_shipped_component_type_and_is_valid) {
  const ParseResult r = load_definition(data("all_types.rig.xml"));
  ASSERT_TRUE(r.ok());
  std::set<std::string> types;
  for (const Component* c : r.definition.all_components()) types.insert(c->type);
  const std::vector<std::string> all = builtin_schemas().types();
  EXPECT_EQ(std::vector<std::string>(types.begin(), types.end()), all) << "the round-trip fixture should use every type";
  EXPECT_TRUE(validate(r.definition).empty()) << places(validate(r.definition))[0];
}

TEST(DefinitionIo, the_model_holds_what_the_file_says) {
  const ParseResult r = load_definition(data("all_types.rig.json"));
  ASSERT_TRUE(r.ok());
  const Definition& d = r.definition;
  EXPECT_EQ(d.name, "creature");
  EXPECT_EQ(d.version, "2.3");
  ASSERT_TRUE(d.gui_location);
  EXPECT_EQ(*d.gui_location, (std::pair{247.0, 461.5}));
  ASSERT_EQ(d.geometry.size(), 2u);
  EXPECT_EQ(d.geometry[1].name, "");
  ASSERT_EQ(d.features.size(), 2u);
  EXPECT_FALSE(d.features[0].switches[0].enabled);
  const Component* arm = d.find_by_name("arm");
  ASSERT_NE(arm, nullptr);
  EXPECT_EQ(arm->side, Side::kLeft);
  EXPECT_EQ(arm->attach, "chest");
  EXPECT_EQ(std::get<bool>(arm->param("stretch")->value), false);
  EXPECT_EQ(std::get<double>(arm->param("maxStretch")->value), 1.25);
  EXPECT_EQ(std::get<std::string>(arm->param("kind")->value), "arm");
  const Component* twist = d.find_by_name("forearmTwist");
  ASSERT_NE(twist, nullptr);
  EXPECT_EQ(std::get<std::int64_t>(twist->param("count")->value), 4) << "an int parameter is read as an int";
  const Component* tail = d.find_by_name("tail");
  ASSERT_NE(tail, nullptr);
  EXPECT_EQ(tail->guides[1].translate.y(), 0.1 + 0.2) << "doubles read back exactly";
  EXPECT_EQ(tail->guides[3].scale, math::Vec3(1, 1, 0.5));
  EXPECT_EQ(tail->guides[0].scale, math::Vec3::Ones()) << "an absent scale is 1 1 1";
  const Component* global = d.find_by_rig_id("dc1d18de-c423-42aa-915a-cfc6c3c62d32");
  ASSERT_NE(global, nullptr);
  EXPECT_EQ(global->where, (SourceLocation{22, 7})) << "a component's place is its object's '{'";
  EXPECT_EQ(global->guides[0].rotate, math::Vec3(0, 45, 0));
}

TEST(DefinitionIo, every_parameter_type_round_trips_exactly_in_both_syntaxes) {
  const Definition d = gadget_definition();
  for (Syntax first : {Syntax::kXml, Syntax::kJson}) {
    const Syntax second = first == Syntax::kXml ? Syntax::kJson : Syntax::kXml;
    const std::string text = write_definition(d, first);
    const ParseResult r = parse_ok(text, first, gadget_schemas());
    ASSERT_EQ(r.definition.components.size(), 1u);
    const Component& c = r.definition.components[0];
    ASSERT_EQ(c.params.size(), d.components[0].params.size());
    for (std::size_t i = 0; i < c.params.size(); ++i) {
      EXPECT_EQ(c.params[i].name, d.components[0].params[i].name);
      EXPECT_TRUE(c.params[i].value == d.components[0].params[i].value)
          << c.params[i].name << " should read back with its type and exact value from " << text;
    }
    const std::string across = write_definition(r.definition, second);
    EXPECT_EQ(write_definition(parse_ok(across, second, gadget_schemas()).definition, first), text)
        << "through the other syntax and back gives the same text";
  }
}

TEST(DefinitionIo, doubles_are_written_in_their_shortest_exact_form) {
  const std::string xml = write_definition(gadget_definition(), Syntax::kXml);
  EXPECT_NE(xml.find(R"(<param name="gain" value="0.30000000000000004"/>)"), std::string::npos) << xml;
  EXPECT_NE(xml.find(R"(<param name="offset" value="0.3333333333333333 -2.5e-300 1e+21"/>)"), std::string::npos) << xml;
  EXPECT_NE(xml.find(R"(<param name="label" value="say &quot;hi&quot; &amp; &lt;bye&gt;&#10;&#9;tab"/>)"), std::string::npos)
      << "attribute text escapes markup and keeps newlines and tabs as references: " << xml;
  const std::string json = write_definition(gadget_definition(), Syntax::kJson);
  EXPECT_NE(json.find(R"("gain": 0.30000000000000004)"), std::string::npos) << json;
  EXPECT_NE(json.find(R"("offset": [0.3333333333333333, -2.5e-300, 1e+21])"), std::string::npos) << json;
  EXPECT_NE(json.find(R"("count": 9223372036854775807)"), std::string::npos) << json;
  Definition d = gadget_definition();
  d.components[0].params = {{"gain", 2.0, {}}};
  EXPECT_NE(write_definition(d, Syntax::kJson).find(R"("gain": 2.0)"), std::string::npos)
      << "a double keeps a decimal point in JSON, so it reads back as a double even without a schema";
  EXPECT_NE(write_definition(d, Syntax::kXml).find(R"(value="2")"), std::string::npos);
}

TEST(DefinitionIo, defaults_are_left_out_and_read_back) {
  Definition d;
  d.name = "tiny";
  Component c;
  c.type = "fkChain";
  c.name = "chain";
  c.guides.resize(1);
  d.components.push_back(c);
  const std::string xml = write_definition(d, Syntax::kXml);
  EXPECT_EQ(xml,
            "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
            "<rig name=\"tiny\" version=\"1.0\">\n"
            "  <component type=\"fkChain\" name=\"chain\" side=\"C\" version=\"1.0\">\n"
            "    <guide/>\n"
            "  </component>\n"
            "</rig>\n")
      << "no rigId, attach, guiLocation or guide values when empty or default; side and version always";
  const std::string json = write_definition(d, Syntax::kJson);
  EXPECT_EQ(json,
            "{\n"
            "  \"rig\": {\n"
            "    \"name\": \"tiny\",\n"
            "    \"version\": \"1.0\",\n"
            "    \"components\": [\n"
            "      {\n"
            "        \"type\": \"fkChain\",\n"
            "        \"name\": \"chain\",\n"
            "        \"side\": \"C\",\n"
            "        \"version\": \"1.0\",\n"
            "        \"guides\": [\n"
            "          {}\n"
            "        ]\n"
            "      }\n"
            "    ]\n"
            "  }\n"
            "}\n");
  const ParseResult r = parse_ok(R"({"rig": {"name": "t", "components": [{"type": "fkChain", "name": "c", "guides": [{}]}]}})",
                                 Syntax::kJson);
  ASSERT_EQ(r.definition.components.size(), 1u);
  EXPECT_EQ(r.definition.version, "1.0");
  EXPECT_EQ(r.definition.components[0].side, Side::kCenter);
  EXPECT_EQ(r.definition.components[0].version, "1.0");
  EXPECT_EQ(r.definition.components[0].guides[0].scale, math::Vec3::Ones());
}

TEST(DefinitionIo, xml_structure_errors_are_all_reported_at_their_place) {
  const ParseResult r = load_definition(data("invalid_structure.rig.xml"));
  const std::vector<std::string> expected = {
      "2:33: unknown attribute 'colour' on <rig> (expected name, version, guiLocation)",
      "3:110: duplicate attribute 'name' on <component>",
      "3:48: <component> side: unknown side 'X' (expected C, L or R)",
      "4:35: <guide> translate: expected three numbers \"x y z\", got '0 1'",
      "5:32: <control> size: bad number 'big'",
      "6:5: unknown element <location> in <component> (expected guide, control, param, feature, component)",
      "7:38: <feature> enabled: 'yes' is not true or false",
      "8:5: <param> needs a value attribute",
      "9:5: unexpected text in <component>",
  };
  EXPECT_EQ(places(r.errors), expected);
  for (const Diagnostic& d : r.errors) EXPECT_EQ(d.file, data("invalid_structure.rig.xml").string());
}

TEST(DefinitionIo, json_structure_errors_are_all_reported_at_their_place) {
  const ParseResult r = load_definition(data("invalid_structure.rig.json"));
  const std::vector<std::string> expected = {
      "13:9: duplicate key 'name' (the last one would win)",
      "5:5: unknown key 'colour' in the rig (expected name, version, guiLocation, geometry, features, data, components)",
      "8:53: 'side': unknown side 'X' (expected C, L or R)",
      "8:69: 'version' must be a string, not a number",
      "10:50: 'translate' must be an array of 3 numbers [x, y, z], not an array of 2 values",
      "11:47: 'size' must be a number, not a string",
      "12:31: parameter 'stretch' must be true/false, a number, a string or [x, y, z], not an object",
  };
  EXPECT_EQ(places(r.errors), expected);
}

TEST(DefinitionIo, syntax_errors_name_their_line_and_column) {
  const ParseResult xml = load_definition(data("syntax_error.rig.xml"));
  ASSERT_EQ(xml.errors.size(), 1u);
  EXPECT_EQ(places(xml.errors)[0], "4:3: XML syntax error: Start-end tags mismatch");
  const ParseResult json = load_definition(data("syntax_error.rig.json"));
  ASSERT_EQ(json.errors.size(), 1u);
  EXPECT_EQ(json.errors[0].where, (SourceLocation{4, 20}));
  EXPECT_NE(json.errors[0].message.find("unexpected ','"), std::string::npos) << json.errors[0].message;
  EXPECT_EQ(json.errors[0].message.find("[json.exception"), std::string::npos) << "no library prefix in the message";
  EXPECT_TRUE(xml.definition.components.empty());
}

TEST(DefinitionIo, json_places_count_code_points_and_find_escaped_keys) {
  // "é" is two bytes; the column counts it as one character. The escaped key
  // "a\/b" is the key "a/b" (a JSON-pointer token "a~1b").
  const std::string text = "{\"rig\": {\"name\": \"\xC3\xA9\", \"a\\/b\": 1,\n \"\\u00e9x\": 2}}";
  const ParseResult r = parse_definition(text, Syntax::kJson, "u.json");
  ASSERT_EQ(r.errors.size(), 2u);
  EXPECT_EQ(places(r.errors)[0].substr(0, 5), "1:23:") << places(r.errors)[0];
  EXPECT_NE(r.errors[0].message.find("'a/b'"), std::string::npos);
  EXPECT_EQ(places(r.errors)[1].substr(0, 4), "2:2:") << places(r.errors)[1];
  EXPECT_NE(r.errors[1].message.find("'\xC3\xA9x'"), std::string::npos) << r.errors[1].message;
}

TEST(DefinitionIo, unknown_and_ill_typed_parameters_are_kept_for_validate) {
  const ParseResult xml = parse_ok(
      R"(<rig name="r"><component type="limb" name="a" rigId="x"><param name="stretch" value="maybe"/><param name="zap" value="1.5"/></component></rig>)",
      Syntax::kXml);
  ASSERT_EQ(xml.definition.components.size(), 1u);
  EXPECT_EQ(std::get<std::string>(xml.definition.components[0].params[0].value), "maybe");
  EXPECT_EQ(std::get<std::string>(xml.definition.components[0].params[1].value), "1.5")
      << "an unknown parameter stays text in XML";
  const ParseResult json = parse_ok(
      R"({"rig": {"name": "r", "components": [{"type": "limb", "name": "a", "params": {"maxStretch": 2, "zap": 1.5, "stretch": "yes"}}]}})",
      Syntax::kJson);
  const Component& c = json.definition.components[0];
  EXPECT_EQ(std::get<double>(c.params[0].value), 2.0) << "an integer given for a double parameter becomes a double";
  EXPECT_EQ(std::get<double>(c.params[1].value), 1.5);
  EXPECT_EQ(std::get<std::string>(c.params[2].value), "yes");
}

TEST(DefinitionIo, files_hold_one_rig) {
  EXPECT_EQ(places(parse_definition("<rigs/>", Syntax::kXml, "f").errors),
            (std::vector<std::string>{"1:1: the root element must be <rig>, not <rigs>"}));
  EXPECT_EQ(places(parse_definition("[1]", Syntax::kJson, "f").errors),
            (std::vector<std::string>{"1:1: the file must hold an object {\"rig\": {...}}, not an array"}));
  EXPECT_EQ(places(parse_definition("{}", Syntax::kJson, "f").errors),
            (std::vector<std::string>{"1:1: no \"rig\" key: the file must hold {\"rig\": {...}}"}));
}

TEST(DefinitionIo, load_reports_unreadable_files_and_unknown_syntaxes) {
  const ParseResult missing = load_definition(data("no_such_file.rig.xml"));
  ASSERT_EQ(missing.errors.size(), 1u);
  EXPECT_NE(missing.errors[0].str().find("no_such_file.rig.xml: cannot be read"), std::string::npos);
  const ParseResult unknown = load_definition(data("all_types.rig.yaml"));
  ASSERT_EQ(unknown.errors.size(), 1u);
  EXPECT_NE(unknown.errors[0].message.find("unknown definition syntax"), std::string::npos);
  EXPECT_EQ(syntax_of("a/b.rig.xml"), Syntax::kXml);
  EXPECT_EQ(syntax_of("B.RIG.JSON"), Syntax::kJson);
  EXPECT_EQ(syntax_of("b.rig"), std::nullopt);
}

TEST(DefinitionIo, diagnostics_print_as_file_line_column_message) {
  EXPECT_EQ((Diagnostic{"a.rig.xml", {3, 7}, "bad"}).str(), "a.rig.xml:3:7: bad");
  EXPECT_EQ((Diagnostic{"a.rig.xml", {}, "bad"}).str(), "a.rig.xml: bad");
  EXPECT_EQ((Diagnostic{"", {3, 7}, "bad"}).str(), "3:7: bad");
}

TEST(DefinitionIo, save_is_atomic_and_writes_the_syntax_of_the_name) {
  TempDir dir;
  const ParseResult r = load_definition(data("all_types.rig.xml"));
  ASSERT_TRUE(r.ok());
  ASSERT_TRUE(save_definition(r.definition, dir.path() / "out.rig.json").is_ok());
  ASSERT_TRUE(save_definition(r.definition, dir.path() / "out.rig.xml").is_ok());
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"out.rig.json", "out.rig.xml"})) << "no temporary file is left";
  EXPECT_EQ(read_text(dir.path() / "out.rig.json"), read_text(data("all_types.rig.json")));
  EXPECT_EQ(read_text(dir.path() / "out.rig.xml"), read_text(data("all_types.rig.xml")));
  EXPECT_EQ(save_definition(r.definition, dir.path() / "out.rig").code(), ErrorCode::kInvalidArgument);
  EXPECT_FALSE(save_definition(r.definition, dir.path() / "missing" / "out.rig.xml").is_ok());
}

TEST(DefinitionIo, special_characters_survive_both_syntaxes) {
  Definition d;
  d.name = "r";
  d.geometry.push_back({"dir with spaces/\"q\" & <x>\n\r\t\xC3\xA9.glb", "m\xC3\xA9sh", {}});
  const std::string xml = write_definition(d, Syntax::kXml);
  const ParseResult back = parse_ok(xml, Syntax::kXml);
  ASSERT_EQ(back.definition.geometry.size(), 1u);
  EXPECT_EQ(back.definition.geometry[0].file, d.geometry[0].file);
  EXPECT_EQ(write_definition(parse_ok(write_definition(back.definition, Syntax::kJson), Syntax::kJson).definition, Syntax::kXml),
            xml);
}

TEST(DefinitionIo, shipped_schema_files_are_the_generated_ones) {
  // Regenerate with `rigel schema --json > schemas/rig.schema.json` and
  // `rigel schema --xsd > schemas/rig.xsd` (docs/RIG.md).
  EXPECT_EQ(read_text(fs::path(RIGEL_SOURCE_DIR) / "schemas" / "rig.schema.json"), definition_json_schema())
      << "schemas/rig.schema.json is out of date";
  EXPECT_EQ(read_text(fs::path(RIGEL_SOURCE_DIR) / "schemas" / "rig.xsd"), definition_xsd()) << "schemas/rig.xsd is out of date";
}

TEST(DefinitionIo, schemas_describe_every_component_type) {
  const nlohmann::json schema = nlohmann::json::parse(definition_json_schema());
  EXPECT_EQ(schema["$schema"], "https://json-schema.org/draft/2020-12/schema");
  const auto& defs = schema["$defs"];
  for (const std::string& type : builtin_schemas().types()) EXPECT_TRUE(defs.contains("component." + type)) << type;
  const auto& limb = defs["component.limb"]["properties"];
  EXPECT_EQ(limb["params"]["properties"]["maxStretch"]["minimum"], 1.0);
  EXPECT_EQ(limb["params"]["properties"]["kind"]["enum"], (nlohmann::json{"arm", "leg"}));
  EXPECT_EQ(limb["params"]["additionalProperties"], false);
  EXPECT_EQ(limb["guides"]["minItems"], 3);
  EXPECT_EQ(limb["guides"]["maxItems"], 3);
  pugi::xml_document xsd;
  const std::string text = definition_xsd();
  ASSERT_TRUE(xsd.load_buffer(text.data(), text.size())) << "the XSD is well-formed XML";
  const pugi::xml_node types = xsd.child("xs:schema").find_child_by_attribute("xs:simpleType", "name", "ComponentType");
  ASSERT_TRUE(types);
  std::vector<std::string> listed;
  for (pugi::xml_node e : types.child("xs:restriction").children("xs:enumeration")) listed.push_back(e.attribute("value").value());
  EXPECT_EQ(listed, builtin_schemas().types());
}

}  // namespace
}  // namespace rigel::rig
