#pragma once
// Private to rigel_math (and its tests): the instruction-set variants behind
// LocalToWorldJob::run(). Each computes every world matrix of a job that has
// passed validate(); run() picks the fastest one the CPU supports. They are
// declared here so that the tests can check every variant the test machine
// can execute against a naive loop, not only the one run() picks.

#include "rigel/math/local_to_world.h"

#if (defined(__x86_64__) || defined(_M_X64)) && (defined(__GNUC__) || defined(__clang__))
// SSE2 is part of x86-64; AVX2 + FMA is compiled per function (target
// attribute) and chosen at run time, so the build needs no -m flags.
#define RIGEL_MATH_X86_KERNELS 1
#else
#define RIGEL_MATH_X86_KERNELS 0
#endif

namespace rigel::math::detail {

// Plain C++: any CPU.
void local_to_world_portable(const LocalToWorldJob& job);

#if RIGEL_MATH_X86_KERNELS
void local_to_world_sse2(const LocalToWorldJob& job);
// Only on a CPU where avx2_fma_supported().
void local_to_world_avx2_fma(const LocalToWorldJob& job);
bool avx2_fma_supported();
#endif

}  // namespace rigel::math::detail
