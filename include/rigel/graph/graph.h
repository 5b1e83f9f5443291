#pragma once
// The dependency graph: nodes with typed attributes, connections between
// plugs, dirty propagation, pull evaluation, a compiled parallel schedule,
// observers and undoable transactions. It replaces the parts of Maya's DG
// that the seed systems stand on.

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <typeinfo>
#include <unordered_map>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/graph/node_type.h"
#include "rigel/graph/uuid.h"
#include "rigel/graph/value.h"

namespace rigel::graph {

// A handle to a node in one Graph. A deleted node's handle goes stale (its
// generation no longer matches) and never aliases a later node.
struct NodeId {
  std::uint32_t index = 0xffffffffu;
  std::uint32_t generation = 0;
  bool is_valid() const { return index != 0xffffffffu; }
  friend bool operator==(const NodeId&, const NodeId&) = default;
};

// node.attr, node.attr[element], or one component of a double3 attribute
// (node.translateX: Maya's child attributes, so a scalar curve or driven key
// can feed one channel).
struct Plug {
  NodeId node;
  AttrIndex attr = kNoAttr;
  std::int32_t element = -1;   // -1: the whole attribute
  std::int8_t component = -1;  // -1: all; 0, 1, 2: x, y, z of a scalar double3
  friend bool operator==(const Plug&, const Plug&) = default;
};

struct Connection {
  Plug src;
  Plug dst;
};

class Graph;

// What a node's compute derives from its inputs and keeps between
// evaluations, such as a skin's compiled influences in float: owned by the
// node (it goes with it), built and checked by the compute, which compares
// the versions of the inputs it was built from (ComputeContext::version)
// with the current ones. A compute only touches its own node's cache, so
// nodes still compute in parallel.
class NodeCache {
 public:
  virtual ~NodeCache() = default;
};

class Node {
 public:
  NodeId id() const { return id_; }
  const Uuid& uuid() const { return uuid_; }
  const std::string& name() const { return name_; }
  const NodeType& type() const { return *type_; }
  // The stored value: for inputs what was set or last pulled, for outputs
  // what compute last wrote. Use Graph::evaluate() for an up-to-date value.
  const Value& value(AttrIndex attr) const { return values_[attr]; }
  bool is_dirty(AttrIndex attr) const { return dirty_[attr] != 0; }
  const std::map<std::string, std::string>& tags() const { return tags_; }
  // nullptr when the tag is not set.
  const std::string* tag_find(const std::string& key) const;
  // Position in creation order (kept across undo/redo); files list nodes in it.
  std::uint64_t order() const { return order_; }
  // Connections into and out of this node.
  std::span<const Connection> inputs() const { return inputs_; }
  std::span<const Connection> outputs() const { return outputs_; }

 private:
  friend class Graph;
  friend class ComputeContext;
  NodeId id_;
  Uuid uuid_;
  std::string name_;
  const NodeType* type_ = nullptr;
  std::vector<Value> values_;
  std::vector<std::uint8_t> dirty_;
  // Per attribute: the node's write clock when the value was last written
  // by a set, an undo/redo or a connection's refresh (0: the default).
  std::vector<std::uint64_t> versions_;
  std::uint64_t clock_ = 0;
  std::unique_ptr<NodeCache> cache_;
  std::map<std::string, std::string> tags_;
  std::uint64_t order_ = 0;
  std::vector<Connection> inputs_;
  std::vector<Connection> outputs_;
  std::uint64_t visit_ = 0;  // traversal mark (Graph::visit_epoch_)
  bool queued_ = false;      // in Graph::dirty_nodes_: some attribute is dirty
};

// What a compute function sees: its node's inputs (already pulled) and
// outputs to write. Only touches its own node, so nodes compute in parallel.
class ComputeContext {
 public:
  ComputeContext(Node& node, double time) : node_(node), time_(time) {}
  const Node& node() const { return node_; }
  double time() const { return time_; }
  const Value& input(AttrIndex attr) const { return node_.values_[attr]; }
  template <typename T>
  const T& get(AttrIndex attr) const { return std::get<T>(node_.values_[attr]); }
  template <typename T>
  void set(AttrIndex attr, T&& value) { node_.values_[attr] = std::forward<T>(value); }
  Value& output(AttrIndex attr) { return node_.values_[attr]; }
  // Changes whenever the input's value is written (set, undo, redo, or
  // refreshed from its connection); equal versions mean the same value.
  std::uint64_t version(AttrIndex attr) const { return node_.versions_[attr]; }
  // The node's cache as a T, made (default-constructed) on first use.
  template <typename T>
  T& cache() {
    // The exact type, compared by typeid: a cheaper test than dynamic_cast,
    // on every compute of every node that keeps a cache.
    NodeCache* now = node_.cache_.get();
    T* held = now && typeid(*now) == typeid(T) ? static_cast<T*>(now) : nullptr;
    if (!held) {
      auto made = std::make_unique<T>();
      held = made.get();
      node_.cache_ = std::move(made);
    }
    return *held;
  }

