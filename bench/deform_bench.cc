// Deformers: linear blend skinning against its target (100,000 vertices x 4
// influences in at most 200 us on one thread), its memory floor, the same on
// every core, dual quaternion skinning, blend shapes, and the graph node.
//
//   deform/lbs/100000x4/serial       LinearBlendSkinningJob::run() (validate()
//                                    included), fixed 4-influence layout
//   deform/lbs/100000x4/parallel     run_parallel(): TBB over both cores
//   deform/lbs/100000x4/general      run() on the general (CSR) layout
//   deform/lbs/100000x4/normals      run() with normals as well
//   deform/lbs/100000x4/{portable,avx2_fma,avx512}
//                                    each instruction-set variant (run()
//                                    picks the best the CPU has)
//   deform/lbs_floor/100000x4        the memory floor: a plain loop reading
//                                    the same arrays (positions, joints,
//                                    weights: 36 bytes a vertex) and writing
//                                    the same output (12), no arithmetic
//   deform/lbs_f64/100000x4          reference only: the AVX-512 kernel
//                                    rewritten for double positions and
//                                    weights (what choosing double costs),
//   deform/lbs_f64_floor/100000x4    and its floor (24 + 8 + 32 read, 24 written)
//   deform/dqs/100000x4/{serial,parallel,stretch}
//                                    DualQuaternionSkinningJob; stretch: every
//                                    joint scaled, so the 3x3 phase runs
//   deform/blend_shape/100000x10/{sparse,dense}/{serial,parallel}
//                                    BlendShapeJob, 10 targets of 10,000
//                                    vertices each, stored sparse; or dense
//   deform/skinning_matrices/64      SkinningMatricesJob, linear output
//   deform/node/skin_cluster/100000x4  a skinCluster node's compute through
//                                    Graph::evaluate after a joint moved (the
//                                    compiled skin kept; output to double)
//
// x_target = time / 200 us; x_floor = time / the floor's time measured in
// the same process just after (best of several runs of each).
//
// Results, 2026-11-23: Release (GCC 12.2, no -march), 2 vCPUs "AMD EPYC"
// (Zen 5, AVX-512), `--benchmark_min_time=0.2`, best of 3 runs. The machine
// was shared with other engineers' builds (load average 5 to 9 on 2 cores),
// so each benchmark's mean was 2 to 2.5x its best iteration; "best" is the
// fastest iteration (what the kernel costs when it has a core), "mean" the
// benchmark's own time.
//
//   benchmark                          best      mean    x_target  x_floor
//   lbs/100000x4/serial (avx512)       159 us    363 us    0.80      1.81 (floor 88 us)
//   lbs/100000x4/avx2_fma              232 us    499 us    1.16      2.62
//   lbs/100000x4/portable             1120 us   2351 us    5.6      12.9
//   lbs/100000x4/general (CSR)         337 us    761 us    1.68      3.86
//   lbs/100000x4/normals               997 us   2153 us    5.0      11.9
//   lbs_floor/100000x4 (48 B/vertex)    84 us    189 us
//   lbs_f64/100000x4 (double)          236 us    561 us    1.18      1.42 (its floor 155-167 us)
//   dqs/100000x4/serial (rigid)       1640 us   3000 us    8.2      19.4
//   dqs/100000x4/stretch              2560 us   5020 us   12.8      29.3
//   blend_shape/100000x10/sparse       134 us    304 us   (100,000 stored deltas)
//   blend_shape/100000x10/dense        292 us    729 us   (1,000,000 stored deltas)
//   skinning_matrices/64               4.1 us for 64 joints
//   node/skin_cluster/100000x4        4.4 ms (conversions and skin build included)
//
// 2026-12-06: normals eight vertices per instruction (float, explicit fused
// operations) instead of one vertex at a time in double: lbs/100000x4/normals
// 1003 us -> 388 us best, against 166 us for the points alone in the same
// run (bench/README.md, "Skinning normals and prepared tracks").
//
// 2026-12-05, same machine, a fresh-machine test run on the other core: the
// skinCluster now keeps its compiled skin and float bind points between
// evaluations (graph::NodeCache, rebuilt when the influence inputs' versions
// change): node/skin_cluster 294 us best, 343 us mean CPU, against the
// serial LBS kernel's 174 us best, 220 us mean in the same run: 1.56-1.7x
// the kernel (was 19x, 4.4 ms). What remains over the kernel is the copy of
// the float result into the node's double output (2.4 MB written a frame)
// and the skinning matrices; the 1.2x needs a float output array.
//
// Two cores: `scaling` reports speedup 0.99 for LBS and DQS with both
// threads taking chunks (threads=2): with the other core busy with a
// compiler, a woken TBB worker did not get it within the 0.16 to 1.6 ms of a
// run, and the main thread did all the work. The one run that found the
// core free, blend_shape/sparse/parallel, took 71.5 us against 134 us serial
// (1.9x). As bench/README.md says of this machine, parallel speed-ups here
// are not measurable; run `--benchmark_filter=scaling` on a quiet one.
//
// Float or double: the double kernel (lbs_f64, the same AVX-512 code with
// 8-wide registers) misses the 200 us target by 1.18x; the float kernel
// meets it with 1.25x to spare. Both are about 1.5-1.9x their floors: the
// per-vertex loads of four joint matrices and the fused multiply-adds, not
// memory, bound them.

