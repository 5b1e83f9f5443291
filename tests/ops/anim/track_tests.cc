#include "rigel/ops/anim/track.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "anim_test_util.h"

namespace rigel::ops::anim {
namespace {

using math::Quat;
using math::Vec3;
using testing::fails_with;
using testing::Random;
using testing::succeeded;

constexpr double kTight = 1e-12;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

Quat about_z(double degrees) { return Quat(Eigen::AngleAxisd(math::to_radians(degrees), Vec3::UnitZ())); }

::testing::AssertionResult same_rotation(const Quat& a, const Quat& b, double tolerance) {
  const double diff = std::min((a.coeffs() - b.coeffs()).cwiseAbs().maxCoeff(), (a.coeffs() + b.coeffs()).cwiseAbs().maxCoeff());
  if (diff <= tolerance) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "quaternions (x y z w) " << a.coeffs().transpose() << " and "
                                       << b.coeffs().transpose() << " differ by " << diff << " (up to sign)";
}

::testing::AssertionResult near(const Vec3& a, const Vec3& b, double tolerance) {
  const double diff = (a - b).cwiseAbs().maxCoeff();
  if (diff <= tolerance) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << a.transpose() << " vs " << b.transpose() << " differ by " << diff;
}

template <typename T>
Track<T> make_track(std::vector<double> times, std::vector<T> values, Interpolation interpolation,
                    std::vector<T> in = {}, std::vector<T> out = {}) {
  Result<Track<T>> track = Track<T>::build(std::move(times), std::move(values), interpolation, std::move(in), std::move(out));
  EXPECT_TRUE(succeeded(track.status()));
  return track ? std::move(track).value() : Track<T>();
}

// ---- rotations ------------------------------------------------------------------

TEST(QuatTrack, linear__slerp_midpoint_of_0_and_90_about_z_is_45) {
  const QuatTrack track = make_track<Quat>({0, 1}, {about_z(0), about_z(90)}, Interpolation::kLinear);
  EXPECT_TRUE(same_rotation(track.evaluate(0.5), about_z(45), kTight));
  EXPECT_TRUE(same_rotation(track.evaluate(0.25), about_z(22.5), kTight)) << "slerp is uniform in angle";
  EXPECT_TRUE(same_rotation(track.evaluate(0.9), about_z(81), kTight));
}

TEST(QuatTrack, linear__takes_shortest_path_for_q_and_minus_q) {
  Quat negated = about_z(90);
  negated.coeffs() = -negated.coeffs();
  const QuatTrack plus = make_track<Quat>({0, 1}, {about_z(0), about_z(90)}, Interpolation::kLinear);
  const QuatTrack minus = make_track<Quat>({0, 1}, {about_z(0), negated}, Interpolation::kLinear);
  for (double t = 0; t <= 1; t += 0.125) {
    EXPECT_TRUE(same_rotation(minus.evaluate(t), plus.evaluate(t), kTight))
        << "-q is the same rotation as q: the path must not go the long way round (t = " << t << ")";
  }
  // 0 -> 270 degrees is 0 -> -90 the short way.
  const QuatTrack wrap = make_track<Quat>({0, 1}, {about_z(0), about_z(270)}, Interpolation::kLinear);
  EXPECT_TRUE(same_rotation(wrap.evaluate(0.5), about_z(-45), kTight));
}

TEST(QuatTrack, step__holds_key_rotation) {
  const QuatTrack track = make_track<Quat>({0, 1, 2}, {about_z(0), about_z(30), about_z(60)}, Interpolation::kStep);
  EXPECT_TRUE(same_rotation(track.evaluate(0.99), about_z(0), kTight));
  EXPECT_TRUE(same_rotation(track.evaluate(1.0), about_z(30), kTight));
  EXPECT_TRUE(same_rotation(track.evaluate(1.7), about_z(30), kTight));
}

TEST(QuatTrack, cubic__matches_hand_computed_hermite_normalised) {
  const Quat v0 = about_z(0), v1 = about_z(90);
  const Quat b0(0.1, 0.0, 0.2, 0.0), a1(0.0, 0.3, 0.0, -0.1);  // out tangent of key 0, in tangent of key 1
  const QuatTrack track = make_track<Quat>({1, 3}, {v0, v1}, Interpolation::kCubicSpline, {Quat(0, 0, 0, 0), a1},
                                           {b0, Quat(0, 0, 0, 0)});
  // s = 1/2, span 2: h00 = h01 = 1/2, h10 = 1/8, h11 = -1/8.
  Eigen::Vector4d p = 0.5 * v0.coeffs() + 0.125 * 2 * b0.coeffs() + 0.5 * v1.coeffs() - 0.125 * 2 * a1.coeffs();
  p.normalize();
  EXPECT_TRUE(same_rotation(track.evaluate(2.0), Quat(p), kTight));
  EXPECT_NEAR(track.evaluate(2.4).norm(), 1.0, kTight) << "glTF: the cubic result is normalised";
}

TEST(QuatTrack, keys_are_normalised) {
  Quat scaled = about_z(90);
  scaled.coeffs() *= 3.0;
  const QuatTrack track = make_track<Quat>({0, 1}, {Quat::Identity(), scaled}, Interpolation::kLinear);
  EXPECT_TRUE(same_rotation(track.evaluate(1.0), about_z(90), kTight));
  EXPECT_TRUE(same_rotation(track.evaluate(0.5), about_z(45), kTight));
}

// ---- translation / scale -----------------------------------------------------------

TEST(Vec3Track, step_and_linear) {
  const Vec3Track step = make_track<Vec3>({0, 1, 2}, {Vec3(0, 0, 0), Vec3(2, 4, 6), Vec3(1, 1, 1)}, Interpolation::kStep);
  EXPECT_TRUE(near(step.evaluate(0.5), Vec3(0, 0, 0), 0));
  EXPECT_TRUE(near(step.evaluate(1.5), Vec3(2, 4, 6), 0));
  const Vec3Track linear = make_track<Vec3>({0, 1, 2}, {Vec3(0, 0, 0), Vec3(2, 4, 6), Vec3(1, 1, 1)}, Interpolation::kLinear);
  EXPECT_TRUE(near(linear.evaluate(0.5), Vec3(1, 2, 3), kTight));
  EXPECT_TRUE(near(linear.evaluate(1.5), Vec3(1.5, 2.5, 3.5), kTight));
}

TEST(Vec3Track, cubic__matches_hand_computed_hermite) {
  const Vec3Track track = make_track<Vec3>({1, 3}, {Vec3(0, 0, 0), Vec3(2, 4, 6)}, Interpolation::kCubicSpline,
                                           {Vec3(9, 9, 9), Vec3(0, 1, 0)}, {Vec3(1, 0, 0), Vec3(9, 9, 9)});
  // s = 1/2, span 2: 0.5 (2, 4, 6) + 0.125 * 2 (1, 0, 0) - 0.125 * 2 (0, 1, 0).
  EXPECT_TRUE(near(track.evaluate(2.0), Vec3(1.25, 1.75, 3.0), kTight));
  // s = 1/4: h00 = 27/32, h10 = 9/64, h01 = 5/32, h11 = -3/64.
  EXPECT_TRUE(near(track.evaluate(1.5), Vec3(2 * 9.0 / 64, 0, 0) + (5.0 / 32) * Vec3(2, 4, 6) - 2 * (3.0 / 64) * Vec3(0, 1, 0), kTight));
  EXPECT_TRUE(near(track.evaluate(3.0), Vec3(2, 4, 6), 0)) << "the first key's in tangent and the last's out tangent are unused";
}

TEST(Vec3Track, outside_keys_holds_end_values) {
  const Vec3Track track = make_track<Vec3>({1, 2}, {Vec3(1, 2, 3), Vec3(4, 5, 6)}, Interpolation::kLinear);
  EXPECT_TRUE(near(track.evaluate(-10), Vec3(1, 2, 3), 0));
  EXPECT_TRUE(near(track.evaluate(10), Vec3(4, 5, 6), 0));
  EXPECT_TRUE(near(Vec3Track().evaluate(1), Vec3::Zero(), 0)) << "an empty track is zero";
  EXPECT_TRUE(same_rotation(QuatTrack().evaluate(1), Quat::Identity(), 0)) << "an empty rotation track is the identity";
  EXPECT_TRUE(std::isnan(track.evaluate(kNaN).x())) << "NaN in, NaN out";
}

TEST(Vec3Track, from_gltf__deinterleaves_cubic_output) {
  const std::vector<double> times = {0, 1};
  const std::vector<Vec3> output = {Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3(3, 0, 0),
                                    Vec3(0, 2, 0), Vec3(5, 5, 5), Vec3(0, 0, 0)};
  Result<Vec3Track> track = Vec3Track::from_gltf(times, output, Interpolation::kCubicSpline);
  ASSERT_TRUE(succeeded(track.status()));
  const Vec3Track expected = make_track<Vec3>({0, 1}, {Vec3(1, 1, 1), Vec3(5, 5, 5)}, Interpolation::kCubicSpline,
                                              {Vec3(0, 0, 0), Vec3(0, 2, 0)}, {Vec3(3, 0, 0), Vec3(0, 0, 0)});
  for (double t = 0; t <= 1; t += 0.1) EXPECT_TRUE(near(track->evaluate(t), expected.evaluate(t), 0));
  EXPECT_TRUE(fails_with(Vec3Track::from_gltf(times, std::span<const Vec3>(output).first(5), Interpolation::kCubicSpline).status(),
                         "sampler output has 5 elements; 2 keys need 6"));
  EXPECT_TRUE(fails_with(Vec3Track::from_gltf(times, output, Interpolation::kLinear).status(), "2 keys need 2"));
}

// ---- cursor -----------------------------------------------------------------------

TEST(QuatTrack, cursor__matches_fresh_search_for_any_sequence) {
  Random random(21);
  for (int c = 0; c < 30; ++c) {
    const int n = 1 + random.index(40);
    std::vector<double> times;
    std::vector<Quat> values, in, out;
    double t = random.uniform(-1, 1);
    for (int i = 0; i < n; ++i) {
      times.push_back(t);
      t += random.uniform(0.01, 0.5);
      values.push_back(Quat(Eigen::Vector4d::Random()).normalized());
      in.push_back(Quat(Eigen::Vector4d::Random()));
      out.push_back(Quat(Eigen::Vector4d::Random()));
    }
    const auto interpolation = static_cast<Interpolation>(c % kInterpolationCount);
    const bool cubic = interpolation == Interpolation::kCubicSpline;
    const QuatTrack track = make_track<Quat>(times, values, interpolation, cubic ? in : std::vector<Quat>{},
                                             cubic ? out : std::vector<Quat>{});
    std::vector<double> samples;
    for (double s = times.front() - 1; s <= times.back() + 1; s += 1.0 / 30) samples.push_back(s);
    for (double s = times.back() + 1; s >= times.front() - 1; s -= 1.0 / 60) samples.push_back(s);
    for (int i = 0; i < 300; ++i) samples.push_back(random.uniform(times.front() - 1, times.back() + 1));
    samples.insert(samples.end(), times.begin(), times.end());
    Cursor cursor;
    for (double s : samples) {
      ASSERT_EQ(track.evaluate(s, cursor).coeffs(), track.evaluate(s).coeffs()) << "track " << c << " t " << s;
    }
    // The attribute path (normalises keys as read) agrees with the built track.
    for (int i = 0; i < 50; ++i) {
      const double s = random.uniform(times.front() - 1, times.back() + 1);
      EXPECT_TRUE(same_rotation(evaluate_arrays(track.arrays(), s), track.evaluate(s), 1e-15));
    }
  }
}

// A linear rotation track prepares each segment's slerp when built; with a
// cursor it samples through them. Nearly equal keys (the lerp branch),
// keys on opposite hemispheres (the short way round) and wide angles all
// give slerp_shortest's bits.
TEST(QuatTrack, linear__prepared_slerps_give_slerp_shortest_bit_for_bit) {
  Random random(22);
  std::vector<double> times;
  std::vector<Quat> values;
  Quat q = Quat::Identity();
  for (int i = 0; i < 60; ++i) {
    times.push_back(i / 30.0);
    const double degrees = i % 3 == 0 ? random.uniform(-0.5, 0.5) : random.uniform(-170, 170);
    q = (q * Quat(Eigen::AngleAxisd(math::to_radians(degrees), Vec3(random.uniform(-1, 1), 1, 0).normalized())))
            .normalized();
    if (i % 4 == 1) q.coeffs() = -q.coeffs();  // the same rotation from the other hemisphere
    values.push_back(q);
  }
  const QuatTrack track = make_track<Quat>(times, values, Interpolation::kLinear);
  Cursor cursor;
  for (int i = 0; i < 59 * 7; ++i) {
    const double t = i / 210.0;
    const std::size_t k = std::min<std::size_t>(static_cast<std::size_t>(i / 7), 58);
    const double s = (t - times[k]) / (times[k + 1] - times[k]);
    const Quat a = track.arrays().values[k], b = track.arrays().values[k + 1];  // normalised when built
    ASSERT_EQ(track.evaluate(t, cursor).coeffs(), slerp_shortest(a, b, s).coeffs()) << "t " << t;
  }
}

// ---- validation -------------------------------------------------------------------

TEST(TrackArrays, validate__values_size_mismatch) {
  EXPECT_TRUE(fails_with(Vec3Track::build({0, 1, 2}, {Vec3::Zero(), Vec3::Zero()}, Interpolation::kLinear).status(),
                         "keyValues has 2 entries but keyTimes has 3"));
}

TEST(TrackArrays, validate__cubic_tangent_size_mismatch) {
  const std::vector<Vec3> two(2, Vec3::Zero()), one(1, Vec3::Zero());
  EXPECT_TRUE(fails_with(Vec3Track::build({0, 1}, two, Interpolation::kCubicSpline, one, two).status(),
                         "inTangents has 1 entries but keyTimes has 2"));
  EXPECT_TRUE(fails_with(Vec3Track::build({0, 1}, two, Interpolation::kCubicSpline, two, {}).status(),
                         "outTangents has 0 entries"));
}

TEST(TrackArrays, validate__tangents_on_non_cubic_track) {
  const std::vector<Vec3> two(2, Vec3::Zero());
  EXPECT_TRUE(fails_with(Vec3Track::build({0, 1}, two, Interpolation::kLinear, two, two).status(),
                         "only cubic spline tracks use tangents"));
}

TEST(TrackArrays, validate__bad_interpolation) {
  EXPECT_TRUE(fails_with(Vec3Track::build({0}, {Vec3::Zero()}, static_cast<Interpolation>(3)).status(),
                         "interpolation: 3 is not an interpolation"));
}

TEST(TrackArrays, validate__unsorted_duplicate_and_nonfinite_times) {
  const std::vector<Vec3> three(3, Vec3::Zero());
  EXPECT_TRUE(fails_with(Vec3Track::build({0, 2, 1}, three, Interpolation::kLinear).status(),
                         "keys[2].time: 1 is before keys[1].time 2"));
  EXPECT_TRUE(fails_with(Vec3Track::build({0, 1, 1}, three, Interpolation::kLinear).status(),
                         "keys[2].time: 1 duplicates keys[1].time 1"));
  EXPECT_TRUE(fails_with(Vec3Track::build({0, kNaN, 2}, three, Interpolation::kLinear).status(),
                         "keys[1].time: must be finite"));
}

TEST(TrackArrays, validate__nonfinite_values_and_tangents) {
  EXPECT_TRUE(fails_with(Vec3Track::build({0, 1}, {Vec3::Zero(), Vec3(0, kNaN, 0)}, Interpolation::kLinear).status(),
                         "keyValues[1]: has a NaN or infinite component"));
  const std::vector<Quat> two(2, Quat::Identity());
  std::vector<Quat> bad = two;
  bad[0].x() = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(fails_with(QuatTrack::build({0, 1}, two, Interpolation::kCubicSpline, two, bad).status(),
                         "outTangents[0]"));
}

TEST(TrackArrays, validate__zero_quaternion) {
  EXPECT_TRUE(fails_with(QuatTrack::build({0, 1}, {Quat::Identity(), Quat(0, 0, 0, 0)}, Interpolation::kLinear).status(),
                         "keyValues[1]: the zero quaternion is not a rotation"));
}

// ---- jobs -------------------------------------------------------------------------

TEST(SampleTracksJob, validate__rejects_each_documented_failure) {
  std::vector<QuatTrack> tracks = {make_track<Quat>({0, 1}, {about_z(0), about_z(90)}, Interpolation::kLinear)};
  std::vector<Cursor> cursors(1), none;
  std::vector<Quat> output(1), empty;
  SampleQuatTracksJob job;
  job.tracks = tracks;
  job.cursors = cursors;
  job.output = output;
  job.time = 0.5;
  EXPECT_TRUE(job.validate()) << "a well-formed job should validate";
  ASSERT_TRUE(job.run());
  EXPECT_TRUE(same_rotation(output[0], about_z(45), kTight));
  job.cursors = none;
  EXPECT_FALSE(job.validate()) << "fewer cursors than tracks should be rejected";
  job.cursors = cursors;
  job.output = empty;
  EXPECT_FALSE(job.validate()) << "fewer outputs than tracks should be rejected";
  EXPECT_FALSE(job.run()) << "run() should refuse an invalid job";
  job.output = output;
  job.time = kNaN;
  EXPECT_FALSE(job.validate()) << "a NaN time should be rejected";
  SampleVec3TracksJob empty_job;
  EXPECT_TRUE(empty_job.run()) << "an empty job is valid";
}

TEST(SlerpShortest, endpoints_and_nearly_equal_rotations) {
  const Quat a = about_z(10), b = about_z(10.000001);
  EXPECT_TRUE(same_rotation(slerp_shortest(a, b, 0.5), about_z(10.0000005), 1e-12)) << "nearly equal: lerp branch";
  EXPECT_TRUE(same_rotation(slerp_shortest(about_z(0), about_z(179), 1.0), about_z(179), kTight));
  EXPECT_NEAR(slerp_shortest(about_z(0), about_z(120), 0.3).norm(), 1.0, kTight);
  EXPECT_TRUE(same_rotation(slerp_shortest(about_z(0), about_z(120), 0.5), about_z(60), kTight));
}

}  // namespace
}  // namespace rigel::ops::anim
