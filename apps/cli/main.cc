// The rigel command line: a thin driver over the library (STYLE.md §8).
// Exit status: 0 success, 1 invalid input, 2 usage error (DESIGN.md).

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <cstdio>
#include <iostream>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "rigel/ephemeral/keying.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/ephemeral/session.h"
#include "rigel/io/bvh_import.h"
#include "rigel/io/gltf_export.h"
#include "rigel/io/gltf_import.h"
#include "rigel/io/report.h"
#include "rigel/io/scene_file.h"
#include "rigel/math/transform.h"
#include "rigel/ops/anim/clips.h"
#include "rigel/scene/transform_types.h"

namespace {

using rigel::Status;
using rigel::graph::NodeId;

constexpr int kExitInvalidInput = 1;
constexpr int kExitUsage = 2;

int fail(const Status& status) {
  std::cerr << "rigel: " << status.message() << "\n";
  return kExitInvalidInput;
}

// Every .rigel file is read over ephemeral::default_registry() (the ops types
// plus ephemeralRig), so scenes holding an ephemeral rig load everywhere.
rigel::Result<std::unique_ptr<rigel::scene::Scene>> load(const std::string& path) {
  return rigel::io::load_scene(path, rigel::ephemeral::default_registry());
}

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

// One finite number filling all of [begin, end); nullopt for anything else.
std::optional<double> parse_number(const char* begin, const char* end) {
  double value = 0.0;
  const auto [ptr, ec] = std::from_chars(begin, end, value);
  if (ec != std::errc() || ptr != end || begin == end || !std::isfinite(value)) return std::nullopt;
  return value;
}

// "X,Y,Z" as three finite numbers; nullopt for anything else.
std::optional<rigel::math::Vec3> parse_vec3(const std::string& text) {
  rigel::math::Vec3 v;
  std::size_t start = 0;
  for (int i = 0; i < 3; ++i) {
    const std::size_t comma = i < 2 ? text.find(',', start) : text.size();
    if (comma == std::string::npos) return std::nullopt;
    const auto number = parse_number(text.data() + start, text.data() + comma);
    if (!number) return std::nullopt;
    v[i] = *number;
    start = comma + 1;
  }
  return v;
}

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
};

// A .glb / .gltf character: joints, meshes, skins and every animation as a clip.
int run_import_gltf(const ImportArgs& args) {
  rigel::io::GltfImportOptions options;
  options.scale = args.scale;
  auto scene = rigel::io::import_gltf(args.input, options);
  if (!scene) return fail(scene.status());
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
  std::cerr << "rigel: imported " << g.node_count() << " nodes (" << joints << " joints, " << meshes << " meshes), " << clips
            << (clips == 1 ? " clip" : " clips") << " into " << args.output << "\n";
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
  std::cerr << "rigel: imported " << file->joints.size() << " joints, " << file->frame_count << " frames at "
            << (*scene)->graph().fps() << " fps into " << args.output << "\n";
  return 0;
}

// ---- export ------------------------------------------------------------------

struct ExportArgs {
  std::string scene;
  std::string output;
  std::string frames;  // "FIRST:LAST"; empty when not given
  bool bake = false;
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
  if (isatty(STDERR_FILENO)) {
    options.progress = [&progress_shown, last = -1](double fraction) mutable {
      const int percent = static_cast<int>(fraction * 100.0);
      if (percent == last) return;
      last = percent;
      progress_shown = true;
      std::fprintf(stderr, "\rrigel: baking %3d%%", percent);
      std::fflush(stderr);
    };
  }
  rigel::io::GltfExportReport report;
  const Status status = rigel::io::export_gltf(**scene, args.output, options, &report);
  if (progress_shown) std::fputc('\n', stderr);
  if (!status) return fail(status);
  if (report.baked) {
    std::cerr << "rigel: note: baked frames " << report.first_frame << " to " << report.last_frame << " at "
              << (*scene)->graph().fps() << " fps: " << report.bake_reason << "\n";
  }
  for (const std::string& note : report.notes) std::cerr << "rigel: note: " << note << "\n";
  std::cerr << "rigel: exported " << report.node_count << " nodes, " << report.mesh_count << " meshes, "
            << report.skin_count << " skins, " << report.animation_count << " animations (" << report.channel_count
            << " channels) to " << args.output << "\n";
  return 0;
}

// ---- ephemeral setup -----------------------------------------------------------

struct EphemeralSetupArgs {
  std::string scene;
  std::string output;
  std::vector<std::string> joints;
  std::string suffix = "_ctrl";
  std::string rig_name = "ephemeralRig";
  bool drop_animation = false;
  double shape_radius = 0.0;
  bool json = false;
};

// A .rigel scene, or a character (.glb, .gltf, .bvh) imported as `rigel
// import` does (units kept); either way over ephemeral::default_registry().
rigel::Result<std::unique_ptr<rigel::scene::Scene>> load_or_import(const std::string& path) {
  const std::string ext = lower_extension(path);
  // The importers build over ops::default_registry(), which has no
  // ephemeralRig type: carry the scene over through its file text.
  auto reload = [&](rigel::Result<std::unique_ptr<rigel::scene::Scene>> imported)
      -> rigel::Result<std::unique_ptr<rigel::scene::Scene>> {
    if (!imported) return imported.status();
    return rigel::io::parse_scene(rigel::io::write_scene(**imported), path, rigel::ephemeral::default_registry());
  };
  if (ext == ".glb" || ext == ".gltf") return reload(rigel::io::import_gltf(path));
  if (ext == ".bvh") {
    auto file = rigel::io::load_bvh(path);
    if (!file) return file.status();
    return reload(rigel::io::import_bvh(*file));
  }
  return load(path);
}

