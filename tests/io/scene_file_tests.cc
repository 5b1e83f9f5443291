// Tests of the .rigel scene file (include/rigel/io/scene_file.h): round
// trips, undo/redo against serialisation, versioning against a golden file,
// malformed input (every refusal names its place), a mutation fuzz, and
// atomic writes.

#include "rigel/io/scene_file.h"
#include "rigel/io/diffable_json.h"
#include "rigel/io/json_depth.h"
#include "rigel/ops/registry.h"
#include "rigel/scene/scene_options.h"
#include "rigel/scene/transform_types.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "io_test_util.h"
#include "rigel/math/transform.h"
#include "../support/slow_build.h"

namespace rigel::io {
namespace {

using namespace rigel::io::testing;  // NOLINT: test helpers
using Json = nlohmann::ordered_json;
using graph::AttrIndex;
using graph::AttrSpec;
using graph::AttrType;
using graph::ValueType;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// Unoptimised (sanitizer) builds run the exhaustive loops on a sample.
using rigel::testing::kSlowBuildDivisor;

// ---- the reference scene ---------------------------------------------------
//
// Every scene node type, every kind of value a scene type holds (double3,
// angles, enums, quaternion mode, bool, double, matrix, arrays of double3 and
// int), non-finite values and a negative zero, tags, a dotted and a non-ASCII
// name, and every kind of non-hierarchy connection: whole matrix, array
// element as source, array element as destination, both ends elements, enum,
// bool, double, quaternion. Fixed uuids, so it is also the content of
// tests/data/scenes/golden_v1.rigel.
void build_reference_scene(Scene& scene) {
  Graph& g = scene.graph();
  ASSERT_TRUE(g.set_fps(30.0).is_ok()) << "30 fps is a valid frame rate";
  g.set_time(0.5);
  Builder b(scene);

  NodeId root = b.node("transform", "root", 1);
  b.set(root, "translate", Vec3(0.0, 1.0, 0.0));
  b.tag(root, "role", "root");

  NodeId spine1 = b.node("joint", "spine.001", 2, root);
  b.set(spine1, "translate", Vec3(0.0, 1.25, 0.0));
  b.set(spine1, "rotate", Vec3(10.0, -20.0, 30.5));
  b.set(spine1, "rotateOrder", std::int64_t{2});  // zxy
  b.set(spine1, "jointOrient", Vec3(0.0, 0.0, 90.0));
  b.set(spine1, "radius", 0.5);
  b.set(spine1, "scale", Vec3(1.0, 2.0, 0.5));
  b.set(spine1, "shear", Vec3(0.1, 0.0, 0.0));
  b.tag(spine1, "side", "C");

  NodeId spine2 = b.node("joint", "spine.002", 3, spine1);
  b.set(spine2, "translate", Vec3(0.0, 1.0, 0.0));
  b.set(spine2, "rotateMode", std::int64_t{1});  // quaternion
  b.set(spine2, "rotateQuaternion", Quat(Quat(0.9, 0.1, 0.2, 0.3).normalized()));
  b.set(spine2, "rotateAxis", Vec3(5.0, 0.0, 0.0));

  NodeId shoulder = b.node("control", "épaule_L", 4, spine2);
  b.set(shoulder, "shapePoints",
        std::vector<Vec3>{Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(-1, 0, 0), Vec3(0, -1, 0)});
  b.set(shoulder, "shapeClosed", false);
  b.set(shoulder, "shapeColor", Vec3(0.0, 0.5, 1.0));
  b.tag(shoulder, "side", "L");
  b.tag(shoulder, "kind", "fk");

  NodeId pivots = b.node("transform", "pivots", 5, root);
  b.set(pivots, "rotatePivot", Vec3(1.0, 0.0, 0.0));
  b.set(pivots, "rotatePivotTranslate", Vec3(0.0, 0.5, 0.0));
  b.set(pivots, "scalePivot", Vec3(0.0, 1.0, 0.0));
  b.set(pivots, "scalePivotTranslate", Vec3(0.25, 0.0, 0.0));
  b.set(pivots, "visibility", false);

  NodeId body = b.node("mesh", "body", 6);
  b.set(body, "points", std::vector<Vec3>{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 0, 1), Vec3(0, 0, 1)});
  b.set(body, "normals", std::vector<Vec3>(4, Vec3(0, 1, 0)));
  b.set(body, "triangles", std::vector<std::int64_t>{0, 1, 2, 0, 2, 3});
  Mat4 offset = Mat4::Identity();
  offset(2, 3) = -2.0;
  b.set(body, "offsetParentMatrix", offset);

  NodeId target = b.node("locator", "target", 7);
  b.set(target, "translate", Vec3(0.5, 1.5, 2.5));
  b.set(target, "localScale", Vec3(2.0, 2.0, 2.0));

  NodeId odd = b.node("locator", "odd.values", 8);
  b.set(odd, "translate", Vec3(kNaN, kInf, -kInf));
  b.set(odd, "rotate", Vec3(-0.0, 1e-310, 1e300));
  b.set(odd, "localScale", Vec3(0.1, 0.2, 0.3));

  b.node("transform", "follow", 9);
  b.node("transform", "empty_group", 10);
  NodeId lod = b.node("mesh", "body.lod1", 11);
  b.set(lod, "triangles", std::vector<std::int64_t>{0, 0, 0});