 private:
  Node& node_;
  double time_;
};

// Notified after each change. Observers must not edit the graph from a
// callback; they may read it.
class Observer {
 public:
  virtual ~Observer() = default;
  virtual void node_added(const Graph&, NodeId) {}
  // Called before the node goes away, so it can still be read.
  virtual void node_removed(const Graph&, NodeId) {}
  virtual void node_renamed(const Graph&, NodeId, const std::string& /*old_name*/) {}
  virtual void attribute_changed(const Graph&, const Plug&) {}
  // Called by set_value (not by undo/redo) just before attribute_changed,
  // with the attribute's whole value before the set (recorders keep it).
  virtual void attribute_set(const Graph&, const Plug&, const Value& /*before*/) {}
  virtual void connection_made(const Graph&, const Connection&) {}
  virtual void connection_broken(const Graph&, const Connection&) {}
  virtual void tag_changed(const Graph&, NodeId, const std::string& /*key*/) {}
  virtual void selection_changed(const Graph&) {}
  virtual void time_changed(const Graph&) {}
};

enum class Execution { kSerial, kParallel };

// How evaluate_all() runs the dirty nodes. kInterpreted refreshes each
// node's inputs through its connections (variants copied, parts resolved
// per plug) and calls its compute. kCompiled runs a program made from the
// schedule on each topology change: one step per node in schedule order,
// its input refreshes resolved into typed copies between the values'
// storage (a double, a double3, one component, a matrix), no connection
// walk, lookup or variant dispatch per frame. Both run the same computes
// in the same order and give bit-identical values; the compiled one is
// the default, the interpreted one the reference it is tested against.
enum class Evaluation { kInterpreted, kCompiled };
// "interpreted" / "compiled", and back (an error naming the choices).
const char* evaluation_name(Evaluation evaluation);
Result<Evaluation> evaluation_from_name(std::string_view name);

class Graph {
 public:
  explicit Graph(std::shared_ptr<const Registry> registry);
  ~Graph();
  Graph(const Graph&) = delete;
  Graph& operator=(const Graph&) = delete;

  const Registry& registry() const { return *registry_; }

  // ---- nodes ---------------------------------------------------------------
  // Creates a node. A name already taken gets a numeric suffix ("arm" ->
  // "arm1"); an empty name becomes the type name. `uuid` nil means generate.
  Result<NodeId> create_node(std::string_view type, std::string_view name, Uuid uuid = Uuid());
  // Deletes a node after breaking its connections; its children become roots.
  Status delete_node(NodeId node);
  // Fails if the name is taken by another node or is not a valid name.
  Status rename(NodeId node, std::string_view name);
  // nullptr for a stale id.
  const Node* node(NodeId id) const;
  // Invalid NodeId when no node has that name / uuid.
  NodeId find(std::string_view name) const;
  NodeId find(const Uuid& uuid) const;
  // Every node, in creation order.
  std::vector<NodeId> nodes() const;
  std::size_t node_count() const { return by_uuid_.size(); }
  // Names must be non-empty, printable, without whitespace, '[' or ']'.
  static bool is_valid_name(std::string_view name);

  // ---- plugs ---------------------------------------------------------------
  // Parses "node.attr", "node.attr[3]" or "node.attrX" (a component of a
  // double3 attribute, X/Y/Z appended to its name). Node names may contain dots.
  Result<Plug> plug_find(std::string_view path) const;
  Result<Plug> plug_find(NodeId node, std::string_view attr, std::int32_t element = -1) const;
  std::string plug_name(const Plug& plug) const;
  // The declared type of what flows through the plug (an element is scalar,
  // a component is a double).
  AttrType plug_type(const Plug& plug) const;

