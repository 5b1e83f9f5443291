#pragma once
// The scene: a dependency graph of transform-hierarchy nodes, with helpers
// for the hierarchy, world matrices and frame-based time.

#include <memory>
#include <string_view>
#include <vector>

#include "rigel/graph/graph.h"
#include "rigel/math/types.h"
#include "rigel/scene/transform_types.h"

namespace rigel::scene {

using graph::Graph;
using graph::NodeId;
using math::Mat4;

class Scene {
 public:
  // A scene over default_registry().
  Scene();
  explicit Scene(std::shared_ptr<const graph::Registry> registry);

  Graph& graph() { return graph_; }
  const Graph& graph() const { return graph_; }

  // Creates a node of `type` named `name` under `parent` (invalid: a root),
  // as one undo step.
  Result<NodeId> create(std::string_view type, std::string_view name, NodeId parent = NodeId{});

  bool is_transform(NodeId node) const;
  // Transform nodes without a parent, in creation order.
  std::vector<NodeId> roots() const;
  // Every transform node, depth first from the roots, parents before
  // children, siblings in creation order.
  std::vector<NodeId> hierarchy() const;
  // Depth below its root (roots are 0).
  int depth(NodeId node) const;

  // Evaluated local (without offset parent) and world matrices; the
  // identity for a node that is not a transform (or does not exist).
  Mat4 local_matrix(NodeId node);
  Mat4 world_matrix(NodeId node);

  // Parents `child` under `parent` (invalid: the world). With keep_world the
  // child's local channels are rewritten so it stays where it is (Maya's
  // default); its pivots and rotate axis must be zero then, otherwise the
  // call fails. A joint keeps its joint orient; the rotation absorbs the
  // difference. Fails when the new parent's world matrix is singular.
  Status reparent(NodeId child, NodeId parent, bool keep_world);

  // The local channels that put transform `node` at `world` under its
  // current parent space (its parentMatrix input and offsetParentMatrix, as
  // evaluated now). A joint keeps its joint orient; the rotation absorbs the
  // difference. Fails, naming the node, when its rotate axis or pivots are
  // not zero or its parent space is singular.
  struct LocalChannels {
    math::Vec3 translate = math::Vec3::Zero();
    graph::AttrIndex rotation_attr = 0;  // xform::kRotate (degrees, Vec3) or kRotateQuaternion (Quat)
    graph::Value rotation;
    math::Vec3 scale = math::Vec3::Ones();
    math::Vec3 shear = math::Vec3::Zero();
  };
  Result<LocalChannels> channels_for_world(NodeId node, const Mat4& world);

  // Frame-based time over the graph's seconds: frame = seconds * fps,
  // snapped to the nearest whole frame when within rounding error of it
  // (31 / 120 * 120 is 31.000000000000004 in doubles).
  double frame() const;
  void set_frame(double frame) { graph_.set_time(frame / graph_.fps()); }

 private:
  Graph graph_;
};

}  // namespace rigel::scene
