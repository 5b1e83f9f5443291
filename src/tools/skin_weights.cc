// Skin weights as data (skin_weights.h): capture, the file, and import with
// matching by uuid, name, a name table or position, and mirroring.

#include "rigel/tools/skin_weights.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <unordered_map>

#include <nlohmann/json.hpp>

#include "rigel/io/checksum.h"
#include "rigel/io/diffable_json.h"
#include "rigel/io/scene_file.h"
#include "rigel/io/json_depth.h"
#include "rigel/ops/deform/nodes.h"
#include "rigel/rig/templates.h"

namespace rigel::tools {

using graph::NodeId;
using graph::Plug;
using Json = nlohmann::ordered_json;
using math::Vec3;
namespace sc = ops::skin_cluster_attr;

namespace {

// One skinCluster of the scene and what it is wired to.
struct SceneSkin {
  NodeId node;
  std::string mesh;                  // the node its outPoints feed ("" when none)
  std::vector<NodeId> joints;        // per jointMatrices element (invalid when unconnected)
  std::vector<SkinInfluence> influences;
  std::vector<Vec3> bind_points;
};

template <typename T>
T value_of(graph::Graph& g, NodeId n, graph::AttrIndex a) {
  const graph::Value& v = g.evaluate(n, a);
  const T* p = std::get_if<T>(&v);
  return p ? *p : T{};
}

std::vector<SceneSkin> scene_skins(scene::Scene& scene) {
  graph::Graph& g = scene.graph();
  std::vector<SceneSkin> out;
  const std::vector<graph::Connection> connections = g.connections();
  for (NodeId id : g.nodes()) {
    if (g.node(id)->type().name() != ops::kSkinClusterType) continue;
    SceneSkin s;
    s.node = id;
    for (const graph::Connection& c : connections)
      if (c.src.node == id && c.src.attr == sc::kOutPoints && g.node(c.dst.node)) s.mesh = g.node(c.dst.node)->name();
    const auto matrices = value_of<std::vector<math::Mat4>>(g, id, sc::kJointMatrices);
    const auto bind_pre = value_of<std::vector<math::Mat4>>(g, id, sc::kBindPreMatrices);
    for (std::size_t k = 0; k < matrices.size(); ++k) {
      const auto src = g.source(Plug{id, sc::kJointMatrices, static_cast<std::int32_t>(k)});
      const NodeId j = src ? src->node : NodeId{};
      s.joints.push_back(j);
      SkinInfluence inf;
      if (const graph::Node* n = g.node(j)) {
        inf.joint = n->name();
        inf.uuid = n->uuid().str();
      }
      const math::Mat4 bind = k < bind_pre.size() ? math::Mat4(bind_pre[k].inverse()) : matrices[k];
      inf.bind = bind.block<3, 1>(0, 3);
      s.influences.push_back(std::move(inf));
    }
    s.bind_points = value_of<std::vector<Vec3>>(g, id, sc::kBindPoints);
    out.push_back(std::move(s));
  }
  return out;
}

Status bad(const std::string& source, const std::string& where, const std::string& what) {
  return Status(ErrorCode::kParseError, source + ": " + where + ": " + what);
}

// The nearest point of a set, by a uniform grid (linear in the points to
// build, about constant per query on a surface).
class Nearest {
 public:
  explicit Nearest(const std::vector<Vec3>& points) : points_(points) {
    if (points.empty()) return;
    lo_ = hi_ = points[0];
    for (const Vec3& p : points) lo_ = lo_.cwiseMin(p), hi_ = hi_.cwiseMax(p);
    const double extent = std::max((hi_ - lo_).maxCoeff(), 1e-9);
    cell_ = std::max(extent / std::max(1.0, std::cbrt(static_cast<double>(points.size()))), 1e-9);
    for (std::size_t i = 0; i < points.size(); ++i) cells_[key(cell_of(points[i]))].push_back(i);
  }
  std::size_t operator()(const Vec3& q) const {
    const std::array<long, 3> c = cell_of(q.cwiseMax(lo_).cwiseMin(hi_));
    std::size_t best = 0;
    double best_d = std::numeric_limits<double>::infinity();
    for (long r = 0;; ++r) {
      for (long x = c[0] - r; x <= c[0] + r; ++x)
        for (long y = c[1] - r; y <= c[1] + r; ++y)
          for (long z = c[2] - r; z <= c[2] + r; ++z) {
            if (std::max({std::labs(x - c[0]), std::labs(y - c[1]), std::labs(z - c[2])}) != r) continue;
            auto it = cells_.find(key({x, y, z}));
            if (it == cells_.end()) continue;
            for (std::size_t i : it->second) {
              const double d = (points_[i] - q).squaredNorm();
              if (d < best_d || (d == best_d && i < best)) best_d = d, best = i;
            }
          }
      // Everything within r cells of the query's cell has been seen; a
      // point nearer than r * cell cannot lie further out.
      if (best_d <= std::pow(static_cast<double>(r) * cell_, 2) || r > 1 << 20) break;
      if (r * cell_ > 2 * (hi_ - lo_).norm() + (q - lo_).norm() + cell_) break;
    }
    return best;
  }

