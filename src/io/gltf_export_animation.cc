// The glTF exporter: which animation can be written from the curves' own
// keys (tracks driving translate, rotateQuaternion and scale of plain
// transforms, scalar curves driving blendShape weights), and writing it so,
// one glTF animation per clip.
#include "gltf_exporter.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <span>
#include <tuple>

#include "rigel/ops/anim/curve.h"
#include "rigel/ops/anim/nodes.h"
#include "rigel/ops/anim/track.h"
#include "rigel/ops/deform/nodes.h"
#include "rigel/scene/transform_types.h"

namespace rigel::io::gltf_exporter {
namespace {

AttrIndex attr_named(const Graph& g, NodeId node, std::string_view name) {
  return g.node(node)->type().attr_find(name);
}

// The keys of a time curve that play in one clip: [begin, end), or none (the
// curve then outputs its restValue).
struct KeySpan {
  std::size_t begin = 0, end = 0;
  bool rest = false;
  std::size_t size() const { return end - begin; }
};

// `clip` is the clip being exported (-1: the scene as it is). A curve whose
// `clip` input is fed by the clips node follows it; another keeps its own.
KeySpan keys_playing(Graph& g, NodeId curve, std::size_t key_count, const ClipList& clips, int clip) {
  const AttrIndex offsets_attr = attr_named(g, curve, "clipOffsets");
  const AttrIndex clip_attr = attr_named(g, curve, "clip");
  if (offsets_attr == graph::kNoAttr || clip_attr == graph::kNoAttr) return {0, key_count, false};
  const auto& offsets = value_as<std::vector<std::int64_t>>(g, curve, offsets_attr);
  if (offsets.empty()) return {0, key_count, false};
  std::int64_t c = value_as<std::int64_t>(g, curve, clip_attr);
  if (clip >= 0 && clips.node.is_valid()) {
    const std::optional<Plug> source = g.source(Plug{curve, clip_attr, -1});
    if (source && source->node == clips.node) c = clip;
  }
  if (c < 0 || static_cast<std::size_t>(c) + 1 >= offsets.size()) return {0, 0, true};
  const std::int64_t begin = offsets[static_cast<std::size_t>(c)], end = offsets[static_cast<std::size_t>(c) + 1];
  if (begin < 0 || end <= begin || static_cast<std::size_t>(end) > key_count) return {0, 0, true};
  return {static_cast<std::size_t>(begin), static_cast<std::size_t>(end), false};
}

template <typename T>
std::span<const T> sub(const std::vector<T>& values, const KeySpan& keys) {
  if (values.empty()) return {};
  return std::span<const T>(values).subspan(keys.begin, keys.size());
}

// A scalar animCurve's keys of one clip, read from its (pulled) attributes.
anim::CurveArrays curve_arrays(const Node& n, const KeySpan& keys) {
  namespace a = anim::curve_attr;
  anim::CurveArrays arrays;
  arrays.times = sub(std::get<std::vector<double>>(n.value(a::kKeyTimes)), keys);
  arrays.values = sub(std::get<std::vector<double>>(n.value(a::kKeyValues)), keys);
  arrays.in_types = sub(std::get<std::vector<std::int64_t>>(n.value(a::kInTangentType)), keys);
  arrays.out_types = sub(std::get<std::vector<std::int64_t>>(n.value(a::kOutTangentType)), keys);
  arrays.in_slopes = sub(std::get<std::vector<double>>(n.value(a::kInSlope)), keys);
  arrays.out_slopes = sub(std::get<std::vector<double>>(n.value(a::kOutSlope)), keys);
  arrays.in_weights = sub(std::get<std::vector<double>>(n.value(a::kInWeight)), keys);
  arrays.out_weights = sub(std::get<std::vector<double>>(n.value(a::kOutWeight)), keys);
  arrays.settings.weighted = std::get<bool>(n.value(a::kWeighted));
  arrays.settings.pre_infinity = static_cast<anim::Infinity>(std::get<std::int64_t>(n.value(a::kPreInfinity)));
  arrays.settings.post_infinity = static_cast<anim::Infinity>(std::get<std::int64_t>(n.value(a::kPostInfinity)));
  return arrays;
}

// True when the curve is a straight line between every pair of keys.
bool curve_is_linear(const anim::CurveArrays& arrays) {
  const auto linear = static_cast<std::int64_t>(anim::TangentType::kLinear);
  if (arrays.times.size() < 2) return true;
  if (arrays.in_types.empty() || arrays.out_types.empty()) return false;  // auto by default
  for (std::size_t k = 0; k + 1 < arrays.times.size(); ++k)
    if (arrays.out_types[k] != linear || arrays.in_types[k + 1] != linear) return false;
  return true;
}

// True when the curve holds each key's value until the next key.
bool curve_is_step(const anim::CurveArrays& arrays) {
  const auto step = static_cast<std::int64_t>(anim::TangentType::kStep);
  if (arrays.times.size() < 2) return true;
  if (arrays.out_types.empty()) return false;
  for (std::size_t k = 0; k + 1 < arrays.times.size(); ++k)
    if (arrays.out_types[k] != step) return false;
  return true;
}

}  // namespace

bool TimeDependence::of(NodeId start) {
  if (auto it = state_.find(start.index); it != state_.end() && it->second != kVisiting) return it->second == kYes;
  struct Frame {
    NodeId id;
    std::size_t next = 0;
    bool yes = false;
  };
  std::vector<Frame> stack{{start, 0, graph_.node(start)->type().time_dependent()}};
  state_[start.index] = kVisiting;
  while (!stack.empty()) {
    Frame& top = stack.back();
    const std::span<const graph::Connection> inputs = graph_.node(top.id)->inputs();
    if (top.yes || top.next >= inputs.size()) {
      const bool yes = top.yes;
      state_[top.id.index] = yes ? kYes : kNo;
      stack.pop_back();
      if (yes && !stack.empty()) stack.back().yes = true;
      continue;
    }
    const NodeId source = inputs[top.next++].src.node;
    if (auto it = state_.find(source.index); it != state_.end()) {
      if (it->second == kYes) top.yes = true;
      continue;  // known, or on the stack (graphs are acyclic, so never)
    }
    state_[source.index] = kVisiting;
    stack.push_back({source, 0, graph_.node(source)->type().time_dependent()});
  }
  return state_[start.index] == kYes;
}

Result<ClipList> read_clips(Graph& g) {
  ClipList list;
  list.node = anim::find_clips_node(g);
  if (!list.node.is_valid()) return list;
  Result<std::vector<anim::Clip>> clips = anim::clips_of(g, list.node);
  if (!clips) return clips.status();
  list.clips = std::move(*clips);
  list.active = static_cast<int>(value_as<std::int64_t>(g, list.node, anim::clips_attr::kActiveClip));
  return list;
}

void Exporter::bake_because(std::string reason) {
  if (bake_reason_.empty()) bake_reason_ = std::move(reason);
}

bool Exporter::shapes_matrix(const Node& n, AttrIndex attr) {
  if (attr < xf::kCount) return attr != xf::kParentMatrix && attr != xf::kVisibility && n.type().is_input(attr);
  return n.type().name() == scene::kJointType && attr == scene::joint_attr::kJointOrient;
}

bool Exporter::is_plain(const Node& n) {
  const Vec3 zero = Vec3::Zero();
  return std::get<Vec3>(n.value(xf::kShear)) == zero && std::get<Vec3>(n.value(xf::kRotatePivot)) == zero &&
         std::get<Vec3>(n.value(xf::kRotatePivotTranslate)) == zero &&
         std::get<Vec3>(n.value(xf::kScalePivot)) == zero &&
         std::get<Vec3>(n.value(xf::kScalePivotTranslate)) == zero &&
         std::get<Mat4>(n.value(xf::kOffsetParentMatrix)) == Mat4::Identity();
}

std::pair<Quat, Quat> Exporter::rotation_frame(const Node& n) {
  const Quat post =
      math::euler_to_quat(math::to_radians(std::get<Vec3>(n.value(xf::kRotateAxis))), math::RotateOrder::kXYZ);
  Quat pre = Quat::Identity();
  if (n.type().name() == scene::kJointType)
    pre = math::euler_to_quat(math::to_radians(std::get<Vec3>(n.value(scene::joint_attr::kJointOrient))),
                              math::RotateOrder::kXYZ);
  return {pre, post};
}

std::pair<NodeId, Path> Exporter::track_feeding(const Node& n, const graph::Connection& c) const {
  const bool whole = c.dst.element < 0 && c.dst.component < 0 && c.src.element < 0 && c.src.component < 0;
  if (!whole || c.src.attr != anim::track_attr::kOutput) return {NodeId{}, Path::kTranslation};
  const bool quaternion_mode = xf::is_quaternion_mode(n);
  const std::string& type = type_of(g_, c.src.node);
  if (type == anim::kAnimCurveVec3Type && c.dst.attr == xf::kTranslate) return {c.src.node, Path::kTranslation};
  if (type == anim::kAnimCurveVec3Type && c.dst.attr == xf::kScale) return {c.src.node, Path::kScale};
  if (type == anim::kAnimCurveQuatType && c.dst.attr == xf::kRotateQuaternion && quaternion_mode)
    return {c.src.node, Path::kRotation};
  return {NodeId{}, Path::kTranslation};
}

void Exporter::apply_rest_values() {
  for (ExportNode& en : nodes_) {
    const Node& n = *g_.node(en.id);
    if (en.detached || !is_plain(n)) continue;
    bool changed = false;
    for (const graph::Connection& c : n.inputs()) {
      const auto [curve_id, path] = track_feeding(n, c);
      if (!curve_id.is_valid()) continue;
      const Node& curve = *g_.node(curve_id);
      const AttrIndex rest = curve.type().attr_find("restValue");
      const AttrIndex offsets = curve.type().attr_find("clipOffsets");
      if (rest == graph::kNoAttr || offsets == graph::kNoAttr ||
          std::get<std::vector<std::int64_t>>(curve.value(offsets)).empty())
        continue;
      changed = true;
      if (path == Path::kTranslation) en.rest.translate = std::get<Vec3>(curve.value(rest));
      if (path == Path::kScale) en.rest.scale = std::get<Vec3>(curve.value(rest));
      if (path == Path::kRotation) {
        const auto [pre, post] = rotation_frame(n);
        const Quat q = std::get<Quat>(curve.value(rest));
        en.rest.rotation = (q.norm() > 1e-6 ? Quat(pre * q.normalized() * post) : Quat(pre * post)).normalized();
        if (en.rest.rotation.w() < 0) en.rest.rotation.coeffs() *= -1.0;
      }
    }
    if (changed) en.rest_matrix = math::trs_matrix(en.rest.translate, en.rest.rotation, en.rest.scale);
  }
}

std::string Exporter::curve_problem(NodeId curve, bool scalar) {
  const Node& n = *g_.node(curve);
  const AttrIndex error_attr = scalar ? AttrIndex{anim::curve_attr::kError} : AttrIndex{anim::track_attr::kError};
  const auto& message = value_as<std::string>(g_, curve, error_attr);
  if (!message.empty()) return n.name() + " has keys it cannot use (" + message + ")";
  const AttrIndex clip_attr = n.type().attr_find("clip");
  for (const graph::Connection& c : n.inputs())
    if (c.dst.attr != clip_attr) return g_.plug_name(c.dst) + " is driven by " + describe(g_, c.src);
  const AttrIndex times_attr = scalar ? AttrIndex{anim::curve_attr::kKeyTimes} : AttrIndex{anim::track_attr::kKeyTimes};
  const auto& times = std::get<std::vector<double>>(n.value(times_attr));
  for (std::size_t k = 0; k < times.size(); ++k) {
    if (times[k] < 0.0) return n.name() + ".keyTimes[" + std::to_string(k) + "] is negative (glTF times are not)";
    if (k > 0 && times[k] > times[k - 1] && static_cast<float>(times[k]) <= static_cast<float>(times[k - 1]))
      return n.name() + ".keyTimes[" + std::to_string(k) + "] is too close to the key before for 32-bit times";
  }
  if (scalar) {
    const auto pre = std::get<std::int64_t>(n.value(anim::curve_attr::kPreInfinity));
    const auto post = std::get<std::int64_t>(n.value(anim::curve_attr::kPostInfinity));
    if (pre != 0 || post != 0) return n.name() + " repeats or extends beyond its keys (pre/post infinity)";
  }
  return {};
}

void Exporter::analyse_animation() {
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    const ExportNode& en = nodes_[i];
    const Node& n = *g_.node(en.id);
    const bool quaternion_mode = xf::is_quaternion_mode(n);
    bool animated = false;
    for (const graph::Connection& c : n.inputs()) {
      const AttrIndex attr = c.dst.attr;
      if (!shapes_matrix(n, attr) || !time_.of(c.src.node)) continue;
      if ((attr == xf::kRotate && quaternion_mode) || (attr == xf::kRotateQuaternion && !quaternion_mode)) continue;
      animated = true;
      const auto [curve_id, path] = track_feeding(n, c);
      if (!curve_id.is_valid()) {
        if (attr == xf::kRotate && type_of(g_, c.src.node) == anim::kAnimCurveVec3Type)
          bake_because(g_.plug_name(c.dst) + " is animated with Euler angles by " + describe(g_, c.src));
        else
          bake_because(g_.plug_name(c.dst) + " is driven by " + describe(g_, c.src));
        continue;
      }
      if (std::string why = curve_problem(curve_id, false); !why.empty()) {
        bake_because(why);
        continue;
      }
      if (en.under_shear) {
        bake_because(n.name() + " is animated below a sheared node, whose shear glTF cannot carry");
        continue;
      }
      DirectTrack t;
      t.node = i;
      t.path = path;
      t.curve = curve_id;
      if (path == Path::kRotation) std::tie(t.pre, t.post) = rotation_frame(n);
      direct_tracks_.push_back(t);
    }
    if (animated && !is_plain(n))
      bake_because(n.name() + " is animated and has shear, pivots or an offsetParentMatrix, which glTF's "
                              "translation/rotation/scale channels cannot carry");
    const NodeId parent = g_.parent(en.id);
    if (en.detached && parent.is_valid() && (animated || time_.of(parent)))
      bake_because(n.name() + " is a skinned mesh that moves with its parent " + name(parent) +
                   " (a glTF skinned mesh node is a root)");
  }

