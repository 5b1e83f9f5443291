// Baking what a rig makes nodes do into keys (bake.h).

#include "rigel/tools/bake.h"

#include <cmath>
#include <unordered_set>

#include "rigel/math/rotation.h"
#include "rigel/ops/anim/channel_keys.h"
#include "rigel/scene/transform_types.h"
#include "frames.h"

namespace rigel::tools {
namespace {

using graph::NodeId;
namespace xform = scene::xform;

struct NodeIdHash {
  std::size_t operator()(NodeId id) const { return (std::size_t{id.generation} << 32) ^ id.index; }
};

bool is_channel(graph::AttrIndex a) {
  return a == xform::kTranslate || a == xform::kRotate || a == xform::kRotateQuaternion || a == xform::kScale;
}

}  // namespace

Result<BakeReport> bake(scene::Scene& scene, const BakeOptions& o) {
  graph::Graph& g = scene.graph();
  Result<std::vector<double>> frame_list = internal::frames_between(g, o.first, o.last, "bake");
  if (!frame_list) return frame_list.status();
  const std::vector<double>& frames = *frame_list;

  // The nodes, parents first.
  std::unordered_set<NodeId, NodeIdHash> wanted(o.nodes.begin(), o.nodes.end());
  for (NodeId id : o.nodes)
    if (!scene.is_transform(id))
      return error(ErrorCode::kInvalidArgument,
                   "bake: " + (g.node(id) ? g.node(id)->name() : std::string("a deleted node")) + " is not a transform");
  std::vector<NodeId> nodes;
  for (NodeId id : scene.hierarchy()) {
    const bool take = o.nodes.empty() ? g.node(id)->type().name() == scene::kJointType : wanted.count(id) > 0;
    if (take) nodes.push_back(id);
  }

  // Sample every node at every frame (the rig evaluated as it is).
  const double time_before = g.time();
  // Progress: one unit per node and frame sampled, as many again for the
  // keys (written a node at a time), one for the end.
  const std::size_t total_work = nodes.size() * frames.size() * 2 + 1;
  std::size_t done = 0;
  // Per node, one entry per frame.
  struct Samples {
    std::vector<math::Vec3> translate, scale, euler;  // euler: degrees
    std::vector<math::Quat> rotation;
  };
  std::vector<Samples> samples(nodes.size());
  for (Samples& list : samples) {
    for (auto* v : {&list.translate, &list.scale, &list.euler}) v->reserve(frames.size());
    list.rotation.reserve(frames.size());
  }
  g.compile();  // the samples are pulls, which use the program but never make it
  for (std::size_t f = 0; f < frames.size(); ++f) {
    scene.set_frame(frames[f]);
    for (std::size_t n = 0; n < nodes.size(); ++n) {
      auto ch = scene.channels_for_world(nodes[n], scene.world_matrix(nodes[n]));
      if (!ch) {
        g.set_time(time_before);
        return ch.status().with_context("bake: frame " + std::to_string(frames[f]));
      }
      const auto order =
          static_cast<math::RotateOrder>(std::get<std::int64_t>(g.node(nodes[n])->value(xform::kRotateOrder)));
      math::Vec3 euler;
      math::Quat rotation;
      if (ch->rotation_attr == xform::kRotate) {
        euler = std::get<math::Vec3>(ch->rotation);
        rotation = math::euler_to_quat(math::to_radians(euler), order);
      } else {
        rotation = std::get<math::Quat>(ch->rotation);
        euler = math::to_degrees(math::quat_to_euler(rotation, order));
      }
      // Continuity: Euler angles closest to the previous frame's, quaternions
      // in the previous frame's hemisphere, so linear keys take the short way.
      Samples& list = samples[n];
      if (!list.euler.empty()) {
        euler = math::to_degrees(math::euler_closest(math::to_radians(euler), math::to_radians(list.euler.back()), order));
        if (rotation.coeffs().dot(list.rotation.back().coeffs()) < 0) rotation.coeffs() *= -1;
      }
      list.translate.push_back(ch->translate);
      list.scale.push_back(ch->scale);
      list.euler.push_back(euler);
      list.rotation.push_back(rotation);
      if (o.progress) o.progress(static_cast<double>(++done) / static_cast<double>(total_work));
    }
  }

  BakeReport report;
  report.nodes = nodes.size();
  report.frames = frames.size();
  graph::Transaction tx(g, "bake");
  // Whatever drove the baked channels lets go of them.
  std::unordered_set<NodeId, NodeIdHash> baked(nodes.begin(), nodes.end());
  for (const graph::Connection& c : g.connections()) {
    if (!baked.count(c.dst.node) || !is_channel(c.dst.attr)) continue;
    if (Status s = g.disconnect(c.src, c.dst); !s) {
      tx.rollback();
      g.set_time(time_before);
      return s.with_context("bake");
    }
    ++report.disconnected;
  }
  // Each channel's keys in one write: its curves' arrays are set once (one
  // undo record each), so time and memory grow with the frames.
  std::vector<double> times(frames.size());
  for (std::size_t f = 0; f < frames.size(); ++f) times[f] = frames[f] / g.fps();
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    Samples& x = samples[n];
    Status s = ops::anim::write_channel_keys(g, nodes[n], xform::kTranslate, times, x.translate, true);
    if (s) s = ops::anim::write_channel_keys(g, nodes[n], xform::kRotate, times, x.euler, true);
    if (s) s = ops::anim::write_channel_keys(g, nodes[n], xform::kRotateQuaternion, times, x.rotation, true);
    if (s) s = ops::anim::write_channel_keys(g, nodes[n], xform::kScale, times, x.scale, true);
    if (!s) {
      tx.rollback();
      g.set_time(time_before);
      return s.with_context("bake: " + g.node(nodes[n])->name());
    }
    x = Samples{};  // written: its memory goes back
    report.keys += 4 * frames.size();
    done += frames.size();
    if (o.progress) o.progress(static_cast<double>(done) / static_cast<double>(total_work));
  }
  g.set_time(time_before);
  if (o.progress) o.progress(1.0);
  return report;
}

}  // namespace rigel::tools
