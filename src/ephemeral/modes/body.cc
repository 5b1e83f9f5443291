// Body mode: the whole character (with the characters merged with it)
// about the body pivot: rotate, translate, and scale that repositions the
// controls without scaling them (seed 001's concatenation).
#include "modes.h"

namespace rigel::ephemeral::modes {

void plan_body(Planner& p) {
  const std::vector<int> rigs = p.grabbed_rigs();
  for (int k : p.grabbed) p.add(k, Role::kBody, -1);
  for (int r : rigs)
    for (int k : p.ix.rig_members[r])
      if (p.sc.entry_of[k] < 0) p.add(k, Role::kBody, -1);
  if (!p.body_pivot)
    p.plan_body_pivot = math::rigid_part(eval_mat(p.graph, p.ix.ctrls[p.grabbed[0]].id, xform::kWorldMatrix));
  else
    p.plan_body_pivot = p.body_pivot;
}

Status solve_body(Drag& d, const Mat4& pivot) {
  d.pivot_new = make(d.rot_m * lin(pivot), pos(pivot) + d.delta.translate);
  d.pivot_motion = d.pivot_new * math::scale_matrix(d.delta.scale) * math::affine_inverse(pivot);
  d.body_rigid = d.delta.scale == Vec3::Ones();
  for (int e : d.sc.units) {
    if (d.plan.entries[e].role != Role::kBody) {
      d.move(e);
      continue;
    }
    // Rigid: only the roots are needed (the hierarchy carries the rest,
    // also across characters: a control under a joint of another one).
    const int parent = d.ix.ctrls[d.sc.ctrl[e]].parent;
    if (!d.body_rigid || parent < 0 || d.sc.entry_of[parent] < 0) d.set_new(e, d.body_world(e));
  }
  return Status::ok();
}

}  // namespace rigel::ephemeral::modes
