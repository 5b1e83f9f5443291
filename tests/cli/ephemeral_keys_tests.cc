// `rigel ephemeral key|keys|scope|merge|unmerge`, `rigel ephemeral setup
// --rig-name` and `rigel pose --key/--auto-key` (docs/EPHEMERAL.md, "Keys,
// keying groups and merged characters"). The fixture is pose_tests.cc's arm
// (shoulder at y = 1 -> elbow -> wrist -> hand, bent in the XZ plane, every
// joint unrotated) plus a sword, a root joint just past the hand, rigged as a
// second character ("swordRig"), so answers can be worked out by hand.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
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

constexpr const char* kArmAndSword = R"({
  "rigel": "scene", "version": 1, "fps": 24, "time": 0,
  "nodes": [
    {"name": "shoulder", "type": "joint", "attrs": {"translate": [0, 1, 0]}},
    {"name": "elbow", "type": "joint", "parent": "shoulder", "attrs": {"translate": [1, 0, -0.5]}},
    {"name": "wrist", "type": "joint", "parent": "elbow", "attrs": {"translate": [1, 0, 0.5]}},
    {"name": "hand", "type": "joint", "parent": "wrist", "attrs": {"translate": [0.25, 0, 0]}},
    {"name": "sword", "type": "joint", "attrs": {"translate": [2.5, 1, 0]}}
  ],
  "connections": []
})";

using Names = std::vector<std::string>;
using Frames = std::vector<double>;
const Names kArmControls = {"shoulder_ctrl", "elbow_ctrl", "wrist_ctrl", "hand_ctrl"};


// The arm rigged as "ephemeralRig" and the sword as "swordRig" (rig.rigel),
// both made by the CLI, in a fresh folder.
class CliKeys : public ::testing::Test {
 protected:
  void SetUp() override {
    rigel::io::testing::write_text(scene(), kArmAndSword);
    const CliRun arm = rigel({"ephemeral", "setup", scene(), "-o", path("arm.rigel"), "--joints",
                              "shoulder,elbow,wrist,hand"});
    ASSERT_TRUE(exited_with(arm, 0)) << arm;
    sword_run_ = rigel({"ephemeral", "setup", path("arm.rigel"), "-o", rig(), "--joints", "sword", "--rig-name",
                        "swordRig", "--json"});
    ASSERT_TRUE(exited_with(sword_run_, 0)) << sword_run_;
  }
  std::string path(const std::string& name) const { return (dir_.path() / name).string(); }
  std::string scene() const { return path("scene.rigel"); }
  std::string rig() const { return path("rig.rigel"); }

  // `rigel ARGS...`, which must succeed.
  CliRun ok(const std::vector<std::string>& args) {
    const CliRun r = rigel(args);
    EXPECT_TRUE(exited_with(r, 0)) << r;
    return r;
  }
  // `rigel ARGS... --json`, which must succeed; its JSON.
  Json json(std::vector<std::string> args) {
    args.push_back("--json");
    const CliRun r = ok(args);
    if (!exited_with(r, 0)) return Json::object();
    return Json::parse(r.out);
  }
  // `rigel ARGS...`, which must fail with `code`, writing neither `out` nor stdout.
  CliRun fails(const std::vector<std::string>& args, int code, const std::string& out) {
    const CliRun r = rigel(args);
    EXPECT_TRUE(exited_with(r, code)) << r;
    EXPECT_FALSE(fs::exists(out)) << "a failed command writes nothing: " << out;
    EXPECT_TRUE(r.out.empty()) << r;
    return r;
  }
  // World transforms of `rigel eval FILE --frame F --json`.
  Json eval(const std::string& file, double frame) {
    const Json j = json({"eval", file, "--frame", std::to_string(frame)});
    return j.contains("nodes") ? j["nodes"] : Json::object();
  }
  // rig.rigel keyed at frames 0 and 10 (rest pose at both), through the CLI.
  std::string keyed_0_10() {
    const Json k0 = json({"ephemeral", "key", rig(), "--control", "elbow_ctrl", "--frame", "0", "-o", path("k0.rigel")});
    EXPECT_EQ(k0["times"].get<Frames>(), (Frames{0}));
    const Json k10 = json({"ephemeral", "key", path("k0.rigel"), "--control", "wrist", "--frame", "10", "-o", path("k10.rigel")});
    EXPECT_EQ(k10["times"].get<Frames>(), (Frames{0, 10}));
    return path("k10.rigel");
  }
  Frames key_frames(const std::string& file, const std::string& control) {
    return json({"ephemeral", "keys", file, "--control", control})["times"].get<Frames>();
  }

