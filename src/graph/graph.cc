// Graph: nodes and their names, plugs, values, tags.
#include "rigel/graph/graph.h"

#include <algorithm>
#include <cctype>
#include <charconv>

#include "graph_internal.h"

namespace rigel::graph {
namespace {

constexpr char kComponentSuffix[] = {'X', 'Y', 'Z'};

}  // namespace

Graph::Graph(std::shared_ptr<const Registry> registry) : registry_(std::move(registry)) {}
Graph::~Graph() = default;

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
  n->versions_.assign(type.attr_count(), 0);
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
  // append, not "[" + ...: GCC 12 warns falsely (-Wstringop-overflow) on that form.
  if (plug.element >= 0) name.append("[").append(std::to_string(plug.element)).append("]");
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
  n->versions_[plug.attr] = ++n->clock_;
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

}  // namespace rigel::graph
