// mGear Shifter guide templates read as rig definitions and a skeleton
// (tools/mgear_guides.h).
#include "rigel/tools/mgear_guides.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <functional>
#include <numbers>
#include <set>
#include <sstream>

#include "rigel/io/json_depth.h"
#include "rigel/math/rotation.h"
#include "rigel/math/transform.h"
#include "rigel/rig/schema.h"
#include "rigel/scene/transform_types.h"

namespace rigel::tools {
namespace {

using Json = nlohmann::ordered_json;
using math::Mat4;
using math::Vec3;

// Maya's default index colours (the drawing-override palette mGear's
// color_fk / color_ik index), as #rrggbb.
constexpr std::array<const char*, 32> kMayaIndexColours = {
    "#787878", "#000000", "#404040", "#999999", "#9b0028", "#000460", "#0000ff", "#004619",
    "#260043", "#c800c8", "#8a4833", "#3f231f", "#992600", "#ff0000", "#00ff00", "#004199",
    "#ffffff", "#ffff00", "#64dcff", "#43ffa3", "#ffb0b0", "#e4ac79", "#ffff63", "#009954",
    "#a16a30", "#9fa130", "#68a130", "#30a15d", "#30a1a1", "#3067a1", "#6f30a1", "#a1306a"};

// mGear's control icons -> rigel's shapes (scene/shapes.h).
const std::map<std::string, std::string>& icon_shapes() {
  static const std::map<std::string, std::string> m = {
      {"arrow", "arrow"},     {"circle", "circle"},     {"compas", "fourArrowCircle"}, {"cross", "cross"},
      {"crossarrow", "fourArrow"}, {"cube", "cube"},    {"cubewithpeak", "cube"},     {"diamond", "diamond"},
      {"null", "locator"},    {"pyramid", "triangle"},  {"sphere", "sphere"},         {"square", "square"},
      {"flower", "circle"},   {"cylinder", "circle"},   {"axis", "locator"},          {"pin", "pin"}};
  return m;
}

// The parameters every component carries over (names, sides, colours).
const std::set<std::string>& common_params() {
  static const std::set<std::string> s = {"comp_type", "comp_name", "comp_side", "comp_index", "Override_Color",
                                          "Use_RGB_Color", "color_fk", "color_ik", "RGB_fk", "RGB_ik"};
  return s;
}

struct Source {
  std::string key;  // "arm_L0"
  const Json* params = nullptr;
  std::string type, name, side_text;
  rig::Side side = rig::Side::kCenter;
  std::int64_t index = 0;
  std::string parent;        // its key, "" at the root
  std::string parent_local;  // the parent's locator
  std::map<std::string, Mat4> tra;
  std::vector<std::string> children;
};

std::string hex_of(const Json& rgb) {
  char text[8];
  auto channel = [&](int i) {
    const double v = rgb.is_array() && rgb.size() == 3 && rgb[i].is_number() ? rgb[i].get<double>() : 0.0;
    return static_cast<int>(std::lround(std::clamp(v, 0.0, 1.0) * 255.0));
  };
  std::snprintf(text, sizeof text, "#%02x%02x%02x", channel(0), channel(1), channel(2));
  return text;
}

// Natural order of locators: root, 0_loc, 1_loc, ... 10_loc.
std::vector<std::string> numbered_locs(const Source& c) {
  std::vector<std::pair<int, std::string>> out;
  for (const auto& [name, m] : c.tra) {
    const std::size_t u = name.find("_loc");
    if (u == std::string::npos || u == 0 || u > 6 || u + 4 != name.size()) continue;  // at most 6 digits
    bool digits = std::all_of(name.begin(), name.begin() + static_cast<long>(u), [](char ch) { return ch >= '0' && ch <= '9'; });
    if (digits) out.emplace_back(std::stoi(name.substr(0, u)), name);
  }
  std::sort(out.begin(), out.end());
  std::vector<std::string> names;
  for (auto& [i, n] : out) names.push_back(n);
  return names;
}

class Importer {
 public:
  explicit Importer(std::string source) : source_(std::move(source)) {}

  Result<MgearImport> run(std::string_view text) {
    Result<Json> doc = io::parse_json(text, source_, 64);
    if (!doc) return doc.status();
    if (Status s = read(*doc); !s) return s;
    out_.definition.name = rig_name_;
    out_.definition.version = "1.0";
    out_.definition.source = source_;
    size_factor_ = size_factor();
    for (const std::string& key : order_)
      if (sources_.at(key).parent.empty()) {
        std::vector<rig::Component> roots;
        if (Status s = emit(key, "", roots); !s) return s;
        for (rig::Component& c : roots) out_.definition.components.push_back(std::move(c));
      }
    return std::move(out_);
  }

 private:
  Status bad(const std::string& what) const { return error(ErrorCode::kInvalidArgument, source_ + ": " + what); }

