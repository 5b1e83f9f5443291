// The IK kernels (rigel/ops/ik), one solve per iteration, validate()
// included (callers pay for it):
//
//   ik_two_bone/solve      TwoBoneIkJob on a leg whose frames are rolled about
//                          the bones, 256 targets in turn (reachable, out of
//                          reach, across the pole plane). Target: at most
//                          150 ns per solve; ozz-animation's IKTwoBoneJob
//                          (floats, SIMD) is quoted at 145 ns. vs_150ns and
//                          vs_ozz_145ns are the measured time over those.
//   ik_two_bone/soft_stretch_weight   the same with soft IK, stretch and a
//                          weight below 1 (exp and two slerps more)
//   ik_fabrik/10_joints    FabrikJob on a curled 10-joint chain, 64 reachable
//                          targets in turn, tolerance 1e-6; iterations is the
//                          mean count it used
//   ik_fabrik_limited/10_joints  the same under 0.6 rad cones
//   ik_ccd/10_joints       CcdJob, the same chain and targets
//   ik_ccd_limited/10_joints     the same under 0.6 rad cones
//   ik_spline/20_joints    SplineIkJob: 20 joints on a 6-point curve, a
//                          129-entry arc-length table, 64 curve shapes in turn
//   ik_spline_stretch/20_joints  the same with stretch and squash
//
// ns_per_solve is the CPU time per iteration (Google Benchmark's CPU column).
// On x86-64 the kernels run their x86-64-v3 (AVX2/FMA) build where the CPU
// has it (src/ops/ik/ik_math.h, RIGEL_IK_MULTIVERSION).

#include <benchmark/benchmark.h>

#include <cmath>
#include <ctime>
#include <vector>

#include "bench_util.h"
#include "rigel/math/types.h"
#include "rigel/ops/ik/ccd.h"
#include "rigel/ops/ik/fabrik.h"
#include "rigel/ops/ik/spline_ik.h"
#include "rigel/ops/ik/two_bone_ik.h"

namespace rigel::bench {
namespace {

using math::Mat3;
using math::Mat4;
using math::Quat;
using math::Vec3;
using ops::ik::JointLimit;

// Frames with x along each bone, z near `normal`, then rolled about the bone
// by `roll` (so nothing is axis-aligned).
std::vector<Mat4> chain_from_points(const std::vector<Vec3>& points, const Vec3& normal, double roll) {
  std::vector<Mat4> world(points.size(), Mat4::Identity());
  Vec3 x = Vec3::UnitX();
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (i + 1 < points.size()) x = (points[i + 1] - points[i]).normalized();
    const Vec3 z = (normal - x * x.dot(normal)).normalized();
    Mat3 frame;
    frame.col(0) = x;
    frame.col(1) = z.cross(x);
    frame.col(2) = z;
    world[i].topLeftCorner<3, 3>() = frame * Eigen::AngleAxisd(roll * static_cast<double>(i + 1), Vec3::UnitX());
    world[i].topRightCorner<3, 1>() = points[i];
  }
  return world;
}

// A leg: hip, knee, ankle, hanging down -y, knee bent forward.
std::vector<Mat4> leg() {
  const Vec3 hip(0.1, 1.0, 0.0);
  const Vec3 knee = hip + Vec3(0, -std::cos(0.2), std::sin(0.2)) * 0.45;
  const Vec3 ankle = knee + Vec3(0, -std::cos(0.2), -std::sin(0.2)) * 0.42;
  return chain_from_points({hip, knee, ankle}, Vec3::UnitX(), 0.7);
}

std::vector<Vec3> leg_targets() {
  std::vector<Vec3> targets(256);
  for (std::size_t n = 0; n < targets.size(); ++n) {
    const double t = static_cast<double>(n) / static_cast<double>(targets.size());
    // A loop that goes across the pole plane and out of reach and back.
    targets[n] = Vec3(0.1 + 0.3 * std::sin(2 * math::kPi * t), 0.25 + 0.3 * std::cos(4 * math::kPi * t),
                      0.2 * std::sin(6 * math::kPi * t));
  }
  return targets;
}

// CPU time of this thread per iteration of the timed loop, measured around
// it: the same measure as Google Benchmark's CPU column and ns_per_solve
// (on a shared machine wall time counts other processes' turns too).
class LoopTimer {
 public:
  LoopTimer() : start_(now()) {}
  double ns_per_iteration(const benchmark::State& state) const {
    const double ns = (now() - start_) * 1e9;
    return state.iterations() > 0 ? ns / static_cast<double>(state.iterations()) : 0.0;
  }

