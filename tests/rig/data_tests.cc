// A definition's data entries (Definition::data, <data kind file/>): read
// and written in both syntaxes with byte-identical round trips, in the
// schema files, compared by diff, validated (unknown kinds and missing
// files at their line), and built as the plan's last step through the
// factory's data importer: recorded like every step, so stepping back,
// remove and an update are exact; a failing import is rolled back.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "../io/io_test_util.h"
#include "rig_test_util.h"
#include "rigel/io/scene_file.h"
#include "rigel/rig/build.h"
#include "rigel/rig/component.h"
#include "rigel/rig/definition_io.h"
#include "rigel/rig/diff.h"
#include "rigel/rig/meta.h"
#include "rigel/scene/transform_types.h"

namespace rigel::rig {
namespace {

namespace fs = std::filesystem;
using io::testing::TempDir;
using io::testing::write_text;

const char* const kXml = R"(<?xml version="1.0" encoding="UTF-8"?>
<rig name="hero" version="1.0">
  <geo file="../skeleton/body.glb"/>
  <feature name="stretch" enabled="true"/>
  <data kind="weights" file="../data/weights/body.weights.json"/>
  <data kind="shapes" file="../data/shapes/hero.shapes.json"/>
  <data kind="weights" file="../data/weights/extra.weights.json"/>
  <component type="global" name="global" side="C" version="1.0" rigId="6513270e-269e-4d37-b2a7-4de452e6b438">
    <guide name="main"/>
  </component>
</rig>
)";

ParseResult parse_ok(const std::string& text, Syntax syntax, const std::string& source = "t") {
  ParseResult r = parse_definition(text, syntax, source);
  EXPECT_TRUE(r.ok()) << (r.errors.empty() ? "" : r.errors[0].str());
  return r;
}

TEST(DefinitionData, data_entries_round_trip_in_file_order_within_and_across_syntaxes) {
  const ParseResult from_xml = parse_ok(kXml, Syntax::kXml);
  const Definition& d = from_xml.definition;
  ASSERT_EQ(d.data.size(), 3u);
  EXPECT_EQ(d.data[0].kind, "weights");
  EXPECT_EQ(d.data[1].kind, "shapes");
  EXPECT_EQ(d.data[1].file, "../data/shapes/hero.shapes.json");
  EXPECT_EQ(d.data[2].file, "../data/weights/extra.weights.json") << "file order kept";
  EXPECT_EQ(d.data[1].where, (SourceLocation{6, 3}));
  EXPECT_EQ(write_definition(d, Syntax::kXml), kXml) << "XML -> model -> XML gives the same text";
  const std::string json = write_definition(d, Syntax::kJson);
  EXPECT_NE(json.find("    \"data\": [\n"
                      "      {\"kind\": \"weights\", \"file\": \"../data/weights/body.weights.json\"},\n"
                      "      {\"kind\": \"shapes\", \"file\": \"../data/shapes/hero.shapes.json\"},\n"),
            std::string::npos)
      << json;
  EXPECT_LT(json.find("\"features\""), json.find("\"data\""));
  EXPECT_LT(json.find("\"data\""), json.find("\"components\""));
  const ParseResult from_json = parse_ok(json, Syntax::kJson);
  ASSERT_EQ(from_json.definition.data.size(), 3u);
  EXPECT_EQ(from_json.definition.data[1].where.line, 13) << "an entry's place is its object";
  EXPECT_EQ(write_definition(from_json.definition, Syntax::kJson), json) << "JSON -> model -> JSON";
  EXPECT_EQ(write_definition(from_json.definition, Syntax::kXml), kXml) << "XML -> JSON -> XML";
  Definition none = d;
  none.data.clear();
  EXPECT_EQ(write_definition(none, Syntax::kJson).find("\"data\""), std::string::npos) << "no data: no key";
}

TEST(DefinitionData, structure_errors_in_data_entries_are_reported_at_their_place) {
  const std::string xml = "<rig name=\"hero\">\n  <data kind=\"weights\" file=\"a.json\" mesh=\"body\"/>\n"
                          "  <data kind=\"weights\" file=\"a.json\"><x/></data>\n</rig>\n";
  const ParseResult x = parse_definition(xml, Syntax::kXml, "hero.rig.xml");
  ASSERT_EQ(x.errors.size(), 2u);
  EXPECT_EQ(x.errors[0].where.line, 2);
  EXPECT_NE(x.errors[0].message.find("mesh"), std::string::npos) << x.errors[0].message;
  EXPECT_EQ(x.errors[1].where.line, 3);
  const std::string json = "{\"rig\": {\"name\": \"hero\",\n \"data\": [\"a.json\",\n {\"kind\": \"weights\", \"file\": 3}]}}";
  const ParseResult j = parse_definition(json, Syntax::kJson, "hero.rig.json");
  ASSERT_EQ(j.errors.size(), 2u);
  EXPECT_EQ(j.errors[0].where.line, 2);
  EXPECT_NE(j.errors[0].message.find("data entry"), std::string::npos) << j.errors[0].message;
  EXPECT_EQ(j.errors[1].where.line, 3);
}

TEST(DefinitionData, validate_names_unknown_kinds_and_missing_files_at_their_line) {
  TempDir dir;
  fs::create_directories(dir.path() / "build");
  fs::create_directories(dir.path() / "data" / "weights");
  write_text(dir.path() / "data" / "weights" / "body.weights.json", "{}");
  const fs::path file = dir.path() / "build" / "hero.rig.xml";
  write_text(file, "<rig name=\"hero\">\n"
                   "  <data kind=\"weights\" file=\"../data/weights/body.weights.json\"/>\n"
                   "  <data kind=\"paint\" file=\"../data/weights/body.weights.json\"/>\n"
                   "  <data kind=\"shapes\" file=\"../data/shapes/hero.shapes.json\"/>\n"
                   "  <data kind=\"shapes\" file=\"\"/>\n"
                   "</rig>\n");
  const std::vector<Diagnostic> problems = check_definition(file);
  ASSERT_EQ(problems.size(), 3u) << problems[0].str();
  EXPECT_EQ(problems[0].str().rfind(file.string() + ":3:3: data: unknown kind 'paint' (kinds: weights, shapes, ", 0), 0u)
      << problems[0].str();
  EXPECT_EQ(problems[1].where.line, 4);
  EXPECT_NE(problems[1].message.find("'../data/shapes/hero.shapes.json' does not exist"), std::string::npos)
      << problems[1].message;
  EXPECT_EQ(problems[2].where.line, 5);
  EXPECT_EQ(problems[2].message, "data without a file");
  // Built in code (no file): relative paths cannot be looked for; kinds still are.
  Definition d = parse_ok(kXml, Syntax::kXml, "").definition;
  EXPECT_TRUE(validate(d).empty()) << validate(d)[0].str();
  d.data[0].kind = "blendshape";
  EXPECT_EQ(validate(d).size(), 1u);
}

TEST(DefinitionData, the_schema_files_and_diff_know_data) {
  const nlohmann::json schema = nlohmann::json::parse(definition_json_schema());
  EXPECT_EQ(schema["$defs"]["rig"]["properties"]["data"]["items"]["$ref"], "#/$defs/data");
  EXPECT_EQ(schema["$defs"]["data"]["properties"]["kind"]["enum"],
            (nlohmann::json{"weights", "shapes", "blendshapes", "driven_poses", "correctives"}));
  const std::string xsd = definition_xsd();
  EXPECT_NE(xsd.find("<xs:element name=\"data\" type=\"Data\"/>"), std::string::npos);
  EXPECT_NE(xsd.find("<xs:simpleType name=\"DataKind\">"), std::string::npos);

  const Definition a = parse_ok(kXml, Syntax::kXml).definition;
  Definition b = a;
  std::swap(b.data[0], b.data[1]);
  const std::vector<Difference> d = diff(a, b);
  ASSERT_EQ(d.size(), 1u);
  EXPECT_EQ(d[0].kind, DifferenceKind::kDataChanged) << "the import order is part of the rig";
  EXPECT_EQ(std::string(difference_kind_name(d[0].kind)), "dataChanged");
  EXPECT_NE(d[0].str().find("rig: data weights ../data/weights/body.weights.json, shapes"), std::string::npos) << d[0].str();
  EXPECT_TRUE(diff(a, parse_ok(write_definition(a, Syntax::kJson), Syntax::kJson).definition).empty());
}

// ---- the data step -----------------------------------------------------------------

// A global control on the metarig, with data entries a test importer reads:
// it sets the translate of the scene's "prop" transform (made before the
// build) to the number in the entry's file name and the colour of the
// rig's global control, and fails for a file named "bad".
struct DataBuild {
  std::unique_ptr<scene::Scene> scene;
  NodeId prop;
  Definition definition;
  ComponentFactory factory = builtin_components();
  std::vector<std::string> calls;  // "kind file" as the importer was given them
};

std::unique_ptr<DataBuild> data_build(std::vector<std::string> files) {
  auto b = std::make_unique<DataBuild>();
  b->scene = testing::metarig();
  auto prop = b->scene->graph().create_node(scene::kTransformType, "prop");
  EXPECT_TRUE(prop.is_ok());
  b->prop = *prop;
  b->scene->graph().clear_history();
  b->definition = parse_ok(kXml, Syntax::kXml, "/assets/hero/build/hero.rig.xml").definition;
  b->definition.data.clear();
  for (const std::string& f : files) b->definition.data.push_back(DataImport{"weights", f, {}});
  DataBuild* self = b.get();
  b->factory.set_data_importer([self](scene::Scene& s, NodeId rig, const DataImport& entry, const fs::path& file) -> Status {
    self->calls.push_back(entry.kind + " " + file.generic_string());
    if (file.stem() == "bad") return Status(ErrorCode::kParseError, file.string() + ": not a weights file");
    graph::Graph& g = s.graph();
    if (!g.node(rig) || g.node(rig)->type().name() != kMetaRootType) return Status(ErrorCode::kInvalidArgument, "not the rig");
    const double x = std::stod(file.stem().string());
    Status st = g.set_value(graph::Plug{self->prop, scene::xform::kTranslate, -1}, graph::Value(math::Vec3(x, 0, 0)));
    const NodeId main = *resolve_address(g, "hero:global/main");
    if (st) st = g.set_value(graph::Plug{main, g.node(main)->type().attr_find("shapeColor"), -1}, graph::Value(math::Vec3(x / 10, 0, 0)));
    return st;
  });
  return b;
}

math::Vec3 prop_at(DataBuild& b) { return std::get<math::Vec3>(b.scene->graph().node(b.prop)->value(scene::xform::kTranslate)); }

TEST(DataStep, the_plan_ends_with_the_data_step_which_imports_in_order_and_steps_back_exactly) {
  auto b = data_build({"../data/1.json", "/elsewhere/2.json"});
  const std::string bare = io::write_scene(*b->scene);
  auto build = Build::open(*b->scene, b->definition, b->factory);
  ASSERT_TRUE(build.is_ok()) << build.status().message();
  const std::vector<PlannedStep>& plan = (*build)->plan();
  ASSERT_EQ(plan.size(), 4u);  // rig, global/meta, global/control, data
  EXPECT_EQ(plan.back().component, -1);
  EXPECT_EQ(plan.back().step, "data");
  ASSERT_TRUE((*build)->go_to(3).is_ok());
  EXPECT_TRUE(b->calls.empty());
  const std::string before = io::write_scene(*b->scene);
  ASSERT_TRUE((*build)->forward().is_ok());
  EXPECT_EQ(b->calls, (std::vector<std::string>{"weights /assets/hero/build/../data/1.json", "weights /elsewhere/2.json"}))
      << "in order, relative files from the definition's folder";
  EXPECT_EQ(prop_at(*b), math::Vec3(2, 0, 0));
  ASSERT_TRUE((*build)->back().is_ok());
  EXPECT_EQ(io::write_scene(*b->scene), before) << "back over the data step: byte for byte";
  ASSERT_TRUE((*build)->build_all().is_ok());
  // In a later process: the record travels on the rig's metaRoot.
  auto reloaded = io::parse_scene(io::write_scene(*b->scene), "built", default_registry());
  ASSERT_TRUE(reloaded.is_ok());
  auto again = Build::reopen(**reloaded, "hero", b->factory);
  ASSERT_TRUE(again.is_ok()) << again.status().message();
  EXPECT_EQ((*again)->position(), 4);
  ASSERT_TRUE((*again)->remove().is_ok());
  EXPECT_EQ(io::write_scene(**reloaded), bare) << "build then remove: byte for byte";
}

TEST(DataStep, a_failing_import_fails_the_step_naming_the_entry_and_rolls_back) {
  auto b = data_build({"1.json", "bad.json"});
  b->definition.data[1].where = SourceLocation{7, 3};
  auto build = Build::open(*b->scene, b->definition, b->factory);
  ASSERT_TRUE(build.is_ok());
  ASSERT_TRUE((*build)->go_to(3).is_ok());
  const std::string before = io::write_scene(*b->scene);
  const Status s = (*build)->forward();
  ASSERT_FALSE(s.is_ok());
  EXPECT_EQ(s.code(), ErrorCode::kParseError);
  EXPECT_NE(s.message().find("/assets/hero/build/hero.rig.xml:7:3: data weights 'bad.json'"), std::string::npos) << s.message();
  EXPECT_NE(s.message().find("bad.json: not a weights file"), std::string::npos) << s.message();
  EXPECT_EQ((*build)->position(), 3);
  EXPECT_EQ(io::write_scene(*b->scene), before) << "the first entry's import rolled back too";
  // A factory without an importer cannot build data.
  auto plain = Build::open(*b->scene, b->definition, builtin_components());
  ASSERT_TRUE(plain.is_ok());
  const Status none = (*plain)->forward();
  EXPECT_EQ(none.code(), ErrorCode::kUnsupported);
  EXPECT_NE(none.message().find("no data importer"), std::string::npos) << none.message();
}

TEST(DataStep, an_update_destructs_the_data_step_first_and_imports_again_last) {
  auto b = data_build({"3.json"});
  auto build = Build::open(*b->scene, b->definition, b->factory);
  ASSERT_TRUE(build.is_ok());
  ASSERT_TRUE((*build)->build_all().is_ok());
  graph::Graph& g = b->scene->graph();
  const NodeId main = *resolve_address(g, "hero:global/main");
  const graph::AttrIndex color = g.node(main)->type().attr_find("shapeColor");
  EXPECT_EQ(std::get<math::Vec3>(g.node(main)->value(color)), math::Vec3(0.3, 0, 0));
  // The global component rebuilt: its control made again, the data imported onto it.
  Definition next = b->definition;
  next.components[0].version = "1.1";
  next.data[0].file = "5.json";
  auto rebuilt = (*build)->rebuild_changed(next);
  ASSERT_TRUE(rebuilt.is_ok()) << rebuilt.status().message();
  EXPECT_EQ(rebuilt->size(), 1u);
  EXPECT_EQ(b->calls.size(), 2u);
  EXPECT_EQ(prop_at(*b), math::Vec3(5, 0, 0));
  const NodeId new_main = *resolve_address(g, "hero:global/main");
  EXPECT_EQ(std::get<math::Vec3>(g.node(new_main)->value(color)), math::Vec3(0.5, 0, 0));
  // Nothing changed but the data: imported again all the same.
  next.data.clear();
  auto dropped = (*build)->rebuild_changed(next);
  ASSERT_TRUE(dropped.is_ok()) << dropped.status().message();
  EXPECT_TRUE(dropped->empty());
  EXPECT_EQ(prop_at(*b), math::Vec3(0, 0, 0)) << "the data step's work undone with it";
  EXPECT_EQ((*build)->plan().back().step, "control");
  // An update that fails at the data step changes nothing.
  next.data = {DataImport{"weights", "bad.json", {}}};
  const std::string before = io::write_scene(*b->scene);
  EXPECT_FALSE((*build)->rebuild_changed(next).is_ok());
  EXPECT_EQ(io::write_scene(*b->scene), before);
}

}  // namespace
}  // namespace rigel::rig
