#pragma once
// Scalar animation curves with Maya's tangent model, and the job that samples
// many of them at one time (STYLE.md §3).
//
// A curve is a list of keys sorted by time. Between two keys the curve is a
// cubic: a Hermite spline in time on unweighted curves, a Bezier in both
// time and value on weighted curves. Each key has an in and an out tangent,
// each with a type that says how its slope is found (from the key's
// neighbours, or given); weighted curves add a handle length per side.
// Outside the keys, pre- and post-infinity modes extend the curve.
//
// Time curves use seconds; driven-key curves use whatever unit their input
// attribute has. Values are unit-agnostic: a curve that drives an angle
// attribute holds degrees, as the attribute does.

#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "rigel/base/status.h"

namespace rigel::ops::anim {

// How a tangent's slope is found (Maya's tangent types, same meaning).
// "Neighbours" are the keys just before and after; end keys have one.
enum class TangentType : std::uint8_t {
  kFixed = 0,     // the key's own slope (Key::in_slope / Key::out_slope)
  kLinear = 1,    // toward the neighbour on this side; flat at an end key
  kFlat = 2,      // slope 0
  kStep = 3,      // out: hold this key's value until the next key; in: flat
  kStepNext = 4,  // out: take the next key's value right after this key; in: flat
  kSpline = 5,    // Maya's "spline": slope of the line through both neighbours
                  // (toward the only neighbour at an end key)
  kClamped = 6,   // spline, but flat when a neighbour's value is within
                  // kClampedTolerance of this key's (Maya's rule)
  kPlateau = 7,   // auto, but flat wherever auto would have to limit the slope
  kAuto = 8,      // Maya's auto: spline with the slope limited so the curve
                  // never overshoots the neighbouring key values; flat at
                  // end keys and at local extremes (the default)
};
inline constexpr int kTangentTypeCount = 9;

// Maya's clamped rule: a neighbour this close in value flattens the tangent.
// An absolute value in the curve's unit (Maya uses the same constant).
inline constexpr double kClampedTolerance = 0.05;

// The curve outside its keys (Maya's pre/post infinity).
enum class Infinity : std::uint8_t {
  kConstant = 0,     // the end key's value
  kLinear = 1,       // the line through the end key along its outer tangent
  kCycle = 2,        // the keyed range repeated
  kCycleOffset = 3,  // repeated, each repetition offset by (last - first value)
  kOscillate = 4,    // repeated, every other repetition mirrored in time
};
inline constexpr int kInfinityCount = 5;

// Names used in files and node enums, indexed by the enum value:
// "fixed", "linear", "flat", "step", "stepNext", "spline", "clamped",
// "plateau", "auto"; and "constant", "linear", "cycle", "cycleOffset",
// "oscillate".
std::span<const std::string_view> tangent_type_names();
std::span<const std::string_view> infinity_names();

// The default handle length of a weighted tangent: a third of the span, which
// makes a weighted segment equal the unweighted (Hermite) one.
inline constexpr double kDefaultWeight = 1.0 / 3.0;

struct Key {
  double time = 0.0;   // seconds for time curves; the input's unit for driven keys
  double value = 0.0;  // the curve's unit
  TangentType in_type = TangentType::kAuto;
  TangentType out_type = TangentType::kAuto;
  // kFixed only: slope of the tangent, value units per time unit (Maya's
  // tangent angle a in these units is atan(slope)).
  double in_slope = 0.0;
  double out_slope = 0.0;
  // Weighted curves only: length of the Bezier handle along time, as a
  // fraction of the span to the neighbouring key on that side. Any type but
  // step uses it. Lengths above 1 are shortened to 1 (so time stays
  // monotonic along the segment; Maya projects them instead).
  double in_weight = kDefaultWeight;
  double out_weight = kDefaultWeight;
};

struct CurveSettings {
  bool weighted = false;
  Infinity pre_infinity = Infinity::kConstant;
  Infinity post_infinity = Infinity::kConstant;
};

// Checks keys and settings; ok, or the first problem found, naming the key
// ("keys[3].time ..."). Fails:
// - if a key's time or value is NaN or infinite;
// - if a key's time is not after the previous key's (unsorted or duplicate);
// - if a tangent type is not one of TangentType (a cast from bad data);
// - if a kFixed tangent's slope is NaN or infinite;
// - on weighted curves, if a weight is NaN, infinite or negative;
// - if an infinity mode is not one of Infinity.
Status validate_keys(std::span<const Key> keys, const CurveSettings& settings = {});

// The index of the segment a sequential playback is in, so that the next
// evaluation starts there instead of searching (ozz's SamplingJob context,
// but keyed on nothing: any value is safe). A cursor that belongs to another
// curve, or one whose curve was rebuilt, still gives exact results: it only
// costs a search.
struct Cursor {
  std::uint32_t key = 0;  // the key that starts the segment last evaluated
};

namespace detail {
// One segment between two keys, precomputed: a polynomial in (t - t0) for
// Hermite, step and linear segments, or a Bezier's value polynomial in its
// parameter u (time polynomial in BezierTime). 64 bytes, one cache line: the
// cursor's check and the evaluation read nothing else.
struct alignas(64) Segment {
  double t0 = 0.0, t1 = 0.0;  // key times: the segment covers [t0, t1)
  double c[4] = {};           // c0 + c1 x + c2 x^2 + c3 x^3
  std::uint32_t kind = 0;     // detail::SegmentKind
};
// Time along a weighted segment as a polynomial in u: x(u) = ((x3 u + x2) u + x1) u,
// normalised to [0, 1] over the segment.
struct BezierTime {
  double x1 = 1.0, x2 = 0.0, x3 = 0.0;
};
// What the infinity modes need: the end keys and their outer slopes.
struct CurveEnds {
  double first_time = 0.0, last_time = 0.0;
  double first_value = 0.0, last_value = 0.0;
  double pre_slope = 0.0, post_slope = 0.0;
  Infinity pre = Infinity::kConstant, post = Infinity::kConstant;
};
}  // namespace detail

// A compiled curve: keys plus one precomputed segment per key interval, so
// evaluation is a cursor check and a cubic. Build it with build(); it is
// immutable afterwards (rebuild to edit). Copyable and movable.
class AnimCurve {
 public:
  // An empty curve: no keys, evaluates to 0 everywhere.
  AnimCurve() = default;

