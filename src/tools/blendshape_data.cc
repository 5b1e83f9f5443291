// Blend shapes as data (blendshape_data.h): capture, the file, and import
// by blendShape name or mesh, targets by name or index.

#include "rigel/tools/blendshape_data.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <set>

#include <nlohmann/json.hpp>

#include "rigel/io/diffable_json.h"
#include "rigel/io/json_depth.h"
#include "rigel/ops/deform/nodes.h"
#include "rigel/scene/transform_types.h"

namespace rigel::tools {

using graph::NodeId;
using graph::Plug;
using Json = nlohmann::ordered_json;
using math::Vec3;
namespace bs = ops::blend_shape_attr;
namespace sc = ops::skin_cluster_attr;
namespace ma = scene::mesh_attr;

namespace {

template <typename T>
T copy_of(graph::Graph& g, NodeId n, graph::AttrIndex a) {
  const graph::Value& v = g.evaluate(n, a);
  const T* p = std::get_if<T>(&v);
  return p ? *p : T{};
}

Status bad(const std::string& source, const std::string& where, const std::string& what) {
  return Status(ErrorCode::kParseError, source + ": " + where + ": " + what);
}

Status refuse(const std::string& where, const std::string& what, const char* field) {
  return Status(ErrorCode::kInvalidArgument, where + ": " + what).with_field(field);
}

std::string blend_where(const std::string& name) { return "blendShape '" + name + "'"; }

bool is_type(const graph::Graph& g, NodeId id, const char* type) {
  const graph::Node* n = g.node(id);
  return n && n->type().name() == type;
}

// The mesh a blendShape deforms: its outPoints feed the mesh's points, or
// the bindPoints of a skinCluster that feeds them. "" when none.
std::string mesh_of(const graph::Graph& g, NodeId blend) {
  for (const graph::Connection& c : g.node(blend)->outputs()) {
    if (c.src.attr != bs::kOutPoints) continue;
    if (is_type(g, c.dst.node, scene::kMeshType) && c.dst.attr == ma::kPoints) return g.node(c.dst.node)->name();
    if (!is_type(g, c.dst.node, ops::kSkinClusterType) || c.dst.attr != sc::kBindPoints) continue;
    for (const graph::Connection& k : g.node(c.dst.node)->outputs())
      if (k.src.attr == sc::kOutPoints && k.dst.attr == ma::kPoints && is_type(g, k.dst.node, scene::kMeshType))
        return g.node(k.dst.node)->name();
  }
  return {};
}

// The first connection into any part of `attr` of `node`.
std::optional<graph::Connection> fed(const graph::Graph& g, NodeId node, graph::AttrIndex attr) {
  for (const graph::Connection& c : g.node(node)->inputs())
    if (c.dst.attr == attr) return c;
  return std::nullopt;
}

struct SceneBlend {
  std::size_t vertex_count = 0;
  std::vector<BlendTarget> targets;
};

// A blendShape's targets as the file holds them: each one's moved vertices
// in rising order with their deltas, its name and its weight now.
Result<SceneBlend> read_blend_shape(graph::Graph& g, NodeId id) {
  const std::string where = blend_where(g.node(id)->name());
  const auto base = copy_of<std::vector<Vec3>>(g, id, bs::kBasePoints);
  const auto deltas = copy_of<std::vector<Vec3>>(g, id, bs::kTargetDeltas);
  const auto offsets = copy_of<std::vector<std::int64_t>>(g, id, bs::kTargetOffsets);
  const auto indices = copy_of<std::vector<std::int64_t>>(g, id, bs::kTargetIndices);
  const auto weights = copy_of<std::vector<double>>(g, id, bs::kWeights);
  const auto names = copy_of<std::vector<std::string>>(g, id, bs::kTargetNames);
  const std::string points = std::to_string(base.size()) + " points";
  if (!offsets.empty() && (offsets.front() != 0 || static_cast<std::uint64_t>(offsets.back()) != deltas.size() ||
                           !std::is_sorted(offsets.begin(), offsets.end())))
    return refuse(where, "targetOffsets must rise from 0 to the " + std::to_string(deltas.size()) + " targetDeltas", "blendShape");
  if (!indices.empty() && indices.size() != deltas.size())
    return refuse(where, std::to_string(indices.size()) + " targetIndices for " + std::to_string(deltas.size()) + " targetDeltas",
                  "blendShape");
  // No indices: every target dense (no deltas at all: every target empty).
  const bool dense = indices.empty() && !deltas.empty();
  SceneBlend out;
  out.vertex_count = base.size();
  std::vector<char> seen(base.size(), 0);
  for (std::size_t t = 0; t + 1 < offsets.size(); ++t) {
    const auto begin = static_cast<std::size_t>(offsets[t]), end = static_cast<std::size_t>(offsets[t + 1]);
    const std::string target = "target " + std::to_string(t);
    if (dense && end - begin != base.size())
      return refuse(where, target + " is dense with " + std::to_string(end - begin) + " deltas for " + points, "blendShape");
    BlendTarget bt;
    bt.index = t;
    bt.name = t < names.size() ? names[t] : std::string();
    bt.weight = t < weights.size() ? weights[t] : 0.0;
    std::vector<std::pair<std::int64_t, Vec3>> moved;
    std::fill(seen.begin(), seen.end(), 0);
    for (std::size_t k = begin; k < end; ++k) {
      const std::int64_t v = dense ? static_cast<std::int64_t>(k - begin) : indices[k];
      if (v < 0 || static_cast<std::uint64_t>(v) >= base.size())
        return refuse(where, target + ": vertex " + std::to_string(v) + " is not one of the " + points, "blendShape");
      if (seen[static_cast<std::size_t>(v)]++)
        return refuse(where, target + ": vertex " + std::to_string(v) + " is listed twice", "blendShape");
      if (!deltas[k].allFinite())
        return refuse(where, target + ": the delta of vertex " + std::to_string(v) + " is not finite", "blendShape");
      if (deltas[k] != Vec3::Zero()) moved.emplace_back(v, deltas[k]);
    }
    std::sort(moved.begin(), moved.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (const auto& [v, d] : moved) bt.vertices.push_back(v), bt.deltas.push_back(d);
    out.targets.push_back(std::move(bt));
  }
  return out;
}

// One target of a file (`at`: its member path), checked against the vertex count.
Result<BlendTarget> read_target(const Json& t, const std::string& at, std::size_t vertex_count, const std::string& source) {
  if (!t.is_object()) return bad(source, at, "expected an object");
  BlendTarget out;
  if (!t.contains("index") || !t["index"].is_number_integer() || t["index"].get<std::int64_t>() < 0)
    return bad(source, at + ".index", "expected a whole number >= 0");
  out.index = t["index"].get<std::size_t>();
  if (!t.contains("name") || !t["name"].is_string()) return bad(source, at + ".name", "expected text (\"\" when unnamed)");
  out.name = t["name"].get<std::string>();
  if (!t.contains("weight") || !t["weight"].is_number() || !std::isfinite(t["weight"].get<double>()))
    return bad(source, at + ".weight", "expected a finite number");
  out.weight = t["weight"].get<double>();
  if (!t.contains("deltas") || !t["deltas"].is_array()) return bad(source, at + ".deltas", "expected an array");
  const Json& rows = t["deltas"];
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const Json& row = rows[k];
    const std::string where = at + ".deltas[" + std::to_string(k) + "]";
    if (!row.is_array() || row.size() != 4) return bad(source, where, "expected [vertex, dx, dy, dz]");
    if (!row[0].is_number_integer() || row[0].get<std::int64_t>() < 0 || row[0].get<std::uint64_t>() >= vertex_count)
      return bad(source, where, "vertex " + row[0].dump() + " is not one of the " + std::to_string(vertex_count) + " (vertexCount)");
    const auto v = row[0].get<std::int64_t>();
    Vec3 d;
    for (std::size_t c = 0; c < 3; ++c) {
      if (!row[c + 1].is_number() || !std::isfinite(row[c + 1].get<double>()))
        return bad(source, where, "expected three finite numbers after the vertex");
      d[static_cast<int>(c)] = row[c + 1].get<double>();
    }
    out.vertices.push_back(v);
    out.deltas.push_back(d);
  }
  // A vertex twice: the later line named.
  std::vector<std::size_t> order(out.vertices.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return out.vertices[a] != out.vertices[b] ? out.vertices[a] < out.vertices[b] : a < b;
  });
  for (std::size_t k = 1; k < order.size(); ++k)
    if (out.vertices[order[k]] == out.vertices[order[k - 1]])
      return bad(source, at + ".deltas[" + std::to_string(order[k]) + "]",
                 "vertex " + std::to_string(out.vertices[order[k]]) + " is listed twice");
  return out;
}

// Where a new blendShape goes on a mesh: in front of the skinCluster that
// feeds its points, else of the points set on it.
struct NewBlend {
  NodeId mesh, skin;  // skin invalid: the mesh's own points
  std::vector<Vec3> base;
};

Result<NewBlend> place_for(graph::Graph& g, const std::string& mesh_name) {
  const std::string where = "mesh '" + mesh_name + "'";
  NewBlend out;
  out.mesh = g.find(mesh_name);
  if (!is_type(g, out.mesh, scene::kMeshType)) return refuse(where, "the scene has no such mesh", "mesh");
  const std::optional<graph::Connection> points = fed(g, out.mesh, ma::kPoints);
  if (!points) {
    out.base = copy_of<std::vector<Vec3>>(g, out.mesh, ma::kPoints);
    return out;
  }
  if (is_type(g, points->src.node, ops::kSkinClusterType) && points->src.attr == sc::kOutPoints && points->dst.element < 0) {
    if (const auto bind = fed(g, points->src.node, sc::kBindPoints))
      return refuse(where, "its skinCluster's bindPoints come from " + g.plug_name(bind->src) + "; a new blendShape has no place",
                    "mesh");
    out.skin = points->src.node;
    out.base = copy_of<std::vector<Vec3>>(g, out.skin, sc::kBindPoints);
    return out;
  }
  return refuse(where, "its points come from " + g.plug_name(points->src) +
                           "; a new blendShape goes in front of a skinCluster or of points set on the mesh",
                "mesh");
}

// What one file blendShape becomes.
struct Plan {
  NodeId node;           // invalid: made (`made`)
  std::optional<NewBlend> made;
  std::string name;      // for messages and the made node
  std::vector<BlendTarget> targets;  // every target after the import, in order
  std::vector<char> from_file;       // per target: the file sets its weight
  std::vector<double> weight_now;    // per target: its weight before the import (0: added)
};

// The scene's targets with the file's merged in (blendshape_data.h's rules).
Status merge(const BlendShapeSet& file, const std::string& where, Plan& plan, BlendShapesReport& report) {
  const std::size_t count = plan.targets.size();
  std::vector<int> claimed(count, -1);
  plan.from_file.assign(count, 0);
  plan.weight_now.clear();
  for (const BlendTarget& t : plan.targets) plan.weight_now.push_back(t.weight);
  report.targets += file.targets.size();
  for (std::size_t f = 0; f < file.targets.size(); ++f) {
    const BlendTarget& t = file.targets[f];
    const std::string which = "the file's target " + std::to_string(t.index) + (t.name.empty() ? "" : " '" + t.name + "'");
    for (std::size_t k = 0; k < t.vertices.size(); ++k)
      if (t.vertices[k] < 0 || static_cast<std::uint64_t>(t.vertices[k]) >= file.vertex_count)
        return refuse(where, which + ": vertex " + std::to_string(t.vertices[k]) + " is out of range (the mesh has " +
                                 std::to_string(file.vertex_count) + " vertices)",
                      "blendShape");
    std::optional<std::size_t> at;
    for (std::size_t s = 0; !at && !t.name.empty() && s < count; ++s)
      if (plan.targets[s].name == t.name && claimed[s] < 0) at = s;
    if (!at && t.index < count && (t.name.empty() || plan.targets[t.index].name.empty())) at = t.index;
    if (at && claimed[*at] >= 0)
      return refuse(where, which + " and the file's target " + std::to_string(file.targets[static_cast<std::size_t>(claimed[*at])].index) +
                               " both go to target " + std::to_string(*at),
                    "blendShape");
    BlendTarget next = t;
    if (at) {
      claimed[*at] = static_cast<int>(f);
      next.index = *at;
      if (next.name.empty()) next.name = plan.targets[*at].name;
      plan.targets[*at] = std::move(next);
      plan.from_file[*at] = 1;
    } else {
      next.index = plan.targets.size();
      report.added.push_back(plan.name + ": " + (t.name.empty() ? "target " + std::to_string(t.index) : t.name));
      plan.targets.push_back(std::move(next));
      plan.from_file.push_back(1);
      plan.weight_now.push_back(0.0);
    }
  }
  return Status::ok();
}

Status write(graph::Graph& g, Plan& p, BlendShapesReport& report) {
  if (p.made) {
    Result<NodeId> id = g.create_node(ops::kBlendShapeType, p.name);
    if (!id) return id.status();
    p.node = *id;
    p.name = g.node(p.node)->name();
    Status s = g.set_value(Plug{p.node, bs::kBasePoints, -1}, graph::Value(p.made->base));
    const Plug to = p.made->skin.is_valid() ? Plug{p.made->skin, sc::kBindPoints, -1} : Plug{p.made->mesh, ma::kPoints, -1};
    if (s) s = g.connect(Plug{p.node, bs::kOutPoints, -1}, to);
    if (!s) return s;
    report.created.push_back(p.name + " on " + g.node(p.made->mesh)->name());
  }
  std::vector<Vec3> deltas;
  std::vector<std::int64_t> offsets{0}, indices;
  std::vector<std::string> names;
  for (const BlendTarget& t : p.targets) {
    deltas.insert(deltas.end(), t.deltas.begin(), t.deltas.end());
    indices.insert(indices.end(), t.vertices.begin(), t.vertices.end());
    offsets.push_back(static_cast<std::int64_t>(deltas.size()));
    names.push_back(t.name);
  }
  if (std::all_of(names.begin(), names.end(), [](const std::string& n) { return n.empty(); })) names.clear();
  Status s = g.set_value(Plug{p.node, bs::kTargetDeltas, -1}, graph::Value(std::move(deltas)));
  if (s) s = g.set_value(Plug{p.node, bs::kTargetOffsets, -1}, graph::Value(std::move(offsets)));
  if (s) s = g.set_value(Plug{p.node, bs::kTargetIndices, -1}, graph::Value(std::move(indices)));
  if (s) s = g.set_value(Plug{p.node, bs::kTargetNames, -1}, graph::Value(std::move(names)));
  // Weights: each element the file gives, unless something drives it.
  bool all_driven = false;
  std::set<std::int32_t> driven;
  for (const graph::Connection& c : g.node(p.node)->inputs()) {
    if (c.dst.attr != bs::kWeights) continue;
    if (c.dst.element < 0) all_driven = true;
    else driven.insert(c.dst.element);
  }
  for (std::size_t t = 0; s && t < p.targets.size(); ++t) {
    if (!p.from_file[t]) continue;
    const auto e = static_cast<std::int32_t>(t);
    if (all_driven || driven.count(e)) {
      if (p.targets[t].weight != p.weight_now[t])
        report.driven.push_back(p.name + ".weights[" + std::to_string(t) + "]");
      continue;
    }
    s = g.set_value(Plug{p.node, bs::kWeights, e}, graph::Value(p.targets[t].weight));
  }
  return s;
}

}  // namespace