// GCC 12 warns that the AVX-512 intrinsics' own "undefined" pass-through
// operand is used uninitialized (GCC bug 105593, fixed in 13); the warning
// is attributed to the intrinsic headers, so it is silenced before them.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

#include <benchmark/benchmark.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <memory>
#include <mutex>
#include <random>
#include <set>
#include <string>
#include <thread>
#include <type_traits>
#include <vector>

#include "../src/ops/deform/skinning_kernels.h"  // the variants, to time each one
#include "rigel/graph/graph.h"
#include "rigel/ops/deform/blend_shape.h"
#include "rigel/ops/deform/nodes.h"
#include "rigel/ops/deform/skinning.h"
#include "rigel/scene/scene.h"
#include "rigel/scene/transform_types.h"

#if RIGEL_DEFORM_X86_KERNELS
#include <immintrin.h>
#endif

namespace rigel::bench {
namespace {

using Clock = std::chrono::steady_clock;
using ops::Vec3f;

constexpr std::size_t kVertices = 100000;
constexpr std::size_t kJoints = 64;
constexpr double kTargetSeconds = 200e-6;

math::Mat4 random_matrix(std::mt19937& rng, double scale_spread) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const math::Quat q = math::Quat(Eigen::Vector4d(unit(rng), unit(rng), unit(rng), unit(rng))).normalized();
  math::Mat4 m = math::Mat4::Identity();
  const math::Vec3 scale = math::Vec3::Constant(1.0) + scale_spread * math::Vec3(unit(rng), unit(rng), unit(rng));
  m.topLeftCorner<3, 3>() = q.toRotationMatrix() * scale.asDiagonal();
  m.topRightCorner<3, 1>() = math::Vec3(unit(rng), unit(rng), unit(rng));
  return m;
}

// 100,000 vertices along a body of 64 joints: each vertex is influenced by
// its nearest joint and three neighbours (distinct), with random weights.
struct SkinFixture {
  ops::Skin skin;          // fixed 4-influence layout
  ops::Skin skin_general;  // the same weights, general layout only
  std::vector<math::Mat4> joint_world, inverse_bind;
  std::vector<ops::SkinMatrix> linear;
  std::vector<ops::DualQuatSkinMatrix> dual_quat, dual_quat_stretch;
  std::vector<Vec3f> positions, normals, out_positions, out_normals;
  // Double copies for the reference kernel.
  std::vector<double> positions_f64, out_f64, weights_f64;
  std::vector<double> matrices_f64;  // 16 per joint, the SkinMatrix layout

