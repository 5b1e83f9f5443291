#pragma once
// Analytic two-bone IK (a leg or an arm: start, mid and end joints), shaped
// as a job (STYLE.md §3). The output convention (corrections in each joint's
// own frame, applied as local_rotation * correction) is described in
// ik_chain.h; ChainCorrectionJob applies it.
//
// The solve, in world space:
// 1. the target distance d = |target - start| is softened (soft IK) and the
//    stretch factor s is found (stretch on);
// 2. the mid joint turns about its hinge axis (mid_axis) until start-to-end
//    is the distance the chain should reach (law of cosines, generalised to a
//    hinge axis that is not perpendicular to the bones);
// 3. the start joint turns the whole chain so that start-to-end points at
//    the target and the chain's hinge axis lies where the pole (or plane)
//    says, then twists it by twist_angle about start-to-target.
// Step 3 maps one frame (start-to-end, hinge axis) onto another, both
// continuous functions of the target and pole, so the knee cannot flip as
// the target moves, except through the one configuration where the pole is
// undefined (pole_vector parallel to start-to-target).

#include <cstdint>
#include <limits>

#include "rigel/ops/ik/ik_chain.h"

namespace rigel::ops::ik {

// How the plane of the chain is chosen.
enum class TwoBonePoleMode : std::uint8_t {
  // The knee points toward pole_vector: the chain's plane holds start,
  // target and start + pole_vector, the knee on the pole's side.
  kPoleVector = 0,
  // The chain's hinge axis (mid_axis in world) is aligned with pole_vector,
  // taken as a plane normal; the knee points along
  // cross(start-to-target, normal).
  kPlaneNormal = 1,
};

// What TwoBoneIkJob::run() writes.
struct TwoBoneIkOutput {
  // Correction of the start joint, in its own frame (local_rotation =
  // local_rotation * start_correction). w >= 0.
  Quat start_correction = Quat::Identity();
  // Correction of the mid joint, in its own frame: a rotation about
  // mid_axis. w >= 0.
  Quat mid_correction = Quat::Identity();
  // The same turns in world space, weight applied: the whole chain turns by
  // start_turn about the start joint after the lower bone turned by
  // mid_turn (about the hinge) about the mid joint. The two are exact for
  // any scale of the joints and their parents; the corrections above are
  // exact only where the joints' parents scale uniformly.
  Quat start_turn = Quat::Identity();
  Quat mid_turn = Quat::Identity();
  // Factor for the mid and end joints' local translations (both bones get
  // longer by it): 1 unless `stretch` is on and the target is beyond reach.
  double stretch = 1.0;
  // Whether the end joint lands on the target (weight aside): the target is
  // within the (stretched) chain's reach and not softened.
  bool reached = false;
};

struct TwoBoneIkJob {
  // Validates job parameters. Returns false:
  // - if start_world, mid_world, end_world or output is null;
  // - if one of the three world matrices is not affine (last row 0 0 0 1);
  // - if mid_axis is not a unit vector (kUnitTolerance);
  // - if target, pole_vector or twist_angle is not finite;
  // - if pole_mode is not one of TwoBonePoleMode's values;
  // - if soft or weight is outside [0, 1] (NaN included);
  // - if stretch is on and max_stretch is below 1 (NaN included; +infinity
  //   means no limit).
  bool validate() const;
  // Solves and writes *output. Returns false if the job is not valid.
  // Degenerate input never produces NaN: a target at the start joint keeps
  // the current start-to-end direction, a pole along start-to-target keeps
  // the hinge axis where it is (projected), a zero-length bone leaves the
  // mid joint unturned.
  bool run() const;

  // World matrices of the three joints (affine); mid is a child of start
  // and end a child of mid (there may be joints in between that the caller
  // keeps fixed). Not owned.
  const Mat4* start_world = nullptr;
  const Mat4* mid_world = nullptr;
  const Mat4* end_world = nullptr;

  // Target of the end joint, world space.
  Vec3 target = Vec3::Zero();
  // World-space direction (from the start joint) the knee points toward
  // (kPoleVector), or the normal of the chain's plane (kPlaneNormal).
  Vec3 pole_vector = Vec3::UnitY();
  TwoBonePoleMode pole_mode = TwoBonePoleMode::kPoleVector;
  // The mid joint's hinge axis, unit, in the mid joint's space. The knee
  // bends by a positive (right-handed) rotation about it: the end bone is the
  // start bone's direction turned by a positive angle about mid_axis.
  Vec3 mid_axis = Vec3::UnitZ();
  // Rotation of the solved chain about start-to-target, radians.
  double twist_angle = 0.0;
  // Soft IK: the fraction of the chain length over which the reach eases
  // toward full extension (0 = off). With chain length L, ds = soft * L and
  // da = L - ds, a target at distance d > da is reached at
  // da + ds * (1 - exp(-(d - da) / ds)): the knee never snaps straight.
  double soft = 0.0;
  // Stretch: beyond reach (or beyond the softened reach), both bones scale
  // by s = min(d / reach, max_stretch) so that the end reaches the target.
  bool stretch = false;
  double max_stretch = std::numeric_limits<double>::infinity();
  // Blend between no correction (0) and the full solve (1): both
  // corrections are slerped from the identity, stretch from 1.
  double weight = 1.0;

  // Output. Not owned.
  TwoBoneIkOutput* output = nullptr;
};

}  // namespace rigel::ops::ik
