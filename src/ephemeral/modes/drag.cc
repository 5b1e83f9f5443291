// One drag's world matrices, before and after, and the roles every mode
// shares (grabbed, follow, keep-world).
#include "modes.h"

namespace rigel::ephemeral::modes {

Drag::Drag(Graph& graph_in, const Index& ix_in, Scratch& sc_in, const Plan& plan_in, const SessionOptions& options_in,
           const Delta& delta_in, std::vector<std::string>& notes)
    : graph(graph_in),
      ix(ix_in),
      sc(sc_in),
      plan(plan_in),
      options(options_in),
      delta(delta_in),
      rot(delta_in.rotate.normalized()),
      rot_m(rot.toRotationMatrix()),
      notes_(notes) {}

std::string Drag::node_name(NodeId id) const { return graph.node(id) ? graph.node(id)->name() : std::string("?"); }

const Mat4& Drag::world(int e) {
  if (!sc.has_w[e]) {
    sc.w[e] = sc.has_last[e] ? sc.last[e] : eval_mat(graph, plan.entries[e].control, xform::kWorldMatrix);
    sc.has_w[e] = 1;
  }
  return sc.w[e];
}

// A joint driven by a control moves rigidly with it (a character rigged
// under another one's joint).
Mat4 Drag::parent_new_world(int e) {
  const Index::Ctrl& c = ix.ctrls[sc.ctrl[e]];
  const int pe = c.parent >= 0 ? sc.entry_of[c.parent] : -1;
  if (pe < 0) return eval_mat(graph, plan.entries[e].control, xform::kParentMatrix);
  if (!c.parent_via_joint) return new_world(pe);
  return Mat4(new_world(pe) * math::affine_inverse(world(pe)) *
              eval_mat(graph, plan.entries[e].control, xform::kParentMatrix));
}

// Free followers are composed through the hierarchy, and body entries that
// the hierarchy carries are computed when asked for (a control kept in
// place under one of them).
const Mat4& Drag::new_world(int e) {
  if (!sc.has_wn[e]) {
    if (plan.entries[e].role == Role::kBody) {
      sc.wn[e] = body_world(e);
    } else {
      const graph::Node& node = *graph.node(plan.entries[e].control);
      sc.wn[e] = parent_new_world(e) * std::get<Mat4>(node.value(xform::kOffsetParentMatrix)) *
                 eval_mat(graph, plan.entries[e].control, xform::kMatrix);
    }
    sc.has_wn[e] = 1;
  }
  return sc.wn[e];
}

void Drag::set_new(int e, const Mat4& m) {
  sc.wn[e] = m;
  sc.has_wn[e] = 1;
}

Mat4 Drag::carry(int driver, const Mat4& w) {
  const Mat4 motion = new_world(driver) * math::affine_inverse(world(driver));
  return math::concat_without_scale_shear(motion, w);
}

Mat4 Drag::apply(const Mat4& base, bool translate) const {
  return make(rot_m * lin(base), pos(base) + (translate ? delta.translate : Vec3::Zero()));
}

Mat4 Drag::body_world(int e) {
  const Mat4& w = world(e);
  return make(rot_m * lin(w), (pivot_motion * w.col(3)).head<3>());
}

void Drag::move(int e) {
  const PlanEntry& en = plan.entries[e];
  switch (en.role) {
    case Role::kGrabbed:
      if (en.driver >= 0) {
        set_new(e, apply(carry(en.driver, world(e)), false));
      } else {
        set_new(e, apply(world(e), true));
        sc.motion[e] = rot;  // its rotation, for magnet followers
        sc.has_motion[e] = 1;
      }
      break;
    case Role::kFollow:
      if (!sc.free[e]) set_new(e, carry(en.driver, world(e)));
      break;
    case Role::kKeepWorld:
      set_new(e, world(e));
      break;
    case Role::kMagnet:
    case Role::kBody:
    case Role::kChain:
      break;  // moved by their mode's solver
  }
}

}  // namespace rigel::ephemeral::modes