  b.connect("spine.002.worldMatrix", "follow.offsetParentMatrix");  // whole matrix, not hierarchy
  b.connect("body.points[2]", "follow.translate");                   // array element as source
  b.connect("target.translate", "épaule_L.shapePoints[3]");          // array element as destination
  b.connect("body.triangles[4]", "body.lod1.triangles[1]");          // elements at both ends
  b.connect("spine.001.rotateOrder", "follow.rotateOrder");           // enum
  b.connect("épaule_L.shapeClosed", "follow.visibility");             // bool
  b.connect("spine.001.radius", "spine.002.radius");                  // double
  b.connect("spine.002.rotateQuaternion", "follow.rotateQuaternion");  // quaternion
  g.clear_history();
}

std::unique_ptr<Scene> load_or_fail(const std::string& text, const std::string& source) {
  Result<std::unique_ptr<Scene>> r = parse_scene(text, source);
  EXPECT_TRUE(r.is_ok()) << source << " should load: " << r.status().message();
  return r.is_ok() ? std::move(*r) : nullptr;
}

// ---- round trips -------------------------------------------------------------

TEST(SceneFile, round_trip__reference_scene_text_and_graph_are_identical) {
  Scene original;
  build_reference_scene(original);
  const std::string first = write_scene(original);
  std::unique_ptr<Scene> loaded = load_or_fail(first, "reference.rigel");
  ASSERT_NE(loaded, nullptr) << "the scene should load (the reason is reported above)";
  const std::string second = write_scene(*loaded);
  EXPECT_EQ(first, second) << "saving a loaded scene should give the text it was loaded from: "
                           << first_difference(first, second);
  EXPECT_TRUE(graphs_identical(original.graph(), loaded->graph()))
      << "a loaded scene should hold the same nodes, values, tags and connections as the saved one";
}

TEST(SceneFile, round_trip__random_uuids_and_awkward_names) {
  Scene original;
  Graph& g = original.graph();
  const std::vector<std::string> names = {"quote\"d", "back\\slash", "a.b.c", "ünïcödé", "tab_less#1", "x{}"};
  NodeId parent;
  for (const std::string& name : names) {
    Result<NodeId> id = original.create("joint", name, parent);
    ASSERT_TRUE(id.is_ok()) << "'" << name << "' is a valid node name: " << id.status().message();
    ASSERT_EQ(g.node(*id)->name(), name) << "the name should be kept as given";
    ASSERT_TRUE(g.set_tag(*id, "note", "value with \"quotes\", \\ and\nnewline").is_ok()) << "any tag text is allowed";
    parent = *id;
  }
  ASSERT_TRUE(g.connect(*g.plug_find("quote\"d.translate"), *g.plug_find("a.b.c.rotate")).is_ok())
      << "a dotted node name should resolve in a plug path";
  const std::string first = write_scene(original);
  std::unique_ptr<Scene> loaded = load_or_fail(first, "names.rigel");
  ASSERT_NE(loaded, nullptr) << "the scene should load (the reason is reported above)";
  EXPECT_EQ(first, write_scene(*loaded)) << "escaped names and tags should round-trip";
  EXPECT_TRUE(graphs_identical(original.graph(), loaded->graph())) << "generated uuids should be kept by the file";
}

TEST(SceneFile, round_trip__empty_scene) {
  Scene original;
  const std::string first = write_scene(original);
  std::unique_ptr<Scene> loaded = load_or_fail(first, "empty.rigel");
  ASSERT_NE(loaded, nullptr) << "the scene should load (the reason is reported above)";
  EXPECT_EQ(first, write_scene(*loaded)) << "an empty scene should round-trip";
  EXPECT_EQ(loaded->graph().node_count(), 0u) << "an empty scene has no nodes";
  EXPECT_EQ(loaded->graph().fps(), 24.0) << "the default frame rate is 24 fps (DESIGN.md)";
}

TEST(SceneFile, round_trip__playback_range_and_selection_sets_are_saved_with_the_scene) {
  Scene original;
  graph::Graph& g = original.graph();
  auto a = g.create_node(scene::kControlType, "a");
  auto b = g.create_node(scene::kControlType, "b");
  ASSERT_TRUE(a && b);
  ASSERT_TRUE(scene::set_playback_range(g, 12, 96).is_ok());
  ASSERT_TRUE(scene::save_selection_set(g, "hands", {*b, *a}).is_ok());
  const std::string first = write_scene(original);
  std::unique_ptr<Scene> loaded = load_or_fail(first, "settings.rigel");
  ASSERT_NE(loaded, nullptr);
  EXPECT_EQ(first, write_scene(*loaded));
  ASSERT_TRUE(scene::playback_range(loaded->graph()));
  EXPECT_EQ(*scene::playback_range(loaded->graph()), (std::array<double, 2>{12, 96}));
  const std::vector<scene::SelectionSet> sets = scene::selection_sets(loaded->graph());
  ASSERT_EQ(sets.size(), 1u);
  EXPECT_EQ(sets[0].name, "hands");
  ASSERT_EQ(sets[0].members.size(), 2u);
  EXPECT_EQ(loaded->graph().node(sets[0].members[0])->name(), "b");
}

TEST(SceneFile, round_trip__example_resaves_to_a_stable_text) {
  const std::string example = read_text(example_path());
  std::unique_ptr<Scene> once = load_or_fail(example, "cmu_131_skeleton.rigel");
  ASSERT_NE(once, nullptr) << "the scene should load (the reason is reported above)";
  const std::string first = write_scene(*once);
  std::unique_ptr<Scene> twice = load_or_fail(first, "resaved.rigel");
  ASSERT_NE(twice, nullptr) << "the scene should load (the reason is reported above)";
  const std::string second = write_scene(*twice);
  EXPECT_EQ(first, second) << "save(load(save(load(example)))) should equal save(load(example)): "
                           << first_difference(first, second);
  EXPECT_EQ(once->graph().node_count(), 32u) << "the example holds a world control and 31 joints";
  EXPECT_TRUE(graphs_identical(once->graph(), twice->graph())) << "the re-saved example should load identically";
}

// Graph::connect lets an int feed an enum, and a disconnected destination
// keeps the last value it received. The graph clamps what an enum receives
// to its names, so the saved scene still loads (parse_scene, like
// Graph::set_value, refuses an enum index that has no name).
TEST(SceneFile, round_trip__enum_left_out_of_range_by_an_int_connection) {
  Scene original;
  Builder b(original);
  NodeId mesh = b.node("mesh", "m", 1);
  b.node("joint", "j", 2);
  b.set(mesh, "triangles", std::vector<std::int64_t>{0, 9});
  b.connect("m.triangles[1]", "j.rotateOrder");
  (void)write_scene(original);  // evaluates: j.rotateOrder receives 9
  Graph& g = original.graph();
  ASSERT_TRUE(g.disconnect(*g.plug_find("m.triangles[1]"), *g.plug_find("j.rotateOrder")).is_ok())
      << "the connection should break";
  Result<std::unique_ptr<Scene>> r = parse_scene(write_scene(original), "enum.rigel");
  EXPECT_TRUE(r.is_ok()) << "every scene the API can build should save to a file that loads: "
                         << r.status().message();
}

// Files are JSON, so names, tags and strings must be UTF-8: the graph
// refuses other bytes, and whatever it accepted serialises without throwing.
TEST(SceneFile, write__names_and_tags_that_are_not_utf8_do_not_throw) {
  Scene original;
  Graph& g = original.graph();
  Result<NodeId> id = g.create_node("joint", "bad\xff");
  if (!id.is_ok()) return;                          // refused by the graph: fixed there
  (void)g.set_tag(*id, "key", "value\xc3");         // may be refused as well
  std::string text;
  EXPECT_NO_THROW(text = write_scene(original)) << "a scene the graph accepted should serialise";
  if (text.empty()) return;
  std::unique_ptr<Scene> loaded = load_or_fail(text, "utf8.rigel");
  if (!loaded) return;
  EXPECT_TRUE(graphs_identical(original.graph(), loaded->graph())) << "the scene should round-trip";
}

TEST(SceneFile, write__is_deterministic) {
  Scene a, b;
  build_reference_scene(a);
  build_reference_scene(b);
  const std::string text = write_scene(a);
  EXPECT_EQ(text, write_scene(a)) << "writing the same scene twice should give the same text";
  EXPECT_EQ(text, write_scene(b)) << "two scenes built the same way should give the same text";
}

TEST(SceneFile, write__follows_the_documented_format) {
  Scene scene;
  build_reference_scene(scene);
  const Json doc = Json::parse(write_scene(scene));
  EXPECT_EQ(doc["rigel"], "scene") << "the file says what it is";
  EXPECT_EQ(doc["version"], kSceneFormatVersion) << "the file carries the format version";
  EXPECT_EQ(doc["fps"], 30.0) << "the frame rate is stored";
  EXPECT_EQ(doc["time"], 0.5) << "the current time is stored in seconds";
  ASSERT_EQ(doc["nodes"].size(), 11u) << "every node is listed";

  std::map<std::string, Json> by_name;
  for (const Json& n : doc["nodes"]) by_name[n["name"].get<std::string>()] = n;
  EXPECT_EQ(by_name["spine.001"]["parent"], "root") << "parents are named, not connected";
  EXPECT_EQ(by_name["spine.001"]["attrs"]["rotateOrder"], "zxy") << "enums are written by name";
  EXPECT_EQ(by_name["spine.001"]["attrs"]["rotate"], Json::parse("[10.0, -20.0, 30.5]")) << "angles stay in degrees";
  EXPECT_EQ(by_name["spine.002"]["attrs"]["rotateMode"], "quaternion") << "the quaternion mode is stored";
  const Quat q = Quat(0.9, 0.1, 0.2, 0.3).normalized();
  EXPECT_EQ(by_name["spine.002"]["attrs"]["rotateQuaternion"], Json::array({q.x(), q.y(), q.z(), q.w()}))
      << "quaternions are [x, y, z, w]";
  const Json& offset = by_name["body"]["attrs"]["offsetParentMatrix"];
  ASSERT_EQ(offset.size(), 16u) << "matrices are 16 numbers";
  EXPECT_EQ(offset[14], -2.0) << "matrices are column-major: the translation is elements 12 to 14";
  EXPECT_EQ(by_name["odd.values"]["attrs"]["translate"], Json::parse(R"(["nan", "inf", "-inf"])"))
      << "non-finite numbers are the strings nan, inf, -inf";
  EXPECT_TRUE(std::signbit(by_name["odd.values"]["attrs"]["rotate"][0].get<double>()))
      << "a negative zero differs from the default and is kept";
  EXPECT_FALSE(by_name["empty_group"].contains("attrs")) << "a node at its defaults writes no attrs";
  EXPECT_FALSE(by_name["follow"].contains("attrs"))
      << "inputs fed by a whole connection are not written: the connection restores them";
  EXPECT_EQ(by_name["épaule_L"]["attrs"]["shapePoints"][3], Json::parse("[0.5, 1.5, 2.5]"))
      << "an array with a connected element is written with the element's current value";
  EXPECT_EQ(by_name["épaule_L"]["tags"], Json::parse(R"({"kind": "fk", "side": "L"})")) << "tags are sorted by key";
  EXPECT_FALSE(by_name["root"].contains("parent")) << "a root names no parent";
  EXPECT_EQ(doc["connections"].size(), 8u)
      << "hierarchy links are written as parents, every other connection as a connection";
  EXPECT_EQ(doc["connections"][0]["src"], "spine.001.radius")
      << "connections are sorted by destination in node order";
}

// ---- undo/redo against serialisation -------------------------------------------

// Random edits through the public Graph and Scene API. Refused edits are
// part of the test: a refused edit must leave nothing behind.
class RandomEditor {
 public:
  RandomEditor(Scene& scene, std::mt19937& rng) : scene_(scene), g_(scene.graph()), rng_(rng) {}

  // One top-level step: an edit, a group of edits in a transaction
  // (sometimes nested, sometimes rolled back), an undo or a redo.
  void step() {
    const int pick = uniform(0, 99);
    if (undid_ && chance(0.5)) {
      log("redo -> " + std::to_string(g_.redo()));
    } else if (pick < 5) {
      log("undo -> " + std::to_string(g_.undo()));
      undid_ = true;
      return;
    } else if (pick < 7) {
      log("redo -> " + std::to_string(g_.redo()));
    } else if (pick < 17) {
      transaction(0);
    } else {
      edit();
    }
    undid_ = false;
  }

  const std::vector<std::string>& history() const { return log_; }

 private:
  int uniform(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng_); }
  bool chance(double p) { return std::bernoulli_distribution(p)(rng_); }
  void log(std::string line) { log_.push_back(std::move(line)); }
  std::string name_of(NodeId id) const { return g_.node(id) ? g_.node(id)->name() : "<none>"; }

  void transaction(int depth) {
    log("begin");
    graph::Transaction t(g_, "random group");
    const int n = uniform(1, 4);
    for (int i = 0; i < n; ++i) {
      if (depth == 0 && chance(0.2)) transaction(depth + 1);
      else edit();
    }
    if (chance(0.25)) {
      log("rollback");
      t.rollback();
    } else {
      log("commit");
    }
  }

  NodeId any_node() {
    std::vector<NodeId> all = g_.nodes();
    if (all.empty()) return NodeId{};
    return all[static_cast<std::size_t>(uniform(0, static_cast<int>(all.size()) - 1))];
  }

  std::string any_name() {
    static const std::vector<std::string> names = {"root", "hips", "spine.001", "spine.002", "arm_L", "arm_L1",
                                                   "ctrl", "loc", "quote\"d", "épaule", "a.b.c", "x9"};
    return names[static_cast<std::size_t>(uniform(0, static_cast<int>(names.size()) - 1))];
  }

  std::string any_type() {
    static const std::vector<std::string> types = {"transform", "joint", "control", "locator", "mesh"};
    return types[static_cast<std::size_t>(uniform(0, 4))];
  }

  double any_double() {
    if (chance(0.85)) return std::uniform_real_distribution<double>(-10.0, 10.0)(rng_);
    static const double special[] = {kNaN, kInf, -kInf, -0.0, 0.0, 1.0, std::numeric_limits<double>::denorm_min(),
                                     1e300, -std::numeric_limits<double>::max()};
    return special[uniform(0, 8)];
  }

  Vec3 any_vec3() { return Vec3(any_double(), any_double(), any_double()); }

  Value any_scalar(const AttrSpec& spec) {
    switch (spec.type.value) {
      case ValueType::kBool: return chance(0.5);
      case ValueType::kInt: return std::int64_t{uniform(-3, 9)};
      case ValueType::kEnum: return std::int64_t{uniform(0, static_cast<int>(spec.enum_names.size()) - 1)};
      case ValueType::kDouble: return any_double();
      case ValueType::kDouble3: return any_vec3();
      case ValueType::kQuat:
        return chance(0.7) ? Quat(Quat(any_double(), any_double(), any_double(), any_double()).normalized())
                           : Quat(any_double(), any_double(), any_double(), any_double());
      case ValueType::kMatrix: {
        if (chance(0.7)) {
          Quat r = Quat(uniform(1, 9), uniform(-9, 9), uniform(-9, 9), uniform(-9, 9)).normalized();
          return math::trs_matrix(any_vec3(), r, Vec3(0.5 + uniform(0, 3), 1.0, 2.0));
        }
        Mat4 m;
        for (int i = 0; i < 16; ++i) m.data()[i] = any_double();
        return m;
      }
      case ValueType::kString: return std::string("s") + std::to_string(uniform(0, 9));
      case ValueType::kMessage: return std::monostate{};
    }
    return std::monostate{};
  }

  // A whole array of 0 to 4 elements, or a scalar.
  Value any_value(const AttrSpec& spec) {
    if (!spec.type.array) return any_scalar(spec);
    Value array = graph::zero_value(spec.type);
    const int n = uniform(0, 4);
    for (int i = 0; i < n; ++i) graph::array_set_element(array, spec.type, static_cast<std::size_t>(i), any_scalar(spec));
    return array;
  }