  SkinFixture() {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    std::uniform_real_distribution<double> weight(0.1, 1.0);
    ops::SkinBuilder builder(kJoints);
    ops::SkinBuilder general(kJoints);
    general.options().fixed_layout = false;
    const int offsets[4][4] = {{0, 1, -1, 2}, {0, -1, 1, -2}, {0, 2, 1, -1}, {0, -2, -1, 1}};
    for (std::size_t v = 0; v < kVertices; ++v) {
      const auto base = static_cast<int>(v * kJoints / kVertices);
      const int* pick = offsets[rng() % 4];
      ops::SkinInfluence influences[4];
      for (int k = 0; k < 4; ++k) {
        const int j = (base + pick[k] + static_cast<int>(kJoints)) % static_cast<int>(kJoints);
        influences[k] = {j, weight(rng)};
      }
      builder.add_vertex(influences);
      general.add_vertex(influences);
      positions.emplace_back(static_cast<float>(unit(rng)), static_cast<float>(unit(rng) + 2.0 * v / kVertices),
                             static_cast<float>(unit(rng)));
      normals.push_back(Vec3f(static_cast<float>(unit(rng)), static_cast<float>(unit(rng)), 1.0f).normalized());
    }
    skin = std::move(builder.build().value());
    skin_general = std::move(general.build().value());
    for (std::size_t j = 0; j < kJoints; ++j) {
      joint_world.push_back(random_matrix(rng, 0.0));
      inverse_bind.push_back(random_matrix(rng, 0.0));
    }
    linear.resize(kJoints);
    dual_quat.resize(kJoints);
    ops::SkinningMatricesJob job;
    job.joint_world = joint_world;
    job.inverse_bind = inverse_bind;
    job.linear = linear;
    job.dual_quat = dual_quat;
    if (!job.run()) std::abort();
    std::vector<math::Mat4> scaled;
    for (std::size_t j = 0; j < kJoints; ++j) scaled.push_back(random_matrix(rng, 0.3));
    dual_quat_stretch.resize(kJoints);
    ops::SkinningMatricesJob stretch_job;
    stretch_job.joint_world = scaled;
    stretch_job.inverse_bind = inverse_bind;
    stretch_job.dual_quat = dual_quat_stretch;
    if (!stretch_job.run()) std::abort();

    out_positions.assign(kVertices, Vec3f::Zero());
    out_normals.assign(kVertices, Vec3f::Zero());
    for (const Vec3f& p : positions) {
      for (int c = 0; c < 3; ++c) positions_f64.push_back(p[c]);
    }
    out_f64.assign(3 * kVertices, 0.0);
    for (float w : skin.fixed_weights()) weights_f64.push_back(w);
    for (const ops::SkinMatrix& m : linear) matrices_f64.insert(matrices_f64.end(), m.m, m.m + 16);
  }
};

SkinFixture& skin_fixture() {
  static SkinFixture fixture;
  return fixture;
}

ops::LinearBlendSkinningJob lbs_job(SkinFixture& f, const ops::Skin& skin, bool normals) {
  ops::LinearBlendSkinningJob job;
  job.skin = &skin;
  job.matrices = f.linear;
  job.in_positions = f.positions;
  job.out_positions = f.out_positions;
  if (normals) {
    job.in_normals = f.normals;
    job.out_normals = f.out_normals;
  }
  return job;
}

// The memory floor of the fixed-layout kernel: every input array read once
// (positions 12 bytes, joints 8, weights 16 a vertex) and the output written
// (12), in blocks so the four streams stay in step, with a sum that keeps
// the reads alive. Plain C++, vectorised by the compiler.
void lbs_floor_once(SkinFixture& f) {
  const float* in = f.positions.data()->data();
  float* out = f.out_positions.data()->data();
  const std::uint16_t* joints = f.skin.fixed_joints().data();
  const auto* weights = reinterpret_cast<const std::uint32_t*>(f.skin.fixed_weights().data());
  // Integer sums (the weights' bits): reassociable, so the compiler
  // vectorises them, where a float sum would be one long serial chain.
  std::uint32_t weight_bits = 0;
  std::uint32_t joint_sum = 0;
  constexpr std::size_t kBlock = 256;
  for (std::size_t b = 0; b < kVertices; b += kBlock) {
    const std::size_t e = std::min(kVertices, b + kBlock);
    for (std::size_t i = 4 * b; i < 4 * e; ++i) weight_bits += weights[i];
    for (std::size_t i = 4 * b; i < 4 * e; ++i) joint_sum += joints[i];
    std::memcpy(out + 3 * b, in + 3 * b, 3 * (e - b) * sizeof(float));
  }
  out[0] += static_cast<float>(weight_bits + joint_sum);
  benchmark::DoNotOptimize(out);
  benchmark::ClobberMemory();
}

#if RIGEL_DEFORM_X86_KERNELS
// Reference only: the AVX-512 kernel for double positions and weights (the
// same 4-influence layout, double 3x4 matrices in two registers each).
__attribute__((target("avx512f,avx512vl,avx512dq,avx2,fma"))) void lbs_f64_once(SkinFixture& f) {
  const double* p = f.positions_f64.data();
  const double* w = f.weights_f64.data();
  const std::uint16_t* j = f.skin.fixed_joints().data();
  const double* m = f.matrices_f64.data();
  double* o = f.out_f64.data();
  const __m512d one = _mm512_set1_pd(1.0);
  const __m512i xy = _mm512_set_epi64(1, 1, 1, 1, 0, 0, 0, 0);
  const __m512i z1 = _mm512_set_epi64(3, 3, 3, 3, 2, 2, 2, 2);
  for (std::size_t v = 0; v < kVertices; ++v) {
    std::uint64_t packed;
    std::memcpy(&packed, j + 4 * v, 8);
    const double* m0 = m + 16 * (packed & 0xffff);
    const double* m1 = m + 16 * ((packed >> 16) & 0xffff);
    const double* m2 = m + 16 * ((packed >> 32) & 0xffff);
    const double* m3 = m + 16 * (packed >> 48);
    const __m512d w0 = _mm512_set1_pd(w[4 * v]), w1 = _mm512_set1_pd(w[4 * v + 1]);
    const __m512d w2 = _mm512_set1_pd(w[4 * v + 2]), w3 = _mm512_set1_pd(w[4 * v + 3]);
    __m512d a01 = _mm512_mul_pd(w0, _mm512_loadu_pd(m0)), a23 = _mm512_mul_pd(w0, _mm512_loadu_pd(m0 + 8));
    __m512d b01 = _mm512_mul_pd(w1, _mm512_loadu_pd(m1)), b23 = _mm512_mul_pd(w1, _mm512_loadu_pd(m1 + 8));
    a01 = _mm512_fmadd_pd(w2, _mm512_loadu_pd(m2), a01);
    a23 = _mm512_fmadd_pd(w2, _mm512_loadu_pd(m2 + 8), a23);
    b01 = _mm512_fmadd_pd(w3, _mm512_loadu_pd(m3), b01);
    b23 = _mm512_fmadd_pd(w3, _mm512_loadu_pd(m3 + 8), b23);
    a01 = _mm512_add_pd(a01, b01);
    a23 = _mm512_add_pd(a23, b23);
    const __m512d point = _mm512_castpd256_pd512(_mm256_maskz_loadu_pd(0x7, p + 3 * v));
    const __m512d pxy = _mm512_permutexvar_pd(xy, point);
    const __m512d pz1 = _mm512_mask_permutexvar_pd(one, 0x0f, z1, point);
    const __m512d r = _mm512_fmadd_pd(a01, pxy, _mm512_mul_pd(a23, pz1));
    const __m256d s = _mm256_add_pd(_mm512_castpd512_pd256(r), _mm512_extractf64x4_pd(r, 1));
    _mm256_mask_storeu_pd(o + 3 * v, 0x7, s);
  }
  benchmark::ClobberMemory();
}
#endif

void lbs_f64_floor_once(SkinFixture& f) {
  const double* in = f.positions_f64.data();
  double* out = f.out_f64.data();
  const std::uint16_t* joints = f.skin.fixed_joints().data();
  const auto* weights = reinterpret_cast<const std::uint64_t*>(f.weights_f64.data());
  std::uint64_t weight_bits = 0;
  std::uint32_t joint_sum = 0;
  constexpr std::size_t kBlock = 256;
  for (std::size_t b = 0; b < kVertices; b += kBlock) {
    const std::size_t e = std::min(kVertices, b + kBlock);
    for (std::size_t i = 4 * b; i < 4 * e; ++i) weight_bits += weights[i];
    for (std::size_t i = 4 * b; i < 4 * e; ++i) joint_sum += joints[i];
    std::memcpy(out + 3 * b, in + 3 * b, 3 * (e - b) * sizeof(double));
  }
  out[0] += static_cast<double>(weight_bits + joint_sum);
  benchmark::DoNotOptimize(out);
  benchmark::ClobberMemory();
}

// Best time of `runs` calls, in seconds.
template <typename Fn>
double best_of(int runs, Fn&& fn) {
  double best = 1e30;
  for (int r = 0; r < runs; ++r) {
    const auto t0 = Clock::now();
    fn();
    best = std::min(best, std::chrono::duration<double>(Clock::now() - t0).count());
  }
  return best;
}

// Times the loop itself (wall clock), then adds the counters of the header
// comment; `floor` (may be null) is timed just after for x_floor.
template <typename Fn, typename Floor>
void timed(benchmark::State& state, Fn&& fn, Floor&& floor) {
  double best = 1e30;
  for (auto _ : state) {
    const auto t0 = Clock::now();
    fn();
    const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    state.SetIterationTime(seconds);
    best = std::min(best, seconds);
  }
  state.counters["best_us"] = best * 1e6;
  state.counters["x_target"] = best / kTargetSeconds;
  if constexpr (!std::is_same_v<std::decay_t<Floor>, std::nullptr_t>) {
    const double floor_seconds = best_of(50, floor);
    state.counters["floor_us"] = floor_seconds * 1e6;
    state.counters["x_floor"] = best / floor_seconds;
  }
}

void lbs(benchmark::State& state, bool general, bool normals, bool parallel) {
  SkinFixture& f = skin_fixture();
  const ops::LinearBlendSkinningJob job = lbs_job(f, general ? f.skin_general : f.skin, normals);
  if (!job.run()) {
    state.SkipWithError("LinearBlendSkinningJob refused a valid job");
    return;
  }
  timed(
      state, [&] { benchmark::DoNotOptimize(parallel ? job.run_parallel() : job.run()); }, [&] { lbs_floor_once(f); });
  state.SetLabel(std::string("kernel: ") + ops::detail::lbs_best_kernel_name());
}

// Serial and parallel runs alternated in one loop, so both see the same
// machine (other processes come and go on a shared 2-core box): the best of
// each, their ratio, and how many threads the parallel runs used (the job's
// run(begin, end) driven by tbb::parallel_for, as a caller splitting the
// work itself would; run_parallel() is that loop).
template <typename Job>
void scaling(benchmark::State& state, const Job& job) {
  const std::size_t count = job.skin->vertex_count();
  double serial = 1e30, parallel = 1e30;
  std::mutex mutex;
  std::set<std::thread::id> threads;
  for (auto _ : state) {
    const auto t0 = Clock::now();
    benchmark::DoNotOptimize(job.run());
    const auto t1 = Clock::now();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 8192), [&](const tbb::blocked_range<std::size_t>& r) {
      benchmark::DoNotOptimize(job.run(r.begin(), r.end()));
      std::lock_guard<std::mutex> lock(mutex);
      threads.insert(std::this_thread::get_id());
    });
    const auto t2 = Clock::now();
    serial = std::min(serial, std::chrono::duration<double>(t1 - t0).count());
    parallel = std::min(parallel, std::chrono::duration<double>(t2 - t1).count());
    state.SetIterationTime(std::chrono::duration<double>(t2 - t0).count());
  }
  state.counters["serial_us"] = serial * 1e6;
  state.counters["parallel_us"] = parallel * 1e6;
  state.counters["speedup"] = serial / parallel;
  state.counters["threads"] = static_cast<double>(threads.size());
}

