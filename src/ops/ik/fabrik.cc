#include "rigel/ops/ik/fabrik.h"

#include <cmath>

#include "ik_math.h"

namespace rigel::ops::ik {

using detail::normalize_in_place;
using detail::translation;

bool FabrikJob::validate() const {
  return detail::valid_chain_job(world, positions, corrections, limits, parent_world, target, tolerance,
                                 max_iterations);
}

namespace {

// The input vector of bone i (joint i to joint i + 1), world space.
Vec3 rest_bone(std::span<const Mat4> world, std::size_t i) { return translation(world[i + 1]) - translation(world[i]); }

// Direction of bone i at its input pose, for when the solve leaves two
// joints on top of each other.
Vec3 rest_direction(std::span<const Mat4> world, std::size_t i) {
  Vec3 d = rest_bone(world, i);
  if (!normalize_in_place(d)) d = Vec3::UnitX();
  return d;
}

// Root to end: turns each joint by the smallest rotation taking its bone from
// where the parent's turn carried it to the bone's current direction. With
// `limits`, a direction is first constrained in the parent's frame and the
// child joint re-placed (FABRIK's backward pass under limits); with
// `corrections`, each joint's turn is written as a correction in its own
// frame; with `turns`, as the world-space turn (for the next forward pass).
// The turn is tracked as a running quaternion (the parent's), so the parent
// frames that limits use are exactly those the corrections produce.
RIGEL_IK_MULTIVERSION void walk_root_to_end(const FabrikJob& job, const JointLimit* limits, Vec3* p, Quat* corrections,
                                            Quat* turns) {
  const std::size_t last = job.world.size() - 1;
  Quat turn = Quat::Identity();  // world-space turn of joint i - 1
  Mat3 parent_frame = detail::rotation_frame(job.parent_world);
  for (std::size_t i = 0; i < last; ++i) {
    const Mat3 frame = detail::rotation_frame(job.world[i]);
    const Vec3 rest = rest_bone(job.world, i);
    const double length = rest.norm();
    Vec3 carried = turn * rest;
    const bool has_carried = normalize_in_place(carried);
    Vec3 d = p[i + 1] - p[i];
    if (!normalize_in_place(d)) d = has_carried ? carried : rest_direction(job.world, i);
    if (limits != nullptr && limits[i].kind != LimitKind::kNone) {
      d = parent_frame * constrain_direction(limits[i], parent_frame.transpose() * d);
      d.normalize();
      p[i + 1] = p[i] + d * length;
    }
    const Quat bone_turn = has_carried ? detail::shortest_arc(carried, d) : Quat::Identity();
    if (corrections != nullptr) {
      // C = (turn * R)^-1 * bone_turn * (turn * R)
      const Quat carried_frame = turn * Quat(frame);
      corrections[i] = detail::positive_w((carried_frame.conjugate() * bone_turn * carried_frame).normalized());
    }
    turn = (bone_turn * turn).normalized();
    if (turns != nullptr) turns[i] = turn;
    // Joint i's frame after the solve, for bone i + 1's limit.
    if (limits != nullptr) parent_frame = turn.toRotationMatrix() * frame;
  }
  if (corrections != nullptr) corrections[last] = Quat::Identity();
}

// FABRIK's forward pass under limits: the end on the target, then each
// joint pulled toward its child as usual, except that where the child's bone
// would leave its limit (seen in this joint's frame, estimated from the last
// backward pass turned with the bone), this joint's bone turns with its
// frame until the child's bone is inside. Without this the limited joints
// near the end stall the solve: the forward pass leaves the joints above them
// where they were, and the backward pass clamps the same bones again.
RIGEL_IK_MULTIVERSION void forward_limited(const FabrikJob& job, Vec3* p, const Quat* turns) {
  const std::size_t last = job.world.size() - 1;
  p[last] = job.target;
  for (std::size_t i = last; i-- > 0;) {
    Vec3 bone = p[i + 1] - p[i];  // toward the child's new position
    if (!normalize_in_place(bone)) bone = turns[i] * rest_direction(job.world, i);
    if (i + 1 < last && job.limits[i + 1].kind != LimitKind::kNone) {
      Vec3 child = p[i + 2] - p[i + 1];
      if (normalize_in_place(child)) {
        Quat frame = turns[i] * Quat(detail::rotation_frame(job.world[i]));
        Vec3 carried = turns[i] * rest_bone(job.world, i);
        if (normalize_in_place(carried)) frame = detail::shortest_arc(carried, bone) * frame;
        const Vec3 local = frame.conjugate() * child;
        const Vec3 allowed = constrain_direction(job.limits[i + 1], local);
        if ((allowed - local).squaredNorm() > 1e-24) {
          bone = (detail::shortest_arc((frame * allowed).normalized(), child) * bone).normalized();
        }
      }
    }
    p[i] = p[i + 1] - bone * rest_bone(job.world, i).norm();
  }
}

}  // namespace

RIGEL_IK_MULTIVERSION bool FabrikJob::run() const {
  if (!validate()) return false;
  const std::size_t count = world.size();
  const std::size_t last = count - 1;
  Vec3* p = positions.data();
  for (std::size_t i = 0; i < count; ++i) p[i] = translation(world[i]);
  const Vec3 root = p[0];
  const bool limited = detail::has_limits(limits);
  const JointLimit* limit_data = limited ? limits.data() : nullptr;

  double total = 0.0;
  for (std::size_t i = 0; i < last; ++i) total += rest_bone(world, i).norm();

  IkChainResult r;
  Vec3 to_target = target - root;
  if (!limited && to_target.norm() >= total) {
    // Out of reach: straight at the target, exactly.
    if (!normalize_in_place(to_target)) to_target = rest_direction(world, 0);
    for (std::size_t i = 0; i < last; ++i) p[i + 1] = p[i] + to_target * rest_bone(world, i).norm();
  } else if (limited) {
    // Under limits, corrections holds each joint's world-space turn from the
    // last backward pass (the frames the forward pass estimates from).
    Quat* turns = corrections.data();
    for (std::size_t i = 0; i < count; ++i) turns[i] = Quat::Identity();
    double error = (p[last] - target).norm();
    while (error > tolerance && r.iterations < max_iterations) {
      forward_limited(*this, p, turns);
      p[0] = root;
      walk_root_to_end(*this, limit_data, p, nullptr, turns);
      ++r.iterations;
      error = (p[last] - target).norm();
    }
  } else {
    // Without limits, corrections holds the bone lengths (in x) while
    // solving: each pull is then one square root and one division.
    for (std::size_t i = 0; i < last; ++i) corrections[i].x() = rest_bone(world, i).norm();
    auto length = [this](std::size_t i) { return corrections[i].x(); };
    // `joint` moved along the line from `anchor` through it to `bone` away
    // (two joints on top of each other: along the bone's input direction).
    auto pull = [this](const Vec3& anchor, const Vec3& joint, double bone, std::size_t i, double sign) -> Vec3 {
      const Vec3 offset = joint - anchor;
      const double n2 = offset.squaredNorm();
      if (n2 > detail::kTinyLength * detail::kTinyLength) return anchor + offset * (bone / std::sqrt(n2));
      return anchor + rest_direction(world, i) * (sign * bone);
    };
    const double tolerance2 = tolerance * tolerance;
    double error2 = (p[last] - target).squaredNorm();
    while (error2 > tolerance2 && r.iterations < max_iterations) {
      // Forward: the end on the target, each joint pulled toward its child.
      p[last] = target;
      for (std::size_t i = last; i-- > 0;) p[i] = pull(p[i + 1], p[i], length(i), i, -1.0);
      // Backward: the root back in place, each child pulled toward its parent.
      p[0] = root;
      for (std::size_t i = 0; i < last; ++i) p[i + 1] = pull(p[i], p[i + 1], length(i), i, 1.0);
      ++r.iterations;
      error2 = (p[last] - target).squaredNorm();
    }
  }
  // Corrections (and, under limits, one more constraining pass, so that even
  // a solve that ran no iteration returns a pose within the limits).
  walk_root_to_end(*this, limit_data, p, corrections.data(), nullptr);
  r.error = (p[last] - target).norm();
  r.reached = r.error <= tolerance;
  if (result != nullptr) *result = r;
  return true;
}

}  // namespace rigel::ops::ik
