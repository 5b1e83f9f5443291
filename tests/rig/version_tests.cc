// Versions of definitions and components (version.h): comparing, and the
// version after one.
#include <gtest/gtest.h>

#include "rigel/rig/version.h"

namespace rigel::rig {
namespace {

TEST(RigDefinition, versions_compare_numerically_and_bump_their_last_part) {
  EXPECT_LT(compare_versions("1.9", "1.10"), 0);
  EXPECT_EQ(compare_versions("1.0", "1"), 0);
  EXPECT_GT(compare_versions("2.0.1", "2.0"), 0);
  EXPECT_EQ(bump_version("1.2"), "1.3");
  EXPECT_EQ(bump_version("1.2.9"), "1.2.10");
  EXPECT_EQ(bump_version("7"), "8");
}

TEST(RigEdit, next_version_adds_one_to_the_last_number) {
  EXPECT_EQ(next_version("1.0"), "1.1");
  EXPECT_EQ(next_version("2"), "3");
  EXPECT_EQ(next_version("1.0.9"), "1.0.10");
  EXPECT_EQ(next_version("1.99"), "1.100");
  EXPECT_EQ(next_version("beta"), "beta.1");
  EXPECT_EQ(next_version(""), "1");
}

}  // namespace
}  // namespace rigel::rig