void lbs_scaling(benchmark::State& state) {
  SkinFixture& f = skin_fixture();
  scaling(state, lbs_job(f, f.skin, false));
}

void dqs_scaling(benchmark::State& state) {
  SkinFixture& f = skin_fixture();
  ops::DualQuaternionSkinningJob job;
  job.skin = &f.skin;
  job.matrices = f.dual_quat;
  job.in_positions = f.positions;
  job.out_positions = f.out_positions;
  scaling(state, job);
}

void lbs_variant(benchmark::State& state, ops::detail::LbsKernel kernel, bool supported) {
  if (!supported) {
    state.SkipWithError("this CPU cannot run the variant");
    return;
  }
  SkinFixture& f = skin_fixture();
  const ops::LinearBlendSkinningJob job = lbs_job(f, f.skin, false);
  timed(
      state,
      [&] {
        kernel(job, 0, kVertices);
        benchmark::ClobberMemory();
      },
      [&] { lbs_floor_once(f); });
}

void lbs_floor(benchmark::State& state) {
  SkinFixture& f = skin_fixture();
  timed(
      state, [&] { lbs_floor_once(f); }, nullptr);
}

void lbs_f64(benchmark::State& state) {
#if RIGEL_DEFORM_X86_KERNELS
  if (!ops::detail::avx512_supported()) {
    state.SkipWithError("the double reference kernel needs AVX-512");
    return;
  }
  SkinFixture& f = skin_fixture();
  timed(
      state, [&] { lbs_f64_once(f); }, [&] { lbs_f64_floor_once(f); });
#else
  state.SkipWithError("the double reference kernel is x86 only");
#endif
}