  Status read(const Json& doc) {
    if (!doc.is_object() || !doc.contains("components_dict") || !doc["components_dict"].is_object())
      return bad("not an mGear guide template (no components_dict object)");
    guide_ = doc.contains("guide_root") && doc["guide_root"].is_object() && doc["guide_root"].contains("param_values")
                 ? &doc["guide_root"]["param_values"]
                 : nullptr;
    if (guide_ && !guide_->is_object()) guide_ = nullptr;
    if (guide_ && guide_->contains("rig_name") && (*guide_)["rig_name"].is_string()) {
      rig_name_ = (*guide_)["rig_name"].get<std::string>();
      if (!graph::Graph::is_valid_name(rig_name_)) rig_name_ = "rig";
    }
    const Json& dict = doc["components_dict"];
    if (doc.contains("components_list")) {
      if (!doc["components_list"].is_array()) return bad("components_list is not a list");
      for (const Json& n : doc["components_list"]) {
        if (!n.is_string()) return bad("components_list holds a value that is not a component name");
        if (!dict.contains(n.get<std::string>()))
          return bad("component '" + n.get<std::string>() + "': listed in components_list, missing from components_dict");
        if (std::find(order_.begin(), order_.end(), n.get<std::string>()) == order_.end())
          order_.push_back(n.get<std::string>());
      }
    }
    for (const auto& [key, entry] : dict.items())
      if (std::find(order_.begin(), order_.end(), key) == order_.end()) order_.push_back(key);
    for (const std::string& key : order_)
      if (Status s = read_component(key, dict[key]); !s) return s;
    for (const std::string& key : order_) {
      Source& c = sources_.at(key);
      if (c.parent.empty()) continue;
      auto p = sources_.find(c.parent);
      if (p == sources_.end()) return bad("component '" + key + "': parent '" + c.parent + "' is not a component");
      p->second.children.push_back(key);
    }
    for (const std::string& key : order_) {
      // A cycle: walking up from here comes back.
      const Source& c = sources_.at(key);
      std::set<std::string> seen{key};
      for (std::string up = c.parent; !up.empty(); up = sources_.at(up).parent)
        if (!seen.insert(up).second) return bad("component '" + key + "': its parents form a cycle");
    }
    // Names: comp_name, with the index where a name repeats on a side.
    std::map<std::pair<std::string, std::string>, int> uses;
    for (const std::string& key : order_) ++uses[{sources_.at(key).name, sources_.at(key).side_text}];
    std::set<std::pair<std::string, std::string>> taken;
    for (const std::string& key : order_) {
      Source& c = sources_.at(key);
      if (uses[{c.name, c.side_text}] > 1) c.name += std::to_string(std::max<std::int64_t>(c.index, 0));
      while (!taken.insert({c.name, c.side_text}).second) c.name += "x";  // the same name, side and index twice
    }
    return Status::ok();
  }

  Status read_component(const std::string& key, const Json& entry) {
    Source c;
    c.key = key;
    const std::string where = "component '" + key + "'";
    if (!entry.is_object() || !entry.contains("param_values") || !entry["param_values"].is_object())
      return bad(where + ": no param_values");
    c.params = &entry["param_values"];
    const Json& p = *c.params;
    if (!p.contains("comp_type") || !p["comp_type"].is_string()) return bad(where + ": no comp_type");
    c.type = p["comp_type"].get<std::string>();
    c.name = p.contains("comp_name") && p["comp_name"].is_string() ? p["comp_name"].get<std::string>() : key;
    if (!graph::Graph::is_valid_name(c.name) || c.name.find('_') != std::string::npos) {
      std::string cleaned;
      for (char ch : c.name)
        if (std::isalnum(static_cast<unsigned char>(ch))) cleaned += ch;
      if (cleaned.empty() || !std::isalpha(static_cast<unsigned char>(cleaned[0]))) cleaned = "c" + cleaned;
      c.name = cleaned;
    }
    c.side_text = p.contains("comp_side") && p["comp_side"].is_string() ? p["comp_side"].get<std::string>() : "C";
    c.side = rig::side_from_name(c.side_text).value_or(rig::Side::kCenter);
    c.index = p.contains("comp_index") && p["comp_index"].is_number_integer() ? p["comp_index"].get<std::int64_t>() : 0;
    if (entry.contains("parent_fullName") && entry["parent_fullName"].is_string())
      c.parent = entry["parent_fullName"].get<std::string>();
    if (entry.contains("parent_localName") && entry["parent_localName"].is_string())
      c.parent_local = entry["parent_localName"].get<std::string>();
    if (!entry.contains("tra") || !entry["tra"].is_object()) return bad(where + ": no tra (guide transforms)");
    for (const auto& [loc, m] : entry["tra"].items()) {
      bool ok = m.is_array() && m.size() == 4;
      Mat4 world = Mat4::Identity();
      for (std::size_t r = 0; ok && r < 4; ++r) {
        ok = m[r].is_array() && m[r].size() == 4;
        for (std::size_t k = 0; ok && k < 4; ++k) {
          ok = m[r][k].is_number() && std::isfinite(m[r][k].get<double>());
          if (ok) world(static_cast<long>(k), static_cast<long>(r)) = m[r][k].get<double>();  // Maya rows -> columns
        }
      }
      if (!ok) return bad(where + ": tra '" + loc + "' is not a 4x4 matrix of numbers");
      c.tra[loc] = world;
    }
    sources_.emplace(key, std::move(c));
    return Status::ok();
  }