 private:
  static double now() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
  }
  double start_;
};

void two_bone(benchmark::State& state, bool extras) {
  const std::vector<Mat4> chain = leg();
  const std::vector<Vec3> targets = leg_targets();
  ops::ik::TwoBoneIkOutput output;
  ops::ik::TwoBoneIkJob job;
  job.start_world = &chain[0];
  job.mid_world = &chain[1];
  job.end_world = &chain[2];
  job.mid_axis = Eigen::AngleAxisd(-1.4, Vec3::UnitX()) * Vec3::UnitZ();  // the hinge, in the rolled mid frame
  job.pole_vector = Vec3(0, 0, 1);
  job.output = &output;
  if (extras) {
    job.soft = 0.1;
    job.stretch = true;
    job.max_stretch = 1.5;
    job.weight = 0.75;
  }
  if (!job.run()) {
    state.SkipWithError("TwoBoneIkJob refused a valid job");
    return;
  }
  std::size_t n = 0;
  const LoopTimer timer;
  for (auto _ : state) {
    job.target = targets[n++ & 255];
    const bool ok = job.run();
    benchmark::DoNotOptimize(ok);
    benchmark::DoNotOptimize(output);
  }
  const double ns = timer.ns_per_iteration(state);
  state.counters["ns_per_solve"] = per_item(1.0);
  state.counters["vs_150ns"] = ns / 150.0;
  state.counters["vs_ozz_145ns"] = ns / 145.0;
}

std::vector<Mat4> curled_ten() {
  std::vector<Vec3> points(10, Vec3::Zero());
  for (std::size_t i = 1; i < points.size(); ++i) {
    const double heading = 0.15 * static_cast<double>(i);
    points[i] = points[i - 1] + Vec3(std::cos(heading), std::sin(heading), 0.05 * std::sin(static_cast<double>(i)));
  }
  return chain_from_points(points, Vec3::UnitZ(), 0.3);
}

std::vector<Vec3> chain_targets() {
  std::vector<Vec3> targets(64);
  for (std::size_t n = 0; n < targets.size(); ++n) {
    const double t = static_cast<double>(n) / static_cast<double>(targets.size());
    targets[n] = Vec3(5 + 0.5 * std::cos(2 * math::kPi * t), 4 + 0.5 * std::sin(2 * math::kPi * t),
                      0.3 * std::sin(4 * math::kPi * t));
  }
  return targets;
}

std::vector<JointLimit> cones(const std::vector<Mat4>& chain, double half_angle) {
  std::vector<JointLimit> limits(chain.size());
  for (std::size_t i = 0; i + 1 < chain.size(); ++i) {
    const Mat3 parent = i == 0 ? Mat3::Identity() : Mat3(chain[i - 1].topLeftCorner<3, 3>());
    limits[i].kind = ops::ik::LimitKind::kCone;
    limits[i].axis =
        (parent.transpose() * (chain[i + 1].topRightCorner<3, 1>() - chain[i].topRightCorner<3, 1>())).normalized();
    limits[i].half_angle = half_angle;
  }
  return limits;
}

