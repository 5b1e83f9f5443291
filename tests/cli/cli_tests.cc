// Tests of the `rigel` command line (apps/cli/main.cc): they run the built
// binary, capture stdout, stderr and the exit status, and hold it to the
// CLI contract of DESIGN.md: exit 0 on success, 1 on invalid input, 2 on
// usage errors; errors name the place on stderr and never crash; `eval
// --json` prints {"frame", "time", "nodes": {NAME: {"t", "q", "s"}}}.

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <fstream>

#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstring>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "../io/io_test_util.h"
#include "cli_test_util.h"
#include "rigel/io/report.h"
#include "rigel/io/scene_file.h"

extern char** environ;

namespace rigel::cli {
namespace {

using namespace rigel::io::testing;   // NOLINT: test helpers
using namespace rigel::cli::testing;  // NOLINT: the CLI runner
using Json = nlohmann::json;

std::string example() { return example_path().string(); }
std::string fixture(const std::string& name) { return (scenes_dir() / name).string(); }

// ---- usage ---------------------------------------------------------------------

TEST(CliUsage, help__prints_usage_and_exits_0) {
  const CliRun r = rigel({"--help"});
  EXPECT_TRUE(r.exited && r.exit_code == 0) << "--help is a success: " << r;
  EXPECT_TRUE(contains(r.out, "Usage:")) << "--help prints usage on stdout: " << r;
  EXPECT_TRUE(contains(r.out, "inspect") && contains(r.out, "eval")) << "--help lists the subcommands: " << r;
}

TEST(CliUsage, subcommand_help__prints_its_options_and_exits_0) {
  const CliRun inspect = rigel({"inspect", "--help"});
  EXPECT_TRUE(inspect.exited && inspect.exit_code == 0) << "inspect --help is a success: " << inspect;
  EXPECT_TRUE(contains(inspect.out, "SCENE") && contains(inspect.out, "--json"))
      << "inspect --help names its argument and options: " << inspect;
  const CliRun eval = rigel({"eval", "--help"});
  EXPECT_TRUE(eval.exited && eval.exit_code == 0) << "eval --help is a success: " << eval;
  for (const char* option : {"SCENE", "--frame", "--time", "--json"})
    EXPECT_TRUE(contains(eval.out, option)) << "eval --help should list " << option << ": " << eval;
}

TEST(CliUsage, usage_errors__exit_2_with_a_message_on_stderr) {
  const std::string chain = fixture("two_joint_chain.rigel");
  const std::vector<std::vector<std::string>> cases = {
      {},
      {"frobnicate"},
      {"inspect"},
      {"eval"},
      {"eval", chain, "--frame", "1", "--time", "0.5"},
      {"eval", chain, "--frame", "abc"},
      {"eval", chain, "--time", "abc"},
      {"eval", chain, "--frame"},
      {"eval", chain, "--frame", "nan"},
      {"eval", chain, "--time", "inf"},
      {"inspect", chain, "--bogus"},
      {"inspect", chain, chain},
  };
  for (const auto& args : cases) {
    std::string line = "rigel";
    for (const std::string& a : args) line += " " + a;
    SCOPED_TRACE(line);
    const CliRun r = rigel(args);
    EXPECT_TRUE(r.exited && r.exit_code == 2) << "a usage error exits 2: " << r;
    EXPECT_FALSE(r.err.empty()) << "a usage error says what is wrong on stderr: " << r;
    EXPECT_TRUE(r.out.empty()) << "a usage error prints nothing on stdout: " << r;
  }
}

// ---- inspect ---------------------------------------------------------------------

TEST(CliInspect, inspect__example_prints_the_hierarchy) {
  const CliRun r = rigel({"inspect", example()});
  ASSERT_TRUE(r.exited && r.exit_code == 0) << "inspecting the example should succeed: " << r;
  EXPECT_TRUE(r.err.empty()) << "a success prints nothing on stderr: " << r;
  EXPECT_TRUE(contains(r.out, "32 nodes (control 1, joint 31)")) << "the summary counts nodes by type: " << r;
  EXPECT_TRUE(contains(r.out, "hierarchy:\n  world_ctrl (control) role=world\n    Hips (joint)"))
      << "the hierarchy is printed indented by depth, with tags: " << r;
  EXPECT_TRUE(contains(r.out, "      LHipJoint (joint)")) << "grandchildren are indented further: " << r;
}

TEST(CliInspect, inspect_json__example_has_node_count_nodes_and_roots) {
  const CliRun r = rigel({"inspect", example(), "--json"});
  ASSERT_TRUE(r.exited && r.exit_code == 0) << "inspect --json on the example should succeed: " << r;
  const Json report = Json::parse(r.out, nullptr, false);
  ASSERT_FALSE(report.is_discarded()) << "stdout should be one JSON document: " << r;
  EXPECT_EQ(report["node_count"], 32) << "the example has 32 nodes";
  ASSERT_TRUE(report["nodes"].is_array()) << "nodes is an array";
  EXPECT_EQ(report["nodes"].size(), 32u) << "every node is listed";
  EXPECT_EQ(report["roots"], Json::array({"world_ctrl"})) << "the world control is the only root";
  Result<std::unique_ptr<scene::Scene>> loaded = io::load_scene(example_path());
  ASSERT_TRUE(loaded.is_ok()) << "the library should load the same file: " << loaded.status().message();
  EXPECT_EQ(report, Json(io::inspect_report(**loaded)))
      << "the CLI prints exactly the library's inspect report";
}

// ---- eval ----------------------------------------------------------------------------

// Checks the contract's shape and returns the names of the nodes.
std::vector<std::string> expect_eval_contract(const Json& report) {
  std::vector<std::string> keys, names;
  for (auto it = report.begin(); it != report.end(); ++it) keys.push_back(it.key());
  std::sort(keys.begin(), keys.end());
  EXPECT_EQ(keys, (std::vector<std::string>{"frame", "nodes", "time"})) << "exactly frame, time and nodes";
  EXPECT_TRUE(report["frame"].is_number() && report["time"].is_number()) << "frame and time are numbers";
  for (auto it = report["nodes"].begin(); it != report["nodes"].end(); ++it) {
    names.push_back(it.key());
    const Json& n = it.value();
    EXPECT_EQ(n.size(), 3u) << it.key() << " has exactly t, q, s";
    for (const auto& [member, size] : {std::pair<const char*, std::size_t>{"t", 3}, {"q", 4}, {"s", 3}}) {
      EXPECT_TRUE(n.contains(member) && n[member].is_array() && n[member].size() == size)
          << it.key() << "." << member << " is an array of " << size;
      if (!n.contains(member)) continue;
      for (const Json& c : n[member]) EXPECT_TRUE(c.is_number()) << it.key() << "." << member << " holds numbers";
    }
    if (n.contains("q") && n["q"].size() == 4) {
      double norm = 0;
      for (const Json& c : n["q"]) norm += c.get<double>() * c.get<double>();
      EXPECT_NEAR(norm, 1.0, 1e-9) << it.key() << ".q is a unit quaternion";
    }
  }
  return names;
}

TEST(CliEval, eval_json__example_matches_the_library) {
  const CliRun r = rigel({"eval", example(), "--json"});
  ASSERT_TRUE(r.exited && r.exit_code == 0) << "eval --json on the example should succeed: " << r;
  EXPECT_TRUE(r.err.empty()) << "a success prints nothing on stderr: " << r;
  const Json report = Json::parse(r.out, nullptr, false);
  ASSERT_FALSE(report.is_discarded()) << "stdout should be one JSON document: " << r;
  std::vector<std::string> names = expect_eval_contract(report);

  Result<std::unique_ptr<scene::Scene>> loaded = io::load_scene(example_path());
  ASSERT_TRUE(loaded.is_ok()) << "the library should load the same file: " << loaded.status().message();
  scene::Scene& s = **loaded;
  std::vector<std::string> transforms;
  for (NodeId id : s.hierarchy()) transforms.push_back(s.graph().node(id)->name());
  std::sort(names.begin(), names.end());
  std::sort(transforms.begin(), transforms.end());
  EXPECT_EQ(names, transforms) << "every transform node is present, and nothing else";

  const Json expected = Json(io::eval_report(s));
  EXPECT_EQ(report["frame"], expected["frame"]) << "the scene's frame";
  EXPECT_EQ(report["time"], expected["time"]) << "the scene's time";
  for (auto it = expected["nodes"].begin(); it != expected["nodes"].end(); ++it) {
    for (const char* member : {"t", "q", "s"}) {
      const Json& want = it.value()[member];
      const Json& got = report["nodes"][it.key()][member];
      ASSERT_EQ(got.size(), want.size()) << it.key() << "." << member;
      for (std::size_t i = 0; i < want.size(); ++i)
        EXPECT_DOUBLE_EQ(got[i].get<double>(), want[i].get<double>())
            << it.key() << "." << member << "[" << i << "] should match io::eval_report";
    }
  }
}

std::string file_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// --eval compiled (issue 19) gives what the interpreted reference gives:
// eval's JSON at frames on and between frames, the scenes bake writes
// (evaluated again), export's baked glTF byte for byte; a wrong name is a
// usage error.
TEST(CliEval, eval_bake_export__compiled_equals_interpreted) {
  TempDir dir;
  const std::string scene = example();
  for (const char* frame : {"0", "7.5", "40"}) {
    const CliRun a = rigel({"eval", scene, "--frame", frame, "--json"});
    const CliRun b = rigel({"eval", scene, "--frame", frame, "--json", "--eval", "compiled"});
    ASSERT_TRUE(exited_with(a, 0) && exited_with(b, 0)) << a << b;
    EXPECT_EQ(a.out, b.out) << "frame " << frame;
  }
  const fs::path baked_i = dir.path() / "baked_i.rigel", baked_c = dir.path() / "baked_c.rigel";
  ASSERT_TRUE(exited_with(rigel({"bake", scene, "--frames", "0:30", "-o", baked_i.string()}), 0));
  ASSERT_TRUE(exited_with(rigel({"bake", scene, "--frames", "0:30", "-o", baked_c.string(), "--eval", "compiled"}), 0));
  for (const char* frame : {"3", "12.25", "30"}) {
    const CliRun a = rigel({"eval", baked_i.string(), "--frame", frame, "--json"});
    const CliRun b = rigel({"eval", baked_c.string(), "--frame", frame, "--json"});
    ASSERT_TRUE(exited_with(a, 0) && exited_with(b, 0)) << a << b;
    EXPECT_EQ(a.out, b.out) << "the baked keys, frame " << frame;
  }
  const fs::path glb_i = dir.path() / "i.glb", glb_c = dir.path() / "c.glb";
  ASSERT_TRUE(exited_with(rigel({"export", scene, "-o", glb_i.string(), "--frames", "0:30"}), 0));
  ASSERT_TRUE(exited_with(rigel({"export", scene, "-o", glb_c.string(), "--frames", "0:30", "--eval", "compiled"}), 0));
  EXPECT_FALSE(file_bytes(glb_i).empty());
  EXPECT_EQ(file_bytes(glb_i), file_bytes(glb_c)) << "the same glTF, byte for byte";
  const CliRun bad = rigel({"eval", scene, "--eval", "fast"});
  EXPECT_TRUE(exited_with(bad, 2)) << bad;
  EXPECT_TRUE(contains(bad.err, "--eval")) << "the option named: " << bad;
}

TEST(CliEval, eval_json__frame_12_at_24_fps_is_half_a_second) {
  const CliRun r = rigel({"eval", fixture("two_joint_chain.rigel"), "--frame", "12", "--json"});
  ASSERT_TRUE(r.exited && r.exit_code == 0) << "eval --frame should succeed: " << r;
  const Json report = Json::parse(r.out, nullptr, false);
  ASSERT_FALSE(report.is_discarded()) << "stdout should be JSON: " << r;
  EXPECT_EQ(report["frame"], 12.0) << "the frame asked for";
  EXPECT_EQ(report["time"], 0.5) << "frame 12 at 24 fps is 0.5 s";
}

TEST(CliEval, eval_json__time_a_quarter_second_is_frame_6) {
  const CliRun r = rigel({"eval", fixture("two_joint_chain.rigel"), "--time", "0.25", "--json"});
  ASSERT_TRUE(r.exited && r.exit_code == 0) << "eval --time should succeed: " << r;
  const Json report = Json::parse(r.out, nullptr, false);
  ASSERT_FALSE(report.is_discarded()) << "stdout should be JSON: " << r;
  EXPECT_EQ(report["time"], 0.25) << "the time asked for";
  EXPECT_EQ(report["frame"], 6.0) << "0.25 s at 24 fps is frame 6";
}

TEST(CliEval, eval_json__chain_fixture_at_its_own_time_matches_hand_computed_values) {
  const CliRun r = rigel({"eval", fixture("two_joint_chain.rigel"), "--json"});
  ASSERT_TRUE(r.exited && r.exit_code == 0) << "eval should succeed: " << r;
  const Json report = Json::parse(r.out, nullptr, false);
  ASSERT_FALSE(report.is_discarded()) << "stdout should be JSON: " << r;
  expect_eval_contract(report);
  EXPECT_EQ(report["time"], 0.125) << "without --frame or --time, the scene's stored time";
  EXPECT_EQ(report["frame"], 3.0) << "0.125 s at 24 fps is frame 3";
  // See tests/io/report_tests.cc for the derivation: tip = (1, 4, 3), aim = (1, 4, 5).
  const Json& tip = report["nodes"]["tip"]["t"];
  const Json& aim = report["nodes"]["aim"]["t"];
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(tip[i].get<double>(), (std::vector<double>{1, 4, 3})[i], 1e-12) << "tip.t[" << i << "]";
    EXPECT_NEAR(aim[i].get<double>(), (std::vector<double>{1, 4, 5})[i], 1e-12) << "aim.t[" << i << "]";
  }
  EXPECT_EQ(report["nodes"].size(), 5u) << "joints, control, locator and mesh are all transform nodes";
}

TEST(CliEval, eval__text_output_lists_every_transform_node) {
  const CliRun r = rigel({"eval", fixture("two_joint_chain.rigel")});
  ASSERT_TRUE(r.exited && r.exit_code == 0) << "eval should succeed: " << r;
  EXPECT_TRUE(contains(r.out, "frame 3")) << "the text names the frame: " << r;
  for (const char* name : {"root", "tip", "tip_ctrl", "aim", "body"})
    EXPECT_TRUE(contains(r.out, name)) << "the text lists " << name << ": " << r;
}

// ---- invalid input -----------------------------------------------------------------------

struct BadInput {
  std::string path;
  std::vector<std::string> parts;  // substrings stderr must contain
};

std::vector<BadInput> bad_inputs() {
  const std::string truncated = fixture("malformed_truncated.rigel");
  const std::string wrong = fixture("malformed_wrong_type.rigel");
  const std::string dangling = fixture("malformed_dangling_connection.rigel");
  const std::string unknown = fixture("malformed_unknown_type.rigel");
  const std::string overflow = fixture("malformed_number_overflow.rigel");
  const std::string missing = fixture("no_such_scene.rigel");
  const std::string folder = scenes_dir().string();
  return {
      {truncated, {truncated + ":23:"}},
      {wrong, {wrong + ": nodes[1] (tip).attrs.translate:", "expected an array of 3 numbers"}},
      {dangling, {dangling + ": connections[0].src:", "no node named 'ghost'"}},
      {unknown, {unknown + ": nodes[3] (aim).type:", "unknown node type 'bone'"}},
      {overflow, {overflow + ":4:", "1e999"}},
      {missing, {missing + ": cannot open"}},
      {folder, {folder + ":", "directory"}},
  };
}

TEST(CliInvalidInput, malformed_files__exit_1_naming_the_place_with_nothing_on_stdout) {
  for (const BadInput& bad : bad_inputs()) {
    for (const std::vector<std::string>& command :
         {std::vector<std::string>{"inspect"}, {"inspect", "--json"}, {"eval"}, {"eval", "--json", "--frame", "2"}}) {
      std::vector<std::string> args = {command[0], bad.path};
      args.insert(args.end(), command.begin() + 1, command.end());
      SCOPED_TRACE("rigel " + command[0] + " " + bad.path);
      const CliRun r = rigel(args);
      ASSERT_TRUE(r.exited) << "invalid input must never crash the CLI: " << r;
      EXPECT_EQ(r.exit_code, 1) << "invalid input exits 1: " << r;
      EXPECT_TRUE(r.out.empty()) << "nothing is printed on stdout when the input is invalid: " << r;
      EXPECT_EQ(r.err.rfind("rigel: ", 0), 0u) << "stderr starts with the program name: " << r;
      for (const std::string& part : bad.parts) EXPECT_TRUE(contains(r.err, part)) << "stderr names " << part << ": " << r;
      EXPECT_FALSE(contains(r.err, "internal error")) << "bad input is not an internal error: " << r;
    }
  }
}

TEST(CliInvalidInput, empty_file__exits_1_naming_line_one) {
  TempDir dir;
  const fs::path path = dir.path() / "empty.rigel";
  write_text(path, "");
  const CliRun r = rigel({"eval", path.string(), "--json"});
  ASSERT_TRUE(r.exited) << "an empty file must not crash the CLI: " << r;
  EXPECT_EQ(r.exit_code, 1) << "an empty file is invalid input: " << r;
  EXPECT_TRUE(contains(r.err, path.string() + ":1:1:")) << "stderr names line 1: " << r;
  EXPECT_TRUE(r.out.empty()) << "nothing on stdout: " << r;
}

TEST(CliImport, import_bvh__writes_a_scene_that_evaluates_the_motion) {
  TempDir dir;
  const std::string out = (dir.path() / "walk.rigel").string();
  const std::string bvh = (source_dir() / "tests/data/bvh/cmu_131_01.bvh").string();
  const CliRun imported = rigel({"import", bvh, "-o", out});
  ASSERT_TRUE(imported.exited && imported.exit_code == 0) << "import should succeed: " << imported;
  EXPECT_TRUE(contains(imported.err, "994 frames at 120 fps")) << "import reports what it read: " << imported;
  const CliRun first = rigel({"eval", out, "--frame", "0", "--json"});
  const CliRun later = rigel({"eval", out, "--frame", "300", "--json"});
  ASSERT_TRUE(first.exited && first.exit_code == 0 && later.exited && later.exit_code == 0) << first << later;
  const Json a = Json::parse(first.out), b = Json::parse(later.out);
  EXPECT_EQ(b["time"], 2.5) << "frame 300 at 120 fps";
  EXPECT_NE(a["nodes"]["LeftKnee"]["t"], b["nodes"]["LeftKnee"]["t"]) << "the motion moves the knee between frames";
  // The bundled example was made from the same file at frame 300 by a
  // separate script (examples/make_cmu_skeleton.py): they must agree.
  const CliRun bundled = rigel({"eval", example(), "--json"});
  ASSERT_TRUE(bundled.exited && bundled.exit_code == 0) << bundled;
  const Json e = Json::parse(bundled.out);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(b["nodes"]["LeftKnee"]["t"][k].get<double>(), e["nodes"]["LeftKnee"]["t"][k].get<double>(), 1e-9)
        << "rigel import and the example generator agree on the knee at frame 300";
  }
}

