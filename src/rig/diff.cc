// Semantic differences between two rig definitions (diff.h).
#include "rigel/rig/diff.h"

#include <algorithm>
#include <cctype>
#include <map>

#include "definition_io_internal.h"

namespace rigel::rig {

const char* difference_kind_name(DifferenceKind kind) {
  switch (kind) {
    case DifferenceKind::kRigName: return "rigName";
    case DifferenceKind::kRigVersion: return "rigVersion";
    case DifferenceKind::kRigGuiLocation: return "rigGuiLocation";
    case DifferenceKind::kGeometryAdded: return "geometryAdded";
    case DifferenceKind::kGeometryRemoved: return "geometryRemoved";
    case DifferenceKind::kDataChanged: return "dataChanged";
    case DifferenceKind::kFeatureAdded: return "featureAdded";
    case DifferenceKind::kFeatureRemoved: return "featureRemoved";
    case DifferenceKind::kFeatureChanged: return "featureChanged";
    case DifferenceKind::kComponentAdded: return "componentAdded";
    case DifferenceKind::kComponentRemoved: return "componentRemoved";
    case DifferenceKind::kComponentMoved: return "componentMoved";
    case DifferenceKind::kComponentRenamed: return "componentRenamed";
    case DifferenceKind::kComponentTypeChanged: return "componentTypeChanged";
    case DifferenceKind::kComponentVersionChanged: return "componentVersionChanged";
    case DifferenceKind::kComponentGuiLocation: return "componentGuiLocation";
    case DifferenceKind::kParamAdded: return "paramAdded";
    case DifferenceKind::kParamRemoved: return "paramRemoved";
    case DifferenceKind::kParamChanged: return "paramChanged";
    case DifferenceKind::kGuideAdded: return "guideAdded";
    case DifferenceKind::kGuideRemoved: return "guideRemoved";
    case DifferenceKind::kGuideChanged: return "guideChanged";
    case DifferenceKind::kControlAdded: return "controlAdded";
    case DifferenceKind::kControlRemoved: return "controlRemoved";
    case DifferenceKind::kControlChanged: return "controlChanged";
  }
  return "?";
}

std::string Difference::str() const {
  std::string who = "rig";
  if (!component.empty() || !rig_id.empty()) {
    who = "component '" + component + "'";
    if (!rig_id.empty()) who += " [" + rig_id.substr(0, 8) + "]";
  }
  const auto none = [](const std::string& s) { return s.empty() ? std::string("(none)") : s; };
  const std::string change = none(old_value) + " -> " + none(new_value);
  switch (kind) {
    case DifferenceKind::kRigName: return who + ": name '" + old_value + "' -> '" + new_value + "'";
    case DifferenceKind::kRigVersion: return who + ": version " + change;
    case DifferenceKind::kRigGuiLocation:
    case DifferenceKind::kComponentGuiLocation: return who + ": guiLocation " + change;
    case DifferenceKind::kGeometryAdded: return who + ": geometry added: " + item;
    case DifferenceKind::kGeometryRemoved: return who + ": geometry removed: " + item;
    case DifferenceKind::kDataChanged: return who + ": data " + change;
    case DifferenceKind::kFeatureAdded: return who + ": feature '" + item + "' added: " + new_value;
    case DifferenceKind::kFeatureRemoved: return who + ": feature '" + item + "' removed (was " + old_value + ")";
    case DifferenceKind::kFeatureChanged: return who + ": feature '" + item + "': " + change;
    case DifferenceKind::kComponentAdded: return who + ": added: " + new_value;
    case DifferenceKind::kComponentRemoved: return who + ": removed (was " + old_value + ")";
    case DifferenceKind::kComponentMoved: return who + ": moved: " + change;
    case DifferenceKind::kComponentRenamed: return who + ": renamed: " + change;
    case DifferenceKind::kComponentTypeChanged: return who + ": type " + change;
    case DifferenceKind::kComponentVersionChanged: return who + ": version " + change;
    case DifferenceKind::kParamAdded: return who + ": parameter '" + item + "' added: " + new_value;
    case DifferenceKind::kParamRemoved: return who + ": parameter '" + item + "' removed (was " + old_value + ")";
    case DifferenceKind::kParamChanged: return who + ": parameter '" + item + "': " + change;
    case DifferenceKind::kGuideAdded: return who + ": " + item + " added: " + new_value;
    case DifferenceKind::kGuideRemoved: return who + ": " + item + " removed (was " + old_value + ")";
    case DifferenceKind::kGuideChanged: return who + ": " + item + ": " + change;
    case DifferenceKind::kControlAdded: return who + ": control '" + item + "' added: " + new_value;
    case DifferenceKind::kControlRemoved: return who + ": control '" + item + "' removed (was " + old_value + ")";
    case DifferenceKind::kControlChanged: return who + ": control '" + item + "': " + change;
  }
  return who;
}

namespace {

using detail::format_double;
using detail::pair_text;
using detail::param_text;
using detail::vec3_text;

std::string gui_text(const std::optional<std::pair<double, double>>& p) { return p ? pair_text(*p) : ""; }

std::string feature_text(const Feature& f) {
  std::string out = std::string("enabled=") + (f.enabled ? "true" : "false");
  if (!f.switches.empty()) {
    out += " switches=";
    for (std::size_t i = 0; i < f.switches.size(); ++i)
      out += (i ? "," : "") + f.switches[i].name + ":" + (f.switches[i].enabled ? "true" : "false");
  }
  return out;
}

std::string guide_text(const Guide& g) {
  std::string out;
  auto add = [&](const std::string& s) { out += (out.empty() ? "" : " ") + s; };
  if (!g.name.empty()) add("name=" + g.name);
  if (!g.joint.empty()) add("joint=" + g.joint);
  if (g.translate != math::Vec3::Zero()) add("translate=" + vec3_text(g.translate));
  if (g.rotate != math::Vec3::Zero()) add("rotate=" + vec3_text(g.rotate));
  if (g.scale != math::Vec3::Ones()) add("scale=" + vec3_text(g.scale));
  return out.empty() ? "(defaults)" : out;
}

std::string control_text(const ControlStyle& s) {
  return "shape=" + (s.shape.empty() ? "(default)" : s.shape) + " color=" + (s.color.empty() ? "(default)" : s.color) +
         " size=" + format_double(s.size);
}

// Data entries in order (the order they are imported in matters).
std::string data_text(const std::vector<DataImport>& data) {
  std::string out;
  for (const DataImport& x : data) out += (out.empty() ? "" : ", ") + x.kind + " " + x.file;
  return out;
}

std::string geometry_text(const Geometry& g) { return g.name.empty() ? g.file : g.file + "#" + g.name; }

std::string normalized_rig_id(std::string_view id) {
  std::string out;
  for (char c : id)
    if (c != '-') out += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

// Components of one definition by match key, with their nesting parents.
struct Indexed {
  std::vector<const Component*> order;  // depth-first
  std::map<const Component*, const Component*> parent;
  std::map<const Component*, std::string> key;
  std::map<std::string, const Component*> by_key;

  explicit Indexed(const Definition& d) {
    for (const Component& root : d.components) add(root, nullptr);
  }
  void add(const Component& c, const Component* p) {
    order.push_back(&c);
    parent[&c] = p;
    std::string k = !c.rig_id.empty() ? "id:" + normalized_rig_id(c.rig_id)
                                      : std::string("name:") + c.name + "/" + side_name(c.side);
    // A duplicate key (an invalid definition) matches in order of appearance.
    for (int n = 2; by_key.count(k); ++n) k = k.substr(0, k.find('#')) + "#" + std::to_string(n);
    key[&c] = k;
    by_key[k] = &c;
    for (const Component& child : c.children) add(child, &c);
  }
  std::string parent_key(const Component* c) const {
    const Component* p = parent.at(c);
    return p ? key.at(p) : "";
  }
  std::string placement(const Component* c) const {
    const Component* p = parent.at(c);
    std::string out = p ? "under '" + p->name + "'" : "at the root";
    if (!c->attach.empty()) out += ", attach " + c->attach;
    return out;
  }
};

class Differ {
 public:
  Differ(const Definition& a, const Definition& b) : a_(a), b_(b), sa_(a), sb_(b) {}

  std::vector<Difference> run() {
    rig();
    for (const Component* c : sa_.order)
      if (!sb_.by_key.count(sa_.key.at(c)))
        add(DifferenceKind::kComponentRemoved, *c, "", c->type + " " + sa_.placement(c), "");
    for (const Component* c : sb_.order) {
      const auto it = sa_.by_key.find(sb_.key.at(c));
      if (it == sa_.by_key.end()) {
        add(DifferenceKind::kComponentAdded, *c, "", "", c->type + " " + sb_.placement(c));
        continue;
      }
      component(*it->second, *c);
    }
    return std::move(out_);
  }

 private:
  void add(DifferenceKind kind, const Component& c, std::string item, std::string old_value, std::string new_value) {
    out_.push_back({kind, c.rig_id, c.name, std::move(item), std::move(old_value), std::move(new_value)});
  }
  void add_rig(DifferenceKind kind, std::string item, std::string old_value, std::string new_value) {
    out_.push_back({kind, "", "", std::move(item), std::move(old_value), std::move(new_value)});
  }

  void rig() {
    if (a_.name != b_.name) add_rig(DifferenceKind::kRigName, "", a_.name, b_.name);
    if (a_.version != b_.version) add_rig(DifferenceKind::kRigVersion, "", a_.version, b_.version);
    if (a_.gui_location != b_.gui_location)
      add_rig(DifferenceKind::kRigGuiLocation, "", gui_text(a_.gui_location), gui_text(b_.gui_location));
    auto has = [](const std::vector<Geometry>& list, const Geometry& g) {
      return std::any_of(list.begin(), list.end(),
                         [&](const Geometry& x) { return x.file == g.file && x.name == g.name; });
    };
    for (const Geometry& g : a_.geometry)
      if (!has(b_.geometry, g)) add_rig(DifferenceKind::kGeometryRemoved, geometry_text(g), geometry_text(g), "");
    for (const Geometry& g : b_.geometry)
      if (!has(a_.geometry, g)) add_rig(DifferenceKind::kGeometryAdded, geometry_text(g), "", geometry_text(g));
    if (data_text(a_.data) != data_text(b_.data))
      add_rig(DifferenceKind::kDataChanged, "", data_text(a_.data), data_text(b_.data));
    features(a_.features, b_.features, nullptr);
  }

  void features(const std::vector<Feature>& fa, const std::vector<Feature>& fb, const Component* c) {
    auto emit = [&](DifferenceKind kind, const std::string& name, std::string o, std::string n) {
      if (c) add(kind, *c, name, std::move(o), std::move(n));
      else add_rig(kind, name, std::move(o), std::move(n));
    };
    auto find = [](const std::vector<Feature>& list, const std::string& name) -> const Feature* {
      for (const Feature& f : list)
        if (f.name == name) return &f;
      return nullptr;
    };
    for (const Feature& f : fa)
      if (!find(fb, f.name)) emit(DifferenceKind::kFeatureRemoved, f.name, feature_text(f), "");
    for (const Feature& f : fb) {
      const Feature* old = find(fa, f.name);
      if (!old) emit(DifferenceKind::kFeatureAdded, f.name, "", feature_text(f));
      else if (feature_text(*old) != feature_text(f))
        emit(DifferenceKind::kFeatureChanged, f.name, feature_text(*old), feature_text(f));
    }
  }

  void component(const Component& a, const Component& b) {
    if (a.name != b.name || a.side != b.side)
      add(DifferenceKind::kComponentRenamed, b, "", a.name + " (" + side_name(a.side) + ")",
          b.name + " (" + side_name(b.side) + ")");
    if (sa_.parent_key(&a) != sb_.parent_key(&b) || a.attach != b.attach || a.after != b.after)
      add(DifferenceKind::kComponentMoved, b, "", sa_.placement(&a), sb_.placement(&b));
    if (a.type != b.type) add(DifferenceKind::kComponentTypeChanged, b, "", a.type, b.type);
    if (a.version != b.version) add(DifferenceKind::kComponentVersionChanged, b, "", a.version, b.version);
    if (a.gui_location != b.gui_location)
      add(DifferenceKind::kComponentGuiLocation, b, "", gui_text(a.gui_location), gui_text(b.gui_location));
    for (const Param& p : a.params)
      if (!b.param(p.name)) add(DifferenceKind::kParamRemoved, b, p.name, param_text(p.value), "");
    for (const Param& p : b.params) {
      const Param* old = a.param(p.name);
      if (!old) add(DifferenceKind::kParamAdded, b, p.name, "", param_text(p.value));
      else if (!(old->value == p.value))
        add(DifferenceKind::kParamChanged, b, p.name, param_text(old->value), param_text(p.value));
    }
    const std::size_t common = std::min(a.guides.size(), b.guides.size());
    auto guide_item = [](std::size_t i, const Guide& g) {
      const std::string& label = !g.name.empty() ? g.name : g.joint;
      return "guide " + std::to_string(i) + (label.empty() ? "" : " (" + label + ")");
    };
    for (std::size_t i = 0; i < common; ++i)
      if (guide_text(a.guides[i]) != guide_text(b.guides[i]))
        add(DifferenceKind::kGuideChanged, b, guide_item(i, b.guides[i]), guide_text(a.guides[i]), guide_text(b.guides[i]));
    for (std::size_t i = common; i < a.guides.size(); ++i)
      add(DifferenceKind::kGuideRemoved, b, guide_item(i, a.guides[i]), guide_text(a.guides[i]), "");
    for (std::size_t i = common; i < b.guides.size(); ++i)
      add(DifferenceKind::kGuideAdded, b, guide_item(i, b.guides[i]), "", guide_text(b.guides[i]));
    for (const ControlStyle& s : a.controls)
      if (!b.control(s.role)) add(DifferenceKind::kControlRemoved, b, s.role, control_text(s), "");
    for (const ControlStyle& s : b.controls) {
      const ControlStyle* old = a.control(s.role);
      if (!old) add(DifferenceKind::kControlAdded, b, s.role, "", control_text(s));
      else if (control_text(*old) != control_text(s))
        add(DifferenceKind::kControlChanged, b, s.role, control_text(*old), control_text(s));
    }
    features(a.features, b.features, &b);
  }

  const Definition& a_;
  const Definition& b_;
  Indexed sa_, sb_;
  std::vector<Difference> out_;
};

}  // namespace

std::vector<Difference> diff(const Definition& a, const Definition& b) { return Differ(a, b).run(); }

}  // namespace rigel::rig