int run_ephemeral_setup(const EphemeralSetupArgs& args) {
  if (!(args.shape_radius >= 0.0) || !std::isfinite(args.shape_radius)) {
    std::cerr << "rigel: --shape-radius must be a number >= 0\n";
    return kExitUsage;
  }
  if (!rigel::graph::Graph::is_valid_name("joint" + args.suffix)) {
    std::cerr << "rigel: --suffix '" << args.suffix << "': control names would not be valid node names\n";
    return kExitUsage;
  }
  if (!rigel::graph::Graph::is_valid_name(args.rig_name)) {
    std::cerr << "rigel: --rig-name '" << args.rig_name << "': not a valid node name\n";
    return kExitUsage;
  }
  for (const std::string& name : args.joints) {
    if (name.empty()) {
      std::cerr << "rigel: --joints: empty joint name (expected A,B,...)\n";
      return kExitUsage;
    }
  }
  auto scene = load_or_import(args.scene);
  if (!scene) return fail(scene.status());
  rigel::scene::Scene& s = **scene;
  rigel::graph::Graph& g = s.graph();
  rigel::ephemeral::SetupOptions options;
  options.control_suffix = args.suffix;
  options.rig_name = args.rig_name;
  options.keep_animation = !args.drop_animation;
  options.shape_radius = args.shape_radius;
  for (const std::string& name : args.joints) {
    const NodeId id = g.find(name);
    if (!id.is_valid()) return fail(Status(rigel::ErrorCode::kNotFound, args.scene + ": --joints: no node named '" + name + "'"));
    options.joints.push_back(id);
  }
  auto result = rigel::ephemeral::setup_ephemeral(s, options);
  if (!result) return fail(result.status().with_context(args.scene));
  if (Status st = rigel::io::save_scene(s, args.output); !st) return fail(st);
  const std::string rig = g.node(result->rig)->name();
  if (args.json) {
    nlohmann::ordered_json out;
    out["rig"] = rig;
    out["controls"] = nlohmann::ordered_json::array();
    out["joints"] = nlohmann::ordered_json::array();
    for (NodeId id : result->controls) out["controls"].push_back(g.node(id)->name());
    for (NodeId id : result->joints) out["joints"].push_back(g.node(id)->name());
    std::cout << out.dump() << "\n";
  }
  std::cerr << "rigel: ephemeral rig '" << rig << "': " << result->controls.size()
            << (result->controls.size() == 1 ? " control" : " controls") << " into " << args.output << "\n";
  return 0;
}

// ---- ephemeral: names, keys and scopes (shared by pose and the key commands) ----

// `name` given to `option` as a control (a joint stands for its control).
rigel::Result<NodeId> resolve_control(const rigel::graph::Graph& g, const std::string& scene, const std::string& option,
                                      const std::string& name) {
  const NodeId id = g.find(name);
  if (!id.is_valid()) return Status(rigel::ErrorCode::kNotFound, scene + ": " + option + ": no node named '" + name + "'");
  const NodeId control = rigel::ephemeral::control_of(g, id);
  if (!control.is_valid()) {
    return Status(rigel::ErrorCode::kInvalidArgument, scene + ": " + option + ": '" + name +
                                                          "' is not a control of an ephemeral rig (nor a joint driven by one)");
  }
  return control;
}

// `name` given to `option` as an ephemeralRig node.
rigel::Result<NodeId> resolve_rig(const rigel::graph::Graph& g, const std::string& scene, const std::string& option,
                                  const std::string& name) {
  const NodeId id = g.find(name);
  std::string rigs;
  for (NodeId r : rigel::ephemeral::rigs_find(g)) rigs += (rigs.empty() ? "" : ", ") + g.node(r)->name();
  const std::string known = rigs.empty() ? "the scene has no ephemeral rig" : "rigs: " + rigs;
  if (!id.is_valid())
    return Status(rigel::ErrorCode::kNotFound, scene + ": " + option + ": no ephemeral rig named '" + name + "' (" + known + ")");
  if (g.node(id)->type().name() != rigel::ephemeral::kRigType) {
    return Status(rigel::ErrorCode::kInvalidArgument,
                  scene + ": " + option + ": '" + name + "' is not an ephemeralRig node (" + known + ")");
  }
  return id;
}

// A key time in seconds as a frame, rounded to 1e-6 frame so that frame 10
// at 24 fps prints 10, not 10.000000000000002.
double frame_of(const rigel::graph::Graph& g, double seconds) {
  return std::round(seconds * g.fps() * 1e6) / 1e6;
}

std::string number_text(double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%g", value);
  return buffer;
}

// The rigs of `controls`, first appearance order.
std::vector<NodeId> rigs_of(const rigel::graph::Graph& g, const std::vector<NodeId>& controls) {
  std::vector<NodeId> out;
  for (NodeId c : controls) {
    const NodeId rig = rigel::ephemeral::rig_of(g, c);
    if (rig.is_valid() && std::find(out.begin(), out.end(), rig) == out.end()) out.push_back(rig);
  }
  return out;
}

