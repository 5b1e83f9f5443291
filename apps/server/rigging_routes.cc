// The JSON API's rigger-action routes (rigging_routes.h).

#include "rigging_routes.h"

#include <optional>
#include <string>
#include <vector>

#include "api_fields.h"
#include "rigel/ops/anim/channel_keys.h"

namespace rigel::server::routes {

using namespace api;

namespace {

// The request's node list (names, uuids or rig addresses), or the selection.
std::vector<graph::NodeId> nodes_or_selection(const app::Workspace& ws, const Json& body, const char* key) {
  auto nodes = nodes_field(body, key, [&](const std::string& ref, const std::string& field) { return ws.node(ref, field); });
  return nodes ? *nodes : ws.selection();
}

bool flag(const Json& body, const char* key, bool fallback) {
  const Json* j = opt(body, key);
  return j ? as_bool(*j, key) : fallback;
}

tools::ControlLook look_of(const Json& j) {
  if (!j.is_object()) refuse(400, "shape: expected an object with points, closed and color", "shape");
  tools::ControlLook look;
  const Json* found = opt(j, "points");
  if (!found) refuse(400, "shape.points: missing", "shape.points");
  const Json& points = *found;
  if (!points.is_array()) refuse(400, "shape.points: expected an array of [x, y, z]", "shape.points");
  for (std::size_t i = 0; i < points.size(); ++i)
    look.points.push_back(as_numbers<3>(points[i], "shape.points[" + std::to_string(i) + "]"));
  if (const Json* c = opt(j, "closed")) look.closed = as_bool(*c, "shape.closed");
  if (const Json* c = opt(j, "color")) look.color = as_numbers<3>(*c, "shape.color");
  return look;
}

}  // namespace

namespace {

const std::string& query_field(const std::map<std::string, std::string>& query, const char* key) {
  auto it = query.find(key);
  if (it == query.end()) refuse(400, std::string("missing query '") + key + "'", key);
  return it->second;
}

}  // namespace

std::string pose_thumbnail(const app::Workspace& ws, const std::map<std::string, std::string>& query) {
  return take(ws.pose_thumbnail(query_field(query, "library"), query_field(query, "name")));
}

Json shape(const app::Workspace& ws, const std::map<std::string, std::string>& query) {
  const graph::NodeId id = take(ws.node(query_field(query, "control"), "control"));
  auto look = ws.control_look(id);
  if (!look) refuse(400, "control: " + look.status().message(), "control");
  Json points = Json::array();
  for (const math::Vec3& p : look->points) points.push_back(vec_json(p));
  return Json{{"control", ws.graph().node(id)->uuid().str()},
              {"name", ws.graph().node(id)->name()},
              {"points", points},
              {"closed", look->closed},
              {"color", vec_json(look->color)}};
}

Json shape_edit(app::Workspace& ws, const Json& body) {
  const std::string op = as_string(need(body, "op"), "op");
  const std::vector<graph::NodeId> controls = nodes_or_selection(ws, body, "controls");
  Json out{{"controls", node_refs_json(ws, controls)}};
  if (op == "paste") {
    tools::LookParts parts{false, false};
    if (const Json* p = opt(body, "parts")) {
      if (!p->is_array()) refuse(400, "parts: expected an array of \"shape\" and \"color\"", "parts");
      for (std::size_t i = 0; i < p->size(); ++i) {
        const std::string part = as_string((*p)[i], "parts[" + std::to_string(i) + "]");
        if (part == "shape") parts.shape = true;
        else if (part == "color") parts.color = true;
        else refuse(400, "parts[" + std::to_string(i) + "]: expected \"shape\" or \"color\", got \"" + part + "\"", "parts");
      }
    } else {
      parts = {true, true};
    }
    check(ws.paste_control_look(controls, look_of(need(body, "shape")), parts));
  } else if (op == "mirror" || op == "flip") {
    check(ws.edit_control_shape(controls, op == "mirror" ? tools::ShapeEdit::kMirror : tools::ShapeEdit::kFlip));
  } else if (op == "opposite") {
    Json pairs = Json::array();
    for (const tools::MirroredShape& p : take(ws.mirror_shape_to_opposite(controls)))
      pairs.push_back(Json{{"from", ws.graph().node(p.from)->uuid().str()}, {"to", ws.graph().node(p.to)->uuid().str()}});
    out["pairs"] = pairs;
  } else {
    refuse(400, "op: expected \"paste\", \"mirror\", \"flip\" or \"opposite\", got \"" + op + "\"", "op");
  }
  out["revision"] = ws.revision();
  return out;
}

Json align(app::Workspace& ws, const Json& body) {
  const graph::NodeId target = take(ws.node(as_string(need(body, "target"), "target"), "target"));
  std::vector<graph::NodeId> nodes = nodes_or_selection(ws, body, "nodes");
  const auto moved = take(ws.align(nodes, target, flag(body, "position", true), flag(body, "rotation", true)));
  return Json{{"revision", ws.revision()}, {"moved", node_refs_json(ws, moved)}};
}

Json locators(app::Workspace& ws, const Json& body) {
  const Json* size = opt(body, "size");
  const auto made = take(ws.create_locators(nodes_or_selection(ws, body, "nodes"), size ? as_number(*size, "size") : 0.1));
  return Json{{"revision", ws.revision()}, {"locators", node_refs_json(ws, made)}};
}

Json mirror_joints(app::Workspace& ws, const Json& body) {
  tools::MirrorJointsOptions options;
  options.update_existing = flag(body, "update", false);
  const auto report = take(ws.mirror_joints(nodes_or_selection(ws, body, "joints"), options));
  return Json{{"revision", ws.revision()},
              {"created", node_refs_json(ws, report.created)},
              {"updated", node_refs_json(ws, report.updated)}};
}

namespace {

std::string data_kind(const Json& body) {
  const std::string kind = as_string(need(body, "kind"), "kind");
  if (kind != "weights" && kind != "shapes" && kind != "blendshapes" && kind != "driven_poses" && kind != "correctives")
    refuse(400, "kind: expected \"weights\", \"shapes\", \"blendshapes\", \"driven_poses\" or \"correctives\", got \"" + kind + "\"", "kind");
  return kind;
}

tools::DrivenData driven_of(const std::string& kind) {
  return kind == "correctives" ? tools::DrivenData::kCorrectives : tools::DrivenData::kPoses;
}

Json driven_set_json(const tools::DrivenPoseSet& set) {
  Json drivers = Json::array();
  for (const tools::DrivenDriver& d : set.drivers) {
    Json curves = Json::array();
    for (const tools::DrivenCurve& c : d.curves)
      curves.push_back(Json{{"node", c.node}, {"driven", c.driven}, {"at", c.times}, {"values", c.values}});
    drivers.push_back(Json{{"driver", d.driver}, {"curves", std::move(curves)}});
  }
  return Json{{"drivers", std::move(drivers)}};
}

std::string rig_of(const Json& body) {
  const Json* r = opt(body, "rig");
  return r ? as_string(*r, "rig") : std::string();
}

}  // namespace

Json data_export(app::Workspace& ws, const Json& body) {
  const std::string kind = data_kind(body);
  const std::string file = as_string(need(body, "file"), "file");
  if (kind != "weights" && opt(body, "format")) refuse(400, "format: only weights take it", "format");
  tools::WeightsFormat format = tools::WeightsFormat::kJson;
  if (const Json* f = opt(body, "format")) format = take(tools::weights_format_named(as_string(*f, "format")));
  const std::filesystem::path path = take(kind == "weights"       ? ws.export_skin_weights(file, format)
                                          : kind == "shapes"      ? ws.export_control_shapes(rig_of(body), file)
                                          : kind == "blendshapes" ? ws.export_blend_shapes(file)
                                                                  : ws.export_driven_poses(driven_of(kind), file));
  // Where it went, as the request names files: inside the served root.
  const std::string shown = ws.root().empty() ? path.string() : path.lexically_relative(ws.root()).generic_string();
  return Json{{"revision", ws.revision()}, {"kind", kind}, {"file", shown}};
}

Json data_import(app::Workspace& ws, const Json& body) {
  const std::string kind = data_kind(body);
  const std::string file = as_string(need(body, "file"), "file");
  if (kind != "weights")
    for (const char* k : {"rename", "nearest", "mirror"})
      if (opt(body, k)) refuse(400, std::string(k) + ": only weights take it", k);
  if (kind == "driven_poses" || kind == "correctives") {
    const tools::DrivenPosesReport r = take(ws.import_driven_poses(driven_of(kind), file));
    return Json{{"revision", ws.revision()}, {"curves", r.curves}, {"created", r.created}, {"keys", r.keys}};
  }
  if (kind == "blendshapes") {
    const tools::BlendShapesReport r = take(ws.import_blend_shapes(file));
    return Json{{"revision", ws.revision()}, {"blendShapes", r.blend_shapes}, {"targets", r.targets},
                {"created", r.created}, {"added", r.added}, {"driven", r.driven}};
  }
  if (kind == "shapes") {
    const tools::ShapesReport r = take(ws.import_control_shapes(rig_of(body), file));
    return Json{{"revision", ws.revision()}, {"set", r.set}, {"missing", r.missing}};
  }
  tools::WeightsImport o;
  o.nearest = flag(body, "nearest", false);
  o.mirror = flag(body, "mirror", false);
  if (const Json* table = opt(body, "rename")) {
    if (!table->is_object()) refuse(400, "rename: expected an object {\"old name\": \"new name\"}", "rename");
    for (auto it = table->begin(); it != table->end(); ++it) o.rename[it.key()] = as_string(it.value(), "rename." + it.key());
  }
  const tools::WeightsReport r = take(ws.import_skin_weights(file, o));
  return Json{{"revision", ws.revision()}, {"skins", r.skins}, {"vertices", r.vertices}, {"remapped", r.remapped}};
}

Json driven_keys(app::Workspace& ws) {
  return Json{{"revision", ws.revision()},
              {"drivenPoses", driven_set_json(take(ws.driven_poses(tools::DrivenData::kPoses)))},
              {"correctives", driven_set_json(take(ws.driven_poses(tools::DrivenData::kCorrectives)))}};
}

Json driven_key_edit(app::Workspace& ws, const Json& body) {
  const std::string op = as_string(need(body, "op"), "op");
  if (op == "remove") {
    const Json& driven = need(body, "driven");
    if (!driven.is_array()) refuse(400, "driven: expected an array of channels", "driven");
    std::vector<std::string> channels;
    for (std::size_t i = 0; i < driven.size(); ++i) channels.push_back(as_string(driven[i], "driven[" + std::to_string(i) + "]"));
    check(ws.remove_driven_keys(channels));
    return Json{{"revision", ws.revision()}, {"removed", channels}};
  }
  if (op == "reader") {
    const std::string joint = as_string(need(body, "joint"), "joint");
    const graph::NodeId j = take(ws.node(joint, "joint"));
    const Vec3 axis = opt(body, "axis") ? as_numbers<3>(*opt(body, "axis"), "axis") : Vec3(1, 0, 0);
    const graph::NodeId reader = take(ws.create_pose_reader(j, axis));
    const std::string name = ws.graph().node(reader)->name();
    return Json{{"revision", ws.revision()}, {"reader", name}, {"angle", name + ".angle"}, {"rotate", name + ".rotate"}};
  }
  if (op != "set") refuse(400, "op: expected \"set\", \"remove\" or \"reader\", got \"" + op + "\"", "op");
  tools::DrivenKeyRequest request;
  request.driver = as_string(need(body, "driver"), "driver");
  if (const Json* at = opt(body, "at")) request.at = as_number(*at, "at");
  if (const Json* tangent = opt(body, "tangent")) {
    auto t = ops::anim::tangent_type_from_name(as_string(*tangent, "tangent"));
    if (!t) refuse(400, "tangent: unknown tangent type " + tangent->dump(), "tangent");
    request.tangent = *t;
  }
  const Json& driven = need(body, "driven");
  if (!driven.is_object()) refuse(400, "driven: expected an object {channel: value or null}", "driven");
  for (auto it = driven.begin(); it != driven.end(); ++it) {
    std::optional<double> value;
    if (!it.value().is_null()) value = as_number(it.value(), "driven." + it.key());
    request.driven.emplace_back(it.key(), value);
  }
  const tools::DrivenKeyReport r = take(ws.set_driven_key(request));
  return Json{{"revision", ws.revision()}, {"at", r.at}, {"curves", r.curves}, {"created", r.created}};
}

}  // namespace rigel::server::routes
