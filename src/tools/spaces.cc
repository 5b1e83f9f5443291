// Space switching and baking (spaces.h).

#include "rigel/tools/spaces.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "rigel/math/transform.h"
#include "rigel/ops/anim/channel_keys.h"
#include "rigel/ops/util/space.h"
#include "rigel/scene/transform_types.h"
#include "frames.h"
#include "tracks.h"

namespace rigel::tools {
namespace {

using graph::AttrIndex;
using graph::Graph;
using graph::NodeId;
using graph::Plug;
using graph::Value;
using math::Mat4;
namespace xform = scene::xform;
namespace anim = ops::anim;
namespace sp = ops::util::space_attr;

constexpr AttrIndex kCompensationChannels[] = {xform::kTranslate, xform::kRotate, xform::kScale, xform::kShear};

double relative_difference(const Mat4& a, const Mat4& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(1.0, b.cwiseAbs().maxCoeff());
}

// The curves keying channel `attr` of `node` (one, or one per component).
std::vector<std::pair<NodeId, Plug>> curves_of(const Graph& g, NodeId node, AttrIndex attr) {
  std::vector<std::pair<NodeId, Plug>> out;
  for (const graph::Connection& c : g.node(node)->inputs())
    if (c.dst.attr == attr && anim::curve_kind(g, c.src.node) == anim::CurveKind::kScalar)
      out.emplace_back(c.src.node, c.dst);
  return out;
}

// The last key time of the channel's curves before `t` (none: no key there).
std::optional<double> key_before(const Graph& g, NodeId node, AttrIndex attr, double t) {
  std::optional<double> before;
  for (const auto& [curve, dst] : curves_of(g, node, attr))
    for (double k : anim::curve_key_times(g, curve))
      if (k < t - anim::kKeyTimeTolerance && (!before || k > *before)) before = k;
  return before;
}

// What a space's target and offset make: T_k * targetOffset[k].
Mat4 space_matrix(scene::Scene& scene, const rig::ControlSpaces& s, int k) {
  const NodeId target = s.spaces[static_cast<std::size_t>(k)].target;
  const Mat4 world = target.is_valid() ? scene.world_matrix(target) : Mat4(Mat4::Identity());
  const auto offsets = std::get<std::vector<Mat4>>(scene.graph().evaluate(s.node, sp::kTargetOffset));
  const auto i = static_cast<std::size_t>(k);
  return world * (i < offsets.size() ? offsets[i] : Mat4(Mat4::Identity()));
}

Mat4 compensation(Graph& g, const rig::ControlSpaces& s) { return std::get<Mat4>(g.evaluate(s.compensation, xform::kMatrix)); }

// Keys the compensation transform's channels at `t` with `m`, every one
// (shear too), so that all of them have the same keys.
Status key_compensation(Graph& g, const rig::ControlSpaces& s, double t, const Mat4& m, std::size_t& keys) {
  internal::Track track = internal::Track::of(g, s.compensation);
  track.push(m);
  track.sheared = true;
  const double times[] = {t};
  return internal::write_tracks(g, times, {track}, {}, true, keys, "space switch");
}

// Steps into and out of the keys at `t` of the channel, and out of the key
// before it.
Status step_keys(Graph& g, NodeId node, AttrIndex attr, double t) {
  const std::optional<double> before = key_before(g, node, attr, t);
  Status s = anim::set_key_tangents(g, node, attr, t, anim::TangentType::kStep, anim::TangentType::kStep);
  if (s && before) s = anim::set_key_tangents(g, node, attr, *before, std::nullopt, anim::TangentType::kStep);
  return s;
}

// The first key time of any time curve in the scene (none without keys).
std::optional<double> first_key_time(const Graph& g) {
  std::optional<double> first;
  for (NodeId id : g.nodes()) {
    if (anim::curve_kind(g, id) == anim::CurveKind::kOther) continue;
    const std::vector<double> times = anim::curve_key_times(g, id);
    if (!times.empty() && (!first || times.front() < *first)) first = times.front();
  }
  return first;
}

// The switch at time `t`: space `to` with the compensation that keeps the
// control where it is. A channel with no key before `t` gets one holding
// its old value at the scene's first key time, when that is before `t` (no
// key outside the clip; before its first key a curve holds that key's
// value, so every earlier frame keeps the old space).
Status key_switch(scene::Scene& scene, const rig::ControlSpaces& s, int to, double t, std::size_t& keys) {
  Graph& g = scene.graph();
  g.set_time(t);
  const int from = s.current;
  const Mat4 old_compensation = compensation(g, s);
  const Mat4 new_compensation =
      math::affine_inverse(space_matrix(scene, s, to)) * space_matrix(scene, s, from) * old_compensation;
  const std::optional<double> start = first_key_time(g);
  const bool earlier = start && *start < t - anim::kKeyTimeTolerance;
  Status st = Status::ok();
  if (earlier && !key_before(g, s.node, sp::kSpace, t)) {
    st = anim::write_channel_key(g, s.node, sp::kSpace, Value(static_cast<double>(from)), *start, true);
    ++keys;
  }
  if (st && earlier && !key_before(g, s.compensation, xform::kTranslate, t))
    st = key_compensation(g, s, *start, old_compensation, keys);
  if (st) st = anim::write_channel_key(g, s.node, sp::kSpace, Value(static_cast<double>(to)), t, true);
  if (st) ++keys;
  if (st) st = key_compensation(g, s, t, new_compensation, keys);
  if (st) st = step_keys(g, s.node, sp::kSpace, t);
  for (AttrIndex a : kCompensationChannels)
    if (st) st = step_keys(g, s.compensation, a, t);
  return st;
}

// Removes the keys of the space and compensation channels in (t_first, t_last].
Status clear_switches(Graph& g, const rig::ControlSpaces& s, double t_first, double t_last) {
  std::vector<std::pair<NodeId, AttrIndex>> channels = {{s.node, sp::kSpace}};
  for (AttrIndex a : kCompensationChannels) channels.emplace_back(s.compensation, a);
  for (const auto& [node, attr] : channels)
    for (const auto& [curve, dst] : curves_of(g, node, attr))
      for (double k : anim::curve_key_times(g, curve)) {
        if (k <= t_first + anim::kKeyTimeTolerance || k > t_last + anim::kKeyTimeTolerance) continue;
        bool removed = false;
        const Value keep = g.evaluate(node, attr);
        if (Status st = anim::delete_curve_key(g, curve, k, dst, keep, removed); !st) return st;
      }
  return Status::ok();
}

}  // namespace

Result<SpaceSwitchReport> switch_space(scene::Scene& scene, NodeId control, const SpaceSwitchOptions& o) {
  Graph& g = scene.graph();
  if (!g.node(control)) return error(ErrorCode::kInvalidArgument, "space switch: no such control").with_field("control");
  const std::string name = g.node(control)->name();
  const double time_before = g.time();
  const rig::ControlSpaces spaces = rig::spaces_of(scene, control);
  if (!spaces.node.is_valid())
    return error(ErrorCode::kInvalidArgument, "space switch: " + name + " has no spaces (add one first)")
        .with_field("control");
  Result<int> to = rig::find_space(spaces, o.space);
  if (!to) return to.status().with_context("space switch of " + name);
  if (o.first.has_value() != o.last.has_value())
    return error(ErrorCode::kInvalidArgument, "space switch: give both ends of the range, or neither").with_field("frames");
  if (o.frame && o.first)
    return error(ErrorCode::kInvalidArgument, "space switch: give a frame or a range, not both").with_field("frames");
  const double at = o.frame.value_or(scene.frame());
  Result<std::vector<double>> frame_list =
      internal::frames_between(g, o.first.value_or(at), o.last.value_or(at), "space switch");
  if (!frame_list) return frame_list.status().with_field("frames");
  const std::vector<double>& frames = *frame_list;
  const bool bake = o.first.has_value();

  const std::size_t total = frames.size() * (bake ? 3 : 1) + 1;
  std::size_t done = 0;
  auto tick = [&] {
    ++done;
    if (o.progress) o.progress(static_cast<double>(done) / static_cast<double>(total));
  };
  // The control's world matrix at every frame, as it is.
  std::vector<Mat4> wanted;
  for (double f : frames) {
    scene.set_frame(f);
    wanted.push_back(scene.world_matrix(control));
    if (bake) tick();
  }
  scene.set_frame(frames.front());
  SpaceSwitchReport report;
  report.frames = frames.size();
  report.from = spaces.spaces[static_cast<std::size_t>(rig::spaces_of(scene, control).current)].name;
  report.to = o.space;
  std::vector<double> times;
  for (double f : frames) times.push_back(f / g.fps());

  graph::Transaction tx(g, (bake ? "bake to space " : "switch to space ") + o.space + " (" + name + ")");
  auto fail = [&](Status s) -> Result<SpaceSwitchReport> {
    tx.rollback();
    g.set_time(time_before);
    return s.with_context("space switch of " + name);
  };
  Status s = Status::ok();
  if (bake) s = clear_switches(g, spaces, times.front(), times.back());
  if (s) s = key_switch(scene, rig::spaces_of(scene, control), *to, times.front(), report.keys);
  if (!s) return fail(s);
  tick();
  if (bake) {
    internal::Track track = internal::Track::of(g, control);
    const NodeId parent = g.parent(control);
    for (std::size_t i = 0; i < frames.size(); ++i) {
      scene.set_frame(frames[i]);
      const Mat4 parent_world = parent.is_valid() ? scene.world_matrix(parent) : Mat4(Mat4::Identity());
      const Mat4 offset = std::get<Mat4>(g.evaluate(control, xform::kOffsetParentMatrix));
      track.push(math::affine_inverse(parent_world * offset) * wanted[i]);
      tick();
    }
    s = internal::write_tracks(g, times, {track}, {}, true, report.keys, "space bake");
    if (!s) return fail(s);
  }
  for (std::size_t i = 0; i < frames.size(); ++i) {
    scene.set_frame(frames[i]);
    const double e = relative_difference(scene.world_matrix(control), wanted[i]);
    if (e > report.max_error) {
      report.max_error = e;
      report.worst_frame = frames[i];
    }
    if (bake) tick();
  }
  g.set_time(time_before);
  return report;
}

}  // namespace rigel::tools