  // Control sizes: the schema's (metres, for a 1.8 m character) scaled by
  // the template's height over 1.8.
  double size_factor() const {
    double lo = 0, hi = 0;
    bool any = false;
    for (const auto& [key, c] : sources_)
      for (const auto& [loc, m] : c.tra) {
        const double y = m(1, 3);
        lo = any ? std::min(lo, y) : y;
        hi = any ? std::max(hi, y) : y;
        any = true;
      }
    return hi - lo > 1e-9 ? (hi - lo) / 1.8 : 1.0;
  }

  static Vec3 position(const Source& c, const std::string& loc) { return c.tra.at(loc).topRightCorner<3, 1>(); }

  Status need(const Source& c, const std::vector<std::string>& locs) const {
    for (const std::string& l : locs)
      if (!c.tra.count(l))
        return bad("component '" + c.key + "' (" + c.type + "): guide locator '" + l + "' is missing from tra");
    return Status::ok();
  }

  // ---- skeleton ---------------------------------------------------------

  std::string add_joint(const Source& c, const std::string& label, const std::string& parent, const Vec3& where) {
    std::string name = c.key + "_" + label;
    if (!graph::Graph::is_valid_name(name)) {
      for (char& ch : name)
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
    }
    while (joint_names_.count(name)) name += "_";
    joint_names_.insert(name);
    out_.joints.push_back(GuideJoint{name, parent, where});
    return name;
  }

  // The joint a child hanging from `c`'s locator `loc` parents to.
  std::string joint_at(const std::string& key, const std::string& loc) const {
    for (std::string k = key, l = loc; !k.empty();) {
      auto it = joints_.find(k);
      if (it != joints_.end()) {
        auto j = it->second.find(l);
        if (j != it->second.end()) return j->second;
        auto f = fallback_.find(k);
        if (f != fallback_.end() && !f->second.empty()) return f->second;
      }
      const Source& s = sources_.at(k);
      l = s.parent_local;
      k = s.parent;
    }
    return "";
  }

  rig::Guide joint_guide(const std::string& name, const std::string& joint) const {
    rig::Guide g;
    g.name = name;
    g.joint = joint;
    return g;
  }

  rig::Guide value_guide(const std::string& name, const Mat4& world) const {
    const math::TransformParts parts = math::decompose_to_parts(world, math::RotateOrder::kXYZ);
    rig::Guide g;
    g.name = name;
    // 12 significant digits: Maya's float noise (89.99999999999999) stays out of the file.
    auto round12 = [](double v) {
      if (v == 0.0 || !std::isfinite(v)) return v;
      const double scale = std::pow(10.0, 11 - static_cast<int>(std::floor(std::log10(std::abs(v)))));
      const double r = std::round(v * scale) / scale;
      return std::abs(r) < 1e-12 ? 0.0 : r;
    };
    g.translate = parts.translate.unaryExpr(round12);
    g.rotate = math::to_degrees(parts.rotate).unaryExpr(round12);
    g.scale = Vec3::Ones();
    return g;
  }

  // ---- colours ------------------------------------------------------------

  std::string colour(const Source& c, bool ik) const {
    const Json& p = *c.params;
    const char* which = ik ? "ik" : "fk";
    auto flag = [](const Json* j, const char* k) { return j && j->contains(k) && (*j)[k].is_boolean() && (*j)[k].get<bool>(); };
    auto from = [&](const Json* j, const std::string& prefix) -> std::string {
      if (!j) return "";
      if (flag(j, "Use_RGB_Color") && j->contains(prefix + "RGB_" + which)) return hex_of((*j)[prefix + "RGB_" + which]);
      const std::string k = prefix + "color_" + which;
      if (j->contains(k) && (*j)[k].is_number_integer()) {
        const std::int64_t i = (*j)[k].get<std::int64_t>();
        if (i >= 0 && i < 32) return kMayaIndexColours[static_cast<std::size_t>(i)];
      }
      return "";
    };
    if (flag(&p, "Override_Color")) return from(&p, "");
    return from(guide_, c.side_text + "_");
  }

