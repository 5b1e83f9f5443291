// The local channels a drag writes: every moved control's new world put
// back under its parent's new world by the scene's world-to-local routine,
// its scale, shear and rotate axis kept, the rotation nearest the current
// one. Channels within rounding of their values are not rewritten.
#include <algorithm>

#include "modes.h"

namespace rigel::ephemeral::modes {

Status local_writes(scene::Scene& scene, Drag& d, bool& exact) {
  Scratch& sc = d.sc;
  const std::vector<PlanEntry>& entries = d.plan.entries;
  Graph& graph = d.graph;
  sc.writes.clear();
  exact = true;
  scene::Scene::ChannelFit fit;
  fit.keep_scale_shear = true;
  fit.nearest_rotation = true;
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const int e = static_cast<int>(i);
    if (sc.free[e]) continue;
    const int parent = d.ix.ctrls[sc.ctrl[e]].parent;
    const int pe = parent >= 0 ? sc.entry_of[parent] : -1;
    // A rigid body motion is carried by the hierarchy below the roots.
    if (d.body_rigid && entries[e].role == Role::kBody && pe >= 0) continue;
    const NodeId id = entries[e].control;
    // Control and parent both turned by the pivot's rotation: the local
    // rotation is unchanged, only the translation is new.
    const bool body_pair = entries[e].role == Role::kBody && pe >= 0 && entries[pe].role == Role::kBody;
    fit.parent_world = d.parent_new_world(e);
    fit.translate_only = body_pair;
    Result<scene::Scene::LocalChannels> ch = scene.channels_for_world(id, d.new_world(e), fit);
    if (!ch) return ch.status().with_context("drag");
    const graph::Node& node = *graph.node(id);
    const Vec3& t0 = std::get<Vec3>(node.value(xform::kTranslate));
    const bool same_t = (ch->translate - t0).norm() <= 1e-12 * std::max(1.0, t0.norm());
    if (body_pair) {
      if (!same_t) sc.writes.push_back(Scratch::Write{e, ch->translate, ch->rotation_attr, ch->rotation, true, false});
      continue;
    }
    if (!ch->exact) exact = false;
    Scratch::Write write{e, same_t ? t0 : ch->translate, ch->rotation_attr, std::move(ch->rotation), !same_t, false};
    if (write.rotation_attr == xform::kRotateQuaternion) {
      const Quat& q0 = std::get<Quat>(node.value(xform::kRotateQuaternion));
      const Quat& qs = std::get<Quat>(write.rotation);
      write.set_r = (q0.normalized().conjugate() * qs).vec().norm() > 1e-13;
    } else {
      const Vec3& r0 = std::get<Vec3>(node.value(xform::kRotate));
      // 1e-11 degrees ~ 2e-13 rad, the quaternion test's threshold.
      write.set_r = (std::get<Vec3>(write.rotation) - r0).cwiseAbs().maxCoeff() > 1e-11;
    }
    if (write.set_t || write.set_r) sc.writes.push_back(std::move(write));
  }
  return Status::ok();
}

}  // namespace rigel::ephemeral::modes
