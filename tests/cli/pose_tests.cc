// `rigel ephemeral setup` and `rigel pose` (DESIGN.md, CLI contract;
// docs/EPHEMERAL.md for what each mode does). The fixture is a small arm
// written by the test: shoulder (a root at y = 1) -> elbow -> wrist -> hand,
// bent in the XZ plane, every joint unrotated, so the answers can be worked
// out by hand.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "../io/io_test_util.h"
#include "cli_test_util.h"

namespace rigel::cli {
namespace {

using namespace rigel::cli::testing;  // NOLINT: the CLI runner
using Json = nlohmann::ordered_json;  // keeps the printed key order
namespace fs = std::filesystem;

constexpr const char* kArm = R"({
  "rigel": "scene", "version": 1, "fps": 24, "time": 0,
  "nodes": [
    {"name": "shoulder", "type": "joint", "attrs": {"translate": [0, 1, 0]}},
    {"name": "elbow", "type": "joint", "parent": "shoulder", "attrs": {"translate": [1, 0, -0.5]}},
    {"name": "wrist", "type": "joint", "parent": "elbow", "attrs": {"translate": [1, 0, 0.5]}},
    {"name": "hand", "type": "joint", "parent": "wrist", "attrs": {"translate": [0.25, 0, 0]}}
  ],
  "connections": []
})";


// The arm, and the arm with its ephemeral rig (made by the CLI), in a fresh folder.
class CliPose : public ::testing::Test {
 protected:
  void SetUp() override {
    rigel::io::testing::write_text(arm(), kArm);
    setup_run_ = rigel({"ephemeral", "setup", arm(), "-o", rig(), "--json"});
    ASSERT_TRUE(exited_with(setup_run_, 0)) << setup_run_;
  }
  std::string path(const std::string& name) const { return (dir_.path() / name).string(); }
  std::string arm() const { return path("arm.rigel"); }
  std::string rig() const { return path("rig.rigel"); }
  std::string out() const { return path("out.rigel"); }

  // `rigel pose RIG -o OUT --json ARGS...`, which must succeed; its JSON.
  Json pose(std::vector<std::string> args) {
    std::vector<std::string> words = {"pose", rig(), "-o", out(), "--json"};
    words.insert(words.end(), args.begin(), args.end());
    const CliRun r = rigel(words);
    EXPECT_TRUE(exited_with(r, 0)) << r;
    if (!exited_with(r, 0)) return Json::object();
    return Json::parse(r.out);
  }
  // World transforms of `rigel eval FILE --json`.
  Json eval(const std::string& file) {
    const CliRun r = rigel({"eval", file, "--json"});
    EXPECT_TRUE(exited_with(r, 0)) << r;
    if (!exited_with(r, 0)) return Json::object();
    return Json::parse(r.out)["nodes"];
  }

  TempDir dir_;
  CliRun setup_run_;
};

// name -> stored attrs of every node of a .rigel file.
std::map<std::string, Json> stored_attrs(const std::string& file) {
  std::map<std::string, Json> out;
  const Json scene = Json::parse(read_text(file));
  for (const Json& n : scene["nodes"]) out[n["name"].get<std::string>()] = n.value("attrs", Json::object());
  return out;
}

std::vector<std::string> keys(const Json& object) {
  std::vector<std::string> names;
  for (auto it = object.begin(); it != object.end(); ++it) names.push_back(it.key());
  return names;
}

using Names = std::vector<std::string>;

// ---- ephemeral setup ------------------------------------------------------------

TEST_F(CliPose, setup__one_control_per_joint_and_a_rig) {
  const Json j = Json::parse(setup_run_.out);
  EXPECT_EQ(j["rig"], "ephemeralRig");
  EXPECT_EQ(j["controls"].get<Names>(), (Names{"shoulder_ctrl", "elbow_ctrl", "wrist_ctrl", "hand_ctrl"}));
  EXPECT_EQ(j["joints"].get<Names>(), (Names{"shoulder", "elbow", "wrist", "hand"}));
  EXPECT_TRUE(contains(setup_run_.err, "ephemeral rig 'ephemeralRig': 4 controls")) << setup_run_;
  // The written scene loads in every command; the controls sit on their joints.
  const Json nodes = eval(rig());
  EXPECT_V3_NEAR(v3(nodes["wrist_ctrl"]["t"]), 2, 1, 0, 1e-12);
  const CliRun inspect = rigel({"inspect", rig()});
  EXPECT_TRUE(exited_with(inspect, 0)) << inspect;
  EXPECT_TRUE(contains(inspect.out, "ephemeralRig")) << inspect;
}