  void style(rig::Component& rc, const Source& c, const std::string& role, bool ik, double size) const {
    rig::ControlStyle s;
    s.role = role;
    const rig::ComponentSchema* schema = rig::builtin_schemas().find(rc.type);
    const rig::ControlSpec* spec = schema ? schema->control(role) : nullptr;
    s.shape = spec ? spec->shape : "circle";
    s.color = colour(c, ik);
    if (s.color.empty()) s.color = spec ? spec->color : "yellow";
    s.size = size > 0 ? size : (spec ? spec->size : 0.2) * size_factor_;
    rc.controls.push_back(std::move(s));
  }

  static rig::Param param(std::string name, rig::ParamValue value) {
    rig::Param p;
    p.name = std::move(name);
    p.value = std::move(value);
    return p;
  }

  // ---- mapping ----------------------------------------------------------------

  struct Mapped {
    rig::Component component;
    std::map<std::string, std::string> hooks;  // locator -> hook name ("" = hook 0)
    std::set<std::string> params;              // parameters carried
  };

  // Joints along a chain of locators, each the child of the one before.
  std::vector<std::string> chain(const Source& c, const std::vector<std::string>& locs, const std::string& parent,
                                 MgearComponentReport& r) {
    std::vector<std::string> names;
    std::string up = parent;
    for (const std::string& l : locs) {
      up = add_joint(c, l, up, position(c, l));
      joints_[c.key][l] = up;
      r.guides[l] = "joint " + up;
      names.push_back(up);
    }
    return names;
  }

  Result<Mapped> map_control(const Source& c, const std::string& parent_joint, MgearComponentReport& r) {
    if (Status s = need(c, {"root"}); !s) return s;
    Mapped m;
    m.component.type = "control";
    const Json& p = *c.params;
    const bool joint = p.contains("joint") && p["joint"].is_boolean() && p["joint"].get<bool>();
    if (joint) {
      const std::string j = add_joint(c, "root", parent_joint, position(c, "root"));
      joints_[c.key]["root"] = j;
      fallback_[c.key] = j;
      m.component.guides.push_back(joint_guide("main", j));
      r.guides["root"] = "joint " + j;
    } else {
      m.component.guides.push_back(value_guide("main", c.tra.at("root")));
      r.guides["root"] = "guide main";
    }
    double size = 0;
    if (c.tra.count("sizeRef")) {
      const double ctl = p.contains("ctlSize") && p["ctlSize"].is_number() ? p["ctlSize"].get<double>() : 1.0;
      size = ctl * (position(c, "sizeRef") - position(c, "root")).norm();
      r.guides["sizeRef"] = "the control's size";
      m.params.insert("ctlSize");
    }
    style(m.component, c, "main", false, size);
    if (p.contains("icon") && p["icon"].is_string()) {
      auto it = icon_shapes().find(p["icon"].get<std::string>());
      if (it != icon_shapes().end()) {
        m.component.controls.back().shape = it->second;
        m.params.insert("icon");
      }
    }
    m.params.insert("joint");
    for (const auto& [loc, w] : c.tra) m.hooks[loc] = "main";
    return m;
  }

  Result<Mapped> map_meta(const Source& c, const std::string& parent_joint, MgearComponentReport& r) {
    if (Status s = need(c, {"root"}); !s) return s;
    Mapped m;
    m.component.type = "meta";
    const std::string root = add_joint(c, "root", parent_joint, position(c, "root"));
    joints_[c.key]["root"] = root;
    fallback_[c.key] = root;
    r.guides["root"] = "joint " + root;
    m.component.guides.push_back(joint_guide("root", root));
    m.hooks["root"] = "root";
    for (const std::string& l : numbered_locs(c)) {
      const std::string j = add_joint(c, l, root, position(c, l));
      joints_[c.key][l] = j;
      r.guides[l] = "joint " + j;
      m.component.guides.push_back(joint_guide(l, j));
      m.hooks[l] = l;
    }
    return m;
  }

