// FK/IK match and bake (match.h).

#include "rigel/tools/match.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "rigel/math/rotation.h"
#include "rigel/math/transform.h"
#include "rigel/ops/anim/channel_keys.h"
#include "rigel/scene/transform_types.h"
#include "frames.h"
#include "tracks.h"

namespace rigel::tools {
namespace {

using graph::AttrIndex;
using graph::NodeId;
using graph::Plug;
using graph::Value;
using math::Mat4;
using math::Quat;
using math::Vec3;
using rig::components::MatchSide;
namespace xform = scene::xform;
namespace anim = ops::anim;

using internal::Track;
using internal::ValueTrack;

double relative_difference(const Mat4& a, const Mat4& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(1.0, b.cwiseAbs().maxCoeff());
}

// Samples one frame's plan into the tracks: each control's local channels
// under its parent as the plan leaves it (a parent set by the plan counts
// with its planned world matrix, not the one it has now).
Status sample(scene::Scene& scene, const rig::components::FkIkMatch& plan, std::vector<Track>& tracks,
              std::vector<ValueTrack>& values) {
  graph::Graph& g = scene.graph();
  if (tracks.empty()) {
    for (const auto& c : plan.controls) tracks.push_back(Track::of(g, c.control));
    for (const auto& v : plan.values) values.push_back(ValueTrack{v.plug, {}});
  }
  if (plan.controls.size() != tracks.size() || plan.values.size() != values.size())
    return error(ErrorCode::kFailedPrecondition, "match: the controls to set changed between frames");
  for (std::size_t i = 0; i < tracks.size(); ++i) {
    Track& t = tracks[i];
    const NodeId parent = g.parent(t.node);
    Mat4 parent_world = parent.is_valid() ? scene.world_matrix(parent) : Mat4(Mat4::Identity());
    for (std::size_t j = 0; j < i; ++j)
      if (plan.controls[j].control == parent) parent_world = plan.controls[j].world;
    const Mat4 offset = std::get<Mat4>(g.evaluate(t.node, xform::kOffsetParentMatrix));
    t.push(math::affine_inverse(parent_world * offset) * plan.controls[i].world);
  }
  for (std::size_t i = 0; i < values.size(); ++i) values[i].values.push_back(plan.values[i].value);
  return Status::ok();
}

// The switch's curve, if it is keyed by one.
NodeId switch_curve(const graph::Graph& g, const Plug& fk_ik) {
  for (const graph::Connection& c : g.node(fk_ik.node)->inputs())
    if (c.dst.attr == fk_ik.attr && anim::curve_kind(g, c.src.node) == anim::CurveKind::kScalar) return c.src.node;
  return {};
}

// Keys the switch at the range's ends with step tangents, and steps out of
// the key before the range (see match.h).
Status key_switch(graph::Graph& g, const Plug& fk_ik, double value, double t_first, double t_last, bool insert,
                  std::size_t& keys) {
  if (!insert) return anim::write_channel_key(g, fk_ik.node, fk_ik.attr, Value(value), t_first, false);
  const NodeId before = switch_curve(g, fk_ik);
  std::optional<double> previous;
  if (before.is_valid())
    for (double t : anim::curve_key_times(g, before))
      if (t < t_first - anim::kKeyTimeTolerance) previous = t;
  const bool one = t_last - t_first <= anim::kKeyTimeTolerance;
  for (double t : {t_first, t_last}) {
    if (one && t != t_first) break;
    Status s = anim::write_channel_key(g, fk_ik.node, fk_ik.attr, Value(value), t, true);
    if (s) s = anim::set_key_tangents(g, fk_ik.node, fk_ik.attr, t, anim::TangentType::kStep, anim::TangentType::kStep);
    if (!s) return s.with_context("match: the switch");
    ++keys;
  }
  if (previous)
    if (Status s = anim::set_key_tangents(g, fk_ik.node, fk_ik.attr, *previous, std::nullopt, anim::TangentType::kStep); !s)
      return s.with_context("match: the switch");
  return Status::ok();
}

}  // namespace

Result<MatchReport> match(scene::Scene& scene, NodeId component, const MatchOptions& o) {
  graph::Graph& g = scene.graph();
  const double time_before = g.time();
  if (o.first.has_value() != o.last.has_value())
    return error(ErrorCode::kInvalidArgument, "match: give both ends of the range, or neither");
  if (!o.key && o.first && *o.first != *o.last)
    return error(ErrorCode::kInvalidArgument, "match: a range is keyed; matching without keys sets one frame");
  const double now = scene.frame();
  Result<std::vector<double>> frame_list =
      internal::frames_between(g, o.first.value_or(now), o.last.value_or(now), "match");
  if (!frame_list) return frame_list.status();
  const std::vector<double>& frames = *frame_list;
  // The plan at the current time first: a component that cannot be matched
  // fails before anything else.
  if (Result<rig::components::FkIkMatch> probe = rig::components::plan_fk_ik_match(scene, component, o.to); !probe)
    return probe.status();

  const std::size_t total = frames.size() * 2 + 1;
  std::size_t done = 0;
  auto tick = [&] {
    ++done;
    if (o.progress) o.progress(static_cast<double>(done) / static_cast<double>(total));
  };
  std::vector<Track> tracks;
  std::vector<ValueTrack> values;
  std::vector<std::vector<Mat4>> wanted;  // per frame, the driven joints' worlds on the side matched to
  Plug fk_ik;
  wanted.reserve(frames.size());
  for (double f : frames) {
    scene.set_frame(f);
    Result<rig::components::FkIkMatch> plan = rig::components::plan_fk_ik_match(scene, component, o.to);
    Status s = plan ? sample(scene, *plan, tracks, values) : plan.status();
    if (!s) {
      g.set_time(time_before);
      return s.with_context("match: frame " + std::to_string(f));
    }
    wanted.push_back(std::move(plan->joint_worlds));
    fk_ik = plan->fk_ik;
    tick();
  }
  g.set_time(time_before);

  MatchReport report;
  report.frames = frames.size();
  for (const Track& t : tracks) report.controls.push_back(t.node);
  std::vector<double> times(frames.size());
  for (std::size_t i = 0; i < frames.size(); ++i) times[i] = frames[i] / g.fps();
  {
    graph::Transaction tx(g, o.to == MatchSide::kFk ? "match FK to IK" : "match IK to FK");
    Status s = o.key ? internal::write_tracks(g, times, tracks, values, true, report.keys, "match")
                     : internal::write_tracks(g, std::span<const double>(times.data(), 1), tracks, values, false,
                                              report.keys, "match");
    if (s) s = key_switch(g, fk_ik, o.to == MatchSide::kFk ? 0.0 : 1.0, times.front(), times.back(), o.key, report.keys);
    if (!s) {
      tx.rollback();
      g.set_time(time_before);
      return s;
    }
  }
  tick();
  // How close it came, frame by frame.
  for (std::size_t i = 0; i < frames.size(); ++i) {
    scene.set_frame(frames[i]);
    const std::vector<Mat4> got = rig::components::fk_ik_side_worlds(scene, component, o.to);
    for (std::size_t j = 0; j < got.size() && j < wanted[i].size(); ++j) {
      const double e = relative_difference(got[j], wanted[i][j]);
      if (e > report.max_error) {
        report.max_error = e;
        report.worst_frame = frames[i];
      }
    }
    tick();
  }
  g.set_time(time_before);
  return report;
}

}  // namespace rigel::tools
