#pragma once
// springChain: secondary motion for a joint chain (a tail, antenna, ears,
// hair): each joint after the root is a particle pulled toward where the
// chain's goal pose puts it by a damped spring, with gravity, and kept at
// its bone length from the one before; the goal pose turned so each bone
// points at its next particle gives the chain's world matrices.
//
// Deterministic and bakeable: the simulation steps at whole frames (fps
// steps per second, each in four equal sub-steps of semi-implicit Euler)
// from startTime, where the chain rests on its goal. The state of every
// frame reached is kept (the node's cache) with the inputs it was stepped
// with, so playing, scrubbing back over frames already played and baking
// all give the values a playback from startTime gives. Reaching a frame
// beyond the last one stepped steps every frame in between, with the
// inputs interpolated linearly from the last frame's to the current ones.
// A frame whose inputs differ from those recorded (an edited key) is
// stepped again from the frame before, and the frames after it dropped.
// Between frames the state is the frame's stepped on by the fraction.
// Changing fps or startTime (or the chain's length) starts over.
//
// Inputs:
//   goalMatrix   matrix[]  the chain's goal pose, root first (world; the FK
//                          controls' worlds): 2 or more
//   startTime    double    seconds: the chain rests on its goal here and before
//   fps          double    steps per second (> 0)
//   stiffness    double    keyable, >= 0: the spring's pull, 1/s^2
//   damping      double    keyable, >= 0: 1/s
//   gravity      double3   keyable, m/s^2 (world)
// Outputs: outWorldMatrices (matrix[]), error (hidden string). Inputs out
// of range give the goal pose and say so in `error`; more than
// kMaxSpringFrames frames from startTime too.

#include <span>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/graph/node_type.h"
#include "rigel/math/types.h"

namespace rigel::ops::util {

inline constexpr const char* kSpringChainType = "springChain";
inline constexpr std::int64_t kMaxSpringFrames = 1'000'000;

namespace spring_attr {
enum : graph::AttrIndex {
  kGoalMatrix = 0,
  kStartTime,
  kFps,
  kStiffness,
  kDamping,
  kGravity,
  kOutWorldMatrices,
  kError,
  kCount
};
}  // namespace spring_attr

struct SpringParams {
  double stiffness = 100.0;
  double damping = 10.0;
  math::Vec3 gravity = math::Vec3::Zero();
};

// Particle positions and velocities, one per joint (the root's follow its goal).
struct SpringState {
  std::vector<math::Vec3> position, velocity;
};

// The state at rest on `goals` (positions, no velocity).
SpringState spring_rest(std::span<const math::Vec3> goals);

// Steps `state` by `dt` seconds (four sub-steps) toward `goals`, the bones'
// lengths taken from the goals.
void spring_step(const SpringParams& params, std::span<const math::Vec3> goals, double dt, SpringState& state);

// The chain's world matrices: goal i turned about its own position so its
// bone points at particle i + 1, moved to particle i; the tip turned as its
// parent.
void spring_worlds(std::span<const math::Mat4> goals, const SpringState& state, std::vector<math::Mat4>& out);

// Adds springChain (called by register_util_types).
Status register_spring_types(graph::Registry& registry);

}  // namespace rigel::ops::util
