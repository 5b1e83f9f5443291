// The glTF exporter: animation sampled frame by frame (and at every key time
// between), for what the curves' own keys cannot say; time and the active
// clip are put back afterwards.
#include "gltf_exporter.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>

#include "rigel/ops/anim/nodes.h"
#include "rigel/ops/deform/nodes.h"

namespace rigel::io::gltf_exporter {

Result<std::vector<double>> Exporter::frame_times(double first, double last) const {
  if ((last - first) > kMaxFrames)
    return error(ErrorCode::kInvalidArgument, "frames " + number(first) + ":" + number(last) + ": more than " +
                                                  number(kMaxFrames) + " frames to bake");
  std::vector<double> times;
  const double fps = g_.fps();
  for (double f = first; f <= last + 1e-9; f += 1.0) times.push_back(f / fps);
  if (times.empty() || times.back() < last / fps - 1e-9 / fps) times.push_back(last / fps);
  // glTF times are 32-bit floats and must increase: a last frame a
  // fraction past a whole one replaces it when the two round together.
  for (std::size_t k = times.size() - 1; k > 0; --k)
    if (static_cast<float>(times[k]) <= static_cast<float>(times[k - 1])) times.erase(times.begin() + static_cast<std::ptrdiff_t>(k) - 1);
  return times;
}

std::pair<double, double> Exporter::key_range() {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (NodeId id : g_.nodes()) {
    const std::string& type = type_of(g_, id);
    if (type != anim::kAnimCurveType && type != anim::kAnimCurveVec3Type && type != anim::kAnimCurveQuatType) continue;
    const auto& times = std::get<std::vector<double>>(g_.node(id)->value(0));  // keyTimes, first in both layouts
    for (double t : times) {
      if (!std::isfinite(t)) continue;
      lo = std::min(lo, t);
      hi = std::max(hi, t);
    }
  }
  if (lo > hi) return {0.0, 0.0};
  const double fps = g_.fps();
  const double first = std::max(0.0, std::floor(lo * fps + 1e-9));
  return {first, std::max(first, std::ceil(hi * fps - 1e-9))};
}

std::vector<double> Exporter::key_times() const {
  std::vector<double> keys;
  for (NodeId id : g_.nodes()) {
    const std::string& type = type_of(g_, id);
    if (type != anim::kAnimCurveType && type != anim::kAnimCurveVec3Type && type != anim::kAnimCurveQuatType) continue;
    const auto& times = std::get<std::vector<double>>(g_.node(id)->value(0));  // keyTimes, first in both layouts
    for (double t : times)
      if (std::isfinite(t)) keys.push_back(t);
  }
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  return keys;
}

void Exporter::add_key_times(std::vector<double>& times, const std::vector<double>& keys) {
  if (times.empty()) return;
  const double first = times.front(), last = times.back();
  const auto begin = std::lower_bound(keys.begin(), keys.end(), first);
  const auto end = std::upper_bound(keys.begin(), keys.end(), last);
  if (begin == end) return;
  std::vector<double> merged;
  merged.reserve(times.size() + static_cast<std::size_t>(end - begin));
  std::merge(times.begin(), times.end(), begin, end, std::back_inserter(merged));
  merged.erase(std::unique(merged.begin(), merged.end(),
                           [](double x, double y) { return static_cast<float>(x) == static_cast<float>(y); }),
               merged.end());
  times = std::move(merged);
}

Status Exporter::bake_all() {
  std::vector<BakeJob> jobs;
  const double fps = g_.fps();
  if (options_.frames) {
    Result<std::vector<double>> times = frame_times(options_.frames->first, options_.frames->second);
    if (!times) return times.status();
    const int active = clips_.clips.empty() ? -1 : clips_.active;
    jobs.push_back({animation_name(active), -1, std::move(*times)});
    report_.first_frame = options_.frames->first;
    report_.last_frame = options_.frames->second;
  } else if (!clips_.clips.empty()) {
    for (std::size_t c = 0; c < clips_.clips.size(); ++c) {
      Result<std::vector<double>> times = frame_times(clips_.clips[c].start * fps, clips_.clips[c].end * fps);
      if (!times) return times.status();
      jobs.push_back({clips_.clips[c].name, static_cast<int>(c), std::move(*times)});
    }
    report_.first_frame = clips_.clips.front().start * fps;
    report_.last_frame = clips_.clips.front().end * fps;
  } else {
    const auto [first, last] = key_range();
    Result<std::vector<double>> times = frame_times(first, last);
    if (!times) return times.status();
    jobs.push_back({"animation", -1, std::move(*times)});
    report_.first_frame = first;
    report_.last_frame = last;
  }
  const std::vector<double> keys = key_times();
  for (BakeJob& job : jobs) add_key_times(job.times, keys);
  std::size_t total = 0, done = 0;
  for (const BakeJob& job : jobs) total += job.times.size();

  // Baking moves time and switches clips; both are put back afterwards
  // (the clip switch is rolled back, so it leaves no undo step).
  const double saved_time = g_.time();
  graph::Transaction transaction(g_, "export glTF (bake)");
  Status status;
  for (const BakeJob& job : jobs) {
    if (job.clip >= 0) {
      status = g_.set_value(Plug{clips_.node, anim::clips_attr::kActive, -1}, std::int64_t{job.clip});
      if (!status) break;
    }
    status = bake(job, done, total);
    if (!status) break;
  }
  transaction.rollback();
  g_.set_time(saved_time);
  g_.evaluate_all();
  return status;
}

Status Exporter::bake(const BakeJob& job, std::size_t& done, std::size_t total) {
  const std::size_t frames = job.times.size();
  const std::size_t count = nodes_.size();
  std::vector<Vec3> translate(frames * count), scale(frames * count);
  std::vector<Quat> rotate(frames * count);
  std::vector<bool> sheared(count, false);
  std::vector<std::vector<double>> weights(meshes_.size());
  std::vector<Mat4> local(skeleton_.size()), world(skeleton_.size());
  Placement placement(count);
  for (std::size_t f = 0; f < frames; ++f) {
    g_.set_time(job.times[f]);
    g_.evaluate_all();
    if (Status s = skeleton_.evaluate(scene_, local, world); !s) return s;
    if (Status s = check_skinned_placement(world); !s) return s;
    for (std::size_t i = 0; i < count; ++i) {
      const ExportNode& n = nodes_[i];
      math::Decomposed d = place(i, local, world, placement);
      if (d.shear.cwiseAbs().maxCoeff() > kShearTolerance) sheared[i] = true;
      Quat q = d.rotation.normalized();
      const Quat& previous = f > 0 ? rotate[(f - 1) * count + i] : n.rest.rotation;
      if (previous.dot(q) < 0.0) q.coeffs() *= -1.0;  // keep the sign continuous
      translate[f * count + i] = d.translate;
      rotate[f * count + i] = q;
      scale[f * count + i] = d.scale;
    }
    for (std::size_t m = 0; m < meshes_.size(); ++m) {
      const MeshExport& mesh = meshes_[m];
      if (mesh.targets.empty()) continue;
      const auto& w = value_as<std::vector<double>>(g_, mesh.blend, ops::blend_shape_attr::kWeights);
      for (std::size_t t = 0; t < mesh.targets.size(); ++t) weights[m].push_back(t < w.size() ? w[t] : 0.0);
    }
    ++done;
    if (options_.progress) options_.progress(static_cast<double>(done) / static_cast<double>(total));
  }

  AnimationExport a;
  a.name = job.name;
  auto channel = [&](std::size_t node, Path path) {
    Channel ch;
    ch.node = static_cast<int>(node);
    ch.path = path;
    ch.times = job.times;
    return ch;
  };
  for (std::size_t i = 0; i < count; ++i) {
    const ExportNode& n = nodes_[i];
    bool moved_t = false, moved_r = false, moved_s = false;
    for (std::size_t f = 0; f < frames; ++f) {
      moved_t = moved_t || !near_vec(translate[f * count + i], n.rest.translate, kConstantTolerance);
      moved_r = moved_r || !near_quat(rotate[f * count + i], n.rest.rotation, kConstantTolerance);
      moved_s = moved_s || !near_vec(scale[f * count + i], n.rest.scale, kConstantTolerance);
    }
    if (moved_t) {
      Channel ch = channel(i, Path::kTranslation);
      for (std::size_t f = 0; f < frames; ++f) {
        const Vec3& v = translate[f * count + i];
        ch.values.insert(ch.values.end(), {v.x(), v.y(), v.z()});
      }
      a.channels.push_back(std::move(ch));
    }
    if (moved_r) {
      Channel ch = channel(i, Path::kRotation);
      for (std::size_t f = 0; f < frames; ++f) {
        const Quat& q = rotate[f * count + i];
        ch.values.insert(ch.values.end(), {q.x(), q.y(), q.z(), q.w()});
      }
      a.channels.push_back(std::move(ch));
    }
    if (moved_s) {
      Channel ch = channel(i, Path::kScale);
      for (std::size_t f = 0; f < frames; ++f) {
        const Vec3& v = scale[f * count + i];
        ch.values.insert(ch.values.end(), {v.x(), v.y(), v.z()});
      }
      a.channels.push_back(std::move(ch));
    }
    if (sheared[i] && (moved_t || moved_r || moved_s))
      report_.notes.push_back(name(n.id) + ": shear is left out of its baked animation (glTF animates "
                                           "translation, rotation and scale only)");
  }
  for (std::size_t m = 0; m < meshes_.size(); ++m) {
    const MeshExport& mesh = meshes_[m];
    if (mesh.targets.empty()) continue;
    bool moved = false;
    for (std::size_t k = 0; k < weights[m].size(); ++k)
      moved = moved || std::abs(weights[m][k] - mesh.weights[k % mesh.targets.size()]) > kConstantTolerance;
    if (!moved) continue;
    Channel ch = channel(mesh.node, Path::kWeights);
    ch.values = std::move(weights[m]);
    a.channels.push_back(std::move(ch));
  }
  if (!a.channels.empty()) animations_.push_back(std::move(a));
  return Status::ok();
}

}  // namespace rigel::io::gltf_exporter
