// Mirror and flip (mirror.h).

#include "rigel/tools/mirror.h"

#include <algorithm>
#include <set>
#include <string>
#include <utility>

#include "frames.h"
#include "mirror_map.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/rig/meta.h"
#include "rigel/scene/transform_types.h"
#include "rigel/tools/keys.h"
#include "tracks.h"

namespace rigel::tools {
namespace {

using graph::AttrIndex;
using graph::NodeId;
using graph::Plug;
using math::Mat4;
namespace xform = scene::xform;

struct PoseJob {
  NodeId source, target;
  internal::MirrorMap map;
};
struct ValueJob {
  Plug source, target;
};

std::string side_of(const graph::Graph& g, NodeId node) {
  const NodeId meta = rig::component_of(g, node);
  return meta.is_valid() ? rig::meta_string(g, meta, "side") : std::string();
}

bool is_control(const graph::Graph& g, NodeId id) { return g.node(id)->type().name() == scene::kControlType; }

Result<PoseJob> pose_job(const graph::Graph& g, NodeId source, NodeId target, const Mat4& m) {
  Result<internal::MirrorMap> map = internal::mirror_map(g, source, target, m, "mirror");
  if (!map) return map.status();
  return PoseJob{source, target, *map};
}

// The controls `all` covers: every control of the rigs of `given` (of every
// rig when none), components in order.
std::vector<NodeId> rig_controls(const graph::Graph& g, const std::vector<NodeId>& given) {
  std::vector<NodeId> rigs;
  for (NodeId c : given) {
    const NodeId r = rig::rig_of(g, c);
    if (r.is_valid() && std::find(rigs.begin(), rigs.end(), r) == rigs.end()) rigs.push_back(r);
  }
  if (given.empty()) rigs = rig::list_rigs(g);
  std::vector<NodeId> out;
  for (NodeId r : rigs)
    for (NodeId meta : rig::rig_components(g, r))
      for (NodeId m : rig::meta_members(g, meta))
        if (is_control(g, m) && !ephemeral::control_of(g, m).is_valid()) out.push_back(m);  // ephemeral ones pose through their session
  return out;
}

// Scalar keyable channels of the components' other nodes (switches, foot
// values), paired by role and index as controls are.
Status value_jobs(const graph::Graph& g, const std::vector<NodeId>& controls, const MirrorOptions& o,
                  std::vector<ValueJob>& out) {
  std::set<std::uint32_t> seen;
  for (NodeId c : controls) {
    const NodeId meta = rig::component_of(g, c);
    if (!meta.is_valid() || !seen.insert(meta.index).second) continue;
    const std::string side = rig::meta_string(g, meta, "side");
    if (side != "L" && side != "R") continue;
    if (!o.flip && side[0] != o.from) continue;
    for (NodeId m : rig::meta_members(g, meta)) {
      const graph::Node& n = *g.node(m);
      if (is_control(g, m) || n.type().world_output() != graph::kNoAttr) continue;
      // Free or keyed channels only (a foot's fkIk follows its limb's).
      Result<std::vector<Channel>> free = channels_of(g, {m});
      if (!free) continue;
      std::vector<AttrIndex> attrs;
      for (const Channel& c : *free) attrs.push_back(c.attr);
      Result<NodeId> pair = rig::mirror_pair(g, m);
      if (!pair) continue;  // its component has no pair (listed with its controls)
      auto add = [&](const Plug& from, const Plug& to) {
        for (const ValueJob& j : out)
          if (j.target == to) return;
        out.push_back({from, to});
      };
      for (AttrIndex a : attrs) {
        if (n.type().attr(a).type.value != graph::ValueType::kDouble) continue;
        add(Plug{m, a, -1}, Plug{*pair, a, -1});
        if (o.flip) add(Plug{*pair, a, -1}, Plug{m, a, -1});
      }
    }
  }
  return Status::ok();
}

Result<std::pair<std::vector<PoseJob>, std::vector<ValueJob>>> plan(const graph::Graph& g, const MirrorOptions& o,
                                                                     std::vector<NodeId>* unpaired) {
  if (o.from != 'L' && o.from != 'R')
    return Status(ErrorCode::kInvalidArgument, "mirror: the side to mirror from is L or R").with_field("from");
  if (o.controls.empty() && !o.all)
    return Status(ErrorCode::kInvalidArgument, "mirror: no controls given").with_field("controls");
  for (NodeId c : o.controls)
    if (!g.node(c) || !is_control(g, c) || !rig::component_of(g, c).is_valid())
      return Status(ErrorCode::kInvalidArgument,
                    "mirror: '" + (g.node(c) ? g.node(c)->name() : std::string("?")) + "' is not a built rig's control")
          .with_field("controls");
  const std::vector<NodeId> controls = o.all ? rig_controls(g, o.controls) : o.controls;
  const Mat4 m = internal::reflection(o.plane);
  std::vector<PoseJob> poses;
  std::set<std::uint32_t> targets;
  auto add = [&](NodeId source, NodeId target) -> Status {
    if (!targets.insert(target.index).second) return Status::ok();
    Result<PoseJob> job = pose_job(g, source, target, m);
    if (!job) return job.status();
    poses.push_back(*job);
    return Status::ok();
  };
  for (NodeId c : controls) {
    Result<NodeId> pair = rig::mirror_pair(g, c);
    if (!pair && o.all) {  // every control: those without a pair are left, and listed
      if (unpaired) unpaired->push_back(c);
      continue;
    }
    if (!pair) return pair.status();
    const std::string side = side_of(g, c);
    const bool centre = *pair == c;
    if (o.flip) {
      if (Status s = add(c, *pair); !s) return s;
      if (!centre)
        if (Status s = add(*pair, c); !s) return s;
    } else if (!centre && (!o.all || side[0] == o.from)) {
      if (Status s = add(c, *pair); !s) return s;
    }
  }
  std::vector<ValueJob> values;
  if (o.all)
    if (Status s = value_jobs(g, controls, o, values); !s) return s;
  if (poses.empty() && values.empty())
    return Status(ErrorCode::kInvalidArgument, "mirror: nothing to mirror (centre controls mirror only with flip)")
        .with_field("controls");
  return std::pair{std::move(poses), std::move(values)};
}

}  // namespace

Result<MirrorReport> mirror(scene::Scene& scene, const MirrorOptions& o) {
  graph::Graph& g = scene.graph();
  const double time_before = g.time();
  if (o.first.has_value() != o.last.has_value())
    return Status(ErrorCode::kInvalidArgument, "mirror: give both ends of the range, or neither").with_field("frames");
  if (!o.key && o.first && *o.first != *o.last)
    return Status(ErrorCode::kInvalidArgument, "mirror: a range is keyed; mirroring without keys sets one frame")
        .with_field("frames");
  MirrorReport report;
  auto jobs = plan(g, o, &report.unpaired);
  if (!jobs) return jobs.status();
  const auto& [poses, value_jobs_] = *jobs;
  const double now = scene.frame();
  Result<std::vector<double>> frame_list = internal::frames_between(g, o.first.value_or(now), o.last.value_or(now), "mirror");
  if (!frame_list) return Status(frame_list.status()).with_field("frames");
  const std::vector<double>& frames = *frame_list;

  std::vector<internal::Track> tracks;
  for (const PoseJob& j : poses) tracks.push_back(internal::Track::of(g, j.target));
  std::vector<internal::ValueTrack> values;
  for (const ValueJob& j : value_jobs_) values.push_back({j.target, {}});
  const std::size_t total = frames.size() + 1;
  std::size_t done = 0;
  for (double f : frames) {
    scene.set_frame(f);
    for (std::size_t i = 0; i < poses.size(); ++i) {
      const Mat4 channels = std::get<Mat4>(g.evaluate(poses[i].source, xform::kMatrix));
      tracks[i].push(poses[i].map(channels));
    }
    for (std::size_t i = 0; i < value_jobs_.size(); ++i)
      values[i].values.push_back(std::get<double>(g.evaluate(value_jobs_[i].source.node, value_jobs_[i].source.attr)));
    ++done;
    if (o.progress) o.progress(static_cast<double>(done) / static_cast<double>(total));
  }
  g.set_time(time_before);

  report.frames = frames.size();
  for (const auto& t : tracks) report.set.push_back(t.node);
  for (const auto& v : values)
    if (std::find(report.set.begin(), report.set.end(), v.plug.node) == report.set.end()) report.set.push_back(v.plug.node);
  std::vector<double> times(frames.size());
  for (std::size_t i = 0; i < frames.size(); ++i) times[i] = frames[i] / g.fps();
  graph::Transaction tx(g, o.flip ? "flip pose" : "mirror pose");
  const Status s = internal::write_tracks(g, o.key ? std::span<const double>(times) : std::span<const double>(times.data(), 1),
                                          tracks, values, o.key, report.keys, "mirror");
  if (!s) {
    tx.rollback();
    g.set_time(time_before);
    return s;
  }
  if (o.progress) o.progress(1.0);
  return report;
}

namespace internal {

Mat4 reflection(MirrorPlane plane) {
  const int axis = plane == MirrorPlane::kYZ ? 0 : plane == MirrorPlane::kXZ ? 1 : 2;  // the axis it negates
  Mat4 m = Mat4::Identity();
  m(axis, axis) = -1;
  return m;
}

Result<MirrorMap> mirror_map(const graph::Graph& g, NodeId source, NodeId target, const Mat4& reflection,
                             const char* what) {
  const std::optional<Mat4> a = rig::rest_world(g, source), b = rig::rest_world(g, target);
  if (!a || !b)
    return Status(ErrorCode::kFailedPrecondition, std::string(what) + ": '" + g.node(a ? target : source)->name() +
                                                      "' has no recorded rest (the rig was built before rigel "
                                                      "recorded it): rebuild it (rigel update --force)")
        .with_field("controls");
  MirrorMap map{math::affine_inverse(*a) * reflection * *b, Mat4::Identity()};
  map.k_inverse = math::affine_inverse(map.k);
  return map;
}

}  // namespace internal

}  // namespace rigel::tools