TEST_F(CliPose, setup__joints_suffix_and_text_summary) {
  const CliRun r = rigel({"ephemeral", "setup", arm(), "-o", out(), "--joints", "wrist,elbow", "--suffix", "_c",
                          "--shape-radius", "0.1"});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  EXPECT_TRUE(r.out.empty()) << r;
  EXPECT_TRUE(contains(r.err, "2 controls")) << r;
  const auto attrs = stored_attrs(out());
  EXPECT_TRUE(attrs.count("elbow_c") && attrs.count("wrist_c") && !attrs.count("shoulder_c")) << read_text(out());
  EXPECT_TRUE(attrs.at("wrist_c").contains("shapePoints")) << "--shape-radius draws a circle";
}

TEST_F(CliPose, setup__imports_a_gltf_character) {
  const std::string glb = (rigel::io::testing::source_dir() / "tests" / "data" / "gltf" / "RiggedSimple.glb").string();
  const CliRun r = rigel({"ephemeral", "setup", glb, "-o", out(), "--json", "--drop-animation"});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  const Json j = Json::parse(r.out);
  ASSERT_FALSE(j["controls"].empty()) << r;
  const std::string control = j["controls"][0];
  const CliRun posed = rigel({"pose", out(), "--control", control, "--mode", "forward", "--rotate", "0,0,30", "-o",
                              path("posed.rigel"), "--json"});
  ASSERT_TRUE(exited_with(posed, 0)) << posed;
  EXPECT_TRUE(Json::parse(posed.out)["moved"].contains(control)) << posed;
}

TEST_F(CliPose, setup__errors_name_the_bad_thing) {
  const CliRun unknown = rigel({"ephemeral", "setup", arm(), "-o", out(), "--joints", "elbow,knee"});
  EXPECT_TRUE(exited_with(unknown, 1)) << unknown;
  EXPECT_TRUE(contains(unknown.err, "--joints: no node named 'knee'")) << unknown;
  const CliRun twice = rigel({"ephemeral", "setup", rig(), "-o", out()});
  EXPECT_TRUE(exited_with(twice, 1)) << twice;
  EXPECT_TRUE(contains(twice.err, "already driven by a control")) << twice;
  const CliRun radius = rigel({"ephemeral", "setup", arm(), "-o", out(), "--shape-radius", "-1"});
  EXPECT_TRUE(exited_with(radius, 2)) << radius;
  EXPECT_TRUE(contains(radius.err, "--shape-radius")) << radius;
  EXPECT_FALSE(fs::exists(out()));
}

// ---- pose: modes ------------------------------------------------------------------

TEST_F(CliPose, forward__writes_the_grabbed_control_only_and_descendants_follow) {
  const Json j = pose({"--control", "elbow_ctrl", "--mode", "forward", "--rotate", "0,0,90"});
  EXPECT_EQ(j["mode"], "forward");
  EXPECT_EQ(j["frame"], 0.0);
  EXPECT_EQ(j["grabbed"].get<Names>(), (Names{"elbow_ctrl"}));
  EXPECT_EQ(keys(j["moved"]), (Names{"elbow_ctrl", "wrist_ctrl", "hand_ctrl"}));
  // The elbow turns in place; the wrist's offset (1, 0, 0.5) turns 90 degrees about z.
  EXPECT_V3_NEAR(v3(j["moved"]["elbow_ctrl"]["t"]), 1, 1, -0.5, 1e-12);
  EXPECT_V3_NEAR(v3(j["moved"]["wrist_ctrl"]["t"]), 1, 2, 0, 1e-12);
  EXPECT_V3_NEAR(v3(j["moved"]["hand_ctrl"]["t"]), 1, 2.25, 0, 1e-12);
  const double h = std::sqrt(0.5);
  const Json& q = j["moved"]["wrist_ctrl"]["q"];
  EXPECT_NEAR(q[2].get<double>(), h, 1e-12);
  EXPECT_NEAR(q[3].get<double>(), h, 1e-12);
  // In the file only elbow_ctrl changed; the joints follow through connections.
  const auto before = stored_attrs(rig()), after = stored_attrs(out());
  ASSERT_EQ(before.size(), after.size());
  for (const auto& [name, attrs] : before)
    EXPECT_EQ(attrs == after.at(name), name != "elbow_ctrl") << name << ": " << attrs << " -> " << after.at(name);
  EXPECT_V3_NEAR(v3(eval(out())["wrist"]["t"]), 1, 2, 0, 1e-12);
}

