// The workspace's motion trails and ghosts (workspace.h; tools/trails.h).

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "rigel/app/workspace.h"
#include "rigel/scene/transform_types.h"
#include "rigel/tools/trails.h"

namespace rigel::app {
namespace {

constexpr std::size_t kMaxGhosts = 100;

Status bad(const char* field, const std::string& message) {
  return Status(ErrorCode::kInvalidArgument, std::string(field) + ": " + message).with_field(field);
}

bool within(double frame) { return std::isfinite(frame) && std::abs(frame) <= kMaxFrame; }

}  // namespace

Result<std::vector<tools::MotionTrail>> Workspace::motion_trails(const std::vector<NodeId>& controls, double first,
                                                                 double last, double step) {
  const std::vector<NodeId> nodes = controls.empty() ? selection() : controls;
  if (nodes.empty()) return bad("controls", "nothing is selected and no controls given");
  if (!within(first) || !within(last)) return bad("frames", "frames must be finite and within 1e6 of 0");
  return tools::motion_trails(*scene_, nodes, first, last, step);
}

Result<Ghosts> Workspace::ghosts(const GhostOptions& options) {
  graph::Graph& g = graph();
  Ghosts out;
  if (!options.frames.empty()) {
    out.frames = options.frames;
  } else if (options.at_keys) {
    const std::vector<NodeId> sel = selection();
    // The selection's keying group's keys (an ephemeral rig's keying set),
    // else its own channels' (a built rig's controls), else every control's.
    if (!sel.empty()) out.frames = keys(sel).frames;
    if (out.frames.empty()) out.frames = tools::key_frames(g, sel.empty() ? all_controls() : sel);
  } else {
    if (options.before < 0) return bad("before", "must be 0 or more");
    if (options.after < 0) return bad("after", "must be 0 or more");
    if (!std::isfinite(options.step) || options.step <= 0) return bad("step", "must be a positive number of frames");
    const double now = scene_->frame();
    for (int i = options.before; i >= 1; --i) out.frames.push_back(now - i * options.step);
    for (int i = 1; i <= options.after; ++i) out.frames.push_back(now + i * options.step);
  }
  if (out.frames.size() > kMaxGhosts) return bad("frames", "more than 100 ghosts");
  for (double f : out.frames)
    if (!within(f)) return bad("frames", "frames must be finite and within 1e6 of 0");
  std::map<std::uint32_t, int> index;  // joint node index -> out.joints[i]
  for (NodeId id : scene_->hierarchy()) {
    if (g.node(id)->type().name() != scene::kJointType) continue;
    index[id.index] = static_cast<int>(out.joints.size());
    out.joints.push_back(id);
  }
  for (NodeId id : out.joints) {
    // The nearest joint above (a joint under a group under a joint is a bone still).
    int parent = -1;
    for (NodeId p = g.parent(id); p.is_valid(); p = g.parent(p))
      if (auto it = index.find(p.index); it != index.end()) {
        parent = it->second;
        break;
      }
    out.parents.push_back(parent);
  }
  auto points = tools::world_positions(*scene_, out.joints, out.frames);
  if (!points) return points.status();
  out.points = std::move(*points);
  return out;
}

}  // namespace rigel::app
