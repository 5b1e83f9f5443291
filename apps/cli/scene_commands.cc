// The scene-file commands of `rigel` (see scene_commands.h): inspect, eval,
// import, export, bake.

#include "scene_commands.h"

#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_util.h"
#include "rigel/app/scene_files.h"
#include "rigel/io/report.h"
#include "rigel/io/scene_file.h"
#include "rigel/math/transform.h"

namespace rigel::cli {
namespace {

using graph::NodeId;

std::string vec(double x, double y, double z) {
  char buffer[96];
  std::snprintf(buffer, sizeof buffer, "(%.6g, %.6g, %.6g)", x, y, z);
  return buffer;
}

void print_json(const nlohmann::ordered_json& j) { std::cout << j.dump(2) << "\n"; }

// --eval: the evaluation the command runs the scene with (CLI11 has checked
// the name). The scene is evaluated once here, so a compiled program exists
// before the command's own evaluations (a bake's pulls, inside its
// transaction, use the program when it is current).
void use_evaluation(scene::Scene& s, const std::string& name) {
  if (auto evaluation = graph::evaluation_from_name(name)) s.graph().set_evaluation(*evaluation);
  s.graph().evaluate_all();
}

// Adds --eval to a command that evaluates a scene.
void add_evaluation_option(CLI::App* command, std::string& target) {
  command
      ->add_option("--eval", target,
                   "Evaluation: compiled (the default: a program made from the graph) or interpreted (the reference; "
                   "the same values)")
      ->check(CLI::IsMember({"interpreted", "compiled"}))
      ->default_str("compiled");
}

// ---- inspect -----------------------------------------------------------------

struct InspectArgs {
  std::string scene;
  bool json = false;
};

int run_inspect(const InspectArgs& args) {
  auto scene = load(args.scene);
  if (!scene) return fail(scene.status());
  auto report = io::inspect_report(**scene);
  if (args.json) {
    std::cout << report.dump(2) << "\n";
    return 0;
  }
  scene::Scene& s = **scene;
  graph::Graph& g = s.graph();
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
  std::string evaluation = "compiled";  // --eval
  std::string scene;
  std::optional<double> frame;
  std::optional<double> time;
  std::optional<std::string> clip;
  bool json = false;
};

int run_eval(const EvalArgs& args) {
  // A non-finite --frame/--time is a bad option value, like --frame abc: a
  // usage error (exit 2), checked before the scene is read.
  if ((args.frame && !std::isfinite(*args.frame)) || (args.time && !std::isfinite(*args.time)))
    return usage_error(std::string(args.frame ? "--frame" : "--time") + " must be a finite number");
  auto scene = load(args.scene);
  if (!scene) return fail(scene.status());
  scene::Scene& s = **scene;
  use_evaluation(s, args.evaluation);
  if (args.frame) s.set_frame(*args.frame);
  if (args.time) s.graph().set_time(*args.time);
  // The clip that plays: --clip picks one of the scene's animClips (an
  // imported glTF's animations), by name or index.
  auto clip = app::play_clip(s, args.clip);
  if (!clip) {
    const Status& st = clip.status();
    return fail(st.with_context(args.scene + (st.field().empty() ? "" : ": --" + st.field())));
  }
  const std::optional<std::string>& clip_name = *clip;
  auto report = io::eval_report(s);
  if (clip_name) report["clip"] = *clip_name;
  if (args.json) {
    std::cout << report.dump() << "\n";
    return 0;
  }
  graph::Graph& g = s.graph();
  std::cout << "frame " << s.frame() << " (" << g.time() << " s)" << (clip_name ? ", clip '" + *clip_name + "'" : "")
            << ", world space:\n";
  for (NodeId id : s.hierarchy()) {
    const auto& t = report["nodes"][g.node(id)->name()];
    math::Quat q(t["q"][3].get<double>(), t["q"][0].get<double>(), t["q"][1].get<double>(), t["q"][2].get<double>());
    math::Vec3 r = math::to_degrees(math::quat_to_euler(q, math::RotateOrder::kXYZ));
    std::string name = std::string(2 * static_cast<std::size_t>(s.depth(id)), ' ') + g.node(id)->name();
    std::printf("  %-28s t %-36s r %-36s s %s\n", name.c_str(), vec(t["t"][0], t["t"][1], t["t"][2]).c_str(),
                vec(r.x(), r.y(), r.z()).c_str(), vec(t["s"][0], t["s"][1], t["s"][2]).c_str());
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

int run_import(const ImportArgs& args) {
  app::OpenOptions options;
  options.scale = args.scale;
  options.skip_end_sites = args.skip_end_sites;
  auto imported = app::import_character(args.input, options);
  if (!imported) {
    // A bad --scale is a bad option value (exit 2); the file's faults are 1.
    if (imported.status().field() == "scale") return usage_error("--scale must be a positive number");
    return fail(imported.status());
  }
  for (const std::string& w : imported->warnings) std::cerr << "rigel: warning: " << args.input << ": " << w << "\n";
  scene::Scene& s = *imported->scene;
  if (Status st = io::save_scene(s, args.output); !st) return fail(st);
  const std::size_t nodes = s.graph().node_count();
  const std::size_t joints = imported->joints, meshes = imported->meshes, clips = imported->clips;
  if (imported->motion) {
    if (args.json) {
      print_json({{"joints", joints}, {"frames", imported->frames}, {"fps", s.graph().fps()}, {"output", args.output}});
    } else {
      std::cerr << "rigel: imported " << joints << " joints, " << imported->frames << " frames at " << s.graph().fps()
                << " fps into " << args.output << "\n";
    }
  } else if (args.json) {
    print_json({{"nodes", nodes}, {"joints", joints}, {"meshes", meshes}, {"clips", clips}, {"output", args.output}});
  } else {
    std::cerr << "rigel: imported " << nodes << " nodes (" << joints << " joints, " << meshes << " meshes), " << clips
              << (clips == 1 ? " clip" : " clips") << " into " << args.output << "\n";
  }
  return 0;
}

// ---- export ------------------------------------------------------------------

struct ExportArgs {
  std::string evaluation = "compiled";  // --eval
  std::string scene;
  std::string output;
  std::string frames;  // "FIRST:LAST"; empty when not given
  bool bake = false;
  bool deform_only = false;
  bool json = false;
};

int run_export(const ExportArgs& args) {
  io::GltfExportOptions options;
  options.bake = args.bake;
  options.deform_only = args.deform_only;
  if (!args.frames.empty()) {
    options.frames = parse_frames(args.frames);
    if (!options.frames) return fail(error(ErrorCode::kInvalidArgument, "--frames '" + args.frames + "': " + kFramesExpected));
  }
  if (Status st = app::check_export_path(args.output); !st) return fail(st);
  auto scene = load(args.scene);
  if (!scene) return fail(scene.status());
  use_evaluation(**scene, args.evaluation);
  // Baking long ranges takes a while: show how far it got, on a terminal only.
  TerminalProgress progress("baking");
  options.progress = progress.callback();
  io::GltfExportReport report;
  const Status status = app::export_scene(**scene, args.output, options, &report);
  progress.finish();
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
  std::string evaluation = "compiled";  // --eval
  std::string scene;
  std::string frames;
  std::vector<std::string> nodes;  // empty: every joint
  std::string output;
  bool json = false;
};

int run_bake(const BakeArgs& args) {
  const auto frames = parse_frames(args.frames);
  if (!frames) return usage_error("--frames '" + args.frames + "': " + kFramesExpected);
  auto scene = load(args.scene);
  if (!scene) return fail(scene.status());
  use_evaluation(**scene, args.evaluation);
  TerminalProgress progress("baking");
  // A command line run has no undo: the bake's undo records (the key arrays
  // before and after) would stay in memory while the file is written.
  auto report = app::bake_nodes(**scene, frames->first, frames->second, args.nodes, progress.callback(), false);
  progress.finish();
  if (!report) {
    const Status& st = report.status();
    return fail(st.with_context(args.scene + (st.field().empty() ? "" : ": --" + st.field())));
  }
  if (Status st = io::save_scene(**scene, args.output); !st) return fail(st);
  if (args.json) {
    print_json({{"nodes", report->nodes},
                {"frames", report->frames},
                {"keys", report->keys},
                {"disconnected", report->disconnected},
                {"output", args.output}});
  } else {
    std::cerr << "rigel: baked " << report->nodes << " nodes over " << report->frames << " frames (" << report->keys
              << " keys; " << report->disconnected << " drivers disconnected) into " << args.output << "\n";
  }
  return 0;
}

}  // namespace

struct SceneCommands::State {
  CLI::App* inspect_cmd = nullptr;
  InspectArgs inspect;
  CLI::App* eval_cmd = nullptr;
  EvalArgs eval;
  CLI::App* import_cmd = nullptr;
  ImportArgs import;
  CLI::App* export_cmd = nullptr;
  ExportArgs export_args;
  CLI::App* bake_cmd = nullptr;
  BakeArgs bake;
};

SceneCommands::SceneCommands() : state_(std::make_unique<State>()) {}
SceneCommands::~SceneCommands() = default;

void add_scene_commands(CLI::App& app, SceneCommands& commands) {
  SceneCommands::State& s = commands.state();
  s.inspect_cmd = app.add_subcommand("inspect", "Print a scene's nodes, hierarchy and connections");
  s.inspect_cmd->footer("Examples:\n  rigel inspect hero.rigel\n  rigel inspect hero.rigel --json | jq '.nodes | length'");
  s.inspect_cmd->add_option("SCENE", s.inspect.scene, "Scene file (.rigel)")->required();
  s.inspect_cmd->add_flag("--json", s.inspect.json, "Print one JSON object instead of text");

  s.eval_cmd = app.add_subcommand("eval", "Evaluate a scene and print world transforms of every transform node");
  s.eval_cmd->footer("Examples:\n  rigel eval walk.rigel --frame 12\n  rigel eval hero.glb.rigel --time 0.5 --clip Run --json");
  s.eval_cmd->add_option("SCENE", s.eval.scene, "Scene file (.rigel)")->required();
  CLI::Option* frame = s.eval_cmd->add_option("--frame", s.eval.frame, "Frame to evaluate at (default: the scene's current time)");
  CLI::Option* time = s.eval_cmd->add_option("--time", s.eval.time, "Time in seconds to evaluate at");
  frame->excludes(time);
  s.eval_cmd->add_option("--clip", s.eval.clip, "Animation clip to play, by name or index (default: the scene's active clip)");
  add_evaluation_option(s.eval_cmd, s.eval.evaluation);
  s.eval_cmd->add_flag("--json", s.eval.json, "Print {\"frame\", \"time\", \"nodes\": {NAME: {\"t\", \"q\", \"s\"}}} (world space)");

  s.import_cmd = app.add_subcommand("import", "Import a character (.glb, .gltf) or motion (.bvh) into a scene file");
  s.import_cmd->footer("Examples:\n  rigel import tests/data/gltf/rigify_human_metarig.glb -o human.rigel\n"
                       "  rigel import walk.bvh --scale 0.0254 -o walk.rigel --json");
  s.import_cmd->add_option("CHARACTER", s.import.input, "File to import (.glb, .gltf, .bvh)")->required();
  s.import_cmd->add_option("-o,--output", s.import.output, "Scene file to write (.rigel)")->required();
  s.import_cmd->add_option("--scale", s.import.scale,
                           "Multiply lengths by this (e.g. 0.0254: inches to metres); default 1, units kept");
  s.import_cmd->add_flag("--skip-end-sites", s.import.skip_end_sites, "Do not create joints for BVH End Sites (.bvh only)");
  s.import_cmd->add_flag("--json", s.import.json, "Print a JSON summary on stdout");

  s.export_cmd = app.add_subcommand("export", "Export a scene's skeleton, meshes, skins and animation to glTF 2.0");
  s.export_cmd->footer("Examples:\n  rigel export hero.rigel -o hero.glb\n  rigel export shot.rigel -o shot.gltf --frames 0:120 --json\n"
                       "  rigel export shot.rigel -o game.glb --deform-only --frames 0:200   # the skinned skeleton and mesh only");
  s.export_cmd->add_option("SCENE", s.export_args.scene, "Scene file (.rigel)")->required();
  s.export_cmd->add_option("-o,--output", s.export_args.output, "File to write (.glb binary, .gltf JSON)")->required();
  s.export_cmd->add_option("--frames", s.export_args.frames, "Bake frames FIRST:LAST (scene frames) instead of writing curves");
  s.export_cmd->add_flag("--bake", s.export_args.bake,
                         "Bake every frame even when the animation can be written as it is (default range: the keys')");
  s.export_cmd->add_flag("--deform-only", s.export_args.deform_only,
                         "Only the deform skeleton (the skins' joints) and the meshes, baked: no controls, rig nodes or "
                         "helper joints (for game engines)");
  add_evaluation_option(s.export_cmd, s.export_args.evaluation);
  s.export_cmd->add_flag("--json", s.export_args.json, "Print a JSON report on stdout");

  s.bake_cmd = app.add_subcommand("bake", "Bake what the rigs make nodes do into keys on the nodes (every joint by default)");
  s.bake_cmd->footer("Examples:\n  rigel bake shot.rigel --frames 0:120 -o baked.rigel\n"
                     "  rigel bake shot.rigel --frames 1:48 --nodes upper_arm.L,forearm.L,hand.L -o arm_baked.rigel");
  s.bake_cmd->add_option("SCENE", s.bake.scene, "Scene file (.rigel)")->required();
  s.bake_cmd->add_option("--frames", s.bake.frames, "FIRST:LAST, scene frames")->required();
  s.bake_cmd->add_option("--nodes", s.bake.nodes, "Transforms to bake (default: every joint)")->delimiter(',');
  s.bake_cmd->add_option("-o,--output", s.bake.output, "Scene file to write (.rigel)")->required();
  add_evaluation_option(s.bake_cmd, s.bake.evaluation);
  s.bake_cmd->add_flag("--json", s.bake.json, "Print a JSON report on stdout");
}

std::optional<int> run_scene_commands(const SceneCommands& commands) {
  const SceneCommands::State& s = commands.state();
  if (*s.inspect_cmd) return run_inspect(s.inspect);
  if (*s.eval_cmd) return run_eval(s.eval);
  if (*s.import_cmd) return run_import(s.import);
  if (*s.export_cmd) return run_export(s.export_args);
  if (*s.bake_cmd) return run_bake(s.bake);
  return std::nullopt;
}

}  // namespace rigel::cli
