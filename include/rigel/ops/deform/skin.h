#pragma once
// Skin weights: which joints move each vertex, and how much. Raw influences
// (per-vertex lists, or the flat CSR arrays files and graph attributes hold)
// go through a validating builder into a compiled, flat, read-only Skin that
// the skinning jobs read (STYLE.md §2: raw -> builder -> compiled).
//
// Precision. Vertex data for the deformers (positions, normals, weights) is
// float, as in glTF buffers, GPU uploads, ozz, USD's skinning and Blender;
// matrix products stay in double until they are rounded once into the
// kernels' per-joint matrices (skinning.h). The reason is the budget of
// 200 us for 100,000 vertices x 4 influences on one thread: measured on the
// reference machine (bench/deform_bench.cc), the float kernel takes 164 us
// against a float memory floor of 83 us, while the same kernel in double
// takes 238 us against a floor of 147 us: the loads and fused multiply-adds
// per vertex double with the width, and the double kernel misses the
// target. Float carries 24 bits: 0.1 um on a 2 m character.

#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <span>
#include <vector>

#include "rigel/base/status.h"

namespace rigel::ops {

// Joint indices are stored in 16 bits (glTF's JOINTS_n are 8 or 16 bits).
inline constexpr std::size_t kMaxSkinJoints = 65536;
// Influences per vertex of the fixed layout (the glTF common case).
inline constexpr std::size_t kFixedInfluences = 4;

// One joint's influence on one vertex.
struct SkinInfluence {
  std::int64_t joint = 0;
  double weight = 0.0;
};

// Influences as flat arrays (CSR): vertex v is influenced by
// joints[offsets[v] .. offsets[v + 1]) with the weights of the same range.
// offsets has vertex_count + 1 entries. What skinCluster nodes store.
struct SkinInfluenceView {
  std::span<const std::int64_t> offsets;
  std::span<const std::int64_t> joints;
  std::span<const double> weights;
};

struct SkinBuildOptions {
  // Number of skinning matrices the skin is used with: every joint index
  // must be below it. At most kMaxSkinJoints.
  std::size_t joint_count = 0;
  // Divide each vertex's weights by their sum, so they sum to 1. Off: weights
  // are kept as given (a vertex whose weights sum to 0.5 then moves half way).
  bool normalize = true;
  // A vertex whose weights sum differs from 1 by more than this is listed in
  // SkinBuildReport::renormalized. Weights stored as float sum to 1 within
  // about 1e-7, so the default lists only vertices that really needed it.
  double report_tolerance = 1e-5;
  // Also build the fixed 4-influence layout when no vertex has more than 4
  // influences (the linear-blend fast path). Off: only the general layout.
  bool fixed_layout = true;
};

// A vertex whose weights did not sum to 1 (beyond report_tolerance).
struct RenormalizedVertex {
  std::uint32_t vertex = 0;
  double weight_sum = 0.0;  // the sum before normalisation
};

// What the builder changed. Real files need it: CesiumMan has 210 of 3,273
// vertices whose weights do not sum to 1.
struct SkinBuildReport {
  std::vector<RenormalizedVertex> renormalized;  // in vertex order
  double largest_deviation = 0.0;                // max |sum - 1| over every vertex (0 when empty)
  std::size_t dropped_zero_weights = 0;          // influences with weight exactly 0
  std::size_t merged_duplicates = 0;             // repeated joints of one vertex, weights summed
  std::size_t max_influences = 0;                // after dropping and merging
};

// Compiled skin weights: flat, read-only, validated (every joint index is
// below joint_count(), every weight is finite and positive, every vertex has
// at least one influence). Built only by build_skin()/SkinBuilder; a
// default-constructed Skin has no vertices.
class Skin {
 public:
  std::size_t vertex_count() const { return offsets_.empty() ? 0 : offsets_.size() - 1; }
  std::size_t joint_count() const { return joint_count_; }
  std::size_t influence_count() const { return joints_.size(); }
  std::size_t max_influences() const { return max_influences_; }