  void edit() {
    const int pick = uniform(0, 99);
    if (pick < 12) create();
    else if (pick < 17) remove();
    else if (pick < 22) rename();
    else if (pick < 50) set_value();
    else if (pick < 65) connect();
    else if (pick < 73) disconnect();
    else if (pick < 82) set_parent();
    else if (pick < 88) reparent();
    else if (pick < 95) set_tag();
    else remove_tag();
  }

  void create() {
    const std::string type = any_type(), name = any_name();
    if (chance(0.3)) {
      Result<NodeId> id = g_.create_node(type, name);
      log("create_node " + type + " " + name + " -> " + (id ? name_of(*id) : id.status().message()));
    } else {
      NodeId parent = chance(0.6) ? any_node() : NodeId{};
      Result<NodeId> id = scene_.create(type, name, parent);
      log("create " + type + " " + name + " under " + name_of(parent) + " -> " +
          (id ? name_of(*id) : id.status().message()));
    }
  }

  void remove() {
    NodeId id = any_node();
    if (!id.is_valid()) return;
    log("delete " + name_of(id));
    (void)g_.delete_node(id);
  }

  void rename() {
    NodeId id = any_node();
    if (!id.is_valid()) return;
    const std::string name = any_name();
    Status s = g_.rename(id, name);
    log("rename " + name_of(id) + " " + name + " -> " + (s ? "ok" : s.message()));
  }

  void set_value() {
    NodeId id = any_node();
    if (!id.is_valid()) return;
    const graph::NodeType& type = g_.node(id)->type();
    std::vector<AttrIndex> storable;
    for (AttrIndex a = 0; a < type.attr_count(); ++a) {
      const AttrSpec& spec = type.attr(a);
      if ((spec.flags & graph::kInput) && (spec.flags & graph::kStorable)) storable.push_back(a);
    }
    const AttrIndex a = storable[static_cast<std::size_t>(uniform(0, static_cast<int>(storable.size()) - 1))];
    const AttrSpec& spec = type.attr(a);
    Plug plug{id, a, -1};
    Value v;
    if (spec.type.array && chance(0.5)) {
      plug.element = uniform(0, 5);
      v = any_scalar(spec);
    } else {
      v = any_value(spec);
    }
    Status s = g_.set_value(plug, v);
    log("set " + g_.plug_name(plug) + " = " + graph::value_to_text(v) + " -> " + (s ? "ok" : s.message()));
  }

  // Pairs of attributes of matching types on scene nodes; "[]" marks an
  // array attribute used by element.
  void connect() {
    struct Pair {
      const char* src;
      const char* dst;
    };
    static const Pair pairs[] = {
        {"worldMatrix", "offsetParentMatrix"}, {"matrix", "offsetParentMatrix"}, {"translate", "translate"},
        {"rotate", "scale"},                   {"scale", "shear"},               {"rotateOrder", "rotateOrder"},
        {"visibility", "visibility"},          {"rotateQuaternion", "rotateQuaternion"},
        {"radius", "radius"},                  {"shapeColor", "localScale"},     {"points[]", "translate"},
        {"shapePoints[]", "rotate"},           {"translate", "shapePoints[]"},   {"jointOrient", "points[]"},
        {"normals[]", "normals[]"},            {"triangles[]", "triangles[]"},   {"shapeClosed", "visibility"},
        {"points", "shapePoints"},             {"matrix", "parentMatrix"},       {"worldMatrix", "parentMatrix"},
    };
    const Pair& pair = pairs[uniform(0, static_cast<int>(std::size(pairs)) - 1)];
    NodeId src = any_node(), dst = any_node();
    if (!src.is_valid()) return;
    auto plug = [&](NodeId node, std::string attr) -> Result<Plug> {
      std::int32_t element = -1;
      if (attr.ends_with("[]")) {
        attr.resize(attr.size() - 2);
        element = uniform(0, 5);
      }
      return g_.plug_find(node, attr, element);
    };
    Result<Plug> s = plug(src, pair.src), d = plug(dst, pair.dst);
    if (!s || !d) return;  // that node type lacks the attribute
    Status c = g_.connect(*s, *d);
    log("connect " + g_.plug_name(*s) + " " + g_.plug_name(*d) + " -> " + (c ? "ok" : c.message()));
  }

  void disconnect() {
    std::vector<graph::Connection> all = g_.connections();
    if (all.empty()) return;
    const graph::Connection c = all[static_cast<std::size_t>(uniform(0, static_cast<int>(all.size()) - 1))];
    log("disconnect " + g_.plug_name(c.src) + " " + g_.plug_name(c.dst));
    Status s = g_.disconnect(c.src, c.dst);
    EXPECT_TRUE(s.is_ok()) << "disconnecting a listed connection should succeed: " << s.message();
  }

  void set_parent() {
    NodeId child = any_node();
    if (!child.is_valid()) return;
    NodeId parent = chance(0.8) ? any_node() : NodeId{};
    Status s = g_.set_parent(child, parent);
    log("set_parent " + name_of(child) + " " + name_of(parent) + " -> " + (s ? "ok" : s.message()));
  }

  void reparent() {
    NodeId child = any_node();
    if (!child.is_valid()) return;
    NodeId parent = chance(0.8) ? any_node() : NodeId{};
    Status s = scene_.reparent(child, parent, /*keep_world=*/true);
    log("reparent " + name_of(child) + " " + name_of(parent) + " -> " + (s ? "ok" : s.message()));
  }

  void set_tag() {
    NodeId id = any_node();
    if (!id.is_valid()) return;
    static const char* keys[] = {"side", "role", "source", "ünï"};
    const std::string key = keys[uniform(0, 3)];
    const std::string value = std::string("v\"") + std::to_string(uniform(0, 5));
    log("tag " + name_of(id) + " " + key + "=" + value);
    (void)g_.set_tag(id, key, value);
  }

  void remove_tag() {
    NodeId id = any_node();
    if (!id.is_valid() || g_.node(id)->tags().empty()) return;
    const std::string key = g_.node(id)->tags().begin()->first;
    log("untag " + name_of(id) + " " + key);
    (void)g_.remove_tag(id, key);
  }

  Scene& scene_;
  Graph& g_;
  std::mt19937& rng_;
  std::vector<std::string> log_;
  bool undid_ = false;  // the last step was an undo: the next may redo it
};

std::string joined(const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& l : lines) text += "  " + l + "\n";
  return text;
}

TEST(SceneFileUndo, random_edits__undo_to_start_and_redo_to_end_serialize_identically) {
  Scene reference;
  build_reference_scene(reference);
  const std::string base = write_scene(reference);
  // 1,000 sequences in optimised builds (about a second); a fifth in
  // unoptimised sanitizer builds, where each costs some 30 times more.
  // RIGEL_UNDO_SEQUENCES=N runs N instead (for a local hunt).
  const char* override_sequences = std::getenv("RIGEL_UNDO_SEQUENCES");
  const int kSequences = override_sequences ? std::atoi(override_sequences) : 1000 / kSlowBuildDivisor;
  // One sequence in ten (one in fifty in unoptimised builds) also checks
  // every intermediate state on the way back.
  constexpr int kCheckEveryStepOf = 10 * kSlowBuildDivisor;
  const auto began = std::chrono::steady_clock::now();
  for (int sequence = 0; sequence < kSequences; ++sequence) {
    const unsigned seed = 20240u + static_cast<unsigned>(sequence);
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::mt19937 rng(seed);
    std::unique_ptr<Scene> scene = load_or_fail(base, "base.rigel");
    ASSERT_NE(scene, nullptr) << "the scene should load (the reason is reported above)";
    Graph& g = scene->graph();
    RandomEditor editor(*scene, rng);
    // Vary the starting point, then forget how it was reached.
    for (int i = std::uniform_int_distribution<int>(0, 8)(rng); i > 0; --i) editor.step();
    g.clear_history();

    const std::string start = write_scene(*scene);
    const bool every_step = sequence % kCheckEveryStepOf == 0;
    std::map<std::size_t, std::string> at_depth{{0, start}};  // undo_count -> serialised state
    for (int i = std::uniform_int_distribution<int>(10, 30)(rng); i > 0; --i) {
      editor.step();
      if (every_step) at_depth[g.undo_count()] = write_scene(*scene);
    }
    const std::string end = write_scene(*scene);

    int undone = 0;
    while (g.undo()) {
      ++undone;
      if (!every_step) continue;
      const std::string now = write_scene(*scene);
      ASSERT_EQ(now, at_depth[g.undo_count()])
          << "undoing to depth " << g.undo_count() << " should restore the state serialised there: "
          << first_difference(at_depth[g.undo_count()], now) << "\nedits:\n" << joined(editor.history());
    }
    const std::string after_undo = write_scene(*scene);
    ASSERT_EQ(after_undo, start) << "undoing every step should restore the starting scene: "
                                 << first_difference(start, after_undo) << "\nedits:\n" << joined(editor.history());
    for (int i = 0; i < undone; ++i) ASSERT_TRUE(g.redo()) << "each undone step should redo";
    const std::string after_redo = write_scene(*scene);
    ASSERT_EQ(after_redo, end) << "redoing every step should restore the end scene: "
                               << first_difference(end, after_redo) << "\nedits:\n" << joined(editor.history());

    std::unique_ptr<Scene> reloaded = load_or_fail(end, "end.rigel");
    ASSERT_NE(reloaded, nullptr) << "the end scene should load\nedits:\n" << joined(editor.history());
    const std::string resaved = write_scene(*reloaded);
    ASSERT_EQ(resaved, end) << "the end scene should round-trip through the file: " << first_difference(end, resaved)
                            << "\nedits:\n" << joined(editor.history());
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count();
  RecordProperty("seconds", std::to_string(seconds));
}

// ---- versioning ------------------------------------------------------------------

std::string with_version(const std::string& version_member) {
  return "{\n  \"rigel\": \"scene\",\n" + version_member + "  \"nodes\": []\n}\n";
}

TEST(SceneFileVersion, version__newer_older_or_missing_is_refused_naming_the_version) {
  {
    Result<std::unique_ptr<Scene>> r = parse_scene(with_version("  \"version\": 2,\n"), "v2.rigel");
    ASSERT_FALSE(r.is_ok()) << "a version 2 file is newer than this build";
    EXPECT_EQ(r.status().code(), ErrorCode::kUnsupported) << "a newer version is unsupported, not malformed";
    EXPECT_NE(r.status().message().find("version 2"), std::string::npos)
        << "the message should name the version: " << r.status().message();
    EXPECT_NE(r.status().message().find("v2.rigel"), std::string::npos) << "the message should name the file";
  }
  {
    Result<std::unique_ptr<Scene>> r = parse_scene(with_version("  \"version\": 0,\n"), "v0.rigel");
    ASSERT_FALSE(r.is_ok()) << "version 0 never existed";
    EXPECT_NE(r.status().message().find("version 0"), std::string::npos)
        << "the message should name the version: " << r.status().message();
  }
  for (const char* member : {"", "  \"version\": \"1\",\n", "  \"version\": 1.5,\n", "  \"version\": null,\n"}) {
    SCOPED_TRACE(member);
    Result<std::unique_ptr<Scene>> r = parse_scene(with_version(member), "nov.rigel");
    ASSERT_FALSE(r.is_ok()) << "a file without an integer version is refused";
    EXPECT_NE(r.status().message().find("nov.rigel: version:"), std::string::npos)
        << "the message should name the version field: " << r.status().message();
  }
  EXPECT_TRUE(parse_scene(with_version("  \"version\": 1,\n"), "v1.rigel").is_ok()) << "version 1 is read";
}

TEST(SceneFileVersion, version__this_build_writes_version_1) {
  EXPECT_EQ(kSceneFormatVersion, 1)
      << "a new format version needs a new golden file (tests/data/scenes/golden_v<N>.rigel) and a test "
         "that version 1 files still load";
}

TEST(SceneFileVersion, version__golden_v1_loads_and_resaves_byte_for_byte) {
  const fs::path path = scenes_dir() / "golden_v1.rigel";
  const std::string golden = read_text(path);
  ASSERT_FALSE(golden.empty()) << "the golden file should be checked in at " << path;
  Result<std::unique_ptr<Scene>> loaded = load_scene(path);
  ASSERT_TRUE(loaded.is_ok()) << "the golden version-1 file should load: " << loaded.status().message();
  const std::string resaved = write_scene(**loaded);
  EXPECT_EQ(resaved, golden) << "re-saving the golden file should reproduce it byte for byte; a difference "
                                "means the format changed: "
                             << first_difference(golden, resaved);
  Scene reference;
  build_reference_scene(reference);
  EXPECT_TRUE(graphs_identical(reference.graph(), (*loaded)->graph()))
      << "the golden file should load into exactly the scene it was written from";
}

// Rewrites the golden file from the reference scene. Run only on purpose,
// after a deliberate format change (with a new version number):
//   rigel_io_tests --gtest_also_run_disabled_tests --gtest_filter='*regenerate_golden*'
TEST(SceneFileVersion, DISABLED_regenerate_golden_v1) {
  Scene reference;
  build_reference_scene(reference);
  Status s = save_scene(reference, scenes_dir() / "golden_v1.rigel");
  EXPECT_TRUE(s.is_ok()) << "writing the golden file should succeed: " << s.message();
}

// ---- malformed files ---------------------------------------------------------------

// A small valid scene to break one field at a time.
Json base_doc() {
  return Json::parse(R"({
  "rigel": "scene", "version": 1, "fps": 24, "time": 0,
  "nodes": [
    {"name": "a", "type": "joint", "uuid": "a1b2c3d4-0000-4000-8000-000000000001",
     "attrs": {"translate": [1, 2, 3], "rotateOrder": "yzx"}, "tags": {"side": "L"}},
    {"name": "b", "type": "joint", "uuid": "a1b2c3d4-0000-4000-8000-000000000002", "parent": "a"},
    {"name": "c", "type": "mesh", "uuid": "a1b2c3d4-0000-4000-8000-000000000003",
     "attrs": {"triangles": [0, 1, 2]}}
  ],
  "connections": [{"src": "a.worldMatrix", "dst": "c.offsetParentMatrix"}]
})");
}

