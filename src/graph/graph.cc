// Over 800 lines: connections, evaluation, undo and observers split into
// their own files with issue 15 (listed there); no behaviour depends on it.
#include "rigel/graph/graph.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cctype>
#include <charconv>
#include <deque>
#include <unordered_map>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace rigel::graph {
namespace {

// Element indices above this are refused: they would allocate huge arrays.
constexpr std::int32_t kMaxElement = 1 << 20;
// Levels smaller than this run serially: spawning tasks costs more.
constexpr std::size_t kParallelMinLevel = 64;
constexpr std::size_t kParallelGrain = 32;

// Two plugs of one attribute that share data: whole vs element or
// component, or the same element/component.
bool overlaps(const Plug& a, const Plug& b) {
  return a.node == b.node && a.attr == b.attr && (a.element < 0 || b.element < 0 || a.element == b.element) &&
         (a.component < 0 || b.component < 0 || a.component == b.component);
}

// Writes `part` into the attribute value `whole` at the plug's element or
// component (or replaces it for a whole plug).
void write_part(Value& whole, AttrType type, const Plug& plug, const Value& part) {
  if (plug.component >= 0) std::get<Vec3>(whole)[plug.component] = std::get<double>(part);
  else if (plug.element >= 0) array_set_element(whole, type, static_cast<std::size_t>(plug.element), part);
  else whole = part;
}

constexpr char kComponentSuffix[] = {'X', 'Y', 'Z'};

bool types_compatible(AttrType a, AttrType b) {
  auto norm = [](AttrType t) {
    if (t.value == ValueType::kEnum) t.value = ValueType::kInt;
    return t;
  };
  return norm(a) == norm(b);
}

}  // namespace

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

struct Graph::Schedule {
  std::uint64_t generation = ~std::uint64_t{0};
  std::vector<NodeId> order;             // parents before children, grouped by level
  std::vector<std::size_t> level_begin;  // offsets into order, plus a final end
  std::vector<std::uint32_t> position;   // node slot index -> index in order
  std::vector<std::uint32_t> level;      // index in order -> level
};

Graph::Graph(std::shared_ptr<const Registry> registry) : registry_(std::move(registry)) {}
Graph::~Graph() = default;

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

// ---- nodes -----------------------------------------------------------------

const Node* Graph::node(NodeId id) const {
  if (id.index >= slots_.size() || generations_[id.index] != id.generation) return nullptr;
  return slots_[id.index].get();
}

Node* Graph::node_mut(NodeId id) { return const_cast<Node*>(node(id)); }

NodeId Graph::find(std::string_view name) const {
  auto it = by_name_.find(std::string(name));
  return it == by_name_.end() ? NodeId{} : it->second;
}

NodeId Graph::find(const Uuid& uuid) const {
  auto it = by_uuid_.find(uuid);
  return it == by_uuid_.end() ? NodeId{} : it->second;
}

std::vector<NodeId> Graph::nodes() const {
  std::vector<const Node*> live;
  live.reserve(by_uuid_.size());
  for (const auto& slot : slots_) {
    if (slot) live.push_back(slot.get());
  }
  std::sort(live.begin(), live.end(), [](const Node* a, const Node* b) { return a->order_ < b->order_; });
  std::vector<NodeId> ids;
  ids.reserve(live.size());
  for (const Node* n : live) ids.push_back(n->id_);
  return ids;
}

bool Graph::is_valid_name(std::string_view name) {
  if (name.empty() || name.size() > 1024 || !is_valid_utf8(name)) return false;
  for (char c : name) {
    auto u = static_cast<unsigned char>(c);
    if (u < 0x21 || u == 0x7f || c == '[' || c == ']') return false;
  }
  return true;
}

std::string Graph::unique_name(std::string_view wanted) const {
  std::string name(wanted);
  if (!by_name_.count(name)) return name;
  // Maya's rule: bump a trailing number, or append 1.
  std::size_t digits = name.size();
  while (digits > 0 && std::isdigit(static_cast<unsigned char>(name[digits - 1]))) --digits;
  std::string base = name.substr(0, digits);
  std::uint64_t n = 1;
  if (digits < name.size() && name.size() - digits < 18) n = std::stoull(name.substr(digits)) + 1;
  for (;; ++n) {
    std::string candidate = base + std::to_string(n);
    if (!by_name_.count(candidate)) return candidate;
  }
}

Result<NodeId> Graph::create_node(std::string_view type_name, std::string_view name, Uuid uuid) {
  const NodeType* type = registry_->find(type_name);
  if (!type) return error(ErrorCode::kNotFound, "unknown node type '" + std::string(type_name) + "'");
  std::string wanted = name.empty() ? type->name() : std::string(name);
  if (!is_valid_name(wanted))
    return error(ErrorCode::kInvalidArgument, "invalid node name '" + wanted + "': names are printable, without spaces or brackets");
  if (uuid.is_nil()) uuid = Uuid::generate();
  else if (by_uuid_.count(uuid)) return error(ErrorCode::kAlreadyExists, "a node with uuid " + uuid.str() + " already exists");
  Result<NodeId> id = create_node_impl(*type, unique_name(wanted), uuid, next_order_++);
  if (!id) return id;
  Edit edit;
  edit.kind = Edit::Kind::kCreate;
  const Node& n = *node(*id);
  edit.x().snapshot = NodeSnapshot{n.uuid_, n.type_, n.name_, n.values_, n.tags_, n.order_};
  record(std::move(edit));
  notify([&](Observer& o) { o.node_added(*this, *id); });
  return id;
}

Result<NodeId> Graph::create_node_impl(const NodeType& type, std::string name, Uuid uuid, std::uint64_t order) {
  std::uint32_t index;
  if (!free_slots_.empty()) {
    index = free_slots_.back();
    free_slots_.pop_back();
  } else {
    index = static_cast<std::uint32_t>(slots_.size());
    slots_.emplace_back();
    generations_.push_back(0);
  }
  auto n = std::make_unique<Node>();
  n->id_ = NodeId{index, generations_[index]};
  n->uuid_ = uuid;
  n->name_ = std::move(name);
  n->type_ = &type;
  n->order_ = order;
  n->values_.reserve(type.attr_count());
  n->dirty_.assign(type.attr_count(), 0);
  for (AttrIndex i = 0; i < type.attr_count(); ++i) n->values_.push_back(type.default_value(i));
  for (AttrIndex o : type.outputs()) n->dirty_[o] = 1;
  NodeId id = n->id_;
  by_name_.emplace(n->name_, id);
  by_uuid_.emplace(uuid, id);
  if (type.time_dependent()) time_dependent_.push_back(id);
  slots_[index] = std::move(n);
  if (!type.outputs().empty()) queue(*slots_[index]);
  next_order_ = std::max(next_order_, order + 1);
  topology_changed();
  return id;
}

