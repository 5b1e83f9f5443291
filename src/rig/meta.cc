#include "rigel/rig/meta.h"

#include <algorithm>
#include <cassert>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "rigel/io/scene_file.h"
#include "rigel/ops/registry.h"
#include "rigel/scene/transform_types.h"

namespace rigel::rig {
namespace {

using graph::AttrSpec;
using graph::AttrType;
using graph::Value;
using graph::ValueType;

constexpr AttrType kString{ValueType::kString, false};
constexpr AttrType kStrings{ValueType::kString, true};
constexpr AttrType kInt{ValueType::kInt, false};
constexpr AttrType kBool{ValueType::kBool, false};
constexpr AttrType kMessage{ValueType::kMessage, false};

AttrSpec string_attr(std::string name, std::string value = "") {
  return graph::input_attr(std::move(name), kString, Value(std::move(value)));
}
AttrSpec message_attr(std::string name) {
  AttrSpec a;
  a.name = std::move(name);
  a.type = kMessage;
  a.flags = graph::kInput | graph::kHidden;
  return a;
}

bool has_type(const Graph& g, NodeId id, std::string_view type) {
  const graph::Node* n = g.node(id);
  return n && n->type().name() == type;
}

// Nodes fed by `meta.attr` through their metaParent, in creation order.
std::vector<NodeId> fed_by(const Graph& g, NodeId meta, std::string_view attr, std::string_view type = {}) {
  std::vector<NodeId> out;
  const graph::Node* n = g.node(meta);
  if (!n) return out;
  const graph::AttrIndex a = n->type().attr_find(attr);
  if (a == graph::kNoAttr) return out;
  for (const graph::Connection& c : n->outputs()) {
    if (c.src.attr != a) continue;
    const graph::Node* d = g.node(c.dst.node);
    if (d->type().attr(c.dst.attr).name != graph::kMetaParentAttr) continue;
    if (!type.empty() && d->type().name() != type) continue;
    out.push_back(c.dst.node);
  }
  std::sort(out.begin(), out.end(), [&](NodeId x, NodeId y) { return g.node(x)->order() < g.node(y)->order(); });
  return out;
}

std::optional<int> int_tag(const graph::Node& n, const char* key) {
  const std::string* t = n.tag_find(key);
  if (!t) return std::nullopt;
  int v = 0;
  auto [end, ec] = std::from_chars(t->data(), t->data() + t->size(), v);
  if (ec != std::errc() || end != t->data() + t->size()) return std::nullopt;
  return v;
}

// START / MIDDLE / END / an integer, against `count` elements.
std::optional<int> index_ref(std::string_view ref, int count) {
  if (ref == "START") return count > 0 ? std::optional<int>(0) : std::nullopt;
  if (ref == "END") return count > 0 ? std::optional<int>(count - 1) : std::nullopt;
  if (ref == "MIDDLE") return count > 0 ? std::optional<int>((count - 1) / 2) : std::nullopt;
  int v = 0;
  auto [end, ec] = std::from_chars(ref.data(), ref.data() + ref.size(), v);
  if (ec != std::errc() || end != ref.data() + ref.size() || v < 0) return std::nullopt;
  return v;
}

// "name[ref]" -> (name, ref); "name" -> (name, "").
std::pair<std::string_view, std::string_view> split_index(std::string_view part) {
  if (part.size() >= 3 && part.back() == ']') {
    const std::size_t open = part.find('[');
    if (open != std::string_view::npos) return {part.substr(0, open), part.substr(open + 1, part.size() - open - 2)};
  }
  return {part, {}};
}

}  // namespace

Status register_rig_types(graph::Registry& registry) {
  graph::NodeTypeSpec manager;
  manager.name = kMetaManagerType;
  manager.description = "The scene's metadata manager (seed 002): metaRoots links every rig's metaRoot";
  manager.attrs = {string_attr("metaType", "manager"), message_attr("metaRoots")};
  if (Status s = registry.add(std::move(manager)); !s) return s;

  graph::NodeTypeSpec root;
  root.name = kMetaRootType;
  root.description = "One built rig: its definition, version and build position; links its components and groups";
  root.attrs = {string_attr("metaType", "rig"),
                string_attr("rigName"),
                string_attr("version"),
                string_attr("definitionPath"),
                string_attr("definition"),
                graph::input_attr("buildPosition", kInt, Value(std::int64_t{0})),
                graph::input_attr("editMode", kBool, Value(false)),
                string_attr("namingTemplate"),
                // Where a published rig came from (tools/publish.h): the
                // asset, its version and the version's folder.
                string_attr("publishedAsset"),
                graph::input_attr("publishedVersion", kInt, Value(std::int64_t{0})),
                string_attr("publishedFrom"),
                string_attr("buildRecord"),
                message_attr("metaChildren"),
                message_attr("members")};
  if (Status s = registry.add(std::move(root)); !s) return s;
  // The definition's path is kept relative to the scene file (io/scene_file.h).
  io::declare_path_attribute(kMetaRootType, "definitionPath");
  io::declare_path_attribute(kMetaRootType, "publishedFrom");

  graph::NodeTypeSpec component;
  component.name = kMetaComponentType;
  component.description = "One built component: its type (metaType), id and version; links every node it built";
  component.attrs = {string_attr("metaType"),
                     string_attr("componentName"),
                     string_attr("side", "C"),
                     string_attr("version"),
                     string_attr("rigId"),
                     graph::input_attr("tags", kStrings, Value(std::vector<std::string>{})),
                     string_attr("buildRecord"),
                     // A call's outputs (build_function.h): JSON {NAME: VALUE}.
                     string_attr("outputs"),
                     message_attr("metaChildren"),
                     message_attr("members")};
  return registry.add(std::move(component));
}

std::shared_ptr<const graph::Registry> default_registry() {
  static const std::shared_ptr<const graph::Registry> registry = [] {
    auto r = std::make_shared<graph::Registry>();
    Status s = scene::register_scene_types(*r);
    if (s) s = ops::register_ops_types(*r);
    if (s) s = register_rig_types(*r);
    assert(s.is_ok() && "the built-in node types must register");
    (void)s;
    return r;
  }();
  return registry;
}

bool is_meta_node(const Graph& g, NodeId id) {
  return has_type(g, id, kMetaManagerType) || has_type(g, id, kMetaRootType) || has_type(g, id, kMetaComponentType);
}

NodeId meta_manager(const Graph& g) {
  for (NodeId id : g.nodes())
    if (has_type(g, id, kMetaManagerType)) return id;
  return {};
}

std::vector<NodeId> list_rigs(const Graph& g) {
  std::vector<NodeId> out;
  for (NodeId id : g.nodes())
    if (has_type(g, id, kMetaRootType)) out.push_back(id);
  std::sort(out.begin(), out.end(), [&](NodeId x, NodeId y) { return g.node(x)->order() < g.node(y)->order(); });
  return out;
}

std::string meta_string(const Graph& g, NodeId meta, std::string_view attr) {
  const graph::Node* n = g.node(meta);
  if (!n) return {};
  const graph::AttrIndex a = n->type().attr_find(attr);
  if (a == graph::kNoAttr) return {};
  if (const auto* s = std::get_if<std::string>(&n->value(a))) return *s;
  if (const auto* i = std::get_if<std::int64_t>(&n->value(a))) return std::to_string(*i);
  return {};
}

NodeId find_rig(const Graph& g, std::string_view name) {
  for (NodeId r : list_rigs(g))
    if (meta_string(g, r, "rigName") == name) return r;
  return {};
}

NodeId meta_parent(const Graph& g, NodeId node) {
  const graph::Node* n = g.node(node);
  if (!n) return {};
  const graph::AttrIndex a = n->type().attr_find(graph::kMetaParentAttr);
  if (a == graph::kNoAttr) return {};
  std::optional<graph::Plug> src = g.source(graph::Plug{node, a, -1});
  return src ? src->node : NodeId{};
}

std::vector<NodeId> meta_children(const Graph& g, NodeId meta) {
  return fed_by(g, meta, "metaChildren", kMetaComponentType);
}

std::vector<NodeId> meta_members(const Graph& g, NodeId meta) { return fed_by(g, meta, "members"); }

std::vector<NodeId> meta_controls(const Graph& g, NodeId meta) {
  std::vector<NodeId> out;
  for (NodeId m : meta_members(g, meta))
    if (g.node(m)->type().name() == scene::kControlType) out.push_back(m);
  return out;
}

NodeId get_meta_child_by_id(const Graph& g, NodeId meta, std::string_view rig_id) {
  for (NodeId c : meta_children(g, meta))
    if (meta_string(g, c, "rigId") == rig_id) return c;
  return {};
}

std::vector<NodeId> rig_components(const Graph& g, NodeId rig) {
  std::vector<NodeId> out;
  std::vector<NodeId> stack = meta_children(g, rig);
  std::reverse(stack.begin(), stack.end());
  while (!stack.empty()) {
    NodeId c = stack.back();
    stack.pop_back();
    out.push_back(c);
    std::vector<NodeId> kids = meta_children(g, c);
    for (auto it = kids.rbegin(); it != kids.rend(); ++it) stack.push_back(*it);
  }
  return out;
}

NodeId find_component(const Graph& g, NodeId rig, std::string_view key) {
  for (NodeId c : rig_components(g, rig))
    if (meta_string(g, c, "rigId") == key) return c;
  for (NodeId c : rig_components(g, rig))
    if (meta_string(g, c, "componentName") == key) return c;
  return {};
}

Result<NodeId> get_meta_connection(const Graph& g, NodeId meta, std::string_view role, int index) {
  std::vector<std::pair<int, NodeId>> hits;
  for (NodeId m : meta_members(g, meta)) {
    const graph::Node& n = *g.node(m);
    const std::string* r = n.tag_find(kTagRole);
    const std::string* s = n.tag_find(kTagStep);
    if ((r && *r == role) || (!r && s && *s == role)) hits.emplace_back(int_tag(n, kTagIndex).value_or(0), m);
  }
  std::stable_sort(hits.begin(), hits.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  const std::string who = g.node(meta) ? g.node(meta)->name() : std::string("?");
  if (hits.empty()) return error(ErrorCode::kNotFound, who + " has no '" + std::string(role) + "'");
  if (index < 0 || index >= static_cast<int>(hits.size()))
    return error(ErrorCode::kNotFound, who + " has " + std::to_string(hits.size()) + " '" + std::string(role) +
                                           "', no index " + std::to_string(index));
  return hits[index].second;
}

std::string rest_world_text(const math::Mat4& world) {
  std::string out;
  char buffer[32];
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) {
      std::snprintf(buffer, sizeof buffer, "%.17g", world(r, c));
      if (!out.empty()) out += ' ';
      out += buffer;
    }
  return out;
}

std::optional<math::Mat4> rest_world(const Graph& g, NodeId control) {
  const graph::Node* n = g.node(control);
  const std::string* text = n ? n->tag_find(kTagRestWorld) : nullptr;
  if (!text) return std::nullopt;
  math::Mat4 m;
  const char* p = text->c_str();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) {
      char* end = nullptr;
      m(r, c) = std::strtod(p, &end);
      if (end == p || !std::isfinite(m(r, c))) return std::nullopt;
      p = end;
    }
  return m;
}

