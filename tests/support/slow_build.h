#pragma once
// Unoptimised builds (the sanitizer build: no NDEBUG) run the exhaustive and
// randomised loops of the tests on a sample, kSlowBuildDivisor times
// smaller; the Release build runs them whole. A loop scaled so says so.

namespace rigel::testing {

#ifdef NDEBUG
inline constexpr int kSlowBuildDivisor = 1;
#else
inline constexpr int kSlowBuildDivisor = 5;
#endif

}  // namespace rigel::testing
