// The workspace's rigger actions (workspace.h): control looks, locators,
// mirrored joints (tools/rigging.h) and matching transforms (through the
// posing session for ephemeral controls).

#include <algorithm>
#include <string>

#include "internal.h"
#include "rigel/app/workspace.h"
#include "rigel/ephemeral/keying.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/math/transform.h"
#include "rigel/scene/transform_types.h"

namespace rigel::app {

using internal::conflict;
using math::Mat4;
namespace xform = scene::xform;

namespace {

// A refusal of the library keeps its field when it names one.
Status named(const Status& s, const std::string& field) {
  return s.field().empty() ? conflict(s, field) : s;
}

}  // namespace

Result<tools::ControlLook> Workspace::control_look(NodeId control) const { return tools::control_look(graph(), control); }

Status Workspace::paste_control_look(const std::vector<NodeId>& controls, const tools::ControlLook& look,
                                     tools::LookParts parts) {
  if (Status s = tools::paste_control_look(graph(), controls, look, parts); !s) return named(s, "controls");
  bump_revision();
  return Status::ok();
}

Status Workspace::edit_control_shape(const std::vector<NodeId>& controls, tools::ShapeEdit edit) {
  if (Status s = tools::edit_control_shape(graph(), controls, edit); !s) return named(s, "controls");
  bump_revision();
  return Status::ok();
}

Result<std::vector<tools::MirroredShape>> Workspace::mirror_shape_to_opposite(const std::vector<NodeId>& controls) {
  auto pairs = tools::mirror_shape_to_opposite(*scene_, controls);
  if (!pairs) return named(pairs.status(), "controls");
  bump_revision();
  return pairs;
}

Result<std::vector<NodeId>> Workspace::create_locators(const std::vector<NodeId>& at, double size) {
  auto made = tools::create_locators(*scene_, at, size);
  if (!made) return named(made.status(), "nodes");
  bump_revision();
  return made;
}

Result<tools::MirrorJointsReport> Workspace::mirror_joints(const std::vector<NodeId>& roots,
                                                           const tools::MirrorJointsOptions& options) {
  // An ephemeral control stands for the joint it drives (its translate feeds the joint's).
  std::vector<NodeId> joints;
  for (NodeId id : roots) {
    NodeId joint = id;
    if (is_control(id) && ephemeral::rig_of(graph(), id).is_valid())
      for (NodeId j : scene_->hierarchy()) {
        const auto src = graph().source({j, xform::kTranslate});
        if (src && src->node == id && graph().node(j)->type().name() == scene::kJointType) joint = j;
      }
    joints.push_back(joint);
  }
  auto report = tools::mirror_joints(*scene_, joints, options);
  if (!report) return named(report.status(), "joints");
  bump_revision();
  return report;
}

Result<std::vector<NodeId>> Workspace::align(const std::vector<NodeId>& nodes, NodeId target, bool position,
                                             bool rotation) {
  if (!graph().node(target) || !scene_->is_transform(target))
    return Status(ErrorCode::kInvalidArgument, "target: not a transform node").with_field("target");
  if (!position && !rotation)
    return Status(ErrorCode::kInvalidArgument, "match: give the position, the rotation or both").with_field("match");
  std::vector<NodeId> moved;
  for (NodeId id : nodes) {
    const graph::Node* n = graph().node(id);
    if (!n || !scene_->is_transform(id))
      return Status(ErrorCode::kInvalidArgument,
                    "nodes: " + (n ? "'" + n->name() + "' is not a transform node" : std::string("a deleted node")))
          .with_field("nodes");
    if (id != target && std::find(moved.begin(), moved.end(), id) == moved.end()) moved.push_back(id);
  }
  if (moved.empty())
    return Status(ErrorCode::kInvalidArgument, "nodes: nothing to match besides the target").with_field("nodes");
  const math::Decomposed to = math::decompose(scene_->world_matrix(target));
  const std::vector<NodeId> selected = selection();
  gesture_ = 0;
  graph::Transaction tx(graph(), rotation && position ? "match transform" : rotation ? "match rotation" : "match position");
  auto fail = [&](const Status& s, NodeId id) -> Status {
    tx.rollback();
    session_->release();
    session_->select(selected);
    gesture_ = 0;
    return named(s, "nodes").with_context("nodes: '" + graph().node(id)->name() + "'");
  };
  for (NodeId id : moved) {
    const math::Decomposed now = math::decompose(scene_->world_matrix(id));
    const math::Vec3 t = position ? to.translate : now.translate;
    const math::Quat q = rotation ? to.rotation : now.rotation;
    if (is_control(id) && ephemeral::rig_of(graph(), id).is_valid()) {
      session_->select({id});
      if (Status s = session_->drag_to(id, math::trs_matrix(t, q, now.scale)); !s) return fail(s, id);
      session_->release();
      continue;
    }
    scene::Scene::ChannelFit fit;
    fit.keep_scale_shear = true;
    fit.nearest_rotation = true;
    auto ch = scene_->channels_for_world(id, math::trs_matrix(t, q, now.scale), fit);
    if (!ch) return fail(ch.status(), id);
    const bool insert = session_->options().auto_key;
    Status s = ephemeral::write_channel(graph(), id, xform::kTranslate, graph::Value(ch->translate), insert);
    if (s) s = ephemeral::write_channel(graph(), id, ch->rotation_attr, ch->rotation, insert);
    if (!s) return fail(s, id);
  }
  session_->select(selected);
  gesture_ = 0;
  bump_revision();
  return moved;
}

}  // namespace rigel::app
