// The workspace's animator tools (workspace.h): FK/IK match and bake, mirror,
// bind pose, tween.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "internal.h"
#include "rigel/app/workspace.h"
#include "rigel/ops/anim/channel_keys.h"
#include "rigel/rig/meta.h"

namespace rigel::app {
namespace {

using internal::conflict;

std::string frame_text(double f) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%g", f);
  return buffer;
}

}  // namespace

Status internal::check_frames(const Workspace& ws, double first, double last) {
  auto bad = [](const std::string& message) {
    return Status(ErrorCode::kInvalidArgument, "frames: " + message).with_field("frames");
  };
  if (!std::isfinite(first) || !std::isfinite(last)) return bad("not a finite frame");
  if (first > last) return bad("the first frame " + frame_text(first) + " is after the last " + frame_text(last));
  if (std::max(std::abs(first), std::abs(last)) > kMaxFrame)
    return bad("out of range (at most " + frame_text(kMaxFrame) + ")");
  if (const auto clip = ws.keyed_frames()) {
    const double tolerance = ops::anim::kKeyTimeTolerance * ws.graph().fps();
    if (first < (*clip)[0] - tolerance || last > (*clip)[1] + tolerance) {
      std::string asked = frame_text(first);
      if (first != last) asked.append(1, ':').append(frame_text(last));
      return bad(asked + " is outside the clip (frames " + frame_text((*clip)[0]) + " to " + frame_text((*clip)[1]) + ")");
    }
  }
  return Status::ok();
}

namespace {
using internal::check_frames;
}  // namespace

std::optional<std::array<double, 2>> Workspace::keyed_frames() const {
  const graph::Graph& g = graph();
  std::optional<std::array<double, 2>> out;
  for (NodeId id : g.nodes()) {
    if (ops::anim::curve_kind(g, id) == ops::anim::CurveKind::kOther) continue;
    const std::vector<double> times = ops::anim::curve_key_times(g, id);
    if (times.empty()) continue;
    const double first = key_frame(times.front(), g.fps()), last = key_frame(times.back(), g.fps());
    if (!out) out = std::array<double, 2>{first, last};
    else out = std::array<double, 2>{std::min((*out)[0], first), std::max((*out)[1], last)};
  }
  return out;
}

Result<tools::MatchReport> Workspace::match(const std::string& rig_name, const std::string& component,
                                            const tools::MatchOptions& options) {
  const graph::Graph& g = graph();
  const NodeId rig = rig::find_rig(g, rig_name);
  if (!rig.is_valid())
    return Status(ErrorCode::kNotFound, "rig: no built rig '" + rig_name + "' in the scene").with_field("rig");
  const NodeId meta = rig::find_component(g, rig, component);
  if (!meta.is_valid())
    return Status(ErrorCode::kNotFound, "component: rig '" + rig_name + "' has no component '" + component + "'")
        .with_field("component");
  // What the component is first (no FK/IK switch: "component"), then when.
  if (auto plan = rig::components::plan_fk_ik_match(*scene_, meta, options.to); !plan)
    return plan.status().field().empty() ? conflict(plan.status()) : plan.status();
  const double now = scene_->frame();
  if (Status s = check_frames(*this, options.first.value_or(now), options.last.value_or(now)); !s) return s;
  Result<tools::MatchReport> report = tools::match(*scene_, meta, options);
  if (!report) return report.status().field().empty() ? conflict(report.status()) : report.status();
  bump_revision();
  return report;
}

Result<tools::MirrorReport> Workspace::mirror(const tools::MirrorOptions& options) {
  const double now = scene_->frame();
  if (Status s = check_frames(*this, options.first.value_or(now), options.last.value_or(now)); !s) return s;
  Result<tools::MirrorReport> report = tools::mirror(*scene_, options);
  if (!report) return report.status().field().empty() ? conflict(report.status()) : report.status();
  bump_revision();
  return report;
}

Result<tools::BindPoseReport> Workspace::reset_bind_pose(const std::vector<NodeId>& nodes, bool key) {
  Result<tools::BindPoseReport> report = tools::reset_bind_pose(graph(), nodes, key);
  if (!report) return report.status().field().empty() ? conflict(report.status()) : report.status();
  bump_revision();
  return report;
}

Result<std::vector<tools::PlugKeys>> Workspace::tween(const std::vector<NodeId>& controls,
                                                      const std::vector<std::string>& attrs, double fraction, bool key) {
  auto channels = key_channels(controls, attrs);
  if (!channels) return channels.status();
  Result<std::size_t> blended = tools::tween(graph(), *channels, fraction, key);
  if (!blended) return blended.status().field().empty() ? conflict(blended.status()) : blended.status();
  if (*blended == 0)
    return Status(ErrorCode::kFailedPrecondition,
                  "tween: no channel has a key both before and after frame " + frame_text(scene_->frame()))
        .with_field("controls");
  bump_revision();
  return tools::keys_of(graph(), *channels);
}

}  // namespace rigel::app
