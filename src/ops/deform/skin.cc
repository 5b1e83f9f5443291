#include "rigel/ops/deform/skin.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

namespace rigel::ops {
namespace {

// Collects the problems of one build: the first kShown in full, then a count,
// so one message reports a file's problems rather than only its first.
class Problems {
 public:
  static constexpr std::size_t kShown = 8;

  void add(std::string message) {
    if (count_ < kShown) {
      if (!text_.empty()) text_ += "; ";
      text_ += message;
    }
    ++count_;
  }
  bool empty() const { return count_ == 0; }
  Status status() const {
    std::string message = text_;
    if (count_ > kShown) message += "; and " + std::to_string(count_ - kShown) + " more";
    if (count_ > 1) message = std::to_string(count_) + " problems in skin weights: " + message;
    return Status(ErrorCode::kInvalidArgument, message);
  }

 private:
  std::string text_;
  std::size_t count_ = 0;
};

std::string number(double value) {
  if (std::isnan(value)) return "NaN";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.17g", value);
  return buffer;
}

Status check_shape(const SkinInfluenceView& in, const SkinBuildOptions& options) {
  if (options.joint_count > kMaxSkinJoints) {
    return Status(ErrorCode::kInvalidArgument, "joint_count " + std::to_string(options.joint_count) +
                                                   " exceeds the skin limit of " + std::to_string(kMaxSkinJoints));
  }
  if (in.joints.size() != in.weights.size()) {
    return Status(ErrorCode::kInvalidArgument, "influence joints (" + std::to_string(in.joints.size()) +
                                                   ") and weights (" + std::to_string(in.weights.size()) +
                                                   ") differ in length");
  }
  if (in.offsets.empty()) {
    return Status(ErrorCode::kInvalidArgument, "influence offsets must have vertex_count + 1 entries (at least 1)");
  }
  if (in.offsets.front() != 0) {
    return Status(ErrorCode::kInvalidArgument,
                  "influence offsets must start at 0, not " + std::to_string(in.offsets.front()));
  }
  for (std::size_t v = 0; v + 1 < in.offsets.size(); ++v) {
    if (in.offsets[v + 1] < in.offsets[v]) {
      return Status(ErrorCode::kInvalidArgument, "influence offsets decrease at vertex " + std::to_string(v) + " (" +
                                                     std::to_string(in.offsets[v]) + " then " +
                                                     std::to_string(in.offsets[v + 1]) + ")");
    }
  }
  if (static_cast<std::uint64_t>(in.offsets.back()) != in.joints.size()) {
    return Status(ErrorCode::kInvalidArgument, "influence offsets end at " + std::to_string(in.offsets.back()) +
                                                   ", not at the number of influences (" +
                                                   std::to_string(in.joints.size()) + ")");
  }
  if (in.joints.size() > std::numeric_limits<std::uint32_t>::max()) {
    return Status(ErrorCode::kInvalidArgument, "a skin holds at most 2^32 - 1 influences");
  }
  return Status::ok();
}

}  // namespace

Result<Skin> build_skin(const SkinInfluenceView& in, const SkinBuildOptions& options, SkinBuildReport* report) {
  if (Status s = check_shape(in, options); !s) return s;
  const std::size_t vertex_count = in.offsets.size() - 1;
  const auto joint_count = static_cast<std::int64_t>(options.joint_count);

  // Pass 1: every problem, so one message covers the whole input. A joint
  // index is checked only where its weight is non-zero: glTF pads unused
  // slots with weight 0, and such a slot never reads a matrix.
  Problems problems;
  for (std::size_t v = 0; v < vertex_count; ++v) {
    const auto begin = static_cast<std::size_t>(in.offsets[v]);
    const auto end = static_cast<std::size_t>(in.offsets[v + 1]);
    // Messages are built only on failure: this loop runs over every
    // influence of every build.
    auto where = [v] { return "vertex " + std::to_string(v); };
    auto slot = [&](std::size_t i) { return where() + " influence " + std::to_string(i - begin); };
    double sum = 0.0;
    bool any = false;
    bool bad = false;
    for (std::size_t i = begin; i < end; ++i) {
      const double w = in.weights[i];
      if (!std::isfinite(w)) {
        problems.add(slot(i) + ": weight " + number(w) + " is not finite");
        bad = true;
      } else if (w < 0.0) {
        problems.add(slot(i) + ": weight " + number(w) + " is negative");
        bad = true;
      } else if (w > 0.0) {
        any = true;
        sum += w;
        if (in.joints[i] < 0 || in.joints[i] >= joint_count) {
          problems.add(slot(i) + ": joint " + std::to_string(in.joints[i]) + " is out of range (the skin has " +
                       std::to_string(options.joint_count) + " joints)");
          bad = true;
        }
      }
    }
    if (bad) continue;
    if (!any) {
      problems.add(where() + ": no influence with a non-zero weight");
    } else if (!std::isfinite(sum)) {
      problems.add(where() + ": weights sum to infinity");
    }
  }
  if (!problems.empty()) return problems.status();

  // Pass 2: compile. Zero weights go, repeated joints merge (w1 M + w2 M =
  // (w1 + w2) M), sums are taken in double and weights rounded to float once.
  Skin skin;
  SkinBuildReport local;
  SkinBuildReport& out = report ? *report : local;
  out = SkinBuildReport{};
  skin.joint_count_ = options.joint_count;
  skin.offsets_.reserve(vertex_count + 1);
  skin.offsets_.push_back(0);
  skin.joints_.reserve(in.joints.size());
  skin.weights_.reserve(in.weights.size());
  std::vector<SkinInfluence> scratch;
  for (std::size_t v = 0; v < vertex_count; ++v) {
    scratch.clear();
    for (auto i = static_cast<std::size_t>(in.offsets[v]); i < static_cast<std::size_t>(in.offsets[v + 1]); ++i) {
      const double w = in.weights[i];
      if (w == 0.0) {
        ++out.dropped_zero_weights;
        continue;
      }
      auto same =
          std::find_if(scratch.begin(), scratch.end(), [&](const SkinInfluence& e) { return e.joint == in.joints[i]; });
      if (same != scratch.end()) {
        same->weight += w;
        ++out.merged_duplicates;
      } else {
        scratch.push_back({in.joints[i], w});
      }
    }
    double sum = 0.0;
    for (const SkinInfluence& e : scratch) sum += e.weight;
    const double deviation = std::abs(sum - 1.0);
    out.largest_deviation = std::max(out.largest_deviation, deviation);
    if (deviation > options.report_tolerance) out.renormalized.push_back({static_cast<std::uint32_t>(v), sum});
    const double scale = options.normalize ? 1.0 / sum : 1.0;
    for (const SkinInfluence& e : scratch) {
      skin.joints_.push_back(static_cast<std::uint16_t>(e.joint));
      skin.weights_.push_back(static_cast<float>(e.weight * scale));
    }
    skin.offsets_.push_back(static_cast<std::uint32_t>(skin.joints_.size()));
    out.max_influences = std::max(out.max_influences, scratch.size());
  }
  skin.max_influences_ = out.max_influences;

  if (options.fixed_layout && out.max_influences <= kFixedInfluences) {
    skin.fixed_ = true;
    skin.fixed_joints_.resize(vertex_count * kFixedInfluences);
    skin.fixed_weights_.assign(vertex_count * kFixedInfluences, 0.0f);
    for (std::size_t v = 0; v < vertex_count; ++v) {
      const std::uint32_t begin = skin.offsets_[v];
      const std::uint32_t count = skin.offsets_[v + 1] - begin;
      for (std::size_t k = 0; k < kFixedInfluences; ++k) {
        const bool real = k < count;
        skin.fixed_joints_[v * kFixedInfluences + k] = skin.joints_[begin + (real ? k : 0)];
        if (real) skin.fixed_weights_[v * kFixedInfluences + k] = skin.weights_[begin + k];
      }
    }
  }
  return skin;
}

Result<Skin> make_skin(std::span<const std::vector<SkinInfluence>> vertices, std::size_t joint_count,
                       const SkinBuildOptions& options, SkinBuildReport* report) {
  SkinBuilder builder(joint_count);
  builder.options() = options;
  builder.options().joint_count = joint_count;
  for (const std::vector<SkinInfluence>& v : vertices) builder.add_vertex(v);
  return builder.build(report);
}

SkinBuilder& SkinBuilder::add_vertex(std::span<const SkinInfluence> influences) {
  for (const SkinInfluence& e : influences) {
    joints_.push_back(e.joint);
    weights_.push_back(e.weight);
  }
  offsets_.push_back(static_cast<std::int64_t>(joints_.size()));
  return *this;
}

SkinBuilder& SkinBuilder::add_vertices(std::span<const std::int64_t> joints, std::span<const double> weights,
                                       std::size_t per_vertex) {
  if (per_vertex == 0) return *this;
  const std::size_t count = std::min(joints.size(), weights.size()) / per_vertex;
  for (std::size_t v = 0; v < count; ++v) {
    for (std::size_t k = 0; k < per_vertex; ++k) {
      joints_.push_back(joints[v * per_vertex + k]);
      weights_.push_back(weights[v * per_vertex + k]);
    }
    offsets_.push_back(static_cast<std::int64_t>(joints_.size()));
  }
  return *this;
}

}  // namespace rigel::ops
