// Control spaces (spaces.h).

#include "rigel/rig/spaces.h"

#include <algorithm>
#include <cctype>
#include <string>
#include <vector>

#include "rigel/math/transform.h"
#include "rigel/ops/constraints/constraints.h"
#include "rigel/ops/util/space.h"
#include "rigel/rig/meta.h"
#include "rigel/scene/transform_types.h"

namespace rigel::rig {
namespace {

using graph::Graph;
using graph::Plug;
using graph::Value;
using math::Mat4;
namespace xform = scene::xform;
namespace sp = ops::util::space_attr;

Plug plug(NodeId node, graph::AttrIndex attr, int element = -1) {
  return Plug{node, attr, static_cast<std::int32_t>(element), -1};
}

// The node connected into `dst` (invalid: none).
NodeId source_of(const Graph& g, NodeId node, graph::AttrIndex attr) {
  const graph::Node* n = g.node(node);
  if (!n) return {};
  for (const graph::Connection& c : n->inputs())
    if (c.dst.attr == attr) return c.src.node;
  return {};
}

// The element connected into `dst[element]`'s source node (invalid: none).
NodeId element_source(const Graph& g, NodeId node, graph::AttrIndex attr, int element) {
  for (const graph::Connection& c : g.node(node)->inputs())
    if (c.dst.attr == attr && c.dst.element == element) return c.src.node;
  return {};
}

bool is_identifier(std::string_view s) {
  if (s.empty() || s.size() > 64 || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  return std::all_of(s.begin(), s.end(), [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
}

Status invalid(const std::string& field, const std::string& message) {
  return error(ErrorCode::kInvalidArgument, message).with_field(field);
}

// Makes the spaceSwitch, its compensation transform and space 0 "parent".
Result<ControlSpaces> make_switch(scene::Scene& scene, NodeId control) {
  Graph& g = scene.graph();
  const std::string name = g.node(control)->name();
  const NodeId parent = g.parent(control);
  const Mat4 rest = std::get<Mat4>(g.evaluate(control, xform::kOffsetParentMatrix));
  Result<NodeId> node = g.create_node(ops::util::kSpaceSwitchType, name + "_spaceSwitch");
  if (!node) return node.status();
  NodeId holder;
  if (const NodeId rig = rig_of(g, control); rig.is_valid())
    if (Result<NodeId> still = get_meta_connection(g, rig, "noTransform"); still) holder = *still;
  Result<NodeId> comp = scene.create(scene::kTransformType, name + "_spaceCompensation", holder);
  if (!comp) return comp.status();
  Status s = g.set_value(plug(*node, sp::kRestOffset), Value(rest));
  if (s) s = g.set_value(plug(*node, sp::kSpaceNames), Value(std::vector<std::string>{"parent"}));
  if (s && parent.is_valid()) s = g.connect(plug(parent, xform::kWorldMatrix), plug(*node, sp::kParentMatrix));
  if (s && parent.is_valid()) s = g.connect(plug(parent, xform::kWorldMatrix), plug(*node, sp::kTargetWorldMatrix, 0));
  if (s) s = g.connect(plug(*comp, xform::kMatrix), plug(*node, sp::kCompensationMatrix));
  if (s) s = g.connect(plug(*node, sp::kOutMatrix), plug(control, xform::kOffsetParentMatrix));
  if (s) s = g.set_tag(*node, "rig.spaceOf", g.node(control)->uuid().str());
  if (s) s = g.set_tag(*comp, "rig.spaceOf", g.node(control)->uuid().str());
  if (!s) return s;
  return spaces_of(scene, control);
}

std::string trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return std::string(s);
}

// The component of `rig` named `ref`, else the first of type `ref`.
NodeId component_named(const Graph& g, NodeId rig, std::string_view ref) {
  const std::vector<NodeId> components = rig_components(g, rig);
  for (NodeId c : components)
    if (meta_string(g, c, "componentName") == ref) return c;
  for (NodeId c : components)
    if (meta_string(g, c, "metaType") == ref) return c;
  return {};
}

}  // namespace

Status add_default_spaces(BuildContext& ctx, NodeId control, std::string_view role, std::string_view spec,
                          bool required) {
  Graph& g = ctx.graph();
  const std::string where = ctx.full_name() + ": spaces '" + std::string(spec) + "'";
  const NodeId rig = rig_of(g, ctx.meta());
  std::size_t start = 0;
  while (start <= spec.size()) {
    const std::size_t comma = std::min(spec.find(',', start), spec.size());
    const std::string entry = trim(spec.substr(start, comma - start));
    start = comma + 1;
    if (entry.empty()) continue;
    std::string name = entry;
    NodeId target;
    if (entry != "world") {
      const std::size_t eq = entry.find('=');
      const std::size_t slash = entry.find('/', eq == std::string::npos ? 0 : eq);
      if (eq == std::string::npos || slash == std::string::npos)
        return invalid("params", where + ": '" + entry + "' is neither world nor NAME=COMPONENT/ROLE");
      name = trim(std::string_view(entry).substr(0, eq));
      const std::string component = trim(std::string_view(entry).substr(eq + 1, slash - eq - 1));
      const std::string target_role = trim(std::string_view(entry).substr(slash + 1));
      const NodeId meta = rig.is_valid() ? component_named(g, rig, component) : NodeId{};
      Result<NodeId> found = meta.is_valid() ? get_meta_connection(g, meta, target_role)
                                             : Result<NodeId>(error(ErrorCode::kNotFound, "no component " + component));
      if (!found) {
        if (required) return invalid("params", where + ": " + found.status().message());
        continue;
      }
      target = *found;
    }
    Result<int> added = add_space(ctx.scene(), control, name, target);
    if (!added) return added.status().with_context(where);
  }
  const ControlSpaces made = spaces_of(ctx.scene(), control);
  if (!made.node.is_valid()) return Status::ok();
  Status s = ctx.link(made.node, std::string(role) + "SpaceSwitch");
  if (s) s = ctx.link(made.compensation, std::string(role) + "SpaceCompensation");
  return s;
}

ControlSpaces spaces_of(scene::Scene& scene, NodeId control) {
  Graph& g = scene.graph();
  ControlSpaces out;
  out.control = control;
  const NodeId node = source_of(g, control, xform::kOffsetParentMatrix);
  if (!node.is_valid() || g.node(node)->type().name() != ops::util::kSpaceSwitchType) return out;
  out.node = node;
  out.compensation = source_of(g, node, sp::kCompensationMatrix);
  const auto names = std::get<std::vector<std::string>>(g.evaluate(node, sp::kSpaceNames));
  for (std::size_t i = 0; i < names.size(); ++i)
    out.spaces.push_back(Space{names[i], element_source(g, node, sp::kTargetWorldMatrix, static_cast<int>(i))});
  out.current = static_cast<int>(std::get<std::int64_t>(g.evaluate(node, sp::kSpaceIndex)));
  return out;
}

Result<int> find_space(const ControlSpaces& spaces, std::string_view name) {
  std::string known;
  for (std::size_t i = 0; i < spaces.spaces.size(); ++i) {
    if (spaces.spaces[i].name == name) return static_cast<int>(i);
    known.append(known.empty() ? "" : ", ").append(spaces.spaces[i].name);
  }
  std::string message = "space '";
  message.append(name).append("': ");
  if (known.empty()) message.append("the control has no spaces (add one first)");
  else message.append("not one of the control's spaces (").append(known).append(")");
  return invalid("space", message);
}

Result<int> add_space(scene::Scene& scene, NodeId control, std::string_view name, NodeId target) {
  Graph& g = scene.graph();
  if (!scene.is_transform(control)) return invalid("control", "add space: the control is not a transform");
  const std::string control_name = g.node(control)->name();
  if (!is_identifier(name))
    return invalid("space", "add space to " + control_name + ": the name '" + std::string(name) +
                                "' is not an identifier (letters, digits, _)");
  if (target.is_valid() && !scene.is_transform(target))
    return invalid("target", "add space to " + control_name + ": the target is not a transform");
  if (target == control) return invalid("target", "add space to " + control_name + ": a control cannot follow itself");
  ControlSpaces now = spaces_of(scene, control);
  if (!now.node.is_valid()) {
    const NodeId driver = source_of(g, control, xform::kOffsetParentMatrix);
    if (driver.is_valid())
      return invalid("control", "add space to " + control_name + ": its offsetParentMatrix is driven by " +
                                    g.node(driver)->name());
  }
  for (const Space& s : now.spaces)
    if (s.name == name) return invalid("space", "add space to " + control_name + ": it has a space '" + s.name + "'");

  graph::Transaction tx(g, "add space " + std::string(name) + " to " + control_name);
  auto fail = [&](Status s) -> Result<int> {
    tx.rollback();
    return s;
  };
  if (!now.node.is_valid()) {
    Result<ControlSpaces> made = make_switch(scene, control);
    if (!made) return fail(made.status());
    now = *made;
  }
  // The new space's offset: following it now gives what the current space gives.
  const auto offsets = std::get<std::vector<Mat4>>(g.evaluate(now.node, sp::kTargetOffset));
  const auto k = static_cast<std::size_t>(now.current);
  const NodeId current_target = now.spaces[k].target;
  const Mat4 current_world = current_target.is_valid() ? scene.world_matrix(current_target) : Mat4(Mat4::Identity());
  const Mat4 current_offset = k < offsets.size() ? offsets[k] : Mat4(Mat4::Identity());
  const Mat4 target_world = target.is_valid() ? scene.world_matrix(target) : Mat4(Mat4::Identity());
  if (!ops::constraints::is_offset_computable(target_world))
    return fail(invalid("target", "add space to " + control_name + ": the target's world matrix is singular"));
  const Mat4 offset = math::affine_inverse(target_world) * current_world * current_offset;

  const int index = static_cast<int>(now.spaces.size());
  std::vector<std::string> names;
  for (const Space& s : now.spaces) names.push_back(s.name);
  names.emplace_back(name);
  std::vector<Mat4> new_offsets(static_cast<std::size_t>(index) + 1, Mat4::Identity());
  for (std::size_t i = 0; i < offsets.size() && i < new_offsets.size(); ++i) new_offsets[i] = offsets[i];
  new_offsets.back() = offset;
  Status s = g.set_value(plug(now.node, sp::kSpaceNames), Value(names));
  if (s) s = g.set_value(plug(now.node, sp::kTargetOffset), Value(new_offsets));
  if (s && target.is_valid()) {
    s = g.connect(plug(target, xform::kWorldMatrix), plug(now.node, sp::kTargetWorldMatrix, index));
    if (!s)
      s = invalid("target", "add space to " + control_name + ": " + g.node(target)->name() +
                                " follows the control (" + s.message() + ")");
  }
  if (!s) return fail(s);
  return index;
}

}  // namespace rigel::rig
