// BVH parsing: the real CMU file, hand-written files with known answers, and
// malformed files that must be refused with the line that is wrong.

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "io_test_util.h"
#include "rigel/io/bvh.h"
#include "rigel/io/bvh_import.h"
#include "rigel/math/rotation.h"
#include "rigel/ops/registry.h"
#include "rigel/scene/transform_types.h"

namespace rigel::io {
namespace {

using testing::source_dir;

const char* kSmall = R"(HIERARCHY
ROOT hips
{
  OFFSET 0 1 0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
  JOINT spine
  {
    OFFSET 0 0.5 0
    CHANNELS 3 Xrotation Yrotation Zrotation
    End Site
    {
      OFFSET 0 0.25 0
    }
  }
}
MOTION
Frames: 2
Frame Time: 0.04
1 2 3 10 20 30 40 50 60
4 5 6 11 21 31 41 51 61
)";

TEST(Bvh, parse__small_file_gives_joints_channels_and_motion) {
  Result<BvhFile> r = parse_bvh(kSmall, "small.bvh");
  ASSERT_TRUE(r.is_ok()) << r.status().message();
  const BvhFile& f = *r;
  ASSERT_EQ(f.joints.size(), 3u) << "hips, spine and spine's end site";
  EXPECT_EQ(f.joints[0].name, "hips") << "root name";
  EXPECT_EQ(f.joints[0].parent, -1) << "the root has no parent";
  EXPECT_EQ(f.joints[1].parent, 0) << "spine is under hips";
  EXPECT_TRUE(f.joints[2].end_site) << "the End Site is kept as a joint";
  EXPECT_EQ(f.joints[2].name, "spine_end") << "an End Site is named after its parent";
  EXPECT_EQ(f.joints[1].offset, math::Vec3(0, 0.5, 0)) << "offsets are read as written";
  EXPECT_EQ(f.channel_count, 9u) << "6 + 3 channels";
  EXPECT_EQ(f.joints[1].first_channel, 6u) << "spine's channels follow the root's";
  EXPECT_EQ(f.frame_count, 2u) << "two frames";
  EXPECT_DOUBLE_EQ(f.frame_time, 0.04) << "Frame Time";
  EXPECT_EQ(f.value(1, 8), 61.0) << "last value of the last row";
  EXPECT_EQ(f.joints[2].line, 10u) << "joints remember their line";
}

TEST(Bvh, rotate_order__follows_the_channel_order) {
  Result<BvhFile> r = parse_bvh(kSmall, "small.bvh");
  ASSERT_TRUE(r.is_ok()) << r.status().message();
  // "Z X Y" is R = Rz * Rx * Ry: Y applies first -> yxz.
  EXPECT_EQ(bvh_rotate_order(r->joints[0]), static_cast<int>(math::RotateOrder::kYXZ)) << "Z X Y listed -> yxz";
  // "X Y Z" is R = Rx * Ry * Rz: Z applies first -> zyx.
  EXPECT_EQ(bvh_rotate_order(r->joints[1]), static_cast<int>(math::RotateOrder::kZYX)) << "X Y Z listed -> zyx";
  BvhJoint only_z;
  only_z.channels = {BvhChannel::kZrotation};
  EXPECT_EQ(bvh_rotate_order(only_z), static_cast<int>(math::RotateOrder::kZXY)) << "missing axes come after the present one";
}

TEST(Bvh, parse__cmu_file_with_mixed_rotation_orders) {
  Result<BvhFile> r = load_bvh((source_dir() / "tests/data/bvh/cmu_131_01.bvh").string());
  ASSERT_TRUE(r.is_ok()) << r.status().message();
  EXPECT_EQ(r->frame_count, 994u) << "the file says Frames: 994";
  EXPECT_NEAR(r->frame_time, 1.0 / 120.0, 1e-6) << "120 fps";
  EXPECT_EQ(r->motion.size(), std::size_t{994} * r->channel_count) << "every row is complete";
  int xyz = 0, yxz = 0;
  for (const BvhJoint& j : r->joints) {
    if (j.end_site) continue;
    int order = bvh_rotate_order(j);
    xyz += order == static_cast<int>(math::RotateOrder::kXYZ);
    yxz += order == static_cast<int>(math::RotateOrder::kYXZ);
  }
  EXPECT_GT(xyz, 0) << "some joints list Z Y X rotations";
  EXPECT_GT(yxz, 0) << "and some list Z X Y: the file mixes orders";
  EXPECT_EQ(r->joints[0].name, "Hips") << "the root";
}

struct Bad {
  std::string text;
  std::string where;  // expected "file:line"
  std::string what;   // expected substring
};

TEST(Bvh, parse__malformed_files_name_the_line) {
  const std::vector<Bad> cases = {
      {"", "bad.bvh:1:", "expected 'HIERARCHY'"},
      {"HIERARCHY\n", "bad.bvh:1:", "ROOT"},
      {"HIERARCHY\nROOT a\n{\nOFFSET 0 0\n}\n", "bad.bvh:5:", "expected a finite number for OFFSET"},
      {"HIERARCHY\nROOT a\n{\nOFFSET 0 0 0\nCHANNELS 1 Wrotation\n}\n", "bad.bvh:5:", "unknown channel 'Wrotation'"},
      {"HIERARCHY\nROOT a\n{\nOFFSET 0 0 0\nCHANNELS 2 Xrotation Xrotation\n}\n", "bad.bvh:5:", "repeated"},
      {"HIERARCHY\nROOT a\n{\nOFFSET 0 0 0\nCHANNELS 7 Xrotation\n}\n", "bad.bvh:5:", "count must be 0 to 6"},
      {"HIERARCHY\nROOT a\n{\nOFFSET 0 nan 0\n}\nMOTION\nFrames: 0\nFrame Time: 1\n", "bad.bvh:4:", "finite number"},
      {"HIERARCHY\nROOT a\n{\nOFFSET 0 0 0\n", "bad.bvh:4:", "not closed"},
      {"HIERARCHY\nROOT a\n{\nOFFSET 0 0 0\n}\n}\nMOTION\n", "bad.bvh:6:", "unbalanced '}'"},
      {"HIERARCHY\nROOT a\n{\nOFFSET 0 0 0\n}\n", "bad.bvh:5:", "expected 'MOTION'"},
      {"HIERARCHY\nROOT a\n{\nOFFSET 0 0 0\nCHANNELS 1 Xrotation\n}\nMOTION\nFrames: 2\nFrame Time: 0.1\n1\n",
       "bad.bvh:10:", "expected 2 frames x 1 channels"},
      {"HIERARCHY\nROOT a\n{\nOFFSET 0 0 0\nCHANNELS 1 Xrotation\n}\nMOTION\nFrames: 1\nFrame Time: 0\n1\n",
       "bad.bvh:9:", "Frame Time must be from 0.0001 to 1000 seconds"},
      {"HIERARCHY\nROOT a\n{\nOFFSET 0 0 0\nCHANNELS 1 Xrotation\n}\nMOTION\nFrames: 1\nFrame Time: 0.1\ninf\n",
       "bad.bvh:10:", "finite number for motion value"},
      {"HIERARCHY\nROOT a\n{\nOFFSET 0 0 0\nEnd Site\n{\nOFFSET 0 0 0\nJOINT b\n{\nOFFSET 0 0 0\n}\n}\n}\nMOTION\n",
       "bad.bvh:8:", "End Site cannot have children"},
      {"HIERARCHY\nJOINT a\n", "bad.bvh:2:", "ROOT"},
      {"HIERARCHY\nROOT a\n{\nOFFSET 0 0 0\nROOT b\n", "bad.bvh:5:", "ROOT inside another joint"},
      {"HIERARCHY\nROOT a\n{\nOFFSET 0 0 0\n}\nMOTION\nFrames: -1\n", "bad.bvh:7:", "whole number"},
  };
  for (const Bad& c : cases) {
    Result<BvhFile> r = parse_bvh(c.text, "bad.bvh");
    ASSERT_FALSE(r.is_ok()) << "should be refused:\n" << c.text;
    const std::string& m = r.status().message();
    EXPECT_NE(m.find(c.where), std::string::npos) << "message should name " << c.where << ": " << m;
    EXPECT_NE(m.find(c.what), std::string::npos) << "message should say '" << c.what << "': " << m;
  }
}

// The MOTION header's ranges (bvh.h): Frames 0..1e8, Frame Time 1e-4..1000 s.
TEST(Bvh, parse__frames_and_frame_time_outside_their_ranges_name_the_line_and_the_limit) {
  const std::string head = "HIERARCHY\nROOT a\n{\nOFFSET 0 0 0\n}\nMOTION\n";
  struct Case {
    std::string motion;
    std::string where, what;
  };
  const std::vector<Case> cases = {
      {"Frames: 2000000000\nFrame Time: 0.1\n", "bad.bvh:7:", "Frames must be a whole number from 0 to 100000000, not 2000000000"},
      {"Frames: 100000001\nFrame Time: 0.1\n", "bad.bvh:7:", "from 0 to 100000000"},
      {"Frames: 1.5\nFrame Time: 0.1\n", "bad.bvh:7:", "not 1.5"},
      {"Frames: 0\nFrame Time: 1e-300\n", "bad.bvh:8:", "Frame Time must be from 0.0001 to 1000 seconds (0.001 to 10000 frames per second), not 1e-300"},
      {"Frames: 0\nFrame Time: 1e300\n", "bad.bvh:8:", "not 1e300"},
      {"Frames: 0\nFrame Time: 0.00009\n", "bad.bvh:8:", "Frame Time must be from"},
      {"Frames: 0\nFrame Time: 1000.5\n", "bad.bvh:8:", "Frame Time must be from"},
      {"Frames: 0\nFrame Time: -0.04\n", "bad.bvh:8:", "Frame Time must be from"},
  };
  for (const Case& c : cases) {
    Result<BvhFile> r = parse_bvh(head + c.motion, "bad.bvh");
    ASSERT_FALSE(r.is_ok()) << c.motion;
    EXPECT_EQ(r.status().message().rfind(c.where + " ", 0), 0u) << r.status().message();
    EXPECT_NE(r.status().message().find(c.what), std::string::npos) << r.status().message();
  }
  // The ends of the ranges are accepted, and import at their frame rates.
  for (const char* motion : {"Frames: 0\nFrame Time: 0.0001\n", "Frames: 0\nFrame Time: 1000\n"}) {
    Result<BvhFile> r = parse_bvh(head + motion, "edge.bvh");
    ASSERT_TRUE(r.is_ok()) << motion << r.status().message();
    Result<std::unique_ptr<scene::Scene>> s = import_bvh(*r);
    ASSERT_TRUE(s.is_ok()) << s.status().message();
    EXPECT_NEAR((*s)->graph().fps() * r->frame_time, 1.0, 1e-12);
  }
  // A BvhFile made in code is held to the same range.
  BvhFile made;
  made.joints.push_back(BvhJoint{});
  made.joints[0].name = "a";
  made.frame_time = 1e300;
  Result<std::unique_ptr<scene::Scene>> s = import_bvh(made);
  ASSERT_FALSE(s.is_ok());
  EXPECT_NE(s.status().message().find("the frame time 1e+300 s is outside [0.0001, 1000] s"), std::string::npos) << s.status().message();
}

TEST(Bvh, parse__deep_nesting_is_refused_not_a_stack_overflow) {
  std::string text = "HIERARCHY\nROOT a\n{\nOFFSET 0 0 0\n";
  for (int i = 0; i < 1200; ++i) text.append("JOINT j").append(std::to_string(i)).append("\n{\nOFFSET 0 0 0\n");
  Result<BvhFile> r = parse_bvh(text, "deep.bvh");
  ASSERT_FALSE(r.is_ok()) << "1,200 levels should be refused";
  EXPECT_NE(r.status().message().find("nested deeper"), std::string::npos) << r.status().message();
}

TEST(Bvh, parse__truncations_and_random_mutations_never_crash) {
  const std::string text = kSmall;
  for (std::size_t n = 0; n < text.size(); ++n) {
    Result<BvhFile> r = parse_bvh(text.substr(0, n), "cut.bvh");
    if (!r.is_ok()) {
      EXPECT_FALSE(r.status().message().empty()) << "a refusal says why (cut at " << n << ")";
    }
  }
  std::mt19937 rng(131);
  for (int i = 0; i < 3000; ++i) {
    std::string m = text;
    int edits = 1 + static_cast<int>(rng() % 4);
    for (int e = 0; e < edits && !m.empty(); ++e) {
      std::size_t at = rng() % m.size();
      switch (rng() % 4) {
        case 0: m[at] = static_cast<char>(rng() % 256); break;
        case 1: m.erase(at, 1 + rng() % 8); break;
        case 2: m.insert(at, m.substr(rng() % m.size(), 1 + rng() % 16)); break;
        default: m.insert(at, 1, (rng() % 2) ? '{' : '}'); break;
      }
    }
    Result<BvhFile> r = parse_bvh(m, "fuzz.bvh");
    if (r.is_ok()) {
      EXPECT_EQ(r->motion.size(), std::size_t{r->frame_count} * r->channel_count) << "an accepted file is consistent";
    } else {
      EXPECT_FALSE(r.status().message().empty()) << "a refusal says why";
    }
  }
}

TEST(Bvh, load__missing_file_is_an_io_error) {
  Result<BvhFile> r = load_bvh("/nonexistent/walk.bvh");
  ASSERT_FALSE(r.is_ok()) << "no such file";
  EXPECT_EQ(r.status().code(), ErrorCode::kIoError) << "reported as an i/o error";
  EXPECT_NE(r.status().message().find("/nonexistent/walk.bvh"), std::string::npos) << "naming the path";
}

// Forward kinematics written straight from the BVH convention, without
// rigel's transform code: each joint's local matrix is T(offset + position
// channels) times the rotation channels multiplied in file order.
std::vector<math::Mat4> naive_bvh_world(const BvhFile& f, std::uint32_t frame) {
  std::vector<math::Mat4> world(f.joints.size());
  for (std::size_t j = 0; j < f.joints.size(); ++j) {
    const BvhJoint& joint = f.joints[j];
    math::Mat4 local = math::Mat4::Identity();
    math::Vec3 t = joint.offset;
    math::Mat3 r = math::Mat3::Identity();
    for (std::size_t k = 0; k < joint.channels.size(); ++k) {
      const double v = f.value(frame, joint.first_channel + static_cast<std::uint32_t>(k));
      const int axis = static_cast<int>(joint.channels[k]) % 3;
      if (joint.channels[k] <= BvhChannel::kZposition) {
        t[axis] += v;
      } else {
        const double a = v * math::kPi / 180.0, c = std::cos(a), s = std::sin(a);
        math::Mat3 m = math::Mat3::Identity();
        const int p = (axis + 1) % 3, q = (axis + 2) % 3;
        m(p, p) = c;
        m(p, q) = -s;
        m(q, p) = s;
        m(q, q) = c;
        r = r * m;
      }
    }
    local.topLeftCorner<3, 3>() = r;
    local.topRightCorner<3, 1>() = t;
    world[j] = joint.parent < 0 ? local : world[static_cast<std::size_t>(joint.parent)] * local;
  }
  return world;
}

TEST(BvhImport, cmu_walk__world_positions_match_naive_forward_kinematics) {
  Result<BvhFile> f = load_bvh((source_dir() / "tests/data/bvh/cmu_131_01.bvh").string());
  ASSERT_TRUE(f.is_ok()) << f.status().message();
  Result<std::unique_ptr<scene::Scene>> imported = import_bvh(*f);
  ASSERT_TRUE(imported.is_ok()) << imported.status().message();
  scene::Scene& s = **imported;
  EXPECT_EQ(s.graph().fps(), 120.0) << "Frame Time 0.0083333 snaps to 120 fps";
  for (std::uint32_t frame : {0u, 1u, 300u, 611u, 993u}) {
    s.set_frame(frame);
    const std::vector<math::Mat4> expected = naive_bvh_world(*f, frame);
    for (std::size_t j = 0; j < f->joints.size(); ++j) {
      graph::NodeId id = s.graph().find(f->joints[j].name);
      ASSERT_TRUE(id.is_valid()) << "joint " << f->joints[j].name << " exists";
      const math::Mat4 world = s.world_matrix(id);
      EXPECT_TRUE(world.isApprox(expected[j], 1e-9) || (world - expected[j]).cwiseAbs().maxCoeff() < 1e-9)
          << f->joints[j].name << " at frame " << frame << "\nrigel:\n" << world << "\nnaive:\n" << expected[j];
    }
  }
}

TEST(BvhImport, scale_and_end_sites_options) {
  Result<BvhFile> f = parse_bvh(kSmall, "small.bvh");
  ASSERT_TRUE(f.is_ok()) << f.status().message();
  BvhImportOptions options;
  options.scale = 0.5;
  options.skip_end_sites = true;
  Result<std::unique_ptr<scene::Scene>> imported = import_bvh(*f, options);
  ASSERT_TRUE(imported.is_ok()) << imported.status().message();
  scene::Scene& s = **imported;
  EXPECT_FALSE(s.graph().find("spine_end").is_valid()) << "End Sites skipped on request";
  EXPECT_EQ(s.graph().fps(), 25.0) << "Frame Time 0.04 is 25 fps";
  s.set_frame(1);
  const math::Mat4 hips = s.world_matrix(s.graph().find("hips"));
  EXPECT_NEAR(hips(1, 3), 0.5 * (1.0 + 5.0), 1e-12) << "offset plus position channel, both scaled";
  options.scale = 0.0;
  EXPECT_FALSE(import_bvh(*f, options).is_ok()) << "a zero scale is refused";
}

TEST(BvhImport, the_scene_is_built_over_the_registry_given) {
  Result<BvhFile> f = parse_bvh(kSmall, "small.bvh");
  ASSERT_TRUE(f.is_ok()) << f.status().message();
  auto registry = std::make_shared<graph::Registry>();
  ASSERT_TRUE(scene::register_scene_types(*registry).is_ok());
  ASSERT_TRUE(ops::register_ops_types(*registry).is_ok());
  BvhImportOptions options;
  options.registry = registry;
  Result<std::unique_ptr<scene::Scene>> imported = import_bvh(*f, options);
  ASSERT_TRUE(imported.is_ok()) << imported.status().message();
  EXPECT_EQ(&(*imported)->graph().registry(), registry.get());
  EXPECT_FALSE((*imported)->graph().can_undo());
  // A registry without the types the importer makes is an error, not a crash.
  options.registry = std::make_shared<graph::Registry>();
  Result<std::unique_ptr<scene::Scene>> refused = import_bvh(*f, options);
  EXPECT_FALSE(refused.is_ok());
}

}  // namespace
}  // namespace rigel::io