  TempDir dir_;
  CliRun sword_run_;
};

// ---- setup --rig-name ------------------------------------------------------------

TEST_F(CliKeys, setup__rig_name_names_the_second_character) {
  const Json j = Json::parse(sword_run_.out);
  EXPECT_EQ(j["rig"], "swordRig");
  EXPECT_EQ(j["controls"].get<Names>(), (Names{"sword_ctrl"}));
  const CliRun r = fails({"ephemeral", "setup", scene(), "-o", path("bad.rigel"), "--rig-name", "two words"}, 2,
                         path("bad.rigel"));
  EXPECT_TRUE(contains(r.err, "--rig-name 'two words'")) << r;
}

// ---- key and keys ----------------------------------------------------------------

TEST_F(CliKeys, key__at_0_and_10_keys_every_control_of_the_character) {
  const Json k0 = json({"ephemeral", "key", rig(), "--control", "elbow_ctrl", "--frame", "0", "-o", path("k0.rigel")});
  EXPECT_EQ(k0["frame"], 0.0);
  EXPECT_EQ(k0["keyed"].get<Names>(), kArmControls) << "scope character: the whole arm, not the sword";
  EXPECT_EQ(k0["times"].get<Frames>(), (Frames{0}));
  const CliRun k10 = ok({"ephemeral", "key", path("k0.rigel"), "--control", "wrist", "--frame", "10", "-o", path("k10.rigel")});
  EXPECT_TRUE(k10.out.empty()) << k10;
  EXPECT_TRUE(contains(k10.err, "keyed 4 controls at frame 10 (keying scope: ephemeralRig=character); key frames: 0, 10")) << k10;

  const Json keys = json({"ephemeral", "keys", path("k10.rigel"), "--control", "hand_ctrl"});
  EXPECT_EQ(keys["control"], "hand_ctrl");
  EXPECT_EQ(keys["rig"], "ephemeralRig");
  EXPECT_EQ(keys["keyScope"], "character");
  EXPECT_EQ(keys["keyingSet"].get<Names>(), kArmControls);
  EXPECT_EQ(keys["times"].get<Frames>(), (Frames{0, 10}));
  ASSERT_EQ(keys["seconds"].size(), 2u);
  EXPECT_NEAR(keys["seconds"][1].get<double>(), 10.0 / 24.0, 1e-12);
  const CliRun text = ok({"ephemeral", "keys", path("k10.rigel"), "--control", "shoulder"});
  EXPECT_TRUE(contains(text.out, "shoulder_ctrl: rig ephemeralRig, keying scope: character")) << text;
  EXPECT_TRUE(contains(text.out, "key frames: 0, 10")) << text;

  // Every control holds both keys: seen one control at a time under scope controls.
  ok({"ephemeral", "scope", path("k10.rigel"), "--rig", "ephemeralRig", "--set", "controls", "-o", path("each.rigel")});
  for (const std::string& control : kArmControls) EXPECT_EQ(key_frames(path("each.rigel"), control), (Frames{0, 10})) << control;
  EXPECT_EQ(key_frames(path("each.rigel"), "sword_ctrl"), Frames{});
  // The keys hold the rest pose.
  EXPECT_V3_NEAR(v3(eval(path("k10.rigel"), 5)["wrist"]["t"]), 2, 1, 0, 1e-12);
}

