// Channel samples keyed once per channel (tracks.h).
#include "tracks.h"

#include "rigel/ops/anim/channel_keys.h"
#include "rigel/scene/transform_types.h"

namespace rigel::tools::internal {
namespace {

namespace xform = scene::xform;
namespace anim = ops::anim;

bool shear_keyed(const graph::Graph& g, graph::NodeId node) {
  for (const graph::Connection& c : g.node(node)->inputs())
    if (c.dst.attr == xform::kShear && anim::curve_kind(g, c.src.node) != anim::CurveKind::kOther) return true;
  return false;
}

}  // namespace

Track Track::of(graph::Graph& g, graph::NodeId node) {
  Track t;
  t.node = node;
  t.quaternion = xform::is_quaternion_mode(*g.node(node));
  t.order = static_cast<math::RotateOrder>(std::get<std::int64_t>(g.evaluate(node, xform::kRotateOrder)));
  return t;
}

void Track::push(const math::Mat4& local) {
  const math::TransformParts parts = math::decompose_to_parts(local, order);
  translate.push_back(parts.translate);
  scale.push_back(parts.scale);
  shear.push_back(parts.shear);
  sheared = sheared || parts.shear.cwiseAbs().maxCoeff() > 1e-12;
  if (quaternion) {
    rotation.push_back(math::euler_to_quat(parts.rotate, order));
  } else {
    const math::Vec3 radians =
        euler.empty() ? parts.rotate : math::euler_closest(parts.rotate, math::to_radians(euler.back()), order);
    euler.push_back(math::to_degrees(radians));
  }
}

Status write_tracks(graph::Graph& g, std::span<const double> times, const std::vector<Track>& tracks,
                    const std::vector<ValueTrack>& values, bool insert, std::size_t& keys, const char* what) {
  for (const Track& t : tracks) {
    Status s = anim::write_channel_keys(g, t.node, xform::kTranslate, times, t.translate, insert);
    if (s && t.quaternion) s = anim::write_channel_keys(g, t.node, xform::kRotateQuaternion, times, t.rotation, insert);
    if (s && !t.quaternion) s = anim::write_channel_keys(g, t.node, xform::kRotate, times, t.euler, insert);
    if (s) s = anim::write_channel_keys(g, t.node, xform::kScale, times, t.scale, insert);
    const bool shear = t.sheared || shear_keyed(g, t.node);
    if (s && shear) s = anim::write_channel_keys(g, t.node, xform::kShear, times, t.shear, insert);
    if (!s) return s.with_context(what);
    if (insert) keys += times.size() * (shear ? 4 : 3);
  }
  for (const ValueTrack& v : values) {
    if (Status s = anim::write_channel_keys(g, v.plug.node, v.plug.attr, times, v.values, insert); !s)
      return s.with_context(what);
    if (insert) keys += times.size();
  }
  return Status::ok();
}

}  // namespace rigel::tools::internal