Status Graph::delete_node(NodeId id) {
  Node* n = node_mut(id);
  if (!n) return error(ErrorCode::kNotFound, "delete: no such node (stale handle)");
  Transaction transaction(*this, "delete " + n->name_);
  // Children become roots; then every other connection is broken.
  for (NodeId child : children(id)) {
    if (Status s = set_parent(child, NodeId{}); !s) return s;
  }
  while (!n->inputs_.empty()) {
    Connection c = n->inputs_.back();
    if (Status s = disconnect(c.src, c.dst); !s) return s;
  }
  while (!n->outputs_.empty()) {
    Connection c = n->outputs_.back();
    if (Status s = disconnect(c.src, c.dst); !s) return s;
  }
  if (std::find(selection_.begin(), selection_.end(), id) != selection_.end()) {
    std::vector<NodeId> rest;
    for (NodeId s : selection_)
      if (!(s == id)) rest.push_back(s);
    select(std::move(rest));
  }
  notify([&](Observer& o) { o.node_removed(*this, id); });
  Edit edit;
  edit.kind = Edit::Kind::kDelete;
  edit.x().snapshot = NodeSnapshot{n->uuid_, n->type_, n->name_, n->values_, n->tags_, n->order_};
  record(std::move(edit));
  return delete_node_impl(id);
}

Status Graph::delete_node_impl(NodeId id) {
  Node* n = node_mut(id);
  assert(n && n->inputs_.empty() && n->outputs_.empty());
  by_name_.erase(n->name_);
  by_uuid_.erase(n->uuid_);
  if (n->type_->time_dependent()) std::erase(time_dependent_, id);
  slots_[id.index].reset();
  ++generations_[id.index];
  free_slots_.push_back(id.index);
  topology_changed();
  return Status::ok();
}

Status Graph::rename(NodeId id, std::string_view name) {
  Node* n = node_mut(id);
  if (!n) return error(ErrorCode::kNotFound, "rename: no such node (stale handle)");
  std::string wanted(name);
  if (!is_valid_name(wanted))
    return error(ErrorCode::kInvalidArgument, "invalid node name '" + wanted + "': names are printable, without spaces or brackets");
  if (wanted == n->name_) return Status::ok();
  if (by_name_.count(wanted)) return error(ErrorCode::kAlreadyExists, "cannot rename '" + n->name_ + "' to '" + wanted + "': the name is taken");
  std::string old = n->name_;
  by_name_.erase(old);
  n->name_ = wanted;
  by_name_.emplace(wanted, id);
  Edit edit;
  edit.kind = Edit::Kind::kRename;
  edit.dst.node = n->uuid_;
  edit.x().text_before = old;
  edit.x().text_after = wanted;
  record(std::move(edit));
  notify([&](Observer& o) { o.node_renamed(*this, id, old); });
  return Status::ok();
}

// ---- plugs -----------------------------------------------------------------

Result<Plug> Graph::plug_find(NodeId id, std::string_view attr_name, std::int32_t element) const {
  const Node* n = node(id);
  if (!n) return error(ErrorCode::kNotFound, "no such node (stale handle)");
  AttrIndex attr = n->type_->attr_find(attr_name);
  std::int8_t component = -1;
  if (attr == kNoAttr && attr_name.size() > 1) {
    // "translateX": a component of a scalar double3 attribute.
    for (std::int8_t k = 0; k < 3; ++k) {
      if (attr_name.back() != kComponentSuffix[k]) continue;
      AttrIndex base = n->type_->attr_find(attr_name.substr(0, attr_name.size() - 1));
      if (base != kNoAttr && n->type_->attr(base).type == AttrType{ValueType::kDouble3, false}) {
        attr = base;
        component = k;
      }
    }
  }
  if (attr == kNoAttr)
    return error(ErrorCode::kNotFound, "node '" + n->name_ + "' (" + n->type_->name() + ") has no attribute '" + std::string(attr_name) + "'");
  const AttrSpec& spec = n->type_->attr(attr);
  if (component >= 0 && element >= 0)
    return error(ErrorCode::kInvalidArgument, n->name_ + "." + std::string(attr_name) + " is not an array and takes no [index]");
  if (element >= 0 && !spec.type.array)
    return error(ErrorCode::kInvalidArgument, n->name_ + "." + spec.name + " is not an array and takes no [index]");
  if (element >= kMaxElement)
    return error(ErrorCode::kInvalidArgument, n->name_ + "." + spec.name + "[" + std::to_string(element) + "]: index too large");
  return Plug{id, attr, element, component};
}

Result<Plug> Graph::plug_find(std::string_view path) const {
  auto bad = [&] {
    return error(ErrorCode::kInvalidArgument, "bad plug '" + std::string(path) + "': expected node.attr or node.attr[index]");
  };
  std::size_t dot = path.rfind('.');
  if (dot == std::string_view::npos || dot == 0 || dot + 1 == path.size()) return bad();
  std::string_view node_name = path.substr(0, dot);
  std::string_view rest = path.substr(dot + 1);
  std::int32_t element = -1;
  if (std::size_t open = rest.find('['); open != std::string_view::npos) {
    if (rest.back() != ']' || open + 2 >= rest.size()) return bad();
    std::string_view digits = rest.substr(open + 1, rest.size() - open - 2);
    auto [ptr, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), element);
    if (ec != std::errc() || ptr != digits.data() + digits.size() || element < 0) return bad();
    rest = rest.substr(0, open);
  }
  NodeId id = find(node_name);
  if (!id.is_valid()) return error(ErrorCode::kNotFound, "no node named '" + std::string(node_name) + "'");
  return plug_find(id, rest, element);
}

