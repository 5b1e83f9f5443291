#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "deform_test_util.h"
#include "rigel/ops/deform/skin.h"

namespace rigel::ops {
namespace {

using testing::Random;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// Builds from flat arrays and expects a failure whose message contains
// every one of `parts`.
void expect_failure(const std::vector<std::int64_t>& offsets, const std::vector<std::int64_t>& joints,
                    const std::vector<double>& weights, std::size_t joint_count, const std::vector<std::string>& parts,
                    const char* why) {
  SkinBuildOptions options;
  options.joint_count = joint_count;
  const Result<Skin> skin = build_skin({offsets, joints, weights}, options);
  ASSERT_FALSE(skin.is_ok()) << why;
  EXPECT_EQ(skin.status().code(), ErrorCode::kInvalidArgument) << why;
  for (const std::string& part : parts) {
    EXPECT_NE(skin.status().message().find(part), std::string::npos)
        << why << ": the message should contain \"" << part << "\", it is: " << skin.status().message();
  }
}

TEST(SkinBuilder, build__accepts_a_well_formed_skin) {
  SkinBuilder builder(3);
  builder.add_vertex({{0, 1.0}}).add_vertex({{1, 0.25}, {2, 0.75}});
  SkinBuildReport report;
  const Result<Skin> skin = builder.build(&report);
  ASSERT_TRUE(skin.is_ok()) << skin.status().message();
  EXPECT_EQ(skin->vertex_count(), 2u);
  EXPECT_EQ(skin->joint_count(), 3u);
  EXPECT_EQ(skin->influence_count(), 3u);
  EXPECT_EQ(skin->max_influences(), 2u);
  EXPECT_EQ(std::vector<std::uint32_t>(skin->offsets().begin(), skin->offsets().end()),
            (std::vector<std::uint32_t>{0, 1, 3}));
  EXPECT_EQ(std::vector<std::uint16_t>(skin->joints().begin(), skin->joints().end()),
            (std::vector<std::uint16_t>{0, 1, 2}));
  EXPECT_EQ(std::vector<float>(skin->weights().begin(), skin->weights().end()),
            (std::vector<float>{1.0f, 0.25f, 0.75f}));
  EXPECT_TRUE(report.renormalized.empty()) << "weights that sum to 1 are not reported";
}

TEST(SkinBuilder, build__accepts_an_empty_skin) {
  const Result<Skin> skin = SkinBuilder(0).build();
  ASSERT_TRUE(skin.is_ok()) << skin.status().message();
  EXPECT_EQ(skin->vertex_count(), 0u);
  EXPECT_TRUE(skin->has_fixed_layout()) << "no vertex has more than 4 influences";
}

TEST(SkinBuilder, build__rejects_a_joint_count_above_the_limit) {
  expect_failure({0}, {}, {}, kMaxSkinJoints + 1, {"joint_count 65537", "65536"},
                 "joint indices are 16 bits: more than 65536 joints cannot be addressed");
}

TEST(SkinBuilder, build__rejects_joints_and_weights_of_different_lengths) {
  expect_failure({0, 2}, {0, 1}, {1.0}, 2, {"joints (2)", "weights (1)"}, "every influence needs a joint and a weight");
}

TEST(SkinBuilder, build__rejects_empty_offsets) {
  expect_failure({}, {}, {}, 1, {"offsets"}, "offsets has vertex_count + 1 entries, so never zero");
}

TEST(SkinBuilder, build__rejects_offsets_that_do_not_start_at_0) {
  expect_failure({1, 2}, {0, 0}, {1.0, 1.0}, 1, {"start at 0"}, "the first vertex's influences start at 0");
}

TEST(SkinBuilder, build__rejects_decreasing_offsets) {
  expect_failure({0, 2, 1, 3}, {0, 0, 0}, {1, 1, 1}, 1, {"decrease at vertex 1"},
                 "a vertex cannot end before it starts");
}

TEST(SkinBuilder, build__rejects_offsets_that_do_not_end_at_the_influence_count) {
  expect_failure({0, 1}, {0, 0}, {1.0, 1.0}, 1, {"end at 1", "(2)"},
                 "influences past the last offset belong to no vertex");
}

TEST(SkinBuilder, build__rejects_a_nan_weight_naming_the_vertex) {
  expect_failure({0, 1, 3}, {0, 0, 1}, {1.0, 0.5, kNaN}, 2, {"vertex 1 influence 1", "NaN", "not finite"},
                 "a NaN weight would make the vertex NaN");
}

TEST(SkinBuilder, build__rejects_an_infinite_weight_naming_the_vertex) {
  expect_failure({0, 1}, {0}, {kInf}, 1, {"vertex 0 influence 0", "inf", "not finite"},
                 "an infinite weight cannot be normalised");
}

TEST(SkinBuilder, build__rejects_a_negative_weight_naming_the_vertex) {
  expect_failure({0, 1, 3}, {0, 0, 1}, {1.0, 1.5, -0.5}, 2, {"vertex 1 influence 1", "-0.5", "negative"},
                 "negative weights push a vertex away from its joint");
}

TEST(SkinBuilder, build__rejects_a_joint_out_of_range_naming_the_vertex) {
  expect_failure({0, 1, 2}, {0, 70}, {1.0, 1.0}, 64, {"vertex 1 influence 0", "joint 70", "64 joints"},
                 "a joint index must address one of the skinning matrices");
}

TEST(SkinBuilder, build__rejects_a_negative_joint_naming_the_vertex) {
  expect_failure({0, 1}, {-1}, {1.0}, 4, {"vertex 0 influence 0", "joint -1"}, "a negative joint index");
}

TEST(SkinBuilder, build__rejects_a_vertex_without_influences) {
  expect_failure({0, 1, 1, 2}, {0, 0}, {1.0, 1.0}, 1, {"vertex 1", "no influence"},
                 "a vertex with no influence has no matrix to follow");
}

TEST(SkinBuilder, build__rejects_a_vertex_whose_weights_are_all_zero) {
  expect_failure({0, 1, 3}, {0, 0, 1}, {1.0, 0.0, 0.0}, 2, {"vertex 1", "no influence with a non-zero weight"},
                 "zero weights are dropped, which leaves nothing");
}

TEST(SkinBuilder, build__rejects_weights_that_sum_to_infinity) {
  const double big = std::numeric_limits<double>::max();
  expect_failure({0, 2}, {0, 1}, {big, big}, 2, {"vertex 0", "sum to infinity"},
                 "finite weights whose sum overflows cannot be normalised");
}

TEST(SkinBuilder, build__rejects_influences_with_a_zero_joint_count) {
  expect_failure({0, 1}, {0}, {1.0}, 0, {"joint 0", "0 joints"}, "no matrix exists for any joint index");
}

TEST(SkinBuilder, build__reports_every_problem_in_one_message) {
  std::vector<std::int64_t> offsets = {0};
  std::vector<std::int64_t> joints;
  std::vector<double> weights;
  for (int v = 0; v < 12; ++v) {
    joints.push_back(v % 2 == 0 ? 99 : 0);  // even vertices: out of range
    weights.push_back(1.0);
    offsets.push_back(static_cast<std::int64_t>(joints.size()));
  }
  expect_failure(offsets, joints, weights, 4, {"6 problems", "vertex 0 ", "vertex 10 "},
                 "one build should list every bad vertex, not only the first");
  std::vector<std::int64_t> many_offsets = {0};
  std::vector<std::int64_t> many_joints;
  std::vector<double> many_weights;
  for (int v = 0; v < 20; ++v) {
    many_joints.push_back(99);
    many_weights.push_back(1.0);
    many_offsets.push_back(v + 1);
  }
  expect_failure(many_offsets, many_joints, many_weights, 4, {"20 problems", "and 12 more"},
                 "past 8 problems the message gives a count instead of each one");
}

TEST(SkinBuilder, build__normalises_weights_and_reports_which_vertices_and_by_how_much) {
  SkinBuilder builder(2);
  builder.add_vertex({{0, 0.3}, {1, 0.3}});         // sums to 0.6
  builder.add_vertex({{0, 0.5}, {1, 0.5}});         // sums to 1
  builder.add_vertex({{0, 1.0}, {1, 1.0 + 1e-7}});  // sums to 2
  builder.add_vertex({{0, 1.0 + 1e-7}});            // within the tolerance: not reported
  SkinBuildReport report;
  const Result<Skin> skin = builder.build(&report);
  ASSERT_TRUE(skin.is_ok()) << skin.status().message();
  EXPECT_EQ(skin->weights()[0], 0.5f) << "0.3 / 0.6";
  EXPECT_EQ(skin->weights()[1], 0.5f) << "0.3 / 0.6";
  ASSERT_EQ(report.renormalized.size(), 2u) << "vertices 0 and 2 do not sum to 1";
  EXPECT_EQ(report.renormalized[0].vertex, 0u);
  EXPECT_NEAR(report.renormalized[0].weight_sum, 0.6, 1e-15) << "the sum before normalisation is reported";
  EXPECT_EQ(report.renormalized[1].vertex, 2u);
  EXPECT_NEAR(report.renormalized[1].weight_sum, 2.0, 1e-6);
  EXPECT_NEAR(report.largest_deviation, 1.0, 1e-6) << "vertex 2 is off by 1";
  EXPECT_EQ(skin->weights()[6], 1.0f) << "a vertex within the tolerance is still normalised";
}

TEST(SkinBuilder, build__without_normalise_keeps_the_weights_and_still_reports) {
  SkinBuilder builder(2);
  builder.options().normalize = false;
  builder.add_vertex({{0, 0.3}, {1, 0.3}});
  SkinBuildReport report;
  const Result<Skin> skin = builder.build(&report);
  ASSERT_TRUE(skin.is_ok()) << skin.status().message();
  EXPECT_EQ(skin->weights()[0], 0.3f) << "normalize off keeps the weight";
  ASSERT_EQ(report.renormalized.size(), 1u) << "and the vertex is still reported";
  EXPECT_NEAR(report.renormalized[0].weight_sum, 0.6, 1e-15);
}

TEST(SkinBuilder, build__drops_zero_weights_and_merges_repeated_joints) {
  SkinBuilder builder(4);
  // glTF pads with weight 0 (often joint 0), and can name a joint twice.
  builder.add_vertex({{2, 0.25}, {0, 0.0}, {2, 0.25}, {3, 0.5}});
  SkinBuildReport report;
  const Result<Skin> skin = builder.build(&report);
  ASSERT_TRUE(skin.is_ok()) << skin.status().message();
  EXPECT_EQ(report.dropped_zero_weights, 1u);
  EXPECT_EQ(report.merged_duplicates, 1u);
  EXPECT_EQ(report.max_influences, 2u);
  ASSERT_EQ(skin->influence_count(), 2u) << "joint 2 once (0.25 + 0.25), joint 3";
  EXPECT_EQ(skin->joints()[0], 2);
  EXPECT_EQ(skin->weights()[0], 0.5f);
  EXPECT_EQ(skin->joints()[1], 3);
  EXPECT_EQ(skin->weights()[1], 0.5f);
}

TEST(SkinBuilder, build__ignores_the_joint_of_a_zero_weight) {
  // A padded slot never reads a matrix, so its joint index is not checked.
  SkinBuilder builder(2);
  builder.add_vertex({{1, 1.0}, {500, 0.0}});
  const Result<Skin> skin = builder.build();
  ASSERT_TRUE(skin.is_ok()) << skin.status().message();
  EXPECT_EQ(skin->influence_count(), 1u);
}

TEST(SkinBuilder, build__makes_the_fixed_layout_padded_with_the_first_joint) {
  SkinBuilder builder(8);
  builder.add_vertex({{5, 0.5}, {6, 0.5}});
  builder.add_vertex({{1, 0.25}, {2, 0.25}, {3, 0.25}, {4, 0.25}});
  const Result<Skin> skin = builder.build();
  ASSERT_TRUE(skin.is_ok()) << skin.status().message();
  ASSERT_TRUE(skin->has_fixed_layout()) << "no vertex has more than 4 influences";
  EXPECT_EQ(std::vector<std::uint16_t>(skin->fixed_joints().begin(), skin->fixed_joints().end()),
            (std::vector<std::uint16_t>{5, 6, 5, 5, 1, 2, 3, 4}))
      << "padding repeats the vertex's first joint (its matrix is already in cache)";
  EXPECT_EQ(std::vector<float>(skin->fixed_weights().begin(), skin->fixed_weights().end()),
            (std::vector<float>{0.5f, 0.5f, 0, 0, 0.25f, 0.25f, 0.25f, 0.25f}))
      << "padding has weight 0";
}

TEST(SkinBuilder, build__has_no_fixed_layout_past_4_influences_or_when_asked) {
  SkinBuilder five(8);
  five.add_vertex({{0, 1}, {1, 1}, {2, 1}, {3, 1}, {4, 1}});
  const Result<Skin> skin = five.build();
  ASSERT_TRUE(skin.is_ok()) << skin.status().message();
  EXPECT_FALSE(skin->has_fixed_layout()) << "5 influences do not fit the 4-wide layout";
  EXPECT_TRUE(skin->fixed_joints().empty());

  SkinBuilder off(8);
  off.options().fixed_layout = false;
  off.add_vertex({{0, 1}});
  const Result<Skin> general = off.build();
  ASSERT_TRUE(general.is_ok()) << general.status().message();
  EXPECT_FALSE(general->has_fixed_layout()) << "fixed_layout = false builds the general layout only";
}

TEST(SkinBuilder, add_vertices__reads_gltf_style_sets) {
  // Two vertices, three JOINTS/WEIGHTS sets of 4 each (12 per vertex), as a
  // glTF file with JOINTS_0..2 concatenated per vertex.
  std::vector<std::int64_t> joints;
  std::vector<double> weights;
  for (int v = 0; v < 2; ++v) {
    for (int k = 0; k < 12; ++k) {
      joints.push_back(k);
      weights.push_back(k < 10 ? 0.1 : 0.0);
    }
  }
  SkinBuilder builder(12);
  builder.add_vertices(joints, weights, 12);
  EXPECT_EQ(builder.vertex_count(), 2u);
  SkinBuildReport report;
  const Result<Skin> skin = builder.build(&report);
  ASSERT_TRUE(skin.is_ok()) << skin.status().message();
  EXPECT_EQ(skin->max_influences(), 10u);
  EXPECT_EQ(report.dropped_zero_weights, 4u) << "two zero slots per vertex";
  EXPECT_FALSE(skin->has_fixed_layout());
}

TEST(SkinBuilder, make_skin__builds_from_per_vertex_lists) {
  Random random(5);
  const auto lists = random.influences(100, 10, 6);
  SkinBuildOptions options;
  const Result<Skin> skin = make_skin(lists, 10, options);
  ASSERT_TRUE(skin.is_ok()) << skin.status().message();
  EXPECT_EQ(skin->vertex_count(), 100u);
  for (std::size_t v = 0; v < 100; ++v) {
    double sum = 0.0;
    for (std::uint32_t k = skin->offsets()[v]; k < skin->offsets()[v + 1]; ++k) sum += skin->weights()[k];
    EXPECT_NEAR(sum, 1.0, 1e-6) << "vertex " << v << " should be normalised";
  }
}

}  // namespace
}  // namespace rigel::ops
