#pragma once
// The scene: a dependency graph of transform-hierarchy nodes, with helpers
// for the hierarchy, world matrices and frame-based time.

#include <memory>
#include <optional>
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
  // evaluated now): the one world-to-local routine (reparenting, baking,
  // builds, posing). A joint keeps its joint orient; the rotation absorbs
  // the difference. Fails, naming the node, when its parent space is
  // singular, or (full decomposition) its rotate axis or pivots are not
  // zero, or (keep_scale_shear) its scale and shear are singular.
  struct LocalChannels {
    math::Vec3 translate = math::Vec3::Zero();
    graph::AttrIndex rotation_attr = 0;  // xform::kRotate (degrees, Vec3) or kRotateQuaternion (Quat)
    graph::Value rotation;
    math::Vec3 scale = math::Vec3::Ones();
    math::Vec3 shear = math::Vec3::Zero();
    // Whether the channels reproduce `world` (to rounding). Only a
    // keep_scale_shear fit can miss: when world's linear part is not the
    // kept scale and shear turned, the fitted rotation is not orthonormal
    // (within 1e-10) and the rotation channel is its nearest reading.
    bool exact = true;
  };
  // How the channels are fitted; the defaults decompose the whole local
  // matrix under the parent space as evaluated now.
  struct ChannelFit {
    // The parent space's world matrix to fit under (what parentMatrix
    // would be), for a solver that places parents and children before
    // writing either. Unset: parentMatrix as evaluated now.
    std::optional<Mat4> parent_world;
    // Keep scale, shear and rotate axis as they are (the output holds them
    // unchanged) and fit translate and the rotation only; rotate axis and
    // pivots may then be non-zero. What a posing tool writes: it moves
    // controls, it never scales them.
    bool keep_scale_shear = false;
    // The rotation nearest the node's current one: the Euler angles closest
    // to rotate (math::euler_closest, so keys interpolate the short way),
    // the quaternion on rotateQuaternion's side. Otherwise the principal
    // angles, and the quaternion of either sign.
    bool nearest_rotation = false;
    // With keep_scale_shear, when the node has no pivots: fit the translate
    // only (the same value as the whole fit gives) and keep the rotation
    // as it is, for a solver that knows the local rotation did not change
    // (a body motion turning a control and its parent alike).
    bool translate_only = false;
  };
  Result<LocalChannels> channels_for_world(NodeId node, const Mat4& world);
  Result<LocalChannels> channels_for_world(NodeId node, const Mat4& world, const ChannelFit& fit);

  // Frame-based time over the graph's seconds: frame = seconds * fps,
  // snapped to the nearest whole frame when within rounding error of it
  // (31 / 120 * 120 is 31.000000000000004 in doubles).
  double frame() const;
  void set_frame(double frame) { graph_.set_time(frame / graph_.fps()); }

 private:
  Graph graph_;
};

}  // namespace rigel::scene
