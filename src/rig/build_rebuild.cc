// Partial rebuilds (Build::rebuild_changed, build.h): only the components
// that changed are built again, on the rest pose, with the animation from
// outside the rig re-attached and, with KeepKeys::kWorld, converted so the
// controls stay where they were.
#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "build_internal.h"
#include "rigel/ops/anim/channel_keys.h"
#include "rigel/ops/util/space.h"
#include "rigel/rig/build.h"
#include "rigel/rig/meta.h"
#include "rigel/scene/transform_types.h"

namespace rigel::rig {

using namespace detail;

namespace {

// A component's own data, for telling what changed (children left out).
std::string signature(const Component& c) {
  std::ostringstream o;
  o.precision(17);
  o << c.type << '|' << c.name << '|' << side_name(c.side) << '|' << c.version << '|' << c.attach << '|';
  for (const std::string& id : c.after) o << id << ',';
  o << '|';
  for (const Guide& g : c.guides)
    o << g.name << ',' << g.joint << ',' << g.translate.transpose() << ',' << g.rotate.transpose() << ','
      << g.scale.transpose() << ';';
  o << '|';
  for (const ControlStyle& s : c.controls) o << s.role << ',' << s.shape << ',' << s.color << ',' << s.size << ';';
  o << '|';
  for (const Param& p : c.params) {
    o << p.name << '=';
    std::visit(
        [&](const auto& v) {
          if constexpr (std::is_same_v<std::decay_t<decltype(v)>, math::Vec3>) o << v.transpose();
          else o << v;
        },
        p.value);
    o << ';';
  }
  o << '|';
  for (const Feature& f : c.features) {
    o << f.name << '=' << f.enabled << '[';
    for (const FeatureSwitch& s : f.switches) o << s.name << '=' << s.enabled << ',';
    o << ']';
  }
  return o.str();
}

// The rest pose a rebuild builds on, whatever the scene's time: every
// member of the components kept (and of the rig itself) loses its time
// curves (animation), each such attribute taking its default, and every
// control's free channels are zeroed. What
// was there comes back afterwards, bit for bit (restore()).
class RestPose {
 public:
  Status enter(graph::Graph& g, const std::vector<NodeId>& nodes) {
    for (NodeId m : nodes) {
      const graph::Node* n = g.node(m);
      if (!n) continue;
      std::vector<graph::Connection> inputs;
      for (const graph::Connection& c : n->inputs()) {
        // Time curves only: every other input is the build's own wiring (from
        // the rig or the character's joints).
        if (ops::anim::curve_kind(g, c.src.node) == ops::anim::CurveKind::kOther) continue;
        inputs.push_back(c);
      }
      for (const graph::Connection& c : inputs) {
        remember(g, m, c.dst.attr);
        held_.push_back(c);
        if (Status s = g.disconnect(c.src, c.dst); !s) return s;
      }
      for (const graph::Connection& c : inputs) {
        const graph::AttrSpec& spec = n->type().attr(c.dst.attr);
        Value rest = n->type().default_value(c.dst.attr);
        if (std::holds_alternative<std::monostate>(rest)) rest = graph::zero_value(spec.type);
        if (c.dst.element >= 0) {
          const graph::AttrType scalar{spec.type.value, false};
          if (Status s = g.set_value(Plug{m, c.dst.attr, c.dst.element}, graph::zero_value(scalar)); !s) return s;
        } else if (Status s = g.set_value(Plug{m, c.dst.attr, -1}, rest); !s) {
          return s;
        }
      }
      if (is_control(g, m)) {
        for (graph::AttrIndex a : {graph::AttrIndex{xform::kTranslate}, graph::AttrIndex{xform::kRotate},
                                   graph::AttrIndex{xform::kRotateQuaternion}, graph::AttrIndex{xform::kScale},
                                   graph::AttrIndex{xform::kShear}})
          remember(g, m, a);
        if (Status s = zero_channels(g, m); !s) return s;
      }
    }
    return Status::ok();
  }

  // Puts back what enter() changed on nodes that still exist.
  Status restore(graph::Graph& g) {
    for (const auto& [plug, value] : values_) {
      if (!g.node(plug.node) || g.source(plug)) continue;
      if (Status s = g.set_value(plug, value); !s) return s;
    }
    for (const graph::Connection& c : held_) {
      if (!g.node(c.src.node) || !g.node(c.dst.node) || g.source(c.dst)) continue;
      if (Status s = g.connect(c.src, c.dst); !s) return s;
    }
    return Status::ok();
  }