  // chain_01, chain_spring_01 and shoulder_01: a joint per locator; FK
  // controls on all but the last (the chain's tip), or IK through all.
  Result<Mapped> map_chain(const Source& c, const std::string& parent_joint, MgearComponentReport& r) {
    if (Status s = need(c, {"root"}); !s) return s;
    Mapped m;
    std::vector<std::string> locs{"root"};
    if (c.type == "shoulder_01") {
      if (Status s = need(c, {"tip"}); !s) return s;
      locs.push_back("tip");
    } else {
      for (const std::string& l : numbered_locs(c)) locs.push_back(l);
    }
    if (locs.size() < 2) return bad("component '" + c.key + "' (" + c.type + "): a chain needs a root and a 0_loc");
    const Json& p = *c.params;
    const std::int64_t mode = p.contains("mode") && p["mode"].is_number_integer() ? p["mode"].get<std::int64_t>() : 0;
    m.params.insert("mode");
    const std::vector<std::string> joints = chain(c, locs, parent_joint, r);
    const bool spring = c.type == "chain_spring_01";  // every joint swings, the tip's bone too
    const bool ik = !spring && mode != 0;
    m.component.type = spring ? "springChain" : ik ? "ikChain" : "fkChain";
    const std::size_t guided = ik || spring ? joints.size() : joints.size() - 1;
    for (std::size_t i = 0; i < guided; ++i) {
      m.component.guides.push_back(joint_guide(locs[i], joints[i]));
      m.hooks[locs[i]] = locs[i];
    }
    for (std::size_t i = guided; i < locs.size(); ++i) m.hooks[locs[i]] = locs[guided - 1];
    fallback_[c.key] = joints[guided - 1];
    if (ik) {
      style(m.component, c, "ik", true, 0);
      style(m.component, c, "pole", true, 0);
      if (mode == 2) r.notes.push_back("mode 2 (FK/IK) is built as IK: rigel's ikChain has no FK side");
    } else {
      style(m.component, c, "fk", false, 0);
    }
    return m;
  }

  // arm_2jnt_*, leg_2jnt_* (limb) and leg_3jnt_01 (quadLeg: its ankle is the hock, its foot the fetlock).
  Result<Mapped> map_limb(const Source& c, const std::string& parent_joint, MgearComponentReport& r, bool arm,
                          bool three = false) {
    std::vector<std::string> locs{"root", arm ? "elbow" : "knee", arm ? "wrist" : "ankle"};
    if (three) locs.push_back("foot");
    if (Status s = need(c, locs); !s) return s;
    Mapped m;
    m.component.type = three ? "quadLeg" : "limb";
    if (c.tra.count("eff")) locs.push_back("eff");
    const std::vector<std::string> joints = chain(c, locs, parent_joint, r);
    const char* names[] = {"upper", "lower", three ? "hock" : "end", "foot"};
    const std::size_t n = three ? 4 : 3;
    for (std::size_t i = 0; i < n; ++i) {
      m.component.guides.push_back(joint_guide(names[i], joints[i]));
      m.hooks[locs[i]] = names[i];
    }
    m.hooks["eff"] = names[n - 1];
    fallback_[c.key] = joints[n - 1];
    m.component.params.push_back(param("kind", std::string(three ? "hind" : arm ? "arm" : "leg")));
    const Json& p = *c.params;
    if (p.contains("blend") && p["blend"].is_number()) {
      m.component.params.push_back(param("defaultMode", std::string(p["blend"].get<double>() >= 0.5 ? "ik" : "fk")));
      m.params.insert("blend");
    }
    if (p.contains("maxstretch") && p["maxstretch"].is_number()) {
      m.component.params.push_back(param("maxStretch", std::max(1.0, p["maxstretch"].get<double>())));
      m.params.insert("maxstretch");
    }
    style(m.component, c, "fk", false, 0);
    style(m.component, c, "ik", true, 0);
    style(m.component, c, "pole", true, 0);
    return m;
  }

  // `count` (>= 2) joints evenly from locator `from` to `to`, a chain under
  // `parent`, named COMPONENT_FROM, COMPONENT_1, ..., COMPONENT_TO, each a
  // guide of `rc` (the ends named by their locators); returns the last.
  std::string joint_line(const Source& c, const std::string& from, const std::string& to, std::int64_t count,
                         const std::string& parent, rig::Component& rc, MgearComponentReport& r) {
    const Vec3 a = position(c, from), b = position(c, to);
    std::string up = parent;
    for (std::int64_t i = 0; i < count; ++i) {
      const bool end = i == 0 || i == count - 1;
      const std::string label = i == 0 ? from : i == count - 1 ? to : std::to_string(i);
      up = add_joint(c, label, up, a + (b - a) * (static_cast<double>(i) / static_cast<double>(count - 1)));
      joints_[c.key][label] = up;
      rc.guides.push_back(joint_guide(end ? label : "", up));
      if (end) r.guides[label] = "joint " + up;
    }
    return up;
  }

  // spine_ik_01, spine_S_shape_01: `division` joints from root to eff.
  Result<Mapped> map_spine(const Source& c, const std::string& parent_joint, MgearComponentReport& r) {
    if (Status s = need(c, {"root", "eff"}); !s) return s;
    Mapped m;
    m.component.type = "spine";
    const Json& p = *c.params;
    std::int64_t count = p.contains("division") && p["division"].is_number_integer() ? p["division"].get<std::int64_t>() : 5;
    m.params.insert("division");
    if (count < 3) {
      r.notes.push_back("division " + std::to_string(count) + " raised to 3: rigel's spine needs 3 joints");
      count = 3;
    }
    count = std::min<std::int64_t>(count, 64);
    const std::string up = joint_line(c, "root", "eff", count, parent_joint, m.component, r);
    m.hooks["root"] = "root";
    m.hooks["eff"] = "eff";
    fallback_[c.key] = up;
    m.component.params.push_back(param("kinematicType", std::string("splineIK")));
    style(m.component, c, "fk", false, 0);
    style(m.component, c, "shoulder", true, 0);
    style(m.component, c, "mid", true, 0);
    return m;
  }

