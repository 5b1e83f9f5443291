#pragma once
// A compiled, flat, parent-first view of a transform hierarchy (STYLE.md
// §2: raw -> builder -> compiled). Playback, skinning and export read world
// matrices through it instead of walking the graph node by node.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/graph/graph.h"
#include "rigel/math/types.h"

namespace rigel::scene {

class Scene;

class Skeleton {
 public:
  // Every transform below `roots` (all roots of the scene when empty), parents
  // before children. Fails on a stale or non-transform root.
  static Result<Skeleton> compile(const Scene& scene, std::span<const graph::NodeId> roots = {});

  std::size_t size() const { return nodes_.size(); }
  std::span<const graph::NodeId> nodes() const { return nodes_; }
  // Index of each joint's parent in this skeleton, math::kNoParent for roots.
  std::span<const std::int32_t> parents() const { return parents_; }
  const std::string& name(std::size_t i) const { return names_[i]; }
  // The graph topology this skeleton was compiled from; recompile when the
  // graph's topology_generation() differs.
  std::uint64_t generation() const { return generation_; }

  // Evaluates local matrices (offset parent folded in) from the graph into
  // `local`, then world matrices into `world` with math::LocalToWorldJob.
  // The world of a root includes its own parent's world matrix when the
  // skeleton starts below the scene's roots. Both spans have size().
  Status evaluate(Scene& scene, std::span<math::Mat4> local, std::span<math::Mat4> world) const;

 private:
  std::vector<graph::NodeId> nodes_;
  std::vector<std::int32_t> parents_;
  std::vector<std::string> names_;
  std::uint64_t generation_ = 0;
};

}  // namespace rigel::scene