void lbs_f64_floor(benchmark::State& state) {
  SkinFixture& f = skin_fixture();
  timed(
      state, [&] { lbs_f64_floor_once(f); }, nullptr);
}

void dqs(benchmark::State& state, bool stretch, bool parallel) {
  SkinFixture& f = skin_fixture();
  ops::DualQuaternionSkinningJob job;
  job.skin = &f.skin;
  job.matrices = stretch ? f.dual_quat_stretch : f.dual_quat;
  job.in_positions = f.positions;
  job.out_positions = f.out_positions;
  if (!job.run()) {
    state.SkipWithError("DualQuaternionSkinningJob refused a valid job");
    return;
  }
  timed(
      state, [&] { benchmark::DoNotOptimize(parallel ? job.run_parallel() : job.run()); }, [&] { lbs_floor_once(f); });
}

// 10 targets over 100,000 vertices: each moves 10,000 vertices of a region
// (a face, a hand), every other vertex of a 20,000-vertex window.
struct BlendFixture {
  ops::BlendShapeTargets sparse, dense;
  std::vector<Vec3f> base, out;
  std::vector<float> weights;

  BlendFixture() {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    ops::BlendShapeBuilder sparse_builder(kVertices);
    ops::BlendShapeBuilder dense_builder(kVertices);
    sparse_builder.sparse_below = 1.1;  // always sparse
    dense_builder.sparse_below = 0.0;   // always dense
    for (int t = 0; t < 10; ++t) {
      std::vector<std::int64_t> indices;
      std::vector<Vec3f> deltas;
      const std::size_t start = static_cast<std::size_t>(t) * 8000;
      for (std::size_t i = 0; i < 10000; ++i) {
        indices.push_back(static_cast<std::int64_t>(start + 2 * i));
        deltas.emplace_back(unit(rng), unit(rng), unit(rng));
      }
      sparse_builder.add_sparse_target(indices, deltas);
      dense_builder.add_sparse_target(indices, deltas);
      weights.push_back(0.1f + 0.08f * static_cast<float>(t));
    }
    sparse = std::move(sparse_builder.build().value());
    dense = std::move(dense_builder.build().value());
    for (std::size_t v = 0; v < kVertices; ++v) base.emplace_back(unit(rng), unit(rng), unit(rng));
    out.assign(kVertices, Vec3f::Zero());
  }
};