Json with(Json doc, const std::string& pointer, Json value) {
  doc[Json::json_pointer(pointer)] = std::move(value);
  return doc;
}

Json without(Json doc, const std::string& pointer) {
  Json::json_pointer p(pointer);
  doc[p.parent_pointer()].erase(p.back());
  return doc;
}

Result<std::unique_ptr<Scene>> parse_doc(const Json& doc) { return parse_scene(doc.dump(2), "bad.rigel"); }

// Refused, with a message that starts with the source name and contains
// every one of `parts`.
::testing::AssertionResult refused(const Result<std::unique_ptr<Scene>>& r, const std::vector<std::string>& parts,
                                   const std::string& source = "bad.rigel") {
  if (r.is_ok()) return ::testing::AssertionFailure() << "was accepted";
  const std::string& m = r.status().message();
  if (m.rfind(source, 0) != 0) return ::testing::AssertionFailure() << "message does not start with " << source << ": " << m;
  for (const std::string& p : parts) {
    if (m.find(p) == std::string::npos) return ::testing::AssertionFailure() << "message does not name '" << p << "': " << m;
  }
  return ::testing::AssertionSuccess() << m;
}

struct BadCase {
  std::string pointer;  // JSON pointer into base_doc()
  Json value;           // what replaces it; a discarded value erases the member
  std::vector<std::string> parts;
};

void expect_each_refused(const std::vector<BadCase>& cases) {
  for (const BadCase& c : cases) {
    SCOPED_TRACE(c.pointer + " = " + (c.value.is_discarded() ? "<erased>" : c.value.dump()));
    Json doc = c.value.is_discarded() ? without(base_doc(), c.pointer) : with(base_doc(), c.pointer, c.value);
    EXPECT_TRUE(refused(parse_doc(doc), c.parts)) << "the file should be refused, naming the place";
  }
}

const Json kErase = Json(Json::value_t::discarded);

TEST(SceneFileMalformed, load__base_document_is_valid) {
  Result<std::unique_ptr<Scene>> r = parse_doc(base_doc());
  ASSERT_TRUE(r.is_ok()) << "the document the malformed cases start from should load: " << r.status().message();
  EXPECT_EQ((*r)->graph().node_count(), 3u) << "the base document has three nodes";
}

TEST(SceneFileMalformed, load__empty_file_names_line_one) {
  EXPECT_TRUE(refused(parse_scene("", "empty.rigel"), {"empty.rigel:1:1:"}, "empty.rigel"))
      << "an empty file is a syntax error at its start";
  EXPECT_TRUE(refused(parse_scene("\n\n  ", "blank.rigel"), {"blank.rigel:3:"}, "blank.rigel"))
      << "a blank file is a syntax error at its end";
}

TEST(SceneFileMalformed, load__syntax_error_names_line_and_column) {
  const std::string missing_comma = "{\n  \"rigel\": \"scene\"\n  \"version\": 1\n}\n";
  EXPECT_TRUE(refused(parse_scene(missing_comma, "s.rigel"), {"s.rigel:3:"}, "s.rigel"))
      << "a missing comma is reported on the line of the next member";
  const std::string bad_literal = "{\n  \"rigel\": \"scene\",\n  \"version\": 1,\n  \"fps\": twentyfour\n}\n";
  EXPECT_TRUE(refused(parse_scene(bad_literal, "s.rigel"), {"s.rigel:4:"}, "s.rigel")) << "a bad literal names its line";
  const std::string trailing = "{\"rigel\": \"scene\", \"version\": 1}\n]\n";
  EXPECT_TRUE(refused(parse_scene(trailing, "s.rigel"), {"s.rigel:2:"}, "s.rigel")) << "trailing text names its line";
  const std::string bad_utf8 = "{\"rigel\": \"scene\", \"version\": 1,\n \"nodes\": [{\"name\": \"\xff\", \"type\": \"joint\"}]}";
  EXPECT_TRUE(refused(parse_scene(bad_utf8, "s.rigel"), {"s.rigel:2:"}, "s.rigel")) << "invalid UTF-8 names its line";
  const std::string nul = std::string("{\"rigel\": \"scene\",\n\"version\": 1\0}", 32);
  EXPECT_TRUE(refused(parse_scene(nul, "s.rigel"), {"s.rigel:2:"}, "s.rigel")) << "a NUL byte names its line";
}

TEST(SceneFileMalformed, load__number_too_large_names_the_line) {
  const std::string text = "{\n  \"rigel\": \"scene\",\n  \"version\": 1,\n  \"fps\": 1e999\n}\n";
  EXPECT_TRUE(refused(parse_scene(text, "big.rigel"), {"big.rigel:4:", "1e999"}, "big.rigel"))
      << "a number beyond double range is refused (not thrown) and its line named";
  const std::string in_attr =
      "{\"rigel\": \"scene\", \"version\": 1, \"nodes\": [\n{\"name\": \"a\", \"type\": \"joint\",\n"
      "\"attrs\": {\"translate\": [0, -1e400, 0]}}]}";
  EXPECT_TRUE(refused(parse_scene(in_attr, "big.rigel"), {"big.rigel:3:"}, "big.rigel"))
      << "a huge number inside an attribute names its line";
}

TEST(SceneFileMalformed, load__truncated_files_fail_cleanly_at_every_offset) {
  for (const fs::path& path : {example_path(), scenes_dir() / "golden_v1.rigel"}) {
    const std::string text = read_text(path);
    const std::size_t end = text.rfind('}');
    ASSERT_NE(end, std::string::npos) << path << " should end with an object";
    int checked = 0;
    for (std::size_t cut = 0; cut <= end; cut += kSlowBuildDivisor) {
      const std::string prefix = text.substr(0, cut);
      Result<std::unique_ptr<Scene>> r = parse_scene(prefix, "cut.rigel");
      ASSERT_FALSE(r.is_ok()) << path.filename() << " cut at byte " << cut << " should be refused";
      int line = 0, column = 0;
      ASSERT_EQ(std::sscanf(r.status().message().c_str(), "cut.rigel:%d:%d:", &line, &column), 2)
          << "a truncated file is a syntax error naming line:column: " << r.status().message();
      const int lines = 1 + static_cast<int>(std::count(prefix.begin(), prefix.end(), '\n'));
      ASSERT_EQ(line, lines) << "cut at byte " << cut << ": the error should be on the last line, where the text "
                             << "stops: " << r.status().message();
      ++checked;
    }
    EXPECT_GT(checked, 100) << "many truncations of " << path.filename() << " should be checked";
  }
}

TEST(SceneFileMalformed, load__not_an_object_or_not_a_scene_is_refused) {
  for (const char* text : {"[]", "42", "\"scene\"", "null", "true"}) {
    SCOPED_TRACE(text);
    EXPECT_TRUE(refused(parse_scene(text, "bad.rigel"), {"JSON object"})) << "a scene file is an object";
  }
  expect_each_refused({
      {"/rigel", kErase, {"bad.rigel: rigel:", "not a rigel scene file"}},
      {"/rigel", "rig", {"bad.rigel: rigel:", "not a rigel scene file"}},
      {"/rigel", 1, {"bad.rigel: rigel:"}},
  });
}

