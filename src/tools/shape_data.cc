// Control shapes and colours as data (shape_data.h).

#include "rigel/tools/shape_data.h"

#include <cmath>

#include <nlohmann/json.hpp>

#include "roles.h"
#include "rigel/io/diffable_json.h"
#include "rigel/io/json_depth.h"
#include "rigel/rig/meta.h"
#include "rigel/scene/transform_types.h"

namespace rigel::tools {

using graph::NodeId;
using Json = nlohmann::ordered_json;
using math::Vec3;

namespace {

Json vec(const Vec3& v) { return Json::array({v.x(), v.y(), v.z()}); }

Status bad(const std::string& source, const std::string& where, const std::string& what) {
  return Status(ErrorCode::kParseError, source + ": " + where + ": " + what);
}

bool read_vec(const Json& j, Vec3& out) {
  if (!j.is_array() || j.size() != 3) return false;
  for (std::size_t i = 0; i < 3; ++i) {
    if (!j[i].is_number() || !std::isfinite(j[i].get<double>())) return false;
    out[static_cast<int>(i)] = j[i].get<double>();
  }
  return true;
}

}  // namespace

Result<ShapeSet> capture_control_shapes(graph::Graph& g, NodeId rig) {
  const graph::Node* root = g.node(rig);
  if (!root || root->type().name() != rig::kMetaRootType)
    return Status(ErrorCode::kInvalidArgument, "rig: not a built rig").with_field("rig");
  ShapeSet out;
  out.rig = rig::meta_string(g, rig, "rigName");
  for (NodeId meta : rig::rig_components(g, rig)) {
    for (NodeId m : rig::meta_members(g, meta)) {
      if (g.node(m)->type().name() != scene::kControlType) continue;
      auto role = internal::role_of(g, meta, m);
      auto look = control_look(g, m);
      if (!role || !look) continue;
      out.controls.push_back(ShapeEntry{rig::meta_string(g, meta, "rigId"), rig::meta_string(g, meta, "componentName"),
                                        role->first, g.node(m)->name(), role->second, std::move(*look)});
    }
  }
  return out;
}

std::string control_shapes_to_json(const ShapeSet& shapes) {
  Json controls = Json::array();
  for (const ShapeEntry& e : shapes.controls) {
    Json points = Json::array();
    for (const Vec3& p : e.look.points) points.push_back(vec(p));
    controls.push_back(Json{{"rigId", e.rig_id},
                            {"component", e.component},
                            {"role", e.role},
                            {"index", e.index},
                            {"name", e.name},
                            {"closed", e.look.closed},
                            {"color", vec(e.look.color)},
                            {"points", std::move(points)}});
  }
  return io::diffable_json(Json{{"rigelShapes", kShapesFormat}, {"rig", shapes.rig}, {"controls", std::move(controls)}});
}

Result<ShapeSet> control_shapes_from_json(std::string_view text, const std::string& source) {
  Result<Json> parsed = io::parse_json(text, source, 16);
  if (!parsed) return parsed.status();
  Json j = std::move(*parsed);
  if (!j.is_object() || !j.contains("rigelShapes") || !j["rigelShapes"].is_number_integer())
    return bad(source, "rigelShapes", "not a rigel control shapes file");
  if (j["rigelShapes"].get<std::int64_t>() > kShapesFormat)
    return Status(ErrorCode::kFailedPrecondition, source + ": made by a newer rigel (shapes format " +
                                                      std::to_string(j["rigelShapes"].get<std::int64_t>()) + ")");
  if (!j.contains("rig") || !j["rig"].is_string()) return bad(source, "rig", "expected text");
  if (!j.contains("controls") || !j["controls"].is_array()) return bad(source, "controls", "expected an array");
  ShapeSet out;
  out.rig = j["rig"].get<std::string>();
  for (std::size_t i = 0; i < j["controls"].size(); ++i) {
    const Json& c = j["controls"][i];
    const std::string at = "controls[" + std::to_string(i) + "]";
    if (!c.is_object()) return bad(source, at, "expected an object");
    for (const char* key : {"rigId", "component", "role", "name"})
      if (!c.contains(key) || !c[key].is_string()) return bad(source, at + "." + key, "expected text");
    if (!c.contains("index") || !c["index"].is_number_integer() || c["index"].get<std::int64_t>() < 0)
      return bad(source, at + ".index", "expected a whole number >= 0");
    ShapeEntry e{c["rigId"].get<std::string>(), c["component"].get<std::string>(), c["role"].get<std::string>(),
                 c["name"].get<std::string>(), c["index"].get<int>(), {}};
    if (!c.contains("closed") || !c["closed"].is_boolean()) return bad(source, at + ".closed", "expected true or false");
    e.look.closed = c["closed"].get<bool>();
    if (!c.contains("color") || !read_vec(c["color"], e.look.color) || e.look.color.minCoeff() < 0 || e.look.color.maxCoeff() > 1)
      return bad(source, at + ".color", "expected [r, g, b] in 0..1");
    if (!c.contains("points") || !c["points"].is_array()) return bad(source, at + ".points", "expected an array");
    for (std::size_t k = 0; k < c["points"].size(); ++k) {
      Vec3 p;
      if (!read_vec(c["points"][k], p)) return bad(source, at + ".points[" + std::to_string(k) + "]", "expected [x, y, z]");
      e.look.points.push_back(p);
    }
    out.controls.push_back(std::move(e));
  }
  return out;
}

Result<ShapesReport> apply_control_shapes(graph::Graph& g, NodeId rig, const ShapeSet& shapes) {
  const graph::Node* root = g.node(rig);
  if (!root || root->type().name() != rig::kMetaRootType)
    return Status(ErrorCode::kInvalidArgument, "rig: not a built rig").with_field("rig");
  ShapesReport report;
  std::vector<std::pair<NodeId, const ControlLook*>> plan;
  for (const ShapeEntry& e : shapes.controls) {
    const NodeId meta = rig::find_component(g, rig, e.rig_id);
    Result<NodeId> c = meta.is_valid() ? rig::get_meta_connection(g, meta, e.role, e.index) : Result<NodeId>(Status(ErrorCode::kNotFound, ""));
    if (!c || g.node(*c)->type().name() != scene::kControlType) {
      report.missing.push_back(e.component + " " + e.role + "[" + std::to_string(e.index) + "]");
      continue;
    }
    plan.emplace_back(*c, &e.look);
  }
  graph::Transaction tx(g, "import control shapes");
  for (const auto& [c, look] : plan) {
    if (Status s = paste_control_look(g, {c}, *look); !s) {
      tx.rollback();
      return s;
    }
  }
  report.set = plan.size();
  return report;
}

}  // namespace rigel::tools
