// Transfer keys (tools/transfer.h) on the biped of examples/biped.rig.xml
// built on the metarig, with a second character ("villain") built from the
// same definition on a copy of the skeleton in the same scene: a
// component's keys land on the other character's at t + offset with their
// values and tangents, a range restricts them, the target's keys outside
// the destination range are kept, a whole character transfers by rigId,
// renamed controls still match, and bad input changes nothing. Also move
// keys and channel values (tools/keys.h), which share the key copy.

#include "rigel/tools/transfer.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "rigel/ops/anim/channel_keys.h"
#include "rigel/scene/transform_types.h"
#include "rigel/tools/keys.h"
#include "tools_test_util.h"

namespace rigel::tools {
namespace {

namespace fs = std::filesystem;
using graph::NodeId;
using graph::Plug;
using graph::Value;
using math::Vec3;
using testing::at;
namespace xform = scene::xform;
using ops::anim::TangentType;

// The hierarchy's joints copied under new names (NAME_2), inputs and all.
void copy_skeleton(scene::Scene& s) {
  graph::Graph& g = s.graph();
  std::map<std::uint32_t, NodeId> copies;
  for (NodeId id : s.hierarchy()) {
    const graph::Node& n = *g.node(id);
    if (n.type().name() != scene::kJointType && n.type().name() != scene::kTransformType) continue;
    NodeId parent;
    for (const graph::Connection& c : n.inputs())
      if (c.dst.attr == xform::kParentMatrix && copies.count(c.src.node.index)) parent = copies[c.src.node.index];
    auto copy = s.create(n.type().name(), n.name() + "_2", parent);
    ASSERT_TRUE(copy.is_ok()) << copy.status().message();
    copies[id.index] = *copy;
    for (graph::AttrIndex a = 0; a < static_cast<graph::AttrIndex>(n.type().attr_count()); ++a) {
      const graph::AttrSpec& spec = n.type().attr(a);
      if (!(spec.flags & graph::kInput) || spec.type.value == graph::ValueType::kMessage || a == xform::kParentMatrix) continue;
      (void)g.set_value(Plug{*copy, a, -1}, n.value(a));
    }
  }
}

// The biped as "hero" on the metarig and as "villain" on its copy.
std::unique_ptr<scene::Scene> two_characters(const fs::path& dir) {
  auto s = testing::import_character(testing::source("tests/data/gltf/rigify_human_metarig.glb"));
  if (!s) return nullptr;
  copy_skeleton(*s);  // before any rig drives the joints
  auto hero = rig::add_rig(*s, testing::source("examples/biped.rig.xml"), ephemeral::components());
  EXPECT_TRUE(hero.is_ok()) << hero.status().message();
  if (!hero) return nullptr;
  std::ifstream in(testing::source("examples/biped.rig.xml"));
  std::stringstream text;
  text << in.rdbuf();
  std::string xml = text.str();
  for (std::size_t p = xml.find("joint=\""); p != std::string::npos; p = xml.find("joint=\"", p + 1)) {
    const std::size_t end = xml.find('"', p + 7);
    xml.insert(end, "_2");
  }
  xml.replace(xml.find("<rig name=\"hero\""), 16, "<rig name=\"villain\"");
  fs::create_directories(dir);
  const fs::path def = dir / "villain.rig.xml";
  std::ofstream(def) << xml;
  auto added = rig::add_rig(*s, def, ephemeral::components());
  EXPECT_TRUE(added.is_ok()) << added.status().message();
  if (!added) return nullptr;
  s->graph().clear_history();
  return s;
}

class Transfer : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("rigel_transfer_" + std::to_string(::getpid()));
    scene_ = two_characters(dir_);
    ASSERT_TRUE(scene_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  graph::Graph& g() { return scene_->graph(); }
  NodeId node(const std::string& address) { return at(g(), address); }

  // Keys `channel` of `address` at `frames` with `values` (one value each).
  void key(const std::string& address, const std::string& attr, const std::vector<double>& frames,
           const std::vector<double>& values, std::optional<TangentType> tangent = std::nullopt) {
    const NodeId n = node(address);
    auto channels = channels_of(g(), {n}, {attr});
    ASSERT_TRUE(channels.is_ok()) << channels.status().message();
    for (std::size_t i = 0; i < frames.size(); ++i) {
      scene_->set_frame(frames[i]);
      const graph::AttrType type = g().node(n)->type().attr((*channels)[0].attr).type;
      if (type.value == graph::ValueType::kDouble) {
        ASSERT_TRUE(set_keys(g(), *channels, values[i], Tangents{tangent, tangent}).is_ok());
      } else {
        const Value v(Vec3(values[i], -values[i], 0.5 * values[i]));
        ASSERT_TRUE(ops::anim::write_channel_key(g(), n, (*channels)[0].attr, v, g().time(), true).is_ok());
      }
    }
  }
  // The value of a scalar channel, or the x of a double3, at `frame`.
  double value(const std::string& address, const std::string& attr, double frame) {
    scene_->set_frame(frame);
    const NodeId n = node(address);
    const Value& v = g().evaluate(n, g().node(n)->type().attr_find(attr));
    if (const auto* d = std::get_if<double>(&v)) return *d;
    return std::get<Vec3>(v).x();
  }
  std::vector<double> frames_of(const std::string& address, const std::string& attr) {
    auto channels = channels_of(g(), {node(address)}, {attr});
    std::vector<double> out;
    for (const PlugKeys& k : keys_of(g(), *channels))
      if (k.name.back() != 'Y' && k.name.back() != 'Z')
        for (double t : k.times) out.push_back(std::round(t * g().fps() * 1e6) / 1e6);
    return out;
  }

  fs::path dir_;
  std::unique_ptr<scene::Scene> scene_;
};

TEST_F(Transfer, an_arms_keys_land_on_the_other_characters_arm_at_t_plus_offset) {
  key("hero:arm_L/fk[0]", "rotate", {0, 10, 20}, {5, 30, -12});
  key("hero:arm_L/fkIkSwitch", "fkIk", {0, 20}, {0, 1}, TangentType::kStep);
  TransferOptions o;
  o.from = node("hero:arm_L");
  o.to = node("villain:arm_L");
  o.offset = 100;
  auto r = transfer_keys(g(), o);
  ASSERT_TRUE(r.is_ok()) << r.status().message();
  EXPECT_EQ(r->keys, 3u * 3 + 2) << "three rotate curves of three keys and the switch's two";
  EXPECT_EQ(r->channels, 4u);
  for (double f : {0.0, 5.0, 10.0, 15.0, 20.0}) {
    EXPECT_NEAR(value("villain:arm_L/fk[0]", "rotate", f + 100), value("hero:arm_L/fk[0]", "rotate", f), 1e-12) << f;
    EXPECT_EQ(value("villain:arm_L/fkIkSwitch", "fkIk", f + 100), value("hero:arm_L/fkIkSwitch", "fkIk", f)) << f;
  }
  EXPECT_EQ(frames_of("villain:arm_L/fk[0]", "rotate"), (std::vector<double>{100, 110, 120}));
  auto channels = channels_of(g(), {node("villain:arm_L/fkIkSwitch")}, {"fkIk"});
  const std::vector<PlugKeys> k = keys_of(g(), *channels);
  ASSERT_EQ(k.size(), 1u);
  EXPECT_EQ(k[0].out_tangents, (std::vector<std::string>{"step", "step"})) << "tangent types travel with the keys";
  EXPECT_TRUE(frames_of("villain:arm_R/fk[0]", "rotate").empty()) << "nothing else of the villain is keyed";
  EXPECT_EQ(frames_of("hero:arm_L/fk[0]", "rotate"), (std::vector<double>{0, 10, 20})) << "the source is unchanged";
  ASSERT_TRUE(g().undo());
  EXPECT_TRUE(frames_of("villain:arm_L/fk[0]", "rotate").empty()) << "one undo step takes it all back";
}

TEST_F(Transfer, a_range_restricts_and_the_targets_keys_outside_it_are_kept) {
  key("hero:arm_L/fk[0]", "rotate", {0, 10, 20, 30}, {5, 30, -12, 8});
  key("villain:arm_L/fk[0]", "rotate", {0, 12, 25, 40}, {1, 2, 3, 4});
  TransferOptions o;
  o.from = node("hero:arm_L");
  o.to = node("villain:arm_L");
  o.first = 10;
  o.last = 20;
  o.offset = 5;
  auto r = transfer_keys(g(), o);
  ASSERT_TRUE(r.is_ok()) << r.status().message();
  // Destination range 15..25: the villain's 25 is replaced, 0, 12 and 40 stay.
  EXPECT_EQ(frames_of("villain:arm_L/fk[0]", "rotate"), (std::vector<double>{0, 12, 15, 25, 40}));
  EXPECT_NEAR(value("villain:arm_L/fk[0]", "rotate", 15), 30, 1e-12);
  EXPECT_NEAR(value("villain:arm_L/fk[0]", "rotate", 25), -12, 1e-12);
  EXPECT_NEAR(value("villain:arm_L/fk[0]", "rotate", 40), 4, 1e-12);
  EXPECT_NEAR(value("villain:arm_L/fk[0]", "rotate", 0), 1, 1e-12);
}

TEST_F(Transfer, a_whole_character_transfers_by_rig_id_and_renamed_controls_still_match) {
  key("hero:arm_L/fk[1]", "rotate", {0, 8}, {10, 20});
  key("hero:leg_R/ik", "translate", {0, 8}, {0.1, 0.2});
  key("hero:global/main", "translate", {0, 8}, {0.0, 1.0});
  ASSERT_TRUE(g().rename(node("villain:leg_R/ik"), "renamed_by_an_animator").is_ok());
  TransferOptions o;
  o.from = node("hero:");
  o.to = node("villain:");
  auto r = transfer_keys(g(), o);
  ASSERT_TRUE(r.is_ok()) << r.status().message();
  EXPECT_EQ(r->components.size(), 3u);
  ASSERT_TRUE(r->first && r->last);
  EXPECT_EQ(*r->first, 0);
  EXPECT_EQ(*r->last, 8);
  for (const char* c : {"arm_L/fk[1]", "leg_R/ik", "global/main"}) {
    const std::string attr = std::string(c) == "arm_L/fk[1]" ? "rotate" : "translate";
    EXPECT_NEAR(value(std::string("villain:") + c, attr, 4), value(std::string("hero:") + c, attr, 4), 1e-12) << c;
  }
}

TEST_F(Transfer, bad_input_is_refused_and_changes_nothing) {
  key("hero:arm_L/fk[0]", "rotate", {0, 10}, {5, 30});
  const std::size_t undo = g().undo_count();
  auto refused = [&](TransferOptions o, const std::string& field, const std::string& says) {
    auto r = transfer_keys(g(), o);
    ASSERT_FALSE(r.is_ok()) << field;
    EXPECT_EQ(r.status().code(), ErrorCode::kInvalidArgument) << r.status().message();
    EXPECT_EQ(r.status().field(), field) << r.status().message();
    EXPECT_NE(r.status().message().find(says), std::string::npos) << r.status().message();
    EXPECT_EQ(g().undo_count(), undo) << "nothing changed: " << r.status().message();
    EXPECT_TRUE(frames_of("villain:arm_L/fk[0]", "rotate").empty());
  };
  TransferOptions o;
  o.from = node("hero:arm_L");
  o.to = node("villain:hand_L");
  refused(o, "to", "same type");
  o.to = node("villain:");
  refused(o, "to", "a component for a component");
  o.to = node("villain:arm_L/fk[0]");
  refused(o, "to", "is not a built rig's component or rig");
  o.to = node("villain:arm_L");
  o.first = 10;
  o.last = 0;
  refused(o, "frames", "first <= last");
  o.last = std::nan("");
  refused(o, "frames", "finite");
  o.first = o.last = std::nullopt;
  o.offset = INFINITY;
  refused(o, "offset", "finite");
  o.offset = 0;
  // The target's fk[0] tagged as another index: the source's has no match.
  ASSERT_TRUE(g().set_tag(node("villain:arm_L/fk[0]"), rig::kTagIndex, "7").is_ok());
  const std::size_t tagged = g().undo_count();
  auto r = transfer_keys(g(), o);
  ASSERT_FALSE(r.is_ok());
  EXPECT_EQ(r.status().field(), "to");
  EXPECT_NE(r.status().message().find("'" + g().node(node("hero:arm_L/fk[0]"))->name() + "' (fk 0"), std::string::npos)
      << r.status().message();
  EXPECT_EQ(g().undo_count(), tagged);
}

TEST_F(Transfer, an_arm_takes_the_other_arms_keys_in_the_same_rig) {
  key("hero:arm_L/fk[1]", "rotate", {0, 6}, {12, 40});
  TransferOptions o;
  o.from = node("hero:arm_L");
  o.to = node("hero:arm_R");
  o.offset = -2;
  auto r = transfer_keys(g(), o);
  ASSERT_TRUE(r.is_ok()) << r.status().message();
  EXPECT_EQ(frames_of("hero:arm_R/fk[1]", "rotate"), (std::vector<double>{-2, 4}));
  EXPECT_NEAR(value("hero:arm_R/fk[1]", "rotate", 4), 40, 1e-12);
}

TEST_F(Transfer, move_keys_keeps_value_and_tangents_and_replaces_a_key_there) {
  key("hero:arm_L/fkIkSwitch", "fkIk", {0, 10, 20}, {0, 1, 0.25}, TangentType::kStep);
  auto channels = channels_of(g(), {node("hero:arm_L/fkIkSwitch")}, {"fkIk"});
  ASSERT_TRUE(channels.is_ok());
  // A key a hair off frame 10 is frame 10's.
  auto moved = move_keys(g(), *channels, (10 + 4e-4) / g().fps(), 20 / g().fps());
  ASSERT_TRUE(moved.is_ok()) << moved.status().message();
  EXPECT_EQ(*moved, 1u);
  const std::vector<PlugKeys> k = keys_of(g(), *channels);
  ASSERT_EQ(k.size(), 1u);
  ASSERT_EQ(k[0].times.size(), 2u) << "the key at 20 was replaced";
  EXPECT_NEAR(k[0].times[1] * g().fps(), 20, 1e-9);
  EXPECT_EQ(std::get<double>(k[0].values[1]), 1.0);
  EXPECT_EQ(k[0].out_tangents[1], "step");
  auto none = move_keys(g(), *channels, 5 / g().fps(), 6 / g().fps());
  ASSERT_FALSE(none.is_ok());
  EXPECT_EQ(none.status().code(), ErrorCode::kNotFound);
  ASSERT_TRUE(g().undo());
  EXPECT_EQ(keys_of(g(), *channels)[0].times.size(), 3u) << "one undo step";
}

TEST_F(Transfer, set_values_keys_a_keyed_channel_and_sets_a_free_one) {
  key("hero:arm_L/fkIkSwitch", "fkIk", {0}, {0});
  auto keyed = channels_of(g(), {node("hero:arm_L/fkIkSwitch")}, {"fkIk"});
  auto free = channels_of(g(), {node("hero:arm_R/fkIkSwitch")}, {"fkIk"});
  scene_->set_frame(12);
  ASSERT_TRUE(set_values(g(), {(*keyed)[0], (*free)[0]}, {1.0}, false).is_ok());
  EXPECT_EQ(value("hero:arm_L/fkIkSwitch", "fkIk", 12), 1.0) << "a curve drives it: the value is a key";
  EXPECT_EQ(frames_of("hero:arm_L/fkIkSwitch", "fkIk"), (std::vector<double>{0, 12}));
  EXPECT_EQ(value("hero:arm_R/fkIkSwitch", "fkIk", 30), 1.0);
  EXPECT_TRUE(frames_of("hero:arm_R/fkIkSwitch", "fkIk").empty()) << "free and no auto-key: set only";
  scene_->set_frame(12);
  ASSERT_TRUE(set_values(g(), *free, {0.5}, true).is_ok());
  EXPECT_EQ(frames_of("hero:arm_R/fkIkSwitch", "fkIk"), (std::vector<double>{12})) << "auto-key keys it";
  auto bad = set_values(g(), *free, {1.0, 2.0, 3.0}, false);
  EXPECT_EQ(bad.field(), "value");
  auto rotate = channels_of(g(), {node("hero:arm_L/fk[0]")}, {"rotate"});
  EXPECT_EQ(set_values(g(), *rotate, {1.0}, false).field(), "value") << "a double3 is posed, not set to a number";
}

}  // namespace
}  // namespace rigel::tools