  namespace ba = ops::blend_shape_attr;
  for (std::size_t m = 0; m < meshes_.size(); ++m) {
    const MeshExport& mesh = meshes_[m];
    if (!mesh.blend.is_valid() || mesh.targets.empty()) continue;
    DirectWeights w;
    w.mesh = m;
    w.curves.assign(mesh.targets.size(), NodeId{});
    bool animated = false;
    for (const graph::Connection& c : g_.node(mesh.blend)->inputs()) {
      if (!time_.of(c.src.node)) continue;
      if (c.dst.attr != ba::kWeights) {
        report_.notes.push_back(g_.plug_name(c.dst) + " changes over time; the targets are written as they are at "
                                                      "the export time");
        continue;
      }
      if (c.dst.element < 0 || static_cast<std::size_t>(c.dst.element) >= w.curves.size()) {
        if (c.dst.element < 0) bake_because(g_.plug_name(c.dst) + " is driven as a whole by " + describe(g_, c.src));
        continue;
      }
      animated = true;
      if (type_of(g_, c.src.node) != anim::kAnimCurveType || c.src.attr != anim::curve_attr::kOutput ||
          c.src.component >= 0) {
        bake_because(g_.plug_name(c.dst) + " is driven by " + describe(g_, c.src));
        continue;
      }
      if (std::string why = curve_problem(c.src.node, true); !why.empty()) {
        bake_because(why);
        continue;
      }
      w.curves[static_cast<std::size_t>(c.dst.element)] = c.src.node;
    }
    if (animated) direct_weights_.push_back(std::move(w));
  }
}

