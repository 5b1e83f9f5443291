#pragma once
// Shared helpers for the deform tests: comparisons that print both sides,
// seeded random skins and matrices, and a naive double-precision reference
// for linear blend skinning (OpenSubdiv's way: the optimised kernels against
// a slow, obvious loop).

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "rigel/math/types.h"
#include "rigel/ops/deform/skin.h"
#include "rigel/ops/deform/skinning.h"
#include "rigel/ops/deform/vertex.h"

namespace rigel::ops::testing {

using math::Mat3;
using math::Mat4;
using math::Quat;
using math::Vec3;

// |a - b| <= tolerance per coordinate, for every vertex.
inline ::testing::AssertionResult points_near(std::span<const Vec3f> actual, std::span<const Vec3f> expected,
                                              double tolerance) {
  if (actual.size() != expected.size()) {
    return ::testing::AssertionFailure() << "sizes differ: " << actual.size() << " vs " << expected.size();
  }
  for (std::size_t v = 0; v < actual.size(); ++v) {
    const double diff = (actual[v].cast<double>() - expected[v].cast<double>()).cwiseAbs().maxCoeff();
    if (!(diff <= tolerance)) {
      return ::testing::AssertionFailure()
             << "vertex " << v << ": " << actual[v].transpose() << " vs " << expected[v].transpose() << " (difference "
             << diff << " > " << tolerance << ")";
    }
  }
  return ::testing::AssertionSuccess();
}

// Equal as floats (==, so 0 equals -0), every coordinate of every vertex.
inline ::testing::AssertionResult points_equal(std::span<const Vec3f> actual, std::span<const Vec3f> expected) {
  if (actual.size() != expected.size()) {
    return ::testing::AssertionFailure() << "sizes differ: " << actual.size() << " vs " << expected.size();
  }
  for (std::size_t v = 0; v < actual.size(); ++v) {
    if (!(actual[v].array() == expected[v].array()).all()) {
      return ::testing::AssertionFailure()
             << "vertex " << v << ": " << actual[v].transpose() << " vs " << expected[v].transpose() << " (not equal)";
    }
  }
  return ::testing::AssertionSuccess();
}

// The same bytes.
inline ::testing::AssertionResult points_identical(std::span<const Vec3f> actual, std::span<const Vec3f> expected) {
  if (actual.size() != expected.size()) {
    return ::testing::AssertionFailure() << "sizes differ: " << actual.size() << " vs " << expected.size();
  }
  for (std::size_t v = 0; v < actual.size(); ++v) {
    if (std::memcmp(actual[v].data(), expected[v].data(), sizeof(Vec3f)) != 0) {
      return ::testing::AssertionFailure() << "vertex " << v << ": " << actual[v].transpose() << " vs "
                                           << expected[v].transpose() << " (bits differ)";
    }
  }
  return ::testing::AssertionSuccess();
}

inline Mat4 to_mat4(const Mat3& linear, const Vec3& translate = Vec3::Zero()) {
  Mat4 m = Mat4::Identity();
  m.topLeftCorner<3, 3>() = linear;
  m.topRightCorner<3, 1>() = translate;
  return m;
}

inline Mat3 rot_x(double a) { return Eigen::AngleAxisd(a, Vec3::UnitX()).toRotationMatrix(); }

class Random {
 public:
  explicit Random(unsigned seed) : engine_(seed) {}
  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(engine_); }
  int index(int count) { return std::uniform_int_distribution<int>(0, count - 1)(engine_); }
  Vec3 vec3(double lo, double hi) { return Vec3(uniform(lo, hi), uniform(lo, hi), uniform(lo, hi)); }
  Vec3f vec3f(double lo, double hi) { return vec3(lo, hi).cast<float>(); }
  Quat quat() {
    return Quat(Eigen::Vector4d(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1), uniform(-1, 1))).normalized();
  }
  Mat4 rigid() { return to_mat4(quat().toRotationMatrix(), vec3(-2, 2)); }
  // Rotation, translation, scale in [lo, hi] per axis, and a little shear.
  Mat4 affine(double lo = 0.5, double hi = 2.0) {
    Mat3 shear = Mat3::Identity();
    shear(0, 1) = uniform(-0.2, 0.2);
    shear(1, 2) = uniform(-0.2, 0.2);
    return to_mat4(quat().toRotationMatrix() * shear * vec3(lo, hi).asDiagonal(), vec3(-2, 2));
  }

  // Per-vertex influence lists: 1..max_influences distinct joints each,
  // random positive weights (not normalised: the builder does it).
  std::vector<std::vector<SkinInfluence>> influences(std::size_t vertices, std::size_t joints, int max_influences) {
    std::vector<std::vector<SkinInfluence>> out(vertices);
    for (auto& list : out) {
      const int count = 1 + index(max_influences);
      while (static_cast<int>(list.size()) < count) {
        const std::int64_t j = index(static_cast<int>(joints));
        bool taken = false;
        for (const SkinInfluence& e : list) taken |= e.joint == j;
        if (!taken) list.push_back({j, uniform(0.05, 1.0)});
      }
    }
    return out;
  }

 private:
  std::mt19937 engine_;
};

inline Skin build_or_die(std::span<const std::vector<SkinInfluence>> vertices, std::size_t joints,
                         bool fixed_layout = true) {
  SkinBuildOptions options;
  options.fixed_layout = fixed_layout;
  Result<Skin> skin = make_skin(vertices, joints, options);
  EXPECT_TRUE(skin.is_ok()) << skin.status().message();
  return skin.is_ok() ? std::move(skin).value() : Skin{};
}

inline std::vector<SkinMatrix> linear_matrices(std::span<const Mat4> matrices) {
  std::vector<SkinMatrix> out;
  for (const Mat4& m : matrices) out.push_back(SkinMatrix::from(m));
  return out;
}

inline std::vector<DualQuatSkinMatrix> dual_quat_matrices(std::span<const Mat4> matrices) {
  std::vector<DualQuatSkinMatrix> out;
  for (const Mat4& m : matrices) out.push_back(DualQuatSkinMatrix::from(m));
  return out;
}

// Naive reference: sum_k w_k (M_k p) in double, from the skin's float
// weights and the float matrices the kernels read.
inline std::vector<Vec3f> reference_lbs(const Skin& skin, std::span<const SkinMatrix> matrices,
                                        std::span<const Vec3f> points) {
  std::vector<Vec3f> out;
  for (std::size_t v = 0; v < skin.vertex_count(); ++v) {
    Vec3 sum = Vec3::Zero();
    for (std::uint32_t k = skin.offsets()[v]; k < skin.offsets()[v + 1]; ++k) {
      const Mat4 m = matrices[skin.joints()[k]].to_mat4();
      sum +=
          double{skin.weights()[k]} * (m.topLeftCorner<3, 3>() * points[v].cast<double>() + m.topRightCorner<3, 1>());
    }
    out.push_back(sum.cast<float>());
  }
  return out;
}

inline std::vector<Vec3f> random_points(Random& random, std::size_t count, double extent = 2.0) {
  std::vector<Vec3f> out;
  for (std::size_t i = 0; i < count; ++i) out.push_back(random.vec3f(-extent, extent));
  return out;
}

inline std::vector<Vec3f> random_normals(Random& random, std::size_t count) {
  std::vector<Vec3f> out;
  for (std::size_t i = 0; i < count; ++i) out.push_back(random.vec3(-1, 1).normalized().cast<float>());
  return out;
}

}  // namespace rigel::ops::testing