std::vector<std::pair<std::string, double>> bind_values(const Graph& g, NodeId node) {
  std::vector<std::pair<std::string, double>> out;
  const graph::Node* n = g.node(node);
  const std::string* text = n ? n->tag_find(kTagBind) : nullptr;
  if (!text) return out;
  std::size_t from = 0;
  while (from < text->size()) {
    std::size_t end = text->find(';', from);
    if (end == std::string::npos) end = text->size();
    const std::string item = text->substr(from, end - from);
    const std::size_t eq = item.find('=');
    if (eq != std::string::npos) {
      char* stop = nullptr;
      const double v = std::strtod(item.c_str() + eq + 1, &stop);
      if (stop != item.c_str() + eq + 1 && std::isfinite(v)) out.emplace_back(item.substr(0, eq), v);
    }
    from = end + 1;
  }
  return out;
}

Result<NodeId> mirror_pair(const Graph& g, NodeId control) {
  const graph::Node* n = g.node(control);
  const NodeId meta = n ? component_of(g, control) : NodeId{};
  auto refuse = [&](const std::string& why) {
    return Status(ErrorCode::kInvalidArgument, (n ? "'" + n->name() + "'" : std::string("a deleted node")) + " " + why)
        .with_field("controls");
  };
  if (!meta.is_valid() || !has_type(g, meta, kMetaComponentType)) return refuse("is not a control of a built rig's component");
  const std::string side = meta_string(g, meta, "side");
  if (side != "L" && side != "R") return control;  // a centre component: its own pair
  const std::string other = side == "L" ? "R" : "L";
  std::string base = meta_string(g, meta, "componentName");
  if (base.size() > 2 && base.compare(base.size() - 2, 2, "_" + side) == 0) base.resize(base.size() - 2);
  const std::string type = meta_string(g, meta, "metaType");
  NodeId pair;
  for (NodeId c : rig_components(g, rig_of(g, meta))) {
    std::string name = meta_string(g, c, "componentName");
    if (name.size() > 2 && name.compare(name.size() - 2, 2, "_" + other) == 0) name.resize(name.size() - 2);
    if (meta_string(g, c, "side") == other && meta_string(g, c, "metaType") == type && name == base) pair = c;
  }
  if (!pair.is_valid())
    return refuse("has no pair: its rig has no " + type + " component '" + base + "' on side " + other);
  const std::string* role = n->tag_find(kTagRole);
  if (!role) return refuse("has no role in its component");
  const std::optional<int> index = int_tag(*n, kTagIndex);
  Result<NodeId> found = get_meta_connection(g, pair, *role, index.value_or(0));
  if (!found)
    return refuse("has no pair: " + meta_string(g, pair, "componentName") + " has no '" + *role + "' " +
                  std::to_string(index.value_or(0)));
  return *found;
}