std::string Graph::plug_name(const Plug& plug) const {
  const Node* n = node(plug.node);
  if (!n) return "<deleted>";
  std::string name = n->name_ + "." + (plug.attr < n->type_->attr_count() ? n->type_->attr(plug.attr).name : "?");
  if (plug.component >= 0 && plug.component < 3) name += kComponentSuffix[plug.component];
  if (plug.element >= 0) name += "[" + std::to_string(plug.element) + "]";
  return name;
}

AttrType Graph::plug_type(const Plug& plug) const {
  AttrType type = node(plug.node)->type_->attr(plug.attr).type;
  if (plug.element >= 0) type.array = false;
  if (plug.component >= 0) type = AttrType{ValueType::kDouble, false};
  return type;
}

Value Graph::plug_value(const Plug& plug) const {
  const Node& n = *node(plug.node);
  if (plug.component >= 0) return std::get<Vec3>(n.values_[plug.attr])[plug.component];
  if (plug.element < 0) return n.values_[plug.attr];
  return array_element(n.values_[plug.attr], n.type_->attr(plug.attr).type, static_cast<std::size_t>(plug.element));
}

// ---- values ----------------------------------------------------------------

Status Graph::set_value(const Plug& plug, Value value) {
  Node* n = node_mut(plug.node);
  if (!n) return error(ErrorCode::kNotFound, "set: no such node (stale handle)");
  if (plug.attr >= n->type_->attr_count()) return error(ErrorCode::kNotFound, "set: no such attribute on '" + n->name_ + "'");
  const AttrSpec& spec = n->type_->attr(plug.attr);
  auto where = [&] { return plug_name(plug); };  // built only for errors
  if (!(spec.flags & kInput)) return error(ErrorCode::kInvalidArgument, where() + " is an output; it cannot be set");
  if (plug.element >= 0 && !spec.type.array) return error(ErrorCode::kInvalidArgument, where() + ": not an array");
  if (plug.element >= kMaxElement) return error(ErrorCode::kInvalidArgument, where() + ": index too large");
  if (plug.component >= 3 || (plug.component >= 0 && spec.type != AttrType{ValueType::kDouble3, false}))
    return error(ErrorCode::kInvalidArgument, where() + ": components exist only on double3 attributes");
  for (const Connection& c : n->inputs_) {
    if (overlaps(c.dst, plug))
      return error(ErrorCode::kInvalidArgument, where() + " is connected from " + plug_name(c.src) + "; disconnect it first");
  }
  AttrType type = plug_type(plug);
  if (type.value == ValueType::kDouble && !type.array && std::holds_alternative<std::int64_t>(value))
    value = static_cast<double>(std::get<std::int64_t>(value));
  if (!value_has_type(value, type))
    return error(ErrorCode::kInvalidArgument, where() + " is a " + type_name(type) + "; got " + value_to_text(value));
  if (const auto* text = std::get_if<std::string>(&value); text && !is_valid_utf8(*text))
    return error(ErrorCode::kInvalidArgument, where() + ": strings must be UTF-8 text");
  if (const auto* texts = std::get_if<std::vector<std::string>>(&value)) {
    for (const std::string& t : *texts)
      if (!is_valid_utf8(t)) return error(ErrorCode::kInvalidArgument, where() + ": strings must be UTF-8 text");
  }
  if (type.value == ValueType::kEnum) {
    auto check = [&](std::int64_t v) { return v >= 0 && v < static_cast<std::int64_t>(spec.enum_names.size()); };
    bool ok = type.array ? std::all_of(std::get<std::vector<std::int64_t>>(value).begin(),
                                       std::get<std::vector<std::int64_t>>(value).end(), check)
                         : check(std::get<std::int64_t>(value));
    if (!ok) return error(ErrorCode::kInvalidArgument, where() + ": enum value out of range");
  }
  Value whole;
  if (plug.element >= 0 || plug.component >= 0) {
    whole = n->values_[plug.attr];
    write_part(whole, spec.type, plug, value);
  } else {
    whole = std::move(value);
  }
  if (values_identical(whole, n->values_[plug.attr])) return Status::ok();

  Edit edit;
  edit.kind = Edit::Kind::kSet;
  edit.dst = PlugRef{n->uuid_, plug.attr, -1};
  edit.before = std::move(n->values_[plug.attr]);
  n->values_[plug.attr] = whole;
  edit.after = std::move(whole);
  dirty_downstream(plug.node, plug.attr);
  if (!observers_.empty()) {
    const Plug whole_plug{plug.node, plug.attr, -1};
    notify([&](Observer& o) { o.attribute_set(*this, whole_plug, edit.before); });
  }
  record(std::move(edit));
  notify([&](Observer& o) { o.attribute_changed(*this, plug); });
  return Status::ok();
}

Result<Value> Graph::evaluate(const Plug& plug) {
  const Node* n = node(plug.node);
  if (!n) return error(ErrorCode::kNotFound, "evaluate: no such node (stale handle)");
  if (plug.attr >= n->type_->attr_count()) return error(ErrorCode::kNotFound, "evaluate: no such attribute on '" + n->name_ + "'");
  if (plug.element >= 0 && !n->type_->attr(plug.attr).type.array)
    return error(ErrorCode::kInvalidArgument, plug_name(plug) + ": not an array");
  if (plug.component >= 3 || (plug.component >= 0 && n->type_->attr(plug.attr).type != AttrType{ValueType::kDouble3, false}))
    return error(ErrorCode::kInvalidArgument, plug_name(plug) + ": components exist only on double3 attributes");
  evaluate(plug.node, plug.attr);
  return plug_value(plug);
}

const Value& Graph::evaluate(NodeId id, AttrIndex attr) {
  Node& n = *node_mut(id);
  if (n.dirty_[attr]) pull(id);
  return n.values_[attr];
}

// ---- dirty propagation and evaluation ----------------------------------------

