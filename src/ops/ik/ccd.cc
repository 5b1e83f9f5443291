#include "rigel/ops/ik/ccd.h"

#include <cmath>

#include "ik_math.h"

namespace rigel::ops::ik {

using detail::normalize_in_place;
using detail::translation;

bool CcdJob::validate() const {
  return detail::valid_chain_job(world, positions, corrections, limits, parent_world, target, tolerance,
                                 max_iterations);
}

namespace {

Vec3 rest_bone(std::span<const Mat4> world, std::size_t i) { return translation(world[i + 1]) - translation(world[i]); }

// While solving, corrections[i] holds joint i's turn relative to its
// parent's: world-space turn W_i = W_{i-1} * relative[i] (W_{-1} = identity).
// A world-space rotation g at joint i changes only relative[i] (to
// W_{i-1}^-1 * g * W_i); its descendants' relative turns stay, so a sweep
// costs O(N), not O(N^2).

// Positions from the relative turns: each bone is its input vector turned
// by its joint, so lengths stay exact however many sweeps ran.
RIGEL_IK_MULTIVERSION void rebuild_positions(std::span<const Mat4> world, Vec3* p, Quat* relative) {
  const std::size_t last = world.size() - 1;
  p[0] = translation(world[0]);
  Quat turn = Quat::Identity();
  for (std::size_t i = 0; i < last; ++i) {
    relative[i].normalize();
    turn = turn * relative[i];
    p[i + 1] = p[i] + turn * rest_bone(world, i);
  }
}

// The parent's frame after its turns: W_{i-1} * R_{i-1} (parent_world's
// frame for joint 0).
Mat3 parent_frame_of(std::span<const Mat4> world, std::size_t i, const Quat& parent_turn, const Mat3& root_frame) {
  return i == 0 ? root_frame : Mat3(parent_turn.toRotationMatrix() * detail::rotation_frame(world[i - 1]));
}

}  // namespace

RIGEL_IK_MULTIVERSION bool CcdJob::run() const {
  if (!validate()) return false;
  const std::size_t count = world.size();
  const std::size_t last = count - 1;
  Vec3* p = positions.data();
  Quat* relative = corrections.data();
  for (std::size_t i = 0; i < count; ++i) {
    p[i] = translation(world[i]);
    relative[i] = Quat::Identity();
  }
  const bool limited = detail::has_limits(limits);
  const Mat3 root_frame = detail::rotation_frame(parent_world);

  double total = 0.0;
  for (std::size_t i = 0; i < last; ++i) total += rest_bone(world, i).norm();

  IkChainResult r;
  Vec3 to_target = target - p[0];
  if (!limited && to_target.norm() >= total) {
    // Out of reach: every bone onto the line to the target, root first.
    if (normalize_in_place(to_target)) {
      Quat parent_turn = Quat::Identity();
      for (std::size_t i = 0; i < last; ++i) {
        Vec3 bone = parent_turn * rest_bone(world, i);
        Quat turn = parent_turn;
        if (normalize_in_place(bone)) turn = (detail::shortest_arc(bone, to_target) * parent_turn).normalized();
        relative[i] = parent_turn.conjugate() * turn;
        parent_turn = turn;
      }
    }
  } else {
    double error = (p[last] - target).norm();
    while (error > tolerance && r.iterations < max_iterations) {
      // turn = W_{last-1}, then walked toward the root: W_{i-1} = W_i * R_i^-1.
      Quat turn = Quat::Identity();
      for (std::size_t i = 0; i < last; ++i) turn = turn * relative[i];
      Vec3 end = p[last];
      for (std::size_t i = last; i-- > 0;) {
        const Quat parent_turn = (turn * relative[i].conjugate()).normalized();
        // p[i] and p[i + 1] are as the sweep found them: only turns of
        // joints above them move them, and those come later in the sweep.
        Quat g = Quat::Identity();
        Vec3 to_end = end - p[i];
        Vec3 to_goal = target - p[i];
        if (normalize_in_place(to_end) && normalize_in_place(to_goal)) g = detail::shortest_arc(to_end, to_goal);
        if (limited && limits[i].kind != LimitKind::kNone) {
          Vec3 bone = p[i + 1] - p[i];
          if (normalize_in_place(bone)) {
            const Mat3 parent_frame = parent_frame_of(world, i, parent_turn, root_frame);
            const Vec3 turned = g * bone;
            const Vec3 wanted = parent_frame.transpose() * turned;
            const Vec3 allowed = constrain_direction(limits[i], wanted);
            if (limits[i].kind == LimitKind::kHinge) {
              // A hinge turns about its axis only: the smallest turn from the
              // bone (in the hinge plane) to the allowed direction (also in
              // it) is about the axis. g's own axis is discarded always, not
              // only past the range, so there is no switch to jump at.
              g = detail::shortest_arc(bone, (parent_frame * allowed).normalized());
            } else if ((allowed - wanted).squaredNorm() > 1e-24) {
              // Outside a cone: follow g with the smallest turn back into it
              // (a fresh turn from the bone would drop g's turn about the
              // bone, and jump as the limit starts to bite).
              g = detail::shortest_arc(turned.normalized(), (parent_frame * allowed).normalized()) * g;
            }
          }
        }
        // W_i becomes g * W_i: relative[i] = W_{i-1}^-1 * g * W_i.
        relative[i] = parent_turn.conjugate() * g * turn;
        end = p[i] + g * (end - p[i]);
        turn = parent_turn;
      }
      rebuild_positions(world, p, relative);
      ++r.iterations;
      error = (p[last] - target).norm();
    }
  }
  if (limited) {
    // Root to end, every bone into its limit: a solve that ran no sweep (or
    // an input outside its limits) still returns a pose within them.
    Quat parent_turn = Quat::Identity();
    for (std::size_t i = 0; i < last; ++i) {
      Quat turn = parent_turn * relative[i];
      if (limits[i].kind != LimitKind::kNone) {
        Vec3 bone = turn * rest_bone(world, i);
        if (normalize_in_place(bone)) {
          const Mat3 parent_frame = parent_frame_of(world, i, parent_turn, root_frame);
          const Vec3 local = parent_frame.transpose() * bone;
          const Vec3 allowed = constrain_direction(limits[i], local);
          if ((allowed - local).squaredNorm() > 1e-24) {
            turn = detail::shortest_arc(bone, (parent_frame * allowed).normalized()) * turn;
            relative[i] = parent_turn.conjugate() * turn;
          }
        }
      }
      parent_turn = turn.normalized();
    }
  }
  rebuild_positions(world, p, relative);
  r.error = (p[last] - target).norm();
  r.reached = r.error <= tolerance;

  // Relative turns to corrections: C_i = R_i^-1 * relative_i * R_i (R_i the
  // joint's rotation frame); the last joint's relative turn is the identity.
  for (std::size_t i = 0; i < count; ++i) {
    const Quat frame(detail::rotation_frame(world[i]));
    relative[i] = detail::positive_w((frame.conjugate() * relative[i] * frame).normalized());
  }
  if (result != nullptr) *result = r;
  return true;
}

}  // namespace rigel::ops::ik
