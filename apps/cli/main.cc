// The rigel command line: a thin driver over the library (STYLE.md §8).
// Exit status: 0 success, 1 invalid input, 2 usage error (DESIGN.md).
// The ephemeral-rig commands (`ephemeral ...`, `pose`) are in
// ephemeral_commands.cc; helpers shared by both files in cli_util.h.

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli_util.h"
#include "definition_commands.h"
#include "ephemeral_commands.h"
#include "pose_command.h"
#include "rig_commands.h"
#include "serve_command.h"
#include "rigel/io/bvh_import.h"
#include "rigel/io/gltf_export.h"
#include "rigel/io/gltf_import.h"
#include "rigel/io/report.h"
#include "rigel/io/scene_file.h"
#include "rigel/math/transform.h"
#include "rigel/ops/anim/clips.h"
#include "rigel/scene/transform_types.h"
#include "rigel/tools/bake.h"

namespace {

using rigel::Status;
using rigel::graph::NodeId;
using rigel::cli::fail;
using rigel::cli::kExitInvalidInput;
using rigel::cli::kExitUsage;
using rigel::cli::load;
using rigel::cli::lower_extension;
using rigel::cli::parse_number;

std::string vec(double x, double y, double z) {
  char buffer[96];
  std::snprintf(buffer, sizeof buffer, "(%.6g, %.6g, %.6g)", x, y, z);
  return buffer;
}

// ---- inspect -----------------------------------------------------------------

struct InspectArgs {
  std::string scene;
  bool json = false;
};

int run_inspect(const InspectArgs& args) {
  auto scene = load(args.scene);
  if (!scene) return fail(scene.status());
  auto report = rigel::io::inspect_report(**scene);
  if (args.json) {
    std::cout << report.dump(2) << "\n";
    return 0;
  }
  rigel::scene::Scene& s = **scene;
  rigel::graph::Graph& g = s.graph();
  std::string types;
  for (auto it = report["types"].begin(); it != report["types"].end(); ++it)
    types += (types.empty() ? "" : ", ") + it.key() + " " + std::to_string(it.value().get<int>());
  std::cout << args.scene << ": " << g.node_count() << " nodes (" << types << "), " << report["connections"].size()
            << " connections, " << g.fps() << " fps, frame " << s.frame() << "\n";
  std::cout << "hierarchy:\n";
  for (NodeId id : s.hierarchy()) {
    const auto& n = *g.node(id);
    std::cout << std::string(2 + 2 * static_cast<std::size_t>(s.depth(id)), ' ') << n.name() << " (" << n.type().name() << ")";
    for (const auto& [k, v] : n.tags()) std::cout << " " << k << "=" << v;
    std::cout << "\n";
  }
  bool header = false;
  for (NodeId id : g.nodes()) {
    if (s.is_transform(id)) continue;
    if (!header) std::cout << "other nodes:\n";
    header = true;
    std::cout << "  " << g.node(id)->name() << " (" << g.node(id)->type().name() << ")\n";
  }
  if (!report["connections"].empty()) {
    std::cout << "connections:\n";
    for (const auto& c : report["connections"])
      std::cout << "  " << c["src"].get<std::string>() << " -> " << c["dst"].get<std::string>() << "\n";
  }
  return 0;
}

// ---- eval --------------------------------------------------------------------

struct EvalArgs {
  std::string scene;
  std::optional<double> frame;
  std::optional<double> time;
  std::optional<std::string> clip;
  bool json = false;
};

int run_eval(const EvalArgs& args) {
  // A non-finite --frame/--time is a bad option value, like --frame abc: a
  // usage error (exit 2), checked before the scene is read.
  if ((args.frame && !std::isfinite(*args.frame)) || (args.time && !std::isfinite(*args.time))) {
    std::cerr << "rigel: " << (args.frame ? "--frame" : "--time") << " must be a finite number\n";
    return kExitUsage;
  }
  auto scene = load(args.scene);
  if (!scene) return fail(scene.status());
  rigel::scene::Scene& s = **scene;
  if (args.frame) s.set_frame(*args.frame);
  if (args.time) s.graph().set_time(*args.time);
  // The clip that plays: --clip picks one of the scene's animClips (an
  // imported glTF's animations), by name or index.
  std::optional<std::string> clip_name;
  if (const NodeId clips = rigel::ops::anim::find_clips_node(s.graph()); clips.is_valid()) {
    if (args.clip) {
      auto index = rigel::ops::anim::resolve_clip(s.graph(), clips, *args.clip);
      if (!index) return fail(index.status().with_context(args.scene + ": --clip"));
      if (Status st = rigel::ops::anim::set_active_clip(s.graph(), clips, *index); !st) return fail(st);
    }
    auto list = rigel::ops::anim::clips_of(s.graph(), clips);
    if (!list) return fail(list.status().with_context(args.scene));
    const auto active = std::get<std::int64_t>(s.graph().evaluate(clips, rigel::ops::anim::clips_attr::kActiveClip));
    if (!list->empty()) clip_name = (*list)[static_cast<std::size_t>(active)].name;
  } else if (args.clip) {
    return fail(Status(rigel::ErrorCode::kNotFound, args.scene + ": --clip: the scene has no animation clips"));
  }
  auto report = rigel::io::eval_report(s);
  if (clip_name) report["clip"] = *clip_name;
  if (args.json) {
    std::cout << report.dump() << "\n";
    return 0;
  }
  rigel::graph::Graph& g = s.graph();
  std::cout << "frame " << s.frame() << " (" << g.time() << " s)" << (clip_name ? ", clip '" + *clip_name + "'" : "")
            << ", world space:\n";
  for (NodeId id : s.hierarchy()) {
    const auto& t = report["nodes"][g.node(id)->name()];
    rigel::math::Quat q(t["q"][3].get<double>(), t["q"][0].get<double>(), t["q"][1].get<double>(), t["q"][2].get<double>());
    rigel::math::Vec3 r = rigel::math::to_degrees(rigel::math::quat_to_euler(q, rigel::math::RotateOrder::kXYZ));
    std::string name = std::string(2 * static_cast<std::size_t>(s.depth(id)), ' ') + g.node(id)->name();
    std::printf("  %-28s t %-36s r %-36s s %s\n", name.c_str(),
                vec(t["t"][0], t["t"][1], t["t"][2]).c_str(), vec(r.x(), r.y(), r.z()).c_str(),
                vec(t["s"][0], t["s"][1], t["s"][2]).c_str());
  }
  return 0;
}

// ---- import ------------------------------------------------------------------

struct ImportArgs {
  std::string input;
  std::string output;
  double scale = 1.0;
  bool skip_end_sites = false;
  bool json = false;
};

void print_json(const nlohmann::ordered_json& j) { std::cout << j.dump(2) << "\n"; }

// A .glb / .gltf character: joints, meshes, skins and every animation as a clip.
int run_import_gltf(const ImportArgs& args) {
  rigel::io::GltfImportOptions options;
  options.scale = args.scale;
  std::vector<std::string> warnings;
  options.warnings = &warnings;
  auto scene = rigel::io::import_gltf(args.input, options);
  if (!scene) return fail(scene.status());
  for (const std::string& w : warnings) std::cerr << "rigel: warning: " << args.input << ": " << w << "\n";
  if (Status s = rigel::io::save_scene(**scene, args.output); !s) return fail(s);
  const rigel::graph::Graph& g = (*scene)->graph();
  std::size_t joints = 0, meshes = 0;
  for (NodeId id : g.nodes()) {
    joints += g.node(id)->type().name() == "joint";
    meshes += g.node(id)->type().name() == "mesh";
  }
  std::size_t clips = 0;
  if (const NodeId clips_node = rigel::ops::anim::find_clips_node(g); clips_node.is_valid()) {
    if (auto list = rigel::ops::anim::clips_of(g, clips_node)) clips = list->size();
  }
  if (args.json) {
    print_json({{"nodes", g.node_count()}, {"joints", joints}, {"meshes", meshes}, {"clips", clips}, {"output", args.output}});
  } else {
    std::cerr << "rigel: imported " << g.node_count() << " nodes (" << joints << " joints, " << meshes << " meshes), "
              << clips << (clips == 1 ? " clip" : " clips") << " into " << args.output << "\n";
  }
  return 0;
}

int run_import(const ImportArgs& args) {
  const std::string ext = lower_extension(args.input);
  if (ext != ".bvh" && ext != ".glb" && ext != ".gltf") {
    std::cerr << "rigel: " << args.input << ": unsupported file type '" << ext << "' (this build imports .bvh, .glb, .gltf)\n";
    return kExitInvalidInput;
  }
  if (!(args.scale > 0.0) || !std::isfinite(args.scale)) {
    std::cerr << "rigel: --scale must be a positive number\n";
    return kExitUsage;
  }
  if (ext != ".bvh") return run_import_gltf(args);
  auto file = rigel::io::load_bvh(args.input);
  if (!file) return fail(file.status());
  rigel::io::BvhImportOptions options;
  options.scale = args.scale;
  options.skip_end_sites = args.skip_end_sites;
  auto scene = rigel::io::import_bvh(*file, options);
  if (!scene) return fail(scene.status());
  if (Status s = rigel::io::save_scene(**scene, args.output); !s) return fail(s);
  if (args.json) {
    print_json({{"joints", file->joints.size()}, {"frames", file->frame_count}, {"fps", (*scene)->graph().fps()},
                {"output", args.output}});
  } else {
    std::cerr << "rigel: imported " << file->joints.size() << " joints, " << file->frame_count << " frames at "
              << (*scene)->graph().fps() << " fps into " << args.output << "\n";
  }
  return 0;
}

// ---- export ------------------------------------------------------------------

struct ExportArgs {
  std::string scene;
  std::string output;
  std::string frames;  // "FIRST:LAST"; empty when not given
  bool bake = false;
  bool json = false;
};

// "A:B" as two finite numbers; nullopt for anything else.
std::optional<std::pair<double, double>> parse_frames(const std::string& text) {
  const std::size_t colon = text.find(':');
  if (colon == std::string::npos) return std::nullopt;
  const auto first = parse_number(text.data(), text.data() + colon);
  const auto last = parse_number(text.data() + colon + 1, text.data() + text.size());
  if (!first || !last) return std::nullopt;
  return std::pair{*first, *last};
}

// A progress callback that prints "rigel: WHAT NN%" on stderr, only on a
// terminal (empty otherwise); `shown` tells whether a line was started.
std::function<void(double)> terminal_progress(const char* what, bool& shown) {
  if (!isatty(STDERR_FILENO)) return {};
  return [what, &shown, last = -1](double fraction) mutable {
    const int percent = static_cast<int>(fraction * 100.0);
    if (percent == last) return;
    last = percent;
    shown = true;
    std::fprintf(stderr, "\rrigel: %s %3d%%", what, percent);
    std::fflush(stderr);
  };
}

int run_export(const ExportArgs& args) {
  rigel::io::GltfExportOptions options;
  options.bake = args.bake;
  if (!args.frames.empty()) {
    options.frames = parse_frames(args.frames);
    if (!options.frames) {
      std::cerr << "rigel: --frames '" << args.frames << "': expected FIRST:LAST, two frame numbers such as 0:120\n";
      return kExitInvalidInput;
    }
  }
  const std::string ext = lower_extension(args.output);
  if (ext != ".glb" && ext != ".gltf") {
    std::cerr << "rigel: " << args.output << ": unsupported file type '" << ext << "' (export writes .glb or .gltf)\n";
    return kExitInvalidInput;
  }
  auto scene = load(args.scene);
  if (!scene) return fail(scene.status());
  // Baking long ranges takes a while: show how far it got, on a terminal only.
  bool progress_shown = false;
  options.progress = terminal_progress("baking", progress_shown);
  rigel::io::GltfExportReport report;
  const Status status = rigel::io::export_gltf(**scene, args.output, options, &report);
  if (progress_shown) std::fputc('\n', stderr);
  if (!status) return fail(status);
  if (report.baked) {
    std::cerr << "rigel: note: baked frames " << report.first_frame << " to " << report.last_frame << " at "
              << (*scene)->graph().fps() << " fps: " << report.bake_reason << "\n";
  }
  for (const std::string& note : report.notes) std::cerr << "rigel: note: " << note << "\n";
  if (args.json) {
    nlohmann::ordered_json j{{"nodes", report.node_count},       {"meshes", report.mesh_count},
                             {"skins", report.skin_count},       {"animations", report.animation_count},
                             {"channels", report.channel_count}, {"baked", report.baked}};
    if (report.baked) {
      j["bakedFrames"] = {report.first_frame, report.last_frame};
      j["bakeReason"] = report.bake_reason;
    }
    j["notes"] = report.notes;
    j["output"] = args.output;
    print_json(j);
  } else {
    std::cerr << "rigel: exported " << report.node_count << " nodes, " << report.mesh_count << " meshes, "
              << report.skin_count << " skins, " << report.animation_count << " animations (" << report.channel_count
              << " channels) to " << args.output << "\n";
  }
  return 0;
}
// ---- bake --------------------------------------------------------------------

struct BakeArgs {
  std::string scene;
  std::string frames;
  std::vector<std::string> nodes;  // empty: every joint
  std::string output;
  bool json = false;
};

int run_bake(const BakeArgs& args) {
  const auto frames = parse_frames(args.frames);
  if (!frames) {
    std::cerr << "rigel: --frames '" << args.frames << "': expected FIRST:LAST, two frame numbers such as 0:120\n";
    return kExitUsage;
  }
  auto scene = load(args.scene);
  if (!scene) return fail(scene.status());
  rigel::tools::BakeOptions options;
  options.first = frames->first;
  options.last = frames->second;
  for (const std::string& name : args.nodes) {
    const NodeId id = (*scene)->graph().find(name);
    if (!id.is_valid()) return fail(rigel::error(rigel::ErrorCode::kNotFound, args.scene + ": --nodes: no node '" + name + "'"));
    options.nodes.push_back(id);
  }
  bool shown = false;
  options.progress = terminal_progress("baking", shown);
  auto report = rigel::tools::bake(**scene, options);
  if (shown) std::fputc('\n', stderr);
  if (!report) return fail(report.status().with_context(args.scene));
  // A command line run has no undo: the bake's undo records (the key arrays
  // before and after) would stay in memory while the file is written.
  (*scene)->graph().clear_history();
  if (Status s = rigel::io::save_scene(**scene, args.output); !s) return fail(s);
  if (args.json) {
    std::cout << nlohmann::ordered_json{{"nodes", report->nodes},
                                        {"frames", report->frames},
                                        {"keys", report->keys},
                                        {"disconnected", report->disconnected},
                                        {"output", args.output}}
                     .dump(2)
              << "\n";
  } else {
    std::cerr << "rigel: baked " << report->nodes << " nodes over " << report->frames << " frames (" << report->keys
              << " keys; " << report->disconnected << " drivers disconnected) into " << args.output << "\n";
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"rigel: a character-rigging engine that needs no host application"};
  app.require_subcommand(1);
  app.set_help_all_flag("--help-all", "Print help for every subcommand");

  InspectArgs inspect;
  CLI::App* inspect_cmd = app.add_subcommand("inspect", "Print a scene's nodes, hierarchy and connections");
  inspect_cmd->add_option("SCENE", inspect.scene, "Scene file (.rigel)")->required();
  inspect_cmd->add_flag("--json", inspect.json, "Print one JSON object instead of text");

  EvalArgs eval;
  CLI::App* eval_cmd = app.add_subcommand("eval", "Evaluate a scene and print world transforms of every transform node");
  eval_cmd->add_option("SCENE", eval.scene, "Scene file (.rigel)")->required();
  CLI::Option* frame = eval_cmd->add_option("--frame", eval.frame, "Frame to evaluate at (default: the scene's current time)");
  CLI::Option* time = eval_cmd->add_option("--time", eval.time, "Time in seconds to evaluate at");
  frame->excludes(time);
  eval_cmd->add_option("--clip", eval.clip, "Animation clip to play, by name or index (default: the scene's active clip)");
  eval_cmd->add_flag("--json", eval.json,
                     "Print {\"frame\", \"time\", \"nodes\": {NAME: {\"t\", \"q\", \"s\"}}} (world space)");

  ImportArgs import;
  CLI::App* import_cmd = app.add_subcommand("import", "Import a character (.glb, .gltf) or motion (.bvh) into a scene file");
  import_cmd->add_option("CHARACTER", import.input, "File to import (.glb, .gltf, .bvh)")->required();
  import_cmd->add_option("-o,--output", import.output, "Scene file to write (.rigel)")->required();
  import_cmd->add_option("--scale", import.scale, "Multiply lengths by this (e.g. 0.0254: inches to metres); default 1, units kept");
  import_cmd->add_flag("--skip-end-sites", import.skip_end_sites, "Do not create joints for BVH End Sites (.bvh only)");
  import_cmd->add_flag("--json", import.json, "Print a JSON summary on stdout");

  ExportArgs export_args;
  CLI::App* export_cmd = app.add_subcommand("export", "Export a scene's skeleton, meshes, skins and animation to glTF 2.0");
  export_cmd->add_option("SCENE", export_args.scene, "Scene file (.rigel)")->required();
  export_cmd->add_option("-o,--output", export_args.output, "File to write (.glb binary, .gltf JSON)")->required();
  export_cmd->add_option("--frames", export_args.frames, "Bake frames FIRST:LAST (scene frames) instead of writing curves");
  export_cmd->add_flag("--bake", export_args.bake,
                       "Bake every frame even when the animation can be written as it is (default range: the keys')");
  export_cmd->add_flag("--json", export_args.json, "Print a JSON report on stdout");

  BakeArgs bake;
  CLI::App* bake_cmd = app.add_subcommand("bake", "Bake what the rigs make nodes do into keys on the nodes (every joint by default)");
  bake_cmd->footer("Examples:\n  rigel bake shot.rigel --frames 0:120 -o baked.rigel\n"
                   "  rigel bake shot.rigel --frames 1:48 --nodes upper_arm.L,forearm.L,hand.L -o arm_baked.rigel");
  bake_cmd->add_option("SCENE", bake.scene, "Scene file (.rigel)")->required();
  bake_cmd->add_option("--frames", bake.frames, "FIRST:LAST, scene frames")->required();
  bake_cmd->add_option("--nodes", bake.nodes, "Transforms to bake (default: every joint)")->delimiter(',');
  bake_cmd->add_option("-o,--output", bake.output, "Scene file to write (.rigel)")->required();
  bake_cmd->add_flag("--json", bake.json, "Print a JSON report on stdout");

  // `ephemeral setup|relations|key|keys|scope|merge|unmerge`.
  rigel::cli::EphemeralCommands ephemeral;
  rigel::cli::add_ephemeral_commands(app, ephemeral);
  // `pose`: one drag of an ephemeral or a built rig's controls.
  rigel::cli::PoseArgs pose;
  rigel::cli::add_pose_command(app, pose);
  // `validate`, `components`, `schema`, `diff`: rig definitions.
  rigel::cli::DefinitionCommands definition;
  rigel::cli::add_definition_commands(app, definition);
  // `build`, `update`, `rigs`, `remove`, `address`: built rigs.
  rigel::cli::RigCommands rig;
  rigel::cli::add_rig_commands(app, rig);
  // `serve`: the web app and the JSON API.
  rigel::cli::ServeArgs serve;
  CLI::App* serve_cmd = rigel::cli::add_serve_command(app, serve);

  // Examples for the commands whose files do not set their own.
  const std::pair<std::vector<const char*>, const char*> examples[] = {
      {{"inspect"}, "Examples:\n  rigel inspect hero.rigel\n  rigel inspect hero.rigel --json | jq '.nodes | length'"},
      {{"eval"}, "Examples:\n  rigel eval walk.rigel --frame 12\n  rigel eval hero.glb.rigel --time 0.5 --clip Run --json"},
      {{"import"}, "Examples:\n  rigel import tests/data/gltf/rigify_human_metarig.glb -o human.rigel\n"
                   "  rigel import walk.bvh --scale 0.0254 -o walk.rigel --json"},
      {{"export"}, "Examples:\n  rigel export hero.rigel -o hero.glb\n  rigel export shot.rigel -o shot.gltf --frames 0:120 --json"},
      {{"schema"}, "Examples:\n  rigel schema --json > rig.schema.json\n  rigel schema --xsd > rig.xsd"},
      {{"pose"}, "Examples:\n  rigel pose human.rigel --control hand.L --mode inverse --max-chain 3 --translate 0,0.15,0.1 -o posed.rigel\n"
                 "  rigel pose human.rigel --control spine.003 --select spine.004,spine.005 --mode forward --rotate 0,15,0 -o posed.rigel"},
      {{"ephemeral", "setup"}, "Examples:\n  rigel ephemeral setup tests/data/gltf/rigify_human_metarig.glb -o human.rigel\n"
                               "  rigel ephemeral setup walk.rigel --joints hips,spine,chest --shape-radius 0.05 -o walk_rig.rigel"},
      {{"ephemeral", "relations"}, "Examples:\n  rigel ephemeral relations human.rigel --json\n"
                                   "  rigel ephemeral relations human.rigel --add pair:hand.L_ctrl:hand.R_ctrl -o human2.rigel"},
      {{"ephemeral", "key"}, "Examples:\n  rigel ephemeral key human.rigel --control hand.L --frame 10 -o keyed.rigel\n"
                             "  rigel ephemeral key keyed.rigel --control hand.L --frame 10 --delete -o keyed.rigel"},
      {{"ephemeral", "keys"}, "Example:\n  rigel ephemeral keys keyed.rigel --control hand.L --json"},
      {{"ephemeral", "scope"}, "Examples:\n  rigel ephemeral scope human.rigel --rig ephemeralRig\n"
                               "  rigel ephemeral scope human.rigel --rig ephemeralRig --set controls -o human2.rigel"},
      {{"ephemeral", "merge"}, "Example:\n  rigel ephemeral merge scene.rigel --rigs hero_rig,sword_rig --carrier hand.R_ctrl --carried sword_rig -o merged.rigel"},
      {{"ephemeral", "unmerge"}, "Example:\n  rigel ephemeral unmerge merged.rigel --rig sword_rig -o apart.rigel"},
  };
  for (const auto& [path, text] : examples) {
    CLI::App* cmd = &app;
    for (const char* name : path) cmd = cmd->get_subcommand(name);
    cmd->footer(text);
  }

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    int code = app.exit(e);
    return code == 0 ? 0 : kExitUsage;
  }
  try {
    if (*inspect_cmd) return run_inspect(inspect);
    if (*eval_cmd) return run_eval(eval);
    if (*import_cmd) return run_import(import);
    if (*export_cmd) return run_export(export_args);
    if (*bake_cmd) return run_bake(bake);
    if (const std::optional<int> code = rigel::cli::run_ephemeral_commands(ephemeral)) return *code;
    if (*pose.command) return rigel::cli::run_pose(pose);
    if (const std::optional<int> code = rigel::cli::run_definition_commands(definition)) return *code;
    if (const std::optional<int> code = rigel::cli::run_rig_commands(rig)) return *code;
    if (*serve_cmd) return rigel::cli::run_serve(serve);
  } catch (const std::exception& e) {
    // Nothing should throw past the library's Status results; if something
    // does, report it as an error instead of crashing.
    std::cerr << "rigel: internal error: " << e.what() << "\n";
    return kExitInvalidInput;
  }
  return kExitUsage;
}