void Graph::dirty_downstream(NodeId start, AttrIndex attr) {
  // Worklist rather than recursion: a 100,000-joint chain must not overflow
  // the stack. A plug already dirty stops the walk: everything downstream of
  // a dirty plug is dirty (evaluation cleans upstream first), so the cost is
  // proportional to what becomes dirty, not to the graph.
  // The worklist is kept between calls: interactive edits dirty a few
  // plugs each, thousands of times a second.
  std::vector<std::pair<Node*, AttrIndex>>& work = dirty_work_;
  work.clear();
  auto push_downstream = [&](Node& n, AttrIndex a) {
    for (AttrIndex o : n.type_->affected_outputs(a)) work.emplace_back(&n, o);
    for (const Connection& c : n.outputs_) {
      if (c.src.attr == a) work.emplace_back(slots_[c.dst.node.index].get(), c.dst.attr);
    }
  };
  push_downstream(*node_mut(start), attr);
  while (!work.empty()) {
    auto [n, a] = work.back();
    work.pop_back();
    if (n->dirty_[a]) continue;
    n->dirty_[a] = 1;
    queue(*n);
    push_downstream(*n, a);
  }
}

// A time change: every output of a time-dependent node but its
// time-invariant ones.
void Graph::dirty_outputs(Node& n) {
  for (AttrIndex o : n.type_->outputs()) {
    if (n.dirty_[o] || (n.type_->attr(o).flags & kTimeInvariant)) continue;
    n.dirty_[o] = 1;
    queue(n);
    dirty_downstream(n.id_, o);
  }
}

void Graph::update_node(Node& n) {
  // Refresh connected inputs that are dirty, then compute if an output is.
  for (const Connection& c : n.inputs_) {
    if (!n.dirty_[c.dst.attr]) continue;
    const Node& src = *slots_[c.src.node.index];
    Value& dst = n.values_[c.dst.attr];
    if (c.dst.element < 0 && c.src.element < 0 && c.dst.component < 0 && c.src.component < 0) {
      dst = src.values_[c.src.attr];
    } else {
      write_part(dst, n.type_->attr(c.dst.attr).type, c.dst, plug_value(c.src));
    }
  }
  for (const Connection& c : n.inputs_) {
    if (!n.dirty_[c.dst.attr]) continue;
    n.dirty_[c.dst.attr] = 0;
    // An int may feed an enum: keep the enum within its names, as set_value does.
    const AttrSpec& spec = n.type_->attr(c.dst.attr);
    if (spec.type.value == ValueType::kEnum) {
      const auto top = static_cast<std::int64_t>(spec.enum_names.size()) - 1;
      Value& v = n.values_[c.dst.attr];
      if (auto* one = std::get_if<std::int64_t>(&v)) *one = std::clamp<std::int64_t>(*one, 0, top);
      else if (auto* many = std::get_if<std::vector<std::int64_t>>(&v))
        for (std::int64_t& e : *many) e = std::clamp<std::int64_t>(e, 0, top);
    }
  }
  // Every attribute is clean after this: connected inputs were refreshed,
  // unconnected inputs are never dirty, and outputs are computed below.
  n.queued_ = false;
  bool compute = false;
  for (AttrIndex o : n.type_->outputs()) compute |= n.dirty_[o] != 0;
  if (!compute) return;
  ComputeContext context(n, time_);
  n.type_->compute()(context);
  for (AttrIndex o : n.type_->outputs()) n.dirty_[o] = 0;
}

void Graph::queue(Node& n) {
  if (n.queued_) return;
  n.queued_ = true;
  dirty_nodes_.push_back(n.id_);
  // Pulls clean nodes without taking them off the list; drop those entries
  // before the list outgrows the graph.
  if (dirty_nodes_.size() > 2 * by_uuid_.size() + 64) {
    std::erase_if(dirty_nodes_, [&](NodeId id) {
      const Node* m = node(id);
      return !m || !m->queued_;
    });
    // A node cleaned and dirtied again appears twice; keep the first.
    const std::uint64_t epoch = ++visit_epoch_;
    std::erase_if(dirty_nodes_, [&](NodeId id) {
      Node* m = slots_[id.index].get();
      if (m->visit_ == epoch) return true;
      m->visit_ = epoch;
      return false;
    });
  }
}

void Graph::pull(NodeId start) {
  // Post-order walk over the dirty part upstream of `start`, then update in
  // that order (sources before the nodes that read them).
  const std::uint64_t epoch = ++visit_epoch_;
  std::vector<Node*> order;
  std::vector<std::pair<Node*, std::size_t>> stack;
  Node* root = node_mut(start);
  root->visit_ = epoch;
  stack.emplace_back(root, 0);
  while (!stack.empty()) {
    auto& [n, next] = stack.back();
    if (next < n->inputs_.size()) {
      const Connection& c = n->inputs_[next++];
      if (!n->dirty_[c.dst.attr]) continue;
      Node* src = slots_[c.src.node.index].get();
      if (src->visit_ == epoch || !src->dirty_[c.src.attr]) continue;
      src->visit_ = epoch;
      stack.emplace_back(src, 0);
      continue;
    }
    order.push_back(n);
    stack.pop_back();
  }
  for (Node* n : order) update_node(*n);
}

const Graph::Schedule& Graph::schedule() {
  if (!schedule_) schedule_ = std::make_unique<Schedule>();
  Schedule& s = *schedule_;
  if (s.generation == topology_generation_) return s;
  // Kahn's algorithm by levels: a node's level is one more than its deepest
  // source, so nodes of one level never read each other and run in parallel.
  std::vector<NodeId> all = nodes();
  std::unordered_map<std::uint32_t, std::size_t> position;
  position.reserve(all.size());
  for (std::size_t i = 0; i < all.size(); ++i) position.emplace(all[i].index, i);
  std::vector<std::uint32_t> pending(all.size(), 0);
  std::vector<std::uint32_t> level(all.size(), 0);
  for (std::size_t i = 0; i < all.size(); ++i) pending[i] = static_cast<std::uint32_t>(node(all[i])->inputs_.size());
  std::deque<std::size_t> ready;
  for (std::size_t i = 0; i < all.size(); ++i)
    if (pending[i] == 0) ready.push_back(i);
  std::uint32_t max_level = 0;
  while (!ready.empty()) {
    std::size_t i = ready.front();
    ready.pop_front();
    max_level = std::max(max_level, level[i]);
    for (const Connection& c : node(all[i])->outputs_) {
      std::size_t j = position[c.dst.node.index];
      level[j] = std::max(level[j], level[i] + 1);
      if (--pending[j] == 0) ready.push_back(j);
    }
  }
  // Counting sort by level, creation order within a level.
  s.level_begin.assign(all.empty() ? 1 : max_level + 2, 0);
  for (std::size_t i = 0; i < all.size(); ++i) ++s.level_begin[level[i] + 1];
  for (std::size_t l = 1; l < s.level_begin.size(); ++l) s.level_begin[l] += s.level_begin[l - 1];
  s.order.assign(all.size(), NodeId{});
  std::vector<std::size_t> fill(s.level_begin.begin(), s.level_begin.end() - 1);
  s.position.assign(slots_.size(), 0);
  s.level.assign(all.size(), 0);
  for (std::size_t i = 0; i < all.size(); ++i) {
    std::size_t at = fill[level[i]]++;
    s.order[at] = all[i];
    s.position[all[i].index] = static_cast<std::uint32_t>(at);
    s.level[at] = level[i];
  }
  s.generation = topology_generation_;
  return s;
}

