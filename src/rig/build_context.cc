// BuildContext (build_context.h): what a step's construct works with.
#include "rigel/rig/build_context.h"

#include <algorithm>
#include <charconv>
#include <string>
#include <utility>
#include <vector>

#include "build_internal.h"
#include "rigel/math/rotation.h"
#include "rigel/math/transform.h"
#include "rigel/ops/constraints/constraints.h"
#include "rigel/ops/util/nodes.h"
#include "rigel/rig/meta.h"
#include "rigel/scene/shapes.h"
#include "rigel/scene/transform_types.h"

namespace rigel::rig {

using namespace detail;

namespace {

const Param* find_param(const Component& c, std::string_view name) { return c.param(name); }

// Puts `id` (made under `parent`) at `world` through its offsetParentMatrix,
// its channels left at rest.
Status place_zeroed(scene::Scene& scene, NodeId id, const Mat4& world, NodeId parent) {
  const Mat4 parent_world = parent.is_valid() ? scene.world_matrix(parent) : Mat4(Mat4::Identity());
  const Mat4 offset = math::affine_inverse(parent_world) * world;
  return scene.graph().set_value(Plug{id, xform::kOffsetParentMatrix, -1}, Value(offset));
}

}  // namespace

Mat4 detail::guide_values(const Guide& guide) {
  math::TransformParts parts;
  parts.translate = guide.translate;
  parts.rotate = math::to_radians(guide.rotate);
  parts.scale = guide.scale;
  return math::compose(parts);
}

std::string BuildContext::full_name() const { return component_ ? component_->full_name() : std::string(); }

bool BuildContext::param_bool(std::string_view name) const {
  const Param* p = find_param(*component_, name);
  if (p && std::holds_alternative<bool>(p->value)) return std::get<bool>(p->value);
  const ParamSpec* s = schema_->param(name);
  return s && std::holds_alternative<bool>(s->default_value) ? std::get<bool>(s->default_value) : false;
}

std::int64_t BuildContext::param_int(std::string_view name) const {
  const Param* p = find_param(*component_, name);
  if (p && std::holds_alternative<std::int64_t>(p->value)) return std::get<std::int64_t>(p->value);
  const ParamSpec* s = schema_->param(name);
  return s && std::holds_alternative<std::int64_t>(s->default_value) ? std::get<std::int64_t>(s->default_value) : 0;
}

double BuildContext::param_double(std::string_view name) const {
  const Param* p = find_param(*component_, name);
  if (p && std::holds_alternative<double>(p->value)) return std::get<double>(p->value);
  if (p && std::holds_alternative<std::int64_t>(p->value)) return static_cast<double>(std::get<std::int64_t>(p->value));
  const ParamSpec* s = schema_->param(name);
  return s && std::holds_alternative<double>(s->default_value) ? std::get<double>(s->default_value) : 0.0;
}

std::string BuildContext::param_string(std::string_view name) const {
  const Param* p = find_param(*component_, name);
  if (p && std::holds_alternative<std::string>(p->value)) return std::get<std::string>(p->value);
  const ParamSpec* s = schema_->param(name);
  return s && std::holds_alternative<std::string>(s->default_value) ? std::get<std::string>(s->default_value)
                                                                     : std::string();
}

math::Vec3 BuildContext::param_vec3(std::string_view name) const {
  const ParamValue* v = param_value(name);
  return v && std::holds_alternative<math::Vec3>(*v) ? std::get<math::Vec3>(*v) : math::Vec3(math::Vec3::Zero());
}

const ParamValue* BuildContext::param_value(std::string_view name) const {
  if (const Param* p = find_param(*component_, name)) return &p->value;
  const ParamSpec* s = schema_->param(name);
  return s ? &s->default_value : nullptr;
}

ControlStyle BuildContext::control_style(std::string_view role) const {
  ControlStyle out;
  out.role = std::string(role);
  if (const ControlSpec* s = schema_ ? schema_->control(role) : nullptr) {
    out.shape = s->shape;
    out.color = s->color;
    out.size = s->size;
  } else {
    out.shape = "circle";
    out.color = "yellow";
  }
  if (const ControlStyle* c = component_ ? component_->control(role) : nullptr) {
    if (!c->shape.empty()) out.shape = c->shape;
    if (!c->color.empty()) out.color = c->color;
    out.size = c->size;
  }
  return out;
}

Result<NodeId> BuildContext::guide_joint(int i) {
  if (i < 0 || i >= guide_count())
    return error(ErrorCode::kNotFound, full_name() + ": no guide " + std::to_string(i));
  const Guide& guide = component_->guides[i];
  if (guide.joint.empty())
    return error(ErrorCode::kNotFound, full_name() + ": guide " + std::to_string(i) + " names no joint");
  NodeId id = graph().find(guide.joint);
  if (!id.is_valid())
    return error(ErrorCode::kNotFound, full_name() + ": guide " + std::to_string(i) + ": the scene has no node '" +
                                           guide.joint + "'");
  return id;
}

Result<Mat4> BuildContext::guide_world(int i) {
  if (i < 0 || i >= guide_count()) return error(ErrorCode::kNotFound, full_name() + ": no guide " + std::to_string(i));
  const Guide& guide = component_->guides[i];
  if (!guide.joint.empty()) {
    Result<NodeId> j = guide_joint(i);
    if (!j) return j.status();
    if (!scene_.is_transform(*j))
      return error(ErrorCode::kInvalidArgument, full_name() + ": guide " + std::to_string(i) + ": '" + guide.joint +
                                                    "' is not a transform");
    return Mat4(scene_.world_matrix(*j) * guide_values(guide));  // the values: an offset in the joint's space
  }
  return guide_values(guide);
}

std::string built_node_name(const std::string& naming_template, const std::string& rig, const std::string& component,
                            const std::string& name, const std::string& side, const std::string& role, int index) {
  const std::string t = naming_template.empty() ? std::string("{rig}_{component}_{role}{index}") : naming_template;
  std::string out;
  bool drop_next = false;  // an empty token takes the '_' after it
  for (std::size_t i = 0; i < t.size();) {
    if (t[i] == '{') {
      const std::size_t end = t.find('}', i);
      const std::string token = end == std::string::npos ? t.substr(i) : t.substr(i, end - i + 1);
      std::string value;
      if (token == "{rig}") value = rig;
      else if (token == "{component}") value = component;
      else if (token == "{name}") value = name;
      else if (token == "{side}") value = side;
      else if (token == "{role}") value = role;
      else if (token == "{index}") value = index >= 0 ? std::to_string(index) : std::string();
      else value = token;  // not a token: kept as written
      i = end == std::string::npos ? t.size() : end + 1;
      if (value.empty()) {
        if (i < t.size() && t[i] == '_') ++i;
        else if (!out.empty() && out.back() == '_') drop_next = true;
        continue;
      }
      out += value;
      continue;
    }
    out += t[i++];
  }
  if (drop_next && !out.empty() && out.back() == '_') out.pop_back();
  return out;
}

Result<NodeId> BuildContext::create(std::string_view type, std::string_view role, int index, int guide, NodeId parent) {
  const std::string name =
      built_node_name(naming_, rig_name(), component_ ? full_name() : std::string(), component_ ? component_->name : std::string(),
                      component_ ? side_name(component_->side) : std::string(), std::string(role), index);
  Result<NodeId> id = parent.is_valid() ? scene_.create(type, name, parent) : graph().create_node(type, name);
  if (!id) return id.status();
  Status s = link(*id, role, index, guide);
  if (!s) return s;
  return id;
}

Status BuildContext::link(NodeId id, std::string_view role, int index, int guide) {
  graph::Graph& g = graph();
  if (!g.node(id)) return error(ErrorCode::kNotFound, full_name() + ": link " + std::string(role) + ": no such node");
  Status s = g.set_tag(id, kTagRole, std::string(role));
  if (s && index >= 0) s = g.set_tag(id, kTagIndex, std::to_string(index));
  if (s) s = g.set_tag(id, kTagStep, step_);
  if (s && guide >= 0) s = g.set_tag(id, kTagGuide, std::to_string(guide));
  if (s && meta_.is_valid())
    s = g.connect(Plug{meta_, g.node(meta_)->type().attr_find("members"), -1},
                  Plug{id, g.node(id)->type().attr_find(graph::kMetaParentAttr), -1});
  return s;
}


Result<NodeId> BuildContext::create_group(std::string_view role, int index, const Mat4& world, NodeId parent) {
  Result<NodeId> id = create(scene::kTransformType, role, index, -1, parent);
  if (!id) return id;
  if (Status s = place_zeroed(scene_, *id, world, parent); !s) return s;
  return id;
}

Result<NodeId> BuildContext::create_control(std::string_view role, int index, int guide, const Mat4& world,
                                            NodeId parent) {
  Result<NodeId> id = create(scene::kControlType, role, index, guide, parent);
  if (!id) return id;
  if (Status s = place_zeroed(scene_, *id, world, parent); !s) return s;
  // Its rest as built, which mirroring relates the two sides by.
  if (Status s = graph().set_tag(*id, kTagRestWorld, rest_world_text(scene_.world_matrix(*id))); !s) return s;
  const ControlStyle style = control_style(role);
  if (Status s = scene::apply_control_shape(graph(), *id, style.shape, style.size, style.color); !s)
    return s.with_context(full_name() + " control '" + std::string(role) + "'");
  return id;
}

Status BuildContext::drive(NodeId driver, NodeId driven) {
  ConstraintSpec spec;
  spec.role = "drive";
  spec.space_role = "parentSpace";
  spec.targets = {driver};
  spec.channels = {"translate", "rotate", "scale"};
  return constrain(spec, driven, static_cast<int>(nodes("drive").size())).status();
}

Result<NodeId> BuildContext::constrain(const ConstraintSpec& spec, NodeId driven, int index) {
  graph::Graph& g = graph();
  const graph::Node* d = g.node(driven);
  const std::string where = full_name() + ": " + spec.role;
  if (!d || !scene_.is_transform(driven))
    return error(ErrorCode::kInvalidArgument, where + ": the driven is not a transform");
  if (spec.targets.empty()) return error(ErrorCode::kInvalidArgument, where + ": no target");
  auto plug = [&](NodeId n, const char* attr, int element = -1) {
    return Plug{n, g.node(n)->type().attr_find(attr), element};
  };
  const std::string name = d->name();
  Result<NodeId> c = create(spec.type, spec.role, index);
  if (!c) return c.status();
  const Mat4 driven_world = scene_.world_matrix(driven);
  std::vector<Mat4> offsets;
  Status s;
  for (std::size_t i = 0; s && i < spec.targets.size(); ++i) {
    s = g.connect(Plug{spec.targets[i], xform::kWorldMatrix, -1}, plug(*c, "targetWorldMatrix", static_cast<int>(i)));
    offsets.push_back(spec.maintain_offset
                          ? ops::constraints::compute_offset(scene_.world_matrix(spec.targets[i]), driven_world)
                          : Mat4(Mat4::Identity()));
  }
  if (s && spec.maintain_offset) s = g.set_value(plug(*c, "targetOffset"), Value(offsets));
  if (s && !spec.weights.empty()) s = g.set_value(plug(*c, "targetWeight"), Value(spec.weights));
  if (s && spec.space != ConstraintSpec::Space::kIdentity) {
    const NodeId space = spec.space == ConstraintSpec::Space::kParent ? g.parent(driven) : spec.space_node;
    Result<NodeId> inv =
        create(ops::util::kInverseMatrixType, spec.space_role.empty() ? spec.role + "Space" : spec.space_role, index);
    if (!inv) return inv.status();
    if (space.is_valid()) s = g.connect(Plug{space, xform::kWorldMatrix, -1}, plug(*inv, "inputMatrix"));
    if (s) s = g.set_value(plug(*inv, "offsetMatrix"), d->value(xform::kOffsetParentMatrix));
    if (s) s = g.connect(plug(*inv, "outputMatrix"), plug(*c, "parentInverseMatrix"));
  }
  // Euler channels in the driven's order, past its joint orient; rest values
  // are what the driven holds now.
  if (s) s = g.set_value(plug(*c, "rotateOrder"), d->value(xform::kRotateOrder));
  if (s && d->type().name() == scene::kJointType)
    s = g.set_value(plug(*c, "jointOrient"), d->value(scene::joint_attr::kJointOrient));
  if (s) s = g.set_value(plug(*c, "restTranslate"), d->value(xform::kTranslate));
  if (s) s = g.set_value(plug(*c, "restRotate"), d->value(xform::kRotate));
  if (s) s = g.set_value(plug(*c, "restScale"), d->value(xform::kScale));
  if (s && xform::is_quaternion_mode(*d))
    s = g.set_value(Plug{driven, xform::kRotateMode, -1}, Value(xform::kEulerMode));
  for (const char* ch : spec.channels) {
    if (!s) break;
    const Plug dst = plug(driven, ch);
    if (g.source(dst)) s = g.disconnect_input(dst);
    if (s) s = g.connect(plug(*c, ch), dst);
  }
  if (!s) return s.with_context(where + " on " + name);
  return c;
}

std::vector<NodeId> BuildContext::nodes(std::string_view role) const {
  std::vector<std::pair<int, NodeId>> hits;
  if (!meta_.is_valid()) return {};
  const graph::Graph& g = scene_.graph();
  for (NodeId m : meta_members(g, meta_)) {
    const graph::Node& n = *g.node(m);
    const std::string* r = n.tag_find(kTagRole);
    if (!r || *r != role) continue;
    const std::string* i = n.tag_find(kTagIndex);
    int index = 0;
    if (i) std::from_chars(i->data(), i->data() + i->size(), index);
    hits.emplace_back(index, m);
  }
  std::stable_sort(hits.begin(), hits.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<NodeId> out;
  for (const auto& h : hits) out.push_back(h.second);
  return out;
}

NodeId BuildContext::node(std::string_view role, int index) const {
  std::vector<NodeId> all = nodes(role);
  return index >= 0 && index < static_cast<int>(all.size()) ? all[index] : NodeId{};
}

Status BuildContext::publish_hook(int index, NodeId node) {
  graph::Graph& g = graph();
  if (!g.node(node)) return error(ErrorCode::kNotFound, "publish_hook: no such node");
  if (meta_parent(g, node) != meta_)
    return error(ErrorCode::kInvalidArgument, "publish_hook: " + g.node(node)->name() + " was not made by " + full_name());
  return g.set_tag(node, kTagHook, std::to_string(index));
}

NodeId BuildContext::attach_node() const { return attach_.is_valid() ? attach_ : rig_group("controls"); }

NodeId BuildContext::rig_group(std::string_view role) const {
  if (!root_.is_valid()) return {};
  const graph::Graph& g = scene_.graph();
  for (NodeId m : meta_members(g, root_)) {
    const std::string* r = g.node(m)->tag_find(kTagRole);
    if (r && *r == role) return m;
  }
  return {};
}
}  // namespace rigel::rig