 private:
  std::array<long, 3> cell_of(const Vec3& p) const {
    return {static_cast<long>(std::floor((p.x() - lo_.x()) / cell_)), static_cast<long>(std::floor((p.y() - lo_.y()) / cell_)),
            static_cast<long>(std::floor((p.z() - lo_.z()) / cell_))};
  }
  static std::uint64_t key(const std::array<long, 3>& c) {
    return (static_cast<std::uint64_t>(c[0] & 0x1fffff) << 42) | (static_cast<std::uint64_t>(c[1] & 0x1fffff) << 21) |
           static_cast<std::uint64_t>(c[2] & 0x1fffff);
  }
  const std::vector<Vec3>& points_;
  Vec3 lo_ = Vec3::Zero(), hi_ = Vec3::Zero();
  double cell_ = 1;
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> cells_;
};

}  // namespace

Result<std::vector<SkinWeights>> capture_skin_weights(scene::Scene& scene) {
  graph::Graph& g = scene.graph();
  std::vector<SkinWeights> out;
  for (SceneSkin& s : scene_skins(scene)) {
    SkinWeights w;
    w.skin = g.node(s.node)->name();
    w.mesh = s.mesh;
    w.influences = std::move(s.influences);
    w.offsets = value_of<std::vector<std::int64_t>>(g, s.node, sc::kInfluenceOffsets);
    w.joints = value_of<std::vector<std::int64_t>>(g, s.node, sc::kInfluenceJoints);
    w.weights = value_of<std::vector<double>>(g, s.node, sc::kInfluenceWeights);
    out.push_back(std::move(w));
  }
  if (out.empty()) return Status(ErrorCode::kInvalidArgument, "the scene has no skinned mesh (no skinCluster)");
  return out;
}

namespace {

constexpr std::string_view kSideMagic = "RIGELWB1";  // 8 bytes, then each skin's block

void put_u32(std::string& out, std::uint64_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}
void put_f64(std::string& out, double d) {
  const auto bits = std::bit_cast<std::uint64_t>(d);
  for (int i = 0; i < 8; ++i) out.push_back(static_cast<char>((bits >> (8 * i)) & 0xff));
}
std::uint64_t get_le(std::string_view bytes, std::size_t at, int n) {
  std::uint64_t v = 0;
  for (int i = 0; i < n; ++i) v |= static_cast<std::uint64_t>(static_cast<unsigned char>(bytes[at + static_cast<std::size_t>(i)])) << (8 * i);
  return v;
}

// The side file: "RIGELWB1", then each skin's block (per vertex its
// influence count, then every entry's influence, then every entry's
// weight: uint32, uint32, float64, little-endian), in the skins' order.
std::string side_file(const std::vector<SkinWeights>& skins) {
  std::string side(kSideMagic);
  for (const SkinWeights& s : skins) {
    for (std::size_t v = 0; v + 1 < s.offsets.size(); ++v) put_u32(side, static_cast<std::uint64_t>(s.offsets[v + 1] - s.offsets[v]));
    for (std::int64_t j : s.joints) put_u32(side, static_cast<std::uint64_t>(j));
    for (double w : s.weights) put_f64(side, w);
  }
  return side;
}

struct SideRef {
  std::string name, checksum;
  std::size_t bytes = 0;
};

// The file; with `side`, each skin points at its block of the side file by
// byte offset instead of listing its vertices.
std::string weights_json(const std::vector<SkinWeights>& skins, const SideRef* side) {
  Json list = Json::array();
  std::size_t offset = kSideMagic.size();
  for (const SkinWeights& s : skins) {
    Json influences = Json::array();
    for (const SkinInfluence& i : s.influences)
      influences.push_back(Json{{"joint", i.joint}, {"uuid", i.uuid}, {"bind", Json::array({i.bind.x(), i.bind.y(), i.bind.z()})}});
    Json skin{{"skin", s.skin}, {"mesh", s.mesh}, {"vertexCount", s.vertex_count()}, {"influences", std::move(influences)}};
    if (side) {
      skin["block"] = Json{{"offset", offset}, {"entries", s.joints.size()}};
      offset += 4 * s.vertex_count() + 12 * s.joints.size();
    } else {
      Json vertices = Json::array();
      for (std::size_t v = 0; v + 1 < s.offsets.size(); ++v) {
        Json row = Json::array();
        for (std::int64_t k = s.offsets[v]; k < s.offsets[v + 1]; ++k) {
          row.push_back(s.joints[static_cast<std::size_t>(k)]);
          row.push_back(s.weights[static_cast<std::size_t>(k)]);
        }
        vertices.push_back(std::move(row));
      }
      skin["vertices"] = std::move(vertices);
    }
    list.push_back(std::move(skin));
  }
  Json top{{"rigelWeights", kWeightsFormat}};
  if (side) top["binary"] = Json{{"file", side->name}, {"bytes", side->bytes}, {"checksum", side->checksum}};
  top["skins"] = std::move(list);
  io::DiffableJsonOptions o;
  o.inline_flat_objects_in_arrays = true;
  return io::diffable_json(top, o);
}

// Skin `w`'s vertices from its block of the side file (checked whole
// against its checksum already).
Status read_block(const std::string& source, const std::string& at, const Json& block, std::string_view bytes,
                  std::size_t vertex_count, SkinWeights& w) {
  if (!block.is_object() || !block.contains("offset") || !block["offset"].is_number_unsigned() || !block.contains("entries") ||
      !block["entries"].is_number_unsigned())
    return bad(source, at, "expected {\"offset\", \"entries\"} (whole numbers)");
  const std::uint64_t offset = block["offset"].get<std::uint64_t>(), entries = block["entries"].get<std::uint64_t>();
  const std::uint64_t size = 4 * static_cast<std::uint64_t>(vertex_count) + 12 * entries;
  if (offset < kSideMagic.size() || offset > bytes.size() || vertex_count > bytes.size() || entries > bytes.size() ||
      size > bytes.size() - offset)
    return bad(source, at, "lies outside the side file (" + std::to_string(bytes.size()) + " bytes)");
  std::size_t p = static_cast<std::size_t>(offset);
  w.offsets.assign(1, 0);
  for (std::size_t v = 0; v < vertex_count; ++v, p += 4)
    w.offsets.push_back(w.offsets.back() + static_cast<std::int64_t>(get_le(bytes, p, 4)));
  if (static_cast<std::uint64_t>(w.offsets.back()) != entries)
    return bad(source, at, "the vertices' influence counts add up to " + std::to_string(w.offsets.back()) + ", not " + std::to_string(entries));
  for (std::uint64_t k = 0; k < entries; ++k, p += 4) {
    const std::uint64_t j = get_le(bytes, p, 4);
    if (j >= w.influences.size())
      return bad(source, at, "entry " + std::to_string(k) + ": influence " + std::to_string(j) + " is not one of the " +
                                 std::to_string(w.influences.size()));
    w.joints.push_back(static_cast<std::int64_t>(j));
  }
  for (std::uint64_t k = 0; k < entries; ++k, p += 8) {
    const double d = std::bit_cast<double>(get_le(bytes, p, 8));
    if (!std::isfinite(d) || d < 0) return bad(source, at, "entry " + std::to_string(k) + ": weight is not a finite number >= 0");
    w.weights.push_back(d);
  }
  return Status::ok();
}

}  // namespace

std::string skin_weights_to_json(const std::vector<SkinWeights>& skins) { return weights_json(skins, nullptr); }

WeightsFiles skin_weights_to_files(const std::vector<SkinWeights>& skins, WeightsFormat format, const std::string& stem) {
  WeightsFiles out;
  if (format == WeightsFormat::kJson) {
    out.json = weights_json(skins, nullptr);
    return out;
  }
  // The side file's name holds its checksum: a new export never overwrites
  // the file an older weights file names, so replacing the pair is atomic
  // (the JSON is written last).
  out.side = side_file(skins);
  const std::string checksum = io::checksum_of(out.side);
  out.side_name = stem + "." + checksum.substr(std::string_view("fnv1a64:").size(), 8) + ".bin";
  const SideRef ref{out.side_name, checksum, out.side.size()};
  out.json = weights_json(skins, &ref);
  return out;
}

Result<WeightsFormat> weights_format_named(std::string_view name) {
  if (name == "json") return WeightsFormat::kJson;
  if (name == "binary") return WeightsFormat::kBinary;
  return Status(ErrorCode::kInvalidArgument, "weights format '" + std::string(name) + "': expected json or binary").with_field("format");
}

Result<std::vector<SkinWeights>> skin_weights_from_json(std::string_view text, const std::string& source, const SideFileReader& read_side) {
  Result<Json> parsed = io::parse_json(text, source, 16);
  if (!parsed) return parsed.status();
  Json j = std::move(*parsed);
  if (!j.is_object() || !j.contains("rigelWeights") || !j["rigelWeights"].is_number_integer())
    return bad(source, "rigelWeights", "not a rigel weights file");
  if (j["rigelWeights"].get<std::int64_t>() > kWeightsFormat)
    return Status(ErrorCode::kFailedPrecondition, source + ": made by a newer rigel (weights format " +
                                                      std::to_string(j["rigelWeights"].get<std::int64_t>()) + ")");
  if (!j.contains("skins") || !j["skins"].is_array()) return bad(source, "skins", "expected an array");
  // The side file, when the arrays are in one: named plainly beside the
  // weights file (never a path elsewhere), of the size and checksum recorded.
  std::string side;
  const bool binary = j.contains("binary");
  if (binary) {
    const Json& b = j["binary"];
    if (!b.is_object() || !b.contains("file") || !b["file"].is_string() || !b.contains("bytes") || !b["bytes"].is_number_unsigned() ||
        !b.contains("checksum") || !b["checksum"].is_string())
      return bad(source, "binary", "expected {\"file\", \"bytes\", \"checksum\"}");
    const std::string name = b["file"].get<std::string>();
    if (name.empty() || name == "." || name == ".." || name.find_first_of("/\\") != std::string::npos)
      return bad(source, "binary.file", "'" + name + "' is not a plain file name (the side file lies beside the weights file)");
    if (!read_side) return bad(source, "binary.file", "names a side file, and nothing reads one here (read the weights file from disk)");
    Result<std::string> bytes = read_side(name);
    if (!bytes) return Status(bytes.status()).with_context(source + ": binary.file");
    side = std::move(*bytes);
    if (side.size() != b["bytes"].get<std::uint64_t>())
      return bad(source, "binary.bytes", name + " has " + std::to_string(side.size()) + " bytes, the file says " + b["bytes"].dump());
    if (io::checksum_of(side) != b["checksum"].get<std::string>())
      return bad(source, "binary.checksum", name + " is not the side file this file was written with (checksum " + io::checksum_of(side) + ")");
    if (side.compare(0, kSideMagic.size(), kSideMagic) != 0) return bad(source, "binary.file", name + " is not a rigel weights side file");
  }
  std::vector<SkinWeights> out;
  for (std::size_t si = 0; si < j["skins"].size(); ++si) {
    const Json& s = j["skins"][si];
    const std::string at = "skins[" + std::to_string(si) + "]";
    if (!s.is_object()) return bad(source, at, "expected an object");
    SkinWeights w;
    for (const char* key : {"skin", "mesh"})
      if (!s.contains(key) || !s[key].is_string()) return bad(source, at + "." + key, "expected text");
    w.skin = s["skin"].get<std::string>();
    w.mesh = s["mesh"].get<std::string>();
    if (!s.contains("influences") || !s["influences"].is_array()) return bad(source, at + ".influences", "expected an array");
    for (std::size_t i = 0; i < s["influences"].size(); ++i) {
      const Json& inf = s["influences"][i];
      const std::string where = at + ".influences[" + std::to_string(i) + "]";
      if (!inf.is_object() || !inf.contains("joint") || !inf["joint"].is_string() || !inf.contains("uuid") ||
          !inf["uuid"].is_string() || !inf.contains("bind") || !inf["bind"].is_array() || inf["bind"].size() != 3)
        return bad(source, where, "expected {\"joint\", \"uuid\", \"bind\": [x, y, z]}");
      SkinInfluence x{inf["joint"].get<std::string>(), inf["uuid"].get<std::string>(), Vec3::Zero()};
      for (int c = 0; c < 3; ++c) {
        const Json& n = inf["bind"][static_cast<std::size_t>(c)];
        if (!n.is_number() || !std::isfinite(n.get<double>())) return bad(source, where + ".bind", "expected three finite numbers");
        x.bind[c] = n.get<double>();
      }
      w.influences.push_back(std::move(x));
    }
    if (binary) {
      if (!s.contains("vertexCount") || !s["vertexCount"].is_number_unsigned()) return bad(source, at + ".vertexCount", "expected a whole number");
      if (!s.contains("block")) return bad(source, at + ".block", "missing (the file's arrays are in its side file)");
      if (Status st = read_block(source, at + ".block", s["block"], side, s["vertexCount"].get<std::size_t>(), w); !st) return st;
      out.push_back(std::move(w));
      continue;
    }
    if (!s.contains("vertices") || !s["vertices"].is_array()) return bad(source, at + ".vertices", "expected an array");
    if (s.contains("vertexCount") && (!s["vertexCount"].is_number_unsigned() || s["vertexCount"].get<std::size_t>() != s["vertices"].size()))
      return bad(source, at + ".vertexCount", "does not match the vertices (" + std::to_string(s["vertices"].size()) + ")");
    w.offsets.push_back(0);
    for (std::size_t v = 0; v < s["vertices"].size(); ++v) {
      const Json& row = s["vertices"][v];
      const std::string where = at + ".vertices[" + std::to_string(v) + "]";
      if (!row.is_array() || row.size() % 2 != 0) return bad(source, where, "expected [influence, weight, ...] pairs");
      for (std::size_t k = 0; k < row.size(); k += 2) {
        if (!row[k].is_number_integer() || row[k].get<std::int64_t>() < 0 ||
            row[k].get<std::size_t>() >= w.influences.size())
          return bad(source, where, "influence " + row[k].dump() + " is not one of the " + std::to_string(w.influences.size()));
        if (!row[k + 1].is_number() || !std::isfinite(row[k + 1].get<double>()) || row[k + 1].get<double>() < 0)
          return bad(source, where, "weight " + row[k + 1].dump() + " is not a finite number >= 0");
        w.joints.push_back(row[k].get<std::int64_t>());
        w.weights.push_back(row[k + 1].get<double>());
      }
      w.offsets.push_back(static_cast<std::int64_t>(w.joints.size()));
    }
    out.push_back(std::move(w));
  }
  return out;
}

Result<WeightsReport> apply_skin_weights(scene::Scene& scene, const std::vector<SkinWeights>& skins, const WeightsImport& options) {
  graph::Graph& g = scene.graph();
  std::vector<SceneSkin> targets = scene_skins(scene);
  struct Plan {
    NodeId node;
    std::vector<std::int64_t> offsets, joints;
    std::vector<double> weights;
  };
  std::vector<Plan> plans;
  WeightsReport report;
  for (const SkinWeights& file : skins) {
    const SceneSkin* t = nullptr;
    for (const SceneSkin& s : targets)
      if (g.node(s.node)->name() == file.skin) t = &s;
    for (const SceneSkin& s : targets)
      if (!t && !file.mesh.empty() && s.mesh == file.mesh) t = &s;
    const std::string where = "skin '" + file.skin + "'";
    if (!t) return Status(ErrorCode::kInvalidArgument, where + ": the scene has no such skinCluster, nor one on mesh '" + file.mesh + "'").with_field("skin");
    const std::size_t n = file.vertex_count();
    if (n != t->bind_points.size() && !t->bind_points.empty())
      return Status(ErrorCode::kInvalidArgument, where + ": " + std::to_string(n) + " vertices in the file, " +
                                                     std::to_string(t->bind_points.size()) + " in the scene").with_field("skin");
    // Each file influence onto one of the target's.
    std::vector<Vec3> target_binds;
    for (const SkinInfluence& i : t->influences) target_binds.push_back(i.bind);
    const Nearest nearest_joint(target_binds);
    std::vector<std::int64_t> map;
    for (const SkinInfluence& inf : file.influences) {
      std::string name = inf.joint;
      if (auto r = options.rename.find(name); r != options.rename.end()) name = r->second;
      const std::string mirrored = options.mirror ? rig::mirror_name(name) : name;
      std::int64_t found = -1;
      for (std::size_t k = 0; found < 0 && mirrored == name && k < t->influences.size(); ++k)
        if (!inf.uuid.empty() && t->influences[k].uuid == inf.uuid) found = static_cast<std::int64_t>(k);
      for (std::size_t k = 0; found < 0 && k < t->influences.size(); ++k)
        if (t->influences[k].joint == mirrored) found = static_cast<std::int64_t>(k);
      if (found < 0 && options.nearest && !target_binds.empty()) {
        const Vec3 p = options.mirror ? Vec3(-inf.bind.x(), inf.bind.y(), inf.bind.z()) : inf.bind;
        found = static_cast<std::int64_t>(nearest_joint(p));
      }
      if (found < 0)
        return Status(ErrorCode::kInvalidArgument, where + ": joint '" + inf.joint + "'" +
                                                       (mirrored != inf.joint ? " (as '" + mirrored + "')" : std::string()) +
                                                       " is not one of the skin's joints (give a rename table or nearest)")
            .with_field("joints");
      if (t->influences[static_cast<std::size_t>(found)].uuid != inf.uuid)
        report.remapped.push_back(inf.joint + " -> " + t->influences[static_cast<std::size_t>(found)].joint);
      map.push_back(found);
    }
    // The source vertex of each: itself, or the one nearest its mirror image.
    std::vector<std::size_t> source(n);
    for (std::size_t v = 0; v < n; ++v) source[v] = v;
    if (options.mirror && !t->bind_points.empty()) {
      const Nearest nearest_point(t->bind_points);
      for (std::size_t v = 0; v < n; ++v) {
        const Vec3& p = t->bind_points[v];
        source[v] = nearest_point(Vec3(-p.x(), p.y(), p.z()));
      }
    }
    Plan plan{t->node, {0}, {}, {}};
    for (std::size_t v = 0; v < n; ++v) {
      const std::size_t u = source[v];
      const std::size_t start = plan.joints.size();
      for (std::int64_t k = file.offsets[u]; k < file.offsets[u + 1]; ++k) {
        const std::int64_t j = map[static_cast<std::size_t>(file.joints[static_cast<std::size_t>(k)])];
        const double w = file.weights[static_cast<std::size_t>(k)];
        auto same = std::find(plan.joints.begin() + static_cast<std::ptrdiff_t>(start), plan.joints.end(), j);
        if (same != plan.joints.end()) plan.weights[static_cast<std::size_t>(same - plan.joints.begin())] += w;
        else plan.joints.push_back(j), plan.weights.push_back(w);
      }
      plan.offsets.push_back(static_cast<std::int64_t>(plan.joints.size()));
    }
    report.vertices += n;
    ++report.skins;
    plans.push_back(std::move(plan));
  }
  graph::Transaction tx(g, "import skin weights");
  for (Plan& p : plans) {
    Status s = g.set_value(Plug{p.node, sc::kInfluenceOffsets, -1}, graph::Value(std::move(p.offsets)));
    if (s) s = g.set_value(Plug{p.node, sc::kInfluenceJoints, -1}, graph::Value(std::move(p.joints)));
    if (s) s = g.set_value(Plug{p.node, sc::kInfluenceWeights, -1}, graph::Value(std::move(p.weights)));
    if (!s) {
      tx.rollback();
      return s.with_context("skin '" + g.node(p.node)->name() + "'");
    }
  }
  return report;
}

}  // namespace rigel::tools