NodeId component_of(const Graph& g, NodeId node) {
  NodeId m = meta_parent(g, node);
  return m.is_valid() && (has_type(g, m, kMetaComponentType) || has_type(g, m, kMetaRootType)) ? m : NodeId{};
}

NodeId rig_of(const Graph& g, NodeId node) {
  NodeId m = is_meta_node(g, node) ? node : component_of(g, node);
  for (int guard = 0; m.is_valid() && guard < 100000; ++guard) {
    if (has_type(g, m, kMetaRootType)) return m;
    m = meta_parent(g, m);
  }
  return {};
}

Result<NodeId> resolve_address(const Graph& g, std::string_view address) {
  const std::string whole(address);
  const std::size_t colon = address.find(':');
  if (colon == std::string_view::npos)
    return error(ErrorCode::kInvalidArgument, "address '" + whole + "': expected RIG:COMPONENT/NAME[INDEX]");
  const std::string_view rig_name = address.substr(0, colon);
  NodeId rig = find_rig(g, rig_name);
  if (!rig.is_valid()) return error(ErrorCode::kNotFound, "address '" + whole + "': no rig '" + std::string(rig_name) + "'");
  std::string_view rest = address.substr(colon + 1);
  if (rest.empty()) return rig;
  std::vector<std::string_view> parts;
  for (std::size_t start = 0;;) {
    const std::size_t slash = rest.find('/', start);
    parts.push_back(rest.substr(start, slash == std::string_view::npos ? std::string_view::npos : slash - start));
    if (slash == std::string_view::npos) break;
    start = slash + 1;
  }
  NodeId component = find_component(g, rig, parts[0]);
  if (!component.is_valid())
    return error(ErrorCode::kNotFound, "address '" + whole + "': rig '" + std::string(rig_name) + "' has no component '" +
                                           std::string(parts[0]) + "'");
  if (parts.size() == 1) return component;
  std::vector<NodeId> members = meta_members(g, component);
  std::size_t next = 1;
  if (auto [name, ref] = split_index(parts[1]); name == "joint" && parts.size() > 2) {
    int guides = 0;
    for (NodeId m : members) guides = std::max(guides, int_tag(*g.node(m), kTagGuide).value_or(-1) + 1);
    std::optional<int> j = index_ref(ref, guides);
    if (!j) return error(ErrorCode::kNotFound, "address '" + whole + "': no joint [" + std::string(ref) + "]");
    std::erase_if(members, [&](NodeId m) { return int_tag(*g.node(m), kTagGuide) != j; });
    next = 2;
  }
  if (next + 1 != parts.size())
    return error(ErrorCode::kInvalidArgument, "address '" + whole + "': expected RIG:COMPONENT[/joint[J]]/NAME[INDEX]");
  auto [name, ref] = split_index(parts[next]);
  // NAME is a role; a step's name stands for the step's nodes only where
  // no node has that role (a limb's fk[1] is its control, not the fkJoint
  // group its step "fk" made under it).
  std::vector<std::pair<int, NodeId>> hits, step_hits;
  for (NodeId m : members) {
    const graph::Node& n = *g.node(m);
    const std::string* r = n.tag_find(kTagRole);
    const std::string* s = n.tag_find(kTagStep);
    if (r && *r == name)
      hits.emplace_back(int_tag(n, kTagIndex).value_or(0), m);
    else if (s && *s == name)
      step_hits.emplace_back(int_tag(n, kTagIndex).value_or(0), m);
  }
  if (hits.empty()) hits = std::move(step_hits);
  std::stable_sort(hits.begin(), hits.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::optional<int> i = ref.empty() ? std::optional<int>(0) : index_ref(ref, static_cast<int>(hits.size()));
  if (hits.empty() || !i || *i >= static_cast<int>(hits.size()))
    return error(ErrorCode::kNotFound, "address '" + whole + "': component '" + std::string(parts[0]) + "' has no '" +
                                           std::string(parts[next]) + "'");
  return hits[*i].second;
}

Result<std::string> address_of(const Graph& g, NodeId node) {
  const graph::Node* n = g.node(node);
  if (!n) return error(ErrorCode::kNotFound, "address: no such node");
  NodeId rig = rig_of(g, node);
  if (!rig.is_valid()) return error(ErrorCode::kNotFound, "address: " + n->name() + " is not part of a rig");
  const std::string rig_name = meta_string(g, rig, "rigName");
  if (node == rig) return rig_name + ":";
  if (has_type(g, node, kMetaComponentType)) return rig_name + ":" + meta_string(g, node, "componentName");
  NodeId comp = component_of(g, node);
  const std::string* role = n->tag_find(kTagRole);
  if (!role) role = n->tag_find(kTagStep);
  if (!comp.is_valid() || !role || comp == rig)
    return error(ErrorCode::kNotFound, "address: " + n->name() + " has no component address");
  // Index among the members with the same role (and guide), as resolve_address counts.
  std::optional<int> guide = int_tag(*n, kTagGuide);
  std::vector<std::pair<int, NodeId>> hits;
  for (NodeId m : meta_members(g, comp)) {
    const graph::Node& x = *g.node(m);
    if (guide && int_tag(x, kTagGuide) != guide) continue;
    const std::string* r = x.tag_find(kTagRole);
    if (!r) r = x.tag_find(kTagStep);
    if (r && *r == *role) hits.emplace_back(int_tag(x, kTagIndex).value_or(0), m);
  }
  std::stable_sort(hits.begin(), hits.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  int index = 0;
  for (std::size_t i = 0; i < hits.size(); ++i)
    if (hits[i].second == node) index = static_cast<int>(i);
  std::string out = rig_name + ":" + meta_string(g, comp, "componentName");
  if (guide) out += "/joint[" + std::to_string(*guide) + "]";
  return out + "/" + *role + "[" + std::to_string(index) + "]";
}

}  // namespace rigel::rig