std::vector<int> Exporter::clip_indices() const {
  std::vector<int> result;
  for (std::size_t c = 0; c < clips_.clips.size(); ++c) result.push_back(static_cast<int>(c));
  if (result.empty()) result.push_back(-1);
  return result;
}

std::string Exporter::animation_name(int clip) const {
  return clip >= 0 ? clips_.clips[static_cast<std::size_t>(clip)].name : "animation";
}

Status Exporter::direct_all() {
  if (direct_tracks_.empty() && direct_weights_.empty()) return Status::ok();
  for (int clip : clip_indices()) {
    AnimationExport a;
    a.name = animation_name(clip);
    for (const DirectTrack& t : direct_tracks_) direct_track(t, clip, a);
    for (const DirectWeights& w : direct_weights_) direct_weights(w, clip, a);
    if (!a.channels.empty()) animations_.push_back(std::move(a));
  }
  return Status::ok();
}

void Exporter::direct_track(const DirectTrack& t, int clip, AnimationExport& a) {
  namespace ta = anim::track_attr;
  const ExportNode& en = nodes_[t.node];
  const Node& curve = *g_.node(t.curve);
  const auto& times = std::get<std::vector<double>>(curve.value(ta::kKeyTimes));
  const KeySpan keys = keys_playing(g_, t.curve, times.size(), clips_, clip);
  Channel ch;
  ch.node = static_cast<int>(t.node);
  ch.path = t.path;
  const auto interpolation = static_cast<anim::Interpolation>(std::get<std::int64_t>(curve.value(ta::kInterpolation)));
  ch.interpolation = interpolation == anim::Interpolation::kStep          ? "STEP"
                     : interpolation == anim::Interpolation::kCubicSpline ? "CUBICSPLINE"
                                                                           : "LINEAR";
  const bool cubic = interpolation == anim::Interpolation::kCubicSpline;
  const double start = clip >= 0 ? clips_.clips[static_cast<std::size_t>(clip)].start : 0.0;

  if (t.path == Path::kRotation) {
    auto convert = [&](const Quat& q, bool normalize) {
      const Quat r(t.pre * (normalize ? q.normalized() : q) * t.post);
      ch.values.insert(ch.values.end(), {r.x(), r.y(), r.z(), r.w()});
    };
    if (keys.size() == 0) {
      // No keys play: the curve's constant value (restValue, or the identity).
      const AttrIndex rest_attr = curve.type().attr_find("restValue");
      const Quat q = keys.rest && rest_attr != graph::kNoAttr ? std::get<Quat>(curve.value(rest_attr)) : Quat::Identity();
      if (near_quat(Quat(t.pre * q.normalized() * t.post), en.rest.rotation, kConstantTolerance)) return;
      ch.interpolation = "LINEAR";
      ch.times = {start};
      convert(q, true);
    } else {
      const auto values = sub(std::get<std::vector<Quat>>(curve.value(ta::kKeyValues)), keys);
      const auto in = sub(std::get<std::vector<Quat>>(curve.value(ta::kInTangents)), keys);
      const auto out = sub(std::get<std::vector<Quat>>(curve.value(ta::kOutTangents)), keys);
      ch.times.assign(times.begin() + static_cast<std::ptrdiff_t>(keys.begin),
                      times.begin() + static_cast<std::ptrdiff_t>(keys.end));
      for (std::size_t k = 0; k < values.size(); ++k) {
        if (cubic) convert(in[k], false);
        convert(values[k], true);
        if (cubic) convert(out[k], false);
      }
    }
  } else {
    auto convert = [&](const Vec3& v) { ch.values.insert(ch.values.end(), {v.x(), v.y(), v.z()}); };
    if (keys.size() == 0) {
      const AttrIndex rest_attr = curve.type().attr_find("restValue");
      const Vec3 v = keys.rest && rest_attr != graph::kNoAttr ? std::get<Vec3>(curve.value(rest_attr)) : Vec3::Zero();
      if (near_vec(v, rest_vec(en, t.path), kConstantTolerance)) return;
      ch.interpolation = "LINEAR";
      ch.times = {start};
      convert(v);
    } else {
      const auto values = sub(std::get<std::vector<Vec3>>(curve.value(ta::kKeyValues)), keys);
      const auto in = sub(std::get<std::vector<Vec3>>(curve.value(ta::kInTangents)), keys);
      const auto out = sub(std::get<std::vector<Vec3>>(curve.value(ta::kOutTangents)), keys);
      ch.times.assign(times.begin() + static_cast<std::ptrdiff_t>(keys.begin),
                      times.begin() + static_cast<std::ptrdiff_t>(keys.end));
      for (std::size_t k = 0; k < values.size(); ++k) {
        if (cubic) convert(in[k]);
        convert(values[k]);
        if (cubic) convert(out[k]);
      }
    }
  }
  a.channels.push_back(std::move(ch));
}