namespace rigel::tools {

namespace fs = std::filesystem;

Status write_skin_weights(const fs::path& file, const std::vector<SkinWeights>& skins, WeightsFormat format) {
  std::string stem = file.filename().string();
  if (stem.ends_with(".json")) stem.resize(stem.size() - 5);
  // The side file the weights file names now, removed once the new pair is
  // written (when it is another).
  std::string old_side;
  {
    std::ifstream in(file, std::ios::binary);
    std::ostringstream text;
    if (in) text << in.rdbuf();
    Result<Json> old = io::parse_json(text.str(), file.string(), 16);
    if (old && old->is_object() && old->contains("binary") && (*old)["binary"].is_object() && (*old)["binary"].contains("file") &&
        (*old)["binary"]["file"].is_string()) {
      const std::string name = (*old)["binary"]["file"].get<std::string>();
      if (name.starts_with(stem + ".") && name.ends_with(".bin") && name.find_first_of("/\\") == std::string::npos) old_side = name;
    }
  }
  const WeightsFiles files = skin_weights_to_files(skins, format, stem);
  if (!files.side_name.empty())
    if (Status s = io::write_file_atomic(file.parent_path() / files.side_name, files.side); !s) return s;
  if (Status s = io::write_file_atomic(file, files.json); !s) return s;
  if (!old_side.empty() && old_side != files.side_name) {
    std::error_code ec;
    fs::remove(file.parent_path() / old_side, ec);  // best effort: a stale side file harms nothing
  }
  return Status::ok();
}

namespace {

Result<std::string> read_bytes(const fs::path& path, const std::string& what) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return Status(ErrorCode::kNotFound, path.string() + ": no such " + what);
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in && !in.eof()) return Status(ErrorCode::kIoError, path.string() + ": cannot be read");
  return text.str();
}

}  // namespace

SideFileReader side_files_beside(const fs::path& file) {
  return [dir = file.parent_path()](const std::string& name) { return read_bytes(dir / name, "side file"); };
}

Result<std::vector<SkinWeights>> read_skin_weights(const fs::path& file) {
  Result<std::string> text = read_bytes(file, "weights file");
  if (!text) return text.status();
  return skin_weights_from_json(*text, file.string(), side_files_beside(file));
}

}  // namespace rigel::tools