  // ---- values --------------------------------------------------------------
  // Sets an unconnected input (or an element of an array input). The value
  // must have the plug's type; an enum accepts its index.
  Status set_value(const Plug& plug, Value value);
  // Pulls: evaluates whatever the plug depends on that is dirty.
  Result<Value> evaluate(const Plug& plug);
  // Fast path for callers that know the plug is valid.
  const Value& evaluate(NodeId node, AttrIndex attr);

  // ---- connections ---------------------------------------------------------
  // src may be any attribute, dst must be an input. Types must match (an
  // element of an array matches the scalar type; int and enum match). A
  // destination has one source; a connection that would close a cycle is
  // refused with a message naming the nodes on the cycle.
  Status connect(const Plug& src, const Plug& dst);
  Status disconnect(const Plug& src, const Plug& dst);
  // Breaks the connection into exactly `dst` (a whole attribute, or one
  // element); ok if nothing feeds it. Element connections into an array are
  // separate plugs: disconnect them by element.
  Status disconnect_input(const Plug& dst);
  std::optional<Plug> source(const Plug& dst) const;
  // Every connection, sorted by destination (node order, attr, element).
  std::vector<Connection> connections() const;

  // ---- hierarchy -----------------------------------------------------------
  // Makes `parent` (invalid NodeId: none) the parent of `child`: connects
  // parent's world output to child's parent input. Refuses cycles.
  Status set_parent(NodeId child, NodeId parent);
  // Invalid when `child` has no parent.
  NodeId parent(NodeId child) const;
  // Children in creation order.
  std::vector<NodeId> children(NodeId parent) const;

  // ---- tags ----------------------------------------------------------------
  Status set_tag(NodeId node, const std::string& key, const std::string& value);
  Status remove_tag(NodeId node, const std::string& key);

  // ---- time and selection (not undoable) -----------------------------------
  double time() const { return time_; }  // seconds
  void set_time(double seconds);
  double fps() const { return fps_; }
  Status set_fps(double fps);
  const std::vector<NodeId>& selection() const { return selection_; }
  // Stale ids are dropped.
  void select(std::vector<NodeId> nodes);

  // ---- evaluation ----------------------------------------------------------
  // Evaluates every dirty node on the compiled schedule. Serial and parallel
  // give bit-identical results.
  void evaluate_all(Execution execution = Execution::kParallel);
  // Bumped on every node or connection change; schedules key on it.
  std::uint64_t topology_generation() const { return topology_generation_; }
  // Number of levels and nodes of the compiled schedule (compiles if needed).
  std::size_t schedule_level_count();
  // In the compiled evaluation, makes its program for the current topology
  // now (evaluate_all() makes it when it runs; a pull never does, but uses
  // it while the topology is unchanged: call this before many pulls).
  // Nothing when it is current or the evaluation is interpreted.
  void compile();
  // The evaluation evaluate_all() and pulls use (kCompiled by default; the
  // interpreted one is the reference it is tested against). Not an edit:
  // not undoable, not saved; results are the same either way.
  void set_evaluation(Evaluation evaluation) { evaluation_ = evaluation; }
  Evaluation evaluation() const { return evaluation_; }

  // ---- undo ----------------------------------------------------------------
  // Groups edits into one undo step; nests (the outermost commit closes it).
  // A non-zero `merge_key` (from new_merge_key(), taken from the outermost
  // transaction) makes an interactive gesture one undo step: when the step
  // on top of the undo stack was committed with the same key and the new
  // one holds only value sets, the new edits merge into it (each plug keeps
  // its first `before` and takes the latest `after`; sets that followed a
  // create, connect or rename stay after it), so a drag of a thousand
  // events undoes at once and costs no memory per event.
  void begin_transaction(std::string label, std::uint64_t merge_key = 0);
  // A key no other gesture has used (thread-safe).
  static std::uint64_t new_merge_key();
  void commit_transaction();
  // Undoes the edits since the innermost open begin_transaction and closes it.
  void rollback_transaction();
  bool in_transaction() const { return !open_.empty(); }
  bool can_undo() const { return !undo_stack_.empty(); }
  bool can_redo() const { return !redo_stack_.empty(); }
  // Label of the step undo()/redo() would apply; empty when none.
  std::string undo_label() const;
  std::string redo_label() const;
  // Return false when there is nothing to undo/redo or a transaction is open.
  bool undo();
  bool redo();
  // Forgets all undo and redo steps (after loading a file, say).
  void clear_history();
  // Most undo steps kept; the oldest go first. Default kDefaultUndoLimit.
  void set_undo_limit(std::size_t steps);
  static constexpr std::size_t kDefaultUndoLimit = 10000;
  std::size_t undo_count() const { return undo_stack_.size(); }

