// Helpers the component classes share (aim.h).
#include "aim.h"

#include <string>

#include "rigel/math/transform.h"
#include "rigel/ops/constraints/nodes.h"
#include "rigel/scene/transform_types.h"

namespace rigel::rig::components {

std::optional<math::Vec3> axis_named(std::string_view name) {
  static const std::pair<std::string_view, math::Vec3> kAxes[] = {
      {"x", math::Vec3::UnitX()},  {"y", math::Vec3::UnitY()},  {"z", math::Vec3::UnitZ()},
      {"-x", -math::Vec3::UnitX()}, {"-y", -math::Vec3::UnitY()}, {"-z", -math::Vec3::UnitZ()}};
  for (const auto& [n, v] : kAxes)
    if (name == n) return v;
  return std::nullopt;
}

math::Mat3 rotation_of(const math::Mat4& m) { return math::decompose(m).rotation.toRotationMatrix(); }

Status aim_constraint(BuildContext& ctx, NodeId driven, NodeId target, const math::Vec3& aim, const math::Vec3& up,
                      const math::Vec3& world_up, NodeId up_node, int index) {
  graph::Graph& g = ctx.graph();
  auto attr = [&](NodeId node, const char* name) {
    return graph::Plug{node, g.node(node)->type().attr_find(name), -1};
  };
  ConstraintSpec spec;
  spec.type = ops::constraints::kAimConstraintType;
  spec.role = "aimConstraint";
  spec.targets = {target};
  spec.maintain_offset = false;
  spec.channels = {"rotate"};
  Result<NodeId> c = ctx.constrain(spec, driven, index);
  if (!c) return c.status();
  Status s = g.set_value(attr(*c, "aimVector"), graph::Value(aim));
  if (s) s = g.set_value(attr(*c, "upVector"), graph::Value(up));
  if (s) s = g.set_value(attr(*c, "worldUpType"), graph::Value(std::int64_t{2}));  // objectRotation
  if (s) s = g.set_value(attr(*c, "worldUpVector"), graph::Value(world_up));
  if (s) s = g.connect(graph::Plug{up_node, scene::xform::kWorldMatrix, -1}, attr(*c, "worldUpMatrix"));
  if (s) s = g.set_value(attr(*c, "constraintTranslate"), g.node(driven)->value(scene::xform::kTranslate));
  if (!s) return s.with_context(ctx.full_name() + ": aim " + std::to_string(index));
  return Status::ok();
}

}  // namespace rigel::rig::components
