#include "rigel/graph/graph.h"

#include <gtest/gtest.h>

#include <set>
#include <string>
#include <vector>

#include "graph_test_util.h"

namespace rigel::graph {
namespace {

using testing::computes;
using testing::eval_double;
using testing::make;
using testing::plug;
using testing::test_registry;

bool mentions(const Status& s, const std::string& text) { return s.message().find(text) != std::string::npos; }

// ---- nodes, names and uuids --------------------------------------------------

TEST(Graph, create_node__unknown_type_is_refused) {
  Graph graph(test_registry());
  Result<NodeId> id = graph.create_node("noSuchType", "x");
  ASSERT_FALSE(id.is_ok()) << "an unregistered type cannot be instantiated";
  EXPECT_EQ(id.status().code(), ErrorCode::kNotFound) << id.status().message();
  EXPECT_EQ(graph.node_count(), 0u) << "nothing was created";
  EXPECT_FALSE(graph.can_undo()) << "a refused create records no undo step";
}

TEST(Graph, create_node__defaults_and_empty_name) {
  Graph graph(test_registry());
  NodeId id = make(graph, "gather", "");
  const Node* n = graph.node(id);
  ASSERT_NE(n, nullptr) << "the new node is reachable by its id";
  EXPECT_EQ(n->name(), "gather") << "an empty name becomes the type name";
  EXPECT_EQ(&n->type(), test_registry()->find("gather")) << "the node points at its registered type";
  EXPECT_EQ(std::get<double>(n->value(testing::gather_attr::kScale)), 1.0) << "inputs start at their declared defaults";
  EXPECT_TRUE(n->is_dirty(testing::gather_attr::kTotal)) << "outputs start dirty: nothing has been computed";
  EXPECT_FALSE(n->is_dirty(testing::gather_attr::kValues)) << "inputs start clean";
  EXPECT_EQ(graph.find("gather"), id) << "found by name";
  EXPECT_EQ(graph.find(n->uuid()), id) << "found by uuid";
}

TEST(Graph, uuid__unique_and_stable) {
  Graph graph(test_registry());
  std::set<Uuid> seen;
  std::vector<NodeId> ids;
  for (int i = 0; i < 200; ++i) {
    ids.push_back(make(graph, "add", "n"));
    EXPECT_TRUE(seen.insert(graph.node(ids.back())->uuid()).second) << "every node gets its own uuid";
  }
  const Uuid u = graph.node(ids[5])->uuid();
  EXPECT_FALSE(u.is_nil()) << "a generated uuid is never nil";
  ASSERT_TRUE(graph.rename(ids[5], "renamed").is_ok()) << "rename";
  EXPECT_EQ(graph.node(ids[5])->uuid(), u) << "renaming keeps the uuid";
  ASSERT_TRUE(graph.connect(plug(graph, ids[4], "sum"), plug(graph, ids[5], "a")).is_ok()) << "connect";
  EXPECT_EQ(graph.node(ids[5])->uuid(), u) << "connecting keeps the uuid";

  ASSERT_TRUE(graph.delete_node(ids[5]).is_ok()) << "delete";
  EXPECT_FALSE(graph.find(u).is_valid()) << "a deleted node is not found by uuid";
  ASSERT_TRUE(graph.undo()) << "undo the delete";
  NodeId back = graph.find(u);
  ASSERT_TRUE(back.is_valid()) << "undoing a delete restores the node under the same uuid";
  EXPECT_EQ(graph.node(ids[5]), nullptr) << "the handle from before the delete stays stale: handles are not stable, uuids are";
  EXPECT_EQ(graph.node(back)->name(), "renamed") << "and its name";
  EXPECT_EQ(graph.node(back)->order(), graph.node(ids[4])->order() + 1) << "and its place in creation order";
  EXPECT_TRUE(graph.source(plug(graph, back, "a")).has_value()) << "and its connections";
}

TEST(Graph, create_node__explicit_uuid_is_kept_and_a_duplicate_refused) {
  Graph graph(test_registry());
  const Uuid u = *Uuid::parse("11111111-2222-4333-8444-555555555555");
  Result<NodeId> a = graph.create_node("add", "a", u);
  ASSERT_TRUE(a.is_ok()) << a.status().message();
  EXPECT_EQ(graph.node(*a)->uuid(), u) << "a given uuid is used as is (files keep their uuids)";
  Result<NodeId> b = graph.create_node("add", "b", u);
  ASSERT_FALSE(b.is_ok()) << "two nodes cannot share a uuid";
  EXPECT_EQ(b.status().code(), ErrorCode::kAlreadyExists) << b.status().message();
  EXPECT_FALSE(graph.find("b").is_valid()) << "the refused node was not created";
}

TEST(Graph, create_node__taken_names_get_maya_style_suffixes) {
  Graph graph(test_registry());
  EXPECT_EQ(graph.node(make(graph, "add", "arm"))->name(), "arm") << "a free name is used as is";
  EXPECT_EQ(graph.node(make(graph, "add", "arm"))->name(), "arm1") << "a taken name gets 1 appended";
  EXPECT_EQ(graph.node(make(graph, "add", "arm"))->name(), "arm2") << "the next free number is used";
  EXPECT_EQ(graph.node(make(graph, "add", "leg7"))->name(), "leg7") << "a free numbered name is used as is";
  EXPECT_EQ(graph.node(make(graph, "add", "leg7"))->name(), "leg8") << "a trailing number is bumped";
  make(graph, "add", "leg9");
  EXPECT_EQ(graph.node(make(graph, "add", "leg7"))->name(), "leg10") << "taken numbers are skipped";
  EXPECT_EQ(graph.node(make(graph, "add", ""))->name(), "add") << "empty name: the type name";
  EXPECT_EQ(graph.node(make(graph, "add", ""))->name(), "add1") << "which also gets a suffix";
  EXPECT_EQ(graph.node_count(), 9u) << "nine nodes, all distinct";
}

TEST(Graph, is_valid_name__refuses_whitespace_brackets_and_controls) {
  for (const char* good : {"a", "arm_L", "robot:arm", "a.b", "x-1", "9", "caf\xc3\xa9"})
    EXPECT_TRUE(Graph::is_valid_name(good)) << "'" << good << "' is a valid node name";
  for (const char* bad : {"", " ", "a b", "a\tb", "a\nb", "a[0]", "]", "a\x7f", "\x01"})
    EXPECT_FALSE(Graph::is_valid_name(bad)) << "'" << bad << "' is not a valid node name";
  EXPECT_FALSE(Graph::is_valid_name(std::string(2000, 'a'))) << "absurdly long names are refused";
}

TEST(Graph, create_node__invalid_name_is_refused) {
  Graph graph(test_registry());
  for (const char* bad : {"a b", "x[1]", "tab\t"}) {
    Result<NodeId> id = graph.create_node("add", bad);
    ASSERT_FALSE(id.is_ok()) << "'" << bad << "' is not a valid name";
    EXPECT_EQ(id.status().code(), ErrorCode::kInvalidArgument) << id.status().message();
  }
  EXPECT_EQ(graph.node_count(), 0u) << "no node was created";
}

TEST(Graph, rename__taken_or_invalid_name_is_refused) {
  Graph graph(test_registry());
  NodeId a = make(graph, "add", "a");
  NodeId b = make(graph, "add", "b");
  const std::size_t steps = graph.undo_count();
  Status taken = graph.rename(b, "a");
  EXPECT_EQ(taken.code(), ErrorCode::kAlreadyExists) << "renaming to another node's name is refused: " << taken.message();
  EXPECT_TRUE(mentions(taken, "'a'")) << "the message names the taken name: " << taken.message();
  for (const char* bad : {"", "with space", "a[2]"}) {
    Status s = graph.rename(b, bad);
    EXPECT_EQ(s.code(), ErrorCode::kInvalidArgument) << "'" << bad << "' is refused: " << s.message();
  }
  EXPECT_EQ(graph.node(b)->name(), "b") << "a refused rename leaves the name";
  EXPECT_EQ(graph.find("a"), a) << "and the other node keeps its name";
  EXPECT_EQ(graph.undo_count(), steps) << "refused renames record nothing";
  EXPECT_TRUE(graph.rename(b, "b").is_ok()) << "renaming to its own name is a no-op, not an error";
  EXPECT_EQ(graph.undo_count(), steps) << "a no-op rename records nothing";

  EXPECT_TRUE(graph.rename(b, "c").is_ok()) << "a free name is accepted";
  EXPECT_FALSE(graph.find("b").is_valid()) << "the old name is released";
  EXPECT_EQ(graph.find("c"), b) << "the new name finds the node";
  EXPECT_TRUE(graph.node(make(graph, "add", "b")) != nullptr) << "the released name can be used again";
  NodeId stale = make(graph, "add", "gone");
  ASSERT_TRUE(graph.delete_node(stale).is_ok()) << "delete";
  EXPECT_EQ(graph.rename(stale, "zzz").code(), ErrorCode::kNotFound) << "renaming a deleted node is refused";
}

TEST(Graph, rename__keeps_every_connection_and_evaluation_flows) {
  Graph graph(test_registry());
  NodeId up = make(graph, "add", "up");
  NodeId mid = make(graph, "add", "mid");
  NodeId down1 = make(graph, "add", "down1");
  NodeId down2 = make(graph, "gather", "down2");
  ASSERT_TRUE(graph.connect(plug(graph, up, "sum"), plug(graph, mid, "a")).is_ok()) << "connect";
  ASSERT_TRUE(graph.connect(plug(graph, mid, "sum"), plug(graph, down1, "b")).is_ok()) << "connect";
  ASSERT_TRUE(graph.connect(plug(graph, mid, "sum"), plug(graph, down2, "values", 2)).is_ok()) << "connect";
  ASSERT_TRUE(graph.set_value(plug(graph, up, "a"), 1.0).is_ok()) << "set";
  EXPECT_EQ(eval_double(graph, down1, "sum"), 1.0) << "before the rename, 1 flows through";
  const std::vector<Connection> before = graph.connections();

  ASSERT_TRUE(graph.rename(mid, "middle").is_ok()) << "rename the node in the middle";
  const std::vector<Connection> after = graph.connections();
  ASSERT_EQ(after.size(), before.size()) << "a rename breaks no connection";
  for (std::size_t i = 0; i < after.size(); ++i) {
    EXPECT_EQ(after[i].src, before[i].src) << "connection " << i << " keeps its source";
    EXPECT_EQ(after[i].dst, before[i].dst) << "connection " << i << " keeps its destination";
  }
  EXPECT_EQ(graph.plug_name(*graph.source(plug(graph, down1, "b"))), "middle.sum") << "plug names use the new name";
  Result<Plug> by_path = graph.plug_find("middle.sum");
  ASSERT_TRUE(by_path.is_ok()) << "the new name resolves in plug paths";
  EXPECT_EQ(by_path->node, mid) << "to the same node";
  EXPECT_FALSE(graph.plug_find("mid.sum").is_ok()) << "the old name no longer resolves";

  ASSERT_TRUE(graph.set_value(plug(graph, up, "a"), 5.0).is_ok()) << "set upstream after the rename";
  EXPECT_EQ(eval_double(graph, down1, "sum"), 5.0) << "evaluation still flows through the renamed node";
  EXPECT_EQ(eval_double(graph, down2, "total"), 5.0) << "also into an array element";
  ASSERT_TRUE(graph.set_value(plug(graph, mid, "b"), 2.0).is_ok()) << "set on the renamed node itself";
  EXPECT_EQ(eval_double(graph, down1, "sum"), 7.0) << "its own inputs still propagate";
}

TEST(Graph, nodes__creation_order_survives_deletes) {
  Graph graph(test_registry());
  NodeId a = make(graph, "add", "a");
  NodeId b = make(graph, "add", "b");
  NodeId c = make(graph, "add", "c");
  ASSERT_TRUE(graph.delete_node(b).is_ok()) << "delete b";
  NodeId d = make(graph, "add", "d");
  EXPECT_EQ(graph.nodes(), (std::vector<NodeId>{a, c, d})) << "creation order, even when d reuses b's slot";
  EXPECT_EQ(graph.node(b), nullptr) << "b's handle is stale";
  EXPECT_NE(b, d) << "a reused slot gets a new generation: the stale handle never aliases the new node";
  EXPECT_EQ(graph.delete_node(b).code(), ErrorCode::kNotFound) << "deleting twice is refused";
}

// ---- plugs -------------------------------------------------------------------

TEST(Graph, plug_find__parses_paths) {
  Graph graph(test_registry());
  NodeId g = make(graph, "gather", "rig.arm:g");
  Result<Plug> whole = graph.plug_find("rig.arm:g.values");
  ASSERT_TRUE(whole.is_ok()) << "node names may contain dots: " << whole.status().message();
  EXPECT_EQ(whole->node, g) << "the last dot separates the attribute";
  EXPECT_EQ(whole->element, -1) << "no [index]: the whole attribute";
  Result<Plug> element = graph.plug_find("rig.arm:g.values[12]");
  ASSERT_TRUE(element.is_ok()) << element.status().message();
  EXPECT_EQ(element->element, 12) << "[12] is element 12";
  EXPECT_EQ(graph.plug_name(*element), "rig.arm:g.values[12]") << "plug_name writes what plug_find reads";

  for (const char* bad : {"rig", ".values", "rig.arm:g.", "rig.arm:g.values[", "rig.arm:g.values[]",
                          "rig.arm:g.values[-1]", "rig.arm:g.values[1x]", "rig.arm:g.values]"}) {
    EXPECT_FALSE(graph.plug_find(bad).is_ok()) << "'" << bad << "' is malformed";
  }
  EXPECT_EQ(graph.plug_find("nobody.values").status().code(), ErrorCode::kNotFound) << "unknown node";
  EXPECT_EQ(graph.plug_find("rig.arm:g.nothing").status().code(), ErrorCode::kNotFound) << "unknown attribute";
  EXPECT_EQ(graph.plug_find("rig.arm:g.scale[0]").status().code(), ErrorCode::kInvalidArgument)
      << "a scalar takes no [index]";
  EXPECT_EQ(graph.plug_find("rig.arm:g.values[99999999]").status().code(), ErrorCode::kInvalidArgument)
      << "absurd indices are refused rather than allocated";
}

// ---- values ------------------------------------------------------------------

TEST(Graph, set_value__checks_plug_and_type) {
  Graph graph(test_registry());
  NodeId k = make(graph, "kinds", "k");
  NodeId a = make(graph, "add", "a");
  EXPECT_EQ(graph.set_value(plug(graph, a, "sum"), 1.0).code(), ErrorCode::kInvalidArgument) << "outputs are not set";
  EXPECT_EQ(graph.set_value(plug(graph, a, "a"), std::string("x")).code(), ErrorCode::kInvalidArgument)
      << "a string is not a double";
  EXPECT_TRUE(graph.set_value(plug(graph, a, "a"), std::int64_t{3}).is_ok()) << "an int is accepted for a double";
  EXPECT_TRUE(std::holds_alternative<double>(graph.node(a)->value(testing::add_attr::kA)))
      << "and stored as a double";
  EXPECT_TRUE(graph.set_value(plug(graph, k, "inEnum"), std::int64_t{2}).is_ok()) << "an enum accepts its index";
  EXPECT_EQ(graph.set_value(plug(graph, k, "inEnum"), std::int64_t{3}).code(), ErrorCode::kInvalidArgument)
      << "an enum index out of range is refused";
  EXPECT_EQ(graph.set_value(plug(graph, k, "inEnum"), std::int64_t{-1}).code(), ErrorCode::kInvalidArgument)
      << "a negative enum index is refused";
  EXPECT_EQ(graph.set_value(plug(graph, k, "inEnumArr"), std::vector<std::int64_t>{0, 5}).code(),
            ErrorCode::kInvalidArgument)
      << "an enum array with an index out of range is refused";
  EXPECT_EQ(graph.set_value(plug(graph, k, "inEnumArr", 1), std::int64_t{4}).code(), ErrorCode::kInvalidArgument)
      << "an enum element out of range is refused";
  EXPECT_EQ(graph.set_value(Plug{k, testing::add_attr::kA, 0}, 1.0).code(), ErrorCode::kInvalidArgument)
      << "an element of a scalar is refused";
  EXPECT_EQ(graph.set_value(Plug{k, 999, -1}, 1.0).code(), ErrorCode::kNotFound) << "no such attribute";
  EXPECT_EQ(graph.set_value(plug(graph, k, "inDoubleArr"), 1.0).code(), ErrorCode::kInvalidArgument)
      << "a scalar is not an array";
  EXPECT_EQ(graph.set_value(Plug{k, graph.node(k)->type().attr_find("inDoubleArr"), 1 << 24}, 1.0).code(),
            ErrorCode::kInvalidArgument)
      << "huge element indices are refused";
}

TEST(Graph, set_value__array_elements_grow_the_array) {
  Graph graph(test_registry());
  NodeId g = make(graph, "gather", "g");
  ASSERT_TRUE(graph.set_value(plug(graph, g, "values", 2), 4.0).is_ok()) << "set element 2 of an empty array";
  EXPECT_TRUE(values_identical(graph.node(g)->value(testing::gather_attr::kValues), std::vector<double>{0, 0, 4}))
      << "the array grew to three with zeros";
  EXPECT_EQ(eval_double(graph, g, "total"), 4.0) << "the compute sees the grown array";
  Result<Value> e = graph.evaluate(plug(graph, g, "values", 2));
  ASSERT_TRUE(e.is_ok()) << e.status().message();
  EXPECT_EQ(std::get<double>(*e), 4.0) << "an element plug evaluates to the element";
  Result<Value> missing = graph.evaluate(plug(graph, g, "values", 10));
  ASSERT_TRUE(missing.is_ok()) << "an element past the end evaluates";
  EXPECT_EQ(std::get<double>(*missing), 0.0) << "to the element zero";
}

// ---- connections ---------------------------------------------------------------

TEST(Graph, connect__type_checks) {
  Graph graph(test_registry());
  NodeId s = make(graph, "kinds", "s");
  NodeId d = make(graph, "kinds", "d");
  auto connect = [&](const char* src, std::int32_t se, const char* dst, std::int32_t de) {
    Status st = graph.connect(plug(graph, s, src, se), plug(graph, d, dst, de));
    if (st.is_ok()) {
      EXPECT_TRUE(graph.disconnect(plug(graph, s, src, se), plug(graph, d, dst, de)).is_ok()) << "undo the probe";
    }
    return st;
  };
  // Every type connects to itself, scalar to scalar and array to array.
  for (const testing::Kind& k : testing::kinds()) {
    const std::string out = std::string("out") + k.suffix, in = std::string("in") + k.suffix;
    EXPECT_TRUE(connect(out.c_str(), -1, in.c_str(), -1).is_ok()) << type_name(k.type) << " connects to itself";
  }
  EXPECT_TRUE(connect("outDoubleArr", 3, "inDouble", -1).is_ok()) << "an element of a double[] feeds a double";
  EXPECT_TRUE(connect("outMatrixArr", 0, "inMatrix", -1).is_ok()) << "an element of a matrix[] feeds a matrix";
  EXPECT_TRUE(connect("outDouble", -1, "inDoubleArr", 4).is_ok()) << "a double feeds an element of a double[]";
  EXPECT_TRUE(connect("outDouble3Arr", 1, "inDouble3Arr", 2).is_ok()) << "element to element";
  EXPECT_TRUE(connect("outInt", -1, "inEnum", -1).is_ok()) << "int feeds enum";
  EXPECT_TRUE(connect("outEnum", -1, "inInt", -1).is_ok()) << "enum feeds int";
  EXPECT_TRUE(connect("outIntArr", 0, "inEnum", -1).is_ok()) << "an int element feeds an enum";
  EXPECT_TRUE(connect("inDouble", -1, "inDoubleArr", 0).is_ok()) << "an input may be a source";

  struct Bad {
    const char* src;
    std::int32_t se;
    const char* dst;
    std::int32_t de;
    const char* why;
  };
  for (const Bad& b : std::vector<Bad>{
           {"outDouble3", -1, "inMatrix", -1, "double3 does not feed a matrix"},
           {"outDouble", -1, "inInt", -1, "double does not feed int"},
           {"outInt", -1, "inDouble", -1, "int does not feed double (no implicit conversion in connections)"},
           {"outBool", -1, "inInt", -1, "bool does not feed int"},
           {"outQuat", -1, "inDouble3", -1, "quaternion does not feed double3"},
           {"outDoubleArr", -1, "inDouble", -1, "a whole array does not feed a scalar"},
           {"outDouble", -1, "inDoubleArr", -1, "a scalar does not feed a whole array"},
           {"outDoubleArr", -1, "inDoubleArr", 0, "a whole array does not feed an element"},
           {"outMatrixArr", 0, "inDouble", -1, "a matrix element does not feed a double"},
           {"outMessage", -1, "inString", -1, "message does not feed string"},
       }) {
    Status st = connect(b.src, b.se, b.dst, b.de);
    EXPECT_EQ(st.code(), ErrorCode::kInvalidArgument) << b.why << ": " << st.message();
    EXPECT_TRUE(mentions(st, "types differ")) << b.why << ": the message says why: " << st.message();
  }
  EXPECT_TRUE(graph.connections().empty()) << "refused connections leave nothing behind";
  EXPECT_FALSE(graph.source(plug(graph, d, "inMatrix")).has_value()) << "no source for a refused destination";
}

TEST(Graph, connect__output_as_destination_is_refused) {
  Graph graph(test_registry());
  NodeId a = make(graph, "add", "a");
  NodeId b = make(graph, "add", "b");
  Status s = graph.connect(plug(graph, a, "sum"), plug(graph, b, "sum"));
  EXPECT_EQ(s.code(), ErrorCode::kInvalidArgument) << "an output is written by compute, never by a connection";
  EXPECT_TRUE(mentions(s, "b.sum")) << "the message names the destination: " << s.message();
  EXPECT_TRUE(mentions(s, "output")) << "and says it is an output: " << s.message();
}

TEST(Graph, connect__one_source_per_destination) {
  Graph graph(test_registry());
  NodeId s1 = make(graph, "gather", "s1");
  NodeId s2 = make(graph, "add", "s2");
  NodeId d = make(graph, "gather", "d");
  ASSERT_TRUE(graph.connect(plug(graph, s2, "sum"), plug(graph, d, "values", 1)).is_ok()) << "element 1";
  EXPECT_EQ(graph.connect(plug(graph, s2, "sum"), plug(graph, d, "values", 1)).code(), ErrorCode::kAlreadyExists)
      << "the same connection twice is refused";
  EXPECT_EQ(graph.connect(plug(graph, s1, "total"), plug(graph, d, "values", 1)).code(), ErrorCode::kAlreadyExists)
      << "a second source for element 1 is refused";
  Status whole = graph.connect(plug(graph, s1, "echo"), plug(graph, d, "values"));
  EXPECT_EQ(whole.code(), ErrorCode::kAlreadyExists) << "the whole array cannot be fed while an element is";
  EXPECT_TRUE(mentions(whole, "d.values[1]") && mentions(whole, "s2.sum"))
      << "the message names the existing connection: " << whole.message();
  EXPECT_TRUE(graph.connect(plug(graph, s1, "total"), plug(graph, d, "values", 0)).is_ok())
      << "another element is a different destination";

  NodeId d2 = make(graph, "gather", "d2");
  ASSERT_TRUE(graph.connect(plug(graph, s1, "echo"), plug(graph, d2, "values")).is_ok()) << "whole array";
  EXPECT_EQ(graph.connect(plug(graph, s2, "sum"), plug(graph, d2, "values", 3)).code(), ErrorCode::kAlreadyExists)
      << "no element can be fed while the whole array is";
  EXPECT_EQ(graph.set_value(plug(graph, d2, "values", 3), 1.0).code(), ErrorCode::kInvalidArgument)
      << "nor set";
  EXPECT_EQ(graph.set_value(plug(graph, d, "values", 1), 1.0).code(), ErrorCode::kInvalidArgument)
      << "a connected element cannot be set";
  EXPECT_TRUE(graph.set_value(plug(graph, d, "values", 2), 1.0).is_ok()) << "an unconnected element can";
  EXPECT_EQ(graph.set_value(plug(graph, d, "values"), std::vector<double>{1}).code(), ErrorCode::kInvalidArgument)
      << "the whole array cannot be set while elements are connected";
  EXPECT_EQ(graph.connections().size(), 3u) << "three connections stand";
}

TEST(Graph, connect__cycle_is_refused_and_names_the_nodes) {
  Graph graph(test_registry());
  NodeId a = make(graph, "add", "alpha");
  NodeId b = make(graph, "add", "beta");
  NodeId c = make(graph, "add", "gamma");
  NodeId other = make(graph, "add", "bystander");
  ASSERT_TRUE(graph.connect(plug(graph, a, "sum"), plug(graph, b, "a")).is_ok()) << "alpha -> beta";
  ASSERT_TRUE(graph.connect(plug(graph, b, "sum"), plug(graph, c, "a")).is_ok()) << "beta -> gamma";
  ASSERT_TRUE(graph.connect(plug(graph, other, "sum"), plug(graph, a, "b")).is_ok()) << "bystander -> alpha";
  const std::uint64_t generation = graph.topology_generation();

  Status three = graph.connect(plug(graph, c, "sum"), plug(graph, a, "a"));
  EXPECT_EQ(three.code(), ErrorCode::kCycle) << "gamma -> alpha closes alpha -> beta -> gamma: " << three.message();
  for (const char* name : {"alpha", "beta", "gamma"})
    EXPECT_TRUE(mentions(three, name)) << "the message names " << name << " on the cycle: " << three.message();
  EXPECT_TRUE(mentions(three, "alpha -> beta -> gamma -> alpha"))
      << "the message lists the cycle in order: " << three.message();
  EXPECT_FALSE(mentions(three, "bystander")) << "nodes off the cycle are not named: " << three.message();

  Status two = graph.connect(plug(graph, b, "sum"), plug(graph, a, "a"));
  EXPECT_EQ(two.code(), ErrorCode::kCycle) << "a two-node cycle: " << two.message();
  EXPECT_TRUE(mentions(two, "alpha") && mentions(two, "beta")) << "names both: " << two.message();

  Status self = graph.connect(plug(graph, a, "sum"), plug(graph, a, "a"));
  EXPECT_EQ(self.code(), ErrorCode::kCycle) << "a node cannot feed itself: " << self.message();
  EXPECT_TRUE(mentions(self, "alpha -> alpha")) << "the self-cycle is named: " << self.message();

  NodeId g = make(graph, "gather", "g");
  Status own_array = graph.connect(plug(graph, g, "total"), plug(graph, g, "values", 0));
  EXPECT_EQ(own_array.code(), ErrorCode::kCycle) << "an output into an element of the same node is a cycle";
  EXPECT_TRUE(mentions(own_array, "g -> g")) << own_array.message();

  EXPECT_EQ(graph.connections().size(), 3u) << "no refused connection was made";
  EXPECT_EQ(graph.topology_generation(), generation + 1) << "only the create of g changed the topology";
  EXPECT_EQ(eval_double(graph, c, "sum"), 0.0) << "the graph still evaluates";
}

TEST(Graph, connect__cycle_through_a_long_path_names_every_node) {
  Graph graph(test_registry());
  std::vector<NodeId> ids;
  for (int i = 0; i < 6; ++i) ids.push_back(make(graph, "add", testing::numbered("n", i)));
  for (int i = 0; i + 1 < 6; ++i)
    ASSERT_TRUE(graph.connect(plug(graph, ids[i], "sum"), plug(graph, ids[i + 1], "a")).is_ok()) << i;
  Status s = graph.connect(plug(graph, ids[5], "sum"), plug(graph, ids[0], "b"));
  EXPECT_EQ(s.code(), ErrorCode::kCycle) << s.message();
  EXPECT_TRUE(mentions(s, "n0 -> n1 -> n2 -> n3 -> n4 -> n5 -> n0")) << "every node on the cycle: " << s.message();
}

TEST(Graph, connect__stale_handles_are_refused) {
  Graph graph(test_registry());
  NodeId a = make(graph, "add", "a");
  NodeId b = make(graph, "add", "b");
  const Plug a_sum = plug(graph, a, "sum");
  const Plug b_in = plug(graph, b, "a");
  ASSERT_TRUE(graph.delete_node(b).is_ok()) << "delete b";
  NodeId reuse = make(graph, "add", "reuse");
  EXPECT_EQ(reuse.index, b.index) << "the freed slot is reused (what makes stale handles dangerous)";
  EXPECT_EQ(graph.connect(a_sum, b_in).code(), ErrorCode::kNotFound) << "a stale destination is refused";
  EXPECT_EQ(graph.connect(Plug{b, testing::add_attr::kSum, -1}, plug(graph, a, "a")).code(), ErrorCode::kNotFound)
      << "a stale source is refused";
  EXPECT_FALSE(graph.source(plug(graph, reuse, "a")).has_value()) << "the new node in the slot was not touched";
  EXPECT_EQ(graph.connect(Plug{NodeId{}, 0, -1}, b_in).code(), ErrorCode::kNotFound) << "an invalid id is refused";
  EXPECT_EQ(graph.connect(Plug{a, 77, -1}, plug(graph, reuse, "a")).code(), ErrorCode::kNotFound)
      << "an attribute index out of range is refused";
  EXPECT_EQ(graph.set_value(b_in, 1.0).code(), ErrorCode::kNotFound) << "set through a stale handle is refused";
  EXPECT_FALSE(graph.evaluate(b_in).is_ok()) << "evaluate through a stale handle is refused";
  EXPECT_EQ(graph.set_tag(b, "k", "v").code(), ErrorCode::kNotFound) << "tag through a stale handle is refused";
  EXPECT_EQ(graph.set_parent(b, NodeId{}).code(), ErrorCode::kNotFound) << "parent through a stale handle";
}

TEST(Graph, disconnect__checks_the_connection_exists) {
  Graph graph(test_registry());
  NodeId a = make(graph, "add", "a");
  NodeId b = make(graph, "add", "b");
  EXPECT_EQ(graph.disconnect(plug(graph, a, "sum"), plug(graph, b, "a")).code(), ErrorCode::kNotFound)
      << "disconnecting what is not connected is refused";
  EXPECT_TRUE(graph.disconnect_input(plug(graph, b, "a")).is_ok()) << "disconnect_input with no source is fine";
  ASSERT_TRUE(graph.connect(plug(graph, a, "sum"), plug(graph, b, "a")).is_ok()) << "connect";
  EXPECT_EQ(graph.disconnect(plug(graph, a, "sum"), plug(graph, b, "b")).code(), ErrorCode::kNotFound)
      << "the wrong destination is refused";
  EXPECT_TRUE(graph.disconnect_input(plug(graph, b, "a")).is_ok()) << "disconnect_input breaks the connection";
  EXPECT_TRUE(graph.connections().empty()) << "nothing left";
}

TEST(Graph, delete_node__breaks_connections_and_orphans_children) {
  Graph graph(test_registry());
  NodeId root = make(graph, "xf", "root");
  NodeId mid = make(graph, "xf", "mid");
  NodeId leaf1 = make(graph, "xf", "leaf1");
  NodeId leaf2 = make(graph, "xf", "leaf2");
  NodeId feed = make(graph, "kinds", "feed");
  ASSERT_TRUE(graph.set_parent(mid, root).is_ok()) << "parent";
  ASSERT_TRUE(graph.set_parent(leaf1, mid).is_ok()) << "parent";
  ASSERT_TRUE(graph.set_parent(leaf2, mid).is_ok()) << "parent";
  ASSERT_TRUE(graph.connect(plug(graph, feed, "outMatrix"), plug(graph, mid, "local")).is_ok()) << "connect";
  Mat4 t = Mat4::Identity();
  t(0, 3) = 2.0;
  ASSERT_TRUE(graph.set_value(plug(graph, root, "local"), t).is_ok()) << "move the root";
  EXPECT_EQ(std::get<Mat4>(*graph.evaluate(plug(graph, leaf1, "world")))(0, 3), 2.0) << "leaf inherits root";

  ASSERT_TRUE(graph.delete_node(mid).is_ok()) << "delete the middle";
  EXPECT_EQ(graph.connections().size(), 0u) << "every connection of the deleted node is gone";
  EXPECT_EQ(graph.children(root).size(), 0u) << "the root lost its child";
  EXPECT_FALSE(graph.parent(leaf1).is_valid()) << "children become roots";
  EXPECT_EQ(std::get<Mat4>(graph.node(leaf1)->value(testing::xf_attr::kParentMatrix)), Mat4::Identity())
      << "an orphan's parent matrix is reset to identity";
  EXPECT_EQ(std::get<Mat4>(*graph.evaluate(plug(graph, leaf1, "world")))(0, 3), 0.0) << "and it is back at the origin";
  EXPECT_EQ(graph.undo_label(), "delete mid") << "a delete is one undo step";
  ASSERT_TRUE(graph.undo()) << "undo the delete";
  NodeId mid2 = graph.find("mid");
  EXPECT_EQ(graph.parent(leaf1), mid2) << "undo restores the children";
  EXPECT_EQ(graph.parent(mid2), root) << "and the parent";
  EXPECT_EQ(graph.connections().size(), 4u) << "and every connection";
  EXPECT_EQ(std::get<Mat4>(*graph.evaluate(plug(graph, leaf2, "world")))(0, 3), 2.0) << "evaluation flows again";
}

// ---- hierarchy -----------------------------------------------------------------

TEST(Graph, set_parent__connects_world_to_parent_matrix) {
  Graph graph(test_registry());
  NodeId p = make(graph, "xf", "p");
  NodeId c1 = make(graph, "xf", "c1");
  NodeId c0 = make(graph, "xf", "c0");
  NodeId k = make(graph, "kinds", "k");
  ASSERT_TRUE(graph.set_parent(c0, p).is_ok()) << "parent c0";
  ASSERT_TRUE(graph.set_parent(c1, p).is_ok()) << "parent c1";
  EXPECT_EQ(graph.parent(c0), p) << "parent() reads the connection";
  EXPECT_EQ(graph.children(p), (std::vector<NodeId>{c1, c0})) << "children in creation order, not parenting order";
  EXPECT_EQ(*graph.source(plug(graph, c0, "parentMatrix")), plug(graph, p, "world")) << "world -> parentMatrix";
  const std::size_t steps = graph.undo_count();
  EXPECT_TRUE(graph.set_parent(c0, p).is_ok()) << "parenting under the same parent is a no-op";
  EXPECT_EQ(graph.undo_count(), steps) << "and records nothing";
  Status cycle = graph.set_parent(p, c0);
  EXPECT_EQ(cycle.code(), ErrorCode::kCycle) << "a node cannot go under its own child: " << cycle.message();
  EXPECT_FALSE(graph.parent(p).is_valid()) << "a refused parenting leaves the node where it was";
  EXPECT_EQ(graph.undo_count(), steps) << "and records nothing";
  EXPECT_EQ(graph.set_parent(k, p).code(), ErrorCode::kInvalidArgument) << "a type without parent input";
  EXPECT_EQ(graph.set_parent(c0, k).code(), ErrorCode::kInvalidArgument) << "a type without world output";
  ASSERT_TRUE(graph.set_parent(c0, c1).is_ok()) << "reparent c0 under its sibling";
  EXPECT_EQ(graph.parent(c0), c1) << "moved";
  EXPECT_EQ(graph.children(p), (std::vector<NodeId>{c1})) << "no longer a child of p";
  ASSERT_TRUE(graph.set_parent(c0, NodeId{}).is_ok()) << "unparent";
  EXPECT_FALSE(graph.parent(c0).is_valid()) << "a root";
  EXPECT_TRUE(graph.set_parent(c0, NodeId{}).is_ok()) << "unparenting a root is a no-op";
}

// ---- tags ----------------------------------------------------------------------

TEST(Graph, tags__set_find_remove) {
  Graph graph(test_registry());
  NodeId a = make(graph, "add", "a");
  EXPECT_EQ(graph.node(a)->tag_find("side"), nullptr) << "no tag yet";
  ASSERT_TRUE(graph.set_tag(a, "side", "L").is_ok()) << "set";
  ASSERT_NE(graph.node(a)->tag_find("side"), nullptr) << "the tag is found";
  EXPECT_EQ(*graph.node(a)->tag_find("side"), "L") << "with its value";
  EXPECT_EQ(graph.set_tag(a, "", "x").code(), ErrorCode::kInvalidArgument) << "an empty key is refused";
  EXPECT_EQ(graph.remove_tag(a, "nope").code(), ErrorCode::kNotFound) << "removing an absent tag is refused";
  ASSERT_TRUE(graph.remove_tag(a, "side").is_ok()) << "remove";
  EXPECT_TRUE(graph.node(a)->tags().empty()) << "gone";
}

// ---- observers -----------------------------------------------------------------

// Records every callback as text, with the arguments it was given.
class Recorder : public Observer {
 public:
  std::vector<std::string> events;
  void node_added(const Graph& g, NodeId id) override { events.push_back("added " + g.node(id)->name()); }
  void node_removed(const Graph& g, NodeId id) override {
    const Node* n = g.node(id);
    events.push_back("removed " + (n ? n->name() : std::string("<unreadable>")));
  }
  void node_renamed(const Graph& g, NodeId id, const std::string& old_name) override {
    events.push_back("renamed " + old_name + " " + g.node(id)->name());
  }
  void attribute_changed(const Graph& g, const Plug& p) override { events.push_back("changed " + g.plug_name(p)); }
  void connection_made(const Graph& g, const Connection& c) override {
    events.push_back("connected " + g.plug_name(c.src) + " " + g.plug_name(c.dst));
  }
  void connection_broken(const Graph& g, const Connection& c) override {
    events.push_back("disconnected " + g.plug_name(c.src) + " " + g.plug_name(c.dst));
  }
  void tag_changed(const Graph& g, NodeId id, const std::string& key) override {
    const std::string* v = g.node(id)->tag_find(key);
    events.push_back("tag " + g.node(id)->name() + " " + key + "=" + (v ? *v : std::string("<none>")));
  }
  void selection_changed(const Graph& g) override {
    std::string text = "selection";
    for (NodeId id : g.selection()) text += " " + g.node(id)->name();
    events.push_back(text);
  }
  void time_changed(const Graph& g) override { events.push_back("time " + std::to_string(g.time())); }
  std::vector<std::string> take() { return std::exchange(events, {}); }
};

using Events = std::vector<std::string>;

TEST(Graph, observers__each_callback_fires_with_its_arguments) {
  Graph graph(test_registry());
  Recorder rec;
  graph.add_observer(&rec);
  graph.add_observer(&rec);  // added twice, notified once

  NodeId a = make(graph, "add", "a");
  NodeId b = make(graph, "gather", "b");
  EXPECT_EQ(rec.take(), (Events{"added a", "added b"})) << "create fires node_added after the node exists";

  ASSERT_TRUE(graph.set_value(plug(graph, a, "a"), 2.0).is_ok()) << "set";
  EXPECT_EQ(rec.take(), (Events{"changed a.a"})) << "set fires attribute_changed with the plug";
  ASSERT_TRUE(graph.set_value(plug(graph, b, "values", 3), 1.0).is_ok()) << "set element";
  EXPECT_EQ(rec.take(), (Events{"changed b.values[3]"})) << "an element set names the element";

  ASSERT_TRUE(graph.connect(plug(graph, a, "sum"), plug(graph, b, "values", 1)).is_ok()) << "connect";
  EXPECT_EQ(rec.take(), (Events{"connected a.sum b.values[1]"})) << "connect fires connection_made";
  ASSERT_TRUE(graph.disconnect(plug(graph, a, "sum"), plug(graph, b, "values", 1)).is_ok()) << "disconnect";
  EXPECT_EQ(rec.take(), (Events{"disconnected a.sum b.values[1]"})) << "disconnect fires connection_broken";

  ASSERT_TRUE(graph.rename(a, "first").is_ok()) << "rename";
  EXPECT_EQ(rec.take(), (Events{"renamed a first"})) << "rename gives the old name; the node has the new one";

  ASSERT_TRUE(graph.set_tag(a, "side", "L").is_ok()) << "tag";
  EXPECT_EQ(rec.take(), (Events{"tag first side=L"})) << "set_tag fires tag_changed after the change";
  ASSERT_TRUE(graph.remove_tag(a, "side").is_ok()) << "untag";
  EXPECT_EQ(rec.take(), (Events{"tag first side=<none>"})) << "remove_tag fires tag_changed";

  graph.select({b, a, b});
  EXPECT_EQ(rec.take(), (Events{"selection b first"})) << "select fires once, duplicates dropped, order kept";

  graph.set_time(1.5);
  EXPECT_EQ(rec.take(), (Events{"time 1.500000"})) << "set_time fires time_changed after the change";

  ASSERT_TRUE(graph.delete_node(b).is_ok()) << "delete";
  EXPECT_EQ(rec.take(), (Events{"selection first", "removed b"}))
      << "deleting a selected node updates the selection, then node_removed fires while it is still readable";

  graph.remove_observer(&rec);
  make(graph, "add", "unseen");
  EXPECT_TRUE(rec.events.empty()) << "a removed observer hears nothing";
}

TEST(Graph, observers__delete_reports_broken_connections_first) {
  Graph graph(test_registry());
  NodeId a = make(graph, "add", "a");
  NodeId b = make(graph, "add", "b");
  ASSERT_TRUE(graph.connect(plug(graph, a, "sum"), plug(graph, b, "a")).is_ok()) << "connect";
  Recorder rec;
  graph.add_observer(&rec);
  ASSERT_TRUE(graph.delete_node(a).is_ok()) << "delete";
  EXPECT_EQ(rec.take(), (Events{"disconnected a.sum b.a", "removed a"}))
      << "connections break (and are reported) before the node goes";
  ASSERT_TRUE(graph.undo()) << "undo";
  EXPECT_EQ(rec.take(), (Events{"added a", "connected a.sum b.a"})) << "undo replays in reverse, with callbacks";
  ASSERT_TRUE(graph.redo()) << "redo";
  const Events redone = rec.take();
  ASSERT_FALSE(redone.empty()) << "redo notifies";
  EXPECT_EQ(redone.front(), "disconnected a.sum b.a") << "redo breaks the connection first";
  EXPECT_EQ(redone.back(), "removed a") << "and removes the node last";
}

TEST(Graph, observers__selection_follows_undo_of_a_create) {
  Graph graph(test_registry());
  NodeId a = make(graph, "add", "a");
  NodeId b = make(graph, "add", "b");
  graph.select({a, b});
  Recorder rec;
  graph.add_observer(&rec);
  ASSERT_TRUE(graph.undo()) << "undo the create of b";
  EXPECT_EQ(graph.selection(), (std::vector<NodeId>{a})) << "a node removed by undo leaves the selection";
  EXPECT_EQ(rec.take(), (Events{"selection a", "removed b"}))
      << "and the selection change is reported, before node_removed, as for delete_node";
  graph.remove_observer(&rec);
}

TEST(Graph, select__drops_stale_ids_and_duplicates) {
  Graph graph(test_registry());
  NodeId a = make(graph, "add", "a");
  NodeId gone = make(graph, "add", "gone");
  ASSERT_TRUE(graph.delete_node(gone).is_ok()) << "delete";
  graph.select({gone, a, NodeId{}, a});
  EXPECT_EQ(graph.selection(), (std::vector<NodeId>{a})) << "stale and invalid ids are dropped, duplicates too";
}

TEST(Graph, connections__sorted_by_destination) {
  Graph graph(test_registry());
  NodeId s = make(graph, "add", "s");
  NodeId g1 = make(graph, "gather", "g1");
  NodeId g2 = make(graph, "gather", "g2");
  ASSERT_TRUE(testing::succeeded(graph.connect(plug(graph, s, "sum"), plug(graph, g2, "values", 0)))) << "test setup";
  ASSERT_TRUE(testing::succeeded(graph.connect(plug(graph, s, "sum"), plug(graph, g1, "scale")))) << "test setup";
  ASSERT_TRUE(testing::succeeded(graph.connect(plug(graph, s, "sum"), plug(graph, g1, "values", 3)))) << "test setup";
  ASSERT_TRUE(testing::succeeded(graph.connect(plug(graph, s, "sum"), plug(graph, g1, "values", 1)))) << "test setup";
  std::vector<std::string> order;
  for (const Connection& c : graph.connections()) order.push_back(graph.plug_name(c.dst));
  EXPECT_EQ(order, (std::vector<std::string>{"g1.values[1]", "g1.values[3]", "g1.scale", "g2.values[0]"}))
      << "by destination node (creation order), attribute index, element";
  EXPECT_EQ(graph.node(s)->outputs().size(), 4u) << "the source lists its four outgoing connections";
  EXPECT_EQ(graph.node(g1)->inputs().size(), 3u) << "g1 lists its three incoming connections";
}

TEST(Graph, observers__nothing_fires_for_no_op_or_refused_edits) {
  Graph graph(test_registry());
  NodeId a = make(graph, "add", "a");
  NodeId b = make(graph, "add", "b");
  NodeId p = make(graph, "xf", "p");
  NodeId c = make(graph, "xf", "c");
  ASSERT_TRUE(graph.set_value(plug(graph, a, "a"), 2.0).is_ok()) << "set";
  ASSERT_TRUE(graph.set_tag(a, "k", "v").is_ok()) << "tag";
  ASSERT_TRUE(graph.connect(plug(graph, a, "sum"), plug(graph, b, "a")).is_ok()) << "connect";
  ASSERT_TRUE(graph.set_parent(c, p).is_ok()) << "parent";
  graph.select({a});
  graph.set_time(2.0);
  const std::size_t steps = graph.undo_count();

  Recorder rec;
  graph.add_observer(&rec);
  EXPECT_TRUE(graph.set_value(plug(graph, a, "a"), 2.0).is_ok()) << "same value";
  EXPECT_TRUE(graph.set_value(plug(graph, a, "a"), std::int64_t{2}).is_ok()) << "same value as an int";
  EXPECT_TRUE(graph.rename(a, "a").is_ok()) << "same name";
  EXPECT_TRUE(graph.set_tag(a, "k", "v").is_ok()) << "same tag";
  EXPECT_TRUE(graph.set_parent(c, p).is_ok()) << "same parent";
  EXPECT_TRUE(graph.set_parent(p, NodeId{}).is_ok()) << "a root stays a root";
  EXPECT_TRUE(graph.disconnect_input(plug(graph, a, "b")).is_ok()) << "nothing to disconnect";
  graph.select({a});
  graph.select({a, a, NodeId{}});
  graph.set_time(2.0);
  EXPECT_FALSE(graph.set_fps(-1.0).is_ok()) << "refused fps";
  EXPECT_FALSE(graph.set_value(plug(graph, b, "a"), 1.0).is_ok()) << "refused: connected";
  EXPECT_FALSE(graph.connect(plug(graph, b, "sum"), plug(graph, a, "a")).is_ok()) << "refused: cycle";
  EXPECT_FALSE(graph.rename(a, "b").is_ok()) << "refused: taken";
  EXPECT_FALSE(graph.create_node("add", "bad name").is_ok()) << "refused: name";
  EXPECT_FALSE(graph.remove_tag(a, "none").is_ok()) << "refused: no tag";
  (void)graph.evaluate(plug(graph, b, "sum"));
  graph.evaluate_all();
  EXPECT_TRUE(rec.events.empty()) << "no-op, refused and evaluation calls notify nobody; got "
                                  << ::testing::PrintToString(rec.events);
  EXPECT_EQ(graph.undo_count(), steps) << "and record no undo step";
  graph.remove_observer(&rec);
}

// ---- time ----------------------------------------------------------------------

TEST(Graph, set_fps__refuses_non_positive_and_absurd_rates) {
  Graph graph(test_registry());
  EXPECT_EQ(graph.fps(), 24.0) << "the default frame rate is 24";
  for (double bad : {0.0, -24.0, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
                     2e6}) {
    EXPECT_EQ(graph.set_fps(bad).code(), ErrorCode::kInvalidArgument) << bad << " fps is refused";
    EXPECT_EQ(graph.fps(), 24.0) << "a refused rate leaves the rate unchanged";
  }
  EXPECT_TRUE(graph.set_fps(29.97).is_ok()) << "fractional rates are fine";
  EXPECT_EQ(graph.fps(), 29.97) << "and kept exactly";
}

TEST(Graph, set_time__recomputes_time_dependent_nodes_only) {
  Graph graph(test_registry());
  NodeId clock = make(graph, "clock", "clock");
  NodeId follower = make(graph, "add", "follower");
  NodeId still = make(graph, "add", "still");
  ASSERT_TRUE(graph.connect(plug(graph, clock, "out"), plug(graph, follower, "a")).is_ok()) << "connect";
  ASSERT_TRUE(graph.set_value(plug(graph, clock, "gain"), 2.0).is_ok()) << "gain";
  graph.evaluate_all();
  EXPECT_EQ(eval_double(graph, follower, "sum"), 0.0) << "time 0";
  const auto clock_runs = computes(graph, clock), still_runs = computes(graph, still);

  graph.set_time(1.25);
  EXPECT_TRUE(graph.node(clock)->is_dirty(testing::clock_attr::kOut)) << "a time change dirties time-dependent outputs";
  EXPECT_TRUE(graph.node(follower)->is_dirty(testing::add_attr::kSum)) << "and what they feed";
  EXPECT_FALSE(graph.node(still)->is_dirty(testing::add_attr::kSum)) << "but nothing else";
  EXPECT_EQ(eval_double(graph, follower, "sum"), 2.5) << "the compute sees the new time";
  EXPECT_EQ(computes(graph, clock), clock_runs + 1) << "the clock recomputed once";
  graph.evaluate_all();
  EXPECT_EQ(computes(graph, still), still_runs) << "the time-independent node did not recompute";
  graph.set_time(1.25);
  EXPECT_FALSE(graph.node(clock)->is_dirty(testing::clock_attr::kOut)) << "setting the same time dirties nothing";

  ASSERT_TRUE(graph.delete_node(clock).is_ok()) << "delete the clock";
  graph.set_time(3.0);  // must not touch the deleted node
  ASSERT_TRUE(graph.undo()) << "undo the delete";
  NodeId back = graph.find("clock");
  EXPECT_EQ(eval_double(graph, back, "out"), 6.0) << "a restored time-dependent node follows time again";
  graph.set_time(4.0);
  EXPECT_EQ(eval_double(graph, back, "out"), 8.0) << "and keeps following it";
}

// What a time change dirties is listed once per topology: connecting,
// disconnecting, creating and deleting between time changes must each
// change what the next time change reaches.
TEST(Graph, set_time__follows_topology_edits_between_time_changes) {
  Graph graph(test_registry());
  NodeId clock = make(graph, "clock", "clock");
  NodeId a = make(graph, "add", "a");
  NodeId b = make(graph, "add", "b");
  ASSERT_TRUE(graph.connect(plug(graph, clock, "out"), plug(graph, a, "a")).is_ok());
  graph.set_time(1.0);
  EXPECT_EQ(eval_double(graph, a, "sum"), 1.0);
  EXPECT_EQ(eval_double(graph, b, "sum"), 0.0);

  ASSERT_TRUE(graph.connect(plug(graph, a, "sum"), plug(graph, b, "a")).is_ok()) << "clock -> a -> b";
  graph.set_time(2.0);
  EXPECT_TRUE(graph.node(b)->is_dirty(testing::add_attr::kSum)) << "a new downstream node is reached";
  EXPECT_EQ(eval_double(graph, b, "sum"), 2.0);

  ASSERT_TRUE(graph.disconnect(plug(graph, clock, "out"), plug(graph, a, "a")).is_ok());
  EXPECT_EQ(eval_double(graph, b, "sum"), 2.0) << "clean again after the disconnect";
  graph.set_time(3.0);
  EXPECT_FALSE(graph.node(a)->is_dirty(testing::add_attr::kSum)) << "a disconnected node is no longer reached";
  EXPECT_EQ(eval_double(graph, b, "sum"), 2.0) << "it keeps the last value it had";

  NodeId second = make(graph, "clock", "second");
  ASSERT_TRUE(graph.connect(plug(graph, second, "out"), plug(graph, a, "b")).is_ok());
  graph.set_time(4.0);
  EXPECT_EQ(eval_double(graph, b, "sum"), 6.0) << "a new clock drives a and b: 2 (kept) + 4";
  ASSERT_TRUE(graph.delete_node(second).is_ok());
  EXPECT_EQ(eval_double(graph, b, "sum"), 6.0) << "clean again after the delete";
  graph.set_time(5.0);  // must not touch the deleted node
  EXPECT_FALSE(graph.node(b)->is_dirty(testing::add_attr::kSum)) << "nothing time-dependent feeds b now";
  ASSERT_TRUE(graph.undo()) << "undo the delete (and its connection)";
  graph.set_time(6.0);
  EXPECT_EQ(eval_double(graph, b, "sum"), 8.0) << "the restored clock drives them again: 2 + 6";
}

// A time-invariant output (kTimeInvariant) of a time-dependent node stays
// clean when the time changes, so a compute can keep what it derived from
// the inputs alone (animation curves keep the check of their keys); an
// input change still dirties it. Only outputs may be time-invariant.
TEST(Graph, set_time__leaves_time_invariant_outputs_clean) {
  auto compute = [](ComputeContext& c) {
    c.output(1) = c.get<double>(0) * c.time();
    if (c.node().is_dirty(2)) c.output(2) = std::get<std::int64_t>(c.output(2)) + 1;  // times checked
  };
  NodeTypeSpec spec;
  spec.name = "checkedClock";
  spec.attrs = {testing::in_spec("gain", testing::kDoubleT, {"out", "checks"}, 1.0), testing::out_spec("out", testing::kDoubleT),
                testing::out_spec("checks", testing::kIntT)};
  spec.attrs[2].flags |= kTimeInvariant;
  spec.compute = compute;
  spec.time_dependent = true;
  auto registry = std::make_shared<Registry>();
  ASSERT_TRUE(registry->add(spec).is_ok());
  Graph graph(registry);
  NodeId n = make(graph, "checkedClock", "c");
  auto checks = [&] { return std::get<std::int64_t>(graph.evaluate(n, 2)); };
  EXPECT_EQ(checks(), 1);
  for (double t : {1.0, 2.0, 3.0}) {
    graph.set_time(t);
    EXPECT_TRUE(graph.node(n)->is_dirty(1)) << t;
    EXPECT_FALSE(graph.node(n)->is_dirty(2)) << t;
    EXPECT_EQ(eval_double(graph, n, "out"), t);
  }
  EXPECT_EQ(checks(), 1) << "time changes did not redo the check";
  ASSERT_TRUE(graph.set_value(plug(graph, n, "gain"), 2.0).is_ok());
  EXPECT_TRUE(graph.node(n)->is_dirty(2)) << "an input change dirties it";
  EXPECT_EQ(eval_double(graph, n, "out"), 6.0);
  EXPECT_EQ(checks(), 2);
  ASSERT_TRUE(graph.undo());
  EXPECT_EQ(checks(), 3) << "so does undo";

  NodeTypeSpec bad;
  bad.name = "badInvariant";
  bad.attrs = {testing::in_spec("gain", testing::kDoubleT, {"out"}), testing::out_spec("out", testing::kDoubleT)};
  bad.attrs[0].flags |= kTimeInvariant;
  bad.compute = compute;
  const Status refused = registry->add(bad);
  EXPECT_FALSE(refused.is_ok());
  EXPECT_NE(refused.message().find("only an output can be time-invariant"), std::string::npos) << refused.message();
}

}  // namespace
}  // namespace rigel::graph
