// Set-driven keys and the driven-pose and corrective data managers
// (driven_poses.h).

#include "rigel/tools/driven_poses.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include <nlohmann/json.hpp>

#include "rigel/io/diffable_json.h"
#include "rigel/io/json_depth.h"
#include "rigel/ops/anim/nodes.h"
#include "rigel/ops/deform/nodes.h"
#include "rigel/ops/util/nodes.h"
#include "rigel/scene/transform_types.h"

namespace rigel::tools {

using graph::NodeId;
using graph::Plug;
using graph::Value;
using Json = nlohmann::ordered_json;
namespace ca = ops::anim::curve_attr;
namespace anim = ops::anim;

namespace {

constexpr double kSameDriverValue = 1e-9;

Status invalid(const std::string& message) { return Status(ErrorCode::kInvalidArgument, message); }

Status bad(const std::string& source, const std::string& where, const std::string& what) {
  return Status(ErrorCode::kParseError, source + ": " + where + ": " + what);
}

bool is_driven_key(const graph::Graph& g, NodeId id) {
  const graph::Node* n = g.node(id);
  return n && n->type().name() == anim::kDrivenKeyType;
}

// What feeds `channel`: a connection into it, into the whole attribute it
// is part of (rotate for rotateX, weights for weights[2]) or into a part
// of it.
std::optional<Plug> feeding(const graph::Graph& g, const Plug& channel) {
  for (const graph::Connection& c : g.node(channel.node)->inputs()) {
    if (c.dst.attr != channel.attr) continue;
    const bool element = c.dst.element < 0 || channel.element < 0 || c.dst.element == channel.element;
    const bool component = c.dst.component < 0 || channel.component < 0 || c.dst.component == channel.component;
    if (element && component) return c.src;
  }
  return std::nullopt;
}

// The drivenKey whose output feeds exactly `channel`, if one does.
std::optional<NodeId> driven_key_of(const graph::Graph& g, const Plug& channel) {
  std::optional<Plug> src = g.source(channel);
  if (src && is_driven_key(g, src->node) && src->attr == ca::kOutput) return src->node;
  return std::nullopt;
}

// A plug by name that carries one double (a double, an element of a
// double[], a component of a double3).
Result<Plug> scalar_plug(const graph::Graph& g, const std::string& name, const char* what) {
  Result<Plug> p = g.plug_find(name);
  if (!p) return invalid(std::string(what) + " " + name + ": " + p.status().message());
  if (g.plug_type(*p) != graph::AttrType{graph::ValueType::kDouble, false})
    return invalid(std::string(what) + " " + name + ": a " + graph::type_name(g.plug_type(*p)) +
                   ", not a number (name one channel: rotateX, weights[2])");
  return p;
}

Result<double> scalar_value(graph::Graph& g, const Plug& p) {
  Result<Value> v = g.evaluate(p);
  if (!v) return v.status();
  if (const double* d = std::get_if<double>(&*v)) return *d;
  return invalid(g.plug_name(p) + ": not a number");
}

template <typename T>
const std::vector<T>& array_of(const graph::Graph& g, NodeId id, graph::AttrIndex attr) {
  return std::get<std::vector<T>>(g.node(id)->value(attr));
}

std::string enum_name(std::span<const std::string_view> names, std::int64_t v) {
  return v >= 0 && static_cast<std::size_t>(v) < names.size() ? std::string(names[static_cast<std::size_t>(v)]) : "?";
}

std::optional<std::int64_t> enum_index(std::span<const std::string_view> names, std::string_view name) {
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return static_cast<std::int64_t>(i);
  return std::nullopt;
}

DrivenCurve curve_of(const graph::Graph& g, NodeId id, const Plug& driven) {
  DrivenCurve c;
  c.node = g.node(id)->name();
  c.driven = g.plug_name(driven);
  c.times = array_of<double>(g, id, ca::kKeyTimes);
  c.values = array_of<double>(g, id, ca::kKeyValues);
  for (std::int64_t t : array_of<std::int64_t>(g, id, ca::kInTangentType))
    c.in_types.push_back(enum_name(anim::tangent_type_names(), t));
  for (std::int64_t t : array_of<std::int64_t>(g, id, ca::kOutTangentType))
    c.out_types.push_back(enum_name(anim::tangent_type_names(), t));
  c.in_slopes = array_of<double>(g, id, ca::kInSlope);
  c.out_slopes = array_of<double>(g, id, ca::kOutSlope);
  c.in_weights = array_of<double>(g, id, ca::kInWeight);
  c.out_weights = array_of<double>(g, id, ca::kOutWeight);
  c.weighted = std::get<bool>(g.node(id)->value(ca::kWeighted));
  c.pre_infinity = enum_name(anim::infinity_names(), std::get<std::int64_t>(g.node(id)->value(ca::kPreInfinity)));
  c.post_infinity = enum_name(anim::infinity_names(), std::get<std::int64_t>(g.node(id)->value(ca::kPostInfinity)));
  return c;
}

// The node arrays of a curve, checked as the node would check them.
struct NodeArrays {
  std::vector<std::int64_t> in_types, out_types;
  std::int64_t pre = 0, post = 0;
};
Result<NodeArrays> node_arrays(const DrivenCurve& c, const std::string& where) {
  NodeArrays out;
  for (const auto* names : {&c.in_types, &c.out_types}) {
    std::vector<std::int64_t>& to = names == &c.in_types ? out.in_types : out.out_types;
    for (const std::string& n : *names) {
      auto v = enum_index(anim::tangent_type_names(), n);
      if (!v) return invalid(where + ": unknown tangent type '" + n + "'");
      to.push_back(*v);
    }
  }
  auto pre = enum_index(anim::infinity_names(), c.pre_infinity);
  auto post = enum_index(anim::infinity_names(), c.post_infinity);
  if (!pre) return invalid(where + ": unknown infinity '" + c.pre_infinity + "'");
  if (!post) return invalid(where + ": unknown infinity '" + c.post_infinity + "'");
  out.pre = *pre;
  out.post = *post;
  anim::CurveArrays arrays{c.times, c.values, out.in_types, out.out_types, c.in_slopes, c.out_slopes,
                           c.in_weights, c.out_weights,
                           anim::CurveSettings{c.weighted, static_cast<anim::Infinity>(out.pre),
                                               static_cast<anim::Infinity>(out.post)}};
  if (c.times.empty()) return invalid(where + ": no keys");
  if (Status s = arrays.validate(); !s) return invalid(where + ": " + s.message());
  return out;
}

Status write_curve(graph::Graph& g, NodeId id, const DrivenCurve& c, const NodeArrays& a) {
  auto set = [&](graph::AttrIndex attr, Value v) { return g.set_value(Plug{id, attr, -1}, std::move(v)); };
  Status s = set(ca::kKeyTimes, c.times);
  if (s) s = set(ca::kKeyValues, c.values);
  if (s) s = set(ca::kInTangentType, a.in_types);
  if (s) s = set(ca::kOutTangentType, a.out_types);
  if (s) s = set(ca::kInSlope, c.in_slopes);
  if (s) s = set(ca::kOutSlope, c.out_slopes);
  if (s) s = set(ca::kInWeight, c.in_weights);
  if (s) s = set(ca::kOutWeight, c.out_weights);
  if (s) s = set(ca::kWeighted, c.weighted);
  if (s) s = set(ca::kPreInfinity, a.pre);
  if (s) s = set(ca::kPostInfinity, a.post);
  return s;
}

// Connects `driver` into the drivenKey's input, replacing another driver.
Status drive_from(graph::Graph& g, NodeId key, const Plug& driver) {
  const Plug input{key, ops::anim::driven_key_attr::kInput, -1};
  if (std::optional<Plug> src = g.source(input)) {
    if (*src == driver) return Status::ok();
    if (Status s = g.disconnect_input(input); !s) return s;
  }
  return g.connect(driver, input);
}

// "ctrl.rotateZ" -> "ctrl_rotateZ_drivenKey", "mesh_blendShape.weights[2]" -> "mesh_blendShape_weights2_drivenKey".
std::string key_node_name(const std::string& channel) {
  std::string out;
  for (char ch : channel) {
    if (ch == '.') out += '_';
    else if (ch != '[' && ch != ']') out += ch;
  }
  return out + "_drivenKey";
}

// ---- JSON ------------------------------------------------------------------

Json numbers(const std::vector<double>& v) { return Json(v); }

Result<std::vector<double>> read_numbers(const Json& j, const std::string& source, const std::string& where) {
  if (!j.is_array()) return bad(source, where, "expected an array of numbers");
  std::vector<double> out;
  for (std::size_t i = 0; i < j.size(); ++i) {
    if (!j[i].is_number() || !std::isfinite(j[i].get<double>()))
      return bad(source, where + "[" + std::to_string(i) + "]", "expected a finite number");
    out.push_back(j[i].get<double>());
  }
  return out;
}

Result<std::vector<std::string>> read_names(const Json& j, const std::string& source, const std::string& where) {
  if (!j.is_array()) return bad(source, where, "expected an array of names");
  std::vector<std::string> out;
  for (std::size_t i = 0; i < j.size(); ++i) {
    if (!j[i].is_string()) return bad(source, where + "[" + std::to_string(i) + "]", "expected a name");
    out.push_back(j[i].get<std::string>());
  }
  return out;
}

Result<std::string> read_string(const Json& j, const char* key, const std::string& source, const std::string& where) {
  if (!j.contains(key) || !j[key].is_string() || j[key].get<std::string>().empty())
    return bad(source, where + "." + key, "expected a non-empty string");
  return j[key].get<std::string>();
}

Result<DrivenCurve> read_curve(const Json& j, const std::string& source, const std::string& where) {
  if (!j.is_object()) return bad(source, where, "expected an object");
  static const std::set<std::string> known = {"node",       "driven",    "keys",      "inTangents", "outTangents",
                                              "inSlopes",   "outSlopes", "inWeights", "outWeights", "weighted",
                                              "preInfinity", "postInfinity"};
  for (const auto& [k, v] : j.items())
    if (!known.count(k)) return bad(source, where + "." + k, "unknown member");
  DrivenCurve c;
  Result<std::string> node = read_string(j, "node", source, where);
  if (!node) return node.status();
  Result<std::string> driven = read_string(j, "driven", source, where);
  if (!driven) return driven.status();
  c.node = *node;
  c.driven = *driven;
  if (!j.contains("keys") || !j["keys"].is_array() || j["keys"].empty())
    return bad(source, where + ".keys", "expected an array of [driver value, value] pairs");
  for (std::size_t k = 0; k < j["keys"].size(); ++k) {
    const Json& key = j["keys"][k];
    const std::string at = where + ".keys[" + std::to_string(k) + "]";
    if (!key.is_array() || key.size() != 2 || !key[0].is_number() || !key[1].is_number() ||
        !std::isfinite(key[0].get<double>()) || !std::isfinite(key[1].get<double>()))
      return bad(source, at, "expected [driver value, value], two finite numbers");
    c.times.push_back(key[0].get<double>());
    c.values.push_back(key[1].get<double>());
  }
  for (auto [member, to] : {std::pair{"inTangents", &c.in_types}, std::pair{"outTangents", &c.out_types}}) {
    if (!j.contains(member)) continue;
    auto names = read_names(j[member], source, where + "." + member);
    if (!names) return names.status();
    *to = std::move(*names);
  }
  for (auto [member, to] : {std::pair{"inSlopes", &c.in_slopes}, std::pair{"outSlopes", &c.out_slopes},
                            std::pair{"inWeights", &c.in_weights}, std::pair{"outWeights", &c.out_weights}}) {
    if (!j.contains(member)) continue;
    auto v = read_numbers(j[member], source, where + "." + member);
    if (!v) return v.status();
    *to = std::move(*v);
  }
  if (j.contains("weighted")) {
    if (!j["weighted"].is_boolean()) return bad(source, where + ".weighted", "expected true or false");
    c.weighted = j["weighted"].get<bool>();
  }
  for (auto [member, to] : {std::pair{"preInfinity", &c.pre_infinity}, std::pair{"postInfinity", &c.post_infinity}}) {
    if (!j.contains(member)) continue;
    if (!j[member].is_string()) return bad(source, where + "." + member, "expected an infinity name");
    *to = j[member].get<std::string>();
  }
  if (Result<NodeArrays> checked = node_arrays(c, where); !checked)
    return Status(ErrorCode::kParseError, source + ": " + checked.status().message());
  return c;
}

}  // namespace

std::string_view driven_data_name(DrivenData kind) { return kind == DrivenData::kPoses ? "drivenPoses" : "correctives"; }

DrivenData driven_data_of(const graph::Graph& g, const Plug& driven) {
  const std::string& type = g.node(driven.node)->type().name();
  return type == ops::kBlendShapeType || type == scene::kJointType ? DrivenData::kCorrectives : DrivenData::kPoses;
}

Result<DrivenPoseSet> capture_driven_poses(const graph::Graph& g, DrivenData kind) {
  std::vector<NodeId> ids = g.nodes();
  std::sort(ids.begin(), ids.end(), [&](NodeId a, NodeId b) { return g.node(a)->order() < g.node(b)->order(); });
  DrivenPoseSet out;
  out.kind = kind;
  std::map<std::string, std::size_t> by_driver;
  for (NodeId id : ids) {
    if (!is_driven_key(g, id)) continue;
    std::optional<Plug> driver = g.source(Plug{id, ops::anim::driven_key_attr::kInput, -1});
    if (!driver) continue;
    // The first channel the curve feeds (a drivenKey feeds one channel).
    std::optional<Plug> driven;
    for (const graph::Connection& c : g.node(id)->outputs())
      if (c.src.attr == ca::kOutput && (!driven || c.dst.node.index < driven->node.index)) driven = c.dst;
    if (!driven || driven_data_of(g, *driven) != kind) continue;
    const std::string name = g.plug_name(*driver);
    auto [it, fresh] = by_driver.emplace(name, out.drivers.size());
    if (fresh) out.drivers.push_back(DrivenDriver{name, {}});
    out.drivers[it->second].curves.push_back(curve_of(g, id, *driven));
  }
  return out;
}

std::string driven_poses_to_json(const DrivenPoseSet& poses) {
  Json drivers = Json::array();
  for (const DrivenDriver& d : poses.drivers) {
    Json curves = Json::array();
    for (const DrivenCurve& c : d.curves) {
      Json keys = Json::array();
      for (std::size_t k = 0; k < c.times.size(); ++k) keys.push_back(Json::array({c.times[k], c.values[k]}));
      Json curve{{"node", c.node}, {"driven", c.driven}, {"keys", std::move(keys)}};
      if (!c.in_types.empty()) curve["inTangents"] = c.in_types;
      if (!c.out_types.empty()) curve["outTangents"] = c.out_types;
      if (!c.in_slopes.empty()) curve["inSlopes"] = numbers(c.in_slopes);
      if (!c.out_slopes.empty()) curve["outSlopes"] = numbers(c.out_slopes);
      if (!c.in_weights.empty()) curve["inWeights"] = numbers(c.in_weights);
      if (!c.out_weights.empty()) curve["outWeights"] = numbers(c.out_weights);
      if (c.weighted) curve["weighted"] = true;
      if (c.pre_infinity != "constant") curve["preInfinity"] = c.pre_infinity;
      if (c.post_infinity != "constant") curve["postInfinity"] = c.post_infinity;
      curves.push_back(std::move(curve));
    }
    drivers.push_back(Json{{"driver", d.driver}, {"curves", std::move(curves)}});
  }
  return io::diffable_json(Json{{"rigelDrivenPoses", kDrivenPosesFormat},
                                {"kind", std::string(driven_data_name(poses.kind))},
                                {"drivers", std::move(drivers)}});
}

Result<DrivenPoseSet> driven_poses_from_json(std::string_view text, const std::string& source, DrivenData kind) {
  Result<Json> parsed = io::parse_json(text, source, 16);
  if (!parsed) return parsed.status();
  const Json& j = *parsed;
  if (!j.is_object() || !j.contains("rigelDrivenPoses") || !j["rigelDrivenPoses"].is_number_integer())
    return bad(source, "the file", "not a driven-poses file (no \"rigelDrivenPoses\" format number)");
  if (j["rigelDrivenPoses"].get<std::int64_t>() > kDrivenPosesFormat)
    return bad(source, "rigelDrivenPoses",
               "made by a newer rigel (format " + j["rigelDrivenPoses"].dump() + "; this rigel reads " +
                   std::to_string(kDrivenPosesFormat) + ")");
  for (const auto& [k, v] : j.items())
    if (k != "rigelDrivenPoses" && k != "kind" && k != "drivers") return bad(source, k, "unknown member");
  const std::string want(driven_data_name(kind));
  if (!j.contains("kind") || !j["kind"].is_string()) return bad(source, "kind", "expected \"drivenPoses\" or \"correctives\"");
  if (j["kind"].get<std::string>() != want)
    return bad(source, "kind", "a file of " + j["kind"].get<std::string>() + ", not " + want);
  if (!j.contains("drivers") || !j["drivers"].is_array()) return bad(source, "drivers", "expected an array");
  DrivenPoseSet out;
  out.kind = kind;
  std::set<std::string> channels;
  for (std::size_t d = 0; d < j["drivers"].size(); ++d) {
    const Json& dj = j["drivers"][d];
    const std::string where = "drivers[" + std::to_string(d) + "]";
    if (!dj.is_object()) return bad(source, where, "expected an object");
    for (const auto& [k, v] : dj.items())
      if (k != "driver" && k != "curves") return bad(source, where + "." + k, "unknown member");
    Result<std::string> driver = read_string(dj, "driver", source, where);
    if (!driver) return driver.status();
    if (!dj.contains("curves") || !dj["curves"].is_array()) return bad(source, where + ".curves", "expected an array");
    DrivenDriver dd{*driver, {}};
    for (std::size_t c = 0; c < dj["curves"].size(); ++c) {
      const std::string at = where + ".curves[" + std::to_string(c) + "]";
      Result<DrivenCurve> curve = read_curve(dj["curves"][c], source, at);
      if (!curve) return curve.status();
      if (!channels.insert(curve->driven).second) return bad(source, at + ".driven", curve->driven + " is driven twice");
      dd.curves.push_back(std::move(*curve));
    }
    out.drivers.push_back(std::move(dd));
  }
  return out;
}

Result<DrivenPosesReport> apply_driven_poses(graph::Graph& g, const DrivenPoseSet& poses) {
  DrivenPosesReport report;
  graph::Transaction tx(g, "import " + std::string(driven_data_name(poses.kind)));
  auto fail = [&](Status s) {
    tx.rollback();
    return s;
  };
  for (const DrivenDriver& d : poses.drivers) {
    Result<Plug> driver = scalar_plug(g, d.driver, "driver");
    if (!driver) return fail(driver.status());
    for (const DrivenCurve& c : d.curves) {
      Result<Plug> channel = scalar_plug(g, c.driven, "driven channel");
      if (!channel) return fail(channel.status());
      Result<NodeArrays> arrays = node_arrays(c, c.driven);
      if (!arrays) return fail(arrays.status());
      std::optional<NodeId> key = driven_key_of(g, *channel);
      if (!key) {
        if (std::optional<Plug> src = feeding(g, *channel))
          return fail(invalid("driven channel " + c.driven + " is driven by " + g.plug_name(*src) + ", not by a driven key"));
        Result<NodeId> made = g.create_node(anim::kDrivenKeyType, c.node);
        if (!made) return fail(made.status());
        if (Status s = g.connect(Plug{*made, ca::kOutput, -1}, *channel); !s) return fail(s);
        key = *made;
        ++report.created;
      }
      if (Status s = write_curve(g, *key, c, *arrays); !s) return fail(s);
      if (Status s = drive_from(g, *key, *driver); !s) return fail(s);
      ++report.curves;
      report.keys += c.times.size();
    }
  }
  return report;
}

Result<DrivenKeyReport> set_driven_key(graph::Graph& g, const DrivenKeyRequest& request) {
  if (request.driven.empty()) return invalid("set driven key: no driven channel");
  Result<Plug> driver = scalar_plug(g, request.driver, "driver");
  if (!driver) return driver.status();
  DrivenKeyReport report;
  if (request.at) {
    if (!std::isfinite(*request.at)) return invalid("driver " + request.driver + ": the driver value is not finite");
    report.at = *request.at;
  } else {
    Result<double> now = scalar_value(g, *driver);
    if (!now) return now.status();
    report.at = *now;
  }
  // Everything read before anything changes.
  struct Target {
    Plug channel;
    std::string name;
    double value;
    std::optional<NodeId> key;
  };
  std::vector<Target> targets;
  std::set<std::string> seen;
  for (const auto& [name, value] : request.driven) {
    Result<Plug> channel = scalar_plug(g, name, "driven channel");
    if (!channel) return channel.status();
    const std::string canonical = g.plug_name(*channel);
    if (!seen.insert(canonical).second) return invalid("driven channel " + canonical + " is named twice");
    if (*channel == *driver) return invalid("driven channel " + canonical + " is the driver");
    Target t{*channel, canonical, 0.0, driven_key_of(g, *channel)};
    if (t.key) {
      std::optional<Plug> from = g.source(Plug{*t.key, anim::driven_key_attr::kInput, -1});
      if (from && !(*from == *driver))
        return invalid("driven channel " + canonical + " is driven by " + g.node(*t.key)->name() + " from " +
                       g.plug_name(*from) + ", not from " + g.plug_name(*driver));
    } else if (std::optional<Plug> src = feeding(g, *channel)) {
      return invalid("driven channel " + canonical + " is driven by " + g.plug_name(*src) + ", not by a driven key");
    }
    if (value) {
      if (!std::isfinite(*value)) return invalid("driven channel " + canonical + ": the value is not finite");
      t.value = *value;
    } else {
      Result<double> now = scalar_value(g, *channel);
      if (!now) return now.status();
      t.value = *now;
    }
    targets.push_back(std::move(t));
  }
  graph::Transaction tx(g, "set driven key " + g.plug_name(*driver));
  auto fail = [&](Status s) {
    tx.rollback();
    return s;
  };
  for (Target& t : targets) {
    if (!t.key) {
      Result<NodeId> made = g.create_node(anim::kDrivenKeyType, key_node_name(t.name));
      if (!made) return fail(made.status());
      if (Status s = g.connect(Plug{*made, ca::kOutput, -1}, t.channel); !s) return fail(s);
      if (Status s = g.connect(*driver, Plug{*made, anim::driven_key_attr::kInput, -1}); !s) return fail(s);
      t.key = *made;
      ++report.created;
    }
    DrivenCurve c = curve_of(g, *t.key, t.channel);
    // Where the key goes: replacing one at the same driver value, else in order.
    std::size_t at = 0;
    while (at < c.times.size() && c.times[at] < report.at - kSameDriverValue) ++at;
    const bool replace = at < c.times.size() && std::abs(c.times[at] - report.at) <= kSameDriverValue;
    const std::string type(anim::tangent_type_names()[static_cast<std::size_t>(request.tangent)]);
    // Tangent types are stored once a key is not auto (each array empty or one entry per key).
    const bool typed = !c.in_types.empty() || !c.out_types.empty() || request.tangent != anim::TangentType::kAuto;
    if (typed) {
      if (c.in_types.empty()) c.in_types.assign(c.times.size(), "auto");
      if (c.out_types.empty()) c.out_types.assign(c.times.size(), "auto");
    }
    if (replace) {
      c.values[at] = t.value;
    } else {
      const auto pos = static_cast<std::ptrdiff_t>(at);
      c.times.insert(c.times.begin() + pos, report.at);
      c.values.insert(c.values.begin() + pos, t.value);
      if (typed)
        for (auto* v : {&c.in_types, &c.out_types}) v->insert(v->begin() + pos, type);
      for (auto* v : {&c.in_slopes, &c.out_slopes})
        if (!v->empty()) v->insert(v->begin() + pos, 0.0);
      for (auto* v : {&c.in_weights, &c.out_weights})
        if (!v->empty()) v->insert(v->begin() + pos, anim::kDefaultWeight);
    }
    Result<NodeArrays> arrays = node_arrays(c, t.name);
    if (!arrays) return fail(arrays.status());
    if (Status s = write_curve(g, *t.key, c, *arrays); !s) return fail(s);
    report.curves.push_back(g.node(*t.key)->name());
  }
  return report;
}

Result<NodeId> create_pose_reader(graph::Graph& g, NodeId joint, const math::Vec3& axis) {
  const graph::Node* j = g.node(joint);
  if (!j || j->type().attr_find("matrix") != scene::xform::kMatrix)
    return Status(ErrorCode::kInvalidArgument, "joint: not a transform").with_field("joint");
  if (!axis.allFinite() || axis.norm() == 0)
    return Status(ErrorCode::kInvalidArgument, "axis: expected a direction, not zero").with_field("axis");
  namespace x = scene::xform;
  const math::Mat4 rest = std::get<math::Mat4>(g.evaluate(joint, x::kMatrix));
  graph::Transaction tx(g, "pose reader on " + j->name());
  Result<NodeId> reader = g.create_node(ops::util::kPoseReaderType, j->name() + "_poseReader");
  Status s = reader.status();
  namespace pr = ops::util::pose_reader_attr;
  if (s) s = g.set_value(Plug{*reader, pr::kRestMatrix, -1}, Value(rest));
  if (s) s = g.set_value(Plug{*reader, pr::kAxis, -1}, Value(axis));
  if (s) s = g.connect(Plug{joint, x::kMatrix, -1}, Plug{*reader, pr::kMatrix, -1});
  if (!s) {
    tx.rollback();
    return s;
  }
  return *reader;
}

Status remove_driven_keys(graph::Graph& g, const std::vector<std::string>& driven) {
  struct Target {
    Plug channel;
    NodeId key;
    double value;
  };
  std::vector<Target> targets;
  for (const std::string& name : driven) {
    Result<Plug> channel = scalar_plug(g, name, "driven channel");
    if (!channel) return channel.status();
    std::optional<NodeId> key = driven_key_of(g, *channel);
    if (!key) return invalid("driven channel " + name + ": no driven key feeds it");
    Result<double> now = scalar_value(g, *channel);
    if (!now) return now.status();
    targets.push_back(Target{*channel, *key, *now});
  }
  graph::Transaction tx(g, "remove driven keys");
  for (const Target& t : targets) {
    Status s = g.node(t.key) ? g.delete_node(t.key) : Status::ok();
    if (s) s = g.set_value(t.channel, Value(t.value));
    if (!s) {
      tx.rollback();
      return s;
    }
  }
  return Status::ok();
}

}  // namespace rigel::tools
