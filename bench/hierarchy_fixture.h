#pragma once
// Transform hierarchies for the benchmarks: chains and bushy (4-ary,
// breadth-first) trees of scene joints, built once per (shape, size) and kept
// for the life of the process, so that a 100,000-node scene is not rebuilt
// for every benchmark run (Google Benchmark calls a benchmark function
// several times while it sizes the iteration count, and several files share
// the same hierarchies). All of them together stay under about 1 GB.

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "rigel/math/local_to_world.h"
#include "rigel/math/types.h"
#include "rigel/scene/scene.h"

namespace rigel::bench {

enum class Shape { kChain, kBushy };

// Children per node of a bushy tree.
inline constexpr std::int32_t kBushyFanout = 4;

const char* shape_name(Shape shape);

// Parent index of each node, parents before children: a chain
// (parents[i] = i - 1) or a breadth-first 4-ary tree (parents[i] = (i-1)/4).
// parents[0] is math::kNoParent.
std::vector<std::int32_t> make_parents(Shape shape, std::size_t count);

// Realistic affine local matrices: a random rotation and a translation of
// about unit length, last row 0 0 0 1. Deterministic (fixed seed).
std::vector<math::Mat4> make_local_matrices(std::size_t count);

// A scene holding one joint hierarchy. nodes[i] is the joint with parent
// nodes[parents[i]]. Every joint has a non-trivial translate, rotate and
// joint orient; the scene has been evaluated once (schedule compiled,
// everything clean) and its undo history cleared.
struct Hierarchy {
  Shape shape = Shape::kChain;
  std::unique_ptr<scene::Scene> scene;
  std::vector<graph::NodeId> nodes;
  std::vector<std::int32_t> parents;
  // Wall-clock seconds the build took (creation + first evaluation).
  double build_seconds = 0.0;
};

// The cached hierarchy for (shape, count), built on first use. nullptr (with
// `error` set) if the scene refused an edit.
Hierarchy* hierarchy_ensure(Shape shape, std::size_t count, std::string* error);

// Nodes of the subtree rooted at `index` (itself included), parents first.
std::vector<std::int32_t> subtree(std::span<const std::int32_t> parents, std::int32_t index);

// The nodes of `nodes` (a subtree, see above) that have no child in it.
std::vector<std::int32_t> subtree_leaves(std::span<const std::int32_t> parents, std::span<const std::int32_t> nodes);

// A value for a channel that differs on every call, so that
// Graph::set_value never takes its "value unchanged" early-out.
math::Vec3 next_channel_value();

}  // namespace rigel::bench
