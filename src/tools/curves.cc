// The graph editor's curves (curves.h).
#include "rigel/tools/curves.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

#include "rigel/ephemeral/keying.h"
#include "rigel/math/rotation.h"
#include "rigel/ops/anim/channel_keys.h"
#include "rigel/ops/anim/curve_edit.h"
#include "rigel/scene/transform_types.h"

namespace rigel::tools {
namespace {

using ops::anim::CurveKind;
using ops::anim::CurveKeys;

constexpr double kDegrees = 180.0 / std::numbers::pi;
constexpr std::size_t kMaxSamples = 100000;

Status bad(const std::string& field, const std::string& message) {
  return Status(ErrorCode::kInvalidArgument, field + ": " + message).with_field(field);
}

// The curve node keying `plug` exactly (invalid when none).
graph::NodeId curve_into(const graph::Graph& g, const graph::Plug& plug) {
  const graph::Node* n = g.node(plug.node);
  if (!n) return {};
  for (const graph::Connection& c : n->inputs())
    if (c.dst == plug && ops::anim::curve_kind(g, c.src.node) != CurveKind::kOther) return c.src.node;
  return {};
}

math::RotateOrder rotate_order_of(const graph::Graph& g, graph::NodeId node) {
  const graph::Node& n = *g.node(node);
  const graph::AttrIndex a = n.type().attr_find("rotateOrder");
  if (a == graph::kNoAttr) return math::RotateOrder::kXYZ;
  const auto* v = std::get_if<std::int64_t>(&n.value(a));
  return v && *v >= 0 && *v < math::kRotateOrderCount ? static_cast<math::RotateOrder>(*v) : math::RotateOrder::kXYZ;
}

// Euler angles (degrees) of quaternion rows, each closest to the one before.
std::vector<math::Vec3> unwrapped_euler(const std::vector<std::vector<double>>& quats, math::RotateOrder order) {
  std::vector<math::Vec3> out;
  out.reserve(quats.size());
  for (const std::vector<double>& q : quats) {
    const math::Quat rotation(q[3], q[0], q[1], q[2]);
    math::Vec3 e = math::quat_to_euler(rotation.normalized(), order);
    if (!out.empty()) e = math::euler_closest(e, out.back() / kDegrees, order);
    out.push_back(e * kDegrees);
  }
  return out;
}

// The sample times: [first, last] every step, plus every key, sorted.
Result<std::vector<double>> sample_times(const graph::Graph& g, const CurveKeys& keys, const CurveViewOptions& o) {
  double first = o.first.value_or(keys.times.empty() ? 0.0 : keys.times.front());
  double last = o.last.value_or(keys.times.empty() ? 0.0 : keys.times.back());
  if (!o.first && !o.last && first == last) {
    first -= 0.5;
    last += 0.5;
  }
  const double step = o.step.value_or(1.0 / g.fps());
  if (!std::isfinite(first)) return bad("first", "not a finite time");
  if (!std::isfinite(last)) return bad("last", "not a finite time");
  if (first > last) return bad("last", "the range ends before it starts");
  if (!std::isfinite(step) || step <= 0) return bad("step", "must be a positive time");
  if ((last - first) / step > static_cast<double>(kMaxSamples))
    return bad("step", "more than 100000 samples; give a larger step or a shorter range");
  std::vector<double> times;
  const auto count = static_cast<std::size_t>(std::floor((last - first) / step + 1e-9));
  for (std::size_t i = 0; i <= count; ++i) times.push_back(first + static_cast<double>(i) * step);
  if (times.back() < last) times.push_back(last);
  for (double t : keys.times)
    if (t >= first && t <= last) times.push_back(t);
  std::sort(times.begin(), times.end());
  times.erase(std::unique(times.begin(), times.end(),
                          [](double a, double b) { return std::abs(a - b) <= ops::anim::kKeyTimeTolerance * 1e-3; }),
              times.end());
  return times;
}

// The view of one curve node driving `plug`.
Status add_views(const graph::Graph& g, const graph::Plug& plug, graph::NodeId curve, const CurveViewOptions& o,
                 std::vector<CurveView>& out) {
  const CurveKeys keys = ops::anim::curve_keys(g, curve);
  Result<std::vector<double>> times = sample_times(g, keys, o);
  if (!times) return times.status();
  const std::vector<std::vector<double>> samples = ops::anim::sample_curve(g, curve, *times);
  const std::string name = g.plug_name(plug);
  const std::string attr = name.substr(name.rfind('.') + 1);
  CurveView base;
  base.plug = plug;
  base.name = name;
  base.curve = g.node(curve)->name();
  base.sample_times = *times;
  base.key_times = keys.times;
  if (keys.kind == CurveKind::kScalar) {
    CurveView v = base;
    v.kind = "curve";
    v.label = attr;
    for (const auto& k : keys.values) v.key_values.push_back(k[0]);
    for (const auto& s : samples) v.sample_values.push_back(s[0]);
    const auto names = ops::anim::tangent_type_names();
    for (auto t : keys.in_types) v.in_tangents.emplace_back(names[static_cast<std::size_t>(t)]);
    for (auto t : keys.out_types) v.out_tangents.emplace_back(names[static_cast<std::size_t>(t)]);
    v.in_slopes = keys.in_slopes;
    v.out_slopes = keys.out_slopes;
    out.push_back(std::move(v));
    return Status::ok();
  }
  const bool euler = keys.kind == CurveKind::kQuat && o.quat_as_euler;
  std::vector<math::Vec3> sample_euler, key_euler;
  if (euler) {
    const math::RotateOrder order = rotate_order_of(g, plug.node);
    sample_euler = unwrapped_euler(samples, order);
    // A key's angles: its sample's (the same unwrapping).
    for (double t : keys.times) {
      const auto at = std::lower_bound(times->begin(), times->end(), t - 1e-12);
      if (at != times->end() && std::abs(*at - t) < 1e-9) {
        key_euler.push_back(sample_euler[static_cast<std::size_t>(at - times->begin())]);
      } else {  // outside the range drawn
        const std::vector<std::vector<double>> one = ops::anim::sample_curve(g, curve, std::span<const double>(&t, 1));
        key_euler.push_back(unwrapped_euler(one, order).front());
      }
    }
  }
  const int components = keys.kind == CurveKind::kVec3 || euler ? 3 : 4;
  for (int c = 0; c < components; ++c) {
    CurveView v = base;
    v.kind = keys.kind == CurveKind::kVec3 ? "vectorTrack" : "rotationTrack";
    v.component = c;
    v.editable = keys.kind == CurveKind::kVec3;
    v.label = euler ? std::string("rotate.") + "xyz"[c] : attr + "." + "xyzw"[c];
    for (std::size_t k = 0; k < keys.times.size(); ++k) v.key_values.push_back(euler ? key_euler[k][c] : keys.values[k][c]);
    for (std::size_t s = 0; s < samples.size(); ++s) v.sample_values.push_back(euler ? sample_euler[s][c] : samples[s][c]);
    out.push_back(std::move(v));
  }
  return Status::ok();
}

struct Target {
  graph::Plug plug;
  graph::NodeId curve;
  std::vector<double> times;  // its keys
};

Result<Target> target_of(const graph::Graph& g, const std::string& name) {
  Result<graph::Plug> plug = g.plug_find(name);
  if (!plug) return Status(plug.status().code(), "keys: " + plug.status().message()).with_field("keys");
  const graph::NodeId curve = curve_into(g, *plug);
  if (!curve.is_valid()) return Status(ErrorCode::kNotFound, "keys: " + name + " has no curve").with_field("keys");
  return Target{*plug, curve, ops::anim::curve_key_times(g, curve)};
}

// The index of the key nearest `t` within the key tolerance.
std::optional<std::size_t> key_index(const graph::Graph& g, const std::vector<double>& times, double t) {
  const double tolerance = ephemeral::key_time_tolerance(g);
  std::optional<std::size_t> best;
  for (std::size_t i = 0; i < times.size(); ++i)
    if (std::abs(times[i] - t) <= tolerance && (!best || std::abs(times[i] - t) < std::abs(times[*best] - t))) best = i;
  return best;
}

std::string frame_text(const graph::Graph& g, double t) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "frame %g", t * g.fps());
  return buffer;
}