// "RIG=SCOPE, ..." and {RIG: SCOPE} for `rigs`.
std::string scopes_text(const rigel::graph::Graph& g, const std::vector<NodeId>& rigs) {
  std::string text;
  for (NodeId r : rigs)
    text += (text.empty() ? "" : ", ") + g.node(r)->name() + "=" + rigel::ephemeral::key_scope_name(rigel::ephemeral::key_scope(g, r));
  return text;
}
nlohmann::ordered_json scopes_json(const rigel::graph::Graph& g, const std::vector<NodeId>& rigs) {
  nlohmann::ordered_json out = nlohmann::ordered_json::object();
  for (NodeId r : rigs) out[g.node(r)->name()] = rigel::ephemeral::key_scope_name(rigel::ephemeral::key_scope(g, r));
  return out;
}

nlohmann::ordered_json names_json(const rigel::graph::Graph& g, const std::vector<NodeId>& ids) {
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (NodeId id : ids) out.push_back(g.node(id)->name());
  return out;
}

// Key times of `controls`' keying set, as frames.
std::vector<double> key_frames(const rigel::graph::Graph& g, const std::vector<NodeId>& controls) {
  std::vector<double> frames;
  for (double t : rigel::ephemeral::key_times(g, controls)) frames.push_back(frame_of(g, t));
  return frames;
}

std::string frames_text(const std::vector<double>& frames) {
  if (frames.empty()) return "none";
  std::string text;
  for (double f : frames) text += (text.empty() ? "" : ", ") + number_text(f);
  return text;
}

int usage_error(const std::string& message) {
  std::cerr << "rigel: " << message << "\n";
  return kExitUsage;
}

// ---- pose --------------------------------------------------------------------

struct PoseArgs {
  std::string scene;
  std::string output;
  std::string control;
  std::string mode;
  std::optional<std::string> translate, rotate, scale, pivot;
  std::vector<std::string> select;
  std::optional<double> frame;
  std::optional<double> time;
  std::optional<double> magnet_fraction;
  std::optional<double> magnet_radius;
  std::optional<int> max_chain;
  bool auto_key = false;
  bool key = false;
  bool json = false;
};