  // neck_ik_01: `division` neck joints from root to neck, the head, eff its tip.
  Result<Mapped> map_neck(const Source& c, const std::string& parent_joint, MgearComponentReport& r) {
    if (Status s = need(c, {"root", "neck", "head"}); !s) return s;
    Mapped m;
    m.component.type = "neck";
    const Json& p = *c.params;
    std::int64_t count = p.contains("division") && p["division"].is_number_integer() ? p["division"].get<std::int64_t>() : 3;
    m.params.insert("division");
    count = std::clamp<std::int64_t>(count, 2, 64);
    const std::string up = joint_line(c, "root", "neck", count, parent_joint, m.component, r);
    const std::string head = add_joint(c, "head", up, position(c, "head"));
    joints_[c.key]["head"] = head;
    m.component.guides.push_back(joint_guide("head", head));
    r.guides["head"] = "joint " + head;
    if (c.tra.count("eff")) {
      const std::string eff = add_joint(c, "eff", head, position(c, "eff"));
      joints_[c.key]["eff"] = eff;
      r.guides["eff"] = "joint " + eff;
    }
    for (const char* tangent : {"tan0", "tan1"})
      if (c.tra.count(tangent)) r.unmapped_guides.push_back(tangent);
    m.hooks["root"] = "root";
    m.hooks["neck"] = "neck";
    m.hooks["head"] = "head";
    m.hooks["eff"] = "head";
    fallback_[c.key] = head;
    style(m.component, c, "neck", false, 0);
    style(m.component, c, "head", false, 0);
    return m;
  }

  Result<Mapped> map_foot(const Source& c, const std::string& parent_joint, MgearComponentReport& r) {
    if (Status s = need(c, {"root", "heel", "inpivot", "outpivot"}); !s) return s;
    const std::vector<std::string> locs = numbered_locs(c);
    if (locs.size() < 2)
      return bad("component '" + c.key + "' (foot_bk_01): a foot needs 0_loc (the ball) and a toe locator");
    Mapped m;
    m.component.type = "foot";
    // The ankle: the parent's joint when it stands at the root, else a new one.
    std::string ankle;
    const auto pj = std::find_if(out_.joints.begin(), out_.joints.end(), [&](const GuideJoint& j) { return j.name == parent_joint; });
    if (pj != out_.joints.end() && (pj->position - position(c, "root")).norm() <= 1e-9) {
      ankle = parent_joint;
    } else {
      ankle = add_joint(c, "root", parent_joint, position(c, "root"));
    }
    joints_[c.key]["root"] = ankle;
    r.guides["root"] = "joint " + ankle;
    const std::vector<std::string> toes = chain(c, locs, ankle, r);
    m.component.guides.push_back(joint_guide("ankle", ankle));
    m.component.guides.push_back(joint_guide("ball", toes[0]));
    m.component.guides.push_back(joint_guide("toe", toes.back()));
    m.component.guides.push_back(value_guide("heel", c.tra.at("heel")));
    m.component.guides.push_back(value_guide("inner", c.tra.at("inpivot")));
    m.component.guides.push_back(value_guide("outer", c.tra.at("outpivot")));
    r.guides["heel"] = "guide heel";
    r.guides["inpivot"] = "guide inner";
    r.guides["outpivot"] = "guide outer";
    m.hooks["root"] = "ankle";
    m.hooks[locs[0]] = "ball";
    for (std::size_t i = 1; i < locs.size(); ++i) m.hooks[locs[i]] = "toe";
    fallback_[c.key] = toes[0];
    style(m.component, c, "foot", true, 0);
    style(m.component, c, "toeFk", false, 0);
    return m;
  }

