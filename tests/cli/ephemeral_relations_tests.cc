// `rigel ephemeral relations` (docs/EPHEMERAL.md, "Relations"): printing a
// rig's relations and editing them (--add, --remove, --set-kind, --group) in
// one transaction. The fixture is a 3-joint arm (shoulder at y = 1 -> elbow
// -> wrist, bent in the XZ plane, every joint unrotated) rigged by the CLI,
// plus a sword joint that is rigged only where a test needs a second rig.

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <sstream>
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
    {"name": "sword", "type": "joint", "attrs": {"translate": [2.5, 1, 0]}}
  ],
  "connections": []
})";

using Names = std::vector<std::string>;

// "kind from to" of every relation of a {"rig", "relations"} object, sorted.
Names triples(const Json& rig) {
  Names out;
  for (const Json& r : rig["relations"])
    out.push_back(r["kind"].get<std::string>() + " " + r["from"].get<std::string>() + " " + r["to"].get<std::string>());
  std::sort(out.begin(), out.end());
  return out;
}

// The defaults of the 3-joint arm: forward down the chain, inverse up it.
const Names kDefaults = {"forward elbow_ctrl wrist_ctrl", "forward shoulder_ctrl elbow_ctrl",
                         "inverse elbow_ctrl shoulder_ctrl", "inverse wrist_ctrl elbow_ctrl"};

class CliRelations : public ::testing::Test {
 protected:
  void SetUp() override {
    rigel::io::testing::write_text(scene(), kArmAndSword);
    const CliRun r = rigel({"ephemeral", "setup", scene(), "--joints", "shoulder,elbow,wrist", "-o", rig()});
    ASSERT_TRUE(exited_with(r, 0)) << r;
  }
  std::string path(const std::string& name) const { return (dir_.path() / name).string(); }
  std::string scene() const { return path("scene.rigel"); }
  std::string rig() const { return path("rig.rigel"); }
  std::string out() const { return path("out.rigel"); }

  // `rigel ephemeral relations ARGS...`, which must succeed.
  CliRun relations(std::vector<std::string> args) {
    args.insert(args.begin(), {"ephemeral", "relations"});
    const CliRun r = rigel(args);
    EXPECT_TRUE(exited_with(r, 0)) << r;
    return r;
  }
  // The relations of FILE's only rig (--json).
  Names listed(const std::string& file) {
    const CliRun r = relations({file, "--json"});
    if (!exited_with(r, 0)) return {};
    return triples(Json::parse(r.out));
  }
  // `rigel ephemeral relations RIG -o OUT ARGS...`, which must fail with
  // `code`, writing nothing and printing nothing on stdout.
  CliRun fails(std::vector<std::string> args, int code) {
    std::vector<std::string> words = {"ephemeral", "relations", rig(), "-o", out()};
    words.insert(words.end(), args.begin(), args.end());
    const CliRun r = rigel(words);
    EXPECT_TRUE(exited_with(r, code)) << r;
    EXPECT_FALSE(fs::exists(out())) << "a failed edit writes nothing";
    EXPECT_TRUE(r.out.empty()) << r;
    return r;
  }

  TempDir dir_;
};

// ---- listing ---------------------------------------------------------------------

TEST_F(CliRelations, list__defaults_on_a_3_joint_arm_forward_down_inverse_up) {
  const CliRun text = relations({rig()});
  std::istringstream lines(text.out);
  Names got;
  for (std::string line; std::getline(lines, line);) got.push_back(line);
  std::sort(got.begin(), got.end());
  EXPECT_EQ(got, (Names{"forward  elbow_ctrl -> wrist_ctrl", "forward  shoulder_ctrl -> elbow_ctrl",
                        "inverse  elbow_ctrl -> shoulder_ctrl", "inverse  wrist_ctrl -> elbow_ctrl"}))
      << text;
  EXPECT_TRUE(text.err.empty()) << "listing reads only, silently: " << text;

  const CliRun json = relations({rig(), "--json", "--rig", "ephemeralRig"});
  const Json j = Json::parse(json.out);
  EXPECT_EQ(j["rig"], "ephemeralRig");
  EXPECT_EQ(j["relations"][0].size(), 3u) << "each relation is {kind, from, to}: " << json;
  EXPECT_EQ(triples(j), kDefaults);
}

