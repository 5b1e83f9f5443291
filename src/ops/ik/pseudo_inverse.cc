#include "rigel/ops/ik/pseudo_inverse.h"

#include "bend_math.h"
#include "ik_math.h"

namespace rigel::ops::ik {

bool PseudoInverseJob::validate() const {
  const std::size_t n = positions.size();
  if (n < 2 || solved.size() != n) return false;
  if (!turns.empty() && turns.size() != n) return false;
  if (detail::overlap(solved.data(), n, positions.data(), n)) return false;
  if (detail::overlap(turns.data(), turns.size(), positions.data(), n)) return false;
  if (detail::overlap(turns.data(), turns.size(), solved.data(), n)) return false;
  for (const Vec3& p : positions)
    if (!detail::all_finite(p)) return false;
  return detail::all_finite(target);
}

bool PseudoInverseJob::run() const {
  if (!validate()) return false;
  const std::size_t n = positions.size();
  const Vec3 dp = target - positions[n - 1];
  for (std::size_t i = 0; i < n; ++i)
    solved[i] = positions[i] + dp * (static_cast<double>(i) / static_cast<double>(n - 1));
  if (keep_lengths) {
    for (std::size_t i = 1; i < n; ++i) {
      const double len = (positions[i] - positions[i - 1]).norm();
      const Vec3 dir = solved[i] - solved[i - 1];
      solved[i] = solved[i - 1] +
                  (dir.norm() > 1e-300 ? Vec3(dir.normalized() * len) : Vec3(positions[i] - positions[i - 1]));
    }
  }
  if (!turns.empty()) {
    for (std::size_t i = 0; i + 1 < n; ++i)
      turns[i] = detail::swing(positions[i + 1] - positions[i], solved[i + 1] - solved[i]);
    turns[n - 1] = Mat3::Identity();
  }
  return true;
}

}  // namespace rigel::ops::ik
