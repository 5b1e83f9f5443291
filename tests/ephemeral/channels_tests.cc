// How a drag writes channels: every moved control's new world goes back
// through the scene's world-to-local routine (Scene::channels_for_world,
// keeping scale, shear and rotate axis, the rotation nearest the current
// one), so controls with a rotate axis, shear, pivots or a quaternion
// rotation land where the solve put them, in every mode.
#include <gtest/gtest.h>

#include "ephemeral_test_util.h"

namespace rigel::ephemeral::testing {
namespace {

::testing::AssertionResult rigid_near(const Mat4& a, const Mat4& b, double tolerance) {
  const double d = (math::rigid_part(a) - math::rigid_part(b)).cwiseAbs().maxCoeff();
  if (d <= tolerance) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "rotation and translation differ by " << d << ":\n" << a << "\nvs\n" << b;
}

Mat4 moved(const Mat4& world, const Vec3& translate, const Quat& rotate) {
  Mat4 out = world;
  out.topLeftCorner<3, 3>() = rotate.toRotationMatrix() * world.topLeftCorner<3, 3>();
  out.topRightCorner<3, 1>() += translate;
  return out;
}

void release_and_undo(Session& session, Graph& graph) {
  session.release();
  EXPECT_TRUE(graph.undo()) << "the gesture is one undo step";
}

TEST(EphemeralChannels, drag_to_reaches_the_target_through_rotate_axis_shear_pivots_and_quaternions) {
  Arm arm = make_arm();
  Graph& g = arm.scene->graph();
  const NodeId wrist = arm.c(2);
  ASSERT_TRUE(succeeded(g.set_value(Plug{wrist, xform::kRotateAxis, -1}, Vec3(10, -20, 5))));
  ASSERT_TRUE(succeeded(g.set_value(Plug{wrist, xform::kShear, -1}, Vec3(0.1, 0, -0.2))));
  ASSERT_TRUE(succeeded(g.set_value(Plug{wrist, xform::kRotatePivot, -1}, Vec3(0.2, 0.1, 0))));
  ASSERT_TRUE(succeeded(g.set_value(Plug{wrist, xform::kScalePivot, -1}, Vec3(0, -0.3, 0.1))));
  ASSERT_TRUE(succeeded(g.set_value(Plug{arm.c(1), xform::kRotateMode, -1}, xform::kQuaternionMode)));
  ASSERT_TRUE(succeeded(g.set_value(Plug{arm.c(1), xform::kRotateQuaternion, -1}, about_z(30))));
  for (Mode mode : {Mode::kForward, Mode::kSuspended, Mode::kInverse, Mode::kPseudoInverse, Mode::kMagnet}) {
    SCOPED_TRACE(mode_name(mode));
    Session session(*arm.scene);
    session.set_mode(mode);
    session.select({wrist});
    const Mat4 target = moved(world(*arm.scene, wrist), Vec3(-0.2, 0.3, 0.1), about_z(25));
    ASSERT_TRUE(succeeded(session.drag_to(wrist, target)));
    EXPECT_TRUE(rigid_near(world(*arm.scene, wrist), target, 1e-9))
        << "the grabbed control should land on its target, its pivots and rotate axis accounted for";
    EXPECT_EQ(std::get<Vec3>(g.node(wrist)->value(xform::kShear)), Vec3(0.1, 0, -0.2)) << "shear is never written";
    EXPECT_EQ(std::get<Vec3>(g.node(wrist)->value(xform::kRotateAxis)), Vec3(10, -20, 5))
        << "rotate axis is never written";
    release_and_undo(session, g);
  }
}

TEST(EphemeralChannels, euler_rotations_stay_nearest_the_current_angles) {
  Arm arm = make_arm();
  Graph& g = arm.scene->graph();
  ASSERT_TRUE(succeeded(g.set_value(Plug{arm.c(0), xform::kRotate, -1}, Vec3(0, 0, 350))));
  Session session(*arm.scene);
  session.select({arm.c(0)});
  ASSERT_TRUE(succeeded(session.drag(Delta{Vec3::Zero(), about_z(-20)})));
  EXPECT_TRUE(vec_near(std::get<Vec3>(g.node(arm.c(0))->value(xform::kRotate)), Vec3(0, 0, 330), 1e-9))
      << "a turn of -20 from 350 writes 330 (not -30): keys between them interpolate the short way";
}

}  // namespace
}  // namespace rigel::ephemeral::testing
