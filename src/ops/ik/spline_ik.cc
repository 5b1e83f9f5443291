#include "rigel/ops/ik/spline_ik.h"

#include <algorithm>
#include <cmath>

#include "ik_math.h"

namespace rigel::ops::ik {

using detail::all_finite;
using detail::normalize_in_place;
using detail::translation;

RIGEL_IK_MULTIVERSION Vec3 bspline_point(std::span<const Vec3> control_points, double u, Vec3* tangent) {
  const int count = static_cast<int>(control_points.size());
  if (tangent != nullptr) *tangent = Vec3::Zero();
  if (count == 0) return Vec3::Zero();
  if (count == 1) return control_points[0];
  const int degree = std::min(3, count - 1);
  const int spans = count - degree;
  // In knot units (x = u * spans) the clamped uniform knots are the
  // integers j - degree clamped to [0, spans]: every knot difference is a
  // small integer, so de Boor's algorithm needs no division.
  const double x = std::clamp(u, 0.0, 1.0) * spans;
  const int span = std::min(static_cast<int>(x), spans - 1);  // x in [span, span + 1]
  auto knot = [&](int j) { return std::clamp(j - degree, 0, spans); };
  static constexpr double kInverse[] = {0.0, 1.0, 1.0 / 2.0, 1.0 / 3.0};

  Vec3 d[4];
  for (int j = 0; j <= degree; ++j) d[j] = control_points[static_cast<std::size_t>(j + span)];
  // de Boor's algorithm on the degree + 1 control points of this span.
  if (tangent != nullptr && degree == 1) *tangent = (d[1] - d[0]) * spans;
  for (int r = 1; r <= degree; ++r) {
    for (int j = degree; j >= r; --j) {
      const int i = j + span;  // control point index; its knots run from knot(i) to knot(i + degree + 1 - r)
      const int lo = knot(i);
      const double alpha = (x - lo) * kInverse[knot(i + degree + 1 - r) - lo];
      d[j] = d[j - 1] + alpha * (d[j] - d[j - 1]);
    }
    // The derivative is degree * (difference of the last two points of the
    // second-to-last column) / span width (1 in knot units, 1 / spans in u).
    if (tangent != nullptr && r == degree - 1) *tangent = (d[degree] - d[degree - 1]) * (degree * spans);
  }
  return d[degree];
}

bool SplineIkJob::validate() const {
  if (control_points.size() < 2) return false;
  for (const Vec3& p : control_points) {
    if (!all_finite(p)) return false;
  }
  if (world.size() < 2 || world_out.size() != world.size()) return false;
  if (detail::overlap(world_out.data(), world_out.size(), world.data(), world.size())) return false;
  if (arc_lengths.size() < 2) return false;
  for (const Mat4& m : world) {
    if (!detail::is_affine(m)) return false;
  }
  if (!detail::is_unit(aim_axis) || !detail::is_unit(up_axis)) return false;
  if (!(std::abs(aim_axis.dot(up_axis)) <= kUnitTolerance)) return false;
  if (!all_finite(up_vector) || !(up_vector.norm() > detail::kTinyLength)) return false;
  return std::isfinite(start_twist) && std::isfinite(end_twist);
}

namespace {

double bone_length(std::span<const Mat4> world, std::size_t i) {
  return (translation(world[i + 1]) - translation(world[i])).norm();
}

// The first u' in (u_lo, u_hi] with |C(u') - from| = length, given
// |C(u_lo) - from| < length <= |C(u_hi) - from|: Newton on
// g(u) = |C(u) - from|^2 - length^2, kept inside the bracket by bisection.
RIGEL_IK_MULTIVERSION double solve_distance(std::span<const Vec3> cps, const Vec3& from, double length, double lo,
                                            double hi) {
  const double target = length * length;
  double u = 0.5 * (lo + hi);
  for (int iteration = 0; iteration < 60; ++iteration) {
    Vec3 tangent;
    const Vec3 offset = bspline_point(cps, u, &tangent) - from;
    const double g = offset.squaredNorm() - target;
    // 1e-14 of length^2 is 5e-15 of the length: the caller snaps the bone
    // to its exact length, so this only decides how far off the curve the
    // joint may sit.
    if (std::abs(g) <= 1e-14 * target) break;
    if (g < 0.0) {
      lo = u;
    } else {
      hi = u;
    }
    if (hi - lo <= 1e-16) break;
    const double slope = 2.0 * offset.dot(tangent);
    const double newton = slope != 0.0 ? u - g / slope : lo;
    const double next = (newton > lo && newton < hi) ? newton : 0.5 * (lo + hi);
    if (std::abs(next - u) <= 1e-16) break;  // converged to rounding
    u = next;
  }
  return u;
}

// The curve's unit tangent at u, or the direction between nearby points
// where the derivative vanishes (repeated control points), or `fallback`.
Vec3 unit_tangent(std::span<const Vec3> cps, double u, const Vec3& fallback) {
  Vec3 t;
  bspline_point(cps, u, &t);
  if (normalize_in_place(t)) return t;
  const double h = 1e-6;
  t = bspline_point(cps, std::min(1.0, u + h)) - bspline_point(cps, std::max(0.0, u - h));
  if (normalize_in_place(t)) return t;
  return fallback;
}

}  // namespace

// Over 150 lines: one solve, read top to bottom in the order of its steps
// (arc lengths, the joints placed along the curve, stretch and squash, the
// twist, the channels), each a few lines over the same locals; the hot loop
// is benchmarked as one function (bench/ik_bench.cc).
RIGEL_IK_MULTIVERSION bool SplineIkJob::run() const {
  if (!validate()) return false;
  const std::size_t count = world.size();
  const std::size_t last = count - 1;
  const std::size_t samples = arc_lengths.size() - 1;
  const auto sample_u = [samples](std::size_t k) { return static_cast<double>(k) / static_cast<double>(samples); };

  // Arc-length table: a polyline through evenly spaced parameters.
  Vec3 previous = bspline_point(control_points, 0.0);
  arc_lengths[0] = 0.0;
  for (std::size_t k = 1; k <= samples; ++k) {
    const Vec3 point = bspline_point(control_points, sample_u(k));
    arc_lengths[k] = arc_lengths[k - 1] + (point - previous).norm();
    previous = point;
  }
  const double curve_length = arc_lengths[samples];
  const Vec3 curve_end = previous;

  double chain_length = 0.0;
  for (std::size_t i = 0; i < last; ++i) chain_length += bone_length(world, i);

  // Positions go to world_out[i]'s translation and each joint's curve
  // parameter to world_out[i](3, 0) until the orientation pass overwrites
  // them (no other scratch needed).
  auto position = [&](std::size_t i) -> Eigen::Block<Mat4, 3, 1> { return world_out[i].topRightCorner<3, 1>(); };
  auto parameter = [&](std::size_t i) -> double& { return world_out[i](3, 0); };
  position(0) = bspline_point(control_points, 0.0);
  parameter(0) = 0.0;
  bool overran = false;
  const Vec3 end_tangent = unit_tangent(control_points, 1.0, Vec3::UnitX());

  if (stretch) {
    double along = 0.0;
    for (std::size_t i = 1; i < count; ++i) {
      along += bone_length(world, i - 1);
      const double wanted = chain_length > 0.0 ? curve_length * along / chain_length : 0.0;
      // The table segment holding `wanted`, then linear in it.
      const std::size_t k = std::min<std::size_t>(
          samples - 1, static_cast<std::size_t>(std::upper_bound(arc_lengths.begin(), arc_lengths.end(), wanted) -
                                                arc_lengths.begin()) -
                           1);
      // Within the segment, the point whose chord from the segment's start
      // is the length left: exact on straight stretches, and off the true
      // arc length only by the chord's shortfall inside one segment.
      const double left = wanted - arc_lengths[k];
      double u = sample_u(k);
      if (left > 0.0) {
        const Vec3 segment_start = bspline_point(control_points, u);
        const double width = arc_lengths[k + 1] - arc_lengths[k];
        u = left >= width ? sample_u(k + 1)
                          : solve_distance(control_points, segment_start, left, sample_u(k), sample_u(k + 1));
      }
      position(i) = bspline_point(control_points, u);
      parameter(i) = u;
    }
  } else {
    for (std::size_t i = 0; i < last; ++i) {
      const Vec3 from = position(i);
      const double length = bone_length(world, i);
      const double u = parameter(i);
      if (length <= 0.0) {
        position(i + 1) = from;
        parameter(i + 1) = u;
        continue;
      }
      // Samples after u, skipping those surely inside the sphere of radius
      // `length` about `from`: the polyline path from `from` to sample j is
      // no shorter than the straight distance.
      std::size_t j = std::min(samples, static_cast<std::size_t>(std::floor(u * static_cast<double>(samples))) + 1);
      double lo = u;
      double hi = -1.0;
      if (u < 1.0) {
        const double first = (bspline_point(control_points, sample_u(j)) - from).norm();
        if (first >= length) {
          hi = sample_u(j);
        } else {
          const double budget = arc_lengths[j] + (length - first);
          const auto skip = static_cast<std::size_t>(
              std::lower_bound(arc_lengths.begin() + static_cast<std::ptrdiff_t>(j), arc_lengths.end(), budget) -
              arc_lengths.begin());
          // Samples j..skip-1 are inside.
          j = std::max(j, skip - 1);
          lo = sample_u(j);
          for (++j; j <= samples; ++j) {
            if ((bspline_point(control_points, sample_u(j)) - from).norm() >= length) {
              hi = sample_u(j);
              break;
            }
            lo = sample_u(j);
          }
        }
      }
      Vec3 next;
      if (hi >= 0.0) {
        const double solved = solve_distance(control_points, from, length, lo, hi);
        next = bspline_point(control_points, solved);
        parameter(i + 1) = solved;
      } else {
        // Past the curve's end: on the line from the end along its tangent,
        // at the point `length` from `from` (the far root of
        // |end + t * tangent - from| = length, t >= 0).
        overran = true;
        const Vec3 v = curve_end - from;
        const double b = end_tangent.dot(v);
        const double t = -b + std::sqrt(std::max(0.0, b * b - v.squaredNorm() + length * length));
        next = curve_end + end_tangent * std::max(0.0, t);
        parameter(i + 1) = 1.0;
      }
      // Snap to the exact bone length (the root finder leaves ~1e-15).
      Vec3 direction = next - from;
      if (normalize_in_place(direction)) next = from + direction * length;
      position(i + 1) = next;
    }
  }

  // Orientations.
  const Vec3 up_world = up_vector.normalized();
  Mat3 joint_axes;
  joint_axes.col(0) = aim_axis.normalized();
  joint_axes.col(1) = up_axis - joint_axes.col(0) * joint_axes.col(0).dot(up_axis);
  joint_axes.col(1).normalize();
  joint_axes.col(2) = joint_axes.col(0).cross(joint_axes.col(1));
  Vec3 previous_aim = end_tangent;
  Vec3 previous_up = up_world;
  double along = 0.0;
  for (std::size_t i = 0; i < count; ++i) {
    const Vec3 p = position(i);
    const double u = parameter(i);
    Vec3 aim;
    bool has_aim = false;
    double bone_stretch = 1.0;
    if (i < last) {
      aim = Vec3(position(i + 1)) - p;
      const double chord = aim.norm();
      const double length = bone_length(world, i);
      if (stretch && length > 0.0) bone_stretch = chord / length;
      has_aim = normalize_in_place(aim);
    } else if (overran) {
      aim = end_tangent;
      has_aim = true;
    }
    if (!has_aim) aim = unit_tangent(control_points, u, previous_aim);

    Vec3 up = up_world - aim * aim.dot(up_world);
    if (!normalize_in_place(up)) {
      up = previous_up - aim * aim.dot(previous_up);
      if (!normalize_in_place(up)) up = aim.unitOrthogonal();
    }
    previous_aim = aim;
    previous_up = up;

    const double fraction =
        chain_length > 0.0 ? along / chain_length : static_cast<double>(i) / static_cast<double>(last);
    const double twist = start_twist + (end_twist - start_twist) * fraction;
    if (i < last) along += bone_length(world, i);
    const Vec3 twisted_up = twist != 0.0 ? Vec3(up * std::cos(twist) + aim.cross(up) * std::sin(twist)) : up;

    Mat3 world_axes;
    world_axes.col(0) = aim;
    world_axes.col(1) = twisted_up;
    world_axes.col(2) = aim.cross(twisted_up);
    const Mat3 rotation = world_axes * joint_axes.transpose();

    // Stretch along the aim axis, squash across it, then the joint's own
    // scale (its input column lengths).
    const double across = squash && bone_stretch > 0.0 ? 1.0 / std::sqrt(bone_stretch) : 1.0;
    const Vec3& a = joint_axes.col(0);
    const Mat3 stretch_matrix = across * Mat3::Identity() + (bone_stretch - across) * (a * a.transpose());
    const Vec3 own_scale(world[i].col(0).head<3>().norm(), world[i].col(1).head<3>().norm(),
                         world[i].col(2).head<3>().norm());

    Mat4 out = Mat4::Identity();
    out.topLeftCorner<3, 3>() = rotation * stretch_matrix * own_scale.asDiagonal();
    out.topRightCorner<3, 1>() = p;
    world_out[i] = out;
  }

  if (result != nullptr) {
    result->curve_length = curve_length;
    result->chain_length = chain_length;
    result->overran = overran;
  }
  return true;
}

}  // namespace rigel::ops::ik