TEST_F(CliKeys, scope__controls_keys_only_the_named_control) {
  const CliRun shown = ok({"ephemeral", "scope", rig(), "--rig", "ephemeralRig"});
  EXPECT_EQ(shown.out, "ephemeralRig: keying scope: character\n");
  ok({"ephemeral", "scope", rig(), "--rig", "ephemeralRig", "--set", "controls", "-o", path("s.rigel")});
  EXPECT_EQ(json({"ephemeral", "scope", path("s.rigel"), "--rig", "ephemeralRig"})["keyScope"], "controls");
  EXPECT_EQ(json({"ephemeral", "scope", path("s.rigel"), "--rig", "swordRig"})["keyScope"], "character");

  const Json k = json({"ephemeral", "key", path("s.rigel"), "--control", "elbow_ctrl", "--frame", "4", "-o", path("k.rigel")});
  EXPECT_EQ(k["keyed"].get<Names>(), (Names{"elbow_ctrl"}));
  EXPECT_EQ(k["times"].get<Frames>(), (Frames{4}));
  const Json wrist = json({"ephemeral", "keys", path("k.rigel"), "--control", "wrist_ctrl"});
  EXPECT_EQ(wrist["keyScope"], "controls");
  EXPECT_EQ(wrist["keyingSet"].get<Names>(), (Names{"wrist_ctrl"}));
  EXPECT_EQ(wrist["times"].get<Frames>(), Frames{});
  EXPECT_EQ(key_frames(path("k.rigel"), "elbow"), (Frames{4})) << "a joint stands for its control";

  // Back to character, keys again cover the arm; the text output names the scope.
  const CliRun set = ok({"ephemeral", "scope", path("k.rigel"), "--rig", "ephemeralRig", "--set", "character", "-o",
                         path("c.rigel")});
  EXPECT_TRUE(contains(set.err, "ephemeralRig: keying scope: character; wrote")) << set;
  EXPECT_EQ(key_frames(path("c.rigel"), "wrist_ctrl"), (Frames{4}));
}

TEST_F(CliKeys, key__time_in_seconds_and_several_controls) {
  const Json k = json({"ephemeral", "key", rig(), "--control", "elbow_ctrl,sword_ctrl", "--time", "0.5", "-o", path("k.rigel")});
  EXPECT_EQ(k["frame"], 12.0);
  EXPECT_EQ(k["keyed"].get<Names>(), (Names{"shoulder_ctrl", "elbow_ctrl", "wrist_ctrl", "hand_ctrl", "sword_ctrl"}));
  EXPECT_EQ(key_frames(path("k.rigel"), "sword"), (Frames{12}));
}

TEST_F(CliKeys, key__delete_removes_the_keys_at_the_frame) {
  const std::string keyed = keyed_0_10();
  const Json d = json({"ephemeral", "key", keyed, "--control", "hand_ctrl", "--frame", "10", "--delete", "-o", path("d.rigel")});
  EXPECT_EQ(d["keyed"].get<Names>(), kArmControls);
  EXPECT_EQ(d["times"].get<Frames>(), (Frames{0}));
  const CliRun again = fails({"ephemeral", "key", path("d.rigel"), "--control", "hand_ctrl", "--frame", "10", "--delete",
                              "-o", path("again.rigel")},
                             1, path("again.rigel"));
  EXPECT_TRUE(contains(again.err, "no key at frame 10")) << again;
  // The last key goes with its curves; the channels keep the pose and are free again.
  const CliRun last = ok({"ephemeral", "key", path("d.rigel"), "--control", "hand_ctrl", "--frame", "0", "--delete", "-o",
                          path("e.rigel")});
  EXPECT_TRUE(contains(last.err, "deleted the keys of 4 controls at frame 0")) << last;
  EXPECT_TRUE(contains(last.err, "key frames: none")) << last;
  EXPECT_EQ(key_frames(path("e.rigel"), "hand_ctrl"), Frames{});
  const Json file = Json::parse(read_text(path("e.rigel")));  // named: a range-for must not iterate a temporary's member
  for (const Json& n : file["nodes"])
    EXPECT_EQ(n["type"].get<std::string>().find("animCurve"), std::string::npos) << n["name"];
  EXPECT_V3_NEAR(v3(eval(path("e.rigel"), 0)["wrist"]["t"]), 2, 1, 0, 1e-12);
  ok({"pose", path("e.rigel"), "--control", "elbow_ctrl", "--mode", "forward", "--rotate", "0,0,90", "--frame", "7", "-o",
      path("posed.rigel")});
}

// ---- pose with keys --------------------------------------------------------------

TEST_F(CliKeys, pose__on_a_key_edits_that_key_only) {
  const std::string keyed = keyed_0_10();
  const Json j = json({"pose", keyed, "--control", "elbow_ctrl", "--mode", "forward", "--rotate", "0,0,90", "--frame",
                       "10", "-o", path("out.rigel")});
  EXPECT_EQ(j["keyScope"], Json::parse(R"({"ephemeralRig": "character"})"));
  EXPECT_EQ(j["keyed"].get<Names>(), kArmControls);
  EXPECT_V3_NEAR(v3(j["moved"]["wrist_ctrl"]["t"]), 1, 2, 0, 1e-12);
  EXPECT_V3_NEAR(v3(eval(path("out.rigel"), 10)["wrist"]["t"]), 1, 2, 0, 1e-12);
  EXPECT_V3_NEAR(v3(eval(path("out.rigel"), 0)["wrist"]["t"]), 2, 1, 0, 1e-12);  // the other key is unchanged
  EXPECT_EQ(key_frames(path("out.rigel"), "elbow_ctrl"), (Frames{0, 10}));
}