void blend_shape(benchmark::State& state, bool dense, bool parallel) {
  static BlendFixture f;
  ops::BlendShapeJob job;
  job.targets = dense ? &f.dense : &f.sparse;
  job.base = f.base;
  job.weights = f.weights;
  job.out = f.out;
  if (!job.run()) {
    state.SkipWithError("BlendShapeJob refused a valid job");
    return;
  }
  timed(
      state, [&] { benchmark::DoNotOptimize(parallel ? job.run_parallel() : job.run()); }, nullptr);
  state.counters["stored_deltas"] = static_cast<double>(job.targets->stored_delta_count());
}

void skinning_matrices(benchmark::State& state) {
  SkinFixture& f = skin_fixture();
  std::vector<ops::SkinMatrix> out(kJoints);
  ops::SkinningMatricesJob job;
  job.joint_world = f.joint_world;
  job.inverse_bind = f.inverse_bind;
  job.linear = out;
  for (auto _ : state) {
    benchmark::DoNotOptimize(job.run());
    benchmark::ClobberMemory();
  }
}

// A skinCluster node driven by 64 joints: rotate the root, evaluate
// outPoints. Only the evaluation is timed: the node keeps its compiled skin
// and float bind points, so it computes the skinning matrices, skins and
// copies the result to its double output.
void skin_cluster_node(benchmark::State& state) {
  SkinFixture& f = skin_fixture();
  auto registry = std::make_shared<graph::Registry>();
  if (!scene::register_scene_types(*registry) || !ops::register_deform_types(*registry)) {
    state.SkipWithError("registration failed");
    return;
  }
  scene::Scene scene(registry);
  graph::Graph& g = scene.graph();
  std::vector<graph::NodeId> joints;
  for (std::size_t j = 0; j < kJoints; ++j) {
    std::string name = "j";  // not "j" + ...: GCC 12 warns falsely on it (-Wrestrict)
    name += std::to_string(j);
    joints.push_back(scene.create(scene::kJointType, name, j == 0 ? graph::NodeId{} : joints[j - 1]).value());
  }
  const graph::NodeId skin = g.create_node(ops::kSkinClusterType, "skin").value();
  namespace a = ops::skin_cluster_attr;
  std::vector<math::Vec3> points;
  for (const Vec3f& p : f.positions) points.push_back(p.cast<double>());
  std::vector<std::int64_t> offsets, joint_ids;
  std::vector<double> weights;
  for (std::uint32_t o : f.skin.offsets()) offsets.push_back(o);
  for (std::uint16_t j : f.skin.joints()) joint_ids.push_back(j);
  for (float w : f.skin.weights()) weights.push_back(w);
  bool ok = g.set_value({skin, a::kBindPoints}, points).is_ok() &&
            g.set_value({skin, a::kInfluenceOffsets}, offsets).is_ok() &&
            g.set_value({skin, a::kInfluenceJoints}, joint_ids).is_ok() &&
            g.set_value({skin, a::kInfluenceWeights}, weights).is_ok() &&
            g.set_value({skin, a::kBindPreMatrices}, f.inverse_bind).is_ok();
  for (std::size_t j = 0; j < kJoints && ok; ++j) {
    ok = g.connect({joints[j], scene::xform::kWorldMatrix}, {skin, a::kJointMatrices, static_cast<std::int32_t>(j)})
             .is_ok();
  }
  if (!ok) {
    state.SkipWithError("building the rig failed");
    return;
  }
  double angle = 0.0;
  for (auto _ : state) {
    state.PauseTiming();
    angle += 1.0;
    (void)g.set_value({joints[0], scene::xform::kRotate}, math::Vec3(0.0, angle, 0.0));
    g.clear_history();
    state.ResumeTiming();
    benchmark::DoNotOptimize(&g.evaluate(skin, a::kOutPoints));
  }
}