TEST(SceneFileMalformed, load__wrong_type_for_each_top_level_field_names_it) {
  expect_each_refused({
      {"/fps", "24", {"bad.rigel: fps:", "expected a number"}},
      {"/fps", Json::array(), {"bad.rigel: fps:"}},
      {"/fps", 0, {"bad.rigel: fps:", "frame rate must be positive"}},
      {"/fps", -24, {"bad.rigel: fps:", "frame rate must be positive"}},
      {"/time", "0", {"bad.rigel: time:", "finite number"}},
      {"/time", "nan", {"bad.rigel: time:"}},
      {"/time", nullptr, {"bad.rigel: time:"}},
      {"/nodes", Json::object(), {"bad.rigel: nodes:", "expected an array"}},
      {"/nodes", "a", {"bad.rigel: nodes:"}},
      {"/connections", Json::object(), {"bad.rigel: connections:", "expected an array"}},
      {"/connections", 0, {"bad.rigel: connections:"}},
  });
}

TEST(SceneFileMalformed, load__wrong_type_for_each_node_field_names_it) {
  expect_each_refused({
      {"/nodes/2", 5, {"nodes[2]:", "expected an object"}},
      {"/nodes/2", Json::array(), {"nodes[2]:"}},
      {"/nodes/1/name", 5, {"nodes[1].name:", "not a string"}},
      {"/nodes/1/name", kErase, {"nodes[1].name:", "missing"}},
      {"/nodes/1/type", 5, {"nodes[1].type:", "not a string"}},
      {"/nodes/1/type", kErase, {"nodes[1].type:", "missing"}},
      {"/nodes/1/uuid", 5, {"nodes[1] (b).uuid:", "not a UUID"}},
      {"/nodes/1/parent", 5, {"nodes[1] (b).parent:", "expected a node name"}},
      {"/nodes/1/parent", nullptr, {"nodes[1] (b).parent:"}},
      {"/nodes/0/attrs", Json::array(), {"nodes[0] (a).attrs:", "expected an object"}},
      {"/nodes/0/attrs", "translate", {"nodes[0] (a).attrs:"}},
      {"/nodes/0/tags", Json::array(), {"nodes[0] (a).tags:", "expected an object"}},
      {"/nodes/0/tags/side", 5, {"nodes[0] (a).tags.side:", "expected a string"}},
      {"/nodes/0/tags/side", nullptr, {"nodes[0] (a).tags.side:"}},
      {"/nodes/0/tags/", "x", {"nodes[0] (a).tags:", "empty"}},
  });
}

TEST(SceneFileMalformed, load__wrong_value_for_each_attribute_kind_names_the_attribute) {
  expect_each_refused({
      // double3 (and angles, which are double3 in degrees)
      {"/nodes/0/attrs/translate", "up", {"nodes[0] (a).attrs.translate:", "expected an array of 3 numbers"}},
      {"/nodes/0/attrs/translate", 1, {"nodes[0] (a).attrs.translate:"}},
      {"/nodes/0/attrs/translate", Json::parse("[1, \"x\", 3]"), {"nodes[0] (a).attrs.translate: [1]:", "expected a number"}},
      {"/nodes/0/attrs/translate", Json::parse("[1, null, 3]"), {"nodes[0] (a).attrs.translate: [1]:"}},
      {"/nodes/0/attrs/rotate", Json::parse("[true, 0, 0]"), {"nodes[0] (a).attrs.rotate: [0]:"}},
      {"/nodes/0/attrs/jointOrient", Json::parse("[0, 0, \"NaN\"]"), {"nodes[0] (a).attrs.jointOrient: [2]:"}},
      // enum
      {"/nodes/0/attrs/rotateOrder", true, {"nodes[0] (a).attrs.rotateOrder:", "expected one of xyz, yzx"}},
      {"/nodes/0/attrs/rotateOrder", 1.5, {"nodes[0] (a).attrs.rotateOrder:"}},
      {"/nodes/0/attrs/rotateMode", "slerp", {"nodes[0] (a).attrs.rotateMode:", "euler, quaternion", "slerp"}},
      // bool
      {"/nodes/0/attrs/visibility", 1, {"nodes[0] (a).attrs.visibility:", "expected true or false"}},
      {"/nodes/0/attrs/visibility", "true", {"nodes[0] (a).attrs.visibility:"}},
      // double
      {"/nodes/0/attrs/radius", "big", {"nodes[0] (a).attrs.radius:", "expected a number"}},
      {"/nodes/0/attrs/radius", Json::array({1}), {"nodes[0] (a).attrs.radius:"}},
      // quaternion and matrix
      {"/nodes/0/attrs/rotateQuaternion", Json::object(), {"nodes[0] (a).attrs.rotateQuaternion:"}},
      {"/nodes/0/attrs/offsetParentMatrix", "identity", {"nodes[0] (a).attrs.offsetParentMatrix:"}},
      // arrays of double3 and of int
      {"/nodes/2/attrs/points", 5, {"nodes[2] (c).attrs.points:", "expected an array of double3"}},
      {"/nodes/2/attrs/points", Json::parse("[[0, 0, 0], [1, 2]]"), {"nodes[2] (c).attrs.points: [1]:", "3 numbers"}},
      {"/nodes/2/attrs/normals", Json::parse("[[0, 1, 0], 7]"), {"nodes[2] (c).attrs.normals: [1]:"}},
      {"/nodes/2/attrs/triangles", Json::parse("[0, 1.5]"), {"nodes[2] (c).attrs.triangles: [1]:", "expected an integer"}},
      {"/nodes/2/attrs/triangles", Json::parse("[0, \"1\"]"), {"nodes[2] (c).attrs.triangles: [1]:"}},
      {"/nodes/2/attrs/triangles", Json::object(), {"nodes[2] (c).attrs.triangles:", "expected an array of int"}},
  });
}

TEST(SceneFileMalformed, load__wrong_array_length_names_the_length) {
  expect_each_refused({
      {"/nodes/0/attrs/translate", Json::parse("[1, 2]"), {".attrs.translate:", "3 numbers", "got 2 elements"}},
      {"/nodes/0/attrs/scale", Json::parse("[1, 2, 3, 4]"), {".attrs.scale:", "got 4 elements"}},
      {"/nodes/0/attrs/rotateQuaternion", Json::parse("[0, 0, 0]"), {".attrs.rotateQuaternion:", "4 numbers"}},
      {"/nodes/0/attrs/offsetParentMatrix", Json::parse("[1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0]"),
       {".attrs.offsetParentMatrix:", "16 numbers", "got 15"}},
      {"/nodes/0/attrs/offsetParentMatrix", Json::parse("[[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]"),
       {".attrs.offsetParentMatrix:", "16 numbers", "got 4"}},
  });
}

TEST(SceneFileMalformed, load__bad_enum_value_lists_the_names) {
  expect_each_refused({
      {"/nodes/0/attrs/rotateOrder", "xzz", {"nodes[0] (a).attrs.rotateOrder:", "xyz, yzx, zxy, xzy, yxz, zyx", "xzz"}},
      {"/nodes/0/attrs/rotateOrder", "XYZ", {"nodes[0] (a).attrs.rotateOrder:"}},
      {"/nodes/0/attrs/rotateOrder", 6, {"nodes[0] (a).attrs.rotateOrder:"}},
      {"/nodes/0/attrs/rotateOrder", -1, {"nodes[0] (a).attrs.rotateOrder:"}},
  });
  Result<std::unique_ptr<Scene>> by_index = parse_doc(with(base_doc(), "/nodes/0/attrs/rotateOrder", 5));
  ASSERT_TRUE(by_index.is_ok()) << "an enum may also be written by index: " << by_index.status().message();
  EXPECT_NE(write_scene(**by_index).find("\"rotateOrder\": \"zyx\""), std::string::npos)
      << "an enum read by index is written by name";
}

TEST(SceneFileMalformed, load__unknown_node_type_names_the_node) {
  expect_each_refused({
      {"/nodes/2/type", "bone", {"nodes[2] (c).type:", "unknown node type 'bone'"}},
      {"/nodes/2/type", "", {"nodes[2] (c).type:"}},
      {"/nodes/2/type", "Joint", {"nodes[2] (c).type:", "'Joint'"}},
  });
}

TEST(SceneFileMalformed, load__unknown_or_unstored_attribute_names_it) {
  expect_each_refused({
      {"/nodes/0/attrs/foo", 1, {"nodes[0] (a).attrs.foo:", "no attribute 'foo'"}},
      {"/nodes/0/attrs/points", Json::array(), {"nodes[0] (a).attrs.points:", "'joint' has no attribute 'points'"}},
      {"/nodes/0/attrs/Translate", Json::parse("[0, 0, 0]"), {"nodes[0] (a).attrs.Translate:"}},
      {"/nodes/0/attrs/worldMatrix", Json::parse("[1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]"),
       {"nodes[0] (a).attrs.worldMatrix:", "not stored in files"}},
      {"/nodes/0/attrs/matrix", Json::parse("[1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]"), {"nodes[0] (a).attrs.matrix:", "not stored"}},
  });
}

TEST(SceneFileMalformed, load__unknown_keys_are_refused) {
  expect_each_refused({
      {"/nodez", Json::array(), {"bad.rigel:", "unknown key 'nodez'"}},
      {"/nodes/1/parnt", "a", {"nodes[1]:", "unknown key 'parnt'"}},
      {"/connections/0/via", "x", {"connections[0]:", "unknown key 'via'"}},
  });
}

TEST(SceneFileMalformed, load__bad_names_and_uuids_are_refused) {
  expect_each_refused({
      {"/nodes/2/name", "a", {"nodes[2] (a).name:", "duplicate node name", "nodes[0]"}},
      {"/nodes/1/name", "", {"nodes[1] ().name:", "invalid node name"}},
      {"/nodes/1/name", "two words", {"nodes[1] (two words).name:", "invalid node name"}},
      {"/nodes/1/name", "arm[0]", {"nodes[1] (arm[0]).name:", "invalid node name"}},
      {"/nodes/2/uuid", "a1b2c3d4-0000-4000-8000-000000000001", {"nodes[2] (c).uuid:", "duplicate uuid"}},
      {"/nodes/2/uuid", "A1B2C3D4-0000-4000-8000-000000000001", {"nodes[2] (c).uuid:", "duplicate uuid"}},
      {"/nodes/1/uuid", "not-a-uuid", {"nodes[1] (b).uuid:", "not a UUID", "not-a-uuid"}},
      {"/nodes/1/uuid", "", {"nodes[1] (b).uuid:", "not a UUID"}},
      {"/nodes/1/uuid", "a1b2c3d4-0000-4000-8000-00000000000g", {"nodes[1] (b).uuid:"}},
      {"/nodes/1/uuid", "a1b2c3d4-0000-4000-8000-0000000000001", {"nodes[1] (b).uuid:"}},
      {"/nodes/1/uuid", "a1b2c3d400000-4000-8000-000000000001", {"nodes[1] (b).uuid:"}},
      {"/nodes/1/uuid", "00000000-0000-0000-0000-000000000000", {"nodes[1] (b).uuid:", "not a UUID"}},
  });
}

