// mGear guide templates read as definitions and skeletons
// (tools/mgear_guides.h): mGear's biped template maps every one of its 38
// components, its locators land where the template puts them, the result
// validates and builds keeping the rest pose; unknown types are reported
// with their children kept; malformed templates are refused naming the
// component.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include "rigel/rig/build.h"
#include "rigel/rig/definition_io.h"
#include "rigel/rig/meta.h"
#include "rigel/tools/data_files.h"
#include "rigel/tools/mgear_guides.h"

namespace rigel::tools {
namespace {

using Json = nlohmann::ordered_json;
using math::Vec3;
namespace fs = std::filesystem;

const fs::path kBiped = fs::path(RIGEL_SOURCE_DIR) / "tests/data/mgear/biped.sgt";

Json biped_json() {
  std::ifstream in(kBiped, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return Json::parse(text.str());
}

Vec3 tra_position(const Json& doc, const std::string& component, const std::string& loc) {
  const Json& m = doc["components_dict"][component]["tra"][loc];
  return Vec3(m[3][0].get<double>(), m[3][1].get<double>(), m[3][2].get<double>());
}

const rig::Component* find_full(const rig::Definition& d, const std::string& full) {
  for (const rig::Component* c : d.all_components())
    if (c->full_name() == full) return c;
  return nullptr;
}

TEST(MgearGuides, the_biped_template_maps_every_component_where_the_guides_are) {
  Result<MgearImport> imported = import_mgear_guides_file(kBiped);
  ASSERT_TRUE(imported.is_ok()) << imported.status().message();
  const MgearImport& m = *imported;
  const Json doc = biped_json();
  ASSERT_EQ(m.components.size(), 38u);
  EXPECT_TRUE(m.unmapped_components().empty());
  EXPECT_EQ(m.definition.all_components().size(), 38u);
  EXPECT_EQ(m.definition.name, "rig");

  std::map<std::string, Vec3> joints;
  for (const GuideJoint& j : m.joints) {
    EXPECT_TRUE(j.parent.empty() || joints.count(j.parent)) << j.name << ": parents come first";
    joints[j.name] = j.position;
  }
  const std::map<std::string, std::string> types = {
      {"control_01", "control"}, {"chain_01", "fkChain"}, {"arm_2jnt_01", "limb"}, {"leg_2jnt_01", "limb"},
      {"spine_ik_01", "spine"},  {"neck_ik_01", "neck"},  {"foot_bk_01", "foot"},   {"shoulder_01", "fkChain"},
      {"eye_01", "eye"},         {"mouth_01", "mouth"},   {"meta_01", "meta"}};
  int checked = 0;
  for (const MgearComponentReport& c : m.components) {
    ASSERT_TRUE(c.mapped()) << c.mgear << ": " << c.problem;
    EXPECT_EQ(c.rigel_type, types.at(c.mgear_type)) << c.mgear;
    const rig::Component* rc = find_full(m.definition, c.rigel_name);
    ASSERT_TRUE(rc) << c.rigel_name;
    const Json& params = doc["components_dict"][c.mgear]["param_values"];
    EXPECT_EQ(rig::side_name(rc->side), params["comp_side"].get<std::string>()) << c.mgear;
    // Each locator with a counterpart: a joint at its translation, or a guide holding it.
    for (const auto& [loc, where] : c.guides) {
      const Vec3 expected = tra_position(doc, c.mgear, loc);
      if (where.starts_with("joint ")) {
        const std::string joint = where.substr(6);
        ASSERT_TRUE(joints.count(joint)) << c.mgear << "." << loc;
        EXPECT_LT((joints[joint] - expected).norm(), 1e-6) << c.mgear << "." << loc;
        ++checked;
      } else if (where.starts_with("guide ")) {
        const std::string name = where.substr(6);
        const auto g = std::find_if(rc->guides.begin(), rc->guides.end(), [&](const rig::Guide& x) { return x.name == name; });
        ASSERT_NE(g, rc->guides.end()) << c.mgear << "." << loc;
        EXPECT_LT((g->translate - expected).norm(), 1e-6) << c.mgear << "." << loc;
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 100);
  // Names carry sides and, where a name repeats on a side, the index.
  EXPECT_TRUE(find_full(m.definition, "arm_L"));
  EXPECT_TRUE(find_full(m.definition, "finger3_R"));
  EXPECT_TRUE(find_full(m.definition, "eye_L"));
  // Parents: the arm hangs from the shoulder, the fingers from the meta's locators.
  const rig::Component* shoulder = find_full(m.definition, "shoulder_L");
  ASSERT_TRUE(shoulder && shoulder->children.size() == 1);
  EXPECT_EQ(shoulder->children[0].full_name(), "arm_L");
  const rig::Component* finger = find_full(m.definition, "finger3_L");
  ASSERT_TRUE(finger);
  EXPECT_EQ(finger->attach, "2_loc");
  // The neck's spline tangents have no counterpart and say so.
  const auto neck = std::find_if(m.components.begin(), m.components.end(), [](const auto& c) { return c.mgear == "neck_C0"; });
  ASSERT_NE(neck, m.components.end());
  EXPECT_NE(std::find(neck->unmapped_guides.begin(), neck->unmapped_guides.end(), "tan0"), neck->unmapped_guides.end());
  // The JSON report lists none unmapped.
  const Json report = mgear_report_json(m);
  EXPECT_TRUE(report["unmapped"].empty());
  EXPECT_EQ(report["components"].size(), 38u);
}

TEST(MgearGuides, the_biped_validates_and_builds_on_its_skeleton_keeping_the_rest_pose) {
  Result<MgearImport> imported = import_mgear_guides_file(kBiped);
  ASSERT_TRUE(imported.is_ok()) << imported.status().message();
  for (const rig::Diagnostic& d : rig::validate(imported->definition)) ADD_FAILURE() << d.str();
  // Written and read back, the definition is the same.
  const std::string text = rig::write_definition(imported->definition, rig::Syntax::kXml);
  const rig::ParseResult back = rig::parse_definition(text, rig::Syntax::kXml, "biped.rig.xml");
  ASSERT_TRUE(back.ok());
  EXPECT_EQ(rig::write_definition(back.definition, rig::Syntax::kXml), text);

  auto scene = guide_skeleton_scene(*imported, rig::default_registry());
  ASSERT_TRUE(scene.is_ok()) << scene.status().message();
  scene::Scene& s = **scene;
  std::map<std::string, math::Mat4> rest;
  for (const GuideJoint& j : imported->joints) {
    const graph::NodeId id = s.graph().find(j.name);
    ASSERT_TRUE(id.is_valid()) << j.name;
    EXPECT_LT((s.world_matrix(id).topRightCorner<3, 1>() - j.position).norm(), 1e-9) << j.name;
    rest[j.name] = s.world_matrix(id);
  }
  auto opened = rig::Build::open(s, imported->definition, components());
  ASSERT_TRUE(opened.is_ok()) << opened.status().message();
  const Status built = (*opened)->build_all();
  ASSERT_TRUE(built.is_ok()) << built.message();
  double worst = 0;
  std::string which;
  for (const auto& [name, m] : rest) {
    const double e = (s.world_matrix(s.graph().find(name)) - m).cwiseAbs().maxCoeff();
    if (e > worst) worst = e, which = name;
  }
  EXPECT_LT(worst, 1e-9) << "at rest nothing moves (worst: " << which << ")";
}

// A small template: a control with a chain under it, as mGear writes them.
Json small_template() {
  auto matrix = [](double x, double y, double z) {
    return Json::array({Json::array({1.0, 0.0, 0.0, 0.0}), Json::array({0.0, 1.0, 0.0, 0.0}),
                        Json::array({0.0, 0.0, 1.0, 0.0}), Json::array({x, y, z, 1.0})});
  };
  Json doc;
  doc["guide_root"] = {{"param_values", {{"rig_name", "small"}}}};
  doc["components_list"] = {"base_C0", "odd_C0", "tail_C0"};
  doc["components_dict"]["base_C0"] = {
      {"param_values", {{"comp_type", "control_01"}, {"comp_name", "base"}, {"comp_side", "C"}, {"comp_index", 0}}},
      {"tra", {{"root", matrix(0, 0, 0)}, {"sizeRef", matrix(0, 0, 1)}}},
      {"parent_fullName", nullptr}};
  doc["components_dict"]["odd_C0"] = {
      {"param_values", {{"comp_type", "gizmo_99"}, {"comp_name", "odd"}, {"comp_side", "C"}, {"comp_index", 0}}},
      {"tra", {{"root", matrix(0, 1, 0)}}},
      {"parent_fullName", "base_C0"},
      {"parent_localName", "root"}};
  doc["components_dict"]["tail_C0"] = {
      {"param_values", {{"comp_type", "chain_01"}, {"comp_name", "tail"}, {"comp_side", "C"}, {"comp_index", 0}, {"mode", 0}}},
      {"tra", {{"root", matrix(0, 1, 0)}, {"0_loc", matrix(0, 1, -1)}, {"1_loc", matrix(0, 1, -2)}}},
      {"parent_fullName", "odd_C0"},
      {"parent_localName", "root"}};
  return doc;
}

TEST(MgearGuides, an_unknown_type_is_reported_and_its_children_hang_from_its_parent) {
  Result<MgearImport> m = import_mgear_guides(small_template().dump(), "small.sgt");
  ASSERT_TRUE(m.is_ok()) << m.status().message();
  EXPECT_EQ(m->unmapped_components(), std::vector<std::string>{"odd_C0"});
  EXPECT_NE(m->components[1].problem.find("gizmo_99"), std::string::npos) << m->components[1].problem;
  ASSERT_EQ(m->definition.components.size(), 1u);
  const rig::Component& base = m->definition.components[0];
  ASSERT_EQ(base.children.size(), 1u);
  EXPECT_EQ(base.children[0].type, "fkChain");
  EXPECT_EQ(base.children[0].guides.size(), 2u) << "a joint per locator, controls on all but the tip";
  EXPECT_EQ(m->joints.size(), 3u);
  EXPECT_EQ(m->definition.name, "small");
  EXPECT_TRUE(rig::validate(m->definition).empty());
  const Json report = mgear_report_json(*m);
  EXPECT_EQ(report["unmapped"], Json::array({"odd_C0"}));
}

// mGear's leg_3jnt_01 (root, knee, ankle, foot, eff) is a quadLeg: its ankle
// the hock, its foot the fetlock; chain_spring_01 a springChain with every
// joint guided; both build on their skeleton keeping the rest.
TEST(MgearGuides, a_three_joint_leg_is_a_quad_leg_that_builds_on_its_skeleton) {
  auto matrix = [](double x, double y, double z) {
    return Json::array({Json::array({1.0, 0.0, 0.0, 0.0}), Json::array({0.0, 1.0, 0.0, 0.0}),
                        Json::array({0.0, 0.0, 1.0, 0.0}), Json::array({x, y, z, 1.0})});
  };
  Json doc = small_template();
  doc["components_list"] = {"base_C0", "leg_L0", "hair_C0"};
  doc["components_dict"]["hair_C0"] = {
      {"param_values", {{"comp_type", "chain_spring_01"}, {"comp_name", "hair"}, {"comp_side", "C"}, {"comp_index", 0}}},
      {"tra", {{"root", matrix(0, 1.5, 0)}, {"0_loc", matrix(0, 1.5, -0.2)}, {"1_loc", matrix(0, 1.4, -0.4)}}},
      {"parent_fullName", "base_C0"},
      {"parent_localName", "root"}};
  doc["components_dict"].erase("odd_C0");
  doc["components_dict"].erase("tail_C0");
  doc["components_dict"]["leg_L0"] = {
      {"param_values", {{"comp_type", "leg_3jnt_01"}, {"comp_name", "leg"}, {"comp_side", "L"}, {"comp_index", 0},
                        {"blend", 1}, {"maxstretch", 1.3}}},
      {"tra", {{"root", matrix(0.2, 1.2, -0.6)}, {"knee", matrix(0.2, 0.8, -0.4)}, {"ankle", matrix(0.2, 0.5, -0.75)},
               {"foot", matrix(0.2, 0.1, -0.7)}, {"eff", matrix(0.2, 0.0, -0.6)}}},
      {"parent_fullName", "base_C0"},
      {"parent_localName", "root"}};
  Result<MgearImport> m = import_mgear_guides(doc.dump(), "quad.sgt");
  ASSERT_TRUE(m.is_ok()) << m.status().message();
  EXPECT_TRUE(m->unmapped_components().empty());
  const rig::Component* leg = find_full(m->definition, "leg_L");
  ASSERT_NE(leg, nullptr);
  EXPECT_EQ(leg->type, "quadLeg");
  ASSERT_EQ(leg->guides.size(), 4u);
  const char* names[] = {"upper", "lower", "hock", "foot"};
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(leg->guides[i].name, names[i]);
  ASSERT_NE(leg->param("defaultMode"), nullptr);
  EXPECT_EQ(std::get<std::string>(leg->param("defaultMode")->value), "ik");
  const rig::Component* hair = find_full(m->definition, "hair");
  ASSERT_NE(hair, nullptr);
  EXPECT_EQ(hair->type, "springChain");
  EXPECT_EQ(hair->guides.size(), 3u) << "every joint, the tip's too";
  for (const rig::Diagnostic& d : rig::validate(m->definition)) ADD_FAILURE() << d.str();
  auto scene = guide_skeleton_scene(*m, rig::default_registry());
  ASSERT_TRUE(scene.is_ok()) << scene.status().message();
  scene::Scene& s = **scene;
  const graph::NodeId hock = s.graph().find(leg->guides[2].joint);
  ASSERT_TRUE(hock.is_valid());
  const math::Mat4 rest = s.world_matrix(hock);
  EXPECT_LT((rest.topRightCorner<3, 1>() - Vec3(0.2, 0.5, -0.75)).norm(), 1e-9);
  auto opened = rig::Build::open(s, m->definition, components());
  ASSERT_TRUE(opened.is_ok()) << opened.status().message();
  const Status built = (*opened)->build_all();
  ASSERT_TRUE(built.is_ok()) << built.message();
  EXPECT_LT((s.world_matrix(hock) - rest).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(MgearGuides, malformed_templates_are_refused_naming_the_component) {
  auto refused = [](const std::string& text, const std::string& expected) {
    Result<MgearImport> m = import_mgear_guides(text, "bad.sgt");
    EXPECT_FALSE(m.is_ok()) << expected;
    if (!m) {
      EXPECT_NE(m.status().message().find(expected), std::string::npos) << m.status().message();
    }
  };
  refused("{ not json", "bad.sgt");
  refused("[]", "components_dict");
  Json doc = small_template();
  doc["components_list"].push_back("ghost_C0");
  refused(doc.dump(), "'ghost_C0'");
  doc = small_template();
  doc["components_dict"]["tail_C0"]["tra"]["0_loc"] = "here";
  refused(doc.dump(), "component 'tail_C0': tra '0_loc'");
  doc = small_template();
  doc["components_dict"]["tail_C0"]["parent_fullName"] = "nobody_C0";
  refused(doc.dump(), "component 'tail_C0': parent 'nobody_C0'");
  doc = small_template();
  doc["components_dict"]["base_C0"]["parent_fullName"] = "tail_C0";
  refused(doc.dump(), "cycle");
  doc = small_template();
  doc["components_dict"]["base_C0"]["param_values"].erase("comp_type");
  refused(doc.dump(), "component 'base_C0': no comp_type");
  doc = small_template();
  doc["components_dict"]["odd_C0"]["param_values"]["comp_type"] = "arm_2jnt_01";
  refused(doc.dump(), "component 'odd_C0' (arm_2jnt_01): guide locator 'elbow'");
}

}  // namespace
}  // namespace rigel::tools