void register_all() {
  using benchmark::kMicrosecond;
  auto manual = [](benchmark::internal::Benchmark* b) { b->UseManualTime()->Unit(kMicrosecond); };
  manual(benchmark::RegisterBenchmark("deform/lbs/100000x4/serial", lbs, false, false, false));
  manual(benchmark::RegisterBenchmark("deform/lbs/100000x4/parallel", lbs, false, false, true));
  manual(benchmark::RegisterBenchmark("deform/lbs/100000x4/scaling", lbs_scaling));
  manual(benchmark::RegisterBenchmark("deform/lbs/100000x4/general", lbs, true, false, false));
  manual(benchmark::RegisterBenchmark("deform/lbs/100000x4/normals", lbs, false, true, false));
  manual(benchmark::RegisterBenchmark("deform/lbs/100000x4/portable", lbs_variant, ops::detail::lbs_portable, true));
#if RIGEL_DEFORM_X86_KERNELS
  manual(benchmark::RegisterBenchmark("deform/lbs/100000x4/avx2_fma", lbs_variant, ops::detail::lbs_avx2_fma,
                                      ops::detail::avx2_fma_supported()));
  manual(benchmark::RegisterBenchmark("deform/lbs/100000x4/avx512", lbs_variant, ops::detail::lbs_avx512,
                                      ops::detail::avx512_supported()));
#endif
  manual(benchmark::RegisterBenchmark("deform/lbs_floor/100000x4", lbs_floor));
  manual(benchmark::RegisterBenchmark("deform/lbs_f64/100000x4", lbs_f64));
  manual(benchmark::RegisterBenchmark("deform/lbs_f64_floor/100000x4", lbs_f64_floor));
  manual(benchmark::RegisterBenchmark("deform/dqs/100000x4/serial", dqs, false, false));
  manual(benchmark::RegisterBenchmark("deform/dqs/100000x4/parallel", dqs, false, true));
  manual(benchmark::RegisterBenchmark("deform/dqs/100000x4/scaling", dqs_scaling));
  manual(benchmark::RegisterBenchmark("deform/dqs/100000x4/stretch", dqs, true, false));
  manual(benchmark::RegisterBenchmark("deform/blend_shape/100000x10/sparse/serial", blend_shape, false, false));
  manual(benchmark::RegisterBenchmark("deform/blend_shape/100000x10/sparse/parallel", blend_shape, false, true));
  manual(benchmark::RegisterBenchmark("deform/blend_shape/100000x10/dense/serial", blend_shape, true, false));
  manual(benchmark::RegisterBenchmark("deform/blend_shape/100000x10/dense/parallel", blend_shape, true, true));
  benchmark::RegisterBenchmark("deform/skinning_matrices/64", skinning_matrices)->Unit(benchmark::kNanosecond);
  benchmark::RegisterBenchmark("deform/node/skin_cluster/100000x4", skin_cluster_node)
      ->Unit(kMicrosecond)
      ->UseRealTime();
}

const bool registered = (register_all(), true);

}  // namespace
}  // namespace rigel::bench
