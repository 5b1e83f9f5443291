// `rigel pose` and `rigel ephemeral` on the cases of issue 14 ("Ephemeral
// posing"), end to end on the bundled characters: several grabbed controls
// on one chain, straight BVH chains in inverse mode, --max-chain 1, a
// zero-length bone, two characters merged (one rigged under the other's
// joints), glTF key times a hair off their frames, usage errors, and carrier
// relations in `ephemeral relations`.

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "../io/io_test_util.h"
#include "cli_test_util.h"

namespace rigel::cli {
namespace {

using namespace rigel::cli::testing;  // NOLINT: the CLI runner
using Json = nlohmann::ordered_json;
namespace fs = std::filesystem;
using Names = std::vector<std::string>;

// The metarig's float32 scales hold its poses to ~1e-7 (docs/EPHEMERAL.md,
// Limits); the bugs these tests guard against are off by the whole motion.
constexpr double kFloat = 1e-6;

std::string gltf(const std::string& name) {
  return (rigel::io::testing::source_dir() / "tests" / "data" / "gltf" / name).string();
}

class CliPoseCases : public ::testing::Test {
 protected:
  std::string path(const std::string& name) const { return (dir_.path() / name).string(); }

  // Runs `rigel ARGS...`, which must exit with `code`.
  CliRun run(const std::vector<std::string>& args, int code = 0) {
    const CliRun r = rigel(args);
    EXPECT_TRUE(exited_with(r, code)) << r;
    return r;
  }
  // `rigel pose SCENE -o OUT --json ARGS...` (must succeed): its JSON.
  Json pose(const std::string& scene, const std::string& out, std::vector<std::string> args) {
    std::vector<std::string> words = {"pose", scene, "-o", out, "--json"};
    words.insert(words.end(), args.begin(), args.end());
    const CliRun r = run(words);
    if (!exited_with(r, 0)) return Json::object();
    last_err_ = r.err;
    return Json::parse(r.out);
  }
  // World transforms of every node: `rigel eval FILE --json`.
  Json eval(const std::string& file) {
    const CliRun r = run({"eval", file, "--json"});
    if (!exited_with(r, 0)) return Json::object();
    return Json::parse(r.out)["nodes"];
  }
  // The metarig with one ephemeral rig on every joint.
  std::string metarig() {
    const std::string m = path("m.rigel");
    if (!fs::exists(m)) run({"ephemeral", "setup", gltf("rigify_human_metarig.glb"), "-o", m});
    return m;
  }

