#include "rigel/ops/util/spring.h"

#include <cmath>
#include <string>
#include <utility>

#include "rigel/graph/graph.h"

namespace rigel::ops::util {
namespace {

using graph::AttrType;
using graph::ComputeContext;
using graph::ValueType;
using math::Mat4;
using math::Quat;
using math::Vec3;

constexpr int kSubSteps = 4;
// A time within this many frames of a whole frame is that frame.
constexpr double kFrameTolerance = 1e-9;

Vec3 position_of(const Mat4& m) { return m.topRightCorner<3, 1>(); }

struct SpringFrame {
  std::vector<Vec3> goals;  // the inputs the frame was stepped with
  SpringParams params;
  SpringState state;
};

bool same(const SpringFrame& f, const std::vector<Vec3>& goals, const SpringParams& p) {
  return f.goals == goals && f.params.stiffness == p.stiffness && f.params.damping == p.damping &&
         f.params.gravity == p.gravity;
}

// Every frame stepped since startTime, while fps, startTime and the
// chain's length stay what they were.
struct SpringCache : graph::NodeCache {
  double start = 0, fps = 0;
  std::size_t count = 0;
  std::vector<SpringFrame> frames;
};

std::string problem_of(const std::vector<Mat4>& goals, double start, double fps, const SpringParams& p) {
  if (goals.size() < 2) return "goalMatrix: a chain of 2 or more joints, got " + std::to_string(goals.size());
  for (std::size_t i = 0; i < goals.size(); ++i)
    if (!goals[i].allFinite()) return "goalMatrix[" + std::to_string(i) + "]: not finite";
  if (!std::isfinite(start)) return "startTime: not finite";
  if (!(fps > 0.0) || !std::isfinite(fps)) return "fps: must be a number above 0";
  if (!(p.stiffness >= 0.0) || !std::isfinite(p.stiffness)) return "stiffness: must be a number from 0";
  if (!(p.damping >= 0.0) || !std::isfinite(p.damping)) return "damping: must be a number from 0";
  if (!p.gravity.allFinite()) return "gravity: not finite";
  return {};
}

void compute_spring(ComputeContext& c) {
  namespace a = spring_attr;
  const auto& goal_worlds = c.get<std::vector<Mat4>>(a::kGoalMatrix);
  auto& out = std::get<std::vector<Mat4>>(c.output(a::kOutWorldMatrices));
  auto& error = std::get<std::string>(c.output(a::kError));
  const double start = c.get<double>(a::kStartTime), fps = c.get<double>(a::kFps);
  const SpringParams params{c.get<double>(a::kStiffness), c.get<double>(a::kDamping), c.get<Vec3>(a::kGravity)};
  SpringCache& cache = c.cache<SpringCache>();
  out = goal_worlds;
  error = problem_of(goal_worlds, start, fps, params);
  const double s = (c.time() - start) * fps;  // frames since startTime
  if (error.empty() && s > static_cast<double>(kMaxSpringFrames))
    error = "time: more than " + std::to_string(kMaxSpringFrames) + " frames after startTime";
  if (!error.empty()) {
    cache.frames.clear();
    return;
  }
  std::vector<Vec3> goals(goal_worlds.size());
  for (std::size_t i = 0; i < goals.size(); ++i) goals[i] = position_of(goal_worlds[i]);
  if (cache.start != start || cache.fps != fps || cache.count != goals.size()) {
    cache.frames.clear();
    cache.start = start;
    cache.fps = fps;
    cache.count = goals.size();
  }
  // At and before startTime the chain rests on its goal.
  if (!(s > kFrameTolerance)) {
    cache.frames.assign(1, SpringFrame{goals, params, spring_rest(goals)});
    return;
  }
  if (cache.frames.empty()) cache.frames.push_back(SpringFrame{goals, params, spring_rest(goals)});
  auto want = static_cast<std::size_t>(std::floor(s + kFrameTolerance));
  double frac = s - static_cast<double>(want);
  if (frac < kFrameTolerance) frac = 0.0;
  // A frame stepped with other inputs (an edit) is stepped again.
  if (frac == 0.0 && want > 0 && want < cache.frames.size() && !same(cache.frames[want], goals, params))
    cache.frames.resize(want);
  const double dt = 1.0 / fps;
  const std::size_t last = cache.frames.size() - 1;
  if (want > last) {
    // The frames in between take the inputs interpolated from the last
    // frame's to these (which the frame asked for takes exactly when whole).
    const std::vector<Vec3> from = cache.frames[last].goals;
    const SpringParams p0 = cache.frames[last].params;
    const double span = static_cast<double>(want - last) + frac;
    cache.frames.reserve(want + 1);
    for (std::size_t j = last + 1; j <= want; ++j) {
      SpringFrame f;
      if (j == want && frac == 0.0) {
        f.goals = goals;
        f.params = params;
      } else {
        const double w = static_cast<double>(j - last) / span;
        f.goals.resize(goals.size());
        for (std::size_t i = 0; i < goals.size(); ++i) f.goals[i] = from[i] + (goals[i] - from[i]) * w;
        f.params.stiffness = p0.stiffness + (params.stiffness - p0.stiffness) * w;
        f.params.damping = p0.damping + (params.damping - p0.damping) * w;
        f.params.gravity = p0.gravity + (params.gravity - p0.gravity) * w;
      }
      f.state = cache.frames[j - 1].state;
      spring_step(f.params, f.goals, dt, f.state);
      cache.frames.push_back(std::move(f));
    }
  }
  SpringState state = cache.frames[want].state;
  if (frac > 0.0) spring_step(params, goals, frac * dt, state);
  spring_worlds(goal_worlds, state, out);
}

}  // namespace

SpringState spring_rest(std::span<const Vec3> goals) {
  SpringState s;
  s.position.assign(goals.begin(), goals.end());
  s.velocity.assign(goals.size(), Vec3::Zero());
  return s;
}

void spring_step(const SpringParams& params, std::span<const Vec3> goals, double dt, SpringState& state) {
  const std::size_t n = goals.size();
  state.position.resize(n, Vec3::Zero());
  state.velocity.resize(n, Vec3::Zero());
  if (n == 0) return;
  const double h = dt / kSubSteps;
  for (int sub = 0; sub < kSubSteps; ++sub) {
    state.position[0] = goals[0];
    state.velocity[0] = Vec3::Zero();
    for (std::size_t i = 1; i < n; ++i) {
      const Vec3 accel = params.stiffness * (goals[i] - state.position[i]) - params.damping * state.velocity[i] +
                         params.gravity;
      state.velocity[i] += accel * h;
      state.position[i] += state.velocity[i] * h;
    }
    // Each particle back at its bone's length from the one before; the
    // velocity takes the correction (position-based), so nothing gains energy.
    for (std::size_t i = 1; i < n; ++i) {
      const double length = (goals[i] - goals[i - 1]).norm();
      const Vec3 d = state.position[i] - state.position[i - 1];
      const double now = d.norm();
      const Vec3 at = now > 1e-12 ? Vec3(state.position[i - 1] + d * (length / now))
                                  : Vec3(state.position[i - 1] + (goals[i] - goals[i - 1]));
      if (h > 0.0) state.velocity[i] += (at - state.position[i]) / h;
      state.position[i] = at;
    }
  }
}

void spring_worlds(std::span<const Mat4> goals, const SpringState& state, std::vector<Mat4>& out) {
  const std::size_t n = goals.size();
  out.assign(goals.begin(), goals.end());
  Quat turn = Quat::Identity();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 at = i == 0 || i >= state.position.size() ? position_of(goals[i]) : state.position[i];
    if (i + 1 < n && i + 1 < state.position.size()) {
      const Vec3 rest = position_of(goals[i + 1]) - position_of(goals[i]);
      const Vec3 now = state.position[i + 1] - at;
      turn = rest == now || rest.norm() < 1e-12 || now.norm() < 1e-12 ? Quat::Identity()
                                                                        : Quat::FromTwoVectors(rest, now);
    }
    out[i].topLeftCorner<3, 3>() = turn.toRotationMatrix() * goals[i].topLeftCorner<3, 3>();
    out[i].topRightCorner<3, 1>() = at;
  }
}

