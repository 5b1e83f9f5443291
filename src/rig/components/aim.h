#pragma once
// What several component classes share (src/rig/components/, not a public
// header): axis parameters, a transform's rotation without scale, and an
// aim constraint set up on a node (eye, piston, squash).
#include <optional>
#include <string_view>

#include "rigel/math/types.h"
#include "rigel/rig/build_context.h"

namespace rigel::rig::components {

// The unit axis an axis parameter names: "x", "y", "z", "-x", "-y", "-z";
// nullopt for anything else.
std::optional<math::Vec3> axis_named(std::string_view name);

// The rotation of an affine matrix without scale (columns normalised, made
// orthonormal).
math::Mat3 rotation_of(const math::Mat4& m);

// An aimConstraint (role "aimConstraint", index `index`) turning `driven`
// (a group: its rotate only, no offset kept) so that its `aim` axis points
// at `target` and its `up` axis toward `world_up` taken in `up_node`'s
// rotation (objectRotation); its pivot is `driven`'s translate now. Errors
// name the component and "aim INDEX".
Status aim_constraint(BuildContext& ctx, NodeId driven, NodeId target, const math::Vec3& aim, const math::Vec3& up,
                      const math::Vec3& world_up, NodeId up_node, int index);

}  // namespace rigel::rig::components
