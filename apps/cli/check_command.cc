// `rigel check FILE` and `rigel check record FILE` (check_command.h): a
// rig's regression poses checked, or recorded, through the app layer.

#include "check_command.h"

#include <iostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_util.h"
#include "rigel/app/rig_checks.h"
#include "rigel/tools/data_files.h"

namespace rigel::cli {
namespace {

using Json = nlohmann::ordered_json;

struct CheckArgs {
  std::string file, tests, character, rig;
  double tolerance = 1e-6;
  bool json = false;
};

struct RecordArgs {
  std::string file, output, character, rig, frames;
  bool json = false;
};

const rig::ComponentFactory& factory() { return tools::components(); }

// "0,10,20" or "0-48" (every frame) or "0-48:8" (every 8th) as frames.
std::optional<std::vector<double>> frames_of(const std::string& text) {
  std::vector<double> out;
  if (text.empty()) return out;
  std::size_t from = 0;
  while (from <= text.size()) {
    const std::size_t comma = text.find(',', from);
    const std::string part = text.substr(from, comma == std::string::npos ? std::string::npos : comma - from);
    const std::size_t dash = part.find('-', 1);
    if (dash == std::string::npos) {
      const auto f = parse_number(part.data(), part.data() + part.size());
      if (!f) return std::nullopt;
      out.push_back(*f);
    } else {
      const std::size_t colon = part.find(':', dash);
      const std::string a = part.substr(0, dash), b = part.substr(dash + 1, colon == std::string::npos ? std::string::npos : colon - dash - 1);
      const std::string by = colon == std::string::npos ? "1" : part.substr(colon + 1);
      const auto first = parse_number(a.data(), a.data() + a.size());
      const auto last = parse_number(b.data(), b.data() + b.size());
      const auto step = parse_number(by.data(), by.data() + by.size());
      if (!first || !last || !step || *step <= 0 || *last < *first || (*last - *first) / *step > 100000) return std::nullopt;
      for (double f = *first; f <= *last + 1e-9; f += *step) out.push_back(f);
    }
    if (comma == std::string::npos) break;
    from = comma + 1;
  }
  return out;
}

int run_check(const CheckArgs& args) {
  auto checked = app::check_rig_tests_file(args.file, args.tests, args.character, args.rig, args.tolerance, factory());
  if (!checked) {
    const Status& s = checked.status();
    if (s.field() == "tolerance" || (s.field() == "tests" && s.code() == ErrorCode::kInvalidArgument))
      return usage_error(s.message());
    return fail(s);
  }
  const tools::RigTestReport& r = checked->report;
  if (args.json) {
    Json mismatches = Json::array();
    for (const tools::RigTestMismatch& m : r.mismatches) {
      Json j{{"pose", m.pose}, {"joint", m.joint}, {"error", m.error}};
      if (!m.problem.empty()) j["problem"] = m.problem;
      mismatches.push_back(std::move(j));
    }
    std::cout << Json{{"rig", checked->rig},         {"tests", checked->tests.string()}, {"ok", r.ok()},
                      {"poses", r.poses},            {"joints", r.joints},              {"maxError", r.max_error},
                      {"tolerance", args.tolerance}, {"mismatches", std::move(mismatches)}}
                     .dump(2, ' ', false, Json::error_handler_t::replace)
              << "\n";
  } else {
    for (const tools::RigTestMismatch& m : r.mismatches) {
      if (!m.problem.empty()) std::cerr << "rigel: pose '" << m.pose << "'" << (m.joint.empty() ? "" : ", joint '" + m.joint + "'") << ": " << m.problem << "\n";
      else std::cerr << "rigel: pose '" << m.pose << "', joint '" << m.joint << "': off by " << number_text(m.error) << "\n";
    }
    std::cerr << "rigel: " << checked->rig << ": " << r.poses << " poses, " << r.joints << " joint checks against "
              << checked->tests.string() << ": " << (r.ok() ? "all match" : std::to_string(r.mismatches.size()) + " mismatches")
              << " (largest difference " << number_text(r.max_error) << ", tolerance " << number_text(args.tolerance) << ")\n";
  }
  return r.ok() ? 0 : kExitInvalidInput;
}

int run_record(const RecordArgs& args) {
  tools::RecordRigTestsOptions options;
  const auto frames = frames_of(args.frames);
  if (!frames) return usage_error("--frames: '" + args.frames + "' is not frames (0,12,24 or 0-48 or 0-48:8)");
  options.frames = *frames;
  auto recorded = app::record_rig_tests_file(args.file, args.output, args.character, args.rig, options, factory());
  if (!recorded) {
    const Status& s = recorded.status();
    if (s.field() == "output" && s.code() == ErrorCode::kInvalidArgument) return usage_error(s.message());
    if (s.field() == "character") return usage_error(args.file + ": the definition names no geometry; give --character");
    return fail(s);
  }
  std::size_t joints = recorded->tests.base.size();
  if (args.json) {
    Json poses = Json::array();
    for (const tools::RigTestPose& p : recorded->tests.poses)
      poses.push_back(Json{{"name", p.name}, {"frame", p.frame}, {"controls", p.pose.entries.size()}, {"moved", p.joints.size()}});
    std::cout << Json{{"rig", recorded->tests.rig}, {"output", recorded->output.string()}, {"joints", joints},
                      {"poses", poses}}
                     .dump(2, ' ', false, Json::error_handler_t::replace)
              << "\n";
  } else {
    std::cerr << "rigel: recorded " << recorded->tests.poses.size() << " poses of " << recorded->tests.rig << " ("
              << joints << " joints) into " << recorded->output.string() << "\n";
  }
  return 0;
}

}  // namespace

struct CheckCommand::State {
  CLI::App* check_cmd = nullptr;
  CLI::App* record_cmd = nullptr;
  CheckArgs check;
  RecordArgs record;
};

CheckCommand::CheckCommand() : state_(std::make_unique<State>()) {}
CheckCommand::~CheckCommand() = default;

void add_check_command(CLI::App& app, CheckCommand& command) {
  CheckCommand::State& s = command.state();
  s.check_cmd = app.add_subcommand("check", "Check a rig's regression poses: every joint of every pose as recorded");
  s.check_cmd->footer("Exit 1 when a joint is off by more than the tolerance (each named: pose, joint, error).\n"
                      "Example:\n  rigel check examples/biped.rig.xml\n"
                      "  rigel check shot.rigel --tests shot.rigtest.json --rig hero --json\n"
                      "  rigel check record examples/biped.rig.xml   # writes examples/biped.rigtest.json");
  s.check_cmd->add_option("FILE", s.check.file, "Definition (.rig.xml, .rig.json, .build.json) or scene (.rigel)");
  s.check_cmd->add_option("--tests", s.check.tests, "Tests file (default: beside the definition, NAME.rigtest.json)");
  s.check_cmd->add_option("--character", s.check.character, "Character to build a definition on (default: the tests')");
  s.check_cmd->add_option("--rig", s.check.rig, "The scene's rig (default: the tests' rig)");
  s.check_cmd->add_option("--tolerance", s.check.tolerance, "Largest difference of a world matrix element (default 1e-6)")
      ->check(CLI::NonNegativeNumber);
  s.check_cmd->add_flag("--json", s.check.json, "Print the report as JSON on stdout");

  s.record_cmd = s.check_cmd->add_subcommand("record", "Record a rig's regression poses and its joints under them");
  s.record_cmd->footer("Without --frames: rest, one pose per component (its controls moved and turned) and all at once.\n"
                       "Example:\n  rigel check record examples/biped.rig.xml\n"
                       "  rigel check record shot.rigel --rig hero --frames 0-96:8 -o shot.rigtest.json");
  s.record_cmd->add_option("FILE", s.record.file, "Definition (.rig.xml, .rig.json, .build.json) or scene (.rigel)")->required();
  s.record_cmd->add_option("-o,--output", s.record.output, "Tests file to write (default: beside the definition)");
  s.record_cmd->add_option("--character", s.record.character, "Character to build a definition on (default: its geometry)");
  s.record_cmd->add_option("--rig", s.record.rig, "The scene's rig (default: its only one)");
  s.record_cmd->add_option("--frames", s.record.frames, "Frames to record as the scene plays: 0,12,24 or 0-48 or 0-48:8");
  s.record_cmd->add_flag("--json", s.record.json, "Print a JSON summary on stdout");
}

std::optional<int> run_check_command(const CheckCommand& command) {
  const CheckCommand::State& s = command.state();
  if (!*s.check_cmd) return std::nullopt;
  if (*s.record_cmd) return run_record(s.record);
  if (s.check.file.empty()) return usage_error("check: give a FILE (a definition or a scene), or `check record FILE`");
  return run_check(s.check);
}

}  // namespace rigel::cli