void Exporter::direct_weights(const DirectWeights& w, int clip, AnimationExport& a) {
  const MeshExport& mesh = meshes_[w.mesh];
  const std::size_t targets = mesh.targets.size();
  const double fps = g_.fps();
  // Per target: the keys that play, or a constant.
  std::vector<anim::CurveArrays> arrays(targets);
  std::vector<std::optional<double>> constant(targets);
  std::set<double> times;
  bool linear = true, step = true;
  for (std::size_t t = 0; t < targets; ++t) {
    if (!w.curves[t].is_valid()) {
      constant[t] = mesh.weights[t];
      continue;
    }
    const Node& curve = *g_.node(w.curves[t]);
    const auto& key_times = std::get<std::vector<double>>(curve.value(anim::curve_attr::kKeyTimes));
    const KeySpan keys = keys_playing(g_, w.curves[t], key_times.size(), clips_, clip);
    if (keys.size() == 0) {
      const AttrIndex rest_attr = curve.type().attr_find("restValue");
      constant[t] = keys.rest && rest_attr != graph::kNoAttr ? std::get<double>(curve.value(rest_attr)) : 0.0;
      continue;
    }
    arrays[t] = curve_arrays(curve, keys);
    times.insert(arrays[t].times.begin(), arrays[t].times.end());
    linear = linear && curve_is_linear(arrays[t]);
    step = step && curve_is_step(arrays[t]);
  }
  if (times.empty()) {
    // Nothing plays: one key when the constants differ from the defaults.
    bool same = true;
    for (std::size_t t = 0; t < targets; ++t) same = same && std::abs(*constant[t] - mesh.weights[t]) <= kConstantTolerance;
    if (same) return;
    times.insert(clip >= 0 ? clips_.clips[static_cast<std::size_t>(clip)].start : 0.0);
  }
  step = step && !linear;  // keyless or single-key curves are both; LINEAR says it plainly
  if (!linear && !step) {
    // Maya tangents are curved between keys: add every frame between them.
    const double first = *times.begin(), last = *times.rbegin();
    for (double f = std::ceil(first * fps); f / fps < last; f += 1.0) times.insert(f / fps);
  }
  Channel ch;
  ch.node = static_cast<int>(mesh.node);
  ch.path = Path::kWeights;
  ch.interpolation = step ? "STEP" : "LINEAR";
  ch.times.assign(times.begin(), times.end());
  // Frames added next to keys can be too close to them for 32-bit times.
  ch.times.erase(std::unique(ch.times.begin(), ch.times.end(),
                             [](double x, double y) { return static_cast<float>(x) == static_cast<float>(y); }),
                 ch.times.end());
  for (double t : ch.times)
    for (std::size_t k = 0; k < targets; ++k)
      ch.values.push_back(constant[k] ? *constant[k] : anim::evaluate_arrays(arrays[k], t));
  a.channels.push_back(std::move(ch));
}

}  // namespace rigel::io::gltf_exporter
