#pragma once
// Scene node types: transform, joint, control, locator and mesh. Every one
// of them is a transform: they share the leading attributes below, in this
// order, so compute functions and tools address them by constant index.

#include <memory>

#include "rigel/base/status.h"
#include "rigel/graph/node_type.h"
#include "rigel/math/transform.h"

namespace rigel::graph {
class Node;
}

namespace rigel::scene {

using graph::AttrIndex;

// Attributes shared by all transform types (angles in degrees).
namespace xform {
enum : AttrIndex {
  kTranslate = 0,          // double3, keyable
  kRotate,                 // double3 angle, keyable (Euler, used in euler mode)
  kRotateOrder,            // enum xyz yzx zxy xzy yxz zyx
  kRotateMode,             // enum euler quaternion
  kRotateQuaternion,       // quaternion (used in quaternion mode)
  kScale,                  // double3, keyable, default 1 1 1
  kShear,                  // double3 xy xz yz
  kRotateAxis,             // double3 angle
  kRotatePivot,            // double3
  kRotatePivotTranslate,   // double3
  kScalePivot,             // double3
  kScalePivotTranslate,    // double3
  kOffsetParentMatrix,     // matrix, between parent and local
  kParentMatrix,           // matrix, hidden: the parent's worldMatrix
  kVisibility,             // bool
  kMatrix,                 // output: local matrix
  kWorldMatrix,            // output: parentMatrix * offsetParentMatrix * matrix
  kCount
};

// kRotateMode's values (math::RotateMode) as the attribute stores them.
inline constexpr std::int64_t kEulerMode = static_cast<std::int64_t>(math::RotateMode::kEuler);
inline constexpr std::int64_t kQuaternionMode = static_cast<std::int64_t>(math::RotateMode::kQuaternion);
// Whether `node` (a transform of any type) keeps its rotation in
// rotateQuaternion, and the channel that holds it (kRotateQuaternion or
// kRotate): the one test of the rotate mode.
bool is_quaternion_mode(const graph::Node& node);
AttrIndex rotation_channel(const graph::Node& node);
}  // namespace xform

namespace joint_attr {
enum : AttrIndex { kJointOrient = xform::kCount, kRadius, kCount };
}
namespace control_attr {
// The control's curve shape, in its local space, drawn as a polyline
// (closed when shapeClosed), and its colour (linear RGB 0..1).
enum : AttrIndex { kShapePoints = xform::kCount, kShapeClosed, kShapeColor, kCount };
}
namespace locator_attr {
enum : AttrIndex { kLocalScale = xform::kCount, kCount };
}
namespace mesh_attr {
// Triangle mesh in the node's local space.
enum : AttrIndex { kPoints = xform::kCount, kNormals, kTriangles, kCount };
}

inline constexpr const char* kTransformType = "transform";
inline constexpr const char* kJointType = "joint";
inline constexpr const char* kControlType = "control";
inline constexpr const char* kLocatorType = "locator";
inline constexpr const char* kMeshType = "mesh";

// Adds the five scene types, the look types (materials.h) and the scene
// settings types (scene_options.h) to `registry`.
Status register_scene_types(graph::Registry& registry);

// A registry holding every node type this build knows (the scene types
// now; later layers add theirs here). Shared and immutable.
std::shared_ptr<const graph::Registry> default_registry();

// True when `type` is one of the transform types (has the shared prefix).
bool is_transform_type(const graph::NodeType& type);

}  // namespace rigel::scene