TEST_F(CliPose, forward__a_joint_name_stands_for_its_control) {
  const Json j = pose({"--control", "elbow", "--mode", "forward", "--translate", "0,0.5,0"});
  EXPECT_EQ(j["grabbed"].get<Names>(), (Names{"elbow_ctrl"}));
  EXPECT_V3_NEAR(v3(j["moved"]["hand_ctrl"]["t"]), 2.25, 1.5, 0, 1e-12);
}

TEST_F(CliPose, inverse__the_end_reaches_the_target_and_bones_keep_their_lengths) {
  const Json j = pose({"--control", "wrist_ctrl", "--mode", "inverse", "--translate", "-0.5,0.3,0"});
  const Json& moved = j["moved"];
  EXPECT_EQ(keys(moved), (Names{"shoulder_ctrl", "elbow_ctrl", "wrist_ctrl", "hand_ctrl"}));
  const V3 shoulder = v3(moved["shoulder_ctrl"]["t"]), elbow = v3(moved["elbow_ctrl"]["t"]),
           wrist = v3(moved["wrist_ctrl"]["t"]), hand = v3(moved["hand_ctrl"]["t"]);
  EXPECT_V3_NEAR(shoulder, 0, 1, 0, 1e-12);  // the chain's top turns in place
  EXPECT_V3_NEAR(wrist, 1.5, 1.3, 0, 1e-9);
  EXPECT_NEAR(dist(shoulder, elbow), std::sqrt(1.25), 1e-9);
  EXPECT_NEAR(dist(elbow, wrist), std::sqrt(1.25), 1e-9);
  EXPECT_NEAR(dist(wrist, hand), 0.25, 1e-9);
  // The file holds the same pose.
  const Json nodes = eval(out());
  EXPECT_V3_NEAR(v3(nodes["wrist"]["t"]), 1.5, 1.3, 0, 1e-9);
  EXPECT_V3_NEAR(v3(nodes["elbow"]["t"]), elbow.x, elbow.y, elbow.z, 1e-12);
}

TEST_F(CliPose, suspended__children_keep_their_world) {
  const Json j = pose({"--control", "elbow_ctrl", "--mode", "suspended", "--translate", "0,0.5,0"});
  EXPECT_EQ(keys(j["moved"]), (Names{"elbow_ctrl"}));
  EXPECT_V3_NEAR(v3(j["moved"]["elbow_ctrl"]["t"]), 1, 1.5, -0.5, 1e-12);
  const Json nodes = eval(out());
  EXPECT_V3_NEAR(v3(nodes["wrist"]["t"]), 2, 1, 0, 1e-12);
  EXPECT_V3_NEAR(v3(nodes["hand"]["t"]), 2.25, 1, 0, 1e-12);
}

TEST_F(CliPose, body__scales_about_the_pivot) {
  // Pivot at the world origin: every control's position doubles, none turns.
  Json j = pose({"--control", "hand_ctrl", "--mode", "body", "--scale", "2,2,2", "--pivot", "0,0,0"});
  EXPECT_EQ(keys(j["moved"]), (Names{"shoulder_ctrl", "elbow_ctrl", "wrist_ctrl", "hand_ctrl"}));
  EXPECT_V3_NEAR(v3(j["moved"]["shoulder_ctrl"]["t"]), 0, 2, 0, 1e-12);
  EXPECT_V3_NEAR(v3(j["moved"]["elbow_ctrl"]["t"]), 2, 2, -1, 1e-12);
  EXPECT_V3_NEAR(v3(j["moved"]["hand_ctrl"]["t"]), 4.5, 2, 0, 1e-12);
  EXPECT_NEAR(j["moved"]["hand_ctrl"]["q"][3].get<double>(), 1.0, 1e-12);
  // Default pivot: --control's own position, so the shoulder stays.
  j = pose({"--control", "shoulder", "--mode", "body", "--scale", "2,2,2"});
  EXPECT_FALSE(j["moved"].contains("shoulder_ctrl")) << j;
  EXPECT_V3_NEAR(v3(j["moved"]["elbow_ctrl"]["t"]), 2, 1, -1, 1e-12);
}