  TempDir dir_;
  std::string last_err_;
};

// ---- several grabbed controls on one chain -------------------------------------

TEST_F(CliPoseCases, multi_grab__each_grabbed_control_moves_by_the_one_motion) {
  const std::string m = metarig();
  const Json before = eval(m);
  for (const std::string mode : {"pseudo-inverse", "inverse"}) {
    for (const Names& grab : {Names{"forearm.L", "hand.L"}, Names{"shin.L", "foot.L"}}) {
      if (mode == "inverse" && grab[0] == "shin.L") continue;  // the knee's chain is one bone (thigh): out of reach
      SCOPED_TRACE(mode + " " + grab[0] + " + " + grab[1]);
      const Json j = pose(m, path("x.rigel"), {"--control", grab[0], "--select", grab[1], "--mode", mode, "--translate", "0,0.1,0"});
      for (const std::string& name : grab) {
        const V3 b = v3(before[name + "_ctrl"]["t"]);
        SCOPED_TRACE(name);
        EXPECT_V3_NEAR(v3(j["moved"][name + "_ctrl"]["t"]), b.x, b.y + 0.1, b.z, kFloat);
      }
      if (mode == "inverse") {
        EXPECT_TRUE(j["notes"].empty()) << j["notes"];
        const Json after = eval(path("x.rigel"));
        for (const auto& [a, b] : {std::pair<std::string, std::string>{"upper_arm.L", "forearm.L"}, {"forearm.L", "hand.L"},
                                   {"shoulder.L", "upper_arm.L"}}) {
          EXPECT_NEAR(dist(v3(after[a]["t"]), v3(after[b]["t"])), dist(v3(before[a]["t"]), v3(before[b]["t"])), kFloat)
              << a << " - " << b;
        }
      }
    }
  }
}

// ---- inverse mode on straight chains (BVH) --------------------------------------

// A BVH chain of `joints` joints (j0 the root) and an end site, each OFFSET
// `offset` from its parent, one frame of zeros.
std::string straight_bvh(int joints, const std::string& offset) {
  std::string text = "HIERARCHY\nROOT j0\n{\n  OFFSET 0 0 0\n  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n";
  for (int i = 1; i < joints; ++i)
    text += "JOINT j" + std::to_string(i) + "\n{\n  OFFSET " + offset + "\n  CHANNELS 3 Zrotation Xrotation Yrotation\n";
  text += "End Site\n{\n  OFFSET " + offset + "\n}\n";
  for (int i = 0; i < joints; ++i) text += "}\n";
  text += "MOTION\nFrames: 1\nFrame Time: 0.0416667\n";
  for (int i = 0; i < 6 + 3 * (joints - 1); ++i) text += i ? " 0" : "0";
  return text + "\n";
}

TEST_F(CliPoseCases, inverse__straight_chains_reach_every_target_within_reach) {
  struct Case {
    std::string offset;
    V3 axis;
    double bone;
  };
  for (const Case& c : {Case{"0 1 0", {0, 1, 0}, 1.0}, Case{"0.5 0 0", {1, 0, 0}, 0.5}, Case{"0 0 -2", {0, 0, -1}, 2.0}}) {
    const std::string bvh = path("chain.bvh"), scene = path("chain.rigel");
    rigel::io::testing::write_text(bvh, straight_bvh(6, c.offset));
    ASSERT_TRUE(exited_with(run({"ephemeral", "setup", bvh, "-o", scene, "--drop-animation"}), 0));
    const Json before = eval(scene);
    struct Drag {
      std::string control;
      double along, side;  // in bone lengths, along the chain's axis and across it
    };
    for (const Drag& d : {Drag{"j5", -1, 0}, Drag{"j5_end", -3, 0}, Drag{"j5_end", -0.01, 0.01}, Drag{"j3", -0.5, 0.4}}) {
      SCOPED_TRACE("offset " + c.offset + ": " + d.control + " along " + std::to_string(d.along) + " side " + std::to_string(d.side));
      // The side is along the first axis across the chain.
      const V3 side = c.axis.x != 0 ? V3{0, 1, 0} : V3{1, 0, 0};
      const V3 t{c.bone * (d.along * c.axis.x + d.side * side.x), c.bone * (d.along * c.axis.y + d.side * side.y),
                 c.bone * (d.along * c.axis.z + d.side * side.z)};
      const std::string delta = std::to_string(t.x) + "," + std::to_string(t.y) + "," + std::to_string(t.z);
      const Json j = pose(scene, path("x.rigel"), {"--control", d.control, "--mode", "inverse", "--translate", delta});
      const V3 b = v3(before[d.control + "_ctrl"]["t"]);
      ASSERT_TRUE(j["moved"].contains(d.control + "_ctrl")) << j;
      EXPECT_V3_NEAR(v3(j["moved"][d.control + "_ctrl"]["t"]), b.x + t.x, b.y + t.y, b.z + t.z, 1e-9 * 6 * c.bone);
      EXPECT_TRUE(j["notes"].empty()) << j["notes"];
      const Json after = eval(path("x.rigel"));
      Names chain = {"j0", "j1", "j2", "j3", "j4", "j5", "j5_end"};
      for (std::size_t i = 1; i < chain.size(); ++i)
        EXPECT_NEAR(dist(v3(after[chain[i]]["t"]), v3(after[chain[i - 1]]["t"])), c.bone, 1e-9) << chain[i];
    }
  }
}

// ---- what inverse mode cannot do it says ------------------------------------------

TEST_F(CliPoseCases, inverse__max_chain_1_keeps_the_bone_and_says_why) {
  const std::string m = metarig();
  const Json before = eval(m);
  const Json j = pose(m, path("x.rigel"), {"--control", "hand.L", "--mode", "inverse", "--max-chain", "1", "--translate", "0,0.1,0"});
  EXPECT_FALSE(j["moved"].contains("hand.L_ctrl")) << j;
  ASSERT_EQ(j["notes"].size(), 1u) << j;
  EXPECT_TRUE(contains(j["notes"][0].get<std::string>(), "'hand.L_ctrl' keeps its position")) << j;
  EXPECT_TRUE(contains(last_err_, "note: 'hand.L_ctrl' keeps its position")) << last_err_;
  const Json after = eval(path("x.rigel"));
  EXPECT_NEAR(dist(v3(after["hand.L"]["t"]), v3(after["forearm.L"]["t"])),
              dist(v3(before["hand.L"]["t"]), v3(before["forearm.L"]["t"])), 1e-12);
}

TEST_F(CliPoseCases, inverse__a_zero_length_bone_moves_nothing_and_says_why) {
  const std::string scene = path("tip.rigel"), rig = path("tip_rig.rigel");
  rigel::io::testing::write_text(scene, R"({
  "rigel": "scene", "version": 1, "fps": 24, "time": 0,
  "nodes": [
    {"name": "hand", "type": "joint", "attrs": {"translate": [0, 1, 0]}},
    {"name": "tip", "type": "joint", "parent": "hand"}
  ],
  "connections": []
})");
  ASSERT_TRUE(exited_with(run({"ephemeral", "setup", scene, "-o", rig}), 0));
  const Json j = pose(rig, path("x.rigel"), {"--control", "tip", "--mode", "inverse", "--translate", "0,1,0"});
  EXPECT_TRUE(j["moved"].empty()) << j;
  ASSERT_EQ(j["notes"].size(), 1u) << j;
  EXPECT_TRUE(contains(j["notes"][0].get<std::string>(), "'tip_ctrl' cannot move in inverse mode")) << j;
  EXPECT_TRUE(contains(last_err_, "0 controls moved")) << last_err_;
  EXPECT_TRUE(contains(last_err_, "note: 'tip_ctrl' cannot move")) << last_err_;
}

// ---- two characters, one rigged under the other's joints ------------------------

TEST_F(CliPoseCases, merged_characters__body_mode_moves_each_control_once) {
  // The metarig's joints and parents, from the imported scene.
  const std::string base = path("base.rigel");
  ASSERT_TRUE(exited_with(run({"import", gltf("rigify_human_metarig.glb"), "-o", base}), 0));
  std::map<std::string, std::string> parent;
  Names joints;
  const Json imported = Json::parse(read_text(base));
  for (const Json& n : imported["nodes"]) {
    if (n["type"] != "joint") continue;
    joints.push_back(n["name"]);
    parent[n["name"]] = n.value("parent", "");
  }
  auto in_left_arm = [&](std::string name) {
    for (; !name.empty(); name = parent.count(name) ? parent[name] : "")
      if (name == "upper_arm.L") return true;
    return false;
  };
  std::string body, arm;
  for (const std::string& j : joints) {
    std::string& list = in_left_arm(j) ? arm : body;
    list += (list.empty() ? "" : ",") + j;
  }
  ASSERT_FALSE(arm.empty());
  const std::string a = path("a.rigel"), two = path("two.rigel"), merged = path("merged.rigel");
  ASSERT_TRUE(exited_with(run({"ephemeral", "setup", base, "--joints", body, "-o", a}), 0));
  ASSERT_TRUE(exited_with(run({"ephemeral", "setup", a, "--joints", arm, "--rig-name", "armRig", "-o", two}), 0));
  ASSERT_TRUE(exited_with(run({"ephemeral", "merge", two, "--rigs", "ephemeralRig,armRig", "-o", merged}), 0));
  const Json before = eval(two);
  std::set<std::string> arm_controls;
  for (const std::string& j : joints)
    if (in_left_arm(j)) arm_controls.insert(j + "_ctrl");

  // Merged, body: every control of both characters moves by 0.1 in x, once.
  Json j = pose(merged, path("x.rigel"), {"--control", "spine", "--mode", "body", "--translate", "0.1,0,0"});
  std::size_t moved = 0;
  for (const std::string& j_name : joints) {
    const std::string c = j_name + "_ctrl";
    ASSERT_TRUE(j["moved"].contains(c)) << c;
    const V3 b = v3(before[c]["t"]);
    SCOPED_TRACE(c);
    EXPECT_V3_NEAR(v3(j["moved"][c]["t"]), b.x + 0.1, b.y, b.z, kFloat);
    ++moved;
  }
  EXPECT_EQ(moved, joints.size());
  // Not merged: body, suspended and forward on the spine leave the arm's
  // character where it is (outside the plan, whichever character it is in).
  for (const std::string mode : {"body", "suspended", "forward"}) {
    j = pose(two, path("y.rigel"), {"--control", "spine", "--mode", mode, "--translate", "0.1,0,0", "--rotate", "0,0,10"});
    EXPECT_TRUE(j["moved"].contains("spine_ctrl")) << mode;
    const Json after = eval(path("y.rigel"));
    for (const std::string& c : arm_controls) {
      SCOPED_TRACE(mode + ": " + c);
      const V3 p0 = v3(before[c]["t"]);
      EXPECT_V3_NEAR(v3(after[c]["t"]), p0.x, p0.y, p0.z, kFloat);
    }
  }
}

// ---- key times a hair off their frames --------------------------------------------

TEST_F(CliPoseCases, keys__a_glTF_key_a_hair_off_frame_38_is_frame_38s_key) {
  const std::string c = path("c.rigel");
  ASSERT_TRUE(exited_with(run({"ephemeral", "setup", gltf("CesiumMan.glb"), "-o", c}), 0));
  const CliRun keys = run({"ephemeral", "keys", c, "--control", "node_3_ctrl", "--json"});
  const Json k0 = Json::parse(keys.out);
  const std::vector<double> frames = k0["times"].get<std::vector<double>>();
  EXPECT_NE(std::find(frames.begin(), frames.end(), 38.0), frames.end()) << "frames print as whole frames: " << k0["times"];
  for (const bool auto_key : {false, true}) {
    std::vector<std::string> args = {"--control", "node_3_ctrl", "--mode", "forward", "--rotate", "0,0,5", "--frame", "38"};
    if (auto_key) args.push_back("--auto-key");
    const Json j = pose(c, path("x.rigel"), args);
    EXPECT_TRUE(j["moved"].contains("node_3_ctrl")) << j;
    const Json k1 = Json::parse(run({"ephemeral", "keys", path("x.rigel"), "--control", "node_3_ctrl", "--json"}).out);
    EXPECT_EQ(k1["times"], k0["times"]) << "no second key a hair away";
    EXPECT_EQ(k1["seconds"], k0["seconds"]);
  }
  // `ephemeral key --frame 38` updates that key too.
  run({"ephemeral", "key", c, "--control", "node_3_ctrl", "--frame", "38", "-o", path("k.rigel")});
  const Json k2 = Json::parse(run({"ephemeral", "keys", path("k.rigel"), "--control", "node_3_ctrl", "--json"}).out);
  EXPECT_EQ(k2["seconds"], k0["seconds"]);
}

// ---- usage -----------------------------------------------------------------------------

TEST_F(CliPoseCases, usage__scale_and_pivot_outside_body_mode_exit_2) {
  const std::string m = metarig();
  for (const Names& extra : {Names{"--scale", "2,2,2"}, Names{"--pivot", "0,0,0"}}) {
    Names args = {"pose", m, "-o", path("x.rigel"), "--control", "hand.L", "--mode", "forward"};
    args.insert(args.end(), extra.begin(), extra.end());
    const CliRun r = run(args, 2);
    EXPECT_TRUE(contains(r.err, extra[0] + " applies in body mode only")) << r;
    EXPECT_FALSE(fs::exists(path("x.rigel")));
  }
}

// ---- carrier relations are listed ---------------------------------------------------

TEST_F(CliPoseCases, relations__carrier_relations_are_listed_text_and_json) {
  const std::string scene = path("s.rigel");
  rigel::io::testing::write_text(scene, R"({
  "rigel": "scene", "version": 1, "fps": 24, "time": 0,
  "nodes": [
    {"name": "shoulder", "type": "joint", "attrs": {"translate": [0, 1, 0]}},
    {"name": "wrist", "type": "joint", "parent": "shoulder", "attrs": {"translate": [1, 0, 0]}},
    {"name": "sword", "type": "joint", "attrs": {"translate": [1.2, 1, 0]}},
    {"name": "blade", "type": "joint", "parent": "sword", "attrs": {"translate": [0.5, 0, 0]}}
  ],
  "connections": []
})");
  const std::string a = path("a.rigel"), b = path("b.rigel"), merged = path("merged.rigel");
  ASSERT_TRUE(exited_with(run({"ephemeral", "setup", scene, "--joints", "shoulder,wrist", "-o", a}), 0));
  ASSERT_TRUE(exited_with(run({"ephemeral", "setup", a, "--joints", "sword,blade", "--rig-name", "swordRig", "-o", b}), 0));
  ASSERT_TRUE(exited_with(run({"ephemeral", "merge", b, "--rigs", "ephemeralRig,swordRig", "--carrier", "wrist_ctrl",
                               "--carried", "swordRig", "-o", merged}), 0));
  const CliRun json = run({"ephemeral", "relations", merged, "--rig", "swordRig", "--json"});
  const Json j = Json::parse(json.out);
  Names carriers, own;
  for (const Json& r : j["relations"]) {
    const std::string text = r["kind"].get<std::string>() + " " + r["from"].get<std::string>() + " " + r["to"].get<std::string>();
    (r.value("carrier", false) ? carriers : own).push_back(text);
  }
  EXPECT_EQ(carriers, (Names{"forward wrist_ctrl sword_ctrl", "inverse sword_ctrl wrist_ctrl"})) << j;
  EXPECT_EQ(own, (Names{"forward sword_ctrl blade_ctrl", "inverse blade_ctrl sword_ctrl"})) << j;
  const CliRun text = run({"ephemeral", "relations", merged, "--rig", "swordRig"});
  EXPECT_TRUE(contains(text.out, "wrist_ctrl -> sword_ctrl  (carrier)")) << text;
  EXPECT_TRUE(contains(text.out, "sword_ctrl -> wrist_ctrl  (carrier)")) << text;
  // Removing one is refused with the way to do it.
  const CliRun removed = run({"ephemeral", "relations", merged, "--remove", "forward:wrist_ctrl:sword_ctrl", "--rig", "swordRig",
                              "-o", path("r.rigel")}, 1);
  EXPECT_TRUE(contains(removed.err, "carrier")) << removed;
}

}  // namespace
}  // namespace rigel::cli
