// The `ephemeral` component class (ephemeral/component.h).
#include "rigel/ephemeral/component.h"

#include <cstdio>
#include <cstdlib>

#include "rigel/ephemeral/keying.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/ops/anim/channel_keys.h"
#include "rigel/scene/transform_types.h"

namespace rigel::ephemeral {
namespace {

using rig::BuildContext;
using rig::Step;

class EphemeralComponent : public rig::ComponentClass {
 public:
  std::string_view type() const override { return "ephemeral"; }
  // The controls hold the joints' pose, not places of guides.
  bool editable() const override { return false; }
  std::vector<Step> steps(const rig::Component&) const override {
    return {
        Step{"setup", "", "",
             [](BuildContext& ctx) -> Status {
               graph::Graph& g = ctx.graph();
               SetupOptions options;
               if (ctx.guide_count() > 0 && !ctx.component().guides[0].joint.empty()) {
                 Result<NodeId> root = ctx.guide_joint(0);
                 if (!root) return root.status();
                 // The guide joint and every joint below it, parent first.
                 std::vector<NodeId> stack = {*root};
                 while (!stack.empty()) {
                   const NodeId j = stack.back();
                   stack.pop_back();
                   if (g.node(j)->type().name() == scene::kJointType) options.joints.push_back(j);
                   const std::vector<NodeId> kids = g.children(j);
                   for (auto it = kids.rbegin(); it != kids.rend(); ++it) stack.push_back(*it);
                 }
                 if (options.joints.empty())
                   return error(ErrorCode::kInvalidArgument,
                                ctx.full_name() + " (ephemeral): guide 0: '" + g.node(*root)->name() + "' is not a joint");
               }
               // Joints another component drives (constraints, solvers) stay
               // with it: the ephemeral rig would take their drivers over.
               for (NodeId j : options.joints) {
                 for (const graph::Connection& c : g.node(j)->inputs()) {
                   if (c.dst.attr == graph::kNoAttr || ops::anim::curve_kind(g, c.src.node) != ops::anim::CurveKind::kOther)
                     continue;
                   const std::string& attr = g.node(j)->type().attr(c.dst.attr).name;
                   if (attr == graph::kMetaParentAttr || c.dst.attr == scene::xform::kParentMatrix) continue;
                   return error(ErrorCode::kInvalidArgument, ctx.full_name() + " (ephemeral): joint '" + g.node(j)->name() +
                                                                 "' is driven by '" + g.node(c.src.node)->name() +
                                                                 "'; an ephemeral rig takes joints no other component drives");
                 }
               }
               options.control_suffix = "_" + ctx.rig_name() + "_" + ctx.full_name() + "_ctrl";
               options.rig_name = ctx.rig_name() + "_" + ctx.full_name() + "_ephemeralRig";
               options.keep_animation = ctx.param_bool("keepAnimation");
               options.shape_radius = ctx.control_style("joint").size;
               Result<SetupResult> made = setup_ephemeral(ctx.scene(), options);
               if (!made) return made.status().with_context(ctx.full_name() + " (ephemeral)");
               Status s = ctx.link(made->rig, "ephemeralRig");
               for (std::size_t i = 0; i < made->controls.size() && s; ++i)
                 s = ctx.link(made->controls[i], "joint", static_cast<int>(i), i == 0 && ctx.guide_count() > 0 ? 0 : -1);
               if (!s) return s;
               const std::optional<KeyScope> scope = key_scope_from_name(ctx.param_string("keyScope"));
               if (!scope) return error(ErrorCode::kInvalidArgument, ctx.full_name() + ": keyScope: unknown scope");
               if (Status st = set_key_scope(g, made->rig, *scope); !st) return st;
               return ctx.publish_hook(0, made->controls.front());
             }},
    };
  }
};

}  // namespace

Status add_ephemeral_component(rig::ComponentFactory& factory) {
  return factory.add(std::make_shared<EphemeralComponent>());
}

const rig::ComponentFactory& components() {
  static const rig::ComponentFactory factory = [] {
    rig::ComponentFactory f = rig::builtin_components();
    if (Status s = add_ephemeral_component(f); !s) {
      std::fprintf(stderr, "rigel: the ephemeral component class: %s\n", s.message().c_str());
      std::abort();
    }
    return f;
  }();
  return factory;
}

}  // namespace rigel::ephemeral