template <typename Job>
void chain_solver(benchmark::State& state, bool limited) {
  const std::vector<Mat4> chain = curled_ten();
  const std::vector<Vec3> targets = chain_targets();
  const std::vector<JointLimit> limits = limited ? cones(chain, 0.6) : std::vector<JointLimit>{};
  std::vector<Vec3> positions(chain.size());
  std::vector<Quat> corrections(chain.size());
  ops::ik::IkChainResult result;
  Job job;
  job.world = chain;
  job.limits = limits;
  job.positions = positions;
  job.corrections = corrections;
  job.result = &result;
  job.tolerance = 1e-6;
  job.max_iterations = 200;
  if (!job.run()) {
    state.SkipWithError("the chain job refused a valid job");
    return;
  }
  std::size_t n = 0;
  double iterations = 0.0;
  double unreached = 0.0;
  for (auto _ : state) {
    job.target = targets[n++ & 63];
    const bool ok = job.run();
    benchmark::DoNotOptimize(ok);
    benchmark::ClobberMemory();
    iterations += result.iterations;
    unreached += result.reached ? 0.0 : 1.0;
  }
  const double count = static_cast<double>(state.iterations());
  state.counters["ns_per_solve"] = per_item(1.0);
  state.counters["iterations"] = count > 0 ? iterations / count : 0.0;
  state.counters["unreached"] = count > 0 ? unreached / count : 0.0;
}

void spline(benchmark::State& state, bool stretch) {
  std::vector<Vec3> points(20);
  for (std::size_t i = 0; i < points.size(); ++i) points[i] = Vec3(0, 0.5 * static_cast<double>(i), 0);
  const std::vector<Mat4> chain = chain_from_points(points, Vec3::UnitZ(), 0.0);
  // 64 curve shapes: a spine bending forward and sideways.
  std::vector<std::vector<Vec3>> shapes(64);
  for (std::size_t n = 0; n < shapes.size(); ++n) {
    const double t = 2 * math::kPi * static_cast<double>(n) / static_cast<double>(shapes.size());
    shapes[n] = {Vec3(0, 0, 0),
                 Vec3(0.3 * std::sin(t), 2, 0.5 * std::cos(t)),
                 Vec3(0.6 * std::sin(t), 4, 1.0 * std::cos(t)),
                 Vec3(0.4 * std::sin(2 * t), 6, 0.8),
                 Vec3(0.2, 8, 0.5 * std::sin(t)),
                 Vec3(0, 10, 0)};
  }
  std::vector<double> arc(129);
  std::vector<Mat4> out(chain.size());
  ops::ik::SplineIkJob job;
  job.world = chain;
  job.arc_lengths = arc;
  job.world_out = out;
  job.up_vector = Vec3(0, 0, 1);
  job.end_twist = 0.5;
  job.stretch = stretch;
  job.squash = stretch;
  job.control_points = shapes[0];
  if (!job.run()) {
    state.SkipWithError("SplineIkJob refused a valid job");
    return;
  }
  std::size_t n = 0;
  for (auto _ : state) {
    job.control_points = shapes[n++ & 63];
    const bool ok = job.run();
    benchmark::DoNotOptimize(ok);
    benchmark::ClobberMemory();
  }
  state.counters["ns_per_solve"] = per_item(1.0);
}

BENCHMARK_CAPTURE(two_bone, solve, false)->Name("ik_two_bone/solve");
BENCHMARK_CAPTURE(two_bone, soft_stretch_weight, true)->Name("ik_two_bone/soft_stretch_weight");
void fabrik(benchmark::State& state, bool limited) { chain_solver<ops::ik::FabrikJob>(state, limited); }
void ccd(benchmark::State& state, bool limited) { chain_solver<ops::ik::CcdJob>(state, limited); }

BENCHMARK_CAPTURE(fabrik, plain, false)->Name("ik_fabrik/10_joints");
BENCHMARK_CAPTURE(fabrik, limited, true)->Name("ik_fabrik_limited/10_joints");
BENCHMARK_CAPTURE(ccd, plain, false)->Name("ik_ccd/10_joints");
BENCHMARK_CAPTURE(ccd, limited, true)->Name("ik_ccd_limited/10_joints");
BENCHMARK_CAPTURE(spline, plain, false)->Name("ik_spline/20_joints");
BENCHMARK_CAPTURE(spline, stretch, true)->Name("ik_spline_stretch/20_joints");

}  // namespace
}  // namespace rigel::bench
