// The glTF importer: animation channels read (one clip per glTF
// animation) and built into curves, one per animated (node, path), with the
// keys of every clip.
#include "gltf_importer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>

#include "rigel/ops/anim/clips.h"
#include "rigel/ops/anim/nodes.h"
#include "rigel/ops/anim/curve.h"
#include "rigel/ops/anim/track.h"
#include "rigel/ops/deform/nodes.h"
#include "rigel/scene/transform_types.h"

namespace rigel::io::gltf_importer {
namespace {

using gltf::type_name;

// A unique string among `taken`: `wanted`, else wanted + 1, 2, ...
std::string unique_among(const std::string& wanted, std::set<std::string>& taken) {
  std::string name = wanted;
  for (int n = 1; taken.count(name); ++n) name = wanted + std::to_string(n);
  taken.insert(name);
  return name;
}

// Keys of several clips in one curve need one interpolation; when the clips
// of a channel disagree they are converted (see the header).
ClipKeys to_cubic(const ClipKeys& keys, std::size_t width) {
  ClipKeys out = keys;
  out.interpolation = ops::anim::Interpolation::kCubicSpline;
  const std::size_t n = keys.times.size();
  out.in_tangents.assign(n * width, 0.0);
  out.out_tangents.assign(n * width, 0.0);
  for (std::size_t k = 0; k + 1 < n; ++k) {
    const double span = keys.times[k + 1] - keys.times[k];
    for (std::size_t w = 0; w < width; ++w) {
      const double slope = (keys.values[(k + 1) * width + w] - keys.values[k * width + w]) / span;
      out.out_tangents[k * width + w] = slope;
      out.in_tangents[(k + 1) * width + w] = slope;
    }
  }
  return out;
}

ClipKeys to_linear(const ClipKeys& keys, std::size_t width, bool rotation) {
  using ops::anim::Interpolation;
  if (keys.interpolation == Interpolation::kLinear) return keys;
  ClipKeys out;
  out.interpolation = Interpolation::kLinear;
  const std::size_t n = keys.times.size();
  auto push = [&](double t, const double* v) {
    out.times.push_back(t);
    out.values.insert(out.values.end(), v, v + width);
  };
  constexpr int kSamples = 16;
  std::vector<double> sample(width);
  for (std::size_t k = 0; k < n; ++k) {
    const double* v = keys.values.data() + k * width;
    push(keys.times[k], v);
    if (k + 1 == n) break;
    const double t0 = keys.times[k], t1 = keys.times[k + 1], span = t1 - t0;
    if (keys.interpolation == Interpolation::kStep) {
      const double hold = t1 - 1e-4 * span;  // hold the value up to just before the next key
      if (hold > t0 && hold < t1) push(hold, v);
      continue;
    }
    const double* next = keys.values.data() + (k + 1) * width;
    for (int j = 1; j < kSamples; ++j) {
      const double s = static_cast<double>(j) / kSamples;
      const double s2 = s * s, s3 = s2 * s;
      const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
      for (std::size_t w = 0; w < width; ++w)
        sample[w] = h00 * v[w] + h10 * span * keys.out_tangents[k * width + w] + h01 * next[w] + h11 * span * keys.in_tangents[(k + 1) * width + w];
      if (rotation) {
        double norm = 0.0;
        for (double c : sample) norm += c * c;
        norm = std::sqrt(norm);
        if (norm > 0.0)
          for (double& c : sample) c /= norm;
      }
      const double t = t0 + s * span;
      if (t > out.times.back() && t < t1) push(t, sample.data());
    }
  }
  return out;
}

}  // namespace

Status Importer::read_channel(std::size_t a, std::size_t c, ClipKeys& out, std::size_t width, Path path) {
  const tinygltf::Animation& anim = m_.animations[a];
  const tinygltf::AnimationChannel& channel = anim.channels[c];
  const auto sampler_index = static_cast<std::size_t>(channel.sampler);
  const tinygltf::AnimationSampler& sampler = anim.samplers[sampler_index];
  const std::string sp = at(dot(at("animations", a), "samplers"), sampler_index);
  using ops::anim::Interpolation;
  out.interpolation = sampler.interpolation == "STEP" ? Interpolation::kStep
                      : sampler.interpolation == "CUBICSPLINE" ? Interpolation::kCubicSpline
                                                               : Interpolation::kLinear;
  const tinygltf::Accessor& input = m_.accessors[static_cast<std::size_t>(sampler.input)];
  if (input.type != TINYGLTF_TYPE_SCALAR || input.componentType != kFloat)
    return bad(dot(sp, "input"), accessor_summary(sampler.input) + "; SCALAR of FLOAT expected");
  auto times = read(sampler.input);
  if (!times) return times.status().with_context(dot(sp, "input"));
  out.times = **times;
  for (std::size_t k = 1; k < out.times.size(); ++k) {
    if (!(out.times[k] > out.times[k - 1]))
      return bad(dot(sp, "input"), "times not increasing at key " + std::to_string(k));
  }
  const tinygltf::Accessor& output = m_.accessors[static_cast<std::size_t>(sampler.output)];
  const std::string op = dot(sp, "output");
  const bool float_only = path == Path::kTranslation || path == Path::kScale;
  const int type = path == Path::kWeights ? TINYGLTF_TYPE_SCALAR : path == Path::kRotation ? TINYGLTF_TYPE_VEC4 : TINYGLTF_TYPE_VEC3;
  const bool type_ok = output.type == type && (output.componentType == kFloat ||
                                               (!float_only && output.normalized && output.componentType != kUnsignedInt));
  if (!type_ok)
    return bad(op, accessor_summary(sampler.output) + "; " + type_name(type) + " of FLOAT" + (float_only ? "" : " or normalized integers") +
                       " expected for " + gltf::path_name(path));
  const bool cubic = out.interpolation == Interpolation::kCubicSpline;
  const std::size_t per_key = path == Path::kWeights ? width : 1;
  const std::size_t expected = out.times.size() * per_key * (cubic ? 3 : 1);
  if (output.count != expected)
    return bad(op, "accessors[" + std::to_string(sampler.output) + "] has " + std::to_string(output.count) + " elements, " +
                       std::to_string(out.times.size()) + " keys need " + std::to_string(expected));
  auto values = read(sampler.output);
  if (!values) return values.status().with_context(op);
  const std::vector<double>& v = **values;
  const std::size_t keys = out.times.size();
  const double scale = path == Path::kTranslation ? options_.scale : 1.0;
  auto take = [&](std::vector<double>& dst, std::size_t key, std::size_t part) {
    // cubic: key k holds in-tangent, value, out-tangent, each `width` numbers
    const std::size_t base = (cubic ? (3 * key + part) : key) * width;
    for (std::size_t w = 0; w < width; ++w) dst.push_back(v[base + w] * scale);
  };
  for (std::size_t k = 0; k < keys; ++k) {
    take(out.values, k, 1);
    if (cubic) {
      take(out.in_tangents, k, 0);
      take(out.out_tangents, k, 2);
    }
    if (path == Path::kRotation) {
      const Quat q = quat_from_xyzw(out.values.data() + 4 * k);
      if (!(q.norm() >= 1e-6)) return bad(op, "key " + std::to_string(k) + " is not a rotation (a zero quaternion)");
    }
  }
  for (const std::vector<double>* list : {&out.values, &out.in_tangents, &out.out_tangents}) {
    for (double x : *list) {
      if (!std::isfinite(x)) return bad(op, "the translation overflows at this scale");
    }
  }
  return Status::ok();
}

Status Importer::read_animations() {
  std::map<std::pair<int, int>, std::size_t> index;  // (node, path) -> channels_ entry
  std::set<std::string> names;
  for (std::size_t a = 0; a < m_.animations.size(); ++a) {
    const tinygltf::Animation& anim = m_.animations[a];
    const std::string path = at("animations", a);
    clip_names_.push_back(unique_among(anim.name.empty() ? "animation_" + std::to_string(a) : anim.name, names));
    // The clip spans every key of the animation's samplers.
    double start = std::numeric_limits<double>::infinity(), end = -start;
    std::map<std::pair<int, int>, std::size_t> seen;  // in this animation: (node, path) -> channel
    for (std::size_t c = 0; c < anim.channels.size(); ++c) {
      const tinygltf::AnimationChannel& channel = anim.channels[c];
      if (channel.target_node < 0) continue;  // an extension's target
      const std::string cp = at(dot(path, "channels"), c);
      const std::string& name = channel.target_path;
      const Path what = name == "translation" ? Path::kTranslation
                        : name == "rotation"  ? Path::kRotation
                        : name == "scale"     ? Path::kScale
                                              : Path::kWeights;
      const auto node = static_cast<std::size_t>(channel.target_node);
      const std::pair<int, int> key{channel.target_node, static_cast<int>(what)};
      if (auto [it, fresh] = seen.emplace(key, c); !fresh)
        return bad(cp, "node " + std::to_string(node) + " " + name + " is also animated by channels[" + std::to_string(it->second) + "]");
      std::size_t width = what == Path::kRotation ? 4 : 3;
      if (what == Path::kWeights) {
        const int mesh = m_.nodes[node].mesh;
        width = mesh < 0 ? 0 : meshes_[static_cast<std::size_t>(mesh)].target_count;
        if (width == 0) return bad(dot(cp, "target"), "node " + std::to_string(node) + " has no morph targets to animate");
      }
      ClipKeys keys;
      if (Status s = read_channel(a, c, keys, width, what); !s) return s;
      auto [it, fresh] = index.emplace(key, channels_.size());
      if (fresh) channels_.push_back(Channel{channel.target_node, what, std::vector<std::optional<ClipKeys>>(m_.animations.size())});
      channels_[it->second].clips[a] = std::move(keys);
    }
    for (const tinygltf::AnimationSampler& sampler : anim.samplers) {
      // Times of unused samplers count too; an unreadable one fails here.
      const tinygltf::Accessor& input = m_.accessors[static_cast<std::size_t>(sampler.input)];
      if (input.type != TINYGLTF_TYPE_SCALAR || input.componentType != kFloat) continue;
      auto times = read(sampler.input);
      if (!times) return times.status().with_context(dot(path, "samplers"));
      for (double t : **times) {
        start = std::min(start, t);
        end = std::max(end, t);
      }
    }
    if (!(start <= end)) start = end = 0.0;
    clip_starts_.push_back(start);
    clip_ends_.push_back(end);
  }
  std::sort(channels_.begin(), channels_.end(), [](const Channel& x, const Channel& y) {
    return std::pair(x.node, static_cast<int>(x.path)) < std::pair(y.node, static_cast<int>(y.path));
  });
  return Status::ok();
}

Status Importer::build_track(const Channel& channel, NodeId clips) {
  using ops::anim::Interpolation;
  namespace ta = ops::anim::track_attr;
  Graph& g = scene_->graph();
  const bool rotation = channel.path == Path::kRotation;
  const std::size_t width = rotation ? 4 : 3;
  const auto node = static_cast<std::size_t>(channel.node);

  std::set<Interpolation> used;
  for (const auto& clip : channel.clips) {
    if (clip) used.insert(clip->interpolation);
  }
  Interpolation interpolation = *used.begin();
  if (used.size() > 1) {
    const bool exact_cubic = !rotation && !used.count(Interpolation::kStep);
    interpolation = exact_cubic ? Interpolation::kCubicSpline : Interpolation::kLinear;
  }
  std::vector<double> times;
  std::vector<double> values, in_tangents, out_tangents;
  std::vector<std::int64_t> offsets = {0};
  for (const auto& clip : channel.clips) {
    if (clip) {
      const ClipKeys keys = clip->interpolation == interpolation          ? *clip
                            : interpolation == Interpolation::kCubicSpline ? to_cubic(*clip, width)
                                                                           : to_linear(*clip, width, rotation);
      times.insert(times.end(), keys.times.begin(), keys.times.end());
      values.insert(values.end(), keys.values.begin(), keys.values.end());
      in_tangents.insert(in_tangents.end(), keys.in_tangents.begin(), keys.in_tangents.end());
      out_tangents.insert(out_tangents.end(), keys.out_tangents.begin(), keys.out_tangents.end());
    }
    offsets.push_back(static_cast<std::int64_t>(times.size()));
  }

  const std::string& owner = g.node(ids_[node])->name();
  const char* suffix = rotation ? "_rotate" : channel.path == Path::kScale ? "_scale" : "_translate";
  Result<NodeId> curve = g.create_node(rotation ? ops::anim::kAnimCurveQuatType : ops::anim::kAnimCurveVec3Type, owner + suffix);
  if (!curve) return curve.status();
  Status s;
  if (rotation) {
    auto quats = [](const std::vector<double>& v) {
      std::vector<Quat> out(v.size() / 4);
      for (std::size_t k = 0; k < out.size(); ++k) out[k] = quat_from_xyzw(v.data() + 4 * k);
      return out;
    };
    s = set(*curve, ta::kKeyValues, quats(values));
    if (s) s = set(*curve, ta::kInTangents, quats(in_tangents));
    if (s) s = set(*curve, ta::kOutTangents, quats(out_tangents));
    if (s) s = set(*curve, ta::kRestValue, rest_rotate_[node]);
  } else {
    auto vecs = [](const std::vector<double>& v) {
      std::vector<Vec3> out(v.size() / 3);
      for (std::size_t k = 0; k < out.size(); ++k) out[k] = Vec3(v[3 * k], v[3 * k + 1], v[3 * k + 2]);
      return out;
    };
    s = set(*curve, ta::kKeyValues, vecs(values));
    if (s) s = set(*curve, ta::kInTangents, vecs(in_tangents));
    if (s) s = set(*curve, ta::kOutTangents, vecs(out_tangents));
    if (s) s = set(*curve, ta::kRestValue, channel.path == Path::kScale ? rest_scale_[node] : rest_translate_[node]);
  }
  if (s) s = set(*curve, ta::kKeyTimes, std::move(times));
  if (s) s = set(*curve, ta::kInterpolation, std::int64_t{static_cast<std::int64_t>(interpolation)});
  if (s) s = set(*curve, ta::kClipOffsets, std::move(offsets));
  if (s) s = connect(clips, ops::anim::clips_attr::kActiveClip, *curve, ta::kClip);
  namespace x = scene::xform;
  const graph::AttrIndex target = rotation ? x::kRotateQuaternion : channel.path == Path::kScale ? x::kScale : x::kTranslate;
  if (s) s = connect(*curve, ta::kOutput, ids_[node], target);
  return s;
}

Status Importer::build_weight_curves(const Channel& channel, NodeId clips) {
  using ops::anim::Interpolation;
  using ops::anim::TangentType;
  namespace ca = ops::anim::curve_attr;
  namespace aa = ops::anim::anim_curve_attr;
  Graph& g = scene_->graph();
  const auto node = static_cast<std::size_t>(channel.node);
  if (blend_shapes_[node].empty()) return Status::ok();  // no surface to deform
  const tinygltf::Node& n = m_.nodes[node];
  const tinygltf::Mesh& mesh = m_.meshes[static_cast<std::size_t>(n.mesh)];
  const std::size_t targets = meshes_[static_cast<std::size_t>(n.mesh)].target_count;
  const std::string& owner = g.node(ids_[node])->name();
  bool any_cubic = false;
  for (const auto& clip : channel.clips) any_cubic |= clip && clip->interpolation == Interpolation::kCubicSpline;
  for (std::size_t t = 0; t < targets; ++t) {
    std::vector<double> times, values, in_slopes, out_slopes;
    std::vector<std::int64_t> in_types, out_types, offsets = {0};
    for (const auto& clip : channel.clips) {
      if (clip) {
        const TangentType type = clip->interpolation == Interpolation::kStep     ? TangentType::kStep
                                 : clip->interpolation == Interpolation::kLinear ? TangentType::kLinear
                                                                                 : TangentType::kFixed;
        for (std::size_t k = 0; k < clip->times.size(); ++k) {
          times.push_back(clip->times[k]);
          values.push_back(clip->values[k * targets + t]);
          in_types.push_back(static_cast<std::int64_t>(type));
          out_types.push_back(static_cast<std::int64_t>(type));
          const bool cubic = clip->interpolation == Interpolation::kCubicSpline;
          in_slopes.push_back(cubic ? clip->in_tangents[k * targets + t] : 0.0);
          out_slopes.push_back(cubic ? clip->out_tangents[k * targets + t] : 0.0);
        }
      }
      offsets.push_back(static_cast<std::int64_t>(times.size()));
    }
    if (!any_cubic) {  // no fixed tangents: the slope arrays stay empty
      in_slopes.clear();
      out_slopes.clear();
    }
    const double rest = !n.weights.empty() ? n.weights[t] : !mesh.weights.empty() ? mesh.weights[t] : 0.0;
    Result<NodeId> curve = g.create_node(ops::anim::kAnimCurveType, owner + "_weight" + std::to_string(t));
    if (!curve) return curve.status();
    Status s = set(*curve, ca::kKeyTimes, std::move(times));
    if (s) s = set(*curve, ca::kKeyValues, std::move(values));
    if (s) s = set(*curve, ca::kInTangentType, std::move(in_types));
    if (s) s = set(*curve, ca::kOutTangentType, std::move(out_types));
    if (s) s = set(*curve, ca::kInSlope, std::move(in_slopes));
    if (s) s = set(*curve, ca::kOutSlope, std::move(out_slopes));
    if (s) s = set(*curve, aa::kClipOffsets, std::move(offsets));
    if (s) s = set(*curve, aa::kRestValue, rest);
    if (s) s = connect(clips, ops::anim::clips_attr::kActiveClip, *curve, aa::kClip);
    for (NodeId shape : blend_shapes_[node]) {
      if (s) s = connect(*curve, ca::kOutput, shape, ops::blend_shape_attr::kWeights, static_cast<std::int32_t>(t));
    }
    if (!s) return s;
  }
  return Status::ok();
}

Status Importer::build_animations() {
  if (m_.animations.empty()) return Status::ok();
  Graph& g = scene_->graph();
  namespace ka = ops::anim::clips_attr;
  Result<NodeId> clips = g.create_node(ops::anim::kAnimClipsType, "clips");
  if (!clips) return clips.status();
  Status s = set(*clips, ka::kClipNames, clip_names_);
  if (s) s = set(*clips, ka::kClipStarts, clip_starts_);
  if (s) s = set(*clips, ka::kClipEnds, clip_ends_);
  if (s) s = set(*clips, ka::kActive, std::int64_t{0});
  if (!s) return s.with_context("animations");
  for (const Channel& channel : channels_) {
    const std::string where = "nodes[" + std::to_string(channel.node) + "]." + gltf::path_name(channel.path) + " animation";
    s = channel.path == Path::kWeights ? build_weight_curves(channel, *clips) : build_track(channel, *clips);
    if (!s) return s.with_context(where);
  }
  return Status::ok();
}

}  // namespace rigel::io::gltf_importer
