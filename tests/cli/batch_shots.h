#pragma once
// What the batch tests (batch_cli_tests.cc: local jobs; batch_slurm_cli_tests.cc:
// a Slurm job array) share: the shots, generated (the biped built once by
// `rigel build`, then kShotCount shots each keyed differently, in-process
// through app::Workspace as `rigel key` and `rigel set` key them: 50
// processes of those take minutes in the sanitizer build), a broken shot,
// the check of a batch report with that shot failed, and the comparison of
// two outputs of one command.

#include <algorithm>
#include <cstddef>
#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "cli_test_util.h"
#include "rigel/app/workspace.h"
#include "rigel/ephemeral/component.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/io/scene_file.h"

namespace rigel::cli::testing {

inline constexpr int kShotCount = 50;
// The broken shot goes among the others (not last): a failure in the
// middle of the run must not disturb the shots after it.
inline constexpr int kBrokenAt = kShotCount / 2;
// The frames `batch bake` bakes; every shot's keys lie inside.
inline constexpr const char* kBakeFrames = "0:12";

// The biped's definition copied into `dir` (hero.rig.xml, its geometry
// named by absolute path) and built from there into dir/hero.rigel: the
// shots' rig follows that copy, so a test can make it newer (`update`).
// Returns the built scene ("" after a failure, reported).
inline std::filesystem::path build_hero(const std::filesystem::path& dir) {
  namespace fs = std::filesystem;
  std::string text = read_text(fs::path(RIGEL_SOURCE_DIR) / "examples/biped.rig.xml");
  const std::string geo = "file=\"../tests/data/gltf/";
  const std::size_t at = text.find(geo);
  EXPECT_NE(at, std::string::npos) << "the example names its geometry " << geo;
  if (at == std::string::npos) return {};
  text.replace(at, geo.size(), "file=\"" + (fs::path(RIGEL_SOURCE_DIR) / "tests/data/gltf/").string());
  io::testing::write_text(dir / "hero.rig.xml", text);
  const CliRun r = rigel({"build", (dir / "hero.rig.xml").string(), "-o", (dir / "hero.rigel").string()});
  EXPECT_TRUE(exited_with(r, 0)) << r;
  return exited_with(r, 0) ? dir / "hero.rigel" : fs::path();
}

// Makes `dir`/hero.rig.xml (build_hero) newer: the left arm's component
// 1.1, so `rigel update` rebuilds it (and what hangs from it) keeping the
// keys on its controls and switch.
inline void bump_left_arm(const std::filesystem::path& dir) {
  std::string text = read_text(dir / "hero.rig.xml");
  const std::string arm = "name=\"arm\" side=\"L\" version=\"1.0\"";
  const std::size_t at = text.find(arm);
  ASSERT_NE(at, std::string::npos) << "the biped has a left arm at 1.0";
  text.replace(at, arm.size(), "name=\"arm\" side=\"L\" version=\"1.1\"");
  io::testing::write_text(dir / "hero.rig.xml", text);
}

// Shot `index`'s keys, no two shots alike: the left arm's FK/IK switch
// from FK at frame 0 to `fk_ik` at `switch_frame`, and its first FK
// control's rotate keyed at frame 0 as built and turned about Y by
// `angle` degrees at `turn_frame`.
struct ShotKeys {
  int switch_frame;
  double fk_ik;
  int turn_frame;
  double angle;
};
inline ShotKeys shot_keys(int index) {
  return {2 + index % 10, (index + 1) / (kShotCount + 1.0), 12 - index % 7, -40.0 + 1.5 * index};
}

// Writes shot `index` of the scene `rig` at `path`: what
//   rigel key RIG --control hero_arm_L_fkIkSwitch --attr fkIk --frame 0 --value 0
//   rigel key .. --control hero_arm_L_fkIkSwitch --attr fkIk --frame F --value V
//   rigel key .. --control hero_arm_L_fk1 --attr rotate --frame 0
//   rigel set .. --control hero_arm_L_fk1 --attr rotateY --value A --frame G -o PATH
// write, with the same library calls, in this process.
inline void write_shot(const std::filesystem::path& rig, int index, const std::filesystem::path& path) {
  auto scene = io::load_scene(rig, ephemeral::default_registry());
  ASSERT_TRUE(scene.is_ok()) << scene.status().message();
  app::Workspace ws(std::move(*scene), rig, {}, ephemeral::components());
  auto sw = ws.key_target("hero_arm_L_fkIkSwitch", "controls");
  auto fk = ws.key_target("hero_arm_L_fk1", "controls");
  ASSERT_TRUE(sw.is_ok() && fk.is_ok()) << "the biped has hero_arm_L_fkIkSwitch and hero_arm_L_fk1";
  const ShotKeys k = shot_keys(index);
  auto check = [&](const Status& s, const char* what) { EXPECT_TRUE(s.is_ok()) << "shot " << index << ": " << what << ": " << s.message(); };
  check(ws.set_frame(0), "frame 0");
  check(ws.set_channel_keys({*sw}, {"fkIk"}, 0.0).status(), "fkIk at 0");
  check(ws.set_channel_keys({*fk}, {"rotate"}).status(), "rotate at 0");
  check(ws.set_frame(k.switch_frame), "the switch's frame");
  check(ws.set_channel_keys({*sw}, {"fkIk"}, k.fk_ik).status(), "fkIk");
  check(ws.set_frame(k.turn_frame), "the turn's frame");
  check(ws.set_channel_values({*fk}, {"rotateY"}, {k.angle}).status(), "rotateY");
  check(ws.save(path).status(), "save");
}

// kShotCount shots of `rig` in `folder`: s00.rigel, s01.rigel, ...
inline std::vector<std::string> write_shots(const std::filesystem::path& rig, const std::filesystem::path& folder) {
  std::filesystem::create_directories(folder);
  std::vector<std::string> shots;
  for (int i = 0; i < kShotCount; ++i) {
    const std::string name = std::string(i < 10 ? "s0" : "s") + std::to_string(i) + ".rigel";
    write_shot(rig, i, folder / name);
    shots.push_back((folder / name).string());
  }
  return shots;
}

// A shot that is not a scene: its JSON stops at line 2 (its log names the
// file and the place).
inline constexpr std::string_view kBrokenShotText = "{\"rigel\": \"scene\", \"version\": 1, \"nodes\": [\n";
inline constexpr const char* kBrokenShotProblem = "broken.rigel:2:1: syntax error";

// The shots as a batch gets them: `shots` with `broken` at kBrokenAt.
inline std::vector<std::string> with_broken(std::vector<std::string> shots, const std::string& broken) {
  shots.insert(shots.begin() + kBrokenAt, broken);
  return shots;
}

// The output of a shot in `out` (its name's stem, .rigel).
inline std::filesystem::path output_of(const std::filesystem::path& out, const std::string& shot) {
  return out / (std::filesystem::path(shot).stem().string() + ".rigel");
}

// Checks the report of `rigel batch OP SHOTS... -o OUT --json` (`run`,
// whose stdout is the report) over `shots` of which the one named
// broken.rigel is broken: exit 1, every shot listed in order, that one
// failed with its log naming the problem and no output, every other ok
// with its log and output; the report file OUT/batch-report.json is what
// was printed. `jobs`: what the report says of them.
inline void expect_report_with_broken_shot(const CliRun& run, const std::string& op, const std::vector<std::string>& shots,
                                           const std::filesystem::path& out, std::size_t jobs) {
  namespace fs = std::filesystem;
  using Json = nlohmann::json;
  EXPECT_TRUE(exited_with(run, 1)) << "one shot failed: " << run;
  EXPECT_TRUE(contains(run.err, "rigel: batch " + op + ": " + std::to_string(shots.size() - 1) + " of " +
                                    std::to_string(shots.size()) + " shots ok"))
      << run;
  const Json report = Json::parse(run.out);
  EXPECT_EQ(report["operation"], op);
  EXPECT_EQ(report["jobs"], jobs);
  ASSERT_EQ(report["shots"].size(), shots.size());
  for (std::size_t i = 0; i < shots.size(); ++i) {
    const Json& s = report["shots"][i];
    EXPECT_EQ(s["shot"], shots[i]) << "every shot, in order";
    const bool broken = fs::path(shots[i]).filename() == "broken.rigel";
    EXPECT_EQ(s["status"], broken ? "failed" : "ok") << s;
    EXPECT_EQ(s["exit"], broken ? 1 : 0) << s;
    EXPECT_EQ(fs::path(s["output"].get<std::string>()), output_of(out, shots[i])) << s;
    EXPECT_EQ(fs::exists(output_of(out, shots[i])), !broken) << s << (broken ? ": a failed shot writes nothing" : "");
    const fs::path log = s["log"].get<std::string>();
    EXPECT_EQ(log, out / "logs" / (fs::path(shots[i]).stem().string() + ".log")) << s;
    ASSERT_TRUE(fs::exists(log)) << s;
    if (broken) {
      EXPECT_TRUE(contains(read_text(log), kBrokenShotProblem)) << "its log says why: " << read_text(log);
    }
  }
  EXPECT_EQ(read_text(out / "batch-report.json"), run.out);
}

// What a retry must leave as it was: the report before it (its text) and
// the modification times of the outputs and logs of the shots in `out`
// that are not broken.rigel.
struct BeforeRetry {
  std::string report;
  std::map<std::filesystem::path, std::filesystem::file_time_type> times;
};
inline BeforeRetry before_retry(const std::vector<std::string>& shots, const std::filesystem::path& out) {
  namespace fs = std::filesystem;
  BeforeRetry before{read_text(out / "batch-report.json"), {}};
  for (const std::string& shot : shots) {
    if (fs::path(shot).filename() == "broken.rigel") continue;
    for (const fs::path& p : {output_of(out, shot), out / "logs" / (fs::path(shot).stem().string() + ".log")}) {
      std::error_code ec;
      before.times[p] = fs::last_write_time(p, ec);
      EXPECT_FALSE(ec) << p;
    }
  }
  return before;
}

// The retry of that run once the broken shot is fixed: `rigel batch OP -o
// OUT --retry-failed OUT/batch-report.json --json` (`run`) ran only it,
// exit 0; the report, printed and in its file, lists every shot ok in
// order, the others' entries as they were, its jobs the first run's and
// its time the sum of both; no other shot's output or log was written
// again.
inline void expect_retried_alone(const CliRun& run, const std::string& op, const std::vector<std::string>& shots,
                                 const std::filesystem::path& out, const BeforeRetry& before) {
  namespace fs = std::filesystem;
  using Json = nlohmann::json;
  ASSERT_TRUE(exited_with(run, 0)) << run;
  EXPECT_TRUE(contains(run.err, "rigel: batch " + op + ": 1 of 1 shots ok")) << "only the failed shot ran: " << run;
  const Json merged = Json::parse(read_text(out / "batch-report.json")), earlier = Json::parse(before.report);
  EXPECT_EQ(merged, Json::parse(run.out));
  EXPECT_EQ(merged["jobs"], earlier["jobs"]);
  EXPECT_GT(merged["seconds"].get<double>(), earlier["seconds"].get<double>()) << "the first run's time and the retry's";
  ASSERT_EQ(merged["shots"].size(), shots.size());
  for (std::size_t i = 0; i < shots.size(); ++i) {
    EXPECT_EQ(merged["shots"][i]["shot"], shots[i]);
    EXPECT_EQ(merged["shots"][i]["status"], "ok") << merged["shots"][i];
    EXPECT_TRUE(fs::exists(output_of(out, shots[i]))) << shots[i];
    if (fs::path(shots[i]).filename() != "broken.rigel") {
      EXPECT_EQ(merged["shots"][i], earlier["shots"][i]) << "a shot that did not run again is reported as it was";
    }
  }
  for (const auto& [path, time] : before.times) EXPECT_EQ(fs::last_write_time(path), time) << path << " was written again";
}

// Whether `text` holds a UUID at `at` (8-4-4-4-12 hex digits, as
// graph::Uuid::str() writes it).
inline bool uuid_at(std::string_view text, std::size_t at) {
  if (at + 36 > text.size()) return false;
  for (std::size_t i = 0; i < 36; ++i) {
    const char c = text[at + i];
    const bool dash = i == 8 || i == 13 || i == 18 || i == 23;
    if (dash ? c != '-' : !((c >= '0' && c <= '9') || (c >= 'a' && c <= 'f') || (c >= 'A' && c <= 'F'))) return false;
  }
  return true;
}

// Calls `token(start)` for each UUID in `text`, in order, and returns
// `text` with each replaced by what that call returns.
template <typename F>
std::string replace_uuids(std::string_view text, F token) {
  std::string out;
  out.reserve(text.size());
  std::size_t done = 0;
  for (std::size_t dash = text.find('-', 8); dash != std::string_view::npos; dash = text.find('-', dash + 1)) {
    const std::size_t start = dash - 8;
    if (start < done || !uuid_at(text, start)) continue;
    out.append(text.substr(done, start - done));
    out += token(start);
    done = start + 36;
    dash = done - 1;
  }
  out.append(text.substr(done));
  return out;
}

// Whether `a` and `b`, what one command wrote from `shot` in two runs,
// are the same file: the same bytes, but for the uuids of the nodes each
// run made (graph::Uuid::generate is random), which need only stand for
// each other one to one, everywhere (each numbered by its first
// appearance); every uuid the shot holds stays as it is.
inline ::testing::AssertionResult same_output(const std::filesystem::path& a, const std::filesystem::path& b,
                                              const std::filesystem::path& shot) {
  const std::string x = read_text(a), y = read_text(b);
  if (x == y) return ::testing::AssertionSuccess();
  std::vector<std::string> kept;
  const std::string input = read_text(shot);
  replace_uuids(input, [&](std::size_t at) {
    kept.push_back(input.substr(at, 36));
    return std::string();
  });
  std::sort(kept.begin(), kept.end());
  auto normal = [&](const std::string& text) {
    std::map<std::string, std::string> made;
    return replace_uuids(text, [&](std::size_t at) {
      std::string uuid = text.substr(at, 36);
      if (std::binary_search(kept.begin(), kept.end(), uuid)) return uuid;
      auto [it, fresh] = made.emplace(uuid, "");
      if (fresh) it->second = "<made uuid " + std::to_string(made.size()) + ">";
      return it->second;
    });
  };
  const std::string nx = normal(x), ny = normal(y);
  if (nx == ny) return ::testing::AssertionSuccess();
  const std::size_t at = static_cast<std::size_t>(std::mismatch(nx.begin(), nx.end(), ny.begin(), ny.end()).first - nx.begin());
  const std::size_t from = at < 200 ? 0 : at - 200;
  return ::testing::AssertionFailure() << a << " and " << b << " (from " << shot << ") differ at byte " << at
                                       << " of their text with made uuids numbered:\n--- " << a.filename() << " ---\n"
                                       << nx.substr(from, 400) << "\n--- " << b.filename() << " ---\n"
                                       << ny.substr(from, 400);
}

}  // namespace rigel::cli::testing
