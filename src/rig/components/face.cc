// The face's component classes: mouth (jaw and lips following it) and
// eyelid (lids following the eye and blinking) and brows (brow joints
// following a main control by falloff).
#include "rigel/rig/components/face.h"

#include "aim.h"

#include <string>

#include "rigel/math/transform.h"
#include "rigel/ops/constraints/nodes.h"
#include "rigel/ops/util/eyelid.h"
#include "rigel/scene/transform_types.h"
#include "rigel/rig/build_context.h"
#include "rigel/rig/component.h"

namespace rigel::rig::components {
namespace {

using math::Mat4;

// The share of the jaw's motion the lip at guide `guide` takes.
double follow_of(BuildContext& ctx, int guide) {
  if (guide == 1) return ctx.param_double("upperLipFollow");
  if (guide == 2) return ctx.param_double("lowerLipFollow");
  return ctx.param_double("cornerFollow");
}

Status check_guides(BuildContext& ctx) {
  if (ctx.guide_count() < 3 || ctx.guide_count() > 5)
    return error(ErrorCode::kInvalidArgument, ctx.full_name() + ": a mouth needs 3 to 5 guides (jaw, upper lip, "
                                                                "lower lip, lip corners), it has " +
                                                  std::to_string(ctx.guide_count()));
  for (int i = 0; i < ctx.guide_count(); ++i)
    if (ctx.component().guides[i].joint.empty())
      return error(ErrorCode::kInvalidArgument,
                   ctx.full_name() + ": guide " + std::to_string(i) + " of a mouth must name a joint");
  return Status::ok();
}

// The follow group `index` held between the attach point (weight 1 - f)
// and `leader` (weight f), by a parentConstraint (translate and rotate).
Status follow(BuildContext& ctx, std::string_view group_role, int index, NodeId leader, double f) {
  ConstraintSpec spec;
  spec.type = ops::constraints::kParentConstraintType;
  spec.role = std::string(group_role) + "Constraint";
  spec.space_role = std::string(group_role) + "Space";
  spec.targets = {ctx.attach_node(), leader};
  spec.weights = {1.0 - f, f};
  spec.channels = {"translate", "rotate"};
  return ctx.constrain(spec, ctx.node(group_role, index), index).status();
}

class Mouth : public ComponentClass {
 public:
  std::string_view type() const override { return "mouth"; }
  std::vector<Step> steps(const Component&) const override {
    return {
        Step{"controls", "", "",
             [](BuildContext& ctx) -> Status {
               if (Status s = check_guides(ctx); !s) return s;
               Result<Mat4> jaw_world = ctx.guide_world(0);
               if (!jaw_world) return jaw_world.status();
               Result<NodeId> jaw = ctx.create_control("jaw", -1, 0, *jaw_world, ctx.attach_node());
               if (!jaw) return jaw.status();
               if (Status s = ctx.publish_hook(0, *jaw); !s) return s;
               for (int g = 1; g < ctx.guide_count(); ++g) {
                 Result<Mat4> world = ctx.guide_world(g);
                 if (!world) return world.status();
                 Result<NodeId> group = ctx.create_group("lipFollow", g - 1, *world, ctx.attach_node());
                 if (!group) return group.status();
                 Result<NodeId> lip = ctx.create_control("lip", g - 1, g, *world, *group);
                 if (!lip) return lip.status();
                 if (g <= 2)
                   if (Status s = ctx.publish_hook(g, *lip); !s) return s;
               }
               return Status::ok();
             }},
        Step{"follow", "", "",
             [](BuildContext& ctx) -> Status {
               for (int g = 1; g < ctx.guide_count(); ++g)
                 if (Status s = follow(ctx, "lipFollow", g - 1, ctx.node("jaw"), follow_of(ctx, g)); !s) return s;
               return Status::ok();
             }},
        Step{"drive", "", "",
             [](BuildContext& ctx) -> Status {
               Result<NodeId> jaw = ctx.guide_joint(0);
               if (!jaw) return jaw.status();
               if (Status s = ctx.drive(ctx.node("jaw"), *jaw); !s) return s;
               for (int g = 1; g < ctx.guide_count(); ++g) {
                 Result<NodeId> joint = ctx.guide_joint(g);
                 if (!joint) return joint.status();
                 if (Status s = ctx.drive(ctx.node("lip", g - 1), *joint); !s) return s;
               }
               return Status::ok();
             }},
    };
  }
};

// ---- eyelid -------------------------------------------------------------

class Eyelid : public ComponentClass {
 public:
  std::string_view type() const override { return "eyelid"; }
  std::vector<Step> steps(const Component&) const override {
    return {
        // Each lid: a follow group at the eye in the eye's parent's frame
        // (turned by the eyelidBlink node) and a lid control under it.
        Step{"controls", "", "",
             [](BuildContext& ctx) -> Status {
               Result<NodeId> eye = ctx.guide_joint(0);
               if (!eye) return eye.status();
               const NodeId head = ctx.graph().parent(*eye);
               const Mat4 frame = head.is_valid() ? math::rigid_part(ctx.scene().world_matrix(head)) : Mat4(Mat4::Identity());
               Mat4 place = frame;  // pivoting at the eye
               place.topRightCorner<3, 1>() = ctx.scene().world_matrix(*eye).topRightCorner<3, 1>();
               for (int lid = 0; lid < 2; ++lid) {
                 Result<NodeId> group = ctx.create_group("lidFollow", lid, place, ctx.attach_node());
                 if (!group) return group.status();
                 Result<Mat4> world = ctx.guide_world(lid + 1);
                 if (!world) return world.status();
                 Result<NodeId> control = ctx.create_control("lid", lid, lid + 1, math::rigid_part(*world), *group);
                 if (!control) return control.status();
                 if (Status s = ctx.publish_hook(lid, *control); !s) return s;
               }
               return Status::ok();
             }},
        Step{"blink", "", "",
             [](BuildContext& ctx) -> Status {
               Result<NodeId> eye = ctx.guide_joint(0);
               if (!eye) return eye.status();
               graph::Graph& g = ctx.graph();
               Result<NodeId> node = ctx.create(ops::util::kEyelidBlinkType, "eyelid");
               if (!node) return node.status();
               namespace a = ops::util::eyelid_attr;
               namespace xform = scene::xform;
               Status s = g.connect(graph::Plug{*eye, xform::kMatrix, -1}, graph::Plug{*node, a::kEyeMatrix, -1});
               if (s) s = g.set_value(graph::Plug{*node, a::kEyeRestMatrix, -1}, g.evaluate(*eye, xform::kMatrix));
               if (s) s = g.set_value(graph::Plug{*node, a::kAxis, -1}, graph::Value(axis_named(ctx.param_string("axis")).value_or(math::Vec3(math::Vec3::UnitX()))));
               const std::pair<graph::AttrIndex, const char*> params[] = {{a::kUpperFollow, "upperFollow"},
                                                                          {a::kLowerFollow, "lowerFollow"},
                                                                          {a::kBlinkHeight, "blinkHeight"},
                                                                          {a::kGap, "gap"}};
               for (const auto& [attr, name] : params)
                 if (s) s = g.set_value(graph::Plug{*node, attr, -1}, graph::Value(ctx.param_double(name)));
               if (s) s = g.connect(graph::Plug{*node, a::kUpperRotate, -1}, graph::Plug{ctx.node("lidFollow", 0), xform::kRotate, -1});
               if (s) s = g.connect(graph::Plug{*node, a::kLowerRotate, -1}, graph::Plug{ctx.node("lidFollow", 1), xform::kRotate, -1});
               return s.is_ok() ? s : s.with_context(ctx.full_name() + " eyelid");
             }},
        Step{"drive", "", "",
             [](BuildContext& ctx) -> Status {
               for (int lid = 0; lid < 2; ++lid) {
                 Result<NodeId> joint = ctx.guide_joint(lid + 1);
                 if (!joint) return joint.status();
                 if (Status s = ctx.drive(ctx.node("lid", lid), *joint); !s) return s;
               }
               return Status::ok();
             }},
    };
  }
};

// ---- brows --------------------------------------------------------------

class Brows : public ComponentClass {
 public:
  std::string_view type() const override { return "brows"; }
  std::vector<Step> steps(const Component&) const override {
    return {
        // A main control at the brows' middle; per brow joint a follow
        // group and a brow control under it.
        Step{"controls", "", "",
             [](BuildContext& ctx) -> Status {
               math::Vec3 middle = math::Vec3::Zero();
               std::vector<Mat4> places;
               for (int g = 0; g < ctx.guide_count(); ++g) {
                 Result<Mat4> world = ctx.guide_world(g);
                 if (!world) return world.status();
                 places.push_back(math::rigid_part(*world));
                 middle += world->topRightCorner<3, 1>() / double(ctx.guide_count());
               }
               Mat4 main_place = places.front();
               main_place.topRightCorner<3, 1>() = middle;
               Result<NodeId> main = ctx.create_control("main", -1, 0, main_place, ctx.attach_node());
               if (!main) return main.status();
               if (Status s = ctx.publish_hook(0, *main); !s) return s;
               for (int g = 0; g < ctx.guide_count(); ++g) {
                 Result<NodeId> group = ctx.create_group("browFollow", g, places[g], ctx.attach_node());
                 if (!group) return group.status();
                 Result<NodeId> brow = ctx.create_control("brow", g, g, places[g], *group);
                 if (!brow) return brow.status();
               }
               return Status::ok();
             }},
        // Brow g follows the main control by innerFollow .. outerFollow,
        // linearly from the first guide (inner) to the last (outer).
        Step{"follow", "", "",
             [](BuildContext& ctx) -> Status {
               const double inner = ctx.param_double("innerFollow"), outer = ctx.param_double("outerFollow");
               const int n = ctx.guide_count();
               for (int g = 0; g < n; ++g) {
                 const double f = n == 1 ? inner : inner + (outer - inner) * double(g) / double(n - 1);
                 if (Status s = follow(ctx, "browFollow", g, ctx.node("main"), f); !s) return s;
               }
               return Status::ok();
             }},
        Step{"drive", "", "",
             [](BuildContext& ctx) -> Status {
               for (int g = 0; g < ctx.guide_count(); ++g) {
                 Result<NodeId> joint = ctx.guide_joint(g);
                 if (!joint) return joint.status();
                 if (Status s = ctx.drive(ctx.node("brow", g), *joint); !s) return s;
               }
               return Status::ok();
             }},
    };
  }
};

}  // namespace

Status add_face_components(ComponentFactory& factory) {
  if (Status s = factory.add(std::make_shared<Mouth>()); !s) return s;
  if (Status s = factory.add(std::make_shared<Brows>()); !s) return s;
  return factory.add(std::make_shared<Eyelid>());
}

}  // namespace rigel::rig::components