  // Fails as validate_keys(), naming the key.
  static Result<AnimCurve> build(std::vector<Key> keys, const CurveSettings& settings = {});

  // The value at `t`. `cursor` is read as a hint and updated: sequential
  // playback (forward or backward) touches O(1) keys, a jump costs a binary
  // search. NaN `t` gives NaN; an empty curve gives 0, a single key its value.
  double evaluate(double t, Cursor& cursor) const;
  // The same with a binary search every time.
  double evaluate(double t) const;

  std::span<const Key> keys() const { return keys_; }
  std::size_t key_count() const { return keys_.size(); }
  const CurveSettings& settings() const { return settings_; }
  // The slopes the tangent types resolved to (value units per time unit);
  // step tangents count as 0. `key` < key_count().
  double in_slope(std::size_t key) const { return in_slopes_[key]; }
  double out_slope(std::size_t key) const { return out_slopes_[key]; }

 private:
  double evaluate_slow(double t, Cursor& cursor) const;
  double evaluate_inside(double t, Cursor& cursor) const;

  std::vector<detail::Segment> segments_;   // key_count() - 1 of them
  std::vector<detail::BezierTime> bezier_;  // weighted curves: one per segment
  std::vector<double> times_;               // key times, for the search
  detail::CurveEnds ends_;
  std::vector<Key> keys_;
  std::vector<double> in_slopes_, out_slopes_;
  CurveSettings settings_;
};

// Keys as parallel arrays: what an animCurve node stores in its attributes.
// `times` and `values` have one entry per key; every other array is either
// empty (each key takes the default: kAuto, slope 0, weight 1/3) or has one
// entry per key. Tangent types are the TangentType values as integers (an
// enum attribute's storage).
struct CurveArrays {
  std::span<const double> times;
  std::span<const double> values;
  std::span<const std::int64_t> in_types;
  std::span<const std::int64_t> out_types;
  std::span<const double> in_slopes;
  std::span<const double> out_slopes;
  std::span<const double> in_weights;
  std::span<const double> out_weights;
  CurveSettings settings;

  // Fails as validate_keys(), and also:
  // - if `values` or an optional array that is not empty has a size other
  //   than times.size() (naming the array and both sizes);
  // - if a tangent type is outside [0, kTangentTypeCount).
  Status validate() const;
  // Key `index` (< times.size()) with the defaults filled in. Needs a valid
  // `*this` (tangent types are taken as they are).
  Key key(std::size_t index) const;
  // All keys; validate() first.
  std::vector<Key> keys() const;
};

// The value of the curve `arrays` describes at `t`, without building an
// AnimCurve: no allocation, a binary search, and only the (at most four)
// keys around `t` read. Gives exactly AnimCurve::evaluate's result. `arrays`
// must have passed validate() (invalid arrays give an unspecified value, but
// never read out of bounds as long as the sizes are consistent).
double evaluate_arrays(const CurveArrays& arrays, double t);

// Samples many curves at one time: the inner loop of playback.
struct SampleCurvesJob {
  // Validates job parameters. Returns false:
  // - if `cursors` or `output` is smaller than `curves`;
  // - if `time` is NaN.
  bool validate() const;
  // output[i] = curves[i].evaluate(time, cursors[i]) for every curve (outputs
  // beyond curves.size() are left alone). Returns false, writing nothing, if
  // the job is not valid.
  bool run() const;

  // Time to sample at, in the curves' time unit (seconds).
  double time = 0.0;
  // The curves, read only.
  std::span<const AnimCurve> curves;
  // One cursor per curve, kept by the caller between runs (sequential
  // playback then costs O(1) per curve). Start them zeroed.
  std::span<Cursor> cursors;
  // One value per curve.
  std::span<double> output;
};

}  // namespace rigel::ops::anim
