// Private to rigel_graph: what the files implementing Graph share. The
// undo records, the compiled schedule and the observer fan-out are declared
// in graph.h as incomplete private types; they are defined here.
#pragma once

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdint>
#include <map>
#include <span>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <unordered_map>
#include <vector>

#include "rigel/graph/graph.h"

namespace rigel::graph {

// Element indices above this are refused: they would allocate huge arrays.
inline constexpr std::int32_t kMaxElement = 1 << 20;

// Two plugs of one attribute that share data: whole vs element or
// component, or the same element/component.
inline bool overlaps(const Plug& a, const Plug& b) {
  return a.node == b.node && a.attr == b.attr && (a.element < 0 || b.element < 0 || a.element == b.element) &&
         (a.component < 0 || b.component < 0 || a.component == b.component);
}

// Writes `part` into the attribute value `whole` at the plug's element or
// component (or replaces it for a whole plug).
inline void write_part(Value& whole, AttrType type, const Plug& plug, const Value& part) {
  if (plug.component >= 0) std::get<Vec3>(whole)[plug.component] = std::get<double>(part);
  else if (plug.element >= 0) array_set_element(whole, type, static_cast<std::size_t>(plug.element), part);
  else whole = part;
}

// An int fed into an enum attribute (or elements of an enum array) kept
// within the enum's names, as set_value does.
inline void clamp_enum(Value& v, const AttrSpec& spec) {
  const auto top = static_cast<std::int64_t>(spec.enum_names.size()) - 1;
  if (auto* one = std::get_if<std::int64_t>(&v)) *one = std::clamp<std::int64_t>(*one, 0, top);
  else if (auto* many = std::get_if<std::vector<std::int64_t>>(&v))
    for (std::int64_t& e : *many) e = std::clamp<std::int64_t>(e, 0, top);
}

// A node by UUID, so that undo/redo survive the node being deleted and
// recreated (NodeIds change; UUIDs do not).
struct PlugRef {
  Uuid node;
  AttrIndex attr = kNoAttr;
  std::int32_t element = -1;
  std::int8_t component = -1;
};

struct NodeSnapshot {
  Uuid uuid;
  const NodeType* type = nullptr;
  std::string name;
  std::vector<Value> values;
  std::map<std::string, std::string> tags;
  std::uint64_t order = 0;
};

// Value sets are most edits (an interactive drag writes hundreds per event),
// so an Edit is kept small and what only node, rename and tag edits need
// lives behind a pointer.
struct EditExtra {
  NodeSnapshot snapshot;                               // create, delete
  std::string key;                                     // tag key
  std::optional<std::string> text_before, text_after;  // rename (names), tag (values)
};

struct Graph::Edit {
  enum class Kind { kCreate, kDelete, kConnect, kDisconnect, kSet, kRename, kTag };
  Kind kind = Kind::kSet;
  PlugRef src, dst;     // connect, disconnect; dst is the plug for set
  Value before, after;  // set: whole attribute; connect: dst before; disconnect: dst after
  std::unique_ptr<EditExtra> extra;
  EditExtra& x() {
    if (!extra) extra = std::make_unique<EditExtra>();
    return *extra;
  }
  const EditExtra& x() const { return *extra; }
};
static_assert(std::is_nothrow_move_constructible_v<Value>, "edit vectors must grow by moving");

struct Graph::Step {
  std::string label;
  std::vector<Edit> edits;
  std::uint64_t merge_key = 0;
  // Merging steps only: where each plug's kSet edit is, built on first merge.
  struct PlugKey {
    Uuid node;
    AttrIndex attr;
    bool operator==(const PlugKey&) const = default;
  };
  struct PlugKeyHash {
    std::size_t operator()(const PlugKey& k) const { return UuidHash{}(k.node) * 31 + k.attr; }
  };
  std::unordered_map<PlugKey, std::size_t, PlugKeyHash> set_at;
  // Merging folds only into the sets after the last other edit (a later
  // set must not move before a create or connect it followed).
  bool indexed = false;
  bool only_sets() const {
    return std::all_of(edits.begin(), edits.end(), [](const Edit& e) { return e.kind == Edit::Kind::kSet; });
  }
};

// An input connection of a node with what refreshing it needs resolved: the
// source node, whether the whole value is copied, whether the destination
// is an enum to clamp.
struct ScheduledInput {
  const Node* src = nullptr;
  const Connection* connection = nullptr;  // into the destination's inputs_
  AttrIndex src_attr = 0;
  AttrIndex dst_attr = 0;
  bool whole = true;  // no element or component on either side: copy the value
  bool enum_dst = false;
};

// `c`, an input connection of `dst`, read from `src`.
inline ScheduledInput resolve_input(const Node& dst, const Node& src, const Connection& c) {
  ScheduledInput in;
  in.src = &src;
  in.connection = &c;
  in.src_attr = c.src.attr;
  in.dst_attr = c.dst.attr;
  in.whole = c.dst.element < 0 && c.src.element < 0 && c.dst.component < 0 && c.src.component < 0;
  in.enum_dst = dst.type().attr(c.dst.attr).type.value == ValueType::kEnum;
  return in;
}

// The compiled schedule: nodes grouped by connected component (nodes joined
// by connections either way; two components never read each other, such as
// two characters), each component's nodes by level (a node's level is one
// more than its deepest source's, so nodes of one level of a component never
// read each other), slot order within a level. Components run as
// parallel tasks, wide levels of a large component in parallel too, and a
// component's nodes run together, while its values are in cache.
struct Graph::Schedule {
  std::uint64_t generation = ~std::uint64_t{0};
  std::vector<NodeId> order;              // by component, then level, then slot
  std::size_t level_count = 0;            // the deepest level + 1
  std::vector<std::uint32_t> position;    // node slot index -> index in order
  std::vector<std::uint32_t> level;       // index in order -> level
  std::vector<std::uint32_t> component;   // index in order -> component, increasing
  // Every node's input connections, flattened in schedule order (see
  // ScheduledInput): evaluation reads one contiguous array instead of each
  // node's connection vector, the source's slot and the attribute spec.
  std::vector<ScheduledInput> inputs;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> input_range;  // node slot index -> [begin, end) in inputs
};

// The compiled evaluation's program (Evaluation::kCompiled), made from the
// schedule for one topology generation: a step per node in schedule order
// (step k is the schedule's order[k]) and its input refreshes resolved into
// typed copies between the values' storage. A scalar value (double,
// double3, quaternion, matrix, int) lives inside its Value for the node's
// lifetime (a node's values never change alternative), so a copy holds
// pointers to it; arrays, strings and element plugs keep the interpreted
// refresh (kGeneric).
enum class ProgramCopy : std::uint8_t {
  kDouble,   // double -> double, either may be one component of a double3
  kDouble3,  // double3 -> double3
  kQuat,     // quaternion -> quaternion
  kMatrix,   // matrix -> matrix
  kInt,      // int or enum -> int or enum (clamped after, as interpreted)
  kBool,     // bool -> bool
  // A scalar into one element of an array (a constraint's target matrix, a
  // blend's weight): `dst` is the whole array value, `element` the index;
  // an element past the array's end takes the interpreted refresh (which
  // grows the array).
  kDoubleElement,
  kDouble3Element,
  kMatrixElement,
  kGeneric,  // the interpreted refresh of `input`
};

struct ProgramOp {
  ProgramCopy copy = ProgramCopy::kGeneric;
  AttrIndex dst_attr = 0;
  const void* src = nullptr;
  void* dst = nullptr;
  const ScheduledInput* input = nullptr;  // into Schedule::inputs
  std::int32_t element = -1;              // the k*Element copies
};

struct ProgramStep {
  Node* node = nullptr;
  ComputeFn compute = nullptr;
  std::uint32_t ops_begin = 0, ops_end = 0;
  bool enums = false;  // some input is an enum fed by a connection: clamp after refresh
  // The node's storage, for prefetching a step ahead of running it (the
  // node's vectors never change size, so their data stays put).
  const Value* values = nullptr;
  const std::uint8_t* dirty = nullptr;
  const std::uint64_t* versions = nullptr;
  const Connection* connections = nullptr;  // the node's output connections (dirty propagation)
  std::span<const AttrIndex> outputs;
};

struct Graph::Program {
  std::uint64_t generation = ~std::uint64_t{0};
  std::vector<ProgramStep> steps;
  std::vector<ProgramOp> ops;
  // Asks the memory system for what step `k` reads and writes (its node,
  // dirty flags, versions, refreshed inputs and outputs) while earlier
  // steps run: a large graph's nodes are spread over the heap, and their
  // cache misses, not their computes, are most of its evaluation.
  void prefetch(std::uint32_t k) const;
  // What dirty propagation reads of step `k`'s node: the node and, once the
  // step has run, its dirty flags and output connections.
  void prefetch_flags(std::size_t k) const;
  // Scratch for evaluate_all: schedule positions of the queued nodes.
  std::vector<std::uint8_t> marks;
  // Per step: resolved (its copies, on its first run), so a topology edit
  // costs a program that touches no node.
  std::unique_ptr<std::atomic<std::uint8_t>[]> ready;
  // The plugs a time change dirties (Graph::time_closure_) in schedule
  // order, made on the first time change of the program: marked in the
  // order the evaluation then runs them, each node's flags prefetched a few
  // entries ahead (the closure's own order is a graph walk's).
  struct TimeMark {
    Node* node = nullptr;
    std::uint8_t* dirty = nullptr;
    AttrIndex attr = 0;
  };
  std::vector<TimeMark> time_marks;
  bool time_marks_made = false;
};

template <typename Fn>
void Graph::notify(Fn&& fn) {
  if (observers_.empty()) return;
  // Observers may add or remove observers while notified: iterate a copy,
  // on the stack for the usual few (set_value notifies on every edit).
  constexpr std::size_t kInline = 8;
  if (observers_.size() <= kInline) {
    std::array<Observer*, kInline> copy{};
    const std::size_t n = observers_.size();
    std::copy(observers_.begin(), observers_.end(), copy.begin());
    for (std::size_t i = 0; i < n; ++i) fn(*copy[i]);
    return;
  }
  auto observers = observers_;
  for (Observer* o : observers) fn(*o);
}

}  // namespace rigel::graph