std::size_t Graph::schedule_level_count() { return schedule().level_begin.size() - 1; }

void Graph::evaluate_all(Execution execution) {
  if (dirty_nodes_.empty()) return;
  const Schedule& s = schedule();
  // Only queued nodes, in schedule order: an edit costs what it dirtied,
  // not the size of the graph.
  std::vector<std::uint32_t> work;
  if (dirty_nodes_.size() * 8 > s.order.size()) {
    for (std::size_t i = 0; i < s.order.size(); ++i) {
      if (slots_[s.order[i].index]->queued_) work.push_back(static_cast<std::uint32_t>(i));
    }
  } else {
    work.reserve(dirty_nodes_.size());
    for (NodeId id : dirty_nodes_) {
      const Node* n = node(id);
      if (n && n->queued_) work.push_back(s.position[id.index]);
    }
    std::sort(work.begin(), work.end());
    work.erase(std::unique(work.begin(), work.end()), work.end());
  }
  dirty_nodes_.clear();
  auto run = [&](std::size_t k) {
    Node& n = *slots_[s.order[work[k]].index];
    if (n.queued_) update_node(n);
  };
  // Queued nodes of one level never read each other: run a large level in parallel.
  for (std::size_t begin = 0; begin < work.size();) {
    std::size_t end = begin + 1;
    while (end < work.size() && s.level[work[end]] == s.level[work[begin]]) ++end;
    if (execution == Execution::kSerial || end - begin < kParallelMinLevel) {
      for (std::size_t k = begin; k < end; ++k) run(k);
    } else {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(begin, end, kParallelGrain),
                        [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t k = r.begin(); k != r.end(); ++k) run(k);
                        });
    }
    begin = end;
  }
}

void Graph::topology_changed() { ++topology_generation_; }

// ---- connections -----------------------------------------------------------

Status Graph::check_connection(const Plug& src, const Plug& dst) const {
  const Node* s = node(src.node);
  const Node* d = node(dst.node);
  if (!s || !d) return error(ErrorCode::kNotFound, "connect: no such node (stale handle)");
  if (src.attr >= s->type_->attr_count() || dst.attr >= d->type_->attr_count())
    return error(ErrorCode::kNotFound, "connect: no such attribute");
  for (const Plug* p : {&src, &dst}) {
    const Node* n = node(p->node);
    if (p->element >= 0 && !n->type_->attr(p->attr).type.array)
      return error(ErrorCode::kInvalidArgument, plug_name(*p) + ": not an array");
    if (p->element >= kMaxElement) return error(ErrorCode::kInvalidArgument, plug_name(*p) + ": index too large");
    if (p->component >= 3 || (p->component >= 0 && (p->element >= 0 || n->type_->attr(p->attr).type != AttrType{ValueType::kDouble3, false})))
      return error(ErrorCode::kInvalidArgument, plug_name(*p) + ": components exist only on double3 attributes");
  }
  const std::string what = "cannot connect " + plug_name(src) + " -> " + plug_name(dst);
  if (!(d->type_->attr(dst.attr).flags & kInput))
    return error(ErrorCode::kInvalidArgument, what + ": the destination is an output");
  AttrType st = plug_type(src), dt = plug_type(dst);
  if (!types_compatible(st, dt))
    return error(ErrorCode::kInvalidArgument, what + ": types differ (" + type_name(st) + " -> " + type_name(dt) + ")");
  for (const Connection& c : d->inputs_) {
    if (overlaps(c.dst, dst))
      return error(ErrorCode::kAlreadyExists, what + ": " + plug_name(c.dst) + " is already connected from " + plug_name(c.src));
  }
  // Cycle: is the source node downstream of the destination node?
  if (src.node == dst.node) return error(ErrorCode::kCycle, what + ": it would create a cycle: " + s->name_ + " -> " + s->name_);
  std::unordered_map<std::uint32_t, std::uint32_t> came_from;  // node index -> predecessor index
  std::vector<std::uint32_t> frontier{dst.node.index};
  came_from.emplace(dst.node.index, dst.node.index);
  bool found = false;
  while (!frontier.empty() && !found) {
    std::uint32_t i = frontier.back();
    frontier.pop_back();
    for (const Connection& c : slots_[i]->outputs_) {
      std::uint32_t j = c.dst.node.index;
      if (!came_from.emplace(j, i).second) continue;
      if (j == src.node.index) {
        found = true;
        break;
      }
      frontier.push_back(j);
    }
  }
  if (found) {
    std::vector<std::string> path;
    for (std::uint32_t i = src.node.index;; i = came_from[i]) {
      path.push_back(slots_[i]->name_);
      if (i == dst.node.index) break;
    }
    std::reverse(path.begin(), path.end());
    std::string cycle;
    for (const std::string& name : path) cycle += name + " -> ";
    cycle += d->name_;
    return error(ErrorCode::kCycle, what + ": it would create a cycle: " + cycle);
  }
  return Status::ok();
}

Status Graph::connect(const Plug& src, const Plug& dst) {
  if (Status s = check_connection(src, dst); !s) return s;
  Edit edit;
  edit.kind = Edit::Kind::kConnect;
  edit.src = PlugRef{node(src.node)->uuid_, src.attr, src.element, src.component};
  edit.dst = PlugRef{node(dst.node)->uuid_, dst.attr, dst.element, dst.component};
  edit.before = node(dst.node)->values_[dst.attr];
  if (Status s = connect_impl(src, dst); !s) return s;
  record(std::move(edit));
  notify([&](Observer& o) { o.connection_made(*this, Connection{src, dst}); });
  return Status::ok();
}