Status register_spring_types(graph::Registry& registry) {
  const std::vector<std::string> outs = {"outWorldMatrices", "error"};
  graph::NodeTypeSpec spec;
  spec.name = kSpringChainType;
  spec.description = "Secondary motion: a chain's joints follow its goal pose on damped springs, stepped per frame";
  spec.attrs = {
      graph::input_attr("goalMatrix", {ValueType::kMatrix, true}, std::vector<Mat4>{}, outs),
      graph::input_attr("startTime", {ValueType::kDouble, false}, 0.0, outs),
      graph::input_attr("fps", {ValueType::kDouble, false}, 24.0, outs),
      graph::input_attr("stiffness", {ValueType::kDouble, false}, 100.0, outs, graph::kKeyable),
      graph::input_attr("damping", {ValueType::kDouble, false}, 10.0, outs, graph::kKeyable),
      graph::input_attr("gravity", {ValueType::kDouble3, false}, Vec3(Vec3::Zero()), outs, graph::kKeyable),
      graph::output_attr("outWorldMatrices", {ValueType::kMatrix, true}),
      graph::output_attr("error", {ValueType::kString, false}, graph::kHidden)};
  spec.compute = compute_spring;
  spec.time_dependent = true;
  return registry.add(std::move(spec));
}

}  // namespace rigel::ops::util