TEST(SceneFileMalformed, load__dangling_parent_names_the_missing_node) {
  expect_each_refused({
      {"/nodes/1/parent", "ghost", {"nodes[1] (b).parent:", "no node named 'ghost'"}},
      {"/nodes/1/parent", "", {"nodes[1] (b).parent:"}},
  });
}

TEST(SceneFileMalformed, load__dangling_connection_names_the_missing_node_or_attribute) {
  expect_each_refused({
      {"/connections/0/src", "ghost.worldMatrix", {"connections[0].src:", "no node named 'ghost'"}},
      {"/connections/0/dst", "ghost.offsetParentMatrix", {"connections[0].dst:", "no node named 'ghost'"}},
      {"/connections/0/dst", "c.nothing", {"connections[0].dst:", "no attribute 'nothing'"}},
      {"/connections/0/src", "a", {"connections[0].src:", "bad plug 'a'"}},
      {"/connections/0/src", ".worldMatrix", {"connections[0].src:", "bad plug"}},
      {"/connections/0/dst", "c.points[x]", {"connections[0].dst:", "bad plug"}},
      {"/connections/0/dst", "c.points[-1]", {"connections[0].dst:", "bad plug"}},
      {"/connections/0/dst", "c.points[99999999999]", {"connections[0].dst:", "bad plug"}},
      {"/connections/0/dst", "c.points[1048576]", {"connections[0].dst:", "index too large"}},
      {"/connections/0/src", "a.translate[0]", {"connections[0].src:", "not an array"}},
      {"/connections/0", "a.worldMatrix", {"connections[0]:", "expected an object"}},
      {"/connections/0/src", 5, {"connections[0].src:", "missing or not a string"}},
      {"/connections/0/dst", kErase, {"connections[0].dst:", "missing"}},
  });
}

TEST(SceneFileMalformed, load__type_mismatched_connection_names_both_types) {
  expect_each_refused({
      {"/connections/0/src", "a.translate", {"connections[0]:", "types differ", "double3", "matrix"}},
      {"/connections/0/src", "c.points", {"connections[0]:", "types differ", "double3[]"}},
      {"/connections/0/dst", "c.worldMatrix", {"connections[0]:", "destination is an output"}},
  });
}

TEST(SceneFileMalformed, load__duplicate_destination_is_refused) {
  Json doc = base_doc();
  doc["connections"].push_back({{"src", "b.worldMatrix"}, {"dst", "c.offsetParentMatrix"}});
  EXPECT_TRUE(refused(parse_doc(doc), {"connections[1]:", "c.offsetParentMatrix", "already connected", "a.worldMatrix"}))
      << "a destination has one source";
  Json element = base_doc();
  element["connections"].push_back({{"src", "a.translate"}, {"dst", "c.points[1]"}});
  element["connections"].push_back({{"src", "b.translate"}, {"dst", "c.points[1]"}});
  EXPECT_TRUE(refused(parse_doc(element), {"connections[2]:", "already connected"})) << "an element has one source";
  Json whole = base_doc();
  whole["nodes"].push_back({{"name", "d"}, {"type", "mesh"}});
  whole["connections"].push_back({{"src", "a.translate"}, {"dst", "c.points[1]"}});
  whole["connections"].push_back({{"src", "d.points"}, {"dst", "c.points"}});
  EXPECT_TRUE(refused(parse_doc(whole), {"connections[2]:", "c.points[1] is already connected"}))
      << "a whole array cannot be fed while one of its elements is";
  Json parent = base_doc();
  parent["connections"].push_back({{"src", "c.worldMatrix"}, {"dst", "b.parentMatrix"}});
  EXPECT_TRUE(refused(parse_doc(parent), {"connections[1]:", "already connected"}))
      << "a connection cannot take the parent input of a parented node";
}

TEST(SceneFileMalformed, load__cyclic_parents_name_the_cycle) {
  Json doc = Json::parse(R"({"rigel": "scene", "version": 1, "nodes": [
    {"name": "hip_L", "type": "joint", "parent": "ankle_L"},
    {"name": "knee_L", "type": "joint", "parent": "hip_L"},
    {"name": "ankle_L", "type": "joint", "parent": "knee_L"}]})");
  EXPECT_TRUE(refused(parse_doc(doc), {"nodes[2] (ankle_L).parent:", "cycle", "hip_L", "knee_L", "ankle_L"}))
      << "a parent cycle is refused at the node that closes it, naming the nodes on it";
  EXPECT_TRUE(refused(parse_doc(with(base_doc(), "/nodes/1/parent", "b")), {"nodes[1] (b).parent:", "cycle"}))
      << "a node cannot be its own parent";
}

TEST(SceneFileMalformed, load__cyclic_connections_name_the_cycle) {
  Json doc = Json::parse(R"({"rigel": "scene", "version": 1,
    "nodes": [{"name": "alpha", "type": "transform"}, {"name": "beta", "type": "transform"},
              {"name": "gamma", "type": "transform"}],
    "connections": [{"src": "alpha.worldMatrix", "dst": "beta.offsetParentMatrix"},
                    {"src": "beta.worldMatrix", "dst": "gamma.offsetParentMatrix"},
                    {"src": "gamma.worldMatrix", "dst": "alpha.offsetParentMatrix"}]})");
  EXPECT_TRUE(refused(parse_doc(doc), {"connections[2]:", "cycle", "alpha -> beta -> gamma -> alpha"}))
      << "a connection cycle is refused at the connection that closes it, naming the cycle";
  Json mixed = Json::parse(R"({"rigel": "scene", "version": 1,
    "nodes": [{"name": "upper", "type": "joint"}, {"name": "lower", "type": "joint", "parent": "upper"}],
    "connections": [{"src": "lower.translate", "dst": "upper.translate"}]})");
  EXPECT_TRUE(refused(parse_doc(mixed), {"connections[0]:", "cycle", "upper", "lower"}))
      << "a connection that loops back through the hierarchy is a cycle";
  Json self = Json::parse(R"({"rigel": "scene", "version": 1, "nodes": [{"name": "solo", "type": "joint"}],
    "connections": [{"src": "solo.translate", "dst": "solo.rotate"}]})");
  EXPECT_TRUE(refused(parse_doc(self), {"connections[0]:", "cycle", "solo -> solo"})) << "a node cannot feed itself";
}

TEST(SceneFileMalformed, load__non_finite_strings_and_optional_fields_are_accepted) {
  Json doc = Json::parse(R"({"rigel": "scene", "version": 1, "nodes": [
    {"name": "n", "type": "joint", "attrs": {"translate": ["nan", "inf", "-inf"], "radius": "inf"}}]})");
  Result<std::unique_ptr<Scene>> r = parse_doc(doc);
  ASSERT_TRUE(r.is_ok()) << "nan, inf and -inf strings are numbers in a scene file: " << r.status().message();
  Graph& g = (*r)->graph();
  const NodeId n = g.find("n");
  ASSERT_TRUE(n.is_valid()) << "the node should exist";
  const Vec3 t = std::get<Vec3>(g.node(n)->value(scene::xform::kTranslate));
  EXPECT_TRUE(std::isnan(t.x()) && t.y() == kInf && t.z() == -kInf) << "the strings decode to nan, inf, -inf";
  EXPECT_EQ(g.fps(), 24.0) << "a missing fps is the default 24";
  EXPECT_EQ(g.time(), 0.0) << "a missing time is 0";
  EXPECT_FALSE(g.node(n)->uuid().is_nil()) << "a node without a uuid gets a fresh one";
  EXPECT_FALSE(g.can_undo()) << "loading leaves no undo history";
}

// ---- fuzz ------------------------------------------------------------------------

// Byte-level mutations of valid files. Every result must either load or be
// refused with a message that starts with the source name; whatever loads
// must save to a text that loads back to the same text.
std::string mutate(std::string text, std::mt19937& rng) {
  static const std::vector<std::string> tokens = {
      "{", "}", "[", "]", "\"", ",", ":", "null", "true", "\"nan\"", "1e999", "-1e999", "-0.0", "[]", "{}", "\"\"",
      "\"joint\"", "\"parent\"", "\"attrs\"", "\"worldMatrix\"", "\"\\u0000\"", "\"\\ud800\"", "[[[[", "}}}}",
      "18446744073709551615", "1048575", "\"a.translate\"", "\\", "\xc3", "\xff"};
  auto pick = [&](std::size_t n) { return n == 0 ? std::size_t{0} : std::uniform_int_distribution<std::size_t>(0, n - 1)(rng); };
  const int count = std::uniform_int_distribution<int>(1, 4)(rng);
  for (int i = 0; i < count; ++i) {
    const std::size_t at = pick(text.size() + 1);
    switch (std::uniform_int_distribution<int>(0, 4)(rng)) {
      case 0:  // flip a bit
        if (at < text.size()) text[at] = static_cast<char>(text[at] ^ (1 << pick(8)));
        break;
      case 1:  // replace a byte with a JSON-significant one
        if (at < text.size()) text[at] = "{}[]\":,0123456789-.eE ntf\\\n"[pick(27)];
        break;
      case 2:  // insert a token
        text.insert(at, tokens[pick(tokens.size())]);
        break;
      case 3:  // delete a span
        text.erase(at, pick(16) + 1);
        break;
      default: {  // duplicate a span elsewhere
        const std::size_t from = pick(text.size());
        const std::string span = text.substr(from, pick(64) + 1);
        text.insert(pick(text.size() + 1), span);
        break;
      }
    }
  }
  return text;
}

