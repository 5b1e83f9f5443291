// Mechanical component classes: piston (two ends aiming at each other),
// squash (a joint that aims at a control and stretches to reach it) and
// wheel (a wheel that rolls as it travels).
#include "rigel/rig/components/mechanical.h"

#include "aim.h"

#include <cmath>
#include <string>

#include "rigel/math/transform.h"
#include "rigel/ops/util/nodes.h"
#include "rigel/rig/build_context.h"
#include "rigel/rig/component.h"
#include "rigel/scene/transform_types.h"

namespace rigel::rig::components {
namespace {

using graph::Plug;
using graph::Value;
using math::Mat3;
using math::Mat4;
using math::Vec3;
namespace xform = scene::xform;

Status piston_guides(BuildContext& ctx, Mat4 worlds[2]) {
  if (ctx.guide_count() != 2)
    return error(ErrorCode::kInvalidArgument,
                 ctx.full_name() + ": a piston needs 2 guides (start, end), it has " + std::to_string(ctx.guide_count()));
  for (int i = 0; i < 2; ++i) {
    if (ctx.component().guides[i].joint.empty())
      return error(ErrorCode::kInvalidArgument,
                   ctx.full_name() + ": guide " + std::to_string(i) + " of a piston must name a joint");
    Result<Mat4> w = ctx.guide_world(i);
    if (!w) return w.status();
    worlds[i] = *w;
  }
  if ((worlds[1].topRightCorner<3, 1>() - worlds[0].topRightCorner<3, 1>()).norm() < 1e-9)
    return error(ErrorCode::kInvalidArgument, ctx.full_name() + ": the piston's start and end joints coincide");
  return Status::ok();
}

// An aim constraint on `hook` (a group under `up_control` at a joint whose
// rest world is `rest`) at `target`: the aim vector the rest direction to
// `target_rest` in the joint's frame, the up the joint axis most across it,
// the world up following `up_control` (objectRotation), so that at rest the
// constraint gives the joint's own rotation.
Status aim_at(BuildContext& ctx, NodeId hook, NodeId up_control, NodeId target, const Mat4& rest_world,
              const Vec3& target_rest, int index) {
  const Mat3 rest = rotation_of(rest_world);
  const Vec3 aim = rest.transpose() * (target_rest - rest_world.topRightCorner<3, 1>()).normalized();
  Vec3 up = Vec3::UnitX();
  for (const Vec3& a : {Vec3(Vec3::UnitY()), Vec3(Vec3::UnitZ())})
    if (std::abs(a.dot(aim)) < std::abs(up.dot(aim))) up = a;
  up = (up - up.dot(aim) * aim).normalized();
  const Vec3 world_up = rotation_of(ctx.scene().world_matrix(up_control)).transpose() * (rest * up);
  return aim_constraint(ctx, hook, target, aim, up, world_up, up_control, index);
}

Status squash_guides(BuildContext& ctx, Mat4 worlds[2]) {
  if (ctx.guide_count() != 2 || ctx.component().guides[0].joint.empty())
    return error(ErrorCode::kInvalidArgument, ctx.full_name() + ": a squash needs 2 guides, a start joint and an end");
  for (int i = 0; i < 2; ++i) {
    Result<Mat4> w = ctx.guide_world(i);
    if (!w) return w.status();
    worlds[i] = *w;
  }
  if ((worlds[1].topRightCorner<3, 1>() - worlds[0].topRightCorner<3, 1>()).norm() < 1e-9)
    return error(ErrorCode::kInvalidArgument, ctx.full_name() + ": the squash's start and end coincide");
  return Status::ok();
}

class Piston : public ComponentClass {
 public:
  std::string_view type() const override { return "piston"; }
  std::vector<Step> steps(const Component&) const override {
    return {
        Step{"controls", "", "",
             [](BuildContext& ctx) -> Status {
               Mat4 worlds[2];
               if (Status s = piston_guides(ctx, worlds); !s) return s;
               const char* roles[] = {"start", "end"};
               for (int i = 0; i < 2; ++i) {
                 Result<NodeId> c = ctx.create_control(roles[i], -1, i, worlds[i], ctx.attach_node());
                 if (!c) return c.status();
                 Result<NodeId> hook = ctx.create_group("hook", i, worlds[i], *c);
                 if (!hook) return hook.status();
                 if (Status s = ctx.publish_hook(i, *hook); !s) return s;
               }
               return Status::ok();
             }},
        Step{"aim", "", "",
             [](BuildContext& ctx) -> Status {
               Mat4 worlds[2];
               if (Status s = piston_guides(ctx, worlds); !s) return s;
               const NodeId controls[] = {ctx.node("start"), ctx.node("end")};
               for (int i = 0; i < 2; ++i)
                 if (Status s = aim_at(ctx, ctx.node("hook", i), controls[i], controls[1 - i], worlds[i],
                                       worlds[1 - i].topRightCorner<3, 1>(), i);
                     !s)
                   return s;
               return Status::ok();
             }},
        Step{"drive", "", "",
             [](BuildContext& ctx) -> Status {
               for (int i = 0; i < 2; ++i) {
                 Result<NodeId> joint = ctx.guide_joint(i);
                 if (!joint) return joint.status();
                 if (Status s = ctx.drive(ctx.node("hook", i), *joint); !s) return s;
               }
               return Status::ok();
             }},
    };
  }
};

class Squash : public ComponentClass {
 public:
  std::string_view type() const override { return "squash"; }
  std::vector<Step> steps(const Component&) const override {
    return {
        Step{"controls", "", "",
             [](BuildContext& ctx) -> Status {
               Mat4 worlds[2];
               if (Status s = squash_guides(ctx, worlds); !s) return s;
               Result<NodeId> start = ctx.create_control("start", -1, 0, worlds[0], ctx.attach_node());
               if (!start) return start.status();
               Result<NodeId> end = ctx.create_control("end", -1, 1, worlds[1], *start);
               if (!end) return end.status();
               Result<NodeId> hook = ctx.create_group("hook", -1, worlds[0], *start);
               if (!hook) return hook.status();
               if (Status s = ctx.publish_hook(0, *hook); !s) return s;
               return ctx.publish_hook(1, *end);
             }},
        Step{"aim", "", "",
             [](BuildContext& ctx) -> Status {
               Mat4 worlds[2];
               if (Status s = squash_guides(ctx, worlds); !s) return s;
               return aim_at(ctx, ctx.node("hook"), ctx.node("start"), ctx.node("end"), worlds[0],
                             worlds[1].topRightCorner<3, 1>(), -1);
             }},
        Step{"stretch", "", "",
             [](BuildContext& ctx) -> Status {
               namespace sq = ops::util::squash_attr;
               Mat4 worlds[2];
               if (Status s = squash_guides(ctx, worlds); !s) return s;
               Result<NodeId> joint = ctx.guide_joint(0);
               if (!joint) return joint.status();
               graph::Graph& g = ctx.graph();
               // Translate and rotate follow the hook; scale comes from the squashStretch node.
               ConstraintSpec spec;
               spec.role = "drive";
               spec.targets = {ctx.node("hook")};
               spec.channels = {"translate", "rotate"};
               if (Result<NodeId> k = ctx.constrain(spec, *joint); !k) return k.status();
               Result<NodeId> node = ctx.create(ops::util::kSquashStretchType, "squashStretch");
               if (!node) return node.status();
               const std::string axis = ctx.param_string("axis");
               Status s = g.connect(Plug{ctx.node("start"), xform::kWorldMatrix, -1}, Plug{*node, sq::kStartMatrix, -1});
               if (s) s = g.connect(Plug{ctx.node("end"), xform::kWorldMatrix, -1}, Plug{*node, sq::kEndMatrix, -1});
               if (s)
                 s = g.set_value(Plug{*node, sq::kRestLength, -1},
                                 Value((worlds[1].topRightCorner<3, 1>() - worlds[0].topRightCorner<3, 1>()).norm()));
               if (s) s = g.set_value(Plug{*node, sq::kAxis, -1}, Value(std::int64_t(axis == "x" ? 0 : axis == "z" ? 2 : 1)));
               if (s) s = g.set_value(Plug{*node, sq::kVolume, -1}, Value(ctx.param_double("volume")));
               if (s) s = g.set_value(Plug{*node, sq::kRestScale, -1}, g.node(*joint)->value(xform::kScale));
               if (s) s = g.connect(Plug{*node, sq::kScale, -1}, Plug{*joint, xform::kScale, -1});
               if (!s) return s.with_context(ctx.full_name() + ": squashStretch");
               return Status::ok();
             }},
    };
  }
};

// An axis parameter (its schema keeps it one of the six names; else z).
Vec3 axis_of(const std::string& name) { return axis_named(name).value_or(Vec3(Vec3::UnitZ())); }

class Wheel : public ComponentClass {
 public:
  std::string_view type() const override { return "wheel"; }
  std::vector<Step> steps(const Component&) const override {
    return {
        Step{"controls", "", "",
             [](BuildContext& ctx) -> Status {
               if (ctx.guide_count() != 1 || ctx.component().guides[0].joint.empty())
                 return error(ErrorCode::kInvalidArgument, ctx.full_name() + ": a wheel needs 1 guide, its joint");
               if (axis_of(ctx.param_string("axle")).cross(axis_of(ctx.param_string("forward"))).norm() < 0.5)
                 return error(ErrorCode::kInvalidArgument, ctx.full_name() + ": the wheel's axle and forward axes "
                                                                             "must differ");
               Result<Mat4> world = ctx.guide_world(0);
               if (!world) return world.status();
               Result<NodeId> main = ctx.create_control("main", -1, 0, *world, ctx.attach_node());
               if (!main) return main.status();
               Result<NodeId> roll = ctx.create_group("roll", -1, *world, *main);
               if (!roll) return roll.status();
               Result<NodeId> spin = ctx.create_control("spin", -1, 0, *world, *roll);
               if (!spin) return spin.status();
               if (Status s = ctx.publish_hook(0, *main); !s) return s;
               return ctx.publish_hook(1, *spin);
             }},
        Step{"roll", "", "",
             [](BuildContext& ctx) -> Status {
               namespace wh = ops::util::wheel_attr;
               graph::Graph& g = ctx.graph();
               const NodeId main = ctx.node("main");
               Result<NodeId> node = ctx.create(ops::util::kWheelRollType, "wheelRoll");
               if (!node) return node.status();
               Status s = g.connect(Plug{main, xform::kWorldMatrix, -1}, Plug{*node, wh::kMatrix, -1});
               if (s) s = g.set_value(Plug{*node, wh::kRestMatrix, -1}, Value(ctx.scene().world_matrix(main)));
               if (s) s = g.set_value(Plug{*node, wh::kForward, -1}, Value(axis_of(ctx.param_string("forward"))));
               if (s) s = g.set_value(Plug{*node, wh::kAxle, -1}, Value(axis_of(ctx.param_string("axle"))));
               if (s) s = g.set_value(Plug{*node, wh::kRadius, -1}, Value(ctx.param_double("radius")));
               if (s) s = g.connect(Plug{*node, wh::kRotate, -1}, Plug{ctx.node("roll"), xform::kRotate, -1});
               if (!s) return s.with_context(ctx.full_name() + ": wheelRoll");
               return Status::ok();
             }},
        Step{"drive", "", "",
             [](BuildContext& ctx) -> Status {
               Result<NodeId> joint = ctx.guide_joint(0);
               if (!joint) return joint.status();
               return ctx.drive(ctx.node("spin"), *joint);
             }},
    };
  }
};

}  // namespace

Status add_mechanical_components(ComponentFactory& factory) {
  if (Status s = factory.add(std::make_shared<Piston>()); !s) return s;
  if (Status s = factory.add(std::make_shared<Squash>()); !s) return s;
  return factory.add(std::make_shared<Wheel>());
}

}  // namespace rigel::rig::components
