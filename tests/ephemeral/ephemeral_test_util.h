#pragma once
// Helpers for the ephemeral tests: small skeletons built joint by joint,
// world positions, and checked calls.

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "rigel/ephemeral/rig.h"
#include "rigel/ephemeral/session.h"
#include "rigel/io/scene_file.h"
#include "rigel/math/transform.h"
#include "rigel/scene/scene.h"
#include "rigel/scene/transform_types.h"

namespace rigel::ephemeral::testing {

using graph::Plug;
using math::Mat4;
using math::Quat;
using math::Vec3;
namespace xform = scene::xform;

inline ::testing::AssertionResult succeeded(const Status& status) {
  if (status.is_ok()) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "failed (" << error_code_name(status.code()) << "): " << status.message();
}

inline ::testing::AssertionResult vec_near(const Vec3& a, const Vec3& b, double tolerance) {
  if ((a - b).norm() <= tolerance) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "(" << a.transpose() << ") vs (" << b.transpose() << "), distance "
                                       << (a - b).norm();
}

inline std::unique_ptr<scene::Scene> make_scene() { return std::make_unique<scene::Scene>(default_registry()); }

// A joint under `parent` at local `translate` with Euler `rotate_deg`.
inline NodeId joint(scene::Scene& s, const std::string& name, NodeId parent, const Vec3& translate,
                    const Vec3& rotate_deg = Vec3::Zero()) {
  Result<NodeId> j = s.create(scene::kJointType, name, parent);
  EXPECT_TRUE(j.is_ok()) << j.status().message();
  EXPECT_TRUE(succeeded(s.graph().set_value(Plug{*j, xform::kTranslate, -1}, translate)));
  EXPECT_TRUE(succeeded(s.graph().set_value(Plug{*j, xform::kRotate, -1}, rotate_deg)));
  return *j;
}

inline Mat4 world(scene::Scene& s, NodeId id) { return s.world_matrix(id); }
inline Vec3 position(scene::Scene& s, NodeId id) { return s.world_matrix(id).topRightCorner<3, 1>(); }

// shoulder (origin) -> elbow (1, 0, 0) bent 30 degrees about z -> wrist (1, 0, 0).
struct Arm {
  std::unique_ptr<scene::Scene> scene;
  NodeId shoulder, elbow, wrist;
  SetupResult rig;
  NodeId c(int i) const { return rig.controls[i]; }
};

inline Arm make_arm() {
  Arm arm;
  arm.scene = make_scene();
  arm.shoulder = joint(*arm.scene, "shoulder", {}, Vec3::Zero());
  arm.elbow = joint(*arm.scene, "elbow", arm.shoulder, Vec3(1, 0, 0), Vec3(0, 0, 30));
  arm.wrist = joint(*arm.scene, "wrist", arm.elbow, Vec3(1, 0, 0));
  Result<SetupResult> r = setup_ephemeral(*arm.scene);
  EXPECT_TRUE(r.is_ok()) << r.status().message();
  arm.rig = *r;
  return arm;
}

// A chain of `count` joints along x, one unit apart, each bent `bend_deg` about z.
struct Chain {
  std::unique_ptr<scene::Scene> scene;
  std::vector<NodeId> joints;
  SetupResult rig;
};

inline Chain make_chain(int count, double bend_deg = 0.0) {
  Chain chain;
  chain.scene = make_scene();
  NodeId parent;
  for (int i = 0; i < count; ++i) {
    parent = joint(*chain.scene, std::string("j").append(std::to_string(i)), parent, i == 0 ? Vec3::Zero() : Vec3(1, 0, 0),
                   Vec3(0, 0, i == 0 ? 0.0 : bend_deg));
    chain.joints.push_back(parent);
  }
  Result<SetupResult> r = setup_ephemeral(*chain.scene);
  EXPECT_TRUE(r.is_ok()) << r.status().message();
  chain.rig = *r;
  return chain;
}

inline Quat about_z(double degrees) { return Quat(Eigen::AngleAxisd(math::to_radians(degrees), Vec3::UnitZ())); }

}  // namespace rigel::ephemeral::testing
