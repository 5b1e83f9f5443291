#include "rigel/scene/skeleton.h"

#include <unordered_map>

#include "rigel/math/local_to_world.h"
#include "rigel/scene/scene.h"

namespace rigel::scene {

Result<Skeleton> Skeleton::compile(const Scene& scene, std::span<const graph::NodeId> roots) {
  const Graph& g = scene.graph();
  std::vector<graph::NodeId> starts(roots.begin(), roots.end());
  if (starts.empty()) starts = scene.roots();
  for (graph::NodeId r : starts) {
    if (!scene.is_transform(r)) return error(ErrorCode::kInvalidArgument, "skeleton: a root is not a transform node");
  }
  Skeleton s;
  s.generation_ = g.topology_generation();
  std::unordered_map<std::uint32_t, std::int32_t> index;  // node slot -> skeleton index
  std::vector<std::pair<graph::NodeId, std::int32_t>> stack;
  for (auto it = starts.rbegin(); it != starts.rend(); ++it) stack.emplace_back(*it, math::kNoParent);
  while (!stack.empty()) {
    auto [id, parent] = stack.back();
    stack.pop_back();
    if (index.count(id.index)) return error(ErrorCode::kInvalidArgument, "skeleton: node '" + g.node(id)->name() + "' is reached twice");
    auto i = static_cast<std::int32_t>(s.nodes_.size());
    index.emplace(id.index, i);
    s.nodes_.push_back(id);
    s.parents_.push_back(parent);
    s.names_.push_back(g.node(id)->name());
    std::vector<graph::NodeId> kids = g.children(id);
    for (auto k = kids.rbegin(); k != kids.rend(); ++k) stack.emplace_back(*k, i);
  }
  return s;
}

Status Skeleton::evaluate(Scene& scene, std::span<math::Mat4> local, std::span<math::Mat4> world) const {
  if (local.size() != size() || world.size() != size())
    return error(ErrorCode::kInvalidArgument, "skeleton evaluate: spans must have one matrix per joint");
  Graph& g = scene.graph();
  if (g.topology_generation() != generation_)
    return error(ErrorCode::kInvalidArgument, "skeleton evaluate: the scene's topology changed; compile again");
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    const auto& offset = std::get<math::Mat4>(g.evaluate(nodes_[i], xform::kOffsetParentMatrix));
    const auto& m = std::get<math::Mat4>(g.evaluate(nodes_[i], xform::kMatrix));
    local[i] = offset * m;
    if (parents_[i] == math::kNoParent) local[i] = std::get<math::Mat4>(g.evaluate(nodes_[i], xform::kParentMatrix)) * local[i];
  }
  math::LocalToWorldJob job;
  job.parents = parents_;
  job.local = local;
  job.world = world;
  if (!job.run()) return error(ErrorCode::kInvalidArgument, "skeleton evaluate: invalid hierarchy");
  return Status::ok();
}

}  // namespace rigel::scene