int run_pose(const PoseArgs& args) {
  namespace eph = rigel::ephemeral;
  using rigel::math::Mat4;
  using rigel::math::Quat;
  using rigel::math::Vec3;
  // Usage errors first (exit 2), before the scene is read.
  const std::optional<eph::Mode> mode = eph::mode_from_name(args.mode);
  if (!mode) {
    std::string modes;
    for (int m = 0; m < eph::kModeCount; ++m)
      modes += std::string(m ? ", " : "") + eph::mode_name(static_cast<eph::Mode>(m));
    return usage_error("--mode '" + args.mode + "': unknown mode; modes: " + modes);
  }
  if ((args.frame && !std::isfinite(*args.frame)) || (args.time && !std::isfinite(*args.time)))
    return usage_error(std::string(args.frame ? "--frame" : "--time") + " must be a finite number");
  eph::Delta delta;
  std::optional<Vec3> pivot;
  struct VecOption {
    const char* name;
    const std::optional<std::string>& text;
  };
  for (const VecOption& o : {VecOption{"--translate", args.translate}, VecOption{"--rotate", args.rotate},
                             VecOption{"--scale", args.scale}, VecOption{"--pivot", args.pivot}}) {
    if (!o.text) continue;
    const std::optional<Vec3> v = parse_vec3(*o.text);
    if (!v) return usage_error(std::string(o.name) + " '" + *o.text + "': expected X,Y,Z, three numbers such as 0,1.5,-2");
    const std::string name = o.name;
    if (name == "--translate") {
      delta.translate = *v;
    } else if (name == "--rotate") {
      // Degrees, XYZ Euler: x applied first (rotation = Rz * Ry * Rx), world axes.
      const Vec3 r = *v * (std::numbers::pi / 180.0);
      delta.rotate = Quat(Eigen::AngleAxisd(r.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(r.y(), Vec3::UnitY()) *
                          Eigen::AngleAxisd(r.x(), Vec3::UnitX()));
    } else if (name == "--scale") {
      delta.scale = *v;
    } else {
      pivot = *v;
    }
  }
  eph::SessionOptions options;
  options.auto_key = args.auto_key;
  if (args.magnet_fraction) {
    if (!(*args.magnet_fraction > 0.0 && *args.magnet_fraction <= 1.0))
      return usage_error("--magnet-fraction must be a number in (0, 1]");
    options.magnet_fraction = *args.magnet_fraction;
  }
  if (args.magnet_radius) {
    if (!(*args.magnet_radius > 0.0) || !std::isfinite(*args.magnet_radius))
      return usage_error("--magnet-radius must be a positive number");
    options.magnet_radius = *args.magnet_radius;
  }
  if (args.max_chain) {
    if (*args.max_chain < 0) return usage_error("--max-chain must be 0 (no limit) or more");
    options.max_chain = *args.max_chain;
  }
  for (const std::string& name : args.select)
    if (name.empty()) return usage_error("--select: empty control name (expected A,B,...)");

  auto scene = load(args.scene);
  if (!scene) return fail(scene.status());
  rigel::scene::Scene& s = **scene;
  rigel::graph::Graph& g = s.graph();
  const std::vector<NodeId> rigs = eph::rigs_find(g);
  if (rigs.empty()) {
    return fail(Status(rigel::ErrorCode::kNotFound,
                       args.scene + ": the scene has no ephemeral rig; run `rigel ephemeral setup " + args.scene +
                           " -o OUT.rigel` first"));
  }
  if (pivot && *mode != eph::Mode::kBody)
    return fail(Status(rigel::ErrorCode::kInvalidArgument, "--pivot applies in body mode only (--mode body)"));
  if (args.frame) s.set_frame(*args.frame);
  if (args.time) g.set_time(*args.time);

  eph::Session session(s, options);
  session.set_mode(*mode);
  // Each name must be a control of an ephemeral rig, or a joint driven by one
  // (it stands for its control, as in Session::select).
  std::vector<NodeId> selection;
  NodeId primary;
  auto resolve = [&](const std::string& option, const std::string& name) -> std::optional<Status> {
    const NodeId id = g.find(name);
    if (!id.is_valid())
      return Status(rigel::ErrorCode::kNotFound, args.scene + ": " + option + ": no node named '" + name + "'");
    session.select({id});
    const std::vector<NodeId> grabbed = session.grabbed();
    if (grabbed.empty()) {
      return Status(rigel::ErrorCode::kInvalidArgument,
                    args.scene + ": " + option + ": '" + name + "' is not a control of an ephemeral rig (nor a joint driven by one)");
    }
    if (!primary.is_valid()) primary = grabbed.front();
    selection.push_back(id);
    return std::nullopt;
  };
  if (auto st = resolve("--control", args.control)) return fail(*st);
  for (const std::string& name : args.select)
    if (auto st = resolve("--select", name)) return fail(*st);
  session.select(selection);
  const std::vector<NodeId> grabbed = session.grabbed();
  if (*mode == eph::Mode::kBody) {
    // The motion is given for --control: the pivot is at it by default.
    Mat4 world = rigel::math::rigid_part(s.world_matrix(primary));
    if (pivot) world = rigel::math::translation_matrix(*pivot);
    session.set_body_pivot(world);
  }

  // Every control of every rig, before and after (world space).
  std::vector<NodeId> controls;
  for (NodeId rig : rigs)
    for (NodeId c : eph::rig_controls(g, rig)) controls.push_back(c);
  std::vector<Mat4> before;
  for (NodeId c : controls) before.push_back(s.world_matrix(c));
  // A keyed channel off its keys is refused (the message names the channel
  // and the frame) unless --auto-key.
  if (Status st = session.drag(delta); !st) {
    const int code = fail(st.with_context(args.scene + ": " + args.mode));
    if (!args.auto_key && st.message().find("auto-key") != std::string::npos) {
      std::cerr << "rigel: note: --auto-key keys the character at frame " << number_text(s.frame())
                << " first; or key it there with `rigel ephemeral key`\n";
    }
    return code;
  }
  session.release();
  // --key: key the grabbed controls' keying group at the pose time.
  std::vector<NodeId> key_set;
  if (args.key) {
    key_set = eph::keying_set(g, grabbed);
    if (Status st = eph::set_key(g, grabbed); !st) return fail(st.with_context(args.scene + ": --key"));
  }
  std::vector<NodeId> keyed;
  for (NodeId c : controls)
    if (eph::has_key_now(g, c)) keyed.push_back(c);
  const std::vector<NodeId> grabbed_rigs = rigs_of(g, grabbed);
  nlohmann::ordered_json moved = nlohmann::ordered_json::object();
  std::size_t moved_count = 0;
  for (std::size_t i = 0; i < controls.size(); ++i) {
    const Mat4 after = s.world_matrix(controls[i]);
    if (rigel::math::is_near(before[i], after, 1e-12)) continue;
    ++moved_count;
    const rigel::math::Decomposed d = rigel::math::decompose(after);
    const Quat& q = d.rotation;
    moved[g.node(controls[i])->name()] = {{"t", {d.translate.x(), d.translate.y(), d.translate.z()}},
                                          {"q", {q.x(), q.y(), q.z(), q.w()}}};
  }
  if (Status st = rigel::io::save_scene(s, args.output); !st) return fail(st);
  if (args.json) {
    nlohmann::ordered_json out;
    out["mode"] = eph::mode_name(*mode);
    out["frame"] = s.frame();
    out["grabbed"] = nlohmann::ordered_json::array();
    for (NodeId id : grabbed) out["grabbed"].push_back(g.node(id)->name());
    out["moved"] = std::move(moved);
    out["keyScope"] = scopes_json(g, grabbed_rigs);
    out["keyed"] = names_json(g, keyed);
    std::cout << out.dump() << "\n";
  }
  std::string names;
  for (NodeId id : grabbed) names += (names.empty() ? "" : ", ") + g.node(id)->name();
  std::cerr << "rigel: posed " << names << " (" << eph::mode_name(*mode) << ", frame " << s.frame() << "): "
            << moved_count << (moved_count == 1 ? " control" : " controls") << " moved; wrote " << args.output << "\n";
  std::cerr << "rigel: keying scope: " << scopes_text(g, grabbed_rigs);
  if (args.key) std::cerr << "; keyed " << key_set.size() << (key_set.size() == 1 ? " control" : " controls");
  std::cerr << "; " << keyed.size() << (keyed.size() == 1 ? " control has" : " controls have") << " a key at frame "
            << number_text(s.frame()) << "\n";
  return 0;
}

// ---- ephemeral key, keys, scope, merge, unmerge ----------------------------------

// A scene read for the key commands: it must hold an ephemeral rig.
rigel::Result<std::unique_ptr<rigel::scene::Scene>> load_rigged(const std::string& path) {
  auto scene = load(path);
  if (!scene) return scene.status();
  if (rigel::ephemeral::rigs_find((*scene)->graph()).empty()) {
    return Status(rigel::ErrorCode::kNotFound,
                  path + ": the scene has no ephemeral rig; run `rigel ephemeral setup " + path + " -o OUT.rigel` first");
  }
  return scene;
}

struct EphemeralKeyArgs {
  std::string scene;
  std::string output;
  std::vector<std::string> controls;
  std::optional<double> frame;
  std::optional<double> time;
  bool remove = false;
  bool json = false;
};

int run_ephemeral_key(const EphemeralKeyArgs& args) {
  namespace eph = rigel::ephemeral;
  if ((args.frame && !std::isfinite(*args.frame)) || (args.time && !std::isfinite(*args.time)))
    return usage_error(std::string(args.frame ? "--frame" : "--time") + " must be a finite number");
  for (const std::string& name : args.controls)
    if (name.empty()) return usage_error("--control: empty control name (expected A,B,...)");
  auto scene = load_rigged(args.scene);
  if (!scene) return fail(scene.status());
  rigel::scene::Scene& s = **scene;
  rigel::graph::Graph& g = s.graph();
  std::vector<NodeId> controls;
  for (const std::string& name : args.controls) {
    auto control = resolve_control(g, args.scene, "--control", name);
    if (!control) return fail(control.status());
    controls.push_back(*control);
  }
  if (args.frame) s.set_frame(*args.frame);
  if (args.time) g.set_time(*args.time);
  const std::vector<NodeId> set = eph::keying_set(g, controls);
  const Status st = args.remove ? eph::delete_key(g, controls) : eph::set_key(g, controls);
  if (!st) return fail(st.with_context(args.scene));
  if (Status saved = rigel::io::save_scene(s, args.output); !saved) return fail(saved);
  const std::vector<double> frames = key_frames(g, controls);
  if (args.json) {
    nlohmann::ordered_json out;
    out["frame"] = frame_of(g, g.time());
    out["keyed"] = names_json(g, set);
    out["times"] = frames;
    std::cout << out.dump() << "\n";
  }
  std::cerr << "rigel: " << (args.remove ? "deleted the keys of " : "keyed ") << set.size()
            << (set.size() == 1 ? " control" : " controls") << " at frame " << number_text(frame_of(g, g.time()))
            << " (keying scope: " << scopes_text(g, rigs_of(g, controls)) << "); key frames: " << frames_text(frames)
            << "; wrote " << args.output << "\n";
  return 0;
}

struct EphemeralKeysArgs {
  std::string scene;
  std::string control;
  bool json = false;
};

int run_ephemeral_keys(const EphemeralKeysArgs& args) {
  namespace eph = rigel::ephemeral;
  auto scene = load_rigged(args.scene);
  if (!scene) return fail(scene.status());
  const rigel::graph::Graph& g = (*scene)->graph();
  auto control = resolve_control(g, args.scene, "--control", args.control);
  if (!control) return fail(control.status());
  const NodeId rig = eph::rig_of(g, *control);
  const std::vector<NodeId> set = eph::keying_set(g, {*control});
  const std::vector<double> seconds = eph::key_times(g, {*control});
  const std::vector<double> frames = key_frames(g, {*control});
  if (args.json) {
    nlohmann::ordered_json out;
    out["control"] = g.node(*control)->name();
    out["rig"] = g.node(rig)->name();
    out["keyScope"] = eph::key_scope_name(eph::key_scope(g, rig));
    out["keyingSet"] = names_json(g, set);
    out["times"] = frames;
    out["seconds"] = seconds;
    std::cout << out.dump() << "\n";
    return 0;
  }
  std::cout << g.node(*control)->name() << ": rig " << g.node(rig)->name()
            << ", keying scope: " << eph::key_scope_name(eph::key_scope(g, rig)) << " (a key keys " << set.size()
            << (set.size() == 1 ? " control" : " controls") << ")\n";
  std::cout << "key frames: " << frames_text(frames) << " (" << g.fps() << " fps)\n";
  return 0;
}

struct EphemeralScopeArgs {
  std::string scene;
  std::string rig;
  std::optional<std::string> set;
  std::optional<std::string> output;
  bool json = false;
};

int run_ephemeral_scope(const EphemeralScopeArgs& args) {
  namespace eph = rigel::ephemeral;
  std::optional<eph::KeyScope> scope;
  if (args.set) {
    scope = eph::key_scope_from_name(*args.set);
    if (!scope) return usage_error("--set '" + *args.set + "': expected character or controls");
    if (!args.output) return usage_error("--set needs -o OUT (the scene to write)");
  } else if (args.output) {
    return usage_error("-o applies with --set only (without --set, scope prints the keying scope)");
  }
  auto scene = load_rigged(args.scene);
  if (!scene) return fail(scene.status());
  rigel::graph::Graph& g = (*scene)->graph();
  auto rig = resolve_rig(g, args.scene, "--rig", args.rig);
  if (!rig) return fail(rig.status());
  if (scope) {
    if (Status st = eph::set_key_scope(g, *rig, *scope); !st) return fail(st.with_context(args.scene));
    if (Status st = rigel::io::save_scene(**scene, *args.output); !st) return fail(st);
  }
  const char* name = eph::key_scope_name(eph::key_scope(g, *rig));
  if (args.json) {
    nlohmann::ordered_json out;
    out["rig"] = args.rig;
    out["keyScope"] = name;
    std::cout << out.dump() << "\n";
  } else if (!scope) {
    std::cout << args.rig << ": keying scope: " << name << "\n";
  }
  if (scope) std::cerr << "rigel: " << args.rig << ": keying scope: " << name << "; wrote " << *args.output << "\n";
  return 0;
}

struct EphemeralMergeArgs {
  std::string scene;
  std::string output;
  std::vector<std::string> rigs;
  std::optional<std::string> carrier;
  std::optional<std::string> carried;
  bool json = false;
};

int run_ephemeral_merge(const EphemeralMergeArgs& args) {
  namespace eph = rigel::ephemeral;
  for (const std::string& name : args.rigs)
    if (name.empty()) return usage_error("--rigs: empty rig name (expected A,B,...)");
  if (args.rigs.size() < 2) return usage_error("--rigs: name two rigs or more (A,B,...)");
  if (args.carrier.has_value() != args.carried.has_value())
    return usage_error("--carrier CONTROL and --carried RIG go together");
  auto scene = load_rigged(args.scene);
  if (!scene) return fail(scene.status());
  rigel::graph::Graph& g = (*scene)->graph();
  std::vector<NodeId> rigs;
  for (const std::string& name : args.rigs) {
    auto rig = resolve_rig(g, args.scene, "--rigs", name);
    if (!rig) return fail(rig.status());
    rigs.push_back(*rig);
  }
  NodeId carrier, carried;
  if (args.carrier) {
    auto c = resolve_control(g, args.scene, "--carrier", *args.carrier);
    if (!c) return fail(c.status());
    auto r = resolve_rig(g, args.scene, "--carried", *args.carried);
    if (!r) return fail(r.status());
    carrier = *c;
    carried = *r;
  }
  if (Status st = eph::merge_characters(g, rigs); !st) return fail(st.with_context(args.scene));
  if (carried.is_valid()) {
    if (Status st = eph::set_carrier(g, carried, carrier); !st) return fail(st.with_context(args.scene + ": --carrier"));
  }
  if (Status st = rigel::io::save_scene(**scene, args.output); !st) return fail(st);
  const std::vector<NodeId> group = eph::merged_rigs(g, rigs.front());
  if (args.json) {
    nlohmann::ordered_json out;
    out["merged"] = names_json(g, group);
    out["carriers"] = nlohmann::ordered_json::object();
    for (NodeId r : group)
      if (const NodeId c = eph::carrier_of(g, r); c.is_valid()) out["carriers"][g.node(r)->name()] = g.node(c)->name();
    std::cout << out.dump() << "\n";
  }
  std::string names;
  for (NodeId r : group) names += (names.empty() ? "" : ", ") + g.node(r)->name();
  std::cerr << "rigel: merged " << names;
  if (carried.is_valid()) std::cerr << "; " << g.node(carrier)->name() << " carries " << g.node(carried)->name();
  std::cerr << "; wrote " << args.output << "\n";
  return 0;
}

struct EphemeralUnmergeArgs {
  std::string scene;
  std::string output;
  std::string rig;
  bool json = false;
};

int run_ephemeral_unmerge(const EphemeralUnmergeArgs& args) {
  namespace eph = rigel::ephemeral;
  auto scene = load_rigged(args.scene);
  if (!scene) return fail(scene.status());
  rigel::graph::Graph& g = (*scene)->graph();
  auto rig = resolve_rig(g, args.scene, "--rig", args.rig);
  if (!rig) return fail(rig.status());
  std::vector<NodeId> others;
  for (NodeId r : eph::merged_rigs(g, *rig))
    if (r != *rig) others.push_back(r);
  if (Status st = eph::unmerge_character(g, *rig); !st) return fail(st.with_context(args.scene));
  if (Status st = rigel::io::save_scene(**scene, args.output); !st) return fail(st);
  if (args.json) {
    nlohmann::ordered_json out;
    out["rig"] = args.rig;
    out["unmergedFrom"] = names_json(g, others);
    std::cout << out.dump() << "\n";
  }
  std::string names;
  for (NodeId r : others) names += (names.empty() ? "" : ", ") + g.node(r)->name();
  std::cerr << "rigel: " << args.rig << (others.empty() ? " was not merged" : " unmerged from " + names) << "; wrote "
            << args.output << "\n";
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

  ExportArgs export_args;
  CLI::App* export_cmd = app.add_subcommand("export", "Export a scene's skeleton, meshes, skins and animation to glTF 2.0");
  export_cmd->add_option("SCENE", export_args.scene, "Scene file (.rigel)")->required();
  export_cmd->add_option("-o,--output", export_args.output, "File to write (.glb binary, .gltf JSON)")->required();
  export_cmd->add_option("--frames", export_args.frames, "Bake frames FIRST:LAST (scene frames) instead of writing curves");
  export_cmd->add_flag("--bake", export_args.bake,
                       "Bake every frame even when the animation can be written as it is (default range: the keys')");

  EphemeralSetupArgs setup;
  CLI::App* ephemeral_cmd = app.add_subcommand(
      "ephemeral",
      "Ephemeral rigs: one control per joint (setup), keys and keying scope (key, keys, scope), merged characters "
      "(merge, unmerge); posed with `rigel pose`");
  ephemeral_cmd->require_subcommand(1);
  CLI::App* setup_cmd = ephemeral_cmd->add_subcommand(
      "setup", "Give joints a control each (mirroring the joint hierarchy) and an ephemeralRig node relating them");
  setup_cmd->add_option("SCENE", setup.scene, "Scene file (.rigel), or a character to import first (.glb, .gltf, .bvh)")
      ->required();
  setup_cmd->add_option("-o,--output", setup.output, "Scene file to write (.rigel)")->required();
  setup_cmd->add_option("--joints", setup.joints, "Joints to rig, by name: A,B,... (default: every joint)")
      ->delimiter(',')
      ->allow_extra_args(false);
  setup_cmd->add_option("--suffix", setup.suffix, "Control name = joint name + this (default _ctrl)");
  setup_cmd->add_option("--rig-name", setup.rig_name,
                        "Name of the ephemeralRig node (default ephemeralRig; a taken name gets a number). Give a "
                        "second character (a prop set up with --joints) its own name");
  setup_cmd->add_flag("--drop-animation", setup.drop_animation,
                      "Break the animation connections into the joints, keeping the current pose (default: they move "
                      "onto the controls)");
  setup_cmd->add_option("--shape-radius", setup.shape_radius,
                        "Radius of each control's circle, in its own space (default 0: no shape)");
  setup_cmd->add_flag("--json", setup.json,
                      "Print {\"rig\", \"controls\": [NAME...], \"joints\": [NAME...]} (controls[i] drives joints[i])");

  EphemeralKeyArgs key;
  CLI::App* key_cmd = ephemeral_cmd->add_subcommand(
      "key", "Key controls at a frame (their keying group: the whole character unless its scope is controls)");
  key_cmd->add_option("SCENE", key.scene, "Scene file with an ephemeral rig (.rigel)")->required();
  key_cmd->add_option("-o,--output", key.output, "Scene file to write (.rigel)")->required();
  key_cmd->add_option("--control", key.controls, "Controls to key: A,B,... (a joint name stands for its control)")
      ->required()
      ->delimiter(',')
      ->allow_extra_args(false);
  CLI::Option* key_frame = key_cmd->add_option("--frame", key.frame, "Frame to key at (default: the scene's current time)");
  CLI::Option* key_time = key_cmd->add_option("--time", key.time, "Time in seconds to key at");
  key_frame->excludes(key_time);
  key_cmd->add_flag("--delete", key.remove, "Delete the keys of the keying group at that frame instead");
  key_cmd->add_flag("--json", key.json,
                    "Print {\"frame\", \"keyed\": [NAME...] (the keying group), \"times\": [FRAME...] (its key frames "
                    "after the edit)}");

  EphemeralKeysArgs keys;
  CLI::App* keys_cmd = ephemeral_cmd->add_subcommand(
      "keys", "Print a control's keying scope and the key frames of its keying group (reads only)");
  keys_cmd->add_option("SCENE", keys.scene, "Scene file with an ephemeral rig (.rigel)")->required();
  keys_cmd->add_option("--control", keys.control, "The control (a joint name stands for its control)")->required();
  keys_cmd->add_flag("--json", keys.json,
                     "Print {\"control\", \"rig\", \"keyScope\", \"keyingSet\": [NAME...], \"times\": [FRAME...], "
                     "\"seconds\": [S...]}");

  EphemeralScopeArgs scope;
  CLI::App* scope_cmd = ephemeral_cmd->add_subcommand(
      "scope", "Print a rig's keying scope, or set it (character: a key keys the whole character; controls: only "
               "the controls named)");
  scope_cmd->add_option("SCENE", scope.scene, "Scene file with an ephemeral rig (.rigel)")->required();
  scope_cmd->add_option("--rig", scope.rig, "The ephemeralRig node, by name (default name: ephemeralRig)")->required();
  scope_cmd->add_option("--set", scope.set, "character or controls (needs -o)");
  scope_cmd->add_option("-o,--output", scope.output, "Scene file to write (.rigel; with --set only)");
  scope_cmd->add_flag("--json", scope.json, "Print {\"rig\", \"keyScope\"}");

  EphemeralMergeArgs merge;
  CLI::App* merge_cmd = ephemeral_cmd->add_subcommand(
      "merge", "Merge characters: they move together in body mode and share keys; optionally a control of one carries another");
  merge_cmd->add_option("SCENE", merge.scene, "Scene file with ephemeral rigs (.rigel)")->required();
  merge_cmd->add_option("-o,--output", merge.output, "Scene file to write (.rigel)")->required();
  merge_cmd->add_option("--rigs", merge.rigs, "ephemeralRig nodes to merge, by name: A,B,... (two or more)")
      ->required()
      ->delimiter(',')
      ->allow_extra_args(false);
  merge_cmd->add_option("--carrier", merge.carrier,
                        "A control (of another merged character) that carries --carried's root controls, e.g. a hand");
  merge_cmd->add_option("--carried", merge.carried, "The rig that --carrier carries, e.g. a prop");
  merge_cmd->add_flag("--json", merge.json, "Print {\"merged\": [RIG...], \"carriers\": {RIG: CONTROL}}");

  EphemeralUnmergeArgs unmerge;
  CLI::App* unmerge_cmd = ephemeral_cmd->add_subcommand(
      "unmerge", "Take a character out of its merge group (clears carriers into and out of it; keys are kept)");
  unmerge_cmd->add_option("SCENE", unmerge.scene, "Scene file with ephemeral rigs (.rigel)")->required();
  unmerge_cmd->add_option("-o,--output", unmerge.output, "Scene file to write (.rigel)")->required();
  unmerge_cmd->add_option("--rig", unmerge.rig, "The ephemeralRig node, by name")->required();
  unmerge_cmd->add_flag("--json", unmerge.json, "Print {\"rig\", \"unmergedFrom\": [RIG...]}");

  PoseArgs pose;
  CLI::App* pose_cmd = app.add_subcommand(
      "pose", "Grab controls of an ephemeral rig, move them in a mode (forward, inverse, ...) and write the scene");
  pose_cmd->add_option("SCENE", pose.scene, "Scene file with an ephemeral rig (.rigel; see `rigel ephemeral setup`)")
      ->required();
  pose_cmd->add_option("-o,--output", pose.output, "Scene file to write (.rigel)")->required();
  pose_cmd->add_option("--control", pose.control,
                       "The control the motion is given for (a joint name stands for its control)")
      ->required();
  pose_cmd->add_option("--mode", pose.mode,
                       "forward, suspended, pseudo-inverse, pseudo-inverse-length, inverse, magnet, magnet-radius, "
                       "body (docs/EPHEMERAL.md)")
      ->required();
  pose_cmd->add_option("--translate", pose.translate, "World-space translation X,Y,Z in scene units");
  pose_cmd->add_option("--rotate", pose.rotate,
                       "World-space rotation X,Y,Z in degrees, XYZ Euler (x applied first: rotation = Rz*Ry*Rx), about "
                       "each grabbed control's own pivot (body mode: the body pivot)");
  pose_cmd->add_option("--select", pose.select, "More controls grabbed with --control: A,B,... (all move together)")
      ->delimiter(',')
      ->allow_extra_args(false);
  CLI::Option* pose_frame = pose_cmd->add_option("--frame", pose.frame, "Frame to pose at (default: the scene's current time)");
  CLI::Option* pose_time = pose_cmd->add_option("--time", pose.time, "Time in seconds to pose at");
  pose_frame->excludes(pose_time);
  pose_cmd->add_option("--scale", pose.scale, "Body mode: scale X,Y,Z about the body pivot, in its axes");
  pose_cmd->add_option("--pivot", pose.pivot,
                       "Body mode: the body pivot's world position X,Y,Z, world axes (default: --control's position and axes)");
  pose_cmd->add_option("--magnet-fraction", pose.magnet_fraction, "Magnet mode: share of the motion per hop (default 0.65)");
  pose_cmd->add_option("--magnet-radius", pose.magnet_radius, "Magnet-radius mode: world distance of the falloff (default 1)");
  pose_cmd->add_option("--max-chain", pose.max_chain,
                       "Inverse modes: most controls in a chain, grabbed and top included (default 0: to a branch or root)");
  pose_cmd->add_flag("--auto-key", pose.auto_key,
                     "A keyed control moved off its keys keys its keying group at this frame first (default: refused)");
  pose_cmd->add_flag("--key", pose.key,
                     "After the motion, key the grabbed controls at this frame (their keying group: the whole "
                     "character unless its keying scope is controls)");
  pose_cmd->add_flag("--json", pose.json,
                     "Print {\"mode\", \"frame\", \"grabbed\": [NAME...], \"moved\": {NAME: {\"t\", \"q\"}}, "
                     "\"keyScope\": {RIG: SCOPE}, \"keyed\": [NAME...]} (moved: world space, every control whose world "
                     "matrix changed; keyed: controls with a key at this frame)");

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
    if (*setup_cmd) return run_ephemeral_setup(setup);
    if (*key_cmd) return run_ephemeral_key(key);
    if (*keys_cmd) return run_ephemeral_keys(keys);
    if (*scope_cmd) return run_ephemeral_scope(scope);
    if (*merge_cmd) return run_ephemeral_merge(merge);
    if (*unmerge_cmd) return run_ephemeral_unmerge(unmerge);
    if (*pose_cmd) return run_pose(pose);
  } catch (const std::exception& e) {
    // Nothing should throw past the library's Status results; if something
    // does, report it as an error instead of crashing.
    std::cerr << "rigel: internal error: " << e.what() << "\n";
    return kExitInvalidInput;
  }
  return kExitUsage;
}
