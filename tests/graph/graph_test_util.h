#pragma once
// Node types and helpers shared by the graph tests. The types are registered
// here, by the tests, so that the graph layer is tested without the scene
// layer above it. Compute functions count their runs twice: a per-node
// "count" output (which nodes recomputed) and a per-type atomic counter (how
// many computes ran in total, safe under parallel evaluation).

#include <gtest/gtest.h>

#include <atomic>
#include <bit>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "rigel/graph/graph.h"
#include "rigel/graph/node_type.h"
#include "rigel/graph/value.h"

namespace rigel::graph::testing {

inline constexpr AttrType kDoubleT{ValueType::kDouble, false};
inline constexpr AttrType kIntT{ValueType::kInt, false};
inline constexpr AttrType kMatrixT{ValueType::kMatrix, false};
inline constexpr AttrType kDoubleArrayT{ValueType::kDouble, true};

inline AttrSpec in_spec(std::string name, AttrType type, std::vector<std::string> affects = {},
                           Value default_value = std::monostate{}) {
  AttrSpec spec;
  spec.name = std::move(name);
  spec.type = type;
  spec.default_value = std::move(default_value);
  spec.flags = kInput | kStorable;
  spec.affects = std::move(affects);
  return spec;
}

inline AttrSpec out_spec(std::string name, AttrType type) {
  AttrSpec spec;
  spec.name = std::move(name);
  spec.type = type;
  spec.flags = kOutput;
  return spec;
}

// ---- "add": sum = a + b ------------------------------------------------------
namespace add_attr {
enum : AttrIndex { kA, kB, kSum, kCount };
}
inline std::atomic<long> g_add_computes{0};
inline void bump_count(ComputeContext& c, AttrIndex count) { std::get<std::int64_t>(c.output(count)) += 1; }
inline void compute_add(ComputeContext& c) {
  c.set(add_attr::kSum, c.get<double>(add_attr::kA) + c.get<double>(add_attr::kB));
  bump_count(c, add_attr::kCount);
  g_add_computes.fetch_add(1, std::memory_order_relaxed);
}

// ---- "split": outX = 2x (x affects only outX), outY = 3y ----------------------
namespace split_attr {
enum : AttrIndex { kX, kY, kOutX, kOutY, kCount };
}
inline void compute_split(ComputeContext& c) {
  c.set(split_attr::kOutX, 2.0 * c.get<double>(split_attr::kX));
  c.set(split_attr::kOutY, 3.0 * c.get<double>(split_attr::kY));
  bump_count(c, split_attr::kCount);
}

// ---- "gather": total = sum(values), echo = values * scale ---------------------
namespace gather_attr {
enum : AttrIndex { kValues, kScale, kTotal, kEcho, kCount };
}
inline void compute_gather(ComputeContext& c) {
  const auto& values = c.get<std::vector<double>>(gather_attr::kValues);
  const double scale = c.get<double>(gather_attr::kScale);
  double total = 0.0;
  std::vector<double> echo;
  for (double v : values) {
    total += v;
    echo.push_back(v * scale);
  }
  c.set(gather_attr::kTotal, total);
  c.set(gather_attr::kEcho, std::move(echo));
  bump_count(c, gather_attr::kCount);
}

// ---- "clock": time dependent, out = time * gain -------------------------------
namespace clock_attr {
enum : AttrIndex { kGain, kOut, kCount };
}
inline void compute_clock(ComputeContext& c) {
  c.set(clock_attr::kOut, c.time() * c.get<double>(clock_attr::kGain));
  bump_count(c, clock_attr::kCount);
}

// ---- "xf": a minimal hierarchy node, world = parentMatrix * local -------------
namespace xf_attr {
enum : AttrIndex { kParentMatrix, kLocal, kWorld, kCount };
}
inline void compute_xf(ComputeContext& c) {
  c.set(xf_attr::kWorld, Mat4(c.get<Mat4>(xf_attr::kParentMatrix) * c.get<Mat4>(xf_attr::kLocal)));
  bump_count(c, xf_attr::kCount);
}

// ---- "versioned": what a compute sees of its input's version -----------------
// aVersion = version(a); builds counts the times the node's cache saw a new
// version of `a` (what a compiled cache such as a skin's would rebuild).
namespace versioned_attr {
enum : AttrIndex { kA, kAVersion, kBuilds, kCount };
}
struct VersionedCache final : NodeCache {
  std::uint64_t seen = 0;
  bool any = false;
  std::int64_t builds = 0;
};
inline void compute_versioned(ComputeContext& c) {
  VersionedCache& cache = c.cache<VersionedCache>();
  const std::uint64_t v = c.version(versioned_attr::kA);
  if (!cache.any || v != cache.seen) {
    cache.any = true;
    cache.seen = v;
    ++cache.builds;
  }
  c.set(versioned_attr::kAVersion, static_cast<std::int64_t>(v));
  c.set(versioned_attr::kBuilds, cache.builds);
  bump_count(c, versioned_attr::kCount);
}

// ---- "kinds": one input and one output of each value type ----------------------
// Inputs are named "in" + suffix, outputs "out" + suffix, for the suffixes
// below. The compute writes nothing: outputs keep their defaults.
struct Kind {
  const char* suffix;
  AttrType type;
};
inline const std::vector<Kind>& kinds() {
  static const std::vector<Kind> all = {
      {"Bool", {ValueType::kBool, false}},          {"Int", {ValueType::kInt, false}},
      {"Enum", {ValueType::kEnum, false}},          {"Double", {ValueType::kDouble, false}},
      {"Double3", {ValueType::kDouble3, false}},    {"Quat", {ValueType::kQuat, false}},
      {"Matrix", {ValueType::kMatrix, false}},      {"String", {ValueType::kString, false}},
      {"Message", {ValueType::kMessage, false}},    {"BoolArr", {ValueType::kBool, true}},
      {"IntArr", {ValueType::kInt, true}},          {"EnumArr", {ValueType::kEnum, true}},
      {"DoubleArr", {ValueType::kDouble, true}},    {"Double3Arr", {ValueType::kDouble3, true}},
      {"QuatArr", {ValueType::kQuat, true}},        {"MatrixArr", {ValueType::kMatrix, true}},
      {"StringArr", {ValueType::kString, true}},
  };
  return all;
}
inline void compute_nothing(ComputeContext&) {}

inline void add_type_or_die(Registry& registry, NodeTypeSpec spec) {
  const std::string name = spec.name;
  Status s = registry.add(std::move(spec));
  if (!s) {
    std::fprintf(stderr, "test node type '%s' failed to register: %s\n", name.c_str(), s.message().c_str());
    std::abort();
  }
}

// The registry of the test types above, shared by every test.
inline std::shared_ptr<const Registry> test_registry() {
  static const std::shared_ptr<const Registry> registry = [] {
    auto r = std::make_shared<Registry>();
    {
      NodeTypeSpec s;
      s.name = "add";
      s.attrs = {in_spec("a", kDoubleT, {"sum"}), in_spec("b", kDoubleT, {"sum"}), out_spec("sum", kDoubleT),
                 out_spec("count", kIntT)};
      s.compute = compute_add;
      add_type_or_die(*r, std::move(s));
    }
    {
      NodeTypeSpec s;
      s.name = "split";
      s.attrs = {in_spec("x", kDoubleT, {"outX"}), in_spec("y", kDoubleT, {"outY"}),
                 out_spec("outX", kDoubleT), out_spec("outY", kDoubleT), out_spec("count", kIntT)};
      s.compute = compute_split;
      add_type_or_die(*r, std::move(s));
    }
    {
      NodeTypeSpec s;
      s.name = "gather";
      s.attrs = {in_spec("values", kDoubleArrayT, {"total", "echo"}),
                 in_spec("scale", kDoubleT, {"echo"}, 1.0), out_spec("total", kDoubleT),
                 out_spec("echo", kDoubleArrayT), out_spec("count", kIntT)};
      s.compute = compute_gather;
      add_type_or_die(*r, std::move(s));
    }
    {
      NodeTypeSpec s;
      s.name = "clock";
      s.attrs = {in_spec("gain", kDoubleT, {"out"}, 1.0), out_spec("out", kDoubleT), out_spec("count", kIntT)};
      s.compute = compute_clock;
      s.time_dependent = true;
      add_type_or_die(*r, std::move(s));
    }
    {
      NodeTypeSpec s;
      s.name = "xf";
      s.attrs = {in_spec("parentMatrix", kMatrixT, {"world"}), in_spec("local", kMatrixT, {"world"}),
                 out_spec("world", kMatrixT), out_spec("count", kIntT)};
      s.compute = compute_xf;
      s.parent_input = "parentMatrix";
      s.world_output = "world";
      add_type_or_die(*r, std::move(s));
    }
    {
      NodeTypeSpec s;
      s.name = "versioned";
      s.attrs = {in_spec("a", kDoubleT, {"aVersion", "builds"}), out_spec("aVersion", kIntT),
                 out_spec("builds", kIntT), out_spec("count", kIntT)};
      s.compute = compute_versioned;
      add_type_or_die(*r, std::move(s));
    }
    {
      NodeTypeSpec s;
      s.name = "kinds";
      for (const Kind& k : kinds()) {
        AttrSpec in = in_spec(std::string("in") + k.suffix, k.type);
        if (k.type.value == ValueType::kEnum) in.enum_names = {"red", "green", "blue"};
        s.attrs.push_back(std::move(in));
      }
      for (const Kind& k : kinds()) {
        AttrSpec out = out_spec(std::string("out") + k.suffix, k.type);
        if (k.type.value == ValueType::kEnum) out.enum_names = {"red", "green", "blue"};
        s.attrs.push_back(std::move(out));
      }
      s.compute = compute_nothing;
      add_type_or_die(*r, std::move(s));
    }
    return std::shared_ptr<const Registry>(std::move(r));
  }();
  return registry;
}

// ---- helpers -----------------------------------------------------------------

// Status as a gtest assertion, so that a failed setup step prints its reason.
inline ::testing::AssertionResult succeeded(const Status& status) {
  if (status.is_ok()) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "failed (" << error_code_name(status.code()) << "): " << status.message();
}

// prefix + i, written so that GCC 12's -Wrestrict false positive on
// `"literal" + std::to_string(i)` (GCC bug 105329) stays quiet.
inline std::string numbered(std::string_view prefix, long i) {
  std::string s(prefix);
  s += std::to_string(i);
  return s;
}

// Creates a node and fails the test (with the reason) if the graph refuses.
inline NodeId make(Graph& graph, std::string_view type, std::string_view name) {
  Result<NodeId> id = graph.create_node(type, name);
  EXPECT_TRUE(id.is_ok()) << "creating " << type << " '" << name << "' should succeed: " << id.status().message();
  return id.is_ok() ? *id : NodeId{};
}

// node.attr[element] by attribute name; fails the test if there is none.
inline Plug plug(const Graph& graph, NodeId node, std::string_view attr, std::int32_t element = -1) {
  Result<Plug> p = graph.plug_find(node, attr, element);
  EXPECT_TRUE(p.is_ok()) << "plug " << attr << " should exist: " << p.status().message();
  return p.is_ok() ? *p : Plug{};
}

inline double eval_double(Graph& graph, NodeId node, std::string_view attr) {
  Result<Value> v = graph.evaluate(plug(graph, node, attr));
  EXPECT_TRUE(v.is_ok()) << v.status().message();
  return v.is_ok() && std::holds_alternative<double>(*v) ? std::get<double>(*v) : -12345.0;
}

// Per-node compute count (the "count" output), read without evaluating.
inline std::int64_t computes(const Graph& graph, NodeId node) {
  const Node* n = graph.node(node);
  if (!n) return -1;
  AttrIndex a = n->type().attr_find("count");
  return a == kNoAttr ? -1 : std::get<std::int64_t>(n->value(a));
}

// Exact text of a value: doubles as the hex of their bits, so that two texts
// are equal only when the values are identical bit for bit.
inline void exact_double(std::string& out, double d) {
  char buffer[24];
  std::snprintf(buffer, sizeof buffer, "%016llx", static_cast<unsigned long long>(std::bit_cast<std::uint64_t>(d)));
  out += buffer;
  out += ' ';
}
template <typename T>
struct IsStdVector : std::false_type {};
template <typename E>
struct IsStdVector<std::vector<E>> : std::true_type {};

inline std::string exact_text(const Value& value) {
  std::string out;
  auto doubles = [&](const double* d, int n) {
    out += '(';
    for (int i = 0; i < n; ++i) exact_double(out, d[i]);
    out += ')';
  };
  auto one = [&](const auto& v) {
    using T = std::decay_t<decltype(v)>;
    if constexpr (std::is_same_v<T, bool>) out += v ? "true " : "false ";
    else if constexpr (std::is_same_v<T, std::int64_t>) out += std::to_string(v) + ' ';
    else if constexpr (std::is_same_v<T, double>) exact_double(out, v);
    else if constexpr (std::is_same_v<T, Vec3>) doubles(v.data(), 3);
    else if constexpr (std::is_same_v<T, Quat>) doubles(v.coeffs().data(), 4);
    else if constexpr (std::is_same_v<T, Mat4>) doubles(v.data(), 16);
    else if constexpr (std::is_same_v<T, std::string>) out += std::to_string(v.size()) + ":" + v + ' ';
  };
  std::visit(
      [&](const auto& v) {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, std::monostate>) {
          out += "message";
        } else if constexpr (std::is_same_v<T, std::vector<bool>>) {
          out += "[";
          for (bool b : v) one(b);
          out += "]";
        } else if constexpr (IsStdVector<T>::value) {
          out += "[";
          for (const auto& e : v) one(e);
          out += "]";
        } else {
          one(v);
        }
      },
      value);
  return out;
}