Status Graph::connect_impl(const Plug& src, const Plug& dst) {
  Node& s = *node_mut(src.node);
  Node& d = *node_mut(dst.node);
  s.outputs_.push_back(Connection{src, dst});
  d.inputs_.push_back(Connection{src, dst});
  topology_changed();
  if (!d.dirty_[dst.attr]) {
    d.dirty_[dst.attr] = 1;
    queue(d);
    dirty_downstream(dst.node, dst.attr);
  }
  return Status::ok();
}

Status Graph::disconnect(const Plug& src, const Plug& dst) {
  const Node* d = node(dst.node);
  if (!d || !node(src.node)) return error(ErrorCode::kNotFound, "disconnect: no such node (stale handle)");
  auto it = std::find_if(d->inputs_.begin(), d->inputs_.end(),
                         [&](const Connection& c) { return c.src == src && c.dst == dst; });
  if (it == d->inputs_.end())
    return error(ErrorCode::kNotFound, plug_name(src) + " is not connected to " + plug_name(dst));
  // The destination keeps the value it last received, as in Maya; pull it
  // first so that value does not depend on when evaluation last ran.
  evaluate(dst.node, dst.attr);
  Edit edit;
  edit.kind = Edit::Kind::kDisconnect;
  edit.src = PlugRef{node(src.node)->uuid_, src.attr, src.element, src.component};
  edit.dst = PlugRef{d->uuid_, dst.attr, dst.element, dst.component};
  disconnect_impl(src, dst);
  edit.after = node(dst.node)->values_[dst.attr];
  record(std::move(edit));
  notify([&](Observer& o) { o.connection_broken(*this, Connection{src, dst}); });
  return Status::ok();
}

void Graph::disconnect_impl(const Plug& src, const Plug& dst) {
  Node& s = *node_mut(src.node);
  Node& d = *node_mut(dst.node);
  auto same = [&](const Connection& c) { return c.src == src && c.dst == dst; };
  s.outputs_.erase(std::find_if(s.outputs_.begin(), s.outputs_.end(), same));
  d.inputs_.erase(std::find_if(d.inputs_.begin(), d.inputs_.end(), same));
  d.dirty_[dst.attr] = 0;
  dirty_downstream(dst.node, dst.attr);
  topology_changed();
}

Status Graph::disconnect_input(const Plug& dst) {
  std::optional<Plug> src = source(dst);
  if (!src) return Status::ok();
  return disconnect(*src, dst);
}

std::optional<Plug> Graph::source(const Plug& dst) const {
  const Node* d = node(dst.node);
  if (!d) return std::nullopt;
  for (const Connection& c : d->inputs_) {
    if (c.dst == dst) return c.src;
  }
  return std::nullopt;
}

std::vector<Connection> Graph::connections() const {
  std::vector<Connection> all;
  for (const auto& slot : slots_) {
    if (slot) all.insert(all.end(), slot->inputs_.begin(), slot->inputs_.end());
  }
  auto key = [&](const Connection& c) {
    return std::make_tuple(node(c.dst.node)->order_, c.dst.attr, c.dst.element, c.dst.component);
  };
  std::sort(all.begin(), all.end(), [&](const Connection& a, const Connection& b) { return key(a) < key(b); });
  return all;
}

// ---- hierarchy -------------------------------------------------------------

NodeId Graph::parent(NodeId child) const {
  const Node* n = node(child);
  if (!n || n->type_->parent_input() == kNoAttr) return NodeId{};
  for (const Connection& c : n->inputs_) {
    if (c.dst.attr == n->type_->parent_input() && c.src.attr == node(c.src.node)->type_->world_output())
      return c.src.node;
  }
  return NodeId{};
}

std::vector<NodeId> Graph::children(NodeId parent_id) const {
  std::vector<NodeId> result;
  const Node* n = node(parent_id);
  if (!n || n->type_->world_output() == kNoAttr) return result;
  for (const Connection& c : n->outputs_) {
    const Node* d = node(c.dst.node);
    if (c.src.attr == n->type_->world_output() && c.dst.attr == d->type_->parent_input()) result.push_back(c.dst.node);
  }
  std::sort(result.begin(), result.end(), [&](NodeId a, NodeId b) { return node(a)->order_ < node(b)->order_; });
  return result;
}

Status Graph::set_parent(NodeId child, NodeId new_parent) {
  const Node* c = node(child);
  if (!c) return error(ErrorCode::kNotFound, "parent: no such child node (stale handle)");
  if (c->type_->parent_input() == kNoAttr)
    return error(ErrorCode::kInvalidArgument, "'" + c->name_ + "' (" + c->type_->name() + ") cannot have a parent");
  const Node* p = nullptr;
  if (new_parent.is_valid()) {
    p = node(new_parent);
    if (!p) return error(ErrorCode::kNotFound, "parent: no such parent node (stale handle)");
    if (p->type_->world_output() == kNoAttr)
      return error(ErrorCode::kInvalidArgument, "'" + p->name_ + "' (" + p->type_->name() + ") cannot be a parent");
  }
  Plug dst{child, c->type_->parent_input(), -1};
  std::optional<Plug> current = source(dst);
  if (p && current && *current == Plug{new_parent, p->type_->world_output(), -1}) return Status::ok();
  if (!p && !current) return Status::ok();
  Transaction transaction(*this, p ? "parent " + c->name_ + " under " + p->name_ : "unparent " + c->name_);
  if (current) {
    if (Status s = disconnect(*current, dst); !s) return s;
    if (Status s = set_value(dst, Mat4(Mat4::Identity())); !s) return s;
  }
  if (p) {
    if (Status s = connect(Plug{new_parent, p->type_->world_output(), -1}, dst); !s) {
      transaction.rollback();
      return s;
    }
  }
  return Status::ok();
}

// ---- tags ------------------------------------------------------------------

