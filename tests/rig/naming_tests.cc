// The naming template of built nodes (BuildOptions::naming_template, the
// setting naming.template): the default gives the names rigel always gave,
// tokens that come out empty take a '_' with them. (A whole build under a
// template: tests/tools/pipeline_tests.cc.)

#include <gtest/gtest.h>

#include "rigel/rig/build.h"

namespace rigel::rig {
namespace {

TEST(Naming, the_template_s_tokens_and_empty_ones) {
  EXPECT_EQ(built_node_name("", "hero", "arm_L", "arm", "L", "ik", -1), "hero_arm_L_ik");
  EXPECT_EQ(built_node_name("", "hero", "arm_L", "arm", "L", "fk", 2), "hero_arm_L_fk2");
  EXPECT_EQ(built_node_name("", "hero", "", "", "", "controls", -1), "hero_controls") << "the rig's own nodes";
  EXPECT_EQ(built_node_name("{side}_{name}_{role}{index}", "hero", "arm_L", "arm", "L", "ik", -1), "L_arm_ik");
  EXPECT_EQ(built_node_name("{rig}:{component}_{role}_{index}", "hero", "arm_L", "arm", "L", "fk", -1), "hero:arm_L_fk");
  EXPECT_EQ(built_node_name("{rig}_{component}_{role}_{index}", "hero", "", "", "", "main", 3), "hero_main_3");
}

}  // namespace
}  // namespace rigel::rig