TEST(SceneFileFuzz, random_byte_mutations_load_or_fail_cleanly) {
  const std::vector<std::string> inputs = {read_text(example_path()), read_text(scenes_dir() / "golden_v1.rigel")};
  // RIGEL_FUZZ_ITERATIONS=N runs a longer fuzz (for a local hunt; the
  // default keeps the test near a second).
  const char* override_iterations = std::getenv("RIGEL_FUZZ_ITERATIONS");
  const int iterations = override_iterations ? std::atoi(override_iterations) : 3000 / kSlowBuildDivisor;
  int loaded = 0, refused_count = 0;
  for (std::size_t k = 0; k < inputs.size(); ++k) {
    std::mt19937 rng(77u + static_cast<unsigned>(k));
    SCOPED_TRACE("input " + std::to_string(k) + ", seed " + std::to_string(77 + k));
    for (int i = 0; i < iterations; ++i) {
      const std::string text = mutate(inputs[k], rng);
      Result<std::unique_ptr<Scene>> r = parse_scene(text, "fuzz.rigel");
      if (!r.is_ok()) {
        ++refused_count;
        ASSERT_EQ(r.status().message().rfind("fuzz.rigel", 0), 0u)
            << "iteration " << i << ": a refusal should name the source: " << r.status().message();
        ASSERT_GT(r.status().message().size(), std::string("fuzz.rigel: ").size())
            << "iteration " << i << ": a refusal should say why";
        continue;
      }
      ++loaded;
      const std::string saved = write_scene(**r);
      Result<std::unique_ptr<Scene>> again = parse_scene(saved, "fuzz-resaved.rigel");
      ASSERT_TRUE(again.is_ok()) << "iteration " << i << ": a scene that loaded should load again after saving: "
                                 << again.status().message();
      const std::string resaved = write_scene(**again);
      ASSERT_EQ(saved, resaved) << "iteration " << i << ": the saved text should be stable: "
                                << first_difference(saved, resaved);
    }
  }
  RecordProperty("loaded", loaded);
  RecordProperty("refused", refused_count);
  EXPECT_GT(refused_count, 0) << "most mutations should break the file";
  EXPECT_GT(loaded, 0) << "some mutations (inside numbers, say) should still load";
}

// Every member and element of the golden file replaced, in turn, by values
// of every JSON kind, and every object member removed.
void collect_pointers(const Json& j, const Json::json_pointer& at, std::vector<Json::json_pointer>& out) {
  if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it) {
      out.push_back(at / it.key());
      collect_pointers(it.value(), at / it.key(), out);
    }
  } else if (j.is_array()) {
    for (std::size_t i = 0; i < j.size(); ++i) {
      out.push_back(at / i);
      collect_pointers(j[i], at / i, out);
    }
  }
}

TEST(SceneFileFuzz, every_field_replaced_by_every_json_kind_loads_or_fails_cleanly) {
  const Json golden = Json::parse(read_text(scenes_dir() / "golden_v1.rigel"));
  std::vector<Json::json_pointer> pointers;
  collect_pointers(golden, Json::json_pointer(), pointers);
  const std::vector<Json> replacements = {nullptr, true, 0, -1, 2.5, "", "nan", "root", Json::array(),
                                          Json::object(), Json::array({1, 2, 3}), Json::array({"x"})};
  int checked = 0;
  for (std::size_t p = 0; p < pointers.size(); p += kSlowBuildDivisor > 1 ? 3 : 1) {
    for (std::size_t r = 0; r <= replacements.size(); ++r) {
      Json doc = golden;
      std::string what;
      if (r == replacements.size()) {
        if (!doc[pointers[p].parent_pointer()].is_object()) continue;
        doc[pointers[p].parent_pointer()].erase(pointers[p].back());
        what = pointers[p].to_string() + " erased";
      } else {
        doc[pointers[p]] = replacements[r];
        what = pointers[p].to_string() + " = " + replacements[r].dump();
      }
      Result<std::unique_ptr<Scene>> loaded = parse_scene(doc.dump(1), "field.rigel");
      ++checked;
      if (!loaded.is_ok()) {
        ASSERT_EQ(loaded.status().message().rfind("field.rigel: ", 0), 0u)
            << what << ": a refusal should name the source and a place: " << loaded.status().message();
        continue;
      }
      const std::string saved = write_scene(**loaded);
      Result<std::unique_ptr<Scene>> again = parse_scene(saved, "field-resaved.rigel");
      ASSERT_TRUE(again.is_ok()) << what << ": a scene that loaded should load again after saving: "
                                 << again.status().message();
      ASSERT_EQ(saved, write_scene(**again)) << what << ": the saved text should be stable";
    }
  }
  EXPECT_GT(checked, 500) << "the golden file has hundreds of fields";
}

// ---- files and atomic writes ---------------------------------------------------------

std::vector<std::string> temporaries(const TempDir& dir) {
  std::vector<std::string> left;
  for (const std::string& name : dir.entries())
    if (name.find(".tmp-") != std::string::npos) left.push_back(name);
  return left;
}

TEST(SceneFileSave, save__writes_a_file_that_loads_back) {
  TempDir dir;
  Scene scene;
  build_reference_scene(scene);
  const fs::path path = dir.path() / "scene.rigel";
  Status s = save_scene(scene, path);
  ASSERT_TRUE(s.is_ok()) << "saving into a writable folder should succeed: " << s.message();
  EXPECT_EQ(read_text(path), write_scene(scene)) << "the file holds exactly what write_scene gives";
  Result<std::unique_ptr<Scene>> loaded = load_scene(path);
  ASSERT_TRUE(loaded.is_ok()) << "the saved file should load: " << loaded.status().message();
  EXPECT_TRUE(graphs_identical(scene.graph(), (*loaded)->graph())) << "the saved file loads into the same scene";
  EXPECT_TRUE(temporaries(dir).empty()) << "no temporary file should be left after a successful save";
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"scene.rigel"}) << "only the scene file should be written";
}

TEST(SceneFileSave, save__replaces_an_existing_file) {
  TempDir dir;
  const fs::path path = dir.path() / "scene.rigel";
  write_text(path, std::string(100000, 'x'));  // longer than the scene: a replace, not an overwrite in place
  Scene scene;
  build_reference_scene(scene);
  Status s = save_scene(scene, path);
  ASSERT_TRUE(s.is_ok()) << "saving over an existing file should succeed: " << s.message();
  EXPECT_EQ(read_text(path), write_scene(scene)) << "the old content should be gone entirely";
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"scene.rigel"}) << "no temporary file should be left";
}

TEST(SceneFileSave, save__into_a_missing_folder_fails_naming_the_path) {
  TempDir dir;
  const fs::path path = dir.path() / "missing" / "scene.rigel";
  Scene scene;
  Status s = save_scene(scene, path);
  ASSERT_FALSE(s.is_ok()) << "a folder that does not exist cannot receive a file";
  EXPECT_EQ(s.code(), ErrorCode::kIoError) << "it is the operating system refusing: " << s.message();
  EXPECT_NE(s.message().find(path.string()), std::string::npos) << "the message should name the path: " << s.message();
  EXPECT_TRUE(dir.entries().empty()) << "nothing should be created beside the missing folder";
}

TEST(SceneFileSave, save__onto_a_folder_fails_and_leaves_no_temporary_file) {
  TempDir dir;
  const fs::path path = dir.path() / "taken";
  fs::create_directory(path);
  Scene scene;
  build_reference_scene(scene);
  Status s = save_scene(scene, path);
  ASSERT_FALSE(s.is_ok()) << "a folder cannot be replaced by a scene file";
  EXPECT_EQ(s.code(), ErrorCode::kIoError) << "it is the operating system refusing: " << s.message();
  EXPECT_NE(s.message().find(path.string()), std::string::npos) << "the message should name the path: " << s.message();
  EXPECT_TRUE(temporaries(dir).empty()) << "the temporary file should be removed after the failed rename";
  EXPECT_TRUE(fs::is_directory(path)) << "the folder should be untouched";
}

TEST(SceneFileSave, write_file_atomic__writes_exact_bytes) {
  TempDir dir;
  const fs::path path = dir.path() / "bytes.bin";
  const std::string content("with\0nul\nand\xff bytes", 19);
  Status s = write_file_atomic(path, content);
  ASSERT_TRUE(s.is_ok()) << "writing should succeed: " << s.message();
  EXPECT_EQ(read_text(path), content) << "the bytes should be written unchanged";
  ASSERT_TRUE(write_file_atomic(path, "").is_ok()) << "an empty file can be written";
  EXPECT_EQ(fs::file_size(path), 0u) << "the empty content replaces the old";
  EXPECT_TRUE(temporaries(dir).empty()) << "no temporary file should be left";
}

// ---- streaming writes (issue 14: a baked shot's file is hundreds of MB) ----

// Records the pieces a stream is handed.
class PieceRecorder : public std::streambuf {
 public:
  std::string text;
  std::size_t pieces = 0;
  std::size_t largest = 0;

 protected:
  std::streamsize xsputn(const char* s, std::streamsize n) override {
    text.append(s, static_cast<std::size_t>(n));
    ++pieces;
    largest = std::max(largest, static_cast<std::size_t>(n));
    return n;
  }
  int_type overflow(int_type c) override {
    if (traits_type::eq_int_type(c, traits_type::eof())) return traits_type::not_eof(c);
    const char ch = traits_type::to_char_type(c);
    return xsputn(&ch, 1) == 1 ? c : traits_type::eof();
  }
};

// A scene with long animation curves (keys a hair off the frames, values
// over many magnitudes) beside a few transforms: nodes of every size.
std::string long_curves_scene_text(int keys) {
  std::mt19937_64 random(14);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-30, 30);
  Json doc = {{"rigel", "scene"}, {"version", 1}, {"fps", 120.0}, {"time", 0.25}, {"nodes", Json::array()},
              {"connections", Json::array()}};
  doc["nodes"].push_back({{"name", "root"}, {"type", "transform"}, {"attrs", {{"translate", {0.1, 2.0, -3.5}}}}});
  for (int c = 0; c < 3; ++c) {
    Json times = Json::array(), values = Json::array();
    for (int k = 0; k < keys; ++k) {
      times.push_back(k / 120.0 + 1e-9 * c);
      values.push_back(unit(random) * std::pow(10.0, exponent(random)));
    }
    const std::string name = "curve" + std::to_string(c);
    doc["nodes"].push_back({{"name", name}, {"type", "animCurve"}, {"attrs", {{"keyTimes", times}, {"keyValues", values}}}});
    doc["connections"].push_back({{"src", name + ".output"}, {"dst", std::string("root.translate") + "XYZ"[c]}});
  }
  doc["nodes"].push_back({{"name", "tip"}, {"type", "joint"}, {"parent", "root"}});
  return doc.dump();
}

