#include "hierarchy_fixture.h"

#include <chrono>
#include <map>
#include <utility>
#include <random>

#include "rigel/math/transform.h"
#include "rigel/scene/transform_types.h"

namespace rigel::bench {

const char* shape_name(Shape shape) { return shape == Shape::kChain ? "chain" : "bushy"; }

std::vector<std::int32_t> make_parents(Shape shape, std::size_t count) {
  std::vector<std::int32_t> parents(count, math::kNoParent);
  for (std::size_t i = 1; i < count; ++i) {
    const auto index = static_cast<std::int32_t>(i);
    parents[i] = shape == Shape::kChain ? index - 1 : (index - 1) / kBushyFanout;
  }
  return parents;
}

std::vector<math::Mat4> make_local_matrices(std::size_t count) {
  std::mt19937 rng(0x5eed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<math::Mat4> local(count);
  for (math::Mat4& m : local) {
    // A normalised 4D Gaussian is a uniformly random rotation.
    math::Quat q(normal(rng), normal(rng), normal(rng), normal(rng));
    q.normalize();
    m = math::trs_matrix(math::Vec3(uniform(rng), uniform(rng), uniform(rng)), q, math::Vec3::Ones());
  }
  return local;
}

namespace {

using Cache = std::map<std::pair<Shape, std::size_t>, std::unique_ptr<Hierarchy>>;

Cache& cache() {
  static Cache instance;
  return instance;
}

std::unique_ptr<Hierarchy> build(Shape shape, std::size_t count, std::string* error) {
  const auto start = std::chrono::steady_clock::now();
  auto h = std::make_unique<Hierarchy>();
  h->shape = shape;
  h->scene = std::make_unique<scene::Scene>();
  h->parents = make_parents(shape, count);
  h->nodes.reserve(count);
  graph::Graph& g = h->scene->graph();
  std::mt19937 rng(0xbeef);
  std::uniform_real_distribution<double> angle(-30.0, 30.0);  // degrees
  for (std::size_t i = 0; i < count; ++i) {
    const graph::NodeId parent = h->parents[i] == math::kNoParent ? graph::NodeId{} : h->nodes[h->parents[i]];
    // Distinct names: Graph::unique_name() probes "joint1", "joint2", ...
    // one by one, which would make building quadratic. (Appended rather than
    // "j" + to_string(i): GCC 12 warns falsely on that form, -Wrestrict.)
    std::string name = "j";
    name += std::to_string(i);
    Result<graph::NodeId> id = h->scene->create(scene::kJointType, name, parent);
    if (!id) {
      *error = id.status().message();
      return nullptr;
    }
    h->nodes.push_back(*id);
    const math::Vec3 translate(0.1 * angle(rng) / 30.0, 1.0, 0.0);
    const math::Vec3 rotate(angle(rng), angle(rng), angle(rng));
    const math::Vec3 orient(0.0, 0.0, angle(rng));
    for (auto [attr, value] : {std::pair<graph::AttrIndex, math::Vec3>{scene::xform::kTranslate, translate},
                               {scene::xform::kRotate, rotate},
                               {scene::joint_attr::kJointOrient, orient}}) {
      if (Status s = g.set_value(graph::Plug{*id, attr, -1}, value); !s) {
        *error = s.message();
        return nullptr;
      }
    }
  }
  g.clear_history();
  g.evaluate_all(graph::Execution::kSerial);  // compiles the schedule, cleans everything
  h->build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return h;
}

}  // namespace

Hierarchy* hierarchy_ensure(Shape shape, std::size_t count, std::string* error) {
  std::unique_ptr<Hierarchy>& slot = cache()[{shape, count}];
  if (!slot) slot = build(shape, count, error);
  return slot.get();
}

std::vector<std::int32_t> subtree(std::span<const std::int32_t> parents, std::int32_t index) {
  // Parents come before children, so one forward sweep marks the subtree.
  std::vector<std::uint8_t> inside(parents.size(), 0);
  std::vector<std::int32_t> result;
  inside[static_cast<std::size_t>(index)] = 1;
  result.push_back(index);
  for (std::size_t i = static_cast<std::size_t>(index) + 1; i < parents.size(); ++i) {
    if (parents[i] != math::kNoParent && inside[static_cast<std::size_t>(parents[i])]) {
      inside[i] = 1;
      result.push_back(static_cast<std::int32_t>(i));
    }
  }
  return result;
}

std::vector<std::int32_t> subtree_leaves(std::span<const std::int32_t> parents, std::span<const std::int32_t> nodes) {
  std::vector<std::uint8_t> has_child(parents.size(), 0);
  for (std::int32_t i : nodes) {
    const std::int32_t p = parents[static_cast<std::size_t>(i)];
    if (p != math::kNoParent) has_child[static_cast<std::size_t>(p)] = 1;
  }
  std::vector<std::int32_t> leaves;
  for (std::int32_t i : nodes) {
    if (!has_child[static_cast<std::size_t>(i)]) leaves.push_back(i);
  }
  return leaves;
}

math::Vec3 next_channel_value() {
  static std::uint64_t counter = 0;
  ++counter;
  // Small, bounded and never repeating two calls in a row.
  return math::Vec3(0.001 * static_cast<double>(counter % 1000) + 0.0005, 0.25, -0.5);
}

}  // namespace rigel::bench
