// The constraint kernels (rigel/ops/constraints), one solve per iteration,
// validate() included (callers pay for it):
//
//   constraints_parent/1   ParentConstraintJob, one target with a
//                          maintain-offset matrix and a parent inverse;
//                          64 target poses in turn
//   constraints_parent/4   the same with four weighted targets
//   constraints_parent_rigid/4  four targets, seed 001's rigid variant
//   constraints_aim/1      AimConstraintJob, one target, scene up
//
// ns_per_solve is the CPU time per iteration. Most of a parent solve is
// math::decompose of each contribution (a 3x3 orthogonalisation); the aim
// solve builds two frames and one quaternion.

#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "bench_util.h"
#include "rigel/math/transform.h"
#include "rigel/ops/constraints/constraints.h"

namespace rigel::bench {
namespace {

using math::Mat4;
using math::Quat;
using math::Vec3;
namespace oc = ops::constraints;

constexpr int kPoses = 64;

// kPoses sets of `targets` world matrices, varied rotation and translation.
std::vector<Mat4> target_poses(int targets) {
  std::vector<Mat4> out;
  for (int p = 0; p < kPoses; ++p) {
    for (int t = 0; t < targets; ++t) {
      const double a = 0.1 * p + 0.7 * t;
      out.push_back(math::trs_matrix(Vec3(std::sin(a), t, std::cos(a)),
                                     Quat(Eigen::AngleAxisd(a, Vec3(1, std::sin(a), 0.5).normalized())),
                                     Vec3(1.0 + 0.1 * t, 1.0, 1.0)));
    }
  }
  return out;
}

void run_parent(benchmark::State& state, bool rigid) {
  const int targets = static_cast<int>(state.range(0));
  const std::vector<Mat4> poses = target_poses(targets);
  std::vector<double> weights(targets, 1.0);
  std::vector<Mat4> offsets;
  const Mat4 driven = math::trs_matrix(Vec3(1, 2, 3), Quat(Eigen::AngleAxisd(0.3, Vec3::UnitY())), Vec3::Ones());
  for (int t = 0; t < targets; ++t) offsets.push_back(oc::compute_offset(poses[t], driven, rigid));
  Mat4 out;
  oc::ParentConstraintJob job;
  job.targets.weights = weights;
  job.targets.offsets = offsets;
  job.parent_inverse = math::affine_inverse(math::trs_matrix(Vec3(0, 1, 0), Quat::Identity(), Vec3::Ones()));
  job.rigid = rigid;
  job.output = &out;
  int pose = 0;
  for (auto _ : state) {
    job.targets.world = std::span<const Mat4>(poses).subspan(static_cast<std::size_t>(pose * targets), targets);
    const bool ok = job.run();
    benchmark::DoNotOptimize(ok);
    benchmark::DoNotOptimize(out);
    pose = (pose + 1) % kPoses;
  }
  state.counters["ns_per_solve"] = per_item(1.0);
}

void BM_ConstraintsParent(benchmark::State& state) { run_parent(state, false); }
void BM_ConstraintsParentRigid(benchmark::State& state) { run_parent(state, true); }

void BM_ConstraintsAim(benchmark::State& state) {
  const std::vector<Mat4> poses = target_poses(1);
  std::vector<double> weights = {1.0};
  Quat out;
  oc::AimConstraintJob job;
  job.targets.weights = weights;
  job.driven_position = Vec3(0, 0.5, 0);
  job.output = &out;
  int pose = 0;
  for (auto _ : state) {
    job.targets.world = std::span<const Mat4>(poses).subspan(static_cast<std::size_t>(pose), 1);
    const bool ok = job.run();
    benchmark::DoNotOptimize(ok);
    benchmark::DoNotOptimize(out);
    pose = (pose + 1) % kPoses;
  }
  state.counters["ns_per_solve"] = per_item(1.0);
}

BENCHMARK(BM_ConstraintsParent)->Name("constraints_parent")->Arg(1)->Arg(4);
BENCHMARK(BM_ConstraintsParentRigid)->Name("constraints_parent_rigid")->Arg(4);
BENCHMARK(BM_ConstraintsAim)->Name("constraints_aim")->Arg(1);

}  // namespace
}  // namespace rigel::bench