  // ---- observers -----------------------------------------------------------
  void add_observer(Observer* observer);
  void remove_observer(Observer* observer);

 private:
  struct Edit;
  struct Step;
  struct Schedule;
  struct Program;
  Node* node_mut(NodeId id);
  Result<NodeId> create_node_impl(const NodeType& type, std::string name, Uuid uuid, std::uint64_t order);
  Status delete_node_impl(NodeId id);
  Status connect_impl(const Plug& src, const Plug& dst);
  void disconnect_impl(const Plug& src, const Plug& dst);
  Status check_connection(const Plug& src, const Plug& dst) const;
  std::string unique_name(std::string_view wanted) const;
  void record(Edit edit);
  void apply(const Edit& edit, bool forward);
  void dirty_downstream(NodeId node, AttrIndex attr);
  void dirty_for_time();
  void update_node(Node& node);
  void queue(Node& node);
  void push_undo(std::unique_ptr<Step> step);
  void pull(NodeId node);
  Value plug_value(const Plug& plug) const;
  void topology_changed();
  const Schedule& schedule();
  const Program& program();
  void run_step(const Program& program, std::uint32_t step);
  template <typename Fn>
  void notify(Fn&& fn);

  std::shared_ptr<const Registry> registry_;
  std::vector<std::unique_ptr<Node>> slots_;
  std::vector<std::uint32_t> generations_;
  std::vector<std::uint32_t> free_slots_;
  std::unordered_map<std::string, NodeId> by_name_;
  std::unordered_map<Uuid, NodeId, UuidHash> by_uuid_;
  std::vector<NodeId> time_dependent_;
  std::uint64_t next_order_ = 0;
  std::uint64_t topology_generation_ = 0;
  std::unique_ptr<Schedule> schedule_;
  std::unique_ptr<Program> program_;
  Evaluation evaluation_ = Evaluation::kCompiled;
  double time_ = 0.0;
  double fps_ = 24.0;
  std::vector<NodeId> selection_;
  std::vector<Observer*> observers_;
  // Undo: open transactions hold the index of their first edit in `pending_`.
  std::vector<std::unique_ptr<Step>> undo_stack_;
  std::vector<std::unique_ptr<Step>> redo_stack_;
  std::unique_ptr<Step> pending_;
  std::unique_ptr<Step> spare_;
  std::size_t last_step_edits_ = 0;
  std::vector<std::pair<Node*, AttrIndex>> dirty_work_;  // dirty_downstream's worklist
  // Every plug a time change dirties (the outputs of time-dependent nodes
  // but their time-invariant ones, and all downstream of them), listed once
  // per topology generation: a frame change marks them in one flat pass
  // instead of walking the graph's connections.
  std::vector<std::pair<Node*, AttrIndex>> time_closure_;
  std::uint64_t time_closure_generation_ = ~std::uint64_t{0};
  std::vector<std::size_t> open_;
  bool replaying_ = false;
  std::uint64_t visit_epoch_ = 0;
  // Nodes with a dirty attribute, so evaluate_all() visits only those. May
  // hold stale or clean entries (skipped); compacted when it grows.
  std::vector<NodeId> dirty_nodes_;
  std::size_t undo_limit_ = kDefaultUndoLimit;
};

// Opens a transaction for its lifetime (commits in the destructor unless
// rolled back).
class Transaction {
 public:
  Transaction(Graph& graph, std::string label, std::uint64_t merge_key = 0) : graph_(graph) {
    graph_.begin_transaction(std::move(label), merge_key);
  }
  ~Transaction() {
    if (open_) graph_.commit_transaction();
  }
  Transaction(const Transaction&) = delete;
  Transaction& operator=(const Transaction&) = delete;
  void rollback() {
    if (open_) graph_.rollback_transaction();
    open_ = false;
  }

 private:
  Graph& graph_;
  bool open_ = true;
};

}  // namespace rigel::graph