TEST(DiffableJson, scalars_are_written_as_json_dump_writes_them) {
  // The writer formats scalars itself (no string per number); the text must
  // stay that of nlohmann's dump, which the golden files were written with.
  std::mt19937_64 random(7);
  Json array = Json::array();
  std::string expected = "[";
  auto add = [&](const Json& v) {
    expected += (array.empty() ? "" : ", ") + v.dump(-1, ' ', false, Json::error_handler_t::replace);
    array.push_back(v);
  };
  for (int i = 0; i < 20000; ++i) {
    const double d = std::bit_cast<double>(random());
    if (std::isfinite(d)) add(d);
  }
  for (double d : {0.0, -0.0, 1.0, 0.1, 1e15, 1e16, 1e-5, 1e-4, 123456789012345678.0, 5e-324, 1.7976931348623157e308,
                   -2.5, 1.0 / 3.0, 100.0, 1e21, 1e22})
    add(d);
  for (std::int64_t i : {std::int64_t{0}, std::int64_t{-1}, std::numeric_limits<std::int64_t>::min(),
                         std::numeric_limits<std::int64_t>::max()})
    add(i);
  add(std::numeric_limits<std::uint64_t>::max());
  add(true);
  add(false);
  add(nullptr);
  add(kNaN);  // dump writes null
  for (const char* text : {"", "plain ascii ~", "quote \" and \\ backslash", "tab\tnewline\n\x01\x1f\x7f", "épaule",
                           "bad \xff utf-8"})
    add(std::string(text));
  expected += "]\n";
  EXPECT_EQ(diffable_json(array), expected) << "each scalar should read as Json::dump writes it";
  const Json object = {{"plain", 1}, {"needs \"escaping\"\n", 2}, {"épaule", 3}, {"bad \xfe", 4}};
  EXPECT_EQ(diffable_json(object), "{\n  \"plain\": 1,\n  \"needs \\\"escaping\\\"\\n\": 2,\n  \"épaule\": 3,\n  \"bad \xef\xbf\xbd\": 4\n}\n")
      << "keys are escaped as dump escapes strings";
}

TEST(DiffableJson, writer_hands_the_stream_bounded_pieces_of_the_same_text) {
  Json doc = {{"keys", Json::array()}, {"objects", Json::array()}};
  for (int i = 0; i < 100000; ++i) doc["keys"].push_back(i / 7.0);
  for (int i = 0; i < 5000; ++i) doc["objects"].push_back({{"time", i / 3.0}, {"value", {i, i + 1}}});
  // Repeated and colliding doubles (the writer keeps the text of recent ones).
  std::mt19937_64 random(3);
  doc["random"] = Json::array();
  for (int i = 0; i < 200000; ++i)
    if (const double d = std::bit_cast<double>(random()); std::isfinite(d)) doc["random"].push_back(d);
  doc["again"] = doc["keys"];
  doc["random again"] = doc["random"];
  for (bool inline_flat : {false, true}) {
    const DiffableJsonOptions options{.inline_flat_objects_in_arrays = inline_flat, .scalar = nullptr};
    const std::string whole = diffable_json(doc, options);
    PieceRecorder recorder;
    std::ostream out(&recorder);
    write_diffable_json(out, doc, options);
    EXPECT_EQ(recorder.text, whole) << "streamed and whole text should be the same (inline_flat " << inline_flat << ")";
    EXPECT_GT(recorder.pieces, whole.size() / (2 * DiffableJsonWriter::kChunk))
        << "a " << whole.size() << "-byte text should reach the stream in pieces, not at the end";
    EXPECT_LE(recorder.largest, DiffableJsonWriter::kChunk + 4096)
        << "no piece should be much larger than the writer's chunk, whatever the size of one array";
  }
}

TEST(SceneFileSave, save__streams_long_curves_to_the_text_write_scene_gives) {
  // save_scene writes node by node (no document, no whole text); the file
  // must be the text of the whole-document layout all the same.
  const int keys = 30000 / kSlowBuildDivisor;
  std::unique_ptr<Scene> scene = load_or_fail(long_curves_scene_text(keys), "long.rigel");
  ASSERT_NE(scene, nullptr) << "the scene should load (the reason is reported above)";
  TempDir dir;
  const fs::path path = dir.path() / "long.rigel";
  Status s = save_scene(*scene, path);
  ASSERT_TRUE(s.is_ok()) << "saving should succeed: " << s.message();
  const std::string saved = read_text(path);
  EXPECT_EQ(saved, write_scene(*scene)) << "the streamed file holds exactly what write_scene gives";
  const Json parsed = Json::parse(saved);
  EXPECT_EQ(saved, diffable_json(parsed)) << "the file should be laid out as diffable_json lays out the whole document: "
                                          << first_difference(saved, diffable_json(parsed));
  EXPECT_EQ(parsed["nodes"][1]["attrs"]["keyTimes"].size(), static_cast<std::size_t>(keys)) << "every key is written";
  std::unique_ptr<Scene> loaded = load_or_fail(saved, "long.rigel");
  ASSERT_NE(loaded, nullptr) << "the saved file should load (the reason is reported above)";
  EXPECT_TRUE(graphs_identical(scene->graph(), loaded->graph())) << "the long curves should round-trip exactly";
  EXPECT_TRUE(temporaries(dir).empty()) << "no temporary file should be left";
}

TEST(SceneFileSave, save__scenes_without_nodes_or_connections_keep_the_layout) {
  TempDir dir;
  Scene empty;
  Scene nodes_only;
  Builder(nodes_only).node("transform", "alone", 1);
  for (Scene* scene : {&empty, &nodes_only}) {
    const fs::path path = dir.path() / "scene.rigel";
    ASSERT_TRUE(save_scene(*scene, path).is_ok()) << "saving should succeed";
    const std::string saved = read_text(path);
    EXPECT_EQ(saved, diffable_json(Json::parse(saved))) << "empty arrays are written [] as diffable_json writes them: "
                                                        << saved;
  }
}

TEST(SceneFileLoad, load__missing_file_is_an_io_error_naming_the_path) {
  TempDir dir;
  const fs::path path = dir.path() / "nowhere.rigel";
  Result<std::unique_ptr<Scene>> r = load_scene(path);
  ASSERT_FALSE(r.is_ok()) << "a missing file cannot load";
  EXPECT_EQ(r.status().code(), ErrorCode::kIoError) << "a missing file is an I/O error: " << r.status().message();
  EXPECT_EQ(r.status().message().rfind(path.string(), 0), 0u) << "the message should start with the path: "
                                                              << r.status().message();
}

TEST(SceneFileLoad, load__folder_is_an_io_error_naming_the_path) {
  TempDir dir;
  Result<std::unique_ptr<Scene>> r = load_scene(dir.path());
  ASSERT_FALSE(r.is_ok()) << "a folder is not a scene file";
  EXPECT_EQ(r.status().code(), ErrorCode::kIoError)
      << "a folder is an I/O error, not a syntax error: " << r.status().message();
  EXPECT_EQ(r.status().message().rfind(dir.path().string(), 0), 0u) << "the message should start with the path: "
                                                                    << r.status().message();
}

TEST(SceneFileLoad, load__file_errors_name_the_file_path) {
  const fs::path path = scenes_dir() / "malformed_wrong_type.rigel";
  Result<std::unique_ptr<Scene>> r = load_scene(path);
  EXPECT_TRUE(refused(r, {path.string() + ": nodes[1] (tip).attrs.translate:"}, path.string()))
      << "load_scene names the file by its path and the place inside it";
}

TEST(SceneFile, round_trip__a_root_parent_matrix_set_directly_is_kept) {
  Scene original;
  Graph& g = original.graph();
  Result<NodeId> root = g.create_node("joint", "root");
  ASSERT_TRUE(root.is_ok()) << "create";
  Mat4 above = Mat4::Identity();
  above(1, 3) = 2.5;
  ASSERT_TRUE(g.set_value(*g.plug_find("root.parentMatrix"), above).is_ok()) << "a root's parentMatrix can be set";
  std::unique_ptr<Scene> loaded = load_or_fail(write_scene(original), "root.rigel");
  ASSERT_TRUE(loaded) << "the scene loads";
  EXPECT_EQ(loaded->world_matrix(loaded->graph().find("root"))(1, 3), 2.5)
      << "the stored parentMatrix still places the root after a reload";
}

TEST(SceneFile, round_trip__animated_scene_loads_with_ops_node_types) {
  // Files hold ops nodes (curves) too: load_scene uses every registered type.
  Scene original(ops::default_registry());
  Graph& g = original.graph();
  Result<NodeId> joint = g.create_node("joint", "hip");
  Result<NodeId> curve = g.create_node("animCurveVec3", "hip_translate");
  ASSERT_TRUE(joint.is_ok() && curve.is_ok()) << "create a joint and a translate track";
  ASSERT_TRUE(g.set_value(*g.plug_find("hip_translate.keyTimes"), std::vector<double>{0.0, 1.0}).is_ok()) << "times";
  ASSERT_TRUE(g.set_value(*g.plug_find("hip_translate.keyValues"), std::vector<Vec3>{Vec3(0, 0, 0), Vec3(2, 4, 6)}).is_ok())
      << "values";
  ASSERT_TRUE(g.connect(*g.plug_find("hip_translate.output"), *g.plug_find("hip.translate")).is_ok()) << "drive translate";
  g.set_time(0.25);
  const std::string text = write_scene(original);
  std::unique_ptr<Scene> loaded = load_or_fail(text, "anim.rigel");
  ASSERT_TRUE(loaded) << "an animated scene loads";
  EXPECT_TRUE(graphs_identical(original.graph(), loaded->graph())) << "and round-trips";
  const Mat4 world = loaded->world_matrix(loaded->graph().find("hip"));
  EXPECT_NEAR(world(0, 3), 0.5, 1e-12) << "the track is evaluated at the stored time (a quarter of the way)";
  EXPECT_NEAR(world(2, 3), 1.5, 1e-12) << "z a quarter of the way to 6";
}

}  // namespace
}  // namespace rigel::io

namespace rigel::io {
namespace {

// The depth check both JSON readers run before parsing (json_depth.h).
TEST(JsonDepth, finds_the_bracket_that_passes_the_limit_skipping_strings) {
  EXPECT_EQ(json_too_deep("[[[]]]", 3), std::string_view::npos);
  EXPECT_EQ(json_too_deep("[[[]]]", 2), 2u);
  EXPECT_EQ(json_too_deep(R"({"a": [1, {"b": []}]})", 4), std::string_view::npos);
  EXPECT_EQ(json_too_deep(R"({"a": [1, {"b": []}]})", 3), 16u);
  EXPECT_EQ(json_too_deep(R"({"a": [1, {"b": []}]})", 2), 10u);
  // Brackets in strings, and escaped quotes, do not count.
  EXPECT_EQ(json_too_deep(R"(["[[[[", "\"[[[", []])", 2), std::string_view::npos);
  EXPECT_EQ(json_too_deep(R"(["\\", [[]]])", 2), 8u);
  // Closing brackets never go below zero; unbalanced text is fine.
  EXPECT_EQ(json_too_deep("]]][[", 1), 4u);
  EXPECT_EQ(json_too_deep(std::string(100000, '['), 256), 256u);
  EXPECT_EQ(json_too_deep("", 0), std::string_view::npos);
}

}  // namespace
}  // namespace rigel::io
