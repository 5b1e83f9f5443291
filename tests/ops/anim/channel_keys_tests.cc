// Keys on transform channels (channel_keys.h): many keys written at once
// (write_channel_keys) give exactly what writing them one at a time gives,
// undo exactly, and cost memory linear in the keys.

#include "rigel/ops/anim/channel_keys.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "anim_test_util.h"
#include "rigel/graph/graph.h"
#include "rigel/ops/anim/nodes.h"
#include "rigel/ops/registry.h"
#include "rigel/scene/transform_types.h"

namespace rigel::ops::anim {
namespace {

using graph::Graph;
using graph::NodeId;
using graph::Plug;
using graph::Value;
using math::Quat;
using math::Vec3;
using testing::fails_with;
using testing::succeeded;
namespace xform = scene::xform;

// Everything a graph holds that keying can change: each node's type and
// input values (by name), and the connections.
struct Snapshot {
  std::map<std::string, std::pair<std::string, std::vector<Value>>> nodes;
  std::vector<std::string> connections;
};

Snapshot snapshot(const Graph& g) {
  Snapshot s;
  for (NodeId id : g.nodes()) {
    const graph::Node& n = *g.node(id);
    std::vector<Value> inputs;
    for (graph::AttrIndex a = 0; a < n.type().attr_count(); ++a)
      if (n.type().is_input(a)) inputs.push_back(n.value(a));
    s.nodes[n.name()] = {n.type().name(), std::move(inputs)};
  }
  for (const graph::Connection& c : g.connections()) s.connections.push_back(g.plug_name(c.src) + " -> " + g.plug_name(c.dst));
  std::sort(s.connections.begin(), s.connections.end());
  return s;
}

::testing::AssertionResult same(const Snapshot& a, const Snapshot& b) {
  if (a.connections != b.connections) return ::testing::AssertionFailure() << "the connections differ";
  if (a.nodes.size() != b.nodes.size())
    return ::testing::AssertionFailure() << a.nodes.size() << " nodes vs " << b.nodes.size();
  for (const auto& [name, node] : a.nodes) {
    auto it = b.nodes.find(name);
    if (it == b.nodes.end()) return ::testing::AssertionFailure() << "no node " << name;
    if (node.first != it->second.first) return ::testing::AssertionFailure() << name << ": types differ";
    for (std::size_t i = 0; i < node.second.size(); ++i)
      if (!graph::values_identical(node.second[i], it->second.second[i]))
        return ::testing::AssertionFailure() << name << ": input " << i << " differs: "
                                             << graph::value_to_text(node.second[i]) << " vs "
                                             << graph::value_to_text(it->second.second[i]);
  }
  return ::testing::AssertionSuccess();
}

// A graph with one transform `t`, prepared by `setup`.
struct Fixture {
  explicit Fixture(const std::function<void(Graph&, NodeId)>& setup) : g(default_registry()) {
    t = *g.create_node(scene::kTransformType, "t");
    setup(g, t);
    g.clear_history();
  }
  Graph g;
  NodeId t;
};

// A double3 or quaternion key list.
template <typename T>
struct Keys {
  std::vector<double> times;
  std::vector<T> values;
};

Quat random_quat(testing::Random& r) {
  Quat q(r.uniform(-1, 1), r.uniform(-1, 1), r.uniform(-1, 1), r.uniform(-1, 1));
  return q.normalized();
}

// Writes `keys` one at a time and all at once on two graphs set up alike;
// both must end identical, the bulk write must undo to the start in one
// step and redo to the same end.
template <typename T>
void expect_bulk_is_sequential(const std::function<void(Graph&, NodeId)>& setup, graph::AttrIndex attr,
                               const Keys<T>& keys, bool insert) {
  Fixture one(setup), bulk(setup), start(setup);
  for (std::size_t k = 0; k < keys.times.size(); ++k)
    ASSERT_TRUE(succeeded(write_channel_key(one.g, one.t, attr, Value(keys.values[k]), keys.times[k], insert)))
        << "key " << k;
  ASSERT_TRUE(succeeded(write_channel_keys(bulk.g, bulk.t, attr, keys.times, keys.values, insert)));
  EXPECT_TRUE(same(snapshot(one.g), snapshot(bulk.g)));
  EXPECT_EQ(bulk.g.undo_count(), 1u);
  ASSERT_TRUE(bulk.g.undo());
  EXPECT_TRUE(same(snapshot(start.g), snapshot(bulk.g)));
  ASSERT_TRUE(bulk.g.redo());
  EXPECT_TRUE(same(snapshot(one.g), snapshot(bulk.g)));
}

// Scalar curves on a channel's components: keys at `times` with values
// `base + i`, tangent arrays filled on x only (y and z keep defaults).
void key_components(Graph& g, NodeId t, graph::AttrIndex attr, const std::vector<double>& times) {
  for (int axis = 0; axis < 3; ++axis) {
    NodeId c = *g.create_node(kAnimCurveType, std::string("c") + static_cast<char>('x' + axis));
    std::vector<double> values;
    for (std::size_t i = 0; i < times.size(); ++i) values.push_back(10.0 * axis + static_cast<double>(i));
    ASSERT_TRUE(succeeded(g.set_value(Plug{c, curve_attr::kKeyTimes, -1}, times)));
    ASSERT_TRUE(succeeded(g.set_value(Plug{c, curve_attr::kKeyValues, -1}, values)));
    if (axis == 0) {
      const std::size_t n = times.size();
      ASSERT_TRUE(succeeded(g.set_value(Plug{c, curve_attr::kInTangentType, -1}, std::vector<std::int64_t>(n, 1))));
      ASSERT_TRUE(succeeded(g.set_value(Plug{c, curve_attr::kOutTangentType, -1}, std::vector<std::int64_t>(n, 0))));
      ASSERT_TRUE(succeeded(g.set_value(Plug{c, curve_attr::kOutSlope, -1}, std::vector<double>(n, 2.5))));
      ASSERT_TRUE(succeeded(g.set_value(Plug{c, curve_attr::kInWeight, -1}, std::vector<double>(n, 0.5))));
    }
    ASSERT_TRUE(succeeded(g.connect(Plug{c, curve_attr::kOutput, -1}, Plug{t, attr, -1, static_cast<std::int8_t>(axis)})));
  }
}

TEST(ChannelKeys, ManyKeysOnAFreeChannelAreTheSequentialKeys) {
  testing::Random r(1);
  Keys<Vec3> v;
  Keys<Quat> q;
  for (int k = 0; k < 40; ++k) {
    v.times.push_back(k / 24.0);
    v.values.push_back(Vec3(r.uniform(-5, 5), r.uniform(-5, 5), r.uniform(-5, 5)));
    q.times.push_back(k / 24.0 + 1e-4);
    q.values.push_back(random_quat(r));  // random signs: keys turned sign-continuous
  }
  auto none = [](Graph&, NodeId) {};
  expect_bulk_is_sequential(none, xform::kTranslate, v, true);
  expect_bulk_is_sequential(none, xform::kRotate, v, true);
  expect_bulk_is_sequential(none, xform::kRotateQuaternion, q, true);
  // Not inserting on a free channel sets it (to the last value).
  expect_bulk_is_sequential(none, xform::kScale, v, false);
  expect_bulk_is_sequential(none, xform::kRotateQuaternion, q, false);
}

// Existing keys and new ones interleaved, new keys a hair (within the key
// tolerance) off old ones, two new keys each within the tolerance of one
// old key, keys before the first and after the last.
TEST(ChannelKeys, ManyKeysMergeIntoScalarCurvesAsSequentialKeys) {
  const double tol = kKeyTimeTolerance;
  const std::vector<double> old_times = {0.1, 0.2, 0.3, 0.5, 0.8};
  auto setup = [&](Graph& g, NodeId t) { key_components(g, t, xform::kTranslate, old_times); };
  testing::Random r(2);
  Keys<Vec3> keys;
  for (double t : {0.0, 0.1 + 0.5 * tol, 0.15, 0.3 - 0.9 * tol, 0.3 + 0.9 * tol, 0.4, 0.45, 0.5, 0.9, 1.0}) {
    keys.times.push_back(t);
    keys.values.push_back(Vec3(r.uniform(-1, 1), r.uniform(-1, 1), r.uniform(-1, 1)));
  }
  expect_bulk_is_sequential(setup, xform::kTranslate, keys, true);
  // Updating only: every time has a key.
  Keys<Vec3> existing;
  for (double t : {0.1 - 0.5 * tol, 0.3, 0.8 + 0.2 * tol}) {
    existing.times.push_back(t);
    existing.values.push_back(Vec3(r.uniform(-1, 1), r.uniform(-1, 1), r.uniform(-1, 1)));
  }
  expect_bulk_is_sequential(setup, xform::kTranslate, existing, false);
  expect_bulk_is_sequential(setup, xform::kTranslate, existing, true);
}

// A quaternion track with cubic tangents and keys with random signs: the new
// keys take the sequential writes' hemispheres, tangents grow by flat ones.
TEST(ChannelKeys, ManyKeysMergeIntoAQuaternionTrackAsSequentialKeys) {
  testing::Random r(3);
  std::vector<Quat> old_values, tangents;
  const std::vector<double> old_times = {0.25, 0.5, 0.75};
  for (std::size_t i = 0; i < old_times.size(); ++i) {
    old_values.push_back(random_quat(r));
    tangents.push_back(Quat(0.1, 0.2, 0.3, 0.4));
  }
  auto setup = [&](Graph& g, NodeId t) {
    NodeId c = *g.create_node(kAnimCurveQuatType, "q");
    ASSERT_TRUE(succeeded(g.set_value(Plug{c, track_attr::kKeyTimes, -1}, old_times)));
    ASSERT_TRUE(succeeded(g.set_value(Plug{c, track_attr::kKeyValues, -1}, old_values)));
    ASSERT_TRUE(succeeded(g.set_value(Plug{c, track_attr::kInTangents, -1}, tangents)));
    ASSERT_TRUE(succeeded(g.set_value(Plug{c, track_attr::kOutTangents, -1}, tangents)));
    ASSERT_TRUE(succeeded(g.set_value(Plug{c, track_attr::kInterpolation, -1}, std::int64_t{2})));
    ASSERT_TRUE(succeeded(g.connect(Plug{c, track_attr::kOutput, -1}, Plug{t, xform::kRotateQuaternion, -1})));
  };
  for (unsigned trial = 0; trial < 20; ++trial) {
    // Random times, some on old keys or a hair off them, spaced more than
    // the tolerance.
    std::vector<double> pool;
    for (int i = 0; i < 8; ++i) pool.push_back(r.uniform(-0.2, 1.0));
    for (double t : old_times) {
      if (r.uniform(0, 1) < 0.5) pool.push_back(t);
      else if (r.uniform(0, 1) < 0.5) pool.push_back(t + r.uniform(-0.9, 0.9) * kKeyTimeTolerance);
    }
    std::sort(pool.begin(), pool.end());
    Keys<Quat> keys;
    for (double t : pool) {
      if (!keys.times.empty() && t - keys.times.back() <= 2 * kKeyTimeTolerance) continue;
      keys.times.push_back(t);
      keys.values.push_back(random_quat(r));
    }
    expect_bulk_is_sequential(setup, xform::kRotateQuaternion, keys, true);
  }
}

// A track holding clips: keys go into the active clip only, later clips'
// offsets move, as one key at a time does.
TEST(ChannelKeys, ManyKeysGoIntoTheActiveClip) {
  auto setup = [](Graph& g, NodeId t) {
    NodeId c = *g.create_node(kAnimCurveVec3Type, "v");
    const std::vector<double> times = {0, 0.5, 1, 0, 0.5, 0, 1, 2};
    std::vector<Vec3> values;
    for (std::size_t i = 0; i < times.size(); ++i) values.push_back(Vec3(static_cast<double>(i), 0, 0));
    ASSERT_TRUE(succeeded(g.set_value(Plug{c, track_attr::kKeyTimes, -1}, times)));
    ASSERT_TRUE(succeeded(g.set_value(Plug{c, track_attr::kKeyValues, -1}, values)));
    ASSERT_TRUE(succeeded(g.set_value(Plug{c, track_attr::kClipOffsets, -1}, std::vector<std::int64_t>{0, 3, 5, 8})));
    ASSERT_TRUE(succeeded(g.set_value(Plug{c, track_attr::kClip, -1}, std::int64_t{1})));
    ASSERT_TRUE(succeeded(g.connect(Plug{c, track_attr::kOutput, -1}, Plug{t, xform::kTranslate, -1})));
  };
  Keys<Vec3> keys{{-1, 0, 0.25, 0.5, 0.75, 3}, {}};
  for (std::size_t i = 0; i < keys.times.size(); ++i) keys.values.push_back(Vec3(0, static_cast<double>(i), 1));
  expect_bulk_is_sequential(setup, xform::kTranslate, keys, true);
  Fixture f(setup);
  ASSERT_TRUE(succeeded(write_channel_keys(f.g, f.t, xform::kTranslate, keys.times, keys.values, true)));
  const graph::Node& v = *f.g.node(f.g.find("v"));
  EXPECT_EQ(std::get<std::vector<std::int64_t>>(v.value(track_attr::kClipOffsets)), (std::vector<std::int64_t>{0, 3, 9, 12}));
}

// With a component keyed and the others free, not inserting: the keyed one
// takes its keys, the free ones the last value.
TEST(ChannelKeys, ManyKeysOnAPartlyKeyedChannel) {
  auto setup = [](Graph& g, NodeId t) {
    NodeId c = *g.create_node(kAnimCurveType, "cy");
    ASSERT_TRUE(succeeded(g.set_value(Plug{c, curve_attr::kKeyTimes, -1}, std::vector<double>{0, 1})));
    ASSERT_TRUE(succeeded(g.set_value(Plug{c, curve_attr::kKeyValues, -1}, std::vector<double>{3, 4})));
    ASSERT_TRUE(succeeded(g.connect(Plug{c, curve_attr::kOutput, -1}, Plug{t, xform::kScale, -1, 1})));
  };
  Keys<Vec3> keys{{0, 1}, {Vec3(2, 2, 2), Vec3(5, 6, 7)}};
  expect_bulk_is_sequential(setup, xform::kScale, keys, false);
  expect_bulk_is_sequential(setup, xform::kScale, keys, true);
}

TEST(ChannelKeys, ManyKeysRefuseBadInputAndChangeNothing) {
  const std::vector<double> old_times = {0, 1};
  auto setup = [&](Graph& g, NodeId t) { key_components(g, t, xform::kTranslate, old_times); };
  Fixture f(setup), start(setup);
  const std::vector<Vec3> two = {Vec3(1, 1, 1), Vec3(2, 2, 2)};
  // Not inserting and a time without a key: nothing written, no undo step.
  EXPECT_TRUE(fails_with(write_channel_keys(f.g, f.t, xform::kTranslate, std::vector<double>{0, 0.5}, two, false),
                         "has no key"));
  EXPECT_TRUE(same(snapshot(start.g), snapshot(f.g)));
  EXPECT_EQ(f.g.undo_count(), 0u);
  EXPECT_TRUE(fails_with(write_channel_keys(f.g, f.t, xform::kTranslate, std::vector<double>{0.5, 0.25}, two, true),
                         "is not after"));
  EXPECT_TRUE(fails_with(write_channel_keys(f.g, f.t, xform::kTranslate,
                                            std::vector<double>{0.5, 0.5 + 0.5 * kKeyTimeTolerance}, two, true),
                         "key tolerance"));
  EXPECT_TRUE(fails_with(write_channel_keys(f.g, f.t, xform::kTranslate, std::vector<double>{0.5}, two, true),
                         "1 times for 2 values"));
  EXPECT_TRUE(fails_with(
      write_channel_keys(f.g, f.t, xform::kTranslate, std::vector<double>{0.5}, std::vector<Quat>{Quat::Identity()}, true),
      "rotateQuaternion"));
  EXPECT_TRUE(fails_with(write_channel_keys(f.g, f.t, xform::kRotateQuaternion, std::vector<double>{0.5},
                                            std::vector<Vec3>{Vec3::Zero()}, true),
                         "not a double3 channel"));
  EXPECT_TRUE(same(snapshot(start.g), snapshot(f.g)));
  EXPECT_EQ(f.g.undo_count(), 0u);
}

// What the undo records of a write hold: the total size of the arrays each
// set recorded, before and after (an observer sees each set's old value,
// and the new one is in the node). Many keys at once: each array once, so
// twice the keys record twice the elements; written one at a time every
// array was recorded once per key (four times the elements).
struct RecordedSets : graph::Observer {
  std::size_t elements = 0, sets = 0;
  void attribute_set(const Graph& g, const Plug& p, const Value& before) override {
    ++sets;
    for (const Value* v : {&before, &g.node(p.node)->value(p.attr)}) {
      std::visit(
          [&](const auto& x) {
            if constexpr (requires { x.size(); }) elements += x.size();
          },
          *v);
    }
  }
};

TEST(ChannelKeys, ManyKeysRecordUndoLinearInTheKeys) {
  auto recorded = [](std::size_t count) {
    const std::vector<double> old_times = {0, 1};
    Fixture f([&](Graph& g, NodeId t) { key_components(g, t, xform::kTranslate, old_times); });
    Keys<Vec3> keys;
    for (std::size_t k = 0; k < count; ++k) {
      keys.times.push_back(0.5 + static_cast<double>(k) / 4096.0);  // between the old keys
      keys.values.push_back(Vec3(1, 2, static_cast<double>(k)));
    }
    RecordedSets r;
    f.g.add_observer(&r);
    EXPECT_TRUE(succeeded(write_channel_keys(f.g, f.t, xform::kTranslate, keys.times, keys.values, true)));
    f.g.remove_observer(&r);
    EXPECT_EQ(std::get<std::vector<double>>(f.g.node(f.g.find("cx"))->value(curve_attr::kKeyTimes)).size(), count + 2);
    return r;
  };
  const RecordedSets small = recorded(1000), large = recorded(2000);
  // Three curves: times and values, and x's four tangent arrays: 10 sets
  // whatever the key count.
  EXPECT_EQ(small.sets, 10u);
  EXPECT_EQ(large.sets, 10u);
  const double ratio = static_cast<double>(large.elements) / static_cast<double>(small.elements);
  EXPECT_GT(ratio, 1.9);
  EXPECT_LT(ratio, 2.1);
}

}  // namespace
}  // namespace rigel::ops::anim