TEST_F(CliKeys, pose__between_keys_needs_auto_key) {
  const std::string keyed = keyed_0_10();
  const std::vector<std::string> args = {"pose", keyed, "--control", "elbow_ctrl", "--mode", "forward", "--rotate",
                                         "0,0,90", "--frame", "5", "-o", path("out.rigel")};
  const CliRun refused = fails(args, 1, path("out.rigel"));
  EXPECT_TRUE(contains(refused.err, "auto-key")) << refused;
  EXPECT_TRUE(contains(refused.err, "elbow_ctrl.rotate")) << refused;
  EXPECT_TRUE(contains(refused.err, "frame 5")) << refused;
  EXPECT_TRUE(contains(refused.err, "note: --auto-key keys the character at frame 5 first")) << refused;

  std::vector<std::string> with = args;
  with.push_back("--auto-key");
  const Json j = json(with);
  EXPECT_EQ(j["keyed"].get<Names>(), kArmControls);
  EXPECT_EQ(key_frames(path("out.rigel"), "shoulder_ctrl"), (Frames{0, 5, 10}));
  EXPECT_V3_NEAR(v3(eval(path("out.rigel"), 5)["wrist"]["t"]), 1, 2, 0, 1e-12);
  EXPECT_V3_NEAR(v3(eval(path("out.rigel"), 0)["wrist"]["t"]), 2, 1, 0, 1e-12);
  EXPECT_V3_NEAR(v3(eval(path("out.rigel"), 10)["wrist"]["t"]), 2, 1, 0, 1e-12);
}

TEST_F(CliKeys, pose__key_keys_the_new_pose_and_text_shows_the_scope) {
  // No keys yet: the pose is free, and --key keys the whole arm there.
  const Json j = json({"pose", rig(), "--control", "elbow_ctrl", "--mode", "forward", "--rotate", "0,0,90", "--frame",
                       "3", "--key", "-o", path("out.rigel")});
  EXPECT_EQ(j["keyed"].get<Names>(), kArmControls);
  EXPECT_EQ(key_frames(path("out.rigel"), "hand"), (Frames{3}));
  EXPECT_EQ(key_frames(path("out.rigel"), "sword_ctrl"), Frames{});
  EXPECT_V3_NEAR(v3(eval(path("out.rigel"), 20)["wrist"]["t"]), 1, 2, 0, 1e-12);  // one key holds the pose

  const CliRun text = ok({"pose", rig(), "--control", "sword", "--mode", "forward", "--translate", "0,1,0", "--key", "-o",
                          path("text.rigel")});
  EXPECT_TRUE(text.out.empty()) << text;
  EXPECT_TRUE(contains(text.err, "keying scope: swordRig=character; keyed 1 control; 1 control has a key at frame 0")) << text;
  // Without --key nothing is keyed, and the scope is still shown.
  const Json free = json({"pose", rig(), "--control", "hand", "--mode", "forward", "--translate", "0,1,0", "-o", path("free.rigel")});
  EXPECT_EQ(free["keyScope"], Json::parse(R"({"ephemeralRig": "character"})"));
  EXPECT_EQ(free["keyed"], Json::array());
}

// ---- merge and unmerge -----------------------------------------------------------

