#pragma once
// Helpers for the scene tests: matrix comparison with a readable failure,
// and random transform hierarchies built deterministically from a seed.

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "rigel/math/types.h"
#include "rigel/scene/scene.h"

namespace rigel::scene::testing {

using math::Mat4;
using math::Quat;
using math::Vec3;

// |a - b| <= tolerance * max(1, largest entry of b), entry by entry.
inline ::testing::AssertionResult matrix_near(const Mat4& a, const Mat4& b, double tolerance) {
  const double scale = std::max(1.0, b.cwiseAbs().maxCoeff());
  const double diff = (a - b).cwiseAbs().maxCoeff();
  if (diff <= tolerance * scale) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "largest difference " << diff << " exceeds " << tolerance * scale << ":\n"
                                       << a << "\n  vs\n"
                                       << b;
}

inline Mat4 rows(std::initializer_list<double> values) {
  Mat4 m;
  auto it = values.begin();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m(r, c) = *it++;
  return m;
}

// Status as a gtest assertion, so that a failed setup step prints its reason.
inline ::testing::AssertionResult succeeded(const Status& status) {
  if (status.is_ok()) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "failed (" << error_code_name(status.code()) << "): " << status.message();
}

inline Status set(Scene& scene, NodeId id, AttrIndex attr, graph::Value value) {
  return scene.graph().set_value(graph::Plug{id, attr, -1}, std::move(value));
}

// What random_channels() may set.
struct ChannelOptions {
  bool pivots = true;       // rotate/scale pivots and their translates, rotate axis
  bool shear = true;
  bool offset_parent = true;
  bool negative_scale = true;
};

// Sets random channels on a transform (and joint orient on joints): every
// rotate order, euler or quaternion mode, scale, shear, pivots, rotate axis,
// offset parent matrix. Values stay moderate so long chains keep precision.
inline void random_channels(Scene& scene, NodeId id, std::mt19937& rng, const ChannelOptions& options = {}) {
  auto u = [&](double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); };
  auto v3 = [&](double lo, double hi) { return Vec3(u(lo, hi), u(lo, hi), u(lo, hi)); };
  auto chance = [&](double p) { return std::bernoulli_distribution(p)(rng); };
  auto check = [&](Status s) { EXPECT_TRUE(s.is_ok()) << s.message(); };
  check(set(scene, id, xform::kTranslate, v3(-2, 2)));
  check(set(scene, id, xform::kRotate, v3(-180, 180)));
  check(set(scene, id, xform::kRotateOrder, std::int64_t{std::uniform_int_distribution<int>(0, 5)(rng)}));
  if (chance(0.2)) {
    check(set(scene, id, xform::kRotateMode, std::int64_t{1}));
    check(set(scene, id, xform::kRotateQuaternion, Quat(u(-1, 1), u(-1, 1), u(-1, 1), u(-1, 1))));
  }
  Vec3 scale = v3(0.7, 1.3);
  if (options.negative_scale && chance(0.1)) scale.x() = -scale.x();
  check(set(scene, id, xform::kScale, scale));
  if (options.shear && chance(0.5)) check(set(scene, id, xform::kShear, v3(-0.3, 0.3)));
  if (options.pivots && chance(0.5)) {
    check(set(scene, id, xform::kRotateAxis, v3(-45, 45)));
    check(set(scene, id, xform::kRotatePivot, v3(-1, 1)));
    check(set(scene, id, xform::kRotatePivotTranslate, v3(-1, 1)));
    check(set(scene, id, xform::kScalePivot, v3(-1, 1)));
    check(set(scene, id, xform::kScalePivotTranslate, v3(-1, 1)));
  }
  if (options.offset_parent && chance(0.3)) {
    Mat4 offset = Mat4::Identity();
    offset.topLeftCorner<3, 3>() = Quat(u(-1, 1), u(-1, 1), u(-1, 1), u(-1, 1)).normalized().toRotationMatrix();
    offset.topRightCorner<3, 1>() = v3(-1, 1);
    check(set(scene, id, xform::kOffsetParentMatrix, offset));
  }
  const graph::Node& n = *scene.graph().node(id);
  const AttrIndex jo = n.type().attr_find("jointOrient");
  if (jo != graph::kNoAttr) check(set(scene, id, jo, v3(-90, 90)));
}

// A random forest of `count` transforms (mostly joints), parents before
// children: each node goes under a recent node (long chains), any earlier
// node (bushy trees) or becomes a new root. The same seed builds the same
// scene, node for node; the undo history is cleared.
inline std::vector<NodeId> random_forest(Scene& scene, std::uint32_t seed, int count, const ChannelOptions& options = {}) {
  std::mt19937 rng(seed);
  std::vector<NodeId> ids;
  ids.reserve(static_cast<std::size_t>(count));
  static const char* kTypes[] = {kJointType, kJointType, kJointType, kTransformType, kControlType, kLocatorType};
  for (int i = 0; i < count; ++i) {
    NodeId parent;
    const int pick = std::uniform_int_distribution<int>(0, 99)(rng);
    if (!ids.empty() && pick >= 2) {
      const std::size_t n = ids.size();
      const std::size_t back =
          pick < 50 ? std::uniform_int_distribution<std::size_t>(1, std::min<std::size_t>(n, 4))(rng)
                    : std::uniform_int_distribution<std::size_t>(1, n)(rng);
      parent = ids[n - back];
    }
    std::string name = "j";
    name += std::to_string(i);
    Result<NodeId> id = scene.create(kTypes[std::uniform_int_distribution<int>(0, 5)(rng)], name, parent);
    EXPECT_TRUE(id.is_ok()) << id.status().message();
    if (!id.is_ok()) return ids;
    ids.push_back(*id);
    random_channels(scene, *id, rng, options);
  }
  scene.graph().clear_history();
  return ids;
}

}  // namespace rigel::scene::testing