inline std::string plug_text(const Graph& graph, const Plug& p) {
  const Node* n = graph.node(p.node);
  std::string text = n ? n->uuid().str() : std::string("<stale>");
  text += "." + (n ? n->type().attr(p.attr).name : std::to_string(p.attr));
  if (p.element >= 0) text += "[" + std::to_string(p.element) + "]";
  return text;
}

// A canonical listing of everything the user edits, in Graph::nodes() order:
// uuid, name, type, every input value (exactly) except inputs fed by a
// whole-attribute connection (their value is whatever the source held when
// last pulled), tags, then Graph::connections(). Evaluates the graph first so
// that connected elements of arrays hold fresh values.
inline std::string canonical_dump(Graph& graph) {
  graph.evaluate_all(Execution::kSerial);
  std::string out;
  for (NodeId id : graph.nodes()) {
    const Node& n = *graph.node(id);
    out += "node " + n.uuid().str() + " '" + n.name() + "' " + n.type().name() + "\n";
    for (AttrIndex a = 0; a < n.type().attr_count(); ++a) {
      if (!n.type().is_input(a)) continue;
      std::optional<Plug> src = graph.source(Plug{id, a, -1});
      out += "  " + n.type().attr(a).name + " = ";
      out += src ? "<connected>" : exact_text(n.value(a));
      out += "\n";
    }
    for (const auto& [key, value] : n.tags()) out += "  tag " + key + " = " + value + "\n";
  }
  for (const Connection& c : graph.connections()) {
    out += "connect " + plug_text(graph, c.src) + " -> " + plug_text(graph, c.dst) + "\n";
  }
  return out;
}

}  // namespace rigel::graph::testing