// Changes per curve node (first appearance order), each applied by edit_curve.
struct CurveChanges {
  graph::NodeId curve;
  std::vector<ops::anim::KeyChange> changes;
};

Result<std::size_t> apply(graph::Graph& g, const std::string& label, std::vector<CurveChanges>& per_curve) {
  graph::Transaction tx(g, label);
  std::size_t count = 0;
  for (const CurveChanges& c : per_curve) {
    if (c.changes.empty()) continue;
    if (Status s = ops::anim::edit_curve(g, c.curve, c.changes); !s) {
      tx.rollback();
      return Status(s.code(), "keys: " + g.node(c.curve)->name() + ": " + s.message()).with_field("keys");
    }
    count += c.changes.size();
  }
  return count;
}

CurveChanges& changes_of(std::vector<CurveChanges>& all, graph::NodeId curve) {
  for (CurveChanges& c : all)
    if (c.curve == curve) return c;
  all.push_back(CurveChanges{curve, {}});
  return all.back();
}

}  // namespace

Result<std::vector<CurveView>> curve_views(const graph::Graph& graph, const std::vector<Channel>& channels,
                                           const CurveViewOptions& options) {
  std::vector<CurveView> out;
  for (const PlugKeys& keys : keys_of(graph, channels)) {
    const graph::NodeId curve = curve_into(graph, keys.plug);
    if (!curve.is_valid()) continue;
    if (Status s = add_views(graph, keys.plug, curve, options, out); !s) return s;
  }
  return out;
}