TEST_F(CliRelations, list__several_rigs_without_rig_lists_every_rig) {
  const std::string two = path("two.rigel");
  const CliRun setup = rigel({"ephemeral", "setup", rig(), "--joints", "sword", "--rig-name", "swordRig", "-o", two});
  ASSERT_TRUE(exited_with(setup, 0)) << setup;
  const CliRun all = relations({two, "--json"});
  std::istringstream lines(all.out);
  std::vector<Json> rigs;
  for (std::string line; std::getline(lines, line);) rigs.push_back(Json::parse(line));
  ASSERT_EQ(rigs.size(), 2u) << "one JSON object a line, one per rig: " << all;
  EXPECT_EQ(rigs[0]["rig"], "ephemeralRig");
  EXPECT_EQ(triples(rigs[0]), kDefaults);
  EXPECT_EQ(rigs[1]["rig"], "swordRig");
  EXPECT_TRUE(rigs[1]["relations"].empty()) << all;
  const CliRun text = relations({two});
  EXPECT_TRUE(contains(text.out, "ephemeralRig:\n") && contains(text.out, "swordRig:\n")) << text;
  const CliRun one = relations({two, "--rig", "swordRig", "--json"});
  EXPECT_EQ(one.out, "{\"rig\":\"swordRig\",\"relations\":[]}\n");

  // A control of another rig is refused by the library: exit 1, nothing written.
  const CliRun other = rigel({"ephemeral", "relations", two, "--add", "pair:wrist_ctrl:sword_ctrl", "-o", out()});
  EXPECT_TRUE(exited_with(other, 1)) << other;
  EXPECT_TRUE(contains(other.err, "--add 'pair:wrist_ctrl:sword_ctrl': relation: 'sword_ctrl' belongs to another rig"))
      << other;
  EXPECT_FALSE(fs::exists(out()));
}

// ---- editing ---------------------------------------------------------------------

TEST_F(CliRelations, add__a_pair_relation_and_a_group) {
  const CliRun r = relations({rig(), "-o", out(), "--add", "pair:shoulder_ctrl:wrist", "--group", "elbow,wrist_ctrl",
                              "--json"});
  Names want = kDefaults;
  for (const char* t : {"pair shoulder_ctrl wrist_ctrl", "pair elbow_ctrl wrist_ctrl", "pair wrist_ctrl elbow_ctrl"})
    want.push_back(t);
  std::sort(want.begin(), want.end());
  EXPECT_EQ(triples(Json::parse(r.out)), want) << "--json lists the relations after the edits: " << r;
  EXPECT_EQ(listed(out()), want) << "the written scene holds them";
  EXPECT_EQ(listed(rig()), kDefaults) << "the input is untouched";
  EXPECT_TRUE(contains(r.err, "1 added, 0 removed, 0 changed, 1 group added; ephemeralRig (7 relations); wrote " + out()))
      << r;
}

TEST_F(CliRelations, remove__a_default_forward_relation_stops_fk_there) {
  relations({rig(), "-o", out(), "--remove", "forward:shoulder_ctrl:elbow_ctrl"});
  EXPECT_EQ(listed(out()), (Names{"forward elbow_ctrl wrist_ctrl", "inverse elbow_ctrl shoulder_ctrl",
                                  "inverse wrist_ctrl elbow_ctrl"}));
  // The shoulder turns 90 degrees about z; the elbow keeps its world matrix
  // (it would swing up to (0, 2, -0.5) with the relation).
  const auto posed = [&](const std::string& file) {
    const CliRun r = rigel({"pose", file, "--control", "shoulder", "--mode", "forward", "--rotate", "0,0,90", "-o",
                            path("posed.rigel"), "--json"});
    EXPECT_TRUE(exited_with(r, 0)) << r;
    return Json::parse(r.out)["moved"];
  };
  const Json with = posed(rig());
  EXPECT_TRUE(with.contains("elbow_ctrl")) << "with the relation the elbow follows: " << with;
  const Json without = posed(out());
  EXPECT_TRUE(without.contains("shoulder_ctrl")) << without;
  EXPECT_FALSE(without.contains("elbow_ctrl")) << "without it the elbow stays: " << without;
  EXPECT_FALSE(without.contains("wrist_ctrl")) << without;
  const CliRun eval = rigel({"eval", path("posed.rigel"), "--json"});
  ASSERT_TRUE(exited_with(eval, 0)) << eval;
  const Json elbow = Json::parse(eval.out)["nodes"]["elbow"]["t"];
  EXPECT_NEAR(elbow[0].get<double>(), 1.0, 1e-9);
  EXPECT_NEAR(elbow[1].get<double>(), 1.0, 1e-9);
  EXPECT_NEAR(elbow[2].get<double>(), -0.5, 1e-9);
}

TEST_F(CliRelations, set_kind__changes_a_relations_kind) {
  const CliRun r = relations({rig(), "-o", out(), "--set-kind", "forward:elbow:wrist=magnet", "--json"});
  EXPECT_EQ(triples(Json::parse(r.out)), (Names{"forward shoulder_ctrl elbow_ctrl", "inverse elbow_ctrl shoulder_ctrl",
                                                "inverse wrist_ctrl elbow_ctrl", "magnet elbow_ctrl wrist_ctrl"}))
      << r;
}

TEST_F(CliRelations, edits__apply_in_command_line_order) {
  // Add then remove: fine, back to the defaults. Remove then add: the remove
  // finds nothing.
  relations({rig(), "-o", out(), "--add", "magnet:shoulder:wrist", "--remove", "magnet:shoulder:wrist"});
  EXPECT_EQ(listed(out()), kDefaults);
  fs::remove(out());
  const CliRun r = fails({"--remove", "magnet:shoulder:wrist", "--add", "magnet:shoulder:wrist"}, 1);
  EXPECT_TRUE(contains(r.err, "--remove 'magnet:shoulder:wrist': relation: no such relation")) << r;
}

