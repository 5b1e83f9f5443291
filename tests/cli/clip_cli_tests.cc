// `rigel eval --clip NAME|INDEX`: which animation clip plays (DESIGN.md,
// Conventions: "the first is active, --clip NAME|INDEX picks another").

#include <gtest/gtest.h>

#include <string>

#include <nlohmann/json.hpp>

#include "../io/io_test_util.h"
#include "cli_test_util.h"

namespace rigel::cli {
namespace {

using namespace rigel::cli::testing;  // NOLINT: the CLI runner
using Json = nlohmann::json;

std::string fixture(const std::string& name) { return (rigel::io::testing::scenes_dir() / name).string(); }

// hip.translate.x of `rigel eval SCENE --time 0.5 --json ARGS...`.
double hip_x(const CliRun& run) { return Json::parse(run.out)["nodes"]["hip"]["t"][0].get<double>(); }

TEST(CliClip, eval__plays_the_first_clip_by_default) {
  const CliRun r = rigel({"eval", fixture("two_clips.rigel"), "--time", "0.5", "--json"});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  EXPECT_DOUBLE_EQ(hip_x(r), 1.0) << "walk: 0 -> 2 over 1 s";
  EXPECT_EQ(Json::parse(r.out)["clip"], "walk");
}

TEST(CliClip, eval__clip_by_name_or_index) {
  for (const char* clip : {"jump", "1"}) {
    const CliRun r = rigel({"eval", fixture("two_clips.rigel"), "--time", "0.5", "--clip", clip, "--json"});
    ASSERT_TRUE(exited_with(r, 0)) << r;
    EXPECT_DOUBLE_EQ(hip_x(r), 11.0) << "jump: 10 -> 14 over 2 s";
    EXPECT_EQ(Json::parse(r.out)["clip"], "jump");
  }
  const CliRun text = rigel({"eval", fixture("two_clips.rigel"), "--time", "0.5", "--clip", "jump"});
  ASSERT_TRUE(exited_with(text, 0)) << text;
  EXPECT_TRUE(contains(text.out, "clip 'jump'")) << text;
}

TEST(CliClip, eval__unknown_clip_exits_1_listing_the_clips) {
  const CliRun r = rigel({"eval", fixture("two_clips.rigel"), "--clip", "run"});
  EXPECT_TRUE(exited_with(r, 1)) << r;
  EXPECT_TRUE(contains(r.err, "--clip: no clip 'run'; clips: 0 'walk', 1 'jump'")) << r;
  EXPECT_TRUE(r.out.empty()) << r;
}

TEST(CliClip, eval__clip_on_a_scene_without_clips_exits_1) {
  const CliRun r = rigel({"eval", fixture("two_joint_chain.rigel"), "--clip", "0"});
  EXPECT_TRUE(exited_with(r, 1)) << r;
  EXPECT_TRUE(contains(r.err, "the scene has no animation clips")) << r;
}

}  // namespace
}  // namespace rigel::cli
