// The JSON API's graph editor routes (curve_routes.h): curves to draw and
// single-key edits. Each reads its request's fields and calls the app layer.

#include "curve_routes.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

#include "api_fields.h"
#include "rigel/ops/anim/channel_keys.h"
#include "rigel/app/workspace.h"

namespace rigel::server::routes {

using namespace api;

namespace {

std::optional<ops::anim::TangentType> tangent_field(const Json& key, const char* field, const std::string& where) {
  const Json* t = opt(key, field);
  if (!t) return std::nullopt;
  const std::string name = as_string(*t, where + "." + field);
  auto type = ops::anim::tangent_type_from_name(name);
  if (!type)
    refuse(400, where + "." + field + ": '" + name +
                    "' is not a tangent type (auto, spline, linear, flat, step, stepNext, clamped, plateau, fixed)",
           "keys");
  return type;
}

}  // namespace

Json curves(app::Workspace& ws, const std::vector<graph::NodeId>& controls,
            const std::map<std::string, std::string>& query) {
  tools::CurveViewOptions options;
  options.first = query_number(query, "first");
  options.last = query_number(query, "last");
  options.step = query_number(query, "step");
  if (const auto e = query_number(query, "euler")) options.quat_as_euler = *e != 0;
  Json out = Json::array();
  for (const tools::CurveView& v : take(ws.curves(controls, options))) {  // in frames
    Json c{{"plug", v.name},        {"curve", v.curve},       {"kind", v.kind},
           {"component", v.component}, {"label", v.label},   {"editable", v.editable},
           {"frames", v.key_times},          {"values", v.key_values}};
    if (v.kind == "curve") {
      c["inTangents"] = v.in_tangents;
      c["outTangents"] = v.out_tangents;
      c["inSlopes"] = v.in_slopes;  // per frame
      c["outSlopes"] = v.out_slopes;
    }
    c["samples"] = Json{{"frames", v.sample_times}, {"values", v.sample_values}};
    out.push_back(std::move(c));
  }
  return Json{{"revision", ws.revision()}, {"fps", ws.graph().fps()}, {"curves", out}};
}

Json curve_keys(app::Workspace& ws, const Json& body) {
  const std::string op = as_string(need(body, "op"), "op");
  if (op != "edit" && op != "insert" && op != "delete")
    refuse(400, "op: expected \"edit\", \"insert\" or \"delete\", got \"" + op + "\"", "op");
  const Json& keys = need(body, "keys");
  if (!keys.is_array() || keys.empty()) refuse(400, "keys: expected a non-empty array of keys", "keys");
  if (keys.size() > 100000) refuse(400, "keys: more than 100000 keys in one edit", "keys");
  std::vector<tools::CurveKeyEdit> edits;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    const std::string where = "keys[" + std::to_string(i) + "]";
    const Json& k = keys[i];
    if (!k.is_object()) refuse(400, where + ": expected an object", "keys");
    tools::CurveKeyEdit e;
    e.key.curve = as_string(need(k, "curve"), where + ".curve");
    e.key.time = as_number(need(k, "frame"), where + ".frame");
    if (op == "edit") {
      if (const Json* t = opt(k, "toFrame")) e.to_time = as_number(*t, where + ".toFrame");
      if (const Json* v = opt(k, "value")) e.value = as_number(*v, where + ".value");
      if (const Json* c = opt(k, "component")) e.component = as_int(*c, where + ".component", "0, 1 or 2");
      if (const auto both = tangent_field(k, "tangent", where)) e.in_type = e.out_type = both;
      if (const auto in = tangent_field(k, "inTangent", where)) e.in_type = in;
      if (const auto out = tangent_field(k, "outTangent", where)) e.out_type = out;
      if (const Json* s = opt(k, "inSlope")) e.in_slope = as_number(*s, where + ".inSlope");
      if (const Json* s = opt(k, "outSlope")) e.out_slope = as_number(*s, where + ".outSlope");
    } else {
      for (const char* field : {"toFrame", "value", "tangent", "inTangent", "outTangent", "inSlope", "outSlope"})
        if (opt(k, field)) refuse(400, where + "." + field + ": an " + op + " takes only curve and frame", "keys");
    }
    edits.push_back(std::move(e));
  }
  std::size_t changed = 0;
  if (op == "edit") {
    changed = take(ws.edit_curve_keys(std::move(edits)));
  } else {
    std::vector<tools::CurveKeyRef> refs;
    for (const tools::CurveKeyEdit& e : edits) refs.push_back(e.key);
    changed = take(op == "insert" ? ws.insert_curve_keys(std::move(refs)) : ws.delete_curve_keys(std::move(refs)));
  }
  return Json{{"revision", ws.revision()}, {"changed", changed}};
}

}  // namespace rigel::server::routes
