// Motion trails and ghosts (trails.h): world positions sampled frame by
// frame from the evaluated graph, the time put back afterwards.

#include "rigel/tools/trails.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "rigel/tools/keys.h"

namespace rigel::tools {

using graph::NodeId;

namespace {

Status bad(const char* field, const std::string& message) {
  return Status(ErrorCode::kInvalidArgument, std::string(field) + ": " + message).with_field(field);
}

}  // namespace

Result<std::vector<std::vector<math::Vec3>>> world_positions(scene::Scene& scene, const std::vector<NodeId>& nodes,
                                                             const std::vector<double>& frames) {
  graph::Graph& g = scene.graph();
  for (NodeId n : nodes)
    if (!g.node(n)) return bad("controls", "no such node (stale handle)");
  for (double f : frames)
    if (!std::isfinite(f)) return bad("frames", "a frame is not finite");
  if (nodes.size() * frames.size() > kMaxTrailSamples)
    return bad("frames", "more than " + std::to_string(kMaxTrailSamples) + " samples: fewer frames or nodes");
  const double time_before = g.time();
  std::vector<std::vector<math::Vec3>> out(frames.size(), std::vector<math::Vec3>(nodes.size()));
  g.compile();  // the samples are pulls, which use the program but never make it
  for (std::size_t f = 0; f < frames.size(); ++f) {
    scene.set_frame(frames[f]);
    for (std::size_t n = 0; n < nodes.size(); ++n) out[f][n] = scene.world_matrix(nodes[n]).block<3, 1>(0, 3);
  }
  g.set_time(time_before);
  return out;
}

std::vector<double> key_frames(const graph::Graph& graph, const std::vector<NodeId>& nodes) {
  std::vector<double> out;
  auto channels = channels_of(graph, nodes);
  if (!channels) return out;
  for (const PlugKeys& k : keys_of(graph, *channels))
    for (double t : k.times) out.push_back(t * graph.fps());
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end(), [](double a, double b) { return std::abs(a - b) < 1e-6; }), out.end());
  return out;
}

Result<std::vector<MotionTrail>> motion_trails(scene::Scene& scene, const std::vector<NodeId>& nodes, double first,
                                               double last, double step) {
  if (!std::isfinite(first) || !std::isfinite(last) || last < first)
    return bad("frames", "expected a range first <= last of finite frames");
  if (!std::isfinite(step) || step <= 0) return bad("step", "must be a positive number of frames");
  if ((last - first) / step > static_cast<double>(kMaxTrailSamples)) return bad("step", "too many samples");
  // One pass over the frames for every node: the range's and every node's keys in it.
  std::vector<double> frames;
  const auto count = static_cast<std::size_t>(std::floor((last - first) / step + 1e-9));
  for (std::size_t i = 0; i <= count; ++i) frames.push_back(first + static_cast<double>(i) * step);
  if (frames.back() < last) frames.push_back(last);
  std::vector<MotionTrail> trails;
  for (NodeId n : nodes) {
    if (!scene.graph().node(n)) return bad("controls", "no such node (stale handle)");
    MotionTrail t;
    t.node = n;
    for (double k : key_frames(scene.graph(), {n}))
      if (k >= first && k <= last) {
        t.key_frames.push_back(k);
        frames.push_back(k);
      }
    trails.push_back(std::move(t));
  }
  std::sort(frames.begin(), frames.end());
  frames.erase(std::unique(frames.begin(), frames.end(), [](double a, double b) { return std::abs(a - b) < 1e-9; }),
               frames.end());
  auto points = world_positions(scene, nodes, frames);
  if (!points) return points.status();
  for (std::size_t n = 0; n < trails.size(); ++n) {
    trails[n].frames = frames;
    trails[n].points.reserve(frames.size());
    for (const auto& at : *points) trails[n].points.push_back(at[n]);
  }
  return trails;
}

}  // namespace rigel::tools