  // General layout: vertex v's influences are [offsets()[v], offsets()[v + 1])
  // of joints() and weights(), in the order given, without zero weights.
  std::span<const std::uint32_t> offsets() const { return offsets_; }
  std::span<const std::uint16_t> joints() const { return joints_; }
  std::span<const float> weights() const { return weights_; }

  // Fixed layout, when has_fixed_layout(): kFixedInfluences entries per
  // vertex. A vertex with fewer influences is padded with its first joint
  // and weight 0 (adding 0 x a matrix changes nothing, and that matrix is
  // already in cache).
  bool has_fixed_layout() const { return fixed_; }
  std::span<const std::uint16_t> fixed_joints() const { return fixed_joints_; }
  std::span<const float> fixed_weights() const { return fixed_weights_; }

 private:
  friend Result<Skin> build_skin(const SkinInfluenceView&, const SkinBuildOptions&, SkinBuildReport*);
  std::size_t joint_count_ = 0;
  std::size_t max_influences_ = 0;
  bool fixed_ = false;
  std::vector<std::uint32_t> offsets_;
  std::vector<std::uint16_t> joints_;
  std::vector<float> weights_;
  std::vector<std::uint16_t> fixed_joints_;
  std::vector<float> fixed_weights_;
};

// Validates and compiles influences. Zero weights are dropped, repeated
// joints of one vertex merged, and (with options.normalize) weights divided
// by their sum. Fails, with a message naming the vertex (and listing up to 8
// bad vertices, with the total), when:
// - options.joint_count is 0 while there are influences, or exceeds
//   kMaxSkinJoints;
// - offsets is empty, does not start at 0, decreases, or does not end at
//   joints.size(); joints and weights differ in length;
// - a weight is NaN or infinite, or negative;
// - a joint index is negative or not below options.joint_count;
// - a vertex has no influence with a non-zero weight;
// - the skin has more than 2^32 - 1 influences.
// With normalize off, weights that do not sum to 1 are kept and reported,
// not refused. `report`, when given, is filled on success.
Result<Skin> build_skin(const SkinInfluenceView& influences, const SkinBuildOptions& options,
                        SkinBuildReport* report = nullptr);

// Per-vertex lists -> Skin: make_skin({{{0, 1.0}}, {{0, 0.5}, {1, 0.5}}}, 2).
Result<Skin> make_skin(std::span<const std::vector<SkinInfluence>> vertices, std::size_t joint_count,
                       const SkinBuildOptions& options = {}, SkinBuildReport* report = nullptr);

// Accumulates vertices one at a time (or glTF-style fixed-stride sets) into
// the flat arrays, then builds. Nothing is checked before build().
class SkinBuilder {
 public:
  explicit SkinBuilder(std::size_t joint_count) { options_.joint_count = joint_count; }

  SkinBuildOptions& options() { return options_; }

  // Appends one vertex with its influences.
  SkinBuilder& add_vertex(std::span<const SkinInfluence> influences);
  SkinBuilder& add_vertex(std::initializer_list<SkinInfluence> influences) {
    return add_vertex(std::span<const SkinInfluence>(influences.begin(), influences.size()));
  }
  // Appends joints.size() / per_vertex vertices, each with `per_vertex`
  // consecutive (joint, weight) pairs: glTF's JOINTS_0/WEIGHTS_0 with
  // per_vertex 4, or several sets concatenated per vertex (JOINTS_0,
  // JOINTS_1, JOINTS_2: per_vertex 12). Trailing entries that do not fill a
  // vertex, and a per_vertex of 0, are ignored.
  SkinBuilder& add_vertices(std::span<const std::int64_t> joints, std::span<const double> weights,
                            std::size_t per_vertex);

  std::size_t vertex_count() const { return offsets_.size() - 1; }
  SkinInfluenceView view() const { return {offsets_, joints_, weights_}; }

  Result<Skin> build(SkinBuildReport* report = nullptr) const { return build_skin(view(), options_, report); }

 private:
  SkinBuildOptions options_;
  std::vector<std::int64_t> offsets_ = {0};
  std::vector<std::int64_t> joints_;
  std::vector<double> weights_;
};

}  // namespace rigel::ops