  Result<Mapped> map_eye(const Source& c, const std::string& parent_joint, MgearComponentReport& r) {
    if (Status s = need(c, {"root", "look"}); !s) return s;
    Mapped m;
    m.component.type = "eye";
    const std::string eye = add_joint(c, "root", parent_joint, position(c, "root"));
    joints_[c.key]["root"] = eye;
    fallback_[c.key] = eye;
    r.guides["root"] = "joint " + eye;
    m.component.guides.push_back(joint_guide("root", eye));
    const Vec3 look = position(c, "look") - position(c, "root");
    const double distance = look.norm();
    if (distance > 1e-9) {
      Vec3::Index axis = 0;
      look.cwiseAbs().maxCoeff(&axis);
      const char* names[] = {"x", "y", "z", "-x", "-y", "-z"};
      m.component.params.push_back(param("aimAxis", std::string(names[axis + (look[axis] < 0 ? 3 : 0)])));
      m.component.params.push_back(param("aimDistance", distance));
      r.guides["look"] = "aimAxis and aimDistance";
      const double off = std::acos(std::clamp(std::abs(look[axis]) / distance, -1.0, 1.0)) * 180.0 / std::numbers::pi;
      if (off > 1e-6)
        r.notes.push_back("the aim control sits on the eye's " + std::string(names[axis]) + " axis at the look "
                          "locator's distance, " + std::to_string(off) + " degrees off the locator");
    } else {
      r.unmapped_guides.push_back("look");
    }
    m.hooks["root"] = "root";
    m.hooks["look"] = "root";
    style(m.component, c, "aim", true, 0);
    style(m.component, c, "master", true, 0);
    return m;
  }

  Result<Mapped> map_mouth(const Source& c, const std::string& parent_joint, MgearComponentReport& r) {
    if (Status s = need(c, {"root", "rotcenter", "lipup", "liplow", "jaw"}); !s) return s;
    Mapped m;
    m.component.type = "mouth";
    const std::string root = add_joint(c, "root", parent_joint, position(c, "root"));
    const std::string jaw = add_joint(c, "rotcenter", root, position(c, "rotcenter"));
    const std::string chin = add_joint(c, "jaw", jaw, position(c, "jaw"));
    const std::string up = add_joint(c, "lipup", root, position(c, "lipup"));
    const std::string low = add_joint(c, "liplow", jaw, position(c, "liplow"));
    const std::pair<const char*, std::string> all[] = {
        {"root", root}, {"rotcenter", jaw}, {"jaw", chin}, {"lipup", up}, {"liplow", low}};
    for (const auto& [loc, j] : all) {
      joints_[c.key][loc] = j;
      r.guides[loc] = "joint " + j;
    }
    fallback_[c.key] = root;
    m.component.guides = {joint_guide("jaw", jaw), joint_guide("upperLip", up), joint_guide("lowerLip", low)};
    m.hooks = {{"root", "jaw"}, {"rotcenter", "jaw"}, {"jaw", "jaw"}, {"lipup", "upperLip"}, {"liplow", "lowerLip"}};
    style(m.component, c, "jaw", false, 0);
    style(m.component, c, "lip", true, 0);
    return m;
  }

  Result<Mapped> map_squash(const Source& c, const std::string& parent_joint, MgearComponentReport& r) {
    if (Status s = need(c, {"root", "tip"}); !s) return s;
    Mapped m;
    m.component.type = "squash";
    const std::vector<std::string> joints = chain(c, {"root", "tip"}, parent_joint, r);
    m.component.guides = {joint_guide("start", joints[0]), joint_guide("end", joints[1])};
    m.hooks = {{"root", "start"}, {"tip", "end"}};
    fallback_[c.key] = joints[0];
    style(m.component, c, "start", false, 0);
    style(m.component, c, "end", true, 0);
    return m;
  }

  Result<Mapped> map(const Source& c, const std::string& parent_joint, MgearComponentReport& r) {
    const std::string& t = c.type;
    if (t == "control_01") return map_control(c, parent_joint, r);
    if (t == "meta_01") return map_meta(c, parent_joint, r);
    if (t == "chain_01" || t == "chain_spring_01" || t == "shoulder_01") return map_chain(c, parent_joint, r);
    if (t == "arm_2jnt_01" || t == "arm_2jnt_02" || t == "arm_2jnt_03" || t == "arm_2jnt_04")
      return map_limb(c, parent_joint, r, true);
    if (t == "leg_2jnt_01" || t == "leg_2jnt_02") return map_limb(c, parent_joint, r, false);
    if (t == "leg_3jnt_01") return map_limb(c, parent_joint, r, false, true);
    if (t == "spine_ik_01" || t == "spine_S_shape_01") return map_spine(c, parent_joint, r);
    if (t == "neck_ik_01") return map_neck(c, parent_joint, r);
    if (t == "foot_bk_01") return map_foot(c, parent_joint, r);
    if (t == "eye_01") return map_eye(c, parent_joint, r);
    if (t == "mouth_01") return map_mouth(c, parent_joint, r);
    if (t == "squash_01") return map_squash(c, parent_joint, r);
    return error(ErrorCode::kNotFound, "no rigel counterpart for mGear type '" + t + "'");
  }

