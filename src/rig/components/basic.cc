// The simplest component classes: global (the rig's root control), hip
// (centre of gravity), control (a plain control), meta (groups, no
// controls) and fkChain (one FK control per joint).
#include "rigel/rig/components/basic.h"

#include "rigel/rig/component.h"

namespace rigel::rig::components {
namespace {

// One control at guide 0, hanging from the attach point, published as hook
// 0; it drives guide 0's joint when the guide names one.
class SingleControl : public ComponentClass {
 public:
  SingleControl(std::string type, bool drives) : type_(std::move(type)), drives_(drives) {}
  std::string_view type() const override { return type_; }
  std::vector<Step> steps(const Component&) const override {
    std::vector<Step> steps;
    steps.push_back(Step{"control", "", "", [](BuildContext& ctx) -> Status {
                           Result<math::Mat4> world = ctx.guide_world(0);
                           if (!world) return world.status();
                           Result<NodeId> c = ctx.create_control("main", -1, 0, *world, ctx.attach_node());
                           if (!c) return c.status();
                           return ctx.publish_hook(0, *c);
                         }});
    if (drives_)
      steps.push_back(Step{"drive", "", "", [](BuildContext& ctx) -> Status {
                             if (ctx.component().guides[0].joint.empty()) return Status::ok();
                             Result<NodeId> joint = ctx.guide_joint(0);
                             if (!joint) return joint.status();
                             return ctx.drive(ctx.node("main"), *joint);
                           }});
    return steps;
  }

 private:
  std::string type_;
  bool drives_;
};

// A chain of FK controls, each the child of the one before, each driving
// its guide's joint.
class FkChain : public ComponentClass {
 public:
  std::string_view type() const override { return "fkChain"; }
  std::vector<Step> steps(const Component&) const override {
    return {
        Step{"controls", "", "",
             [](BuildContext& ctx) -> Status {
               NodeId parent = ctx.attach_node();
               for (int i = 0; i < ctx.guide_count(); ++i) {
                 Result<math::Mat4> world = ctx.guide_world(i);
                 if (!world) return world.status();
                 Result<NodeId> c = ctx.create_control("fk", i, i, *world, parent);
                 if (!c) return c.status();
                 if (Status s = ctx.publish_hook(i, *c); !s) return s;
                 parent = *c;
               }
               return Status::ok();
             }},
        Step{"drive", "", "",
             [](BuildContext& ctx) -> Status {
               for (int i = 0; i < ctx.guide_count(); ++i) {
                 if (ctx.component().guides[i].joint.empty()) continue;
                 Result<NodeId> joint = ctx.guide_joint(i);
                 if (!joint) return joint.status();
                 if (Status s = ctx.drive(ctx.node("fk", i), *joint); !s) return s;
               }
               return Status::ok();
             }},
    };
  }
};

// A group at each guide, hanging from the attach point, each published as
// the hook of its guide: places for children, no controls, nothing driven.
class Meta : public ComponentClass {
 public:
  std::string_view type() const override { return "meta"; }
  std::vector<Step> steps(const Component&) const override {
    return {Step{"groups", "", "", [](BuildContext& ctx) -> Status {
                   if (ctx.guide_count() < 1)
                     return error(ErrorCode::kInvalidArgument, ctx.full_name() + ": a meta needs 1 or more guides");
                   for (int i = 0; i < ctx.guide_count(); ++i) {
                     Result<math::Mat4> world = ctx.guide_world(i);
                     if (!world) return world.status();
                     Result<NodeId> g = ctx.create_group("group", i, *world, ctx.attach_node());
                     if (!g) return g.status();
                     if (Status s = ctx.publish_hook(i, *g); !s) return s;
                   }
                   return Status::ok();
                 }}};
  }
};

}  // namespace

Status add_basic_components(ComponentFactory& factory) {
  if (Status s = factory.add(std::make_shared<SingleControl>("global", false)); !s) return s;
  if (Status s = factory.add(std::make_shared<SingleControl>("hip", true)); !s) return s;
  if (Status s = factory.add(std::make_shared<SingleControl>("control", true)); !s) return s;
  if (Status s = factory.add(std::make_shared<Meta>()); !s) return s;
  return factory.add(std::make_shared<FkChain>());
}

}  // namespace rigel::rig::components
