#pragma once
// Blend shapes (morph targets): out = base + sum_t weight_t * delta_t.
// Targets are compiled once (BlendShapeBuilder -> BlendShapeTargets), each
// stored dense (one delta per vertex, as glTF's morph targets) or sparse
// (sorted vertex indices and their deltas, for the usual target that moves a
// face or a hand and leaves the rest of the mesh alone). The builder picks.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/ops/deform/vertex.h"

namespace rigel::ops {

// Compiled targets: validated, zero deltas dropped, sparse indices sorted.
// Built only by BlendShapeBuilder; a default-constructed one has no
// vertices and no targets.
class BlendShapeTargets {
 public:
  // One target's deltas. Dense: indices is empty and deltas has one entry
  // per vertex. Sparse: deltas[i] moves vertex indices[i]; indices ascend.
  struct Target {
    std::span<const std::uint32_t> indices;
    std::span<const Vec3f> deltas;
    bool dense = false;
  };

  std::size_t vertex_count() const { return vertex_count_; }
  std::size_t target_count() const { return targets_.size(); }
  Target target(std::size_t t) const;
  // Deltas stored (dense targets count every vertex).
  std::size_t stored_delta_count() const { return deltas_.size(); }

 private:
  friend class BlendShapeBuilder;
  struct Range {
    std::size_t delta_begin = 0;
    std::size_t index_begin = 0;
    std::size_t count = 0;
    bool dense = false;
  };
  std::size_t vertex_count_ = 0;
  std::vector<Range> targets_;
  std::vector<Vec3f> deltas_;
  std::vector<std::uint32_t> indices_;
};

// Collects targets for a mesh of `vertex_count` vertices, then validates and
// compiles them. Nothing is checked before build().
class BlendShapeBuilder {
 public:
  explicit BlendShapeBuilder(std::size_t vertex_count) : vertex_count_(vertex_count) {}

  // A target is stored sparse when it moves fewer than this fraction of the
  // vertices (a sparse entry is 16 bytes, a dense one 12, and a dense target
  // streams without indirection).
  double sparse_below = 0.5;

  // One delta per vertex (glTF).
  BlendShapeBuilder& add_dense_target(std::span<const Vec3f> deltas);
  // deltas[i] moves vertex indices[i]; any order.
  BlendShapeBuilder& add_sparse_target(std::span<const std::int64_t> indices, std::span<const Vec3f> deltas);

  std::size_t target_count() const { return pending_.size(); }

  // Fails, naming the target (and the vertex), when:
  // - the mesh has more than 2^32 - 1 vertices;
  // - a dense target does not have vertex_count deltas;
  // - a sparse target's indices and deltas differ in length;
  // - a sparse index is negative or not below vertex_count, or a vertex is
  //   listed twice in one target;
  // - a delta holds a NaN or infinity.
  Result<BlendShapeTargets> build() const;

 private:
  struct Pending {
    bool dense = false;
    std::vector<std::int64_t> indices;
    std::vector<Vec3f> deltas;
  };
  std::size_t vertex_count_;
  std::vector<Pending> pending_;
};

// out[v] = base[v] + sum over targets t, in order, of weights[t] * delta_t[v].
// Targets whose weight is 0 are skipped. Every vertex is independent and
// gives the same bits whatever range runs it.
struct BlendShapeJob {
  // Validates job parameters. Returns false:
  // - if targets is nullptr;
  // - if base or out does not have targets->vertex_count() entries;
  // - if weights does not have targets->target_count() entries;
  // - if a weight is NaN or infinite;
  // - if out overlaps base without being exactly base (in place is fine).
  bool validate() const;
  bool run() const;
  // Vertices [begin, end) only; false if not valid or the range is not
  // within [0, vertex_count].
  bool run(std::size_t begin, std::size_t end) const;
  bool run_parallel(std::size_t grain = 0) const;

  const BlendShapeTargets* targets = nullptr;
  std::span<const Vec3f> base;
  std::span<const float> weights;
  std::span<Vec3f> out;
};

}  // namespace rigel::ops