TEST_F(CliPose, multi_select__every_grabbed_control_applies_the_motion) {
  // Forward: each grabbed control turns about its own pivot, after being
  // carried by the grabbed control above it (the curl of docs/EPHEMERAL.md).
  const Json j = pose({"--control", "wrist_ctrl", "--select", "elbow_ctrl", "--mode", "forward", "--rotate", "0,0,10"});
  EXPECT_EQ(j["grabbed"].get<Names>(), (Names{"elbow_ctrl", "wrist_ctrl"}));
  const double pi = std::acos(-1.0);
  EXPECT_NEAR(j["moved"]["elbow_ctrl"]["q"][2].get<double>(), std::sin(10 * pi / 360), 1e-12);
  EXPECT_NEAR(j["moved"]["wrist_ctrl"]["q"][2].get<double>(), std::sin(20 * pi / 360), 1e-12);
  // Suspended: both move by the translation, in world.
  const Json s = pose({"--control", "elbow", "--select", "hand", "--mode", "suspended", "--translate", "0,0,1"});
  EXPECT_EQ(keys(s["moved"]), (Names{"elbow_ctrl", "hand_ctrl"}));
  EXPECT_V3_NEAR(v3(s["moved"]["hand_ctrl"]["t"]), 2.25, 1, 1, 1e-12);
}

TEST_F(CliPose, frame__sets_the_time_before_posing) {
  const Json j = pose({"--control", "elbow_ctrl", "--mode", "forward", "--translate", "0,1,0", "--frame", "12"});
  EXPECT_EQ(j["frame"], 12.0);
  EXPECT_EQ(Json::parse(read_text(out()))["time"], 0.5);
  const Json t = pose({"--control", "elbow_ctrl", "--mode", "forward", "--translate", "0,1,0", "--time", "0.25"});
  EXPECT_EQ(t["frame"], 6.0);
}

TEST_F(CliPose, text_output_and_help) {
  const CliRun r = rigel({"pose", rig(), "--control", "elbow_ctrl", "--mode", "magnet", "--translate", "0,1,0",
                          "--magnet-fraction", "0.5", "-o", out()});
  ASSERT_TRUE(exited_with(r, 0)) << r;
  EXPECT_TRUE(r.out.empty()) << r;
  EXPECT_TRUE(contains(r.err, "posed elbow_ctrl (magnet, frame 0): ")) << r;
  EXPECT_TRUE(contains(r.err, "controls moved; wrote " + out())) << r;
  const CliRun help = rigel({"pose", "--help"});
  EXPECT_TRUE(exited_with(help, 0)) << help;
  EXPECT_TRUE(contains(help.out, "Rz*Ry*Rx")) << help;
}

// ---- pose: errors ------------------------------------------------------------------

// `rigel pose RIG -o OUT ARGS...`, which must fail with `code` (writing nothing).
CliRun pose_fails(const std::string& rig, const std::string& out, std::vector<std::string> args, int code) {
  std::vector<std::string> words = {"pose", rig, "-o", out};
  words.insert(words.end(), args.begin(), args.end());
  const CliRun r = rigel(words);
  EXPECT_TRUE(exited_with(r, code)) << r;
  EXPECT_FALSE(fs::exists(out)) << "a failed pose writes nothing";
  EXPECT_TRUE(r.out.empty()) << r;
  return r;
}

