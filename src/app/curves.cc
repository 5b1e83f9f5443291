// The workspace's graph editor: curves of the channel box's channels and
// single-key edits (workspace.h, tools/curves.h).

#include <cmath>
#include <string>

#include "internal.h"
#include "rigel/app/workspace.h"
#include "rigel/tools/curves.h"

namespace rigel::app {
namespace {

using internal::conflict;

// Frames as seconds; errors name "keys" for a frame out of range.
Status to_seconds(double& frame, double fps) {
  if (!std::isfinite(frame) || std::abs(frame) > kMaxFrame)
    return Status(ErrorCode::kInvalidArgument, "keys: a frame is not finite or beyond 1e6").with_field("keys");
  frame /= fps;
  return Status::ok();
}

Status refs_to_seconds(std::vector<tools::CurveKeyRef>& keys, double fps) {
  if (keys.empty()) return Status(ErrorCode::kInvalidArgument, "keys: no key given").with_field("keys");
  for (tools::CurveKeyRef& k : keys)
    if (Status s = to_seconds(k.time, fps); !s) return s;
  return Status::ok();
}

// A tools refusal: the caller's input named, or a conflict with the scene.
Status refused(const Status& s) { return s.field().empty() ? conflict(s) : s; }

}  // namespace

Result<std::vector<tools::CurveView>> Workspace::curves(const std::vector<NodeId>& controls,
                                                        const tools::CurveViewOptions& options) {
  if (controls.empty())
    return Status(ErrorCode::kFailedPrecondition, "nothing is selected and no controls given").with_field("controls");
  std::vector<tools::Channel> channels;
  for (NodeId id : controls) {
    if (!graph().node(id))
      return Status(ErrorCode::kNotFound, "controls: no such node (stale handle)").with_field("controls");
    for (NodeId holder : internal::channel_holders(graph(), id)) {
      auto of = tools::channels_of(graph(), {holder});
      if (of) channels.insert(channels.end(), of->begin(), of->end());
    }
  }
  tools::CurveViewOptions seconds = options;
  const double fps = graph().fps();
  for (auto [value, field] : {std::pair{&seconds.first, "first"}, std::pair{&seconds.last, "last"},
                              std::pair{&seconds.step, "step"}}) {
    if (!*value) continue;
    if (!std::isfinite(**value) || std::abs(**value) > kMaxFrame)
      return Status(ErrorCode::kInvalidArgument, std::string(field) + ": not a frame within 1e6 of 0").with_field(field);
    **value /= fps;
  }
  Result<std::vector<tools::CurveView>> views = tools::curve_views(graph(), channels, seconds);
  if (!views) return views;
  // Frames out, as in: keys as they are, samples to a billionth of a frame
  // (a range asked in frames comes back in those frames, 30 and not
  // 30.000000000000007), slopes per frame.
  for (tools::CurveView& v : *views) {
    for (double& t : v.key_times) t *= fps;
    for (double& t : v.sample_times) t = std::round(t * fps * 1e9) / 1e9;
    for (double& s : v.in_slopes) s /= fps;
    for (double& s : v.out_slopes) s /= fps;
  }
  return views;
}

Result<std::size_t> Workspace::edit_curve_keys(std::vector<tools::CurveKeyEdit> edits) {
  if (edits.empty()) return Status(ErrorCode::kInvalidArgument, "keys: no key given").with_field("keys");
  const double fps = graph().fps();
  for (tools::CurveKeyEdit& e : edits) {
    if (Status s = to_seconds(e.key.time, fps); !s) return s;
    if (e.to_time)
      if (Status s = to_seconds(*e.to_time, fps); !s) return s;
    // Slopes come per frame, the curves keep them per second.
    if (e.in_slope) *e.in_slope *= fps;
    if (e.out_slope) *e.out_slope *= fps;
  }
  Result<std::size_t> n = tools::edit_curve_keys(graph(), edits);
  if (!n) return refused(n.status());
  bump_revision();
  return n;
}

Result<std::size_t> Workspace::insert_curve_keys(std::vector<tools::CurveKeyRef> keys) {
  if (Status s = refs_to_seconds(keys, graph().fps()); !s) return s;
  Result<std::size_t> n = tools::insert_curve_keys(graph(), keys);
  if (!n) return refused(n.status());
  if (*n > 0) bump_revision();
  return n;
}

Result<std::size_t> Workspace::delete_curve_keys(std::vector<tools::CurveKeyRef> keys) {
  if (Status s = refs_to_seconds(keys, graph().fps()); !s) return s;
  Result<std::size_t> n = tools::delete_curve_keys(graph(), keys);
  if (!n) return refused(n.status());
  bump_revision();
  return n;
}

}  // namespace rigel::app