Status Graph::set_tag(NodeId id, const std::string& key, const std::string& value) {
  Node* n = node_mut(id);
  if (!n) return error(ErrorCode::kNotFound, "tag: no such node (stale handle)");
  if (key.empty()) return error(ErrorCode::kInvalidArgument, "tag on '" + n->name_ + "': the key is empty");
  if (!is_valid_utf8(key) || !is_valid_utf8(value))
    return error(ErrorCode::kInvalidArgument, "tag on '" + n->name_ + "': keys and values must be UTF-8 text");
  auto it = n->tags_.find(key);
  if (it != n->tags_.end() && it->second == value) return Status::ok();
  Edit edit;
  edit.kind = Edit::Kind::kTag;
  edit.dst.node = n->uuid_;
  edit.x().key = key;
  if (it != n->tags_.end()) edit.x().text_before = it->second;
  edit.x().text_after = value;
  n->tags_[key] = value;
  record(std::move(edit));
  notify([&](Observer& o) { o.tag_changed(*this, id, key); });
  return Status::ok();
}

Status Graph::remove_tag(NodeId id, const std::string& key) {
  Node* n = node_mut(id);
  if (!n) return error(ErrorCode::kNotFound, "tag: no such node (stale handle)");
  auto it = n->tags_.find(key);
  if (it == n->tags_.end()) return error(ErrorCode::kNotFound, "'" + n->name_ + "' has no tag '" + key + "'");
  Edit edit;
  edit.kind = Edit::Kind::kTag;
  edit.dst.node = n->uuid_;
  edit.x().key = key;
  edit.x().text_before = it->second;
  n->tags_.erase(it);
  record(std::move(edit));
  notify([&](Observer& o) { o.tag_changed(*this, id, key); });
  return Status::ok();
}

const std::string* Node::tag_find(const std::string& key) const {
  auto it = tags_.find(key);
  return it == tags_.end() ? nullptr : &it->second;
}

// ---- time and selection ------------------------------------------------------

void Graph::set_time(double seconds) {
  if (seconds == time_) return;
  time_ = seconds;
  for (NodeId id : time_dependent_) dirty_outputs(*node_mut(id));
  notify([&](Observer& o) { o.time_changed(*this); });
}

Status Graph::set_fps(double fps) {
  if (!(fps > 0.0) || fps > 1e6) return error(ErrorCode::kInvalidArgument, "frame rate must be positive, got " + std::to_string(fps));
  fps_ = fps;
  return Status::ok();
}

void Graph::select(std::vector<NodeId> nodes_to_select) {
  std::vector<NodeId> clean;
  for (NodeId id : nodes_to_select) {
    if (node(id) && std::find(clean.begin(), clean.end(), id) == clean.end()) clean.push_back(id);
  }
  if (clean == selection_) return;
  selection_ = std::move(clean);
  notify([&](Observer& o) { o.selection_changed(*this); });
}

// ---- undo ------------------------------------------------------------------

void Graph::record(Edit edit) {
  if (replaying_) return;
  redo_stack_.clear();
  if (open_.empty()) {
    auto step = std::make_unique<Step>();
    switch (edit.kind) {
      case Edit::Kind::kCreate: step->label = "create " + edit.x().snapshot.name; break;
      case Edit::Kind::kDelete: step->label = "delete " + edit.x().snapshot.name; break;
      case Edit::Kind::kConnect: step->label = "connect"; break;
      case Edit::Kind::kDisconnect: step->label = "disconnect"; break;
      case Edit::Kind::kSet: step->label = "set"; break;
      case Edit::Kind::kRename: step->label = "rename " + *edit.x().text_before + " to " + *edit.x().text_after; break;
      case Edit::Kind::kTag: step->label = "tag " + edit.x().key; break;
    }
    step->edits.push_back(std::move(edit));
    push_undo(std::move(step));
    return;
  }
  pending_->edits.push_back(std::move(edit));
}

void Graph::apply(const Edit& e, bool forward) {
  auto id_of = [&](const Uuid& u) { return find(u); };
  auto plug_of = [&](const PlugRef& r) { return Plug{id_of(r.node), r.attr, r.element, r.component}; };
  auto restore = [&](const NodeSnapshot& s) {
    Result<NodeId> id = create_node_impl(*s.type, s.name, s.uuid, s.order);
    assert(id.is_ok());
    Node& n = *node_mut(*id);
    n.values_ = s.values;
    for (AttrIndex o : n.type_->outputs()) n.dirty_[o] = 1;
    n.tags_ = s.tags;
    notify([&](Observer& o) { o.node_added(*this, *id); });
  };
  auto remove = [&](const Uuid& u) {
    NodeId id = id_of(u);
    // As delete_node(): the selection drops the node (and says so) before
    // node_removed.
    if (std::erase(selection_, id) != 0) notify([&](Observer& o) { o.selection_changed(*this); });
    notify([&](Observer& o) { o.node_removed(*this, id); });
    (void)delete_node_impl(id);
  };
  auto set_whole = [&](const PlugRef& r, const Value& v) {
    Plug p = plug_of(r);
    Node& n = *node_mut(p.node);
    n.values_[p.attr] = v;
    // `v` was recorded when the edit was made, when elements of this array
    // fed by other connections may have been stale (dirty, not yet pulled).
    // Mark the attribute dirty so that those elements are pulled again
    // rather than served stale from the restored copy.
    if (std::any_of(n.inputs_.begin(), n.inputs_.end(), [&](const Connection& c) { return c.dst.attr == p.attr; })) {
      n.dirty_[p.attr] = 1;
      queue(n);
    }
    dirty_downstream(p.node, p.attr);
    notify([&](Observer& o) { o.attribute_changed(*this, Plug{p.node, p.attr, -1}); });
  };
  auto link = [&](bool make) {
    Plug src = plug_of(e.src), dst = plug_of(e.dst);
    if (make) {
      (void)connect_impl(src, dst);
      notify([&](Observer& o) { o.connection_made(*this, Connection{src, dst}); });
    } else {
      disconnect_impl(src, dst);
      notify([&](Observer& o) { o.connection_broken(*this, Connection{src, dst}); });
    }
  };
  switch (e.kind) {
    case Edit::Kind::kCreate:
      forward ? restore(e.x().snapshot) : remove(e.x().snapshot.uuid);
      break;
    case Edit::Kind::kDelete:
      forward ? remove(e.x().snapshot.uuid) : restore(e.x().snapshot);
      break;
    case Edit::Kind::kConnect:
      if (forward) {
        link(true);
      } else {
        link(false);
        set_whole(PlugRef{e.dst.node, e.dst.attr, -1}, e.before);
      }
      break;
    case Edit::Kind::kDisconnect:
      if (forward) {
        link(false);
        set_whole(PlugRef{e.dst.node, e.dst.attr, -1}, e.after);
      } else {
        link(true);
      }
      break;
    case Edit::Kind::kSet:
      set_whole(e.dst, forward ? e.after : e.before);
      break;
    case Edit::Kind::kRename: {
      NodeId id = id_of(e.dst.node);
      Node& n = *node_mut(id);
      std::string old = n.name_;
      by_name_.erase(old);
      n.name_ = forward ? *e.x().text_after : *e.x().text_before;
      by_name_.emplace(n.name_, id);
      notify([&](Observer& o) { o.node_renamed(*this, id, old); });
      break;
    }
    case Edit::Kind::kTag: {
      NodeId id = id_of(e.dst.node);
      Node& n = *node_mut(id);
      const std::optional<std::string>& v = forward ? e.x().text_after : e.x().text_before;
      if (v) n.tags_[e.x().key] = *v;
      else n.tags_.erase(e.x().key);
      notify([&](Observer& o) { o.tag_changed(*this, id, e.x().key); });
      break;
    }
  }
}

