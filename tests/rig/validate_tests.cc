// validate() and check_definition() (rig/definition_io.h): every semantic
// problem of a definition, all at once, each at its element.

#include <gtest/gtest.h>

#include <filesystem>

#include "rigel/rig/definition_io.h"

namespace rigel::rig {
namespace {

namespace fs = std::filesystem;

fs::path data(const std::string& name) { return fs::path(RIGEL_SOURCE_DIR) / "tests" / "data" / "rig" / name; }

std::vector<std::string> places(const std::vector<Diagnostic>& errors) {
  std::vector<std::string> out;
  for (const Diagnostic& d : errors)
    out.push_back(std::to_string(d.where.line) + ":" + std::to_string(d.where.column) + ": " + d.message);
  return out;
}

// A rig of a global component and `children` under it, valid apart from
// what each test changes.
Component make(const std::string& type, const std::string& name, int guides) {
  Component c;
  c.type = type;
  c.name = name;
  c.rig_id = new_rig_id();
  c.guides.resize(static_cast<std::size_t>(guides));
  return c;
}
Definition rig_with(std::vector<Component> children) {
  Definition d;
  d.name = "r";
  Component global = make("global", "global", 1);
  global.children = std::move(children);
  d.components.push_back(std::move(global));
  return d;
}
std::vector<std::string> messages(const Definition& d, const SchemaRegistry& s = builtin_schemas()) {
  std::vector<std::string> out;
  for (const Diagnostic& e : validate(d, s)) out.push_back(e.message);
  return out;
}

TEST(Validate, an_invalid_file_lists_every_problem_at_its_element) {
  const std::vector<Diagnostic> errors = check_definition(data("invalid_semantic.rig.xml"));
  const std::vector<std::string> expected = {
      "5:5: component 'wing' (wing, L): unknown component type 'wing' (types: blendShapeSliders, brows, call, control, corrective, ephemeral, eye, eyelid, fkChain, "
      "foot, global, hand, hip, ikChain, limb, meta, mouth, neck, piston, quadLeg, simple, spine, springChain, squash, tail, twist, wheel)",
      "6:5: component 'hip' (hip): no rigId (every component needs its own UUID v4)",
      "8:7: component 'arm' (limb, L): rigId 'not-a-uuid' is not a UUID v4 (32 hex digits, dashes optional, version 4)",
      "8:7: component 'arm' (limb, L): has 2 guides; limb takes exactly 3 (upper, lower, end)",
      "8:7: component 'arm' (limb, L): attach 'knee': its parent component 'hip' (hip) has no hook 'knee' (its hooks: "
      "hip; or 0, START, MIDDLE, END)",
      "11:9: component 'arm' (limb, L): parameter 'kind' = 'tentacle' is not one of arm, leg",
      "12:9: component 'arm' (limb, L): parameter 'stretch' must be a bool (true or false), not string 'maybe'",
      "13:9: component 'arm' (limb, L): parameter 'maxStretch' = 0.5 is out of range (at least 1)",
      "14:9: component 'arm' (limb, L): unknown parameter 'wingspan' (limb takes kind, defaultMode, stretch, maxStretch, "
      "poleDistance, ikSpaces)",
      "15:9: component 'arm' (limb, L): unknown control role 'tail' (limb has fk, ik, pole, switch)",
      "15:9: component 'arm' (limb, L): unknown control shape 'blob' (shapes: circle, square, cube, sphere, diamond, "
      "cross, arrow, doubleArrow, fourArrow, fourArrowCircle, locator, pin, triangle)",
      "15:9: component 'arm' (limb, L): unknown colour 'chartreuse' (a palette name such as yellow, red, blue, green, "
      "cyan, magenta, orange, purple, pink, white, black, grey, lightBlue, darkBlue, lightGreen, darkGreen, darkRed, "
      "brown, or #rrggbb)",
      "17:7: component 'arm' (limb, L): duplicate component name 'arm' on side L: names prefix node names; the other is "
      "component 'arm' (limb, L) (line 8)",
      "17:7: component 'arm' (limb, L): duplicate rigId 7B02A8E0B4CA4F42B954E77B73DF9F1C: component 'wing' (wing, L) "
      "(line 5) has it too; every component needs its own",
      "22:7: component 'inner' (global): a global component must be a root, but it is nested in component 'hip' (hip)",
  };
  EXPECT_EQ(places(errors), expected);
  for (const Diagnostic& d : errors) EXPECT_EQ(d.file, data("invalid_semantic.rig.xml").string());
}

TEST(Validate, a_cycle_through_hooks_names_its_components) {
  const std::vector<std::string> expected = {
      "11:11: component 'a' (fkChain): cycle through hooks: 'a' -> 'c' -> 'b' -> 'a' (each depends on the next through "
      "nesting, attach or after, so none can be built first)",
      "30:11: component 'd' (fkChain): attach 'd.0': a component cannot attach to itself",
  };
  EXPECT_EQ(places(check_definition(data("cycle.rig.json"))), expected);
}

TEST(Validate, check_definition_merges_parse_and_semantic_errors_in_file_order) {
  const std::vector<std::string> got = places(check_definition(data("invalid_structure.rig.xml")));
  ASSERT_EQ(got.size(), 10u);
  EXPECT_EQ(got[1], "3:48: <component> side: unknown side 'X' (expected C, L or R)");
  EXPECT_EQ(got[2], "3:110: duplicate attribute 'name' on <component>");
  EXPECT_EQ(got[6], "7:5: component 'global' (global): unknown feature 'stretch' (features of global: none)");
  EXPECT_EQ(places(check_definition(data("syntax_error.rig.json"))).size(), 1u)
      << "after a syntax error there is no model to check";
  EXPECT_TRUE(check_definition(data("all_types.rig.json")).empty());
}

TEST(Validate, attach_resolves_parent_hooks_first_then_other_components) {
  Component spine = make("spine", "spine", 3);
  spine.guides[2].joint = "chest.001";
  Component arm = make("limb", "arm", 3);
  arm.side = Side::kLeft;
  arm.attach = "chest.001";  // a hook of the parent, though it has a dot
  Component arm_r = make("limb", "arm", 3);
  arm_r.side = Side::kRight;
  arm_r.attach = "END";
  Component hand = make("hand", "hand", 1);
  hand.attach = "arm_L.end";  // NAME_SIDE of another component
  spine.children = {arm, arm_r};
  Component prop = make("simple", "prop", 1);
  prop.attach = arm.rig_id + ".lower";  // by rigId
  Definition d = rig_with({spine, hand, prop});
  EXPECT_TRUE(validate(d).empty()) << places(validate(d))[0];

  d.components[0].children[1].attach = "arm.end";
  EXPECT_EQ(messages(d), (std::vector<std::string>{
                             "component 'hand' (hand): attach 'arm.end': 'arm' names several components (arm_L, arm_R): "
                             "write NAME_SIDE or the rigId"}));
  d.components[0].children[1].attach = "arm_L.wrist";
  EXPECT_EQ(messages(d), (std::vector<std::string>{
                             "component 'hand' (hand): attach 'arm_L.wrist': component 'arm' (limb, L) has no hook 'wrist' "
                             "(its hooks: upper, lower, end; or 0..2, START, MIDDLE, END)"}));
  d.components[0].children[1].attach = "3";
  EXPECT_EQ(messages(d), (std::vector<std::string>{
                             "component 'hand' (hand): attach '3': its parent component 'global' (global) has no hook '3' "
                             "(its hooks: main; or 0, START, MIDDLE, END)"}));
  d.components[0].attach = "hips";
  d.components[0].children[1].attach = "";
  EXPECT_EQ(messages(d), (std::vector<std::string>{
                             "component 'global' (global): attach 'hips': a root component has no parent hook to attach to; "
                             "write OTHER.HOOK to attach it to another component"}));
}

TEST(Validate, guides_controls_features_and_parameters_follow_the_schema) {
  Component limb = make("limb", "leg", 3);
  limb.guides[0].name = "upper";
  limb.guides[1].name = "knee";
  limb.guides[2].name = "upper";
  limb.controls = {{"fk", "", "", 0.0, {}}, {"fk", "circle", "#12345g", 1.0, {}}};
  limb.features = {{"ik", true, {{"a", true, {}}, {"a", false, {}}}, {}}, {"fly", true, {}, {}}};
  limb.params = {{"stretch", true, {}}, {"stretch", false, {}}, {"maxStretch", std::int64_t{2}, {}},
                 {"poleDistance", std::string("far"), {}}};
  Component twist = make("twist", "twist", 2);
  twist.params = {{"count", 2.0, {}}, {"axis", std::int64_t{1}, {}}};
  Definition d = rig_with({limb, twist});
  d.features = {{"glow", true, {}, {}}};
  const std::vector<std::string> expected = {
      "the rig: unknown feature 'glow' (features of the component types: ik, stretch)",
      "component 'leg' (limb): duplicate parameter 'stretch'",
      "component 'leg' (limb): parameter 'poleDistance' must be a number, not string 'far'",
      "component 'leg' (limb): guide 1 is named 'knee', but limb's guides are upper, lower, end, in that order",
      "component 'leg' (limb): guide 2 is named 'upper', but limb's guides are upper, lower, end, in that order",
      "component 'leg' (limb): duplicate guide name 'upper'",
      "component 'leg' (limb): control size 0 must be a positive number",
      "component 'leg' (limb): duplicate control role 'fk'",
      "component 'leg' (limb): unknown colour '#12345g' (a palette name such as yellow, red, blue, green, cyan, magenta, "
      "orange, purple, pink, white, black, grey, lightBlue, darkBlue, lightGreen, darkGreen, darkRed, brown, or #rrggbb)",
      "component 'leg' (limb): feature 'ik': duplicate switch 'a'",
      "component 'leg' (limb): unknown feature 'fly' (features of limb: ik, stretch)",
      "component 'twist' (twist): parameter 'count' must be an int, not double '2'",
      "component 'twist' (twist): parameter 'axis' = '1' is not one of x, y, z",
  };
  EXPECT_EQ(messages(d), expected) << "an int is accepted for a double parameter (maxStretch 2), not the reverse";
}

TEST(Validate, names_versions_and_parent_rules) {
  Definition d = rig_with({make("hip", "a b", 1), make("hip", "", 1)});
  d.name = "";
  d.components[0].version = "";
  d.components[0].children[0].rig_id = d.components[0].rig_id;
  EXPECT_EQ(messages(d), (std::vector<std::string>{
                             "the rig has no name",
                             "component 'global' (global): no version",
                             "component 'a b' (hip): name 'a b': use letters, digits, '_' and '-' (it prefixes node names)",
                             "component 'a b' (hip): duplicate rigId " + d.components[0].rig_id +
                                 ": component 'global' (global) has it too; every component needs its own",
                             "component '' (hip): no name",
                         }));
  // needs_parent: no shipped type has it, so a registry of its own.
  SchemaRegistry s;
  ComponentSchema leaf;
  leaf.type = "leaf";
  leaf.needs_parent = true;
  leaf.hooks = {"tip"};
  ASSERT_TRUE(s.add(leaf).is_ok());
  Definition lone;
  lone.name = "r";
  lone.components.push_back(make("leaf", "leaf", 0));
  EXPECT_EQ(messages(lone, s), (std::vector<std::string>{
                                   "component 'leaf' (leaf): a leaf component needs a parent: nest it in one, or attach "
                                   "it to OTHER.HOOK"}));
}

}  // namespace
}  // namespace rigel::rig