TEST_F(CliRelations, names_with_colons_split_where_both_ends_exist) {
  rigel::io::testing::write_text(scene(), R"({"rigel": "scene", "version": 1, "fps": 24, "time": 0, "nodes": [
    {"name": "mixamorig:Arm", "type": "joint"},
    {"name": "mixamorig:Hand", "type": "joint", "parent": "mixamorig:Arm", "attrs": {"translate": [1, 0, 0]}}],
    "connections": []})");
  const CliRun setup = rigel({"ephemeral", "setup", scene(), "-o", rig()});
  ASSERT_TRUE(exited_with(setup, 0)) << setup;
  const CliRun r = relations({rig(), "-o", out(), "--add", "pair:mixamorig:Arm:mixamorig:Hand_ctrl", "--json"});
  EXPECT_TRUE(contains(r.out, R"({"kind":"pair","from":"mixamorig:Arm_ctrl","to":"mixamorig:Hand_ctrl"})")) << r;
}

// ---- errors ----------------------------------------------------------------------

TEST_F(CliRelations, errors__malformed_specs_and_missing_output_exit_2) {
  CliRun r = fails({"--add", "forward:shoulder_ctrl"}, 2);
  EXPECT_TRUE(contains(r.err, "--add 'forward:shoulder_ctrl': expected KIND:FROM:TO")) << r;
  r = fails({"--remove", "sideways:shoulder:elbow"}, 2);
  EXPECT_TRUE(contains(r.err, "--remove 'sideways:shoulder:elbow': unknown kind 'sideways'; kinds: forward, inverse, pair, magnet"))
      << r;
  r = fails({"--set-kind", "forward:shoulder:elbow"}, 2);
  EXPECT_TRUE(contains(r.err, "--set-kind 'forward:shoulder:elbow': expected KIND:FROM:TO=NEWKIND")) << r;
  r = fails({"--set-kind", "forward:shoulder:elbow=up"}, 2);
  EXPECT_TRUE(contains(r.err, "unknown kind 'up'")) << r;
  r = fails({"--group", "elbow"}, 2);
  EXPECT_TRUE(contains(r.err, "--group 'elbow': a group needs two controls or more")) << r;
  r = fails({"--group", "elbow,,wrist"}, 2);
  EXPECT_TRUE(contains(r.err, "--group 'elbow,,wrist': empty control name")) << r;
  // Edits need -o; -o needs edits.
  r = rigel({"ephemeral", "relations", rig(), "--add", "pair:shoulder:wrist"});
  EXPECT_TRUE(exited_with(r, 2)) << r;
  EXPECT_TRUE(contains(r.err, "--add needs -o OUT")) << r;
  fails({}, 2);
}

TEST_F(CliRelations, errors__unknown_names_and_refusals_exit_1_naming_them) {
  CliRun r = fails({"--add", "pair:shoulder:knee"}, 1);
  EXPECT_TRUE(contains(r.err, "--add 'pair:shoulder:knee': no node named 'knee'")) << r;
  r = fails({"--add", "pair:shoulder:wrist", "--rig", "armRig"}, 1);
  EXPECT_TRUE(contains(r.err, "--rig: no ephemeral rig named 'armRig' (rigs: ephemeralRig)")) << r;
  r = fails({"--group", "elbow,sword"}, 1);
  EXPECT_TRUE(contains(r.err, "--group 'elbow,sword': 'sword' is not a control of an ephemeral rig")) << r;
  r = fails({"--add", "forward:shoulder:elbow_ctrl"}, 1);
  EXPECT_TRUE(contains(r.err, rig() + ": --add 'forward:shoulder:elbow_ctrl': relation: this forward relation exists already"))
      << r;
  r = fails({"--remove", "pair:shoulder:elbow"}, 1);
  EXPECT_TRUE(contains(r.err, "--remove 'pair:shoulder:elbow': relation: no such relation")) << r;
  r = fails({"--add", "pair:elbow:elbow_ctrl"}, 1);
  EXPECT_TRUE(contains(r.err, "--add 'pair:elbow:elbow_ctrl': relation: a control cannot drive itself")) << r;
  r = fails({"--set-kind", "forward:shoulder:elbow=magnet", "--set-kind", "forward:shoulder:elbow=pair"}, 1);
  EXPECT_TRUE(contains(r.err, "--set-kind 'forward:shoulder:elbow=pair': relation: no such relation")) << r;
  // A good edit before a refused one is undone: nothing is written.
  r = fails({"--add", "pair:shoulder:wrist", "--add", "pair:shoulder:wrist"}, 1);
  EXPECT_TRUE(contains(r.err, "exists already")) << r;
  // A scene without a rig.
  r = rigel({"ephemeral", "relations", scene()});
  EXPECT_TRUE(exited_with(r, 1)) << r;
  EXPECT_TRUE(contains(r.err, "no ephemeral rig")) << r;
}

}  // namespace
}  // namespace rigel::cli
