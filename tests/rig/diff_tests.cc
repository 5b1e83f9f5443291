// diff() (rig/diff.h): semantic differences matched by rigId, across syntaxes.

#include <gtest/gtest.h>

#include <filesystem>

#include "rigel/rig/definition_io.h"
#include "rigel/rig/diff.h"

namespace rigel::rig {
namespace {

namespace fs = std::filesystem;

Definition fixture(const std::string& name) {
  const ParseResult r = load_definition(fs::path(RIGEL_SOURCE_DIR) / "tests" / "data" / "rig" / name);
  EXPECT_TRUE(r.ok());
  return r.definition;
}

std::vector<std::string> lines(const std::vector<Difference>& differences) {
  std::vector<std::string> out;
  for (const Difference& d : differences) out.push_back(d.str());
  return out;
}

Component* by_name(Definition& d, const std::string& name) {
  return const_cast<Component*>(d.find_by_name(name));
}

TEST(Diff, the_same_rig_in_two_syntaxes_has_no_differences) {
  const Definition xml = fixture("all_types.rig.xml"), json = fixture("all_types.rig.json");
  EXPECT_TRUE(diff(xml, json).empty()) << lines(diff(xml, json))[0];
  EXPECT_TRUE(diff(xml, xml).empty());
}

TEST(Diff, every_kind_of_change_is_reported_with_old_and_new_values) {
  const Definition a = fixture("all_types.rig.xml");
  Definition b = a;
  b.name = "beast";
  b.version = "2.4";
  b.geometry.pop_back();
  b.features[1].enabled = true;
  Component* arm = by_name(b, "arm");
  arm->name = "wing";                                   // renamed (matched by rigId)
  arm->params[3].value = 1.75;                          // maxStretch changed
  arm->params.erase(arm->params.begin() + 4);           // poleDistance removed
  arm->guides[0].translate = math::Vec3(0, 1, 0);       // guide changed
  arm->controls[0].color = "blue";                      // control changed
  Component* leg = by_name(b, "leg");
  leg->version = "1.3";
  leg->attach = "0";                                    // moved: other attach
  Component* tail = by_name(b, "tail");
  tail->params.push_back({"custom", std::string("x"), {}});  // added
  Component* ponytail = by_name(b, "ponytail");
  Component moved = *ponytail;
  // Move the ponytail from the spine to the global component.
  Component* spine = by_name(b, "spine");
  spine->children.erase(spine->children.begin() + 2);
  b.components[0].children.push_back(moved);
  Component fresh;
  fresh.type = "fkChain";
  fresh.name = "extra";
  fresh.rig_id = "7555bffe-fa4f-4203-b3b0-cf6ae3662809";
  fresh.guides.resize(1);
  b.components[0].children.push_back(fresh);
  by_name(b, "eyes")->type = "fkChain";
  // Removing the face (ephemeral) component.
  auto& roots = b.components[0].children;
  roots.erase(std::find_if(roots.begin(), roots.end(), [](const Component& c) { return c.name == "face"; }));

  const std::vector<std::string> expected = {
      "rig: name 'creature' -> 'beast'",
      "rig: version 2.3 -> 2.4",
      "rig: geometry removed: ../characters/creature_props.glb",
      "rig: feature 'ik': enabled=false -> enabled=true",
      "component 'face' [519d34d4]: removed (was ephemeral under 'global')",
      "component 'eyes' [85dbd9cf]: type eye -> fkChain",
      "component 'wing' [056085bd]: renamed: arm (L) -> wing (L)",
      "component 'wing' [056085bd]: parameter 'poleDistance' removed (was 0.4)",
      "component 'wing' [056085bd]: parameter 'maxStretch': 1.25 -> 1.75",
      "component 'wing' [056085bd]: guide 0 (upper): name=upper joint=upper_arm.L -> name=upper joint=upper_arm.L "
      "translate=0 1 0",
      "component 'wing' [056085bd]: control 'ik': shape=cube color=red size=0.15 -> shape=cube color=blue size=0.15",
      "component 'leg' [9b2c3e59]: moved: under 'hip', attach hip -> under 'hip', attach 0",
      "component 'leg' [9b2c3e59]: version 1.2 -> 1.3",
      "component 'tail' [99e61a79]: parameter 'custom' added: x",
      "component 'ponytail' [214fd738]: moved: under 'spine', attach MIDDLE -> under 'global', attach MIDDLE",
      "component 'extra' [7555bffe]: added: fkChain under 'global'",
  };
  const std::vector<Difference> differences = diff(a, b);
  EXPECT_EQ(lines(differences), expected);
  ASSERT_EQ(differences.size(), expected.size());
  EXPECT_EQ(differences[8].kind, DifferenceKind::kParamChanged);
  EXPECT_EQ(differences[8].item, "maxStretch");
  EXPECT_EQ(differences[8].old_value, "1.25");
  EXPECT_EQ(differences[8].new_value, "1.75");
  EXPECT_EQ(differences[8].rig_id, "056085bd-f7e6-45bb-8505-54f724ac83a7");
  EXPECT_STREQ(difference_kind_name(differences[15].kind), "componentAdded");
}

TEST(Diff, components_match_by_rig_id_not_by_name) {
  Definition a = fixture("all_types.rig.xml");
  Definition b = a;
  // Same name, new identity: one removed and one added, not a change.
  by_name(b, "tail")->rig_id = "7555bffe-fa4f-4203-b3b0-cf6ae3662809";
  const std::vector<Difference> d = diff(a, b);
  ASSERT_EQ(d.size(), 2u) << lines(d)[0];
  EXPECT_EQ(d[0].kind, DifferenceKind::kComponentRemoved);
  EXPECT_EQ(d[1].kind, DifferenceKind::kComponentAdded);
  // rigIds compare as UUIDs: case and dashes do not matter.
  Definition c = a;
  by_name(c, "tail")->rig_id = "99E61A794FE6482FBF2ADF830151597A";
  EXPECT_TRUE(diff(a, c).empty()) << lines(diff(a, c))[0];
}

}  // namespace
}  // namespace rigel::rig