Result<std::size_t> edit_curve_keys(graph::Graph& graph, const std::vector<CurveKeyEdit>& edits) {
  std::vector<CurveChanges> per_curve;
  for (const CurveKeyEdit& e : edits) {
    Result<Target> target = target_of(graph, e.key.curve);
    if (!target) return target.status();
    const std::optional<std::size_t> k = key_index(graph, target->times, e.key.time);
    if (!k)
      return Status(ErrorCode::kNotFound, "keys: " + e.key.curve + " has no key at " + frame_text(graph, e.key.time))
          .with_field("keys");
    ops::anim::KeyChange change;
    change.key = *k;
    change.time = e.to_time;
    change.value = e.value;
    change.component = e.component >= 0 ? e.component : target->plug.component;
    change.in_type = e.in_type;
    change.out_type = e.out_type;
    change.in_slope = e.in_slope;
    change.out_slope = e.out_slope;
    changes_of(per_curve, target->curve).changes.push_back(change);
  }
  return apply(graph, "edit keys", per_curve);
}

Result<std::size_t> insert_curve_keys(graph::Graph& graph, const std::vector<CurveKeyRef>& keys) {
  std::vector<CurveChanges> per_curve;
  for (const CurveKeyRef& r : keys) {
    Result<Target> target = target_of(graph, r.curve);
    if (!target) return target.status();
    if (!std::isfinite(r.time)) return bad("keys", r.curve + ": the time is not finite");
    if (key_index(graph, target->times, r.time)) continue;  // a key there already
    ops::anim::KeyChange change;
    change.time = r.time;
    auto& list = changes_of(per_curve, target->curve).changes;
    const bool twice = std::any_of(list.begin(), list.end(), [&](const ops::anim::KeyChange& c) {
      return std::abs(*c.time - r.time) <= ephemeral::key_time_tolerance(graph);
    });
    if (!twice) list.push_back(change);
  }
  return apply(graph, "insert keys", per_curve);
}

Result<std::size_t> delete_curve_keys(graph::Graph& graph, const std::vector<CurveKeyRef>& keys) {
  graph::Transaction tx(graph, "delete keys");
  std::size_t count = 0;
  for (const CurveKeyRef& r : keys) {
    Result<Target> target = target_of(graph, r.curve);
    if (!target) {
      tx.rollback();
      return target.status();
    }
    const std::optional<std::size_t> k = key_index(graph, target->times, r.time);
    if (!k) {
      tx.rollback();
      return Status(ErrorCode::kNotFound, "keys: " + r.curve + " has no key at " + frame_text(graph, r.time))
          .with_field("keys");
    }
    const graph::Value keep = graph.evaluate(target->plug.node, target->plug.attr);
    graph::Value channel_value = keep;
    if (target->plug.component >= 0) channel_value = std::get<math::Vec3>(keep)[target->plug.component];
    bool removed = false;
    if (Status s = ops::anim::delete_curve_key(graph, target->curve, target->times[*k], target->plug, channel_value,
                                               removed);
        !s) {
      tx.rollback();
      return Status(s.code(), "keys: " + s.message()).with_field("keys");
    }
    count += removed ? 1 : 0;
  }
  return count;
}

}  // namespace rigel::tools
