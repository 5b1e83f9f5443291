// The workspace's posing, time, keys and saves (workspace.h).

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "internal.h"
#include "rigel/app/workspace.h"
#include "rigel/ephemeral/keying.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/io/scene_file.h"
#include "rigel/math/transform.h"
#include "rigel/scene/transform_types.h"

namespace rigel::app {

namespace xform = scene::xform;

namespace {

using internal::conflict;
using internal::make_parent;
using internal::saved;

std::string frame_limit_text() { return std::to_string(static_cast<int>(kMaxFrame)); }

Status bad(const char* field, const std::string& message) {
  return Status(ErrorCode::kInvalidArgument, std::string(field) + ": " + message).with_field(field);
}

// A rotation a drag can use: finite and of non-zero length (normalised).
Result<Quat> usable_rotation(const Quat& q, const char* field) {
  if (!q.coeffs().allFinite()) return bad(field, "not a finite rotation");
  if (q.coeffs().norm() < 1e-9) return bad(field, "not a rotation (zero length)");
  return q.normalized();
}

// The motion of a drag, checked once for every driver: finite, a rotation
// of non-zero length, and scale only in body mode, positive.
Result<ephemeral::Delta> usable_delta(ephemeral::Delta d, ephemeral::Mode mode) {
  if (!d.translate.allFinite()) return bad("translate", "not a finite motion");
  auto q = usable_rotation(d.rotate, "rotate");
  if (!q) return q.status();
  d.rotate = *q;
  if (!d.scale.allFinite()) return bad("scale", "not a finite scale");
  if (mode != ephemeral::Mode::kBody && d.scale != Vec3::Ones()) return bad("scale", "scale applies in body mode only");
  if ((d.scale.array() <= 0).any()) return bad("scale", "body scale must be positive");
  return d;
}

}  // namespace

// ---- posing --------------------------------------------------------------------

void Workspace::select(std::vector<NodeId> controls, bool add) {
  if (add) {
    std::vector<NodeId> all = graph().selection();
    for (NodeId id : controls)
      if (std::find(all.begin(), all.end(), id) == all.end()) all.push_back(id);
    controls = std::move(all);
  }
  session_->select(std::move(controls));
  gesture_ = 0;
  bump_revision();
}

void Workspace::set_mode(ephemeral::Mode mode) {
  session_->set_mode(mode);
  gesture_ = 0;
  bump_revision();
}

void Workspace::set_body_pivot(NodeId control, const std::optional<Vec3>& at) {
  session_->set_body_pivot(at ? math::translation_matrix(*at) : math::rigid_part(scene_->world_matrix(control)));
}

Status Workspace::set_options(const ephemeral::SessionOptions& options) {
  if (Status s = options.validate(); !s) return s;
  session_->set_options(options);
  bump_revision();
  return Status::ok();
}

// Moves controls that belong to no ephemeral rig (a built rig's): each gets
// the world delta about its own pivot, written into its channels (keys as
// the session does: the key at this time, or a new one with auto-key). One
// undo step per gesture.
Status Workspace::drag_direct(const std::vector<NodeId>& controls, const Vec3& dt, const Quat& dq) {
  if (gesture_ == 0) gesture_ = graph::Graph::new_merge_key();
  graph::Transaction tx(graph(), "drag", gesture_);
  for (NodeId c : controls) {
    const Mat4 w = scene_->world_matrix(c);
    Mat4 target = w;
    target.block<3, 3>(0, 0) = dq.toRotationMatrix() * w.block<3, 3>(0, 0);
    target.block<3, 1>(0, 3) = w.block<3, 1>(0, 3) + dt;
    auto ch = scene_->channels_for_world(c, target);
    if (!ch) {
      tx.rollback();
      return conflict(ch.status(), "control");
    }
    const bool insert = session_->options().auto_key;
    Status s = ephemeral::write_channel(graph(), c, xform::kTranslate, graph::Value(ch->translate), insert);
    if (s) s = ephemeral::write_channel(graph(), c, ch->rotation_attr, ch->rotation, insert);
    if (!s) {
      tx.rollback();
      return conflict(s, "control");
    }
  }
  return Status::ok();
}

Workspace::Before Workspace::before_drag() const {
  Before b;
  b.local = pose(Space::kLocal);
  if (report_moved_controls_)
    for (NodeId id : all_controls()) b.controls.emplace_back(id, scene_->world_matrix(id));
  return b;
}

DragReport Workspace::drag_report(const Before& before, std::vector<NodeId> dragged, bool session_dragged) const {
  DragReport r;
  r.dragged = std::move(dragged);
  const std::vector<Trs> now = pose(Space::kLocal);
  const bool partial = before.local.size() == now.size();
  for (std::size_t i = 0; i < now.size(); ++i)
    if (!partial || !(before.local[i] == now[i])) r.moved.push_back(now[i]);
  for (const auto& [id, world] : before.controls) {
    if (!graph().node(id)) continue;
    const Mat4 after = scene_->world_matrix(id);
    if (math::is_near(world, after, 1e-12)) continue;
    const math::Decomposed d = math::decompose(after);
    r.moved_controls.push_back(Trs{id, d.translate, d.rotation, d.scale});
  }
  if (session_dragged) r.notes = session_->notes();
  return r;
}

Result<DragReport> Workspace::drag(const ephemeral::Delta& motion) {
  auto checked = usable_delta(motion, session_->mode());
  if (!checked) return checked.status();
  const ephemeral::Delta& delta = *checked;
  const std::vector<NodeId> selected = selection();
  if (selected.empty())
    return Status(ErrorCode::kFailedPrecondition, "nothing is selected: select controls first").with_field("controls");
  const Before before = before_drag();
  std::vector<NodeId> dragged = session_->grabbed();
  const bool session_dragged = !dragged.empty();
  if (session_dragged) {
    if (Status s = session_->drag(delta); !s) return conflict(s);
  } else {
    if (delta.scale != Vec3::Ones())
      return bad("scale", "only body mode on an ephemeral rig scales");
    for (NodeId id : selected)
      if (is_control(id)) dragged.push_back(id);
    if (Status s = drag_direct(dragged, delta.translate, delta.rotate); !s) return s;
  }
  bump_revision();
  return drag_report(before, std::move(dragged), session_dragged);
}

Result<DragReport> Workspace::drag_to(NodeId control, const std::optional<Vec3>& translate,
                                      const std::optional<Quat>& rotate) {
  if (translate && !translate->allFinite()) return bad("to.t", "not a finite position");
  std::optional<Quat> rotation;
  if (rotate) {
    auto q = usable_rotation(*rotate, "to.q");
    if (!q) return q.status();
    rotation = *q;
  }
  const Before before = before_drag();
  std::vector<NodeId> selected = selection();
  const Mat4 now = scene_->world_matrix(control);
  const math::Decomposed d = math::decompose(now);
  const Vec3 t = translate ? *translate : Vec3(now.block<3, 1>(0, 3));
  const Quat q = rotation ? *rotation : d.rotation;
  if (std::find(selected.begin(), selected.end(), control) == selected.end()) {
    session_->select({control});
    selected = {control};
  }
  const bool session_dragged = ephemeral::rig_of(graph(), control).is_valid();
  std::vector<NodeId> dragged;
  if (session_dragged) {
    dragged = session_->grabbed();
    if (Status s = session_->drag_to(control, math::trs_matrix(t, q, d.scale)); !s) return conflict(s, "control");
  } else {
    for (NodeId id : selected)
      if (is_control(id) && !ephemeral::rig_of(graph(), id).is_valid()) dragged.push_back(id);
    if (Status s = drag_direct(dragged, t - d.translate, (q * d.rotation.conjugate()).normalized()); !s) return s;
  }
  bump_revision();
  return drag_report(before, std::move(dragged), session_dragged);
}

void Workspace::release() {
  session_->release();
  gesture_ = 0;
  bump_revision();
}

Result<std::string> Workspace::undo() {
  const std::string label = graph().undo_label();
  if (!graph().undo()) return Status(ErrorCode::kFailedPrecondition, "nothing to undo");
  gesture_ = 0;
  bump_revision();
  return label;
}

Result<std::string> Workspace::redo() {
  const std::string label = graph().redo_label();
  if (!graph().redo()) return Status(ErrorCode::kFailedPrecondition, "nothing to redo");
  gesture_ = 0;
  bump_revision();
  return label;
}

Status Workspace::set_frame(double frame) {
  if (!std::isfinite(frame)) return Status(ErrorCode::kInvalidArgument, "frame: not a finite number").with_field("frame");
  if (std::abs(frame) > kMaxFrame) {
    char text[64];
    std::snprintf(text, sizeof text, "%g", frame);
    return Status(ErrorCode::kInvalidArgument, std::string("frame: ") + text + " is out of range (at most " +
                                                   frame_limit_text() + " frames either side of 0)")
        .with_field("frame");
  }
  scene_->set_frame(frame);
  gesture_ = 0;
  bump_revision();
  return Status::ok();
}

Status Workspace::set_time(double seconds) {
  if (!std::isfinite(seconds)) return Status(ErrorCode::kInvalidArgument, "time: not a finite number").with_field("time");
  if (std::abs(seconds * graph().fps()) > kMaxFrame) {
    char text[64];
    std::snprintf(text, sizeof text, "%g", seconds);
    return Status(ErrorCode::kInvalidArgument, std::string("time: ") + text + " s is out of range (at most " +
                                                   frame_limit_text() + " frames either side of 0)")
        .with_field("time");
  }
  graph().set_time(seconds);
  gesture_ = 0;
  bump_revision();
  return Status::ok();
}

// ---- keys ----------------------------------------------------------------------

Result<KeyReport> Workspace::set_key(const std::vector<NodeId>& controls) {
  if (controls.empty())
    return Status(ErrorCode::kFailedPrecondition, "nothing is selected and no controls given").with_field("controls");
  if (Status s = ephemeral::set_key(graph(), controls); !s) return conflict(s);
  bump_revision();
  return keys(controls);
}

Result<KeyReport> Workspace::delete_key(const std::vector<NodeId>& controls) {
  if (controls.empty())
    return Status(ErrorCode::kFailedPrecondition, "nothing is selected and no controls given").with_field("controls");
  if (Status s = ephemeral::delete_key(graph(), controls); !s) return conflict(s);
  bump_revision();
  return keys(controls);
}

// ---- keys on any keyable channel ---------------------------------------------------

Result<std::vector<tools::Channel>> Workspace::key_channels(const std::vector<NodeId>& controls,
                                                            const std::vector<std::string>& attrs) const {
  if (controls.empty())
    return Status(ErrorCode::kFailedPrecondition, "nothing is selected and no controls given").with_field("controls");
  return tools::channels_of(graph(), attrs.empty() ? tools::keying_group(graph(), controls) : controls, attrs);
}

Result<std::vector<tools::PlugKeys>> Workspace::set_channel_keys(const std::vector<NodeId>& controls,
                                                                 const std::vector<std::string>& attrs,
                                                                 const std::optional<double>& value,
                                                                 const tools::Tangents& tangents) {
  auto channels = key_channels(controls, attrs);
  if (!channels) return channels.status();
  if (Status s = tools::set_keys(graph(), *channels, value, tangents); !s) return s.field().empty() ? conflict(s) : s;
  bump_revision();
  return tools::keys_of(graph(), *channels);
}

Result<std::vector<tools::PlugKeys>> Workspace::delete_channel_keys(const std::vector<NodeId>& controls,
                                                                    const std::vector<std::string>& attrs) {
  auto channels = key_channels(controls, attrs);
  if (!channels) return channels.status();
  if (Status s = tools::delete_keys(graph(), *channels); !s) return conflict(s);
  bump_revision();
  return tools::keys_of(graph(), *channels);
}

Result<std::vector<tools::PlugKeys>> Workspace::channel_keys(const std::vector<NodeId>& controls,
                                                             const std::vector<std::string>& attrs) const {
  auto channels = tools::channels_of(graph(), controls, attrs);
  if (!channels) return channels.status();
  return tools::keys_of(graph(), *channels);
}

// ---- files ---------------------------------------------------------------------

Result<fs::path> Workspace::save(const fs::path& path) {
  const fs::path target = path.empty() ? scene_path_ : path;
  if (target.empty())
    return Status(ErrorCode::kInvalidArgument, "path: the scene has no file yet; give a path").with_field("path");
  if (Status s = make_parent(target, "path"); !s) return s;
  if (Status s = saved(io::save_scene(*scene_, target), "path"); !s) return s;
  scene_path_ = target;
  return target;
}

}  // namespace rigel::app
