#include "rigel/io/bvh_import.h"

#include <cmath>
#include <cstdio>
#include <string>

#include "rigel/ops/anim/nodes.h"
#include "rigel/ops/anim/track.h"
#include "rigel/ops/registry.h"
#include "rigel/scene/transform_types.h"

namespace rigel::io {
namespace {

using graph::NodeId;
using graph::Plug;
using math::Vec3;

double snapped_fps(double frame_time) {
  const double fps = 1.0 / frame_time;
  const double whole = std::round(fps);
  return std::abs(fps - whole) <= 1e-3 * fps ? whole : fps;
}

// A linear animCurveVec3 named `name` with one key per motion row, driving `target`.
Status add_track(graph::Graph& g, const std::string& name, const std::vector<double>& times, std::vector<Vec3> values,
                 const Plug& target) {
  Result<NodeId> curve = g.create_node(ops::anim::kAnimCurveVec3Type, name);
  if (!curve) return curve.status();
  using namespace ops::anim;
  Status s = g.set_value(Plug{*curve, track_attr::kKeyTimes, -1}, times);
  if (s) s = g.set_value(Plug{*curve, track_attr::kKeyValues, -1}, std::move(values));
  if (s) s = g.set_value(Plug{*curve, track_attr::kInterpolation, -1}, static_cast<std::int64_t>(Interpolation::kLinear));
  if (s) s = g.connect(Plug{*curve, track_attr::kOutput, -1}, target);
  return s;
}

}  // namespace

Result<std::unique_ptr<scene::Scene>> import_bvh(const BvhFile& file, const BvhImportOptions& options) {
  if (!(options.scale > 0.0) || !std::isfinite(options.scale))
    return error(ErrorCode::kInvalidArgument, "BVH import: scale must be a positive number");
  if (!(file.frame_time >= kBvhMinFrameTime && file.frame_time <= kBvhMaxFrameTime)) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", file.frame_time);
    return error(ErrorCode::kInvalidArgument, std::string("BVH import: the frame time ") + text + " s is outside [0.0001, 1000] s");
  }
  auto scene = std::make_unique<scene::Scene>(options.registry ? options.registry : ops::default_registry());
  graph::Graph& g = scene->graph();
  const double fps = snapped_fps(file.frame_time);
  if (Status s = g.set_fps(fps); !s) return s;

  std::vector<double> times(file.frame_count);
  for (std::uint32_t f = 0; f < file.frame_count; ++f) times[f] = f / fps;

  std::vector<NodeId> ids(file.joints.size());
  for (std::size_t j = 0; j < file.joints.size(); ++j) {
    const BvhJoint& joint = file.joints[j];
    if (joint.end_site && options.skip_end_sites) continue;
    const NodeId parent = joint.parent >= 0 ? ids[static_cast<std::size_t>(joint.parent)] : NodeId{};
    const std::string name = graph::Graph::is_valid_name(joint.name) ? joint.name : "joint";
    Result<NodeId> id = scene->create(scene::kJointType, name, parent);
    if (!id) return id.status().with_context("BVH joint " + joint.name + " (line " + std::to_string(joint.line) + ")");
    ids[j] = *id;
    const std::string& node_name = g.node(*id)->name();
    const Vec3 offset = joint.offset * options.scale;
    if (Status s = g.set_value(Plug{*id, scene::xform::kTranslate, -1}, offset); !s) return s;
    const int order = bvh_rotate_order(joint);
    if (Status s = g.set_value(Plug{*id, scene::xform::kRotateOrder, -1}, static_cast<std::int64_t>(order)); !s) return s;
    if (file.frame_count == 0 || joint.channels.empty()) continue;

    bool has_position = false, has_rotation = false;
    for (BvhChannel c : joint.channels) {
      (c <= BvhChannel::kZposition ? has_position : has_rotation) = true;
    }
    std::vector<Vec3> translate(has_position ? file.frame_count : 0, offset);
    std::vector<Vec3> rotate(has_rotation ? file.frame_count : 0, Vec3::Zero());
    for (std::uint32_t f = 0; f < file.frame_count; ++f) {
      for (std::size_t k = 0; k < joint.channels.size(); ++k) {
        const double v = file.value(f, joint.first_channel + static_cast<std::uint32_t>(k));
        const int axis = static_cast<int>(joint.channels[k]) % 3;
        if (joint.channels[k] <= BvhChannel::kZposition) translate[f][axis] += v * options.scale;
        else rotate[f][axis] = v;  // degrees, as the rotate attribute
      }
    }
    if (has_position) {
      if (Status s = add_track(g, node_name + "_translate", times, std::move(translate), Plug{*id, scene::xform::kTranslate, -1}); !s)
        return s;
    }
    if (has_rotation) {
      if (Status s = add_track(g, node_name + "_rotate", times, std::move(rotate), Plug{*id, scene::xform::kRotate, -1}); !s)
        return s;
    }
  }
  g.clear_history();
  return scene;
}

}  // namespace rigel::io
