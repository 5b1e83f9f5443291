// Dirty propagation, pull evaluation, the compiled schedule, and parallel
// against serial evaluation (STYLE.md §7: the optimised evaluator checked
// against a simple reference).

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "graph_test_util.h"
#include "rigel/graph/graph.h"

namespace rigel::graph {
namespace {

using testing::computes;
using testing::eval_double;
using testing::g_add_computes;
using testing::make;
using testing::plug;
using testing::test_registry;
namespace add = testing::add_attr;
namespace split = testing::split_attr;

Status link(Graph& g, NodeId s, const char* sa, NodeId d, const char* da, std::int32_t de = -1) {
  return g.connect(plug(g, s, sa), plug(g, d, da, de));
}

TEST(Evaluation, set_value__dirties_only_downstream) {
  Graph graph(test_registry());
  NodeId up = make(graph, "add", "up");
  NodeId a = make(graph, "add", "a");
  NodeId b = make(graph, "add", "b");
  NodeId c = make(graph, "add", "c");
  NodeId side = make(graph, "add", "side");
  NodeId apart = make(graph, "add", "apart");
  ASSERT_TRUE(link(graph, up, "sum", a, "a").is_ok()) << "up -> a";
  ASSERT_TRUE(link(graph, a, "sum", b, "a").is_ok()) << "a -> b";
  ASSERT_TRUE(link(graph, b, "sum", c, "b").is_ok()) << "b -> c";
  ASSERT_TRUE(link(graph, up, "sum", side, "a").is_ok()) << "up -> side";
  graph.evaluate_all();
  for (NodeId id : graph.nodes()) {
    for (AttrIndex i = 0; i < 4; ++i) EXPECT_FALSE(graph.node(id)->is_dirty(i)) << "evaluate_all cleans everything";
  }

  ASSERT_TRUE(graph.set_value(plug(graph, a, "b"), 1.0).is_ok()) << "set a.b";
  EXPECT_FALSE(graph.node(a)->is_dirty(add::kB)) << "the set input itself holds its value: not dirty";
  EXPECT_TRUE(graph.node(a)->is_dirty(add::kSum)) << "the output it affects is dirty";
  EXPECT_TRUE(graph.node(b)->is_dirty(add::kA)) << "a connected input downstream is dirty";
  EXPECT_TRUE(graph.node(b)->is_dirty(add::kSum)) << "and its outputs";
  EXPECT_TRUE(graph.node(c)->is_dirty(add::kSum)) << "two hops downstream is dirty";
  EXPECT_FALSE(graph.node(c)->is_dirty(add::kA)) << "c.a is not fed by anything dirty";
  EXPECT_FALSE(graph.node(up)->is_dirty(add::kSum)) << "upstream stays clean";
  EXPECT_FALSE(graph.node(side)->is_dirty(add::kSum)) << "a sibling branch stays clean";
  EXPECT_FALSE(graph.node(apart)->is_dirty(add::kSum)) << "an unrelated node stays clean";
  EXPECT_FALSE(graph.node(a)->is_dirty(add::kA)) << "a.a is fed by clean up.sum";
}

TEST(Evaluation, evaluate__returns_updated_values) {
  Graph graph(test_registry());
  NodeId a = make(graph, "add", "a");
  NodeId b = make(graph, "add", "b");
  ASSERT_TRUE(link(graph, a, "sum", b, "a").is_ok()) << "a -> b";
  ASSERT_TRUE(graph.set_value(plug(graph, a, "a"), 2.0).is_ok()) << "set";
  ASSERT_TRUE(graph.set_value(plug(graph, b, "b"), 3.0).is_ok()) << "set";
  EXPECT_EQ(eval_double(graph, b, "sum"), 5.0) << "b.sum = (2 + 0) + 3";
  ASSERT_TRUE(graph.set_value(plug(graph, a, "b"), 10.0).is_ok()) << "set upstream";
  EXPECT_EQ(std::get<double>(graph.node(b)->value(add::kSum)), 5.0) << "the stored value is stale until pulled";
  EXPECT_EQ(eval_double(graph, b, "sum"), 15.0) << "evaluate pulls the change through";
  EXPECT_EQ(eval_double(graph, b, "a"), 12.0) << "a connected input evaluates to its source";
  EXPECT_EQ(std::get<double>(graph.evaluate(b, add::kSum)), 15.0) << "the fast path agrees";
}

TEST(Evaluation, evaluate__caches_clean_results) {
  Graph graph(test_registry());
  NodeId a = make(graph, "add", "a");
  NodeId b = make(graph, "add", "b");
  ASSERT_TRUE(link(graph, a, "sum", b, "a").is_ok()) << "a -> b";
  EXPECT_EQ(computes(graph, a), 0) << "nothing computes before it is asked for";
  (void)eval_double(graph, b, "sum");
  EXPECT_EQ(computes(graph, a), 1) << "pulling b computes a once";
  EXPECT_EQ(computes(graph, b), 1) << "and b once";
  const long total = g_add_computes.load();
  for (int i = 0; i < 5; ++i) (void)eval_double(graph, b, "sum");
  (void)eval_double(graph, a, "sum");
  graph.evaluate_all(Execution::kSerial);
  graph.evaluate_all(Execution::kParallel);
  EXPECT_EQ(g_add_computes.load(), total) << "clean values are served from the cache: no compute at all";
  ASSERT_TRUE(graph.set_value(plug(graph, b, "b"), 1.0).is_ok()) << "set b.b";
  (void)eval_double(graph, b, "sum");
  EXPECT_EQ(computes(graph, a), 1) << "a change downstream does not recompute upstream";
  EXPECT_EQ(computes(graph, b), 2) << "only b recomputes";
}

TEST(Evaluation, evaluate_all__recomputes_only_the_dirty_part) {
  Graph graph(test_registry());
  NodeId root = make(graph, "add", "root");
  NodeId x1 = make(graph, "add", "x1");
  NodeId x2 = make(graph, "add", "x2");
  NodeId y1 = make(graph, "add", "y1");
  NodeId y2 = make(graph, "add", "y2");
  NodeId z = make(graph, "add", "z");
  ASSERT_TRUE(link(graph, root, "sum", x1, "a").is_ok()) << "connect";
  ASSERT_TRUE(link(graph, root, "sum", x2, "a").is_ok()) << "connect";
  ASSERT_TRUE(link(graph, x1, "sum", y1, "a").is_ok()) << "connect";
  ASSERT_TRUE(link(graph, x2, "sum", y2, "a").is_ok()) << "connect";
  ASSERT_TRUE(link(graph, y1, "sum", z, "a").is_ok()) << "connect";
  ASSERT_TRUE(link(graph, y2, "sum", z, "b").is_ok()) << "connect";
  graph.evaluate_all();
  for (NodeId id : graph.nodes()) EXPECT_EQ(computes(graph, id), 1) << "first evaluation computes every node once";

  ASSERT_TRUE(graph.set_value(plug(graph, x1, "b"), 1.0).is_ok()) << "set x1.b";
  const long before = g_add_computes.load();
  graph.evaluate_all();
  EXPECT_EQ(g_add_computes.load() - before, 3) << "x1, y1 and z recompute; nothing else";
  EXPECT_EQ(computes(graph, x1), 2) << "x1 recomputed";
  EXPECT_EQ(computes(graph, y1), 2) << "y1 recomputed";
  EXPECT_EQ(computes(graph, z), 2) << "z recomputed once, though only one of its inputs changed";
  EXPECT_EQ(computes(graph, root), 1) << "root is upstream: not recomputed";
  EXPECT_EQ(computes(graph, x2), 1) << "the other branch is not recomputed";
  EXPECT_EQ(computes(graph, y2), 1) << "the other branch is not recomputed";
  EXPECT_EQ(eval_double(graph, z, "sum"), 1.0) << "and the result is right";
}

TEST(Evaluation, affects__an_input_dirties_only_the_outputs_it_affects) {
  Graph graph(test_registry());
  NodeId s = make(graph, "split", "s");
  NodeId p = make(graph, "add", "p");
  NodeId q = make(graph, "add", "q");
  ASSERT_TRUE(link(graph, s, "outX", p, "a").is_ok()) << "outX -> p";
  ASSERT_TRUE(link(graph, s, "outY", q, "a").is_ok()) << "outY -> q";
  graph.evaluate_all();
  ASSERT_TRUE(graph.set_value(plug(graph, s, "x"), 1.0).is_ok()) << "set x";
  EXPECT_TRUE(graph.node(s)->is_dirty(split::kOutX)) << "x affects outX";
  EXPECT_FALSE(graph.node(s)->is_dirty(split::kOutY)) << "x does not affect outY";
  EXPECT_TRUE(graph.node(p)->is_dirty(add::kSum)) << "p reads outX: dirty";
  EXPECT_FALSE(graph.node(q)->is_dirty(add::kA)) << "q reads outY: clean";
  EXPECT_FALSE(graph.node(q)->is_dirty(add::kSum)) << "q reads outY: clean";
  (void)eval_double(graph, q, "sum");
  EXPECT_EQ(computes(graph, s), 1) << "pulling through the clean outY computes nothing";
  EXPECT_EQ(computes(graph, q), 1) << "q is clean";
  EXPECT_EQ(eval_double(graph, p, "sum"), 2.0) << "p sees 2x";
  EXPECT_EQ(computes(graph, s), 2) << "s recomputed for outX";
  graph.evaluate_all();
  EXPECT_EQ(computes(graph, q), 1) << "q never recomputed";

  ASSERT_TRUE(graph.set_value(plug(graph, s, "y"), 1.0).is_ok()) << "set y";
  EXPECT_FALSE(graph.node(p)->is_dirty(add::kSum)) << "y does not reach p";
  EXPECT_EQ(eval_double(graph, q, "sum"), 3.0) << "q sees 3y";
}

TEST(Evaluation, pull__100000_node_chain_without_stack_overflow) {
  constexpr int kCount = 100000;
  Graph graph(test_registry());
  std::vector<NodeId> chain;
  chain.reserve(kCount);
  for (int i = 0; i < kCount; ++i) {
    chain.push_back(make(graph, "add", testing::numbered("n", i)));
    ASSERT_TRUE(graph.set_value(Plug{chain.back(), add::kB, -1}, 1.0).is_ok()) << "set b";
    if (i > 0) {
      ASSERT_TRUE(graph.connect(Plug{chain[i - 1], add::kSum, -1}, Plug{chain[i], add::kA, -1}).is_ok()) << "link " << i;
    }
  }
  ASSERT_TRUE(graph.set_value(Plug{chain[0], add::kA, -1}, 0.5).is_ok()) << "set the head";
  long before = g_add_computes.load();
  EXPECT_EQ(std::get<double>(graph.evaluate(chain.back(), add::kSum)), 0.5 + kCount)
      << "pulling the tail evaluates the whole chain, iteratively";
  EXPECT_EQ(g_add_computes.load() - before, kCount) << "each node computed exactly once";

  ASSERT_TRUE(graph.set_value(Plug{chain[kCount / 2], add::kB, -1}, 2.0).is_ok()) << "set in the middle";
  EXPECT_FALSE(graph.node(chain[kCount / 2 - 1])->is_dirty(add::kSum)) << "the first half stays clean";
  EXPECT_TRUE(graph.node(chain.back())->is_dirty(add::kSum)) << "the tail is dirty";
  before = g_add_computes.load();
  EXPECT_EQ(std::get<double>(graph.evaluate(chain.back(), add::kSum)), 1.5 + kCount) << "the change arrives";
  EXPECT_EQ(g_add_computes.load() - before, kCount / 2) << "only the second half recomputes";

  ASSERT_TRUE(graph.set_value(Plug{chain[0], add::kA, -1}, 1.5).is_ok()) << "set the head again";
  graph.evaluate_all(Execution::kParallel);
  EXPECT_EQ(std::get<double>(graph.node(chain.back())->value(add::kSum)), 2.5 + kCount)
      << "evaluate_all also handles a chain (one node per level)";
  EXPECT_EQ(graph.schedule_level_count(), static_cast<std::size_t>(kCount)) << "one level per link";
}

TEST(Evaluation, disconnect__keeps_the_last_value) {
  Graph graph(test_registry());
  NodeId a = make(graph, "add", "a");
  NodeId b = make(graph, "add", "b");
  NodeId g = make(graph, "gather", "g");
  ASSERT_TRUE(link(graph, a, "sum", b, "a").is_ok()) << "a -> b";
  ASSERT_TRUE(link(graph, a, "sum", g, "values", 1).is_ok()) << "a -> g.values[1]";
  EXPECT_EQ(eval_double(graph, b, "sum"), 0.0) << "evaluate once";
  ASSERT_TRUE(graph.set_value(plug(graph, a, "a"), 3.0).is_ok()) << "change the source, not pulled yet";
  ASSERT_TRUE(graph.disconnect(plug(graph, a, "sum"), plug(graph, b, "a")).is_ok()) << "disconnect";
  EXPECT_EQ(std::get<double>(graph.node(b)->value(add::kA)), 3.0)
      << "the destination keeps the value the source had at the disconnect, pulled even if never evaluated";
  ASSERT_TRUE(graph.disconnect(plug(graph, a, "sum"), plug(graph, g, "values", 1)).is_ok()) << "disconnect element";
  EXPECT_TRUE(values_identical(graph.node(g)->value(testing::gather_attr::kValues), std::vector<double>{0.0, 3.0}))
      << "an element keeps its last value too";
  ASSERT_TRUE(graph.set_value(plug(graph, a, "a"), 10.0).is_ok()) << "change the source again";
  EXPECT_EQ(eval_double(graph, b, "sum"), 3.0) << "the former destination no longer follows";
  EXPECT_EQ(eval_double(graph, g, "total"), 3.0) << "the former element no longer follows";
  ASSERT_TRUE(graph.set_value(plug(graph, b, "a"), 4.0).is_ok()) << "a disconnected input can be set again";
  EXPECT_EQ(eval_double(graph, b, "sum"), 4.0) << "and evaluates";
}

TEST(Evaluation, connect__dirties_the_destination_and_element_connections_flow) {
  Graph graph(test_registry());
  NodeId a = make(graph, "add", "a");
  NodeId b = make(graph, "add", "b");
  NodeId g = make(graph, "gather", "g");
  NodeId h = make(graph, "gather", "h");
  ASSERT_TRUE(graph.set_value(plug(graph, a, "a"), 2.0).is_ok()) << "set";
  ASSERT_TRUE(graph.set_value(plug(graph, b, "a"), 5.0).is_ok()) << "set";
  ASSERT_TRUE(graph.set_value(plug(graph, g, "values", 1), 100.0).is_ok()) << "set an element";
  graph.evaluate_all();
  EXPECT_EQ(eval_double(graph, g, "total"), 100.0) << "one element";
  ASSERT_TRUE(link(graph, a, "sum", g, "values", 0).is_ok()) << "a -> g.values[0]";
  EXPECT_TRUE(graph.node(g)->is_dirty(testing::gather_attr::kTotal)) << "a new connection dirties downstream";
  ASSERT_TRUE(link(graph, b, "sum", g, "values", 3).is_ok()) << "b -> g.values[3]";
  EXPECT_EQ(eval_double(graph, g, "total"), 107.0) << "connected elements arrive; the set element stays";
  EXPECT_TRUE(values_identical(graph.node(g)->value(testing::gather_attr::kValues), std::vector<double>{2, 100, 0, 5}))
      << "element 3 grew the array; element 2 is a zero";
  ASSERT_TRUE(graph.set_value(plug(graph, g, "scale"), 2.0).is_ok()) << "scale";
  ASSERT_TRUE(link(graph, g, "echo", h, "values").is_ok()) << "whole array g.echo -> h.values";
  EXPECT_EQ(eval_double(graph, h, "total"), 214.0) << "a whole array flows";
  NodeId c = make(graph, "add", "c");
  ASSERT_TRUE(graph.connect(plug(graph, g, "echo", 3), plug(graph, c, "a")).is_ok()) << "g.echo[3] -> c.a";
  EXPECT_EQ(eval_double(graph, c, "sum"), 10.0) << "an array element feeds a scalar";
  ASSERT_TRUE(graph.set_value(plug(graph, b, "b"), 1.0).is_ok()) << "b changes";
  EXPECT_EQ(eval_double(graph, c, "sum"), 12.0) << "and the change reaches c through two element links";
  NodeId d = make(graph, "add", "d");
  ASSERT_TRUE(graph.connect(plug(graph, g, "echo", 9), plug(graph, d, "a")).is_ok()) << "past the end";
  EXPECT_EQ(eval_double(graph, d, "sum"), 0.0) << "an element past the end of the source reads as zero";
}

// ---- random DAGs: evaluate_all (serial and parallel) against pull ------------

// Builds `count` nodes of the test types with random values and random
// connections from earlier nodes (so no cycles). The same seed builds the
// same graph, node for node.
std::vector<NodeId> build_random_dag(Graph& graph, std::uint32_t seed, int count, std::string_view prefix = "n") {
  std::mt19937 rng(seed);
  auto uniform = [&](double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); };
  auto chance = [&](double p) { return std::bernoulli_distribution(p)(rng); };
  std::vector<NodeId> ids;
  std::vector<Plug> double_sources;  // scalar double outputs so far
  std::vector<Plug> array_sources;   // double[] outputs so far
  auto pick = [&](const std::vector<Plug>& from) { return from[std::uniform_int_distribution<std::size_t>(0, from.size() - 1)(rng)]; };
  static const char* kTypes[] = {"add", "split", "gather"};
  for (int i = 0; i < count; ++i) {
    const char* type = kTypes[std::uniform_int_distribution<int>(0, 2)(rng)];
    NodeId id = make(graph, type, testing::numbered(prefix, i));
    ids.push_back(id);
    const NodeType& t = graph.node(id)->type();
    for (AttrIndex a = 0; a < t.attr_count(); ++a) {
      if (!t.is_input(a)) continue;
      const AttrSpec& spec = t.attr(a);
      if (spec.type.value == ValueType::kMessage) continue;  // metaParent
      if (!spec.type.array) {
        if (!double_sources.empty() && chance(0.6)) {
          EXPECT_TRUE(testing::succeeded(graph.connect(pick(double_sources), Plug{id, a, -1}))) << "test setup";
        } else {
          EXPECT_TRUE(testing::succeeded(graph.set_value(Plug{id, a, -1}, uniform(-2, 2)))) << "test setup";
        }
      } else if (!array_sources.empty() && chance(0.3)) {
        EXPECT_TRUE(testing::succeeded(graph.connect(pick(array_sources), Plug{id, a, -1}))) << "test setup";
      } else {
        const int n = std::uniform_int_distribution<int>(0, 4)(rng);
        for (int e = 0; e < n; ++e) {
          if (!double_sources.empty() && chance(0.5)) {
            EXPECT_TRUE(testing::succeeded(graph.connect(pick(double_sources), Plug{id, a, e}))) << "test setup";
          } else if (!array_sources.empty() && chance(0.3)) {
            Plug src = pick(array_sources);
            src.element = std::uniform_int_distribution<int>(0, 5)(rng);
            EXPECT_TRUE(testing::succeeded(graph.connect(src, Plug{id, a, e}))) << "test setup";
          } else {
            EXPECT_TRUE(testing::succeeded(graph.set_value(Plug{id, a, e}, uniform(-2, 2)))) << "test setup";
          }
        }
      }
    }
    for (AttrIndex o : t.outputs()) {
      if (t.attr(o).type == testing::kDoubleT) double_sources.push_back(Plug{id, o, -1});
      if (t.attr(o).type == testing::kDoubleArrayT) array_sources.push_back(Plug{id, o, -1});
    }
  }
  return ids;
}

// Applies the same random input edits to a graph built by build_random_dag.
void random_edits(Graph& graph, const std::vector<NodeId>& ids, std::uint32_t seed, int edits) {
  std::mt19937 rng(seed);
  for (int i = 0; i < edits; ++i) {
    NodeId id = ids[std::uniform_int_distribution<std::size_t>(0, ids.size() - 1)(rng)];
    const double v = std::uniform_real_distribution<double>(-3, 3)(rng);
    // First unconnected scalar input, if any.
    const NodeType& t = graph.node(id)->type();
    for (AttrIndex a = 0; a < t.attr_count(); ++a) {
      if (t.is_input(a) && !t.attr(a).type.array && t.attr(a).type.value != ValueType::kMessage &&
          !graph.source(Plug{id, a, -1})) {
        EXPECT_TRUE(testing::succeeded(graph.set_value(Plug{id, a, -1}, v))) << "test setup";
        break;
      }
    }
  }
}

// Every output of every node, compared bit for bit.
::testing::AssertionResult same_outputs(const Graph& a, const Graph& b, const std::vector<NodeId>& ids) {
  for (std::size_t i = 0; i < ids.size(); ++i) {
    const Node& na = *a.node(ids[i]);
    const Node& nb = *b.node(ids[i]);
    for (AttrIndex o : na.type().outputs()) {
      if (na.type().attr(o).name == "count") continue;
      if (!values_identical(na.value(o), nb.value(o)))
        return ::testing::AssertionFailure() << "node " << na.name() << "." << na.type().attr(o).name << ": "
                                             << testing::exact_text(na.value(o)) << " vs "
                                             << testing::exact_text(nb.value(o));
    }
  }
  return ::testing::AssertionSuccess();
}

long total_computes(const Graph& g, const std::vector<NodeId>& ids) {
  long total = 0;
  for (NodeId id : ids) total += computes(g, id);
  return total;
}

// Dirty propagation (breadth first; prefetching in schedule order when the
// compiled program is current) marks exactly the plugs downstream of the
// one set: checked against a plain depth-first closure over the public
// API, in both evaluations, on a random DAG with element connections.
TEST(Evaluation, set_value__dirties_exactly_the_downstream_closure) {
  for (Evaluation e : {Evaluation::kInterpreted, Evaluation::kCompiled}) {
    SCOPED_TRACE(evaluation_name(e));
    Graph g(test_registry());
    const std::vector<NodeId> ids = build_random_dag(g, 21, 3000);
    g.set_evaluation(e);
    std::mt19937 rng(3);
    int checked = 0;
    for (int round = 0; round < 40; ++round) {
      g.evaluate_all(Execution::kSerial);  // everything clean (and the program current)
      const NodeId id = ids[std::uniform_int_distribution<std::size_t>(0, ids.size() - 1)(rng)];
      const NodeType& t = g.node(id)->type();
      AttrIndex set = kNoAttr;
      for (AttrIndex a = 0; a < t.attr_count() && set == kNoAttr; ++a)
        if (t.is_input(a) && !t.attr(a).type.array && t.attr(a).type.value != ValueType::kMessage &&
            !g.source(Plug{id, a, -1}))
          set = a;
      if (set == kNoAttr) continue;
      // The expected closure: what the set plug affects and feeds, and so on.
      std::set<std::pair<std::uint32_t, AttrIndex>> expected;
      std::vector<std::pair<NodeId, AttrIndex>> stack;
      const auto downstream = [&](NodeId n, AttrIndex a) {
        for (AttrIndex o : g.node(n)->type().affected_outputs(a)) stack.emplace_back(n, o);
        for (const Connection& c : g.node(n)->outputs())
          if (c.src.attr == a) stack.emplace_back(c.dst.node, c.dst.attr);
      };
      downstream(id, set);
      while (!stack.empty()) {
        const auto [n, a] = stack.back();
        stack.pop_back();
        if (expected.emplace(n.index, a).second) downstream(n, a);
      }
      ASSERT_TRUE(testing::succeeded(g.set_value(Plug{id, set, -1}, static_cast<double>(round)))) << "test setup";
      for (NodeId n : ids) {
        const Node& node = *g.node(n);
        for (AttrIndex a = 0; a < node.type().attr_count(); ++a)
          ASSERT_EQ(node.is_dirty(a), expected.count({n.index, a}) == 1)
              << node.name() << "." << node.type().attr(a).name << " after setting " << g.node(id)->name() << "."
              << t.attr(set).name;
      }
      checked += expected.size() > 1 ? 1 : 0;
    }
    EXPECT_GT(checked, 10) << "test setup: most sets reach past their own node";
  }
}

TEST(Evaluation, evaluate_all__serial_parallel_and_pull_agree_bit_for_bit) {
  constexpr int kCount = 3000;
  for (std::uint32_t seed : {1u, 2u, 3u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    Graph serial(test_registry()), parallel(test_registry()), pulled(test_registry());
    const std::vector<NodeId> ids = build_random_dag(serial, seed, kCount);
    ASSERT_EQ(build_random_dag(parallel, seed, kCount), ids) << "same seed, same graph";
    ASSERT_EQ(build_random_dag(pulled, seed, kCount), ids) << "same seed, same graph";
    ASSERT_EQ(serial.connections().size(), pulled.connections().size()) << "same connections";

    for (int round = 0; round < 3; ++round) {
      SCOPED_TRACE("round " + std::to_string(round));
      if (round > 0) {
        random_edits(serial, ids, seed * 100 + round, 50);
        random_edits(parallel, ids, seed * 100 + round, 50);
        random_edits(pulled, ids, seed * 100 + round, 50);
      }
      serial.evaluate_all(Execution::kSerial);
      parallel.evaluate_all(Execution::kParallel);
      // Pull every output, in a shuffled order, as a reader would.
      std::vector<NodeId> order = ids;
      std::shuffle(order.begin(), order.end(), std::mt19937(seed + round));
      for (NodeId id : order) {
        for (AttrIndex o : pulled.node(id)->type().outputs()) (void)pulled.evaluate(id, o);
      }
      EXPECT_TRUE(same_outputs(serial, parallel, ids)) << "parallel evaluate_all must match serial bit for bit";
      EXPECT_TRUE(same_outputs(serial, pulled, ids)) << "evaluate_all must match pull evaluation bit for bit";
      EXPECT_EQ(total_computes(serial, ids), total_computes(parallel, ids))
          << "serial and parallel run the same computes";
      EXPECT_EQ(total_computes(serial, ids), total_computes(pulled, ids))
          << "pull runs exactly the computes evaluate_all runs: each dirty node once";
      for (NodeId id : ids) {
        for (AttrIndex a = 0; a < parallel.node(id)->type().attr_count(); ++a)
          ASSERT_FALSE(parallel.node(id)->is_dirty(a)) << "nothing stays dirty after evaluate_all";
      }
    }
    EXPECT_GT(parallel.schedule_level_count(), 2u) << "a random DAG has several levels";
    EXPECT_LT(parallel.schedule_level_count(), static_cast<std::size_t>(kCount / 64))
        << "so some level is wide enough to run in parallel (the parallel path is exercised)";
  }
}

// Independent parts of a graph (characters: no connection between them)
// are scheduled as separate components and run as parallel tasks, each level
// by level; the result is the serial one, bit for bit, edits included.
TEST(Evaluation, evaluate_all__independent_components_in_parallel_agree_with_serial) {
  constexpr int kParts = 12;
  constexpr int kCount = 400;
  Graph serial(test_registry()), parallel(test_registry()), pulled(test_registry());
  std::vector<NodeId> ids;
  for (int part = 0; part < kParts; ++part) {
    const std::string prefix = testing::numbered("p", part) + "_";
    const auto seed = static_cast<std::uint32_t>(40 + part);
    const std::vector<NodeId> made = build_random_dag(serial, seed, kCount, prefix);
    ASSERT_EQ(build_random_dag(parallel, seed, kCount, prefix), made) << "same seed, same graph";
    ASSERT_EQ(build_random_dag(pulled, seed, kCount, prefix), made) << "same seed, same graph";
    ids.insert(ids.end(), made.begin(), made.end());
  }
  for (int round = 0; round < 4; ++round) {
    SCOPED_TRACE("round " + std::to_string(round));
    if (round > 0) {
      for (Graph* g : {&serial, &parallel, &pulled}) random_edits(*g, ids, 900 + round, 40);
    }
    if (round == 2) {  // a topology change between rounds: one part feeds another
      const auto is_add = [&](NodeId id) { return serial.node(id)->type().name() == "add"; };
      const auto src = std::find_if(ids.begin(), ids.begin() + kCount, is_add);
      const auto dst = std::find_if(ids.begin() + kCount, ids.begin() + 2 * kCount, [&](NodeId id) {
        return is_add(id) && !serial.source(Plug{id, testing::add_attr::kB, -1});
      });
      ASSERT_TRUE(src != ids.begin() + kCount && dst != ids.begin() + 2 * kCount) << "test setup";
      for (Graph* g : {&serial, &parallel, &pulled}) {
        ASSERT_TRUE(g->connect(Plug{*src, testing::add_attr::kSum, -1}, Plug{*dst, testing::add_attr::kB, -1}).is_ok())
            << "part 0 feeds part 1";
      }
    }
    serial.evaluate_all(Execution::kSerial);
    parallel.evaluate_all(Execution::kParallel);
    for (NodeId id : ids)
      for (AttrIndex o : pulled.node(id)->type().outputs()) (void)pulled.evaluate(id, o);
    EXPECT_TRUE(same_outputs(serial, parallel, ids)) << "parallel components must match serial bit for bit";
    EXPECT_TRUE(same_outputs(serial, pulled, ids)) << "and pull evaluation";
    EXPECT_EQ(total_computes(serial, ids), total_computes(parallel, ids)) << "the same computes";
  }
}

// The compiled evaluation (issue 19) against the interpreted reference on
// random DAGs (scalar, array and element connections): evaluate_all serial
// and parallel and pulls in compiled mode, through input edits, a
// connection made and broken, undo and redo, and a node deleted (each a
// recompile): every output bit for bit, and the same computes.
TEST(Evaluation, compiled__agrees_with_interpreted_bit_for_bit_through_edits) {
  constexpr int kCount = 1200;
  for (std::uint32_t seed : {7u, 8u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    Graph reference(test_registry()), serial(test_registry()), parallel(test_registry()), pulled(test_registry());
    std::vector<NodeId> ids = build_random_dag(reference, seed, kCount);
    for (Graph* g : {&serial, &parallel, &pulled}) {
      ASSERT_EQ(build_random_dag(*g, seed, kCount), ids) << "same seed, same graph";
      g->set_evaluation(Evaluation::kCompiled);
    }
    EXPECT_EQ(reference.evaluation(), Evaluation::kCompiled) << "the default";
    reference.set_evaluation(Evaluation::kInterpreted);
    Graph* all[] = {&reference, &serial, &parallel, &pulled};
    const auto is_add = [&](NodeId id) { return reference.node(id)->type().name() == "add"; };
    const auto src = std::find_if(ids.begin(), ids.begin() + kCount / 2, is_add);
    const auto dst = std::find_if(ids.begin() + kCount / 2, ids.end(), [&](NodeId id) {
      return is_add(id) && !reference.source(Plug{id, add::kB, -1});
    });
    ASSERT_TRUE(src != ids.begin() + kCount / 2 && dst != ids.end()) << "test setup";
    const Plug from{*src, add::kSum, -1}, to{*dst, add::kB, -1};
    for (int round = 0; round < 7; ++round) {
      SCOPED_TRACE("round " + std::to_string(round));
      if (round > 0 && round != 6) {  // round 6 undoes round 5's delete
        for (Graph* g : all) random_edits(*g, ids, seed * 1000 + round, 40);
      }
      for (Graph* g : all) {
        switch (round) {
          case 2: ASSERT_TRUE(g->connect(from, to).is_ok()) << "a connection made"; break;
          case 3: ASSERT_TRUE(g->disconnect(from, to).is_ok()) << "and broken"; break;
          case 4:
            ASSERT_TRUE(g->undo() && g->undo() && g->undo()) << "undo";
            ASSERT_TRUE(g->redo()) << "redo";
            break;
          case 5:  // after the round's edits: a node deleted
            ASSERT_TRUE(g->delete_node(ids[kCount / 3]).is_ok()) << "a node deleted";
            break;
          case 6: ASSERT_TRUE(g->undo()) << "the delete undone"; break;
          default: break;
        }
      }
      if (round == 5) ids.erase(ids.begin() + kCount / 3);
      if (round == 6) ids.insert(ids.begin() + kCount / 3, reference.find(testing::numbered("n", kCount / 3)));
      reference.evaluate_all(Execution::kSerial);
      serial.evaluate_all(Execution::kSerial);
      parallel.evaluate_all(Execution::kParallel);
      std::vector<NodeId> order = ids;
      std::shuffle(order.begin(), order.end(), std::mt19937(seed + round));
      pulled.compile();  // a pull uses the program, never makes it
      for (NodeId id : order) {
        NodeId here = pulled.find(reference.node(id)->name());
        for (AttrIndex o : pulled.node(here)->type().outputs()) (void)pulled.evaluate(here, o);
      }
      if (round == 6) {
        // The undone delete recreated the node under a new handle in each graph.
        for (Graph* g : {&serial, &parallel, &pulled})
          ASSERT_EQ(g->find(reference.node(ids[kCount / 3])->name()).index, ids[kCount / 3].index) << "test setup";
      }
      EXPECT_TRUE(same_outputs(reference, serial, ids)) << "compiled serial must match interpreted bit for bit";
      EXPECT_TRUE(same_outputs(reference, parallel, ids)) << "compiled parallel must match interpreted bit for bit";
      EXPECT_TRUE(same_outputs(reference, pulled, ids)) << "compiled pulls must match interpreted bit for bit";
      EXPECT_EQ(total_computes(reference, ids), total_computes(serial, ids)) << "the same computes";
      EXPECT_EQ(total_computes(reference, ids), total_computes(pulled, ids)) << "the same computes by pull";
    }
  }
}

TEST(Evaluation, evaluation__names_round_trip_and_unknown_names_are_refused) {
  for (Evaluation e : {Evaluation::kInterpreted, Evaluation::kCompiled}) {
    auto back = evaluation_from_name(evaluation_name(e));
    ASSERT_TRUE(back.is_ok());
    EXPECT_EQ(*back, e);
  }
  auto bad = evaluation_from_name("fast");
  ASSERT_FALSE(bad.is_ok());
  EXPECT_NE(bad.status().message().find("'fast'"), std::string::npos) << bad.status().message();
  EXPECT_NE(bad.status().message().find("interpreted or compiled"), std::string::npos) << bad.status().message();
}

TEST(Evaluation, schedule__is_recompiled_when_topology_changes) {
  Graph graph(test_registry());
  NodeId a = make(graph, "add", "a");
  NodeId b = make(graph, "add", "b");
  EXPECT_EQ(graph.schedule_level_count(), 1u) << "two unconnected nodes: one level";
  const std::uint64_t g0 = graph.topology_generation();
  ASSERT_TRUE(link(graph, a, "sum", b, "a").is_ok()) << "a -> b";
  EXPECT_GT(graph.topology_generation(), g0) << "a connection bumps the topology generation";
  EXPECT_EQ(graph.schedule_level_count(), 2u) << "a -> b: two levels";
  const std::uint64_t g1 = graph.topology_generation();
  ASSERT_TRUE(graph.set_value(plug(graph, a, "a"), 1.0).is_ok()) << "set";
  ASSERT_TRUE(graph.rename(a, "a2").is_ok()) << "rename";
  ASSERT_TRUE(graph.set_tag(a, "k", "v").is_ok()) << "tag";
  EXPECT_EQ(graph.topology_generation(), g1) << "values, names and tags do not change the topology";
  ASSERT_TRUE(graph.delete_node(a).is_ok()) << "delete";
  EXPECT_GT(graph.topology_generation(), g1) << "a delete does";
  EXPECT_EQ(graph.schedule_level_count(), 1u) << "one node left: one level";
  graph.evaluate_all();
  EXPECT_EQ(eval_double(graph, b, "sum"), 1.0) << "b kept the last value it received";
  Graph empty(test_registry());
  EXPECT_EQ(empty.schedule_level_count(), 0u) << "an empty graph has no levels";
  empty.evaluate_all();
}

TEST(Evaluation, evaluate_all__after_many_pulls_still_finds_every_dirty_node) {
  // Pulls clean nodes without taking them off the dirty list; the list is
  // compacted when it grows. Whatever is dirty must still be evaluated.
  Graph graph(test_registry());
  NodeId a = make(graph, "add", "a");
  NodeId b = make(graph, "add", "b");
  NodeId c = make(graph, "add", "c");
  ASSERT_TRUE(link(graph, a, "sum", b, "a").is_ok()) << "connect";
  ASSERT_TRUE(link(graph, b, "sum", c, "a").is_ok()) << "connect";
  for (int i = 1; i <= 500; ++i) {
    ASSERT_TRUE(graph.set_value(plug(graph, a, "a"), static_cast<double>(i)).is_ok()) << "set a.a";
    EXPECT_EQ(eval_double(graph, b, "sum"), static_cast<double>(i)) << "pulling b cleans a and b, not c";
  }
  const long before = g_add_computes.load();
  graph.evaluate_all();
  EXPECT_EQ(g_add_computes.load() - before, 1) << "only c was still dirty";
  EXPECT_EQ(std::get<double>(graph.node(c)->value(graph.node(c)->type().attr_find("sum"))), 500.0)
      << "evaluate_all brought c up to date";
  graph.evaluate_all();
  EXPECT_EQ(g_add_computes.load() - before, 1) << "a second evaluate_all finds nothing dirty";
}


// A node's cache (ComputeContext::cache) is rebuilt from its inputs only
// when their versions change: a set, an undo or redo of one, and a
// connection's refresh each give a new version; evaluating again, or an
// edit elsewhere, does not.
TEST(Evaluation, version__changes_on_every_write_of_the_input_and_only_then) {
  Graph graph(test_registry());
  const NodeId v = make(graph, "versioned", "v");
  const NodeId other = make(graph, "add", "other");
  auto builds = [&] { return std::get<std::int64_t>(*graph.evaluate(plug(graph, v, "builds"))); };
  auto version = [&] { return std::get<std::int64_t>(*graph.evaluate(plug(graph, v, "aVersion"))); };
  EXPECT_EQ(builds(), 1) << "first evaluation builds the cache";
  const std::int64_t v0 = version();
  ASSERT_TRUE(graph.set_value(plug(graph, other, "a"), 5.0).is_ok());
  EXPECT_EQ(eval_double(graph, other, "sum"), 5.0);
  EXPECT_EQ(builds(), 1) << "an edit elsewhere keeps it";

  ASSERT_TRUE(graph.set_value(plug(graph, v, "a"), 2.0).is_ok());
  EXPECT_EQ(builds(), 2) << "a set gives a new version";
  const std::int64_t v1 = version();
  EXPECT_NE(v1, v0);
  ASSERT_TRUE(graph.set_value(plug(graph, v, "a"), 2.0).is_ok());
  EXPECT_EQ(builds(), 2) << "setting the same value is no write";

  ASSERT_TRUE(graph.undo());
  EXPECT_EQ(builds(), 3) << "undo writes the old value back: a new version";
  EXPECT_NE(version(), v1);
  ASSERT_TRUE(graph.redo());
  EXPECT_EQ(builds(), 4) << "so does redo";

  ASSERT_TRUE(link(graph, other, "sum", v, "a").is_ok());
  EXPECT_EQ(builds(), 5) << "a new connection refreshes the input";
  EXPECT_EQ(builds(), 5) << "evaluating again changes nothing";
  ASSERT_TRUE(graph.set_value(plug(graph, other, "b"), 1.0).is_ok());
  EXPECT_EQ(builds(), 6) << "the source changed: the refreshed input has a new version";
  ASSERT_TRUE(graph.undo());
  EXPECT_EQ(builds(), 7) << "undoing the source's change refreshes it again";

  ASSERT_TRUE(graph.delete_node(v).is_ok());
  ASSERT_TRUE(graph.undo());
  const NodeId back = graph.find("v");
  ASSERT_TRUE(graph.node(back) != nullptr);
  EXPECT_EQ(std::get<std::int64_t>(*graph.evaluate(plug(graph, back, "builds"))), 1)
      << "a node brought back by undo starts with no cache";
}

}  // namespace
}  // namespace rigel::graph