TEST(CliImport, import__bad_input_and_usage) {
  TempDir dir;
  const std::string out = (dir.path() / "x.rigel").string();
  const CliRun missing_output = rigel({"import", (source_dir() / "tests/data/bvh/cmu_131_01.bvh").string()});
  EXPECT_TRUE(missing_output.exited && missing_output.exit_code == 2) << "-o is required: " << missing_output;
  const CliRun unsupported = rigel({"import", example(), "-o", out});
  EXPECT_TRUE(unsupported.exited && unsupported.exit_code == 1) << "a .rigel is not importable: " << unsupported;
  EXPECT_TRUE(contains(unsupported.err, "unsupported file type")) << unsupported;
  const std::string bad = (dir.path() / "bad.bvh").string();
  {
    std::ofstream f(bad);
    f << "HIERARCHY\nROOT a\n{\nOFFSET 0 0\n}\n";
  }
  const CliRun malformed = rigel({"import", bad, "-o", out});
  EXPECT_TRUE(malformed.exited && malformed.exit_code == 1) << "a malformed BVH is invalid input: " << malformed;
  EXPECT_TRUE(contains(malformed.err, "bad.bvh:5:")) << "the message names the line: " << malformed;
  EXPECT_TRUE(malformed.out.empty()) << "nothing on stdout";
  EXPECT_FALSE(std::filesystem::exists(out)) << "no scene is written when the import fails";
  const CliRun bad_scale = rigel({"import", (source_dir() / "tests/data/bvh/cmu_131_01.bvh").string(), "-o", out, "--scale", "-1"});
  EXPECT_TRUE(bad_scale.exited && bad_scale.exit_code == 2) << "a negative scale is a usage error: " << bad_scale;
}

}  // namespace
}  // namespace rigel::cli