namespace rigel::ops::anim {
namespace {

// A scalar channel (a transform's translateX keyed by its own curve): many
// keys at once as one at a time; tangent types set per key, in and out
// alone or both, undone in one step; tracks and missing keys refused.
TEST(ChannelKeys, ScalarKeysAndTangentTypes) {
  Keys<double> k{{0.0, 0.5, 1.0}, {1.0, 3.0, 2.0}};
  auto none = [](Graph&, NodeId) {};
  Fixture f(none);
  const NodeId curve = *f.g.create_node(kAnimCurveType, "c");
  ASSERT_TRUE(succeeded(f.g.connect(Plug{curve, curve_attr::kOutput, -1}, Plug{f.t, xform::kTranslate, -1, 0})));
  // A scalar write goes to a scalar attribute: translate is a double3.
  EXPECT_TRUE(fails_with(write_channel_keys(f.g, f.t, xform::kTranslate, k.times, k.values, true),
                         "not a scalar channel"));
  ASSERT_TRUE(succeeded(write_channel_keys(f.g, f.t, xform::kTranslate,
                                           std::span<const double>(k.times), std::span<const Vec3>(std::vector<Vec3>{
                                               Vec3(1, 0, 0), Vec3(3, 0, 0), Vec3(2, 0, 0)}),
                                           true)));
  f.g.clear_history();
  ASSERT_TRUE(succeeded(set_key_tangents(f.g, f.t, xform::kTranslate, 0.5, TangentType::kStep, TangentType::kStep)));
  ASSERT_TRUE(succeeded(set_key_tangents(f.g, f.t, xform::kTranslate, 1.0 + 1e-9, std::nullopt, TangentType::kLinear)));
  const auto& in = std::get<std::vector<std::int64_t>>(f.g.node(curve)->value(curve_attr::kInTangentType));
  const auto& out = std::get<std::vector<std::int64_t>>(f.g.node(curve)->value(curve_attr::kOutTangentType));
  EXPECT_EQ(in, (std::vector<std::int64_t>{8, 3, 8}));
  EXPECT_EQ(out, (std::vector<std::int64_t>{8, 3, 1}));
  // Stepped out of 0.5: the value holds until the next key.
  f.g.set_time(0.75);
  EXPECT_DOUBLE_EQ(std::get<Vec3>(f.g.evaluate(f.t, xform::kTranslate)).x(), 3.0);
  EXPECT_TRUE(fails_with(set_key_tangents(f.g, f.t, xform::kTranslate, 0.25, TangentType::kStep, std::nullopt),
                         "has no key at frame 6"));
  EXPECT_EQ(f.g.undo_count(), 2u);
  ASSERT_TRUE(f.g.undo());
  ASSERT_TRUE(f.g.undo());
  EXPECT_TRUE(std::get<std::vector<std::int64_t>>(f.g.node(curve)->value(curve_attr::kOutTangentType)).size() == 3u);
  EXPECT_EQ(std::get<std::vector<std::int64_t>>(f.g.node(curve)->value(curve_attr::kOutTangentType)),
            (std::vector<std::int64_t>(3, 8)))
      << "back to auto";
  // A quaternion track has one interpolation for all its keys.
  std::vector<Quat> q(3, Quat::Identity());
  ASSERT_TRUE(succeeded(write_channel_keys(f.g, f.t, xform::kRotateQuaternion, k.times, q, true)));
  EXPECT_TRUE(fails_with(set_key_tangents(f.g, f.t, xform::kRotateQuaternion, 0.5, TangentType::kStep, std::nullopt),
                         "tangent types apply to curves"));
}

}  // namespace
}  // namespace rigel::ops::anim
