#pragma once
// Finger curl and spread, shaped as a job (STYLE.md §3): each finger
// control's offsetParentMatrix turned from its rest by the hand's curl and
// spread values. The fingerCurl node (finger.h) calls it.
//
// Per control i (n = rest_offset_parent.size()), of finger k = finger[i]:
//   curl_i   = curl + finger_curl[k]                         (degrees)
//   spread_i = spread * spread_weight[i]                     (degrees)
//   R_i      = rot(spread_axis[i], spread_i) * rot(bend_axis[i], curl_i)
//   output[i] = rest_offset_parent[i] * R_i
// rot(a, t): the rotation by t about the unit axis a (right-hand rule), in
// the control's own frame (axes are given in that frame), so the control
// turns about its own origin (the finger joint) and everything under it
// follows. A zero angle gives rest_offset_parent[i] exactly. Every control
// of a finger gets that finger's curl; spread_weight is usually nonzero only
// on a finger's first control (rig::components hand: the fingers fan out
// from the middle one).

#include <cstdint>
#include <span>

#include "rigel/math/types.h"

namespace rigel::ops::util {

// rest_offset * rot(spread_axis, spread) * rot(bend_axis, curl), angles in
// radians, axes unit length; a zero angle leaves its rotation out.
math::Mat4 finger_offset(const math::Mat4& rest_offset, const math::Vec3& spread_axis, double spread,
                         const math::Vec3& bend_axis, double curl);

// The first thing FingerCurlJob::run() could not use. The control keeps
// what it can: a missing finger index gives it the shared curl only, a
// non-finite angle or a missing, zero or non-finite axis gives it no turn
// for that part (curl or spread).
struct FingerCurlResult {
  enum class Problem {
    kNone,
    kMissingFinger,   // finger[control] is missing
    kCurlNotFinite,   // curl_i is not finite
    kSpreadNotFinite, // spread_i is not finite
    kBadBendAxis,     // bend_axis[control] is missing, zero or not finite while curl_i is not 0
    kBadSpreadAxis,   // spread_axis[control] is missing, zero or not finite while spread_i is not 0
  };
  Problem problem = Problem::kNone;
  std::size_t control = 0;  // the control it concerns
};

struct FingerCurlJob {
  // Validates job parameters. Returns false:
  // - if output is smaller than rest_offset_parent.
  bool validate() const;
  // Writes output[0 .. n) and *result when given. Returns false if the job
  // is not valid.
  bool run() const;

  // Curl and spread of every finger, degrees.
  double curl = 0.0;
  double spread = 0.0;
  // Extra curl per finger, degrees (missing element: 0). Not owned.
  std::span<const double> finger_curl;
  // Per control: its finger's index k (an index outside finger_curl: no
  // extra curl).
  std::span<const std::int64_t> finger;
  // Per control: offsetParentMatrix at rest; its size is the control count.
  std::span<const math::Mat4> rest_offset_parent;
  // Per control: the curl and spread axes in the control's frame (any
  // length: normalized here).
  std::span<const math::Vec3> bend_axis;
  std::span<const math::Vec3> spread_axis;
  // Per control (missing: 0).
  std::span<const double> spread_weight;

  // Output: each control's offsetParentMatrix. Not owned.
  std::span<math::Mat4> output;
  // Optional output.
  FingerCurlResult* result = nullptr;
};

}  // namespace rigel::ops::util