 private:
  void remember(const graph::Graph& g, NodeId node, graph::AttrIndex attr) {
    const Plug p{node, attr, -1};
    for (const auto& v : values_)
      if (v.first == p) return;
    values_.emplace_back(p, g.node(node)->value(attr));
  }

  std::vector<std::pair<Plug, Value>> values_;
  std::vector<graph::Connection> held_;
};

// An input of a rebuilt control from outside the rig (an animation curve,
// say), remembered by (rigId, role, index, attribute) to re-attach it to the
// new control, never by name.
struct Kept {
  std::string rig_id, role, index, attr;
  std::int32_t element = -1;   // an array element (fingerCurl[k])
  std::int8_t component = -1;  // x, y, z of a double3 (a curve per component)
  Plug src;
};

// A keyed control of a rebuilt component and where it was in the world at
// each of its key times (--keep-keys world).
struct KeyedControl {
  std::string rig_id, role, index;
  std::vector<double> times;
  std::vector<Mat4> worlds;
};

// The control of component `rig_id` with `role` and `index`, or invalid.
NodeId member_with(const graph::Graph& g, NodeId root, const std::string& rig_id, const std::string& role,
                   const std::string& index) {
  const NodeId meta = find_component(g, root, rig_id);
  if (!meta.is_valid()) return {};
  for (NodeId m : meta_members(g, meta)) {
    const graph::Node& n = *g.node(m);
    const std::string* r = n.tag_find(kTagRole);
    const std::string* i = n.tag_find(kTagIndex);
    if (r && *r == role && (i ? *i : std::string()) == index) return m;
  }
  return {};
}

std::string frame_label(const graph::Graph& g, double t) {
  std::ostringstream out;
  out << "frame " << t * g.fps();
  return out.str();
}

// The controls that `kept` holds time curves for, with the world matrix of
// each at each of its key times (the scene's time is restored).
std::vector<KeyedControl> keyed_controls(scene::Scene& scene, NodeId root, const std::vector<Kept>& kept) {
  graph::Graph& g = scene.graph();
  std::vector<KeyedControl> out;
  for (const Kept& k : kept) {
    if (ops::anim::curve_kind(g, k.src.node) == ops::anim::CurveKind::kOther) continue;
    auto it = std::find_if(out.begin(), out.end(), [&](const KeyedControl& c) {
      return c.rig_id == k.rig_id && c.role == k.role && c.index == k.index;
    });
    if (it == out.end()) it = out.insert(out.end(), KeyedControl{k.rig_id, k.role, k.index, {}, {}});
    for (double t : ops::anim::curve_key_times(g, k.src.node)) it->times.push_back(t);
  }
  std::vector<NodeId> nodes;
  std::vector<double> all;
  for (KeyedControl& c : out) {
    std::sort(c.times.begin(), c.times.end());
    std::vector<double> unique;
    for (double t : c.times)
      if (unique.empty() || t - unique.back() > ops::anim::kKeyTimeTolerance) unique.push_back(t);
    c.times = std::move(unique);
    c.worlds.resize(c.times.size());
    nodes.push_back(member_with(g, root, c.rig_id, c.role, c.index));
    all.insert(all.end(), c.times.begin(), c.times.end());
  }
  // One pass over time, every control at once.
  std::sort(all.begin(), all.end());
  all.erase(std::unique(all.begin(), all.end()), all.end());
  const double now = g.time();
  for (double t : all) {
    g.set_time(t);
    for (std::size_t i = 0; i < out.size(); ++i) {
      auto at = std::find(out[i].times.begin(), out[i].times.end(), t);
      if (at != out[i].times.end() && scene.is_transform(nodes[i]))
        out[i].worlds[static_cast<std::size_t>(at - out[i].times.begin())] = scene.world_matrix(nodes[i]);
    }
  }
  g.set_time(now);
  return out;
}

bool same_value(const Value& a, const Value& b) {
  if (const auto* q = std::get_if<math::Quat>(&a)) return std::abs(std::abs(q->dot(std::get<math::Quat>(b))) - 1.0) < 1e-14;
  return (std::get<math::Vec3>(a) - std::get<math::Vec3>(b)).cwiseAbs().maxCoeff() < 1e-10;
}

// A control whose world matrix is this close to where it was is in place.
constexpr double kInPlace = 1e-9;

// Writes keys on the new controls so each `keyed` control is where it was
// at each of its key times (Build::KeepKeys::kWorld); parents first, so a
// child reads its parent's converted pose.
Status restore_world_keys(scene::Scene& scene, NodeId root, const std::vector<KeyedControl>& keyed) {
  graph::Graph& g = scene.graph();
  struct Item {
    const KeyedControl* control;
    NodeId node;
    int depth;
  };
  std::vector<Item> items;
  for (const KeyedControl& c : keyed) {
    const NodeId node = member_with(g, root, c.rig_id, c.role, c.index);
    if (scene.is_transform(node) && !c.times.empty()) items.push_back(Item{&c, node, scene.depth(node)});
  }
  std::stable_sort(items.begin(), items.end(), [](const Item& a, const Item& b) { return a.depth < b.depth; });
  const double now = g.time();
  Status s;
  for (const Item& item : items) {
    const KeyedControl& c = *item.control;
    const std::string name = g.node(item.node)->name();
    // Where the kept keys already put the control where it was (its rest
    // did not change), they stay as they are, bit for bit.
    bool in_place = true;
    for (std::size_t i = 0; i < c.times.size() && in_place; ++i) {
      g.set_time(c.times[i]);
      in_place = (scene.world_matrix(item.node) - c.worlds[i]).cwiseAbs().maxCoeff() <= kInPlace;
    }
    if (in_place) continue;
    std::vector<scene::Scene::LocalChannels> need;
    for (std::size_t i = 0; i < c.times.size() && s; ++i) {
      g.set_time(c.times[i]);
      Result<scene::Scene::LocalChannels> ch = scene.channels_for_world(item.node, c.worlds[i]);
      if (!ch) s = ch.status().with_context("keep world positions of '" + name + "' at " + frame_label(g, c.times[i]));
      else need.push_back(std::move(*ch));
    }
    if (!s) break;
    // Euler keys continuous: each angle within 180 degrees of the one before.
    if (need[0].rotation_attr == xform::kRotate) {
      for (std::size_t i = 1; i < need.size(); ++i) {
        auto& r = std::get<math::Vec3>(need[i].rotation);
        const auto& p = std::get<math::Vec3>(need[i - 1].rotation);
        for (int k = 0; k < 3; ++k) r[k] += 360.0 * std::round((p[k] - r[k]) / 360.0);
      }
    }
    const graph::Node& n = *g.node(item.node);
    for (graph::AttrIndex attr : {graph::AttrIndex{xform::kTranslate}, need[0].rotation_attr,
                                  graph::AttrIndex{xform::kScale}, graph::AttrIndex{xform::kShear}}) {
      std::vector<Value> values;
      for (const auto& ch : need) {
        if (attr == xform::kTranslate) values.push_back(ch.translate);
        else if (attr == xform::kScale) values.push_back(ch.scale);
        else if (attr == xform::kShear) values.push_back(ch.shear);
        else values.push_back(ch.rotation);
      }
      bool keyed_attr = false;
      for (const graph::Connection& conn : n.inputs()) keyed_attr = keyed_attr || conn.dst.attr == attr;
      // A channel that already holds what is needed at every time is left alone.
      bool holds = true;
      for (std::size_t i = 0; i < values.size() && holds; ++i) {
        g.set_time(c.times[i]);
        holds = same_value(g.evaluate(item.node, attr), values[i]);
      }
      if (holds) continue;
      bool constant = true;
      for (const Value& v : values) constant = constant && same_value(v, values[0]);
      if (!keyed_attr && constant) {
        // A free channel that keeps one value stays free.
        if (!same_value(n.value(attr), values[0])) s = g.set_value(Plug{item.node, attr, -1}, values[0]);
      } else {
        // All of a channel's keys in one pass (linear in the keys: a long
        // shot's update does not copy the key arrays once per key).
        std::vector<math::Vec3> vectors;
        std::vector<math::Quat> quats;
        for (const Value& v : values) {
          if (const auto* q = std::get_if<math::Quat>(&v)) quats.push_back(*q);
          else vectors.push_back(std::get<math::Vec3>(v));
        }
        s = quats.empty() ? ops::anim::write_channel_keys(g, item.node, attr, c.times, vectors, true)
                          : ops::anim::write_channel_keys(g, item.node, attr, c.times, quats, true);
      }
      if (!s) break;
    }
    if (!s) break;
    for (std::size_t i = 0; i < c.times.size() && s; ++i) {
      g.set_time(c.times[i]);
      const Mat4 world = scene.world_matrix(item.node);
      const double miss = (world - c.worlds[i]).cwiseAbs().maxCoeff();
      if (!(miss <= 1e-6)) {
        std::ostringstream out;
        out << "keep world positions: '" << name << "' misses its place at " << frame_label(g, c.times[i]) << " by "
            << miss;
        s = error(ErrorCode::kInvalidArgument, out.str());
      }
    }
    if (!s) break;
  }
  g.set_time(now);
  return s;
}


// A component before an update: what tells whether it changed.
struct OldComponent {
  std::string signature, version, parent;
};

// Which components each component's controls take spaces from (rig/spaces.h),
// by rigId: the components of its spaceSwitches' targets.
std::map<std::string, std::set<std::string>> space_sources(const graph::Graph& g, NodeId root) {
  std::map<std::string, std::set<std::string>> out;
  for (NodeId meta : rig_components(g, root)) {
    const std::string id = meta_string(g, meta, "rigId");
    for (NodeId m : meta_members(g, meta)) {
      if (g.node(m)->type().name() != ops::util::kSpaceSwitchType) continue;
      for (const graph::Connection& c : g.node(m)->inputs()) {
        if (c.dst.attr != ops::util::space_attr::kTargetWorldMatrix) continue;
        const NodeId from = component_of(g, c.src.node);
        if (from.is_valid() && from != meta && rig_of(g, from) == root) out[id].insert(meta_string(g, from, "rigId"));
      }
    }
  }
  return out;
}

// The rigIds an update destructs and constructs again: components new or
// changed (as `when` says), moved to another parent, what hangs from them
// (their hooks are made again), what builds after them (it read them), and what takes a space from them or from a
// component that is gone (the space's target is made again).
std::set<std::string> dirty_components(const std::vector<const Component*>& components, const std::vector<int>& parent,
                                       const std::vector<AttachTarget>& attach, const std::vector<std::vector<int>>& after,
                                       const std::map<std::string, OldComponent>& old, Build::Rebuild when,
                                       const std::map<std::string, std::set<std::string>>& follows) {
  std::set<std::string> dirty;
  for (std::size_t i = 0; i < components.size(); ++i) {
    const Component& c = *components[i];
    const int p = parent[i];
    const std::string parent_id = p >= 0 ? components[p]->rig_id : "";
    auto it = old.find(c.rig_id);
    const bool changed = it == old.end() || it->second.parent != parent_id ||
                         (when == Build::Rebuild::kAll) ||
                         (when == Build::Rebuild::kChanged && it->second.signature != signature(c)) ||
                         (when == Build::Rebuild::kNewerVersion && compare_versions(it->second.version, c.version) != 0);
    if (changed) dirty.insert(c.rig_id);
  }
  for (bool grew = true; grew;) {
    grew = false;
    for (std::size_t i = 0; i < components.size(); ++i) {
      if (dirty.count(components[i]->rig_id)) continue;
      const int p = parent[i];
      const int a = attach[i].component;
      bool space_dirty = false;
      if (auto f = follows.find(components[i]->rig_id); f != follows.end())
        for (const std::string& from : f->second) {
          const bool present = std::any_of(components.begin(), components.end(),
                                           [&](const Component* c) { return c->rig_id == from; });
          space_dirty = space_dirty || dirty.count(from) || !present;
        }
      const bool read_dirty = std::any_of(after[i].begin(), after[i].end(),
                                          [&](int k) { return dirty.count(components[k]->rig_id) != 0; });
      if ((p >= 0 && dirty.count(components[p]->rig_id)) || (a >= 0 && dirty.count(components[a]->rig_id)) ||
          space_dirty || read_dirty) {
        dirty.insert(components[i]->rig_id);
        grew = true;
      }
    }
  }
  return dirty;
}

// Animation on the controls of what is rebuilt (the components `ids` that
// are dirty or removed): curves and other inputs from outside the rig,
// remembered by (rigId, role, index, attribute) so they re-attach to the
// new controls, never by name.
std::vector<Kept> outside_inputs(const graph::Graph& g, NodeId root, const std::vector<std::string>& ids,
                                 const std::set<std::string>& dirty, const std::set<std::string>& removed) {
  std::vector<Kept> kept;
  for (const std::string& id : ids) {
    if (!dirty.count(id) && !removed.count(id)) continue;
    NodeId meta = find_component(g, root, id);
    for (NodeId m : meta_members(g, meta)) {
      const graph::Node& n = *g.node(m);
      const std::string* role = n.tag_find(kTagRole);
      if (!role) continue;
      const std::string* index = n.tag_find(kTagIndex);
      for (const graph::Connection& c : n.inputs()) {
        if (n.type().attr(c.dst.attr).name == graph::kMetaParentAttr || c.dst.attr == xform::kParentMatrix) continue;
        if (rig_of(g, c.src.node) == root) continue;  // the rig's own wiring is rebuilt
        kept.push_back(Kept{id, *role, index ? *index : "", n.type().attr(c.dst.attr).name, c.dst.element, c.dst.component,
                              c.src});
      }
    }
  }
  return kept;
}

// Disconnects each kept input from its old control; the source keeps going.
Status detach_kept(graph::Graph& g, NodeId root, const std::vector<Kept>& kept) {
  for (const Kept& k : kept) {
    std::optional<graph::Connection> link;
    for (const graph::Connection& c : g.node(k.src.node)->outputs()) {
      const graph::Node& d = *g.node(c.dst.node);
      if (c.src.attr == k.src.attr && c.src.element == k.src.element && d.type().attr(c.dst.attr).name == k.attr &&
          c.dst.element == k.element && c.dst.component == k.component &&
          rig_of(g, c.dst.node) == root && component_of(g, c.dst.node) == find_component(g, root, k.rig_id)) {
        link = c;  // a copy: disconnecting changes the list
        break;
      }
    }
    if (link)
      if (Status s = g.disconnect(link->src, link->dst); !s) return s;
  }
  return Status::ok();
}

// Connects each kept input again where the new rig has the same control.
Status reattach_kept(graph::Graph& g, NodeId root, const std::vector<Kept>& kept) {
  for (const Kept& k : kept) {
    NodeId meta = find_component(g, root, k.rig_id);
    if (!meta.is_valid()) continue;  // the component is gone
    for (NodeId m : meta_members(g, meta)) {
      const graph::Node& n = *g.node(m);
      const std::string* role = n.tag_find(kTagRole);
      const std::string* index = n.tag_find(kTagIndex);
      if (!role || *role != k.role || (index ? *index : std::string()) != k.index) continue;
      const graph::AttrIndex a = n.type().attr_find(k.attr);
      const Plug dst{m, a, k.element, k.component};
      if (a == graph::kNoAttr || g.source(dst)) break;
      if (Status s = g.connect(k.src, dst); !s) return s;
      break;
    }
  }
  return Status::ok();
}

}  // namespace

bool detail::is_control(const graph::Graph& g, NodeId id) {
  const graph::Node* n = g.node(id);
  return n && n->type().name() == scene::kControlType;
}

Status detail::zero_channels(graph::Graph& g, NodeId control) {
  auto free = [&](graph::AttrIndex a) { return !g.source(Plug{control, a, -1}).has_value(); };
  Status s;
  if (free(xform::kTranslate)) s = g.set_value(Plug{control, xform::kTranslate, -1}, Value(math::Vec3(math::Vec3::Zero())));
  if (s && free(xform::kRotate)) s = g.set_value(Plug{control, xform::kRotate, -1}, Value(math::Vec3(math::Vec3::Zero())));
  if (s && free(xform::kRotateQuaternion))
    s = g.set_value(Plug{control, xform::kRotateQuaternion, -1}, Value(math::Quat(math::Quat::Identity())));
  if (s && free(xform::kScale)) s = g.set_value(Plug{control, xform::kScale, -1}, Value(math::Vec3(math::Vec3::Ones())));
  if (s && free(xform::kShear)) s = g.set_value(Plug{control, xform::kShear, -1}, Value(math::Vec3(math::Vec3::Zero())));
  return s;
}

Result<std::vector<std::string>> Build::rebuild_changed(Definition next, Rebuild when, KeepKeys keep) {
  if (Status s = sync(); !s) return s;
  if (position_ != static_cast<int>(plan_.size()))
    return error(ErrorCode::kInvalidArgument, "rebuild: the build is not complete (step " + std::to_string(position_) +
                                                  " of " + std::to_string(plan_.size()) + ")");
  if (next.name != definition_.name)
    return error(ErrorCode::kInvalidArgument, "rebuild: the rig is '" + definition_.name + "', not '" + next.name + "'");
  std::map<std::string, OldComponent> old;
  for (std::size_t i = 0; i < components_.size(); ++i) {
    const int p = records_->parent[i];
    old[components_[i]->rig_id] = OldComponent{signature(*components_[i]), components_[i]->version,
                                               p >= 0 ? components_[p]->rig_id : ""};
  }
  const std::map<std::string, std::set<std::string>> follows = space_sources(scene_.graph(), root());
  const Definition old_def = definition_;
  std::vector<std::string> old_ids;
  for (const Component* c : components_) old_ids.push_back(c->rig_id);
  const std::vector<PlannedStep> old_plan = plan_;

  definition_ = std::move(next);
  if (Status s = replan(); !s) {
    definition_ = old_def;
    (void)replan();
    return s;
  }
  const std::set<std::string> dirty =
      dirty_components(components_, records_->parent, records_->attach, records_->after, old, when, follows);
  std::set<std::string> removed;
  for (const std::string& id : old_ids) {
    bool present = false;
    for (const Component* c : components_) present = present || c->rig_id == id;
    if (!present) removed.insert(id);
  }
  graph::Graph& g = scene_.graph();
  NodeId root = this->root();
  const std::vector<Kept> kept = outside_inputs(g, root, old_ids, dirty, removed);

  // --keep-keys world: where each keyed control is at each of its key times.
  std::vector<KeyedControl> keyed;
  if (keep == KeepKeys::kWorld) keyed = keyed_controls(scene_, root, kept);

  g.begin_transaction("update " + definition_.name);
  std::set<std::string> owners;
  // The data step first, back: it comes last and may have changed what the
  // rebuilt components own (their controls' shapes). It is done again at
  // the end, so an update re-imports the data (the files may have changed).
  Status s;
  if (auto data = records_->done.find({"", kDataStep}); data != records_->done.end()) {
    s = undo_record(g, data->second);
    records_->done.erase(data);
    records_->text.erase("");
  }
  if (s) s = detach_kept(g, root, kept);
  // Build on the rest pose, not on the pose at the scene's time.
  RestPose rest;
  if (s) {
    std::vector<NodeId> still = meta_members(g, root);
    for (const std::string& id : old_ids) {
      if (dirty.count(id) || removed.count(id)) continue;
      for (NodeId m : meta_members(g, find_component(g, root, id))) still.push_back(m);
    }
    s = rest.enter(g, still);
  }
  // Destruct, newest first, the old steps of dirty and removed components.
  for (int i = static_cast<int>(old_plan.size()) - 1; i >= 0 && s; --i) {
    if (old_plan[i].component < 0) continue;
    const std::string& id = old_ids[old_plan[i].component];
    if (!dirty.count(id) && !removed.count(id)) continue;
    auto it = records_->done.find({id, old_plan[i].step});
    if (it == records_->done.end()) continue;
    s = undo_record(g, it->second);
    records_->done.erase(it);
    records_->text.erase(id);
  }
  // Construct theirs in the new plan's order.
  for (std::size_t i = 0; i < plan_.size() && s; ++i) {
    if (plan_[i].component < 0) continue;
    const std::string& id = components_[plan_[i].component]->rig_id;
    if (!dirty.count(id)) continue;
    s = construct(static_cast<int>(i));
    owners.insert(id);
  }
  position_ = static_cast<int>(plan_.size());
  if (s) s = reattach_kept(g, root, kept);
  if (s) s = rest.restore(g);
  if (s && !keyed.empty()) s = restore_world_keys(scene_, root, keyed);
  for (std::size_t i = 0; i < plan_.size() && s; ++i)
    if (plan_[i].component < 0 && plan_[i].step == kDataStep) s = construct(static_cast<int>(i));
  if (s) s = g.set_value(Plug{root, g.node(root)->type().attr_find("version"), -1}, Value(definition_.version));
  for (const Component* c : components_) {
    if (!s || dirty.count(c->rig_id)) continue;
    NodeId meta = find_component(g, root, c->rig_id);
    if (meta_string(g, meta, "version") != c->version)
      s = g.set_value(Plug{meta, g.node(meta)->type().attr_find("version"), -1}, Value(c->version));
  }
  for (const std::string& owner : owners)
    if (s) s = save_state(owner);
  if (s) s = save_state("");
  if (!s) {
    g.rollback_transaction();
    definition_ = old_def;
    (void)replan();
    records_->done.clear();
    return s.with_context("update " + definition_.name);
  }
  g.commit_transaction();
  std::vector<std::string> out;
  for (const Component* c : components_)
    if (dirty.count(c->rig_id)) out.push_back(c->rig_id);
  for (const std::string& id : removed) out.push_back(id);
  return out;
}

}  // namespace rigel::rig
