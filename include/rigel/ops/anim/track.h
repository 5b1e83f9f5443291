#pragma once
// glTF animation tracks: translation and scale (Vec3Track) and rotation
// (QuatTrack) sampled with glTF's three interpolations. These are what the
// glTF importer produces; Maya-style curves are in curve.h.
//
// glTF semantics (glTF 2.0 §3.11, Appendix C): times in seconds, strictly
// increasing; outside the keys the end values hold (no infinity modes);
// LINEAR rotation is a spherical linear interpolation (shortest path),
// LINEAR translation/scale a linear one; STEP holds a key's value until the
// next key; CUBICSPLINE is a cubic Hermite spline whose tangents are given
// per key (in value units per second), the result normalised for rotations.

#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/math/types.h"
#include "rigel/ops/anim/curve.h"  // Cursor

namespace rigel::ops::anim {

enum class Interpolation : std::uint8_t {
  kStep = 0,         // glTF STEP
  kLinear = 1,       // glTF LINEAR: lerp, or slerp for rotations
  kCubicSpline = 2,  // glTF CUBICSPLINE
};
inline constexpr int kInterpolationCount = 3;

// "step", "linear", "cubicSpline", indexed by the enum value.
std::span<const std::string_view> interpolation_names();

// Keys as parallel arrays (what animCurveVec3 / animCurveQuat nodes store).
// T is math::Vec3 or math::Quat.
template <typename T>
struct TrackArrays {
  std::span<const double> times;  // seconds, increasing
  std::span<const T> values;      // one per key
  // Cubic spline only, one per key each: glTF's in-tangent a_k and
  // out-tangent b_k. Must be empty for step and linear tracks.
  std::span<const T> in_tangents;
  std::span<const T> out_tangents;
  Interpolation interpolation = Interpolation::kLinear;

  // Ok, or the first problem found, naming the key. Fails:
  // - if `values` has a size other than times.size();
  // - for cubic spline tracks, if `in_tangents` or `out_tangents` has a size
  //   other than times.size(); for the others, if either is not empty;
  // - if `interpolation` is not one of Interpolation;
  // - if a time is NaN or infinite, or not after the previous key's
  //   (unsorted or duplicate);
  // - if a value or tangent has a NaN or infinite component;
  // - for rotations, if a value is (nearly) the zero quaternion (norm below
  //   1e-6), which is no rotation at all.
  Status validate() const;
};

// The value of the track `arrays` describes at `t`, without building a
// Track: a binary search, no allocation. Rotation keys are normalised as
// they are read. `arrays` must have passed validate() (invalid arrays give an
// unspecified value, but never read out of bounds as long as the sizes are
// consistent). No keys: zero / the identity rotation.
template <typename T>
T evaluate_arrays(const TrackArrays<T>& arrays, double t);

namespace detail {
// One linear rotation segment's slerp, worked out once when a track is
// built: the end key on the short way round, the angle between the keys and
// 1 / sin(angle). `theta` < 0: the keys are nearly equal and the segment is a
// normalised lerp. slerp_along(a, slerp_span(a, b), s) is
// slerp_shortest(a, b, s) bit for bit, without its acos, sin and division.
struct SlerpSpan {
  math::Quat end = math::Quat::Identity();
  double theta = -1.0;
  double inv_sin = 0.0;
};
SlerpSpan slerp_span(const math::Quat& a, const math::Quat& b);
math::Quat slerp_along(const math::Quat& a, const SlerpSpan& span, double s);
}  // namespace detail

// A track that owns its keys (rotations normalised when built; a linear
// rotation track's slerps prepared then too).
template <typename T>
class Track {
 public:
  // No keys: zero / the identity rotation everywhere.
  Track() = default;

  // Fails as TrackArrays::validate().
  static Result<Track> build(std::vector<double> times, std::vector<T> values, Interpolation interpolation,
                             std::vector<T> in_tangents = {}, std::vector<T> out_tangents = {});
  // From a glTF sampler's input and output accessors: for cubic splines the
  // output holds three elements per key (in-tangent, value, out-tangent).
  // Fails as build(), and if the output's size is not the key count (times
  // three for cubic splines).
  static Result<Track> from_gltf(std::span<const double> times, std::span<const T> output,
                                 Interpolation interpolation);

  // The value at `t`; `cursor` as for AnimCurve::evaluate (sequential
  // playback touches O(1) keys). NaN `t` gives NaN components.
  T evaluate(double t, Cursor& cursor) const;
  // The same with a binary search.
  T evaluate(double t) const;

  TrackArrays<T> arrays() const { return {times_, values_, in_tangents_, out_tangents_, interpolation_}; }
  std::size_t key_count() const { return times_.size(); }
  Interpolation interpolation() const { return interpolation_; }

 private:
  std::vector<double> times_;
  std::vector<T> values_;
  std::vector<T> in_tangents_, out_tangents_;
  Interpolation interpolation_ = Interpolation::kLinear;
  // Linear rotation tracks: one per segment (times_.size() - 1); else empty.
  std::vector<detail::SlerpSpan> slerp_;
};

using Vec3Track = Track<math::Vec3>;
using QuatTrack = Track<math::Quat>;

// Samples many tracks at one time (playback of an imported clip).
template <typename T>
struct SampleTracksJob {
  // Validates job parameters. Returns false:
  // - if `cursors` or `output` is smaller than `tracks`;
  // - if `time` is NaN.
  bool validate() const;
  // output[i] = tracks[i].evaluate(time, cursors[i]). Returns false, writing
  // nothing, if the job is not valid.
  bool run() const;

  double time = 0.0;                  // seconds
  std::span<const Track<T>> tracks;   // read only
  std::span<Cursor> cursors;          // one per track, kept between runs
  std::span<T> output;                // one per track
};

using SampleVec3TracksJob = SampleTracksJob<math::Vec3>;
using SampleQuatTracksJob = SampleTracksJob<math::Quat>;

// Shortest-path spherical linear interpolation of unit quaternions: s = 0
// gives a, s = 1 gives b or -b (whichever is nearer a).
math::Quat slerp_shortest(const math::Quat& a, const math::Quat& b, double s);

}  // namespace rigel::ops::anim