Result<std::vector<BlendShapeSet>> capture_blend_shapes(graph::Graph& g) {
  std::vector<BlendShapeSet> out;
  for (NodeId id : g.nodes()) {
    if (!is_type(g, id, ops::kBlendShapeType)) continue;
    Result<SceneBlend> read = read_blend_shape(g, id);
    if (!read) return read.status();
    out.push_back(BlendShapeSet{g.node(id)->name(), mesh_of(g, id), read->vertex_count, std::move(read->targets)});
  }
  if (out.empty()) return Status(ErrorCode::kInvalidArgument, "the scene has no blend shapes (no blendShape node)");
  return out;
}

std::string blend_shapes_to_json(const std::vector<BlendShapeSet>& sets) {
  Json list = Json::array();
  for (const BlendShapeSet& s : sets) {
    Json targets = Json::array();
    for (const BlendTarget& t : s.targets) {
      Json deltas = Json::array();
      for (std::size_t k = 0; k < t.vertices.size(); ++k)
        deltas.push_back(Json::array({t.vertices[k], t.deltas[k].x(), t.deltas[k].y(), t.deltas[k].z()}));
      targets.push_back(Json{{"index", t.index}, {"name", t.name}, {"weight", t.weight}, {"deltas", std::move(deltas)}});
    }
    list.push_back(Json{{"blendShape", s.blend_shape},
                        {"mesh", s.mesh},
                        {"vertexCount", s.vertex_count},
                        {"targets", std::move(targets)}});
  }
  return io::diffable_json(Json{{"rigelBlendShapes", kBlendShapesFormat}, {"blendShapes", std::move(list)}});
}

