#include "rigel/scene/shapes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "rigel/scene/scene.h"
#include "rigel/scene/transform_types.h"
#include "scene_test_util.h"

namespace rigel::scene {
namespace {

using graph::Plug;
using math::Vec3;
using testing::succeeded;

double max_abs_coordinate(const ControlShape& shape) {
  double m = 0.0;
  for (const Vec3& p : shape.points) m = std::max(m, p.cwiseAbs().maxCoeff());
  return m;
}

// ---- shapes ------------------------------------------------------------------

TEST(ControlShapes, every_name_gives_a_unit_sized_strip) {
  const std::vector<std::string> names = control_shape_names();
  EXPECT_EQ(names.size(), 13u) << "the thirteen documented shapes";
  for (const std::string& name : names) {
    std::optional<ControlShape> shape = control_shape(name);
    ASSERT_TRUE(shape.has_value()) << name << " is listed, so it exists";
    EXPECT_GE(shape->points.size(), 2u) << name << " has a strip to draw";
    for (const Vec3& p : shape->points) EXPECT_TRUE(p.allFinite()) << name << ": every point is finite";
    const double extent = max_abs_coordinate(*shape);
    EXPECT_LE(extent, 1.0 + 1e-12) << name << " fits the unit box";
    EXPECT_GE(extent, 0.5) << name << " is about unit size, not a speck";
  }
}

TEST(ControlShapes, size_scales_every_point_exactly) {
  for (const std::string& name : control_shape_names()) {
    const ControlShape unit = *control_shape(name);
    for (double size : {0.25, 3.0, 17.5}) {
      std::optional<ControlShape> scaled = control_shape(name, size);
      ASSERT_TRUE(scaled.has_value()) << name << " at size " << size;
      ASSERT_EQ(scaled->points.size(), unit.points.size()) << name << ": size does not change the point count";
      EXPECT_EQ(scaled->closed, unit.closed) << name << ": size does not change closure";
      for (std::size_t i = 0; i < unit.points.size(); ++i)
        EXPECT_EQ(scaled->points[i], Vec3(unit.points[i] * size)) << name << " point " << i << " scales exactly";
    }
  }
}

TEST(ControlShapes, closed_flags) {
  for (const char* name : {"circle", "square", "diamond", "cross", "arrow", "doubleArrow", "fourArrow",
                           "fourArrowCircle", "triangle"})
    EXPECT_TRUE(control_shape(name)->closed) << name << " is an outline, drawn closed";
  for (const char* name : {"cube", "sphere", "locator", "pin"})
    EXPECT_FALSE(control_shape(name)->closed) << name << " is a path through retraced edges, drawn open";
}

TEST(ControlShapes, flat_shapes_lie_in_the_xz_plane) {
  for (const char* name : {"circle", "square", "diamond", "cross", "arrow", "doubleArrow", "fourArrow",
                           "fourArrowCircle", "triangle"}) {
    const ControlShape shape = *control_shape(name);  // named: a temporary's member would dangle in the loop
    for (const Vec3& p : shape.points) EXPECT_EQ(p.y(), 0.0) << name << " is flat with Y up";
  }
  const ControlShape circle = *control_shape("circle");
  EXPECT_EQ(circle.points.size(), 24u) << "circles have 24 segments";
  for (const Vec3& p : circle.points) EXPECT_NEAR(p.norm(), 1.0, 1e-15) << "circle radius 1";
}

TEST(ControlShapes, cube_strip_covers_all_twelve_edges) {
  const ControlShape cube = *control_shape("cube");
  std::vector<std::pair<Vec3, Vec3>> seen;
  for (std::size_t i = 0; i + 1 < cube.points.size(); ++i) {
    const Vec3 a = cube.points[i], b = cube.points[i + 1];
    EXPECT_EQ((a - b).cwiseAbs().sum(), 2.0) << "segment " << i << " is one cube edge";
    seen.emplace_back(a, b);
  }
  int edges = 0;
  for (int axis = 0; axis < 3; ++axis) {
    for (double u : {-1.0, 1.0}) {
      for (double v : {-1.0, 1.0}) {
        Vec3 a, b;
        a[axis] = -1, b[axis] = 1;
        a[(axis + 1) % 3] = b[(axis + 1) % 3] = u;
        a[(axis + 2) % 3] = b[(axis + 2) % 3] = v;
        bool found = false;
        for (const auto& [p, q] : seen) found = found || (p == a && q == b) || (p == b && q == a);
        EXPECT_TRUE(found) << "edge " << a.transpose() << " - " << b.transpose() << " is drawn";
        edges += found;
      }
    }
  }
  EXPECT_EQ(edges, 12);
}

TEST(ControlShapes, sphere_is_three_joined_circles) {
  const ControlShape sphere = *control_shape("sphere");
  for (const Vec3& p : sphere.points) {
    EXPECT_NEAR(p.norm(), 1.0, 1e-15) << "every point lies on the unit sphere";
    EXPECT_EQ((p.array() == 0.0).count() >= 1, true) << "every point lies on one of the three coordinate planes";
  }
  int xz = 0, xy = 0, yz = 0;
  for (const Vec3& p : sphere.points) {
    xz += p.y() == 0.0;
    xy += p.z() == 0.0;
    yz += p.x() == 0.0;
  }
  EXPECT_GE(xz, 24) << "an XZ circle";
  EXPECT_GE(xy, 24) << "an XY circle";
  EXPECT_GE(yz, 24) << "a YZ circle";
  for (std::size_t i = 0; i + 1 < sphere.points.size(); ++i)
    EXPECT_LT((sphere.points[i + 1] - sphere.points[i]).norm(), 0.27) << "no jump across the sphere at " << i;
}

TEST(ControlShapes, unknown_names_and_bad_sizes_give_nothing) {
  EXPECT_FALSE(control_shape("hexagon").has_value()) << "unknown shape";
  EXPECT_FALSE(control_shape("").has_value()) << "empty name";
  EXPECT_FALSE(control_shape("Circle").has_value()) << "names are case-sensitive";
  EXPECT_FALSE(control_shape("circle", 0.0).has_value()) << "zero size";
  EXPECT_FALSE(control_shape("circle", -1.0).has_value()) << "negative size";
  EXPECT_FALSE(control_shape("circle", std::numeric_limits<double>::quiet_NaN()).has_value()) << "NaN size";
  EXPECT_FALSE(control_shape("circle", std::numeric_limits<double>::infinity()).has_value()) << "infinite size";
}

// ---- colours -----------------------------------------------------------------

TEST(ControlColors, every_palette_name_is_in_range) {
  const std::vector<std::string> names = color_names();
  EXPECT_EQ(names.size(), 18u) << "the eighteen documented colours";
  for (const std::string& name : names) {
    std::optional<Vec3> rgb = color_from_name(name);
    ASSERT_TRUE(rgb.has_value()) << name << " is listed, so it exists";
    EXPECT_TRUE((rgb->array() >= 0.0).all() && (rgb->array() <= 1.0).all()) << name << " is within [0, 1]";
  }
  EXPECT_EQ(*color_from_name("yellow"), Vec3(1, 1, 0));
  EXPECT_EQ(*color_from_name("red"), Vec3(1, 0, 0));
  EXPECT_EQ(*color_from_name("white"), Vec3(1, 1, 1));
  EXPECT_EQ(*color_from_name("black"), Vec3(0, 0, 0));
}

TEST(ControlColors, hex_parsing) {
  EXPECT_EQ(*color_from_name("#ff0000"), Vec3(1, 0, 0));
  EXPECT_EQ(*color_from_name("#FF8000"), Vec3(1, 128 / 255.0, 0)) << "upper case hex";
  EXPECT_EQ(*color_from_name("#aBcDeF"), Vec3(0xab / 255.0, 0xcd / 255.0, 0xef / 255.0)) << "mixed case hex";
  EXPECT_EQ(*color_from_name("#000000"), Vec3(0, 0, 0));
  EXPECT_FALSE(color_from_name("#GG0000").has_value()) << "not hex digits";
  EXPECT_FALSE(color_from_name("#fff").has_value()) << "short form is not accepted";
  EXPECT_FALSE(color_from_name("ff0000").has_value()) << "the '#' is required";
  EXPECT_FALSE(color_from_name("#ff00000").has_value()) << "too long";
  EXPECT_FALSE(color_from_name("#ff000").has_value()) << "too short";
  EXPECT_FALSE(color_from_name("#").has_value()) << "just the '#'";
  EXPECT_FALSE(color_from_name("# ff000").has_value()) << "space is not a digit";
  EXPECT_FALSE(color_from_name("").has_value()) << "empty";
  EXPECT_FALSE(color_from_name("Yellow").has_value()) << "palette names are case-sensitive";
  EXPECT_FALSE(color_from_name("chartreuse").has_value()) << "unknown name";
}

// ---- apply_control_shape ------------------------------------------------------

TEST(ApplyControlShape, sets_points_closure_and_colour_as_one_undo_step) {
  Scene scene;
  graph::Graph& g = scene.graph();
  Result<NodeId> ctl = scene.create(kControlType, "hand_ctl");
  ASSERT_TRUE(ctl.is_ok());
  const std::size_t steps = g.undo_count();
  ASSERT_TRUE(succeeded(apply_control_shape(g, *ctl, "cube", 2.5, "#00ff00")));
  EXPECT_EQ(g.undo_count(), steps + 1) << "one undo step";
  const graph::Node* node = g.node(*ctl);
  const ControlShape cube = *control_shape("cube", 2.5);
  EXPECT_EQ(std::get<std::vector<Vec3>>(node->value(control_attr::kShapePoints)), cube.points);
  EXPECT_EQ(std::get<bool>(node->value(control_attr::kShapeClosed)), false) << "a cube is drawn open";
  EXPECT_EQ(std::get<Vec3>(node->value(control_attr::kShapeColor)), Vec3(0, 1, 0));

  ASSERT_TRUE(g.undo());
  EXPECT_TRUE(std::get<std::vector<Vec3>>(node->value(control_attr::kShapePoints)).empty()) << "undo clears points";
  EXPECT_EQ(std::get<bool>(node->value(control_attr::kShapeClosed)), true) << "undo restores the default";
  EXPECT_EQ(std::get<Vec3>(node->value(control_attr::kShapeColor)), Vec3(1, 1, 0)) << "undo restores yellow";
  ASSERT_TRUE(g.redo());
  EXPECT_EQ(std::get<std::vector<Vec3>>(node->value(control_attr::kShapePoints)), cube.points) << "redo";
  EXPECT_EQ(std::get<Vec3>(node->value(control_attr::kShapeColor)), Vec3(0, 1, 0)) << "redo";
}

TEST(ApplyControlShape, refuses_bad_input_and_changes_nothing) {
  Scene scene;
  graph::Graph& g = scene.graph();
  const NodeId ctl = *scene.create(kControlType, "ctl");
  const NodeId jnt = *scene.create(kJointType, "jnt");
  const std::size_t steps = g.undo_count();

  Status s = apply_control_shape(g, jnt, "circle", 1.0, "red");
  EXPECT_EQ(s.code(), ErrorCode::kNotFound) << "a joint is not a control";
  EXPECT_NE(s.message().find("jnt"), std::string::npos) << "names the node: " << s.message();
  EXPECT_EQ(apply_control_shape(g, NodeId{}, "circle", 1.0, "red").code(), ErrorCode::kNotFound) << "invalid id";

  s = apply_control_shape(g, ctl, "hexagon", 1.0, "red");
  EXPECT_EQ(s.code(), ErrorCode::kInvalidArgument);
  EXPECT_NE(s.message().find("hexagon"), std::string::npos) << "names the shape: " << s.message();
  s = apply_control_shape(g, ctl, "circle", 1.0, "#fff");
  EXPECT_EQ(s.code(), ErrorCode::kInvalidArgument);
  EXPECT_NE(s.message().find("#fff"), std::string::npos) << "names the colour: " << s.message();
  EXPECT_EQ(apply_control_shape(g, ctl, "circle", 0.0, "red").code(), ErrorCode::kInvalidArgument) << "zero size";
  EXPECT_EQ(g.undo_count(), steps) << "refused calls record nothing";
  EXPECT_TRUE(std::get<std::vector<Vec3>>(g.node(ctl)->value(control_attr::kShapePoints)).empty());

  // A connected colour: points and closure were set first, then rolled back.
  const NodeId loc = *scene.create(kLocatorType, "loc");
  ASSERT_TRUE(succeeded(g.connect(Plug{loc, xform::kTranslate}, Plug{ctl, control_attr::kShapeColor})));
  const std::size_t connected_steps = g.undo_count();
  s = apply_control_shape(g, ctl, "square", 1.0, "blue");
  EXPECT_FALSE(s.is_ok()) << "a connected shapeColor cannot be set";
  EXPECT_TRUE(std::get<std::vector<Vec3>>(g.node(ctl)->value(control_attr::kShapePoints)).empty())
      << "the points set before the failure are rolled back";
  EXPECT_EQ(g.undo_count(), connected_steps) << "a rolled back call leaves no undo step";
}

}  // namespace
}  // namespace rigel::scene