std::uint64_t Graph::new_merge_key() {
  static std::atomic<std::uint64_t> next{1};
  return next.fetch_add(1, std::memory_order_relaxed);
}

void Graph::begin_transaction(std::string label, std::uint64_t merge_key) {
  if (open_.empty()) {
    pending_ = spare_ ? std::move(spare_) : std::make_unique<Step>();
    // Interactive edits repeat: size the step like the last one.
    pending_->edits.reserve(std::min<std::size_t>(last_step_edits_, 1 << 16));
    pending_->label = std::move(label);
    pending_->merge_key = merge_key;
  }
  open_.push_back(pending_->edits.size());
}

void Graph::commit_transaction() {
  assert(!open_.empty() && "commit_transaction without begin_transaction");
  if (open_.empty()) return;
  open_.pop_back();
  if (!open_.empty()) return;
  std::unique_ptr<Step> step = std::move(pending_);
  if (step->edits.empty()) return;
  last_step_edits_ = step->edits.size();
  Step* top = undo_stack_.empty() ? nullptr : undo_stack_.back().get();
  // A step with other edits (a key that created a curve) may be merged
  // into, but is never merged itself.
  if (step->merge_key == 0 || !top || top->merge_key != step->merge_key || !step->only_sets()) {
    push_undo(std::move(step));
    return;
  }
  // Same gesture: fold into the step on top.
  if (!top->indexed) {
    std::size_t first = top->edits.size();
    while (first > 0 && top->edits[first - 1].kind == Edit::Kind::kSet) --first;
    for (std::size_t i = first; i < top->edits.size(); ++i)
      top->set_at[Step::PlugKey{top->edits[i].dst.node, top->edits[i].dst.attr}] = i;
    top->indexed = true;
  }
  for (Edit& e : step->edits) {
    auto [it, added] = top->set_at.try_emplace(Step::PlugKey{e.dst.node, e.dst.attr}, top->edits.size());
    if (added) top->edits.push_back(std::move(e));
    else top->edits[it->second].after = std::move(e.after);
  }
  step->edits.clear();
  step->set_at.clear();
  step->indexed = false;
  spare_ = std::move(step);
}

void Graph::rollback_transaction() {
  assert(!open_.empty() && "rollback_transaction without begin_transaction");
  if (open_.empty()) return;
  std::size_t first = open_.back();
  replaying_ = true;
  for (std::size_t i = pending_->edits.size(); i > first; --i) apply(pending_->edits[i - 1], false);
  replaying_ = false;
  pending_->edits.resize(first);
  commit_transaction();
}

std::string Graph::undo_label() const { return undo_stack_.empty() ? "" : undo_stack_.back()->label; }
std::string Graph::redo_label() const { return redo_stack_.empty() ? "" : redo_stack_.back()->label; }

bool Graph::undo() {
  if (undo_stack_.empty() || !open_.empty()) return false;
  std::unique_ptr<Step> step = std::move(undo_stack_.back());
  undo_stack_.pop_back();
  replaying_ = true;
  for (auto it = step->edits.rbegin(); it != step->edits.rend(); ++it) apply(*it, false);
  replaying_ = false;
  redo_stack_.push_back(std::move(step));
  return true;
}

bool Graph::redo() {
  if (redo_stack_.empty() || !open_.empty()) return false;
  std::unique_ptr<Step> step = std::move(redo_stack_.back());
  redo_stack_.pop_back();
  replaying_ = true;
  for (const Edit& e : step->edits) apply(e, true);
  replaying_ = false;
  undo_stack_.push_back(std::move(step));
  return true;
}

void Graph::push_undo(std::unique_ptr<Step> step) {
  undo_stack_.push_back(std::move(step));
  if (undo_stack_.size() > undo_limit_) {
    // Drop the oldest quarter at once so trimming is amortised O(1).
    std::size_t drop = std::max<std::size_t>(1, undo_stack_.size() - undo_limit_ * 3 / 4);
    undo_stack_.erase(undo_stack_.begin(), undo_stack_.begin() + static_cast<std::ptrdiff_t>(drop));
  }
}

void Graph::set_undo_limit(std::size_t steps) {
  undo_limit_ = std::max<std::size_t>(1, steps);
  if (undo_stack_.size() > undo_limit_)
    undo_stack_.erase(undo_stack_.begin(), undo_stack_.end() - static_cast<std::ptrdiff_t>(undo_limit_));
}

void Graph::clear_history() {
  undo_stack_.clear();
  redo_stack_.clear();
}

void Graph::add_observer(Observer* observer) {
  if (std::find(observers_.begin(), observers_.end(), observer) == observers_.end()) observers_.push_back(observer);
}

void Graph::remove_observer(Observer* observer) { std::erase(observers_, observer); }

}  // namespace rigel::graph