Result<std::vector<BlendShapeSet>> blend_shapes_from_json(std::string_view text, const std::string& source) {
  Result<Json> parsed = io::parse_json(text, source, 16);
  if (!parsed) return parsed.status();
  const Json j = std::move(*parsed);
  if (!j.is_object() || !j.contains("rigelBlendShapes") || !j["rigelBlendShapes"].is_number_integer())
    return bad(source, "rigelBlendShapes", "not a rigel blend shapes file");
  if (j["rigelBlendShapes"].get<std::int64_t>() > kBlendShapesFormat)
    return Status(ErrorCode::kFailedPrecondition, source + ": made by a newer rigel (blend shapes format " +
                                                      std::to_string(j["rigelBlendShapes"].get<std::int64_t>()) + ")");
  if (!j.contains("blendShapes") || !j["blendShapes"].is_array()) return bad(source, "blendShapes", "expected an array");
  std::vector<BlendShapeSet> out;
  for (std::size_t i = 0; i < j["blendShapes"].size(); ++i) {
    const Json& b = j["blendShapes"][i];
    const std::string at = "blendShapes[" + std::to_string(i) + "]";
    if (!b.is_object()) return bad(source, at, "expected an object");
    BlendShapeSet set;
    for (const char* key : {"blendShape", "mesh"})
      if (!b.contains(key) || !b[key].is_string()) return bad(source, at + "." + key, "expected text");
    set.blend_shape = b["blendShape"].get<std::string>();
    set.mesh = b["mesh"].get<std::string>();
    if (!b.contains("vertexCount") || !b["vertexCount"].is_number_integer() || b["vertexCount"].get<std::int64_t>() < 0)
      return bad(source, at + ".vertexCount", "expected a whole number >= 0");
    set.vertex_count = b["vertexCount"].get<std::size_t>();
    if (!b.contains("targets") || !b["targets"].is_array()) return bad(source, at + ".targets", "expected an array");
    std::map<std::size_t, std::size_t> indices;
    std::map<std::string, std::size_t> names;
    for (std::size_t t = 0; t < b["targets"].size(); ++t) {
      const std::string where = at + ".targets[" + std::to_string(t) + "]";
      Result<BlendTarget> target = read_target(b["targets"][t], where, set.vertex_count, source);
      if (!target) return target.status();
      if (auto [it, fresh] = indices.emplace(target->index, t); !fresh)
        return bad(source, where + ".index", std::to_string(target->index) + " is also targets[" + std::to_string(it->second) + "]'s");
      if (!target->name.empty())
        if (auto [it, fresh] = names.emplace(target->name, t); !fresh)
          return bad(source, where + ".name", "'" + target->name + "' is also targets[" + std::to_string(it->second) + "]'s");
      set.targets.push_back(std::move(*target));
    }
    out.push_back(std::move(set));
  }
  return out;
}

