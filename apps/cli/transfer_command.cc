// `rigel transfer` (see transfer_command.h).

#include "transfer_command.h"

#include <array>
#include <cmath>
#include <iostream>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_util.h"
#include "rigel/app/workspace.h"
#include "rigel/ephemeral/component.h"
#include "rigel/tools/data_files.h"

namespace rigel::cli {

CLI::App* add_transfer_command(CLI::App& app, TransferArgs& args) {
  CLI::App* cmd = app.add_subcommand("transfer", "Transfer keys from one built component (or character) onto another");
  cmd->footer(
      "--from and --to name a component (RIG:COMPONENT, by name or rigId) or a whole character (RIG:). Components "
      "pair by rigId, else name and side; controls and switches by their role and index, never by node names. A key "
      "at source frame t lands at t + --offset with its value and tangents; the target's keys inside the "
      "destination range are replaced, those outside kept.\n"
      "Examples:\n  rigel transfer shot.rigel --from hero:arm_L --to villain:arm_L -o shot.rigel\n"
      "  rigel transfer shot.rigel --from hero: --to villain: --frames 0:48 --offset 100 -o shot.rigel --json");
  cmd->add_option("SCENE", args.scene, "Scene file (.rigel)")->required();
  cmd->add_option("--from", args.from, "The source: RIG:COMPONENT or RIG:")->required();
  cmd->add_option("--to", args.to, "The target: RIG:COMPONENT or RIG: (the same kind as --from)")->required();
  cmd->add_option("--frames", args.frames, "Source frames FIRST:LAST (default: every key)");
  cmd->add_option("--offset", args.offset, "Frames added to each key's time (default 0)");
  cmd->add_option("-o,--output", args.output, "Scene file to write (.rigel)")->required();
  cmd->add_flag("--json", args.json, "Print a JSON report on stdout");
  args.command = cmd;
  return cmd;
}

int run_transfer(const TransferArgs& args) {
  using Json = nlohmann::ordered_json;
  if (!std::isfinite(args.offset)) return usage_error("--offset must be a finite number");
  std::optional<std::array<double, 2>> frames;
  if (!args.frames.empty()) {
    const auto range = parse_frames(args.frames);
    if (!range) return usage_error("--frames '" + args.frames + "': " + kFramesExpected);
    frames = std::array<double, 2>{range->first, range->second};
  }
  auto scene = load(args.scene);
  if (!scene) return fail(scene.status());
  app::Workspace ws(std::move(*scene), args.scene, {}, tools::components());
  auto report = ws.transfer_keys(args.from, args.to, frames, args.offset);
  if (!report) {
    const Status& s = report.status();
    const std::string option = s.field().empty() ? "" : ": --" + s.field();
    return fail(s.with_context(args.scene + option));
  }
  if (auto saved = ws.save(args.output); !saved) return fail(saved.status());
  const graph::Graph& g = ws.graph();
  if (args.json) {
    Json set = Json::array(), components = Json::array();
    for (graph::NodeId n : report->set) set.push_back(g.node(n)->name());
    for (const auto& [a, b] : report->components)
      components.push_back(Json{{"from", g.node(a)->name()}, {"to", g.node(b)->name()}});
    Json out{{"from", args.from}, {"to", args.to}, {"offset", args.offset}, {"channels", report->channels},
             {"keys", report->keys}, {"components", components}, {"set", set}, {"output", args.output}};
    out["frames"] = report->first ? Json::array({*report->first, *report->last}) : Json(nullptr);
    std::cout << out.dump() << "\n";
  }
  std::cerr << "rigel: transferred " << report->keys << " keys on " << report->channels
            << (report->channels == 1 ? " channel" : " channels") << " from " << args.from << " to " << args.to;
  if (report->first)
    std::cerr << " (frames " << number_text(*report->first) << ":" << number_text(*report->last) << ", offset "
              << number_text(args.offset) << ")";
  std::cerr << "; wrote " << args.output << "\n";
  return 0;
}

}  // namespace rigel::cli
