// The face's component classes: mouth (jaw and lips following it).
#include "rigel/rig/components/face.h"

#include <string>

#include "rigel/ops/constraints/nodes.h"
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
               for (int g = 1; g < ctx.guide_count(); ++g) {
                 const double f = follow_of(ctx, g);
                 ConstraintSpec spec;
                 spec.type = ops::constraints::kParentConstraintType;
                 spec.role = "lipFollowConstraint";
                 spec.space_role = "lipFollowSpace";
                 spec.targets = {ctx.attach_node(), ctx.node("jaw")};
                 spec.weights = {1.0 - f, f};
                 spec.channels = {"translate", "rotate"};
                 Result<NodeId> k = ctx.constrain(spec, ctx.node("lipFollow", g - 1), g - 1);
                 if (!k) return k.status();
               }
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

}  // namespace

Status add_face_components(ComponentFactory& factory) { return factory.add(std::make_shared<Mouth>()); }

}  // namespace rigel::rig::components