Result<BlendShapesReport> apply_blend_shapes(graph::Graph& g, const std::vector<BlendShapeSet>& sets,
                                             const BlendShapesImport& options) {
  std::vector<std::pair<NodeId, std::string>> scene;  // every blendShape and its mesh
  for (NodeId id : g.nodes())
    if (is_type(g, id, ops::kBlendShapeType)) scene.emplace_back(id, mesh_of(g, id));
  BlendShapesReport report;
  std::vector<Plan> plans;
  std::set<std::string> claimed;  // nodes, and meshes given a new blendShape
  for (const BlendShapeSet& file : sets) {
    const std::string where = blend_where(file.blend_shape);
    Plan plan;
    for (const auto& [id, mesh] : scene)
      if (g.node(id)->name() == file.blend_shape) plan.node = id;
    for (const auto& [id, mesh] : scene)
      if (!plan.node.is_valid() && !file.mesh.empty() && mesh == file.mesh) plan.node = id;
    std::size_t vertex_count = 0;
    if (plan.node.is_valid()) {
      plan.name = g.node(plan.node)->name();
      Result<SceneBlend> read = read_blend_shape(g, plan.node);
      if (!read) return read.status();
      vertex_count = read->vertex_count;
      plan.targets = std::move(read->targets);
    } else {
      if (!options.create || !is_type(g, g.find(file.mesh), scene::kMeshType))
        return refuse(where, "the scene has no such blendShape, nor one on mesh '" + file.mesh + "'" +
                                 (options.create ? "" : " (and none is made)"),
                      "blendShape");
      Result<NewBlend> place = place_for(g, file.mesh);
      if (!place) return place.status().with_context(where);
      vertex_count = place->base.size();
      plan.made = std::move(*place);
      plan.name = graph::Graph::is_valid_name(file.blend_shape) ? file.blend_shape : file.mesh + "_blendShape";
    }
    const std::string key = plan.node.is_valid() ? plan.name : "mesh " + file.mesh;
    if (!claimed.insert(key).second)
      return refuse(where, "the file lists it (or its mesh '" + file.mesh + "') twice", "blendShape");
    if (file.vertex_count != vertex_count)
      return refuse(where, std::to_string(file.vertex_count) + " vertices in the file, " + std::to_string(vertex_count) +
                               " in the scene",
                    "blendShape");
    if (Status s = merge(file, where, plan, report); !s) return s;
    plans.push_back(std::move(plan));
  }
  graph::Transaction tx(g, "import blend shapes");
  for (Plan& p : plans) {
    if (Status s = write(g, p, report); !s) {
      tx.rollback();
      return s.with_context(blend_where(p.name));
    }
    ++report.blend_shapes;
  }
  return report;
}

}  // namespace rigel::tools
