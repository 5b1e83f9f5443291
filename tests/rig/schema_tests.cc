#include <gtest/gtest.h>

#include "rigel/rig/definition.h"
#include "rigel/rig/schema.h"

namespace rigel::rig {
namespace {

TEST(RigSchema, every_shipped_component_type_is_registered) {
  const std::vector<std::string> expected = {
      "blendShapeSliders", "brows", "call",    "control", "corrective", "ephemeral",   "eye",    "eyelid", "fkChain", "foot",
      "global",            "hand",    "hip",     "ikChain",    "limb",        "meta",   "mouth",  "neck",    "piston",
      "quadLeg",           "simple",  "spine",   "springChain", "squash",     "tail",   "twist",  "wheel"};
  EXPECT_EQ(builtin_schemas().types(), expected);
}

TEST(RigSchema, registry_refuses_duplicates_and_defaults_outside_their_spec) {
  SchemaRegistry r;
  ComponentSchema a;
  a.type = "a";
  ASSERT_TRUE(r.add(a).is_ok());
  EXPECT_EQ(r.add(a).code(), ErrorCode::kAlreadyExists);
  ComponentSchema b;
  b.type = "b";
  b.params.push_back(ParamSpec{"n", ParamType::kInt, std::int64_t{5}, 0.0, 3.0, {}, ""});
  EXPECT_EQ(r.add(b).code(), ErrorCode::kInvalidArgument) << "5 is outside 0..3";
  ComponentSchema c;
  c.type = "c";
  c.params.push_back(ParamSpec{"e", ParamType::kEnum, std::string("z"), {}, {}, {"x", "y"}, ""});
  EXPECT_EQ(r.add(c).code(), ErrorCode::kInvalidArgument) << "z is not a choice";
}

TEST(RigSchema, hooks_expand_per_guide_and_resolve_by_index_name_and_keyword) {
  const ComponentSchema* chain = builtin_schemas().find("fkChain");
  ASSERT_NE(chain, nullptr);
  Component c;
  c.type = "fkChain";
  c.guides.resize(4);
  c.guides[1].name = "elbow";
  c.guides[2].joint = "hand.L";
  const std::vector<std::string> hooks = chain->hook_names(c);
  EXPECT_EQ(hooks, (std::vector<std::string>{"0", "elbow", "hand.L", "3"}));
  EXPECT_EQ(resolve_hook(hooks, ""), 0);
  EXPECT_EQ(resolve_hook(hooks, "START"), 0);
  EXPECT_EQ(resolve_hook(hooks, "MIDDLE"), 1);
  EXPECT_EQ(resolve_hook(hooks, "END"), 3);
  EXPECT_EQ(resolve_hook(hooks, "2"), 2);
  EXPECT_EQ(resolve_hook(hooks, "elbow"), 1);
  EXPECT_EQ(resolve_hook(hooks, "4"), std::nullopt);
  EXPECT_EQ(resolve_hook(hooks, "knee"), std::nullopt);
}

TEST(RigDefinition, rig_ids_are_uuid_v4_with_or_without_dashes) {
  EXPECT_TRUE(is_rig_id("08495011515e4c1d926513662cc869dd"));  // seed 002's example
  EXPECT_TRUE(is_rig_id(new_rig_id()));
  EXPECT_FALSE(is_rig_id("08495011515e3c1d926513662cc869dd")) << "version nibble 3";
  EXPECT_FALSE(is_rig_id("08495011515e4c1dc26513662cc869dd")) << "variant c";
  EXPECT_FALSE(is_rig_id("hello"));
  EXPECT_NE(new_rig_id(), new_rig_id());
}

}  // namespace
}  // namespace rigel::rig
