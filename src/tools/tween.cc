// Tween and breakdown (tween.h).

#include "rigel/tools/tween.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include "rigel/math/rotation.h"
#include "rigel/ops/anim/channel_keys.h"
#include "rigel/scene/transform_types.h"

namespace rigel::tools {
namespace {

using graph::NodeId;
using graph::Plug;
using graph::Value;
using math::Quat;
using math::Vec3;
namespace xform = scene::xform;
namespace anim = ops::anim;

// The nearest key times of the channel's curves before and after `t`.
std::pair<std::optional<double>, std::optional<double>> neighbours(const graph::Graph& g, const Channel& c, double t) {
  std::optional<double> before, after;
  for (const graph::Connection& conn : g.node(c.node)->inputs()) {
    if (conn.dst.attr != c.attr) continue;
    for (double k : anim::curve_key_times(g, conn.src.node)) {
      if (k < t - anim::kKeyTimeTolerance && (!before || k > *before)) before = k;
      if (k > t + anim::kKeyTimeTolerance && (!after || k < *after)) after = k;
    }
  }
  return {before, after};
}

Quat slerp(const Quat& a, const Quat& b, double f) {
  Quat to = b;
  if (a.dot(to) < 0) to.coeffs() = -to.coeffs();
  const double cos_angle = std::clamp(a.dot(to), -1.0, 1.0);
  const double angle = std::acos(cos_angle);
  if (angle < 1e-12) return Quat((a.coeffs() + f * (to.coeffs() - a.coeffs())).normalized());
  // Valid beyond [0, 1] too: the turn continues past either key.
  const double s = std::sin(angle);
  return Quat(((std::sin((1 - f) * angle) / s) * a.coeffs() + (std::sin(f * angle) / s) * to.coeffs()).normalized());
}

Value blend(const graph::Node& n, graph::AttrIndex attr, const Value& a, const Value& b, double f) {
  if (const auto* x = std::get_if<double>(&a)) return *x + f * (std::get<double>(b) - *x);
  if (const auto* q = std::get_if<Quat>(&a)) return slerp(*q, std::get<Quat>(b), f);
  const Vec3& u = std::get<Vec3>(a);
  const Vec3& v = std::get<Vec3>(b);
  if (attr == xform::kRotate && n.type().attr(attr).name == "rotate") {
    const auto order = static_cast<math::RotateOrder>(std::get<std::int64_t>(n.value(xform::kRotateOrder)));
    const Vec3 ru = math::to_radians(u), rv = math::to_radians(v);
    const Quat q = slerp(math::euler_to_quat(ru, order), math::euler_to_quat(rv, order), f);
    return Vec3(math::to_degrees(math::euler_closest(math::quat_to_euler(q, order), ru, order)));
  }
  return Vec3(u + f * (v - u));
}

}  // namespace

Result<std::size_t> tween(graph::Graph& g, const std::vector<Channel>& channels, double fraction, bool key) {
  if (!std::isfinite(fraction) || std::abs(fraction) > 10)
    return Status(ErrorCode::kInvalidArgument, "tween: the fraction must be a finite number within -10..10")
        .with_field("fraction");
  const double t = g.time();
  struct Blend {
    Channel channel;
    Value value;
  };
  std::vector<Blend> blends;
  for (const Channel& c : channels) {
    if (!g.node(c.node)) return Status(ErrorCode::kNotFound, "tween: no such node (stale handle)").with_field("controls");
    const auto [before, after] = neighbours(g, c, t);
    if (!before || !after) continue;
    g.set_time(*before);
    Result<Value> a = g.evaluate(Plug{c.node, c.attr, -1});
    g.set_time(*after);
    Result<Value> b = g.evaluate(Plug{c.node, c.attr, -1});
    g.set_time(t);
    if (!a) return a.status();
    if (!b) return b.status();
    blends.push_back({c, blend(*g.node(c.node), c.attr, *a, *b, fraction)});
  }
  g.set_time(t);
  graph::Transaction tx(g, "tween");
  for (const Blend& b : blends) {
    if (Status s = anim::write_channel_key(g, b.channel.node, b.channel.attr, b.value, t, key); !s) {
      tx.rollback();
      return s.with_context("tween");
    }
  }
  return blends.size();
}

}  // namespace rigel::tools