TEST_F(CliPose, errors__unknown_names_exit_1_naming_them) {
  CliRun r = pose_fails(rig(), out(), {"--control", "knee_ctrl", "--mode", "forward"}, 1);
  EXPECT_TRUE(contains(r.err, "--control: no node named 'knee_ctrl'")) << r;
  r = pose_fails(rig(), out(), {"--control", "elbow_ctrl", "--select", "wrist_ctrl,toe", "--mode", "forward"}, 1);
  EXPECT_TRUE(contains(r.err, "--select: no node named 'toe'")) << r;
  r = pose_fails(rig(), out(), {"--control", "ephemeralRig", "--mode", "forward"}, 1);
  EXPECT_TRUE(contains(r.err, "'ephemeralRig' is not a control of an ephemeral rig")) << r;
}

TEST_F(CliPose, errors__scene_without_a_rig_exits_1) {
  const CliRun r = pose_fails(arm(), out(), {"--control", "elbow", "--mode", "forward"}, 1);
  EXPECT_TRUE(contains(r.err, "no ephemeral rig")) << r;
  EXPECT_TRUE(contains(r.err, "rigel ephemeral setup")) << r;
}

TEST_F(CliPose, errors__keyed_channel_exits_1_with_the_sessions_message) {
  // RiggedSimple's animation moves onto the controls (no --drop-animation).
  const std::string glb = (rigel::io::testing::source_dir() / "tests" / "data" / "gltf" / "RiggedSimple.glb").string();
  const std::string keyed = path("keyed.rigel");
  const CliRun setup = rigel({"ephemeral", "setup", glb, "-o", keyed, "--json"});
  ASSERT_TRUE(exited_with(setup, 0)) << setup;
  const std::string control = Json::parse(setup.out)["controls"][0];
  const CliRun r = pose_fails(keyed, out(), {"--control", control, "--mode", "forward", "--rotate", "0,0,30"}, 1);
  EXPECT_TRUE(contains(r.err, "drag")) << r;
  EXPECT_TRUE(contains(r.err, control)) << r;
}

TEST_F(CliPose, errors__usage_errors_exit_2) {
  CliRun r = pose_fails(rig(), out(), {"--control", "elbow_ctrl", "--mode", "ik"}, 2);
  EXPECT_TRUE(contains(r.err, "--mode 'ik'")) << r;
  EXPECT_TRUE(contains(r.err, "forward, suspended, pseudo-inverse, pseudo-inverse-length, inverse, magnet, magnet-radius, body")) << r;
  r = pose_fails(rig(), out(), {"--control", "elbow_ctrl", "--mode", "forward", "--translate", "1,2"}, 2);
  EXPECT_TRUE(contains(r.err, "--translate '1,2'")) << r;
  r = pose_fails(rig(), out(), {"--control", "elbow_ctrl", "--mode", "forward", "--rotate", "0,x,0"}, 2);
  EXPECT_TRUE(contains(r.err, "--rotate '0,x,0'")) << r;
  r = pose_fails(rig(), out(), {"--control", "elbow_ctrl", "--mode", "forward", "--frame", "nan"}, 2);
  EXPECT_TRUE(contains(r.err, "--frame")) << r;
  r = pose_fails(rig(), out(), {"--control", "elbow_ctrl", "--mode", "magnet", "--magnet-fraction", "2"}, 2);
  EXPECT_TRUE(contains(r.err, "--magnet-fraction")) << r;
  pose_fails(rig(), out(), {"--mode", "forward"}, 2);  // --control is required
}

TEST_F(CliPose, errors__scale_and_pivot_outside_body_mode_exit_2) {
  // Usage errors (exit 2), found before the scene is read.
  CliRun r = pose_fails(rig(), out(), {"--control", "elbow_ctrl", "--mode", "forward", "--scale", "2,2,2"}, 2);
  EXPECT_TRUE(contains(r.err, "--scale applies in body mode only")) << r;
  r = pose_fails(rig(), out(), {"--control", "elbow_ctrl", "--mode", "inverse", "--pivot", "0,0,0"}, 2);
  EXPECT_TRUE(contains(r.err, "--pivot applies in body mode only")) << r;
  r = pose_fails(path("missing.rigel"), out(), {"--control", "elbow_ctrl", "--mode", "inverse", "--scale", "1,2,1"}, 2);
  EXPECT_TRUE(contains(r.err, "--scale applies in body mode only")) << r;
}

}  // namespace
}  // namespace rigel::cli
