// A build's plan (components in build order, their steps) and stepping
// through it (build.h): each forward or back constructs or destructs one
// step as one undo step.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <optional>
#include <set>
#include <string>

#include "build_internal.h"
#include "rigel/rig/build.h"
#include "rigel/rig/component.h"
#include "rigel/rig/meta.h"
#include "rigel/scene/transform_types.h"

namespace rigel::rig {

using namespace detail;

namespace {

const Feature* find_feature(const std::vector<Feature>& list, std::string_view name) {
  for (const Feature& f : list)
    if (f.name == name) return &f;
  return nullptr;
}

// Whether a step of `c` (null: the rig's own) that names `feature` and
// switch `sw` runs: the component's feature, else the rig's, decides.
bool step_enabled(const Definition& d, const Component* c, const std::string& feature, const std::string& sw) {
  if (feature.empty()) return true;
  const Feature* f = c ? find_feature(c->features, feature) : nullptr;
  if (!f) f = find_feature(d.features, feature);
  if (!f) return true;
  if (!f->enabled) return false;
  if (sw.empty()) return true;
  for (const FeatureSwitch& s : f->switches)
    if (s.name == sw) return s.enabled;
  return true;
}

// The bind values (kTagBind) of the keyable scalars of the nodes a step
// made that are not transforms (a limb's fkIk, a foot's roll): what a bind
// pose reset gives them back. Controls need none: they are built zeroed.
Status record_bind_values(graph::Graph& g, NodeId meta, const std::string& step) {
  if (!g.node(meta)) return Status::ok();
  for (NodeId m : meta_members(g, meta)) {
    const graph::Node& n = *g.node(m);
    const std::string* made = n.tag_find(kTagStep);
    if (!made || *made != step || n.type().world_output() != graph::kNoAttr) continue;
    std::string text;
    for (graph::AttrIndex a = 0; a < static_cast<graph::AttrIndex>(n.type().attr_count()); ++a) {
      const graph::AttrSpec& spec = n.type().attr(a);
      if (!(spec.flags & graph::kKeyable) || !(spec.flags & graph::kInput) || spec.type.array ||
          spec.type.value != graph::ValueType::kDouble)
        continue;
      const auto* v = std::get_if<double>(&g.evaluate(m, a));
      if (!v) continue;
      char buffer[64];
      std::snprintf(buffer, sizeof buffer, "%.17g", *v);
      text += (text.empty() ? "" : ";") + spec.name + "=" + buffer;
    }
    if (!text.empty())
      if (Status s = g.set_tag(m, kTagBind, text); !s) return s;
  }
  return Status::ok();
}

}  // namespace

Status detail::import_definition_data(scene::Scene& scene, const Definition& d, const ComponentFactory& factory,
                                      NodeId root) {
  for (const DataImport& x : d.data) {
    std::string where = d.source.empty() ? std::string("definition") : d.source;
    if (x.where.line > 0) {
      where += ':';
      where += std::to_string(x.where.line);
      where += ':';
      where += std::to_string(x.where.column);
    }
    where += ": data ";
    where += x.kind;
    where += " '";
    where += x.file;
    where += '\'';
    if (!factory.data_importer())
      return error(ErrorCode::kUnsupported,
                   where + ": this build has no data importer (build with the tools layer's components)");
    std::filesystem::path file(x.file);
    if (file.is_relative()) file = std::filesystem::path(d.source).parent_path() / file;
    if (Status s = factory.data_importer()(scene, root, x, file); !s) return s.with_context(where);
  }
  return Status::ok();
}

Status Build::replan() {
  const Definition& d = definition_;
  components_.clear();
  std::vector<int> parent;
  std::function<void(const Component&, int)> walk = [&](const Component& c, int p) {
    const int me = static_cast<int>(components_.size());
    components_.push_back(&c);
    parent.push_back(p);
    for (const Component& child : c.children) walk(child, me);
  };
  for (const Component& root : d.components) walk(root, -1);
  const int n = static_cast<int>(components_.size());

  // Classes, unique ids and names.
  std::set<std::string> ids, names;
  for (const Component* c : components_) {
    const std::string who = "component '" + c->full_name() + "'";
    if (!factory_.find(c->type))
      return error(ErrorCode::kNotFound, "build: " + who + ": no component class for type '" + c->type + "'");
    if (c->rig_id.empty() || !ids.insert(c->rig_id).second)
      return error(ErrorCode::kInvalidArgument, "build: " + who + ": missing or duplicate rigId");
    if (!names.insert(c->full_name()).second)
      return error(ErrorCode::kInvalidArgument, "build: two components are named '" + c->full_name() + "'");
  }
  // Attach targets: "HOOK" of the parent, or "OTHER.HOOK" of another component.
  std::vector<AttachTarget> attach(n);
  auto find_component_index = [&](std::string_view key) {
    for (int i = 0; i < n; ++i)
      if (components_[i]->rig_id == key || components_[i]->full_name() == key || components_[i]->name == key) return i;
    return -1;
  };
  for (int i = 0; i < n; ++i) {
    const Component& c = *components_[i];
    attach[i] = AttachTarget{parent[i], c.attach};
    if (const std::size_t dot = c.attach.find('.'); dot != std::string::npos) {
      const int other = find_component_index(std::string_view(c.attach).substr(0, dot));
      if (other >= 0) attach[i] = AttachTarget{other, c.attach.substr(dot + 1)};
    }
    if (attach[i].component == i)
      return error(ErrorCode::kCycle, "build: component '" + c.full_name() + "' attaches to itself");
    if (attach[i].component >= 0) {
      const Component& target = *components_[attach[i].component];
      const ComponentSchema* ts = factory_.schemas().find(target.type);
      if (!ts || !resolve_hook(ts->hook_names(target), attach[i].hook))
        return error(ErrorCode::kNotFound, "build: component '" + c.full_name() + "' attaches to hook '" +
                                               attach[i].hook + "', which '" + target.full_name() + "' does not have");
    }
  }
  // Order: parents and attach targets first, file order otherwise (Kahn).
  std::vector<int> order;
  std::vector<int> state(n, 0);
  std::vector<std::vector<int>> deps(n);
  // What each builds after (Component::after), by index.
  std::vector<std::vector<int>> after(n);
  for (int i = 0; i < n; ++i) {
    for (const std::string& id : components_[i]->after) {
      int other = -1;
      for (int k = 0; k < n && other < 0; ++k)
        if (components_[k]->rig_id == id) other = k;
      if (other < 0 || other == i)
        return error(ErrorCode::kNotFound, "build: component '" + components_[i]->full_name() + "': after '" + id +
                                               "': no other component has that rigId");
      after[i].push_back(other);
    }
  }
  for (int i = 0; i < n; ++i) {
    if (parent[i] >= 0) deps[i].push_back(parent[i]);
    if (attach[i].component >= 0 && attach[i].component != parent[i]) deps[i].push_back(attach[i].component);
    for (int a : after[i]) deps[i].push_back(a);
  }
  std::vector<char> placed(n, 0);
  while (static_cast<int>(order.size()) < n) {
    bool progress = false;
    for (int i = 0; i < n; ++i) {
      if (placed[i]) continue;
      if (std::all_of(deps[i].begin(), deps[i].end(), [&](int d) { return placed[d] != 0; })) {
        placed[i] = 1;
        order.push_back(i);
        progress = true;
      }
    }
    if (!progress) {
      std::string names_in_cycle;
      for (int i = 0; i < n; ++i)
        if (!placed[i]) names_in_cycle += (names_in_cycle.empty() ? "" : ", ") + components_[i]->full_name();
      return error(ErrorCode::kCycle, "build: components attach to each other in a cycle: " + names_in_cycle);
    }
  }
  std::vector<const Component*> ordered;
  std::vector<int> new_index(n);
  for (int k = 0; k < n; ++k) {
    new_index[order[k]] = k;
    ordered.push_back(components_[order[k]]);
  }
  records_->parent.assign(n, -1);
  records_->attach.assign(n, AttachTarget{});
  records_->after.assign(n, {});
  for (int i = 0; i < n; ++i) {
    for (int a : after[i]) records_->after[new_index[i]].push_back(new_index[a]);
    records_->parent[new_index[i]] = parent[i] >= 0 ? new_index[parent[i]] : -1;
    records_->attach[new_index[i]] =
        AttachTarget{attach[i].component >= 0 ? new_index[attach[i].component] : -1, attach[i].hook};
  }
  components_ = std::move(ordered);

  // Steps.
  steps_.clear();
  plan_.clear();
  plan_.push_back(PlannedStep{-1, kRigStep, "", "", true});
  for (int i = 0; i < n; ++i) {
    const Component& c = *components_[i];
    steps_.push_back(factory_.find(c.type)->steps(c));
    std::set<std::string> step_names{kMetaStep};
    plan_.push_back(PlannedStep{i, kMetaStep, "", "", true});
    for (const Step& s : steps_.back()) {
      if (!step_names.insert(s.name).second)
        return error(ErrorCode::kInvalidArgument, "build: component type '" + c.type + "' has two steps named '" + s.name + "'");
      plan_.push_back(PlannedStep{i, s.name, s.feature, s.switch_name, step_enabled(definition_, &c, s.feature, s.switch_name)});
    }
  }
  // The hand-made data last: it changes what the components made (control
  // shapes) and what the character holds (skin weights).
  if (!d.data.empty()) plan_.push_back(PlannedStep{-1, kDataStep, "", "", true});
  return Status::ok();
}

Status Build::construct(int index) {
  const PlannedStep& p = plan_[index];
  if (!p.enabled) return Status::ok();
  graph::Graph& g = scene_.graph();
  const std::string key = key_of(*this, p.component);
  const Component* comp = p.component >= 0 ? components_[p.component] : nullptr;

  // The manager is shared by every rig: made outside any record, removed by
  // remove() when no rig is left.
  if (!meta_manager(g).is_valid()) {
    if (Result<NodeId> m = g.create_node(kMetaManagerType, "metaManager"); !m) return m.status();
  }

  BuildContext ctx(scene_, definition_);
  ctx.edit_mode_ = options_.edit_mode;
  ctx.naming_ = options_.naming_template;
  ctx.step_ = p.step;
  ctx.root_ = root();
  if (comp) {
    ctx.component_ = comp;
    ctx.schema_ = factory_.schemas().find(comp->type);
    ctx.meta_ = find_component(g, ctx.root_, comp->rig_id);
    const AttachTarget& at = records_->attach[p.component];
    if (at.component >= 0) {
      NodeId target_meta = find_component(g, ctx.root_, components_[at.component]->rig_id);
      const ComponentSchema* ts = factory_.schemas().find(components_[at.component]->type);
      const std::optional<int> hook = resolve_hook(ts->hook_names(*components_[at.component]), at.hook);
      for (NodeId m : meta_members(g, target_meta)) {
        const std::string* h = g.node(m)->tag_find(kTagHook);
        if (h && hook && *h == std::to_string(*hook)) ctx.attach_ = m;
      }
      if (!ctx.attach_.is_valid())
        return error(ErrorCode::kNotFound, "build " + comp->full_name() + ": '" +
                                               components_[at.component]->full_name() + "' published no hook '" +
                                               at.hook + "'");
    }
  }

  StepRecord record;
  record.step = p.step;
  Status status;
  {
    Recorder recorder(g, record);
    if (p.component < 0 && p.step == kDataStep) {
      status = import_definition_data(scene_, definition_, factory_, ctx.root_);
    } else if (p.component < 0) {
      // The rig's own step: its metaRoot and groups.
      Result<NodeId> r = g.create_node(kMetaRootType, definition_.name + "_meta");
      if (!r) return r.status();
      auto set = [&](NodeId node, const char* attr, Value v) {
        return g.set_value(Plug{node, g.node(node)->type().attr_find(attr), -1}, std::move(v));
      };
      status = set(*r, "rigName", Value(definition_.name));
      if (status) status = set(*r, "version", Value(definition_.version));
      if (status) status = set(*r, "definitionPath", Value(definition_.source));
      if (status && options_.edit_mode) status = set(*r, "editMode", Value(true));
      if (status && !options_.naming_template.empty()) status = set(*r, "namingTemplate", Value(options_.naming_template));
      if (status) {
        NodeId mgr = meta_manager(g);
        status = g.connect(Plug{mgr, g.node(mgr)->type().attr_find("metaRoots"), -1},
                           Plug{*r, g.node(*r)->type().attr_find(graph::kMetaParentAttr), -1});
      }
      ctx.root_ = *r;
      ctx.meta_ = *r;
      if (status) {
        Result<NodeId> top = ctx.create(scene::kTransformType, "top", -1, -1, NodeId{});
        Result<NodeId> controls = top ? ctx.create(scene::kTransformType, "controls", -1, -1, *top) : top;
        Result<NodeId> still = top ? ctx.create(scene::kTransformType, "noTransform", -1, -1, *top) : top;
        if (!top) status = top.status();
        else if (!controls) status = controls.status();
        else if (!still) status = still.status();
      }
    } else if (p.step == kMetaStep) {
      Result<NodeId> m = g.create_node(kMetaComponentType, definition_.name + "_" + comp->full_name() + "_meta");
      if (!m) return m.status();
      auto set = [&](const char* attr, Value v) {
        return g.set_value(Plug{*m, g.node(*m)->type().attr_find(attr), -1}, std::move(v));
      };
      status = set("metaType", Value(comp->type));
      if (status) status = set("componentName", Value(comp->full_name()));
      if (status) status = set("side", Value(std::string(side_name(comp->side))));
      if (status) status = set("version", Value(comp->version));
      if (status) status = set("rigId", Value(comp->rig_id));
      if (status) {
        const int parent = records_->parent[p.component];
        NodeId up = parent >= 0 ? find_component(g, ctx.root_, components_[parent]->rig_id) : ctx.root_;
        status = g.connect(Plug{up, g.node(up)->type().attr_find("metaChildren"), -1},
                           Plug{*m, g.node(*m)->type().attr_find(graph::kMetaParentAttr), -1});
      }
    } else {
      const std::vector<Step>& steps = steps_[p.component];
      auto it = std::find_if(steps.begin(), steps.end(), [&](const Step& s) { return s.name == p.step; });
      status = it->construct ? it->construct(ctx) : Status::ok();
      if (status) status = record_bind_values(g, ctx.meta_, p.step);
    }
    if (status && !recorder.failure().empty()) status = error(ErrorCode::kInvalidArgument, recorder.failure());
  }
  if (!status) return status.with_context("build " + (comp ? comp->full_name() + "/" : std::string()) + p.step);
  records_->done[{key, p.step}] = std::move(record);
  records_->text.erase(key);  // save_state() writes and remembers the new text
  return Status::ok();
}

Status Build::destruct(int index) {
  const PlannedStep& p = plan_[index];
  const std::string key = key_of(*this, p.component);
  auto it = records_->done.find({key, p.step});
  if (it == records_->done.end()) return Status::ok();  // passed over
  if (Status s = undo_record(scene_.graph(), it->second); !s) return s;
  records_->done.erase(it);
  records_->text.erase(key);
  return Status::ok();
}

Status Build::forward() {
  if (Status s = sync(); !s) return s;
  if (position_ >= static_cast<int>(plan_.size())) return error(ErrorCode::kInvalidArgument, "build: already at the end");
  graph::Graph& g = scene_.graph();
  g.begin_transaction("build " + definition_.name + ": " + plan_[position_].step);
  Status s = construct(position_);
  if (s) {
    ++position_;
    s = save_state(key_of(*this, plan_[position_ - 1].component));
    if (!s) --position_;
  }
  if (!s) {
    g.rollback_transaction();
    records_->done.erase({key_of(*this, plan_[position_].component), plan_[position_].step});
    records_->text.erase(key_of(*this, plan_[position_].component));
    return s;
  }
  g.commit_transaction();
  return Status::ok();
}

Status Build::back() {
  if (Status s = sync(); !s) return s;
  if (position_ <= 0) return error(ErrorCode::kInvalidArgument, "build: already at the start");
  graph::Graph& g = scene_.graph();
  g.begin_transaction("unbuild " + definition_.name + ": " + plan_[position_ - 1].step);
  Status s = destruct(position_ - 1);
  if (s) {
    --position_;
    s = save_state(key_of(*this, plan_[position_].component));
    if (s && position_ == 0 && list_rigs(g).empty()) {
      if (NodeId m = meta_manager(g); m.is_valid()) s = g.delete_node(m);
    }
  }
  if (!s) {
    g.rollback_transaction();
    return s;
  }
  g.commit_transaction();
  return Status::ok();
}

Status Build::go_to(int position) {
  if (position < 0 || position > static_cast<int>(plan_.size()))
    return error(ErrorCode::kInvalidArgument, "build: no step " + std::to_string(position) + " (the plan has " +
                                                  std::to_string(plan_.size()) + ")");
  while (position_ < position)
    if (Status s = forward(); !s) return s;
  while (position_ > position)
    if (Status s = back(); !s) return s;
  return Status::ok();
}

Status Build::remove() { return go_to(0); }

Status Build::set_feature(std::string_view feature, bool enabled, std::string_view switch_name) {
  Definition next = definition_;
  Feature* f = nullptr;
  for (Feature& x : next.features)
    if (x.name == feature) f = &x;
  if (!f) {
    next.features.push_back(Feature{std::string(feature), true, {}, {}});
    f = &next.features.back();
  }
  if (switch_name.empty()) {
    f->enabled = enabled;
  } else {
    FeatureSwitch* s = nullptr;
    for (FeatureSwitch& x : f->switches)
      if (x.name == switch_name) s = &x;
    if (!s) {
      f->switches.push_back(FeatureSwitch{std::string(switch_name), true, {}});
      s = &f->switches.back();
    }
    s->enabled = enabled;
  }
  // Rebuild from the first step whose state changes.
  std::vector<bool> before;
  for (const PlannedStep& p : plan_) before.push_back(p.enabled);
  int first = static_cast<int>(plan_.size());
  for (std::size_t i = 0; i < plan_.size(); ++i) {
    const Component* c = plan_[i].component >= 0 ? components_[plan_[i].component] : nullptr;
    if (step_enabled(next, c, plan_[i].feature, plan_[i].switch_name) != before[i]) {
      first = static_cast<int>(i);
      break;
    }
  }
  const int target = position_;
  if (first < position_)
    if (Status s = go_to(first); !s) return s;
  definition_ = std::move(next);
  if (Status s = replan(); !s) return s;
  if (Status s = go_to(target); !s) return s;
  if (!root().is_valid()) return Status::ok();
  graph::Transaction tx(scene_.graph(), "feature " + std::string(feature));
  return save_state("");
}

}  // namespace rigel::rig
