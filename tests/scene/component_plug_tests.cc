// Component plugs (node.translateX): one channel of a double3 attribute as
// its own plug, so scalar curves and driven keys can feed single channels.

#include <gtest/gtest.h>

#include "rigel/scene/scene.h"
#include "rigel/scene/transform_types.h"

namespace rigel::scene {
namespace {

using graph::Plug;
using math::Vec3;

struct Pair {
  Scene scene;
  NodeId a, b;
  Pair() {
    a = *scene.create(kJointType, "a");
    b = *scene.create(kJointType, "b");
  }
  Plug plug(const char* path) { return *scene.graph().plug_find(path); }
};

TEST(ComponentPlug, plug_find__names_a_component_and_round_trips) {
  Pair p;
  Result<Plug> x = p.scene.graph().plug_find("a.translateX");
  ASSERT_TRUE(x.is_ok()) << x.status().message();
  EXPECT_EQ(x->attr, xform::kTranslate) << "translateX is a part of translate";
  EXPECT_EQ(x->component, 0) << "X is component 0";
  EXPECT_EQ(p.scene.graph().plug_name(p.plug("a.rotateZ")), "a.rotateZ") << "names round-trip";
  EXPECT_EQ(p.scene.graph().plug_type(*x), (graph::AttrType{graph::ValueType::kDouble, false})) << "a component is a double";
  EXPECT_FALSE(p.scene.graph().plug_find("a.radiusX").is_ok()) << "radius is a double: it has no components";
  EXPECT_FALSE(p.scene.graph().plug_find("a.translateW").is_ok()) << "only X, Y and Z";
  EXPECT_FALSE(p.scene.graph().plug_find("a.translateX[0]").is_ok()) << "a component takes no index";
}

TEST(ComponentPlug, set_value__changes_one_channel_and_undoes) {
  Pair p;
  graph::Graph& g = p.scene.graph();
  ASSERT_TRUE(g.set_value(p.plug("a.translate"), Vec3(1, 2, 3)).is_ok()) << "set the whole vector";
  ASSERT_TRUE(g.set_value(p.plug("a.translateY"), 5.0).is_ok()) << "set one channel";
  EXPECT_EQ(std::get<Vec3>(*g.evaluate(p.plug("a.translate"))), Vec3(1, 5, 3)) << "only Y changed";
  EXPECT_EQ(std::get<double>(*g.evaluate(p.plug("a.translateY"))), 5.0) << "a component evaluates to a double";
  EXPECT_EQ(p.scene.world_matrix(p.a)(1, 3), 5.0) << "and moves the joint";
  ASSERT_TRUE(g.undo()) << "undo the channel set";
  EXPECT_EQ(std::get<Vec3>(*g.evaluate(p.plug("a.translate"))), Vec3(1, 2, 3)) << "undo restores the vector";
  EXPECT_FALSE(g.set_value(p.plug("a.translateX"), Vec3(1, 1, 1)).is_ok()) << "a component takes a double";
}

TEST(ComponentPlug, connect__one_channel_drives_another) {
  Pair p;
  graph::Graph& g = p.scene.graph();
  ASSERT_TRUE(g.connect(p.plug("a.translateX"), p.plug("b.rotateY")).is_ok()) << "component to component";
  ASSERT_TRUE(g.set_value(p.plug("a.translate"), Vec3(90, 0, 0)).is_ok()) << "move a";
  EXPECT_EQ(std::get<Vec3>(*g.evaluate(p.plug("b.rotate"))), Vec3(0, 90, 0)) << "b.rotateY follows a.translateX";
  EXPECT_NEAR(p.scene.world_matrix(p.b)(0, 2), 1.0, 1e-12) << "b is turned 90 degrees about Y";
  EXPECT_TRUE(g.set_value(p.plug("b.rotateX"), 10.0).is_ok()) << "an unconnected sibling channel can be set";
  EXPECT_FALSE(g.set_value(p.plug("b.rotateY"), 10.0).is_ok()) << "the connected channel cannot";
  EXPECT_FALSE(g.set_value(p.plug("b.rotate"), Vec3(0, 0, 0)).is_ok()) << "nor the whole vector it is part of";
  EXPECT_FALSE(g.connect(p.plug("a.translate"), p.plug("b.rotate")).is_ok())
      << "the whole vector already has a connected part";
  EXPECT_TRUE(g.connect(p.plug("a.translateZ"), p.plug("b.rotateZ")).is_ok()) << "another channel can be fed";
  EXPECT_FALSE(g.connect(p.plug("a.translate"), p.plug("b.rotateX")).is_ok()) << "a double3 cannot feed a double";
  ASSERT_TRUE(g.undo() && g.undo() && g.undo()) << "undo the second connection, the channel set and the move";
  ASSERT_TRUE(g.undo()) << "undo the first connection";
  ASSERT_TRUE(g.set_value(p.plug("a.translate"), Vec3(45, 0, 0)).is_ok()) << "move a again";
  EXPECT_EQ(std::get<Vec3>(*g.evaluate(p.plug("b.rotate"))), Vec3(0, 0, 0)) << "after undo b no longer follows a";
}

}  // namespace
}  // namespace rigel::scene
