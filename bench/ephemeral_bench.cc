// Ephemeral drags on a 159-control character (Rigify's human metarig from
// tests/data/gltf): one iteration is one drag event, i.e. the solve of the
// session's plan and the write-back of control channels as one undo step.
// "plan+drag" variants release the plan first, so they also pay for the walk
// (the first drag after a selection or mode change). Drags alternate in
// sign so the pose stays bounded.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <memory>

#include "bench_util.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/ephemeral/session.h"
#include "rigel/io/gltf_import.h"
#include "rigel/io/scene_file.h"

namespace rigel::bench {
namespace {

using ephemeral::Delta;
using ephemeral::Mode;
using math::Quat;
using math::Vec3;

std::unique_ptr<scene::Scene> metarig() {
  auto imported = io::import_gltf(std::filesystem::path(RIGEL_SOURCE_DIR) / "tests/data/gltf/rigify_human_metarig.glb");
  if (!imported) return nullptr;
  auto loaded = io::parse_scene(io::write_scene(**imported), "metarig", ephemeral::default_registry());
  if (!loaded) return nullptr;
  ephemeral::SetupOptions o;
  o.keep_animation = false;
  if (!ephemeral::setup_ephemeral(**loaded, o)) return nullptr;
  (*loaded)->graph().clear_history();
  return std::move(*loaded);
}

// `display`: also bring the whole scene up to date after each drag
// (Graph::evaluate_all: controls, joints and the skinned mesh), as a
// viewport showing the character would.
void drag(benchmark::State& state, Mode mode, const char* joint, bool rotate, bool replan, int max_chain, bool scale,
          bool display = false) {
  auto scene = metarig();
  if (!scene) {
    state.SkipWithError("could not build the metarig");
    return;
  }
  ephemeral::SessionOptions options;
  options.max_chain = max_chain;
  options.magnet_radius = 0.3;
  ephemeral::Session session(*scene, options);
  session.set_mode(mode);
  graph::NodeId control = scene->graph().find(std::string(joint) + "_ctrl");
  session.select({control});
  HistoryTrim trim(state, scene->graph());
  double sign = 1;
  std::size_t plan_size = 0;
  for (auto _ : state) {
    if (replan) session.release();
    Delta d;
    if (rotate) d.rotate = Quat(Eigen::AngleAxisd(sign * 0.02, Vec3(0.3, 1, 0.2).normalized()));
    else d.translate = Vec3(0.01, -0.005, 0.008) * sign;
    if (scale) d.scale = Vec3::Constant(sign > 0 ? 1.01 : 1 / 1.01);
    Status s = session.drag(d);
    if (!s) {
      state.SkipWithError(s.message().c_str());
      break;
    }
    if (display) scene->graph().evaluate_all(graph::Execution::kSerial);
    sign = -sign;
    trim.tick();
  }
  if (auto p = session.plan()) plan_size = (*p)->entries.size();
  state.counters["plan_controls"] = static_cast<double>(plan_size);
}

BENCHMARK_CAPTURE(drag, forward_spine_rotate, Mode::kForward, "spine", true, false, 0, false)->Name("ephemeral/forward/spine_rotate");
BENCHMARK_CAPTURE(drag, forward_spine_rotate_plan, Mode::kForward, "spine", true, true, 0, false)->Name("ephemeral/forward/spine_rotate/plan+drag");
BENCHMARK_CAPTURE(drag, suspended, Mode::kSuspended, "spine.003", false, false, 0, false)->Name("ephemeral/suspended/chest_translate");
BENCHMARK_CAPTURE(drag, pseudo, Mode::kPseudoInverse, "hand.L", false, false, 0, false)->Name("ephemeral/pseudo-inverse/hand_translate");
BENCHMARK_CAPTURE(drag, pseudo_len, Mode::kPseudoInverseLength, "hand.L", false, false, 0, false)->Name("ephemeral/pseudo-inverse-length/hand_translate");
BENCHMARK_CAPTURE(drag, inverse2, Mode::kInverse, "hand.L", false, false, 3, false)->Name("ephemeral/inverse/two_bone_hand");
BENCHMARK_CAPTURE(drag, inverse2_plan, Mode::kInverse, "hand.L", false, true, 3, false)->Name("ephemeral/inverse/two_bone_hand/plan+drag");
BENCHMARK_CAPTURE(drag, inverse_fabrik, Mode::kInverse, "hand.L", false, false, 0, false)->Name("ephemeral/inverse/fabrik_hand_to_chest");
BENCHMARK_CAPTURE(drag, magnet, Mode::kMagnet, "spine.003", false, false, 0, false)->Name("ephemeral/magnet/chest_translate");
BENCHMARK_CAPTURE(drag, magnet_display, Mode::kMagnet, "spine.003", false, false, 0, false, true)->Name("ephemeral/magnet/chest_translate/+evaluate_all");
BENCHMARK_CAPTURE(drag, inverse2_display, Mode::kInverse, "hand.L", false, false, 3, false, true)->Name("ephemeral/inverse/two_bone_hand/+evaluate_all");
BENCHMARK_CAPTURE(drag, magnet_plan, Mode::kMagnet, "spine.003", false, true, 0, false)->Name("ephemeral/magnet/chest_translate/plan+drag");
BENCHMARK_CAPTURE(drag, magnet_radius, Mode::kMagnetRadius, "hand.L", false, false, 0, false)->Name("ephemeral/magnet-radius/hand_translate");
BENCHMARK_CAPTURE(drag, body, Mode::kBody, "spine", true, false, 0, false)->Name("ephemeral/body/rotate");
BENCHMARK_CAPTURE(drag, body_scale, Mode::kBody, "spine", false, false, 0, true)->Name("ephemeral/body/scale_all_written");

}  // namespace
}  // namespace rigel::bench