TEST_F(CliKeys, merge__a_carried_prop_follows_the_arm_until_unmerged) {
  const Json m = json({"ephemeral", "merge", rig(), "--rigs", "ephemeralRig,swordRig", "--carrier", "hand_ctrl",
                       "--carried", "swordRig", "-o", path("m.rigel")});
  EXPECT_EQ(m["merged"].get<Names>(), (Names{"ephemeralRig", "swordRig"}));
  EXPECT_EQ(m["carriers"], Json::parse(R"({"swordRig": "hand_ctrl"})"));

  // Forward from the elbow: the sword (at 2.5, 1, 0) turns 90 degrees about
  // z around the elbow (1, 1, -0.5) with the hand.
  const Json j = json({"pose", path("m.rigel"), "--control", "elbow_ctrl", "--mode", "forward", "--rotate", "0,0,90", "-o",
                       path("out.rigel")});
  ASSERT_TRUE(j["moved"].contains("sword_ctrl")) << j;
  EXPECT_V3_NEAR(v3(j["moved"]["sword_ctrl"]["t"]), 1, 2.5, 0, 1e-12);
  EXPECT_V3_NEAR(v3(eval(path("out.rigel"), 0)["sword"]["t"]), 1, 2.5, 0, 1e-12);

  // Merged characters share one keying group.
  const Json k = json({"ephemeral", "key", path("m.rigel"), "--control", "elbow", "--frame", "0", "-o", path("k.rigel")});
  EXPECT_EQ(k["keyed"].get<Names>(), (Names{"shoulder_ctrl", "elbow_ctrl", "wrist_ctrl", "hand_ctrl", "sword_ctrl"}));

  const Json u = json({"ephemeral", "unmerge", path("m.rigel"), "--rig", "swordRig", "-o", path("u.rigel")});
  EXPECT_EQ(u["unmergedFrom"].get<Names>(), (Names{"ephemeralRig"}));
  const Json after = json({"pose", path("u.rigel"), "--control", "elbow_ctrl", "--mode", "forward", "--rotate", "0,0,90",
                           "-o", path("out2.rigel")});
  EXPECT_FALSE(after["moved"].contains("sword_ctrl")) << after;
  EXPECT_V3_NEAR(v3(eval(path("out2.rigel"), 0)["sword"]["t"]), 2.5, 1, 0, 1e-12);
  const CliRun again = ok({"ephemeral", "unmerge", path("u.rigel"), "--rig", "swordRig", "-o", path("u2.rigel")});
  EXPECT_TRUE(contains(again.err, "swordRig was not merged")) << again;
}

TEST_F(CliKeys, merge__without_a_carrier_body_mode_moves_both) {
  const CliRun m = ok({"ephemeral", "merge", rig(), "--rigs", "ephemeralRig,swordRig", "-o", path("m.rigel")});
  EXPECT_TRUE(contains(m.err, "merged ephemeralRig, swordRig; wrote")) << m;
  const Json j = json({"pose", path("m.rigel"), "--control", "shoulder", "--mode", "body", "--translate", "0,1,0", "-o",
                       path("out.rigel")});
  EXPECT_V3_NEAR(v3(j["moved"]["sword_ctrl"]["t"]), 2.5, 2, 0, 1e-12);
  const Json forward = json({"pose", path("m.rigel"), "--control", "elbow", "--mode", "forward", "--rotate", "0,0,90", "-o",
                             path("out.rigel")});
  EXPECT_FALSE(forward["moved"].contains("sword_ctrl")) << "no carrier: forward leaves the sword";
}

// ---- errors ------------------------------------------------------------------------

TEST_F(CliKeys, errors__unknown_names_exit_1_naming_the_option_and_name) {
  const std::string out = path("out.rigel");
  CliRun r = fails({"ephemeral", "key", rig(), "--control", "elbow_ctrl,knee", "-o", out}, 1, out);
  EXPECT_TRUE(contains(r.err, "--control: no node named 'knee'")) << r;
  r = fails({"ephemeral", "key", rig(), "--control", "swordRig", "-o", out}, 1, out);
  EXPECT_TRUE(contains(r.err, "--control: 'swordRig' is not a control of an ephemeral rig")) << r;
  r = fails({"ephemeral", "keys", rig(), "--control", "knee"}, 1, out);
  EXPECT_TRUE(contains(r.err, "--control: no node named 'knee'")) << r;
  r = fails({"ephemeral", "scope", rig(), "--rig", "bodyRig"}, 1, out);
  EXPECT_TRUE(contains(r.err, "--rig: no ephemeral rig named 'bodyRig' (rigs: ephemeralRig, swordRig)")) << r;
  r = fails({"ephemeral", "scope", rig(), "--rig", "elbow_ctrl", "--set", "controls", "-o", out}, 1, out);
  EXPECT_TRUE(contains(r.err, "--rig: 'elbow_ctrl' is not an ephemeralRig node")) << r;
  r = fails({"ephemeral", "merge", rig(), "--rigs", "ephemeralRig,shieldRig", "-o", out}, 1, out);
  EXPECT_TRUE(contains(r.err, "--rigs: no ephemeral rig named 'shieldRig'")) << r;
  r = fails({"ephemeral", "merge", rig(), "--rigs", "ephemeralRig,swordRig", "--carrier", "palm", "--carried", "swordRig",
             "-o", out},
            1, out);
  EXPECT_TRUE(contains(r.err, "--carrier: no node named 'palm'")) << r;
  r = fails({"ephemeral", "merge", rig(), "--rigs", "ephemeralRig,swordRig", "--carrier", "hand", "--carried", "shieldRig",
             "-o", out},
            1, out);
  EXPECT_TRUE(contains(r.err, "--carried: no ephemeral rig named 'shieldRig'")) << r;
  r = fails({"ephemeral", "unmerge", rig(), "--rig", "shieldRig", "-o", out}, 1, out);
  EXPECT_TRUE(contains(r.err, "--rig: no ephemeral rig named 'shieldRig'")) << r;
}