  // Maps `key` and its children; appends what it makes to `into` (a parent's
  // children, or the roots). `attach`: the hook of the nearest mapped
  // ancestor this one hangs from.
  Status emit(const std::string& key, const std::string& attach, std::vector<rig::Component>& into) {
    const Source& c = sources_.at(key);
    MgearComponentReport r;
    r.mgear = key;
    r.mgear_type = c.type;
    const std::string parent_joint = c.parent.empty() ? "" : joint_at(c.parent, c.parent_local);
    Result<Mapped> mapped = map(c, parent_joint, r);
    if (!mapped && mapped.status().code() == ErrorCode::kInvalidArgument) return mapped.status();
    if (!mapped) {
      r.problem = mapped.status().message();
      out_.components.push_back(std::move(r));
      // Its children hang from what it hangs from.
      for (const std::string& child : c.children)
        if (Status s = emit(child, attach, into); !s) return s;
      return Status::ok();
    }
    Mapped& m = *mapped;
    rig::Component& rc = m.component;
    rc.name = c.name;
    rc.side = c.side;
    rc.rig_id = rig::new_rig_id();
    rc.attach = attach;
    r.rigel_type = rc.type;
    r.rigel_name = rc.full_name();
    for (const auto& [name, value] : c.params->items())
      if (!common_params().count(name) && !m.params.count(name)) r.unmapped_params.push_back(name);
    for (const auto& [loc, w] : c.tra)
      if (!r.guides.count(loc) &&
          std::find(r.unmapped_guides.begin(), r.unmapped_guides.end(), loc) == r.unmapped_guides.end())
        r.unmapped_guides.push_back(loc);
    out_.components.push_back(std::move(r));
    for (const std::string& child : c.children) {
      const Source& cs = sources_.at(child);
      auto h = m.hooks.find(cs.parent_local);
      const std::string hook = h != m.hooks.end() ? h->second : "";
      if (Status s = emit(child, hook, rc.children); !s) return s;
    }
    into.push_back(std::move(rc));
    return Status::ok();
  }

  std::string source_;
  std::string rig_name_ = "rig";
  const Json* guide_ = nullptr;
  std::vector<std::string> order_;
  std::map<std::string, Source> sources_;
  std::map<std::string, std::map<std::string, std::string>> joints_;  // component -> locator -> joint
  std::map<std::string, std::string> fallback_;                       // component -> the joint children default to
  std::set<std::string> joint_names_;
  double size_factor_ = 1.0;
  MgearImport out_;
};

}  // namespace

std::vector<std::string> MgearImport::unmapped_components() const {
  std::vector<std::string> out;
  for (const MgearComponentReport& c : components)
    if (!c.mapped()) out.push_back(c.mgear);
  return out;
}

Result<MgearImport> import_mgear_guides(std::string_view text, const std::string& source) {
  return Importer(source).run(text);
}

Result<MgearImport> import_mgear_guides_file(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return error(ErrorCode::kNotFound, file.string() + ": cannot be read");
  std::ostringstream text;
  text << in.rdbuf();
  return import_mgear_guides(text.str(), file.string());
}

Result<std::unique_ptr<scene::Scene>> guide_skeleton_scene(const MgearImport& imported,
                                                           std::shared_ptr<const graph::Registry> registry) {
  auto scene = std::make_unique<scene::Scene>(std::move(registry));
  std::map<std::string, std::pair<graph::NodeId, Vec3>> made;
  for (const GuideJoint& j : imported.joints) {
    graph::NodeId parent;
    Vec3 parent_position = Vec3::Zero();
    if (!j.parent.empty()) {
      auto it = made.find(j.parent);
      if (it == made.end())
        return error(ErrorCode::kFailedPrecondition, "joint '" + j.name + "': its parent '" + j.parent + "' comes after it");
      parent = it->second.first;
      parent_position = it->second.second;
    }
    Result<graph::NodeId> id = scene->create(scene::kJointType, j.name, parent);
    if (!id) return id.status();
    if (scene->graph().node(*id)->name() != j.name)
      return error(ErrorCode::kInvalidArgument, "joint '" + j.name + "': the name is taken");
    const Vec3 local = j.position - parent_position;
    if (Status s = scene->graph().set_value(graph::Plug{*id, scene::xform::kTranslate, -1}, graph::Value(local)); !s)
      return s;
    made[j.name] = {*id, j.position};
  }
  return scene;
}

nlohmann::ordered_json mgear_report_json(const MgearImport& imported) {
  Json components = Json::array();
  for (const MgearComponentReport& c : imported.components) {
    Json j{{"mgear", c.mgear}, {"mgearType", c.mgear_type}};
    if (c.mapped()) {
      j["rigel"] = c.rigel_name;
      j["rigelType"] = c.rigel_type;
    } else {
      j["problem"] = c.problem;
    }
    j["guides"] = c.guides;
    j["unmappedParams"] = c.unmapped_params;
    j["unmappedGuides"] = c.unmapped_guides;
    j["notes"] = c.notes;
    components.push_back(std::move(j));
  }
  return Json{{"rig", imported.definition.name},
              {"components", std::move(components)},
              {"unmapped", imported.unmapped_components()},
              {"joints", imported.joints.size()}};
}

}  // namespace rigel::tools