TEST_F(CliKeys, errors__invalid_edits_exit_1_with_the_librarys_message) {
  const std::string out = path("out.rigel");
  // A carrier of the carried character itself.
  CliRun r = fails({"ephemeral", "merge", rig(), "--rigs", "ephemeralRig,swordRig", "--carrier", "sword_ctrl", "--carried",
                    "swordRig", "-o", out},
                   1, out);
  EXPECT_TRUE(contains(r.err, "--carrier")) << r;
  EXPECT_TRUE(contains(r.err, "belongs to the carried character itself")) << r;
  // Deleting where there is no key.
  r = fails({"ephemeral", "key", rig(), "--control", "elbow_ctrl", "--frame", "3", "--delete", "-o", out}, 1, out);
  EXPECT_TRUE(contains(r.err, "no key at frame 3")) << r;
  // A scene without an ephemeral rig.
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"ephemeral", "key", scene(), "--control", "elbow", "-o", out},
        std::vector<std::string>{"ephemeral", "keys", scene(), "--control", "elbow"},
        std::vector<std::string>{"ephemeral", "scope", scene(), "--rig", "ephemeralRig"},
        std::vector<std::string>{"ephemeral", "unmerge", scene(), "--rig", "ephemeralRig", "-o", out}}) {
    r = fails(args, 1, out);
    EXPECT_TRUE(contains(r.err, "no ephemeral rig; run `rigel ephemeral setup")) << r;
  }
}

TEST_F(CliKeys, errors__usage_errors_exit_2) {
  const std::string out = path("out.rigel");
  CliRun r = fails({"ephemeral", "key", rig(), "--control", "elbow_ctrl", "--frame", "nan", "-o", out}, 2, out);
  EXPECT_TRUE(contains(r.err, "--frame must be a finite number")) << r;
  fails({"ephemeral", "key", rig(), "--control", "elbow_ctrl", "--frame", "1", "--time", "1", "-o", out}, 2, out);
  fails({"ephemeral", "key", rig(), "-o", out}, 2, out);                        // --control is required
  fails({"ephemeral", "key", rig(), "--control", "elbow_ctrl"}, 2, out);        // so is -o
  fails({"ephemeral", "keys", rig()}, 2, out);                                  // and --control
  r = fails({"ephemeral", "scope", rig(), "--rig", "ephemeralRig", "--set", "everything", "-o", out}, 2, out);
  EXPECT_TRUE(contains(r.err, "--set 'everything': expected character or controls")) << r;
  r = fails({"ephemeral", "scope", rig(), "--rig", "ephemeralRig", "--set", "controls"}, 2, out);
  EXPECT_TRUE(contains(r.err, "--set needs -o")) << r;
  r = fails({"ephemeral", "scope", rig(), "--rig", "ephemeralRig", "-o", out}, 2, out);
  EXPECT_TRUE(contains(r.err, "-o applies with --set only")) << r;
  fails({"ephemeral", "scope", rig()}, 2, out);  // --rig is required
  r = fails({"ephemeral", "merge", rig(), "--rigs", "ephemeralRig", "-o", out}, 2, out);
  EXPECT_TRUE(contains(r.err, "--rigs: name two rigs or more")) << r;
  r = fails({"ephemeral", "merge", rig(), "--rigs", "ephemeralRig,swordRig", "--carrier", "hand_ctrl", "-o", out}, 2, out);
  EXPECT_TRUE(contains(r.err, "--carrier CONTROL and --carried RIG go together")) << r;
  fails({"ephemeral", "unmerge", rig(), "-o", out}, 2, out);  // --rig is required
  fails({"ephemeral", "frobnicate", rig()}, 2, out);
}

}  // namespace
}  // namespace rigel::cli
