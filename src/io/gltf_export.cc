#include "rigel/io/gltf_export.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <iterator>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>
#include <set>
#include <span>
#include <sstream>
#include <tuple>
#include <unordered_map>

#include "rigel/io/gltf_import.h"
#include "rigel/io/scene_file.h"
#include "rigel/math/transform.h"
#include "rigel/ops/anim/clips.h"
#include "rigel/ops/anim/curve.h"
#include "rigel/ops/anim/nodes.h"
#include "rigel/ops/anim/track.h"
#include "rigel/ops/deform/nodes.h"
#include "rigel/ops/deform/skin.h"
#include "rigel/scene/skeleton.h"
#include "rigel/scene/transform_types.h"

#include "gltf_materials.h"

namespace rigel::io {
namespace {

namespace fs = std::filesystem;
namespace xf = scene::xform;
namespace anim = ops::anim;
using graph::AttrIndex;
using graph::Graph;
using graph::Node;
using graph::NodeId;
using graph::Plug;
using graph::Value;
using math::Mat4;
using math::Quat;
using math::Vec3;

// A skinned mesh's world matrix and its skinCluster's geomMatrix count as
// equal within this (relative to the larger entry, at least 1).
constexpr double kGeomTolerance = 1e-9;
// Shear below this is rounding, not shear.
constexpr double kShearTolerance = 1e-9;
// Shear left out of the file is reported (a note) above this: below, it is
// beyond what 32-bit floats in a viewer show.
constexpr double kVisibleShear = 1e-4;
// A baked channel is constant when every sample is within this of the first
// (relative to its size, at least 1); a constant channel is left out when it
// is this close to the node's static value.
constexpr double kConstantTolerance = 1e-10;
// Scales this close to 1 are 1 (decomposition rounding).
constexpr double kUnitScaleTolerance = 1e-14;
// More frames than this in one export is a mistake, not a bake.
constexpr double kMaxFrames = 1e7;

enum class Path : std::uint8_t { kTranslation, kRotation, kScale, kWeights };

const char* path_name(Path path) {
  switch (path) {
    case Path::kTranslation: return "translation";
    case Path::kRotation: return "rotation";
    case Path::kScale: return "scale";
    case Path::kWeights: return "weights";
  }
  return "";
}

std::string lower(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

// A number as people write it: "12", "0.5", "1e-07".
std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.10g", value);
  return text;
}

double max_abs(const Mat4& m) { return m.cwiseAbs().maxCoeff(); }

bool near_matrix(const Mat4& a, const Mat4& b, double tolerance) {
  return math::is_near(a, b, tolerance * std::max({1.0, max_abs(a), max_abs(b)}));
}

bool near_vec(const Vec3& a, const Vec3& b, double tolerance) {
  const double scale = std::max({1.0, a.cwiseAbs().maxCoeff(), b.cwiseAbs().maxCoeff()});
  return (a - b).cwiseAbs().maxCoeff() <= tolerance * scale;
}

// q and -q are the same rotation.
bool near_quat(const Quat& a, const Quat& b, double tolerance) {
  const double plus = (a.coeffs() - b.coeffs()).cwiseAbs().maxCoeff();
  const double minus = (a.coeffs() + b.coeffs()).cwiseAbs().maxCoeff();
  return std::min(plus, minus) <= tolerance;
}

std::string type_of(const Graph& g, NodeId id) { return g.node(id)->type().name(); }

// "hips_rotate.output (animCurveVec3)"
std::string describe(const Graph& g, const Plug& plug) { return g.plug_name(plug) + " (" + type_of(g, plug.node) + ")"; }

template <typename T>
const T& value_as(Graph& g, NodeId node, AttrIndex attr) {
  return std::get<T>(g.evaluate(node, attr));
}

// ---- what depends on time ----------------------------------------------------

// Whether a node's outputs change with the graph's time: its type is
// time-dependent, or something upstream is. Memoised; iterative, so deep
// chains do not overflow the stack.
class TimeDependence {
 public:
  explicit TimeDependence(const Graph& graph) : graph_(graph) {}

  bool of(NodeId start) {
    if (auto it = state_.find(start.index); it != state_.end() && it->second != kVisiting) return it->second == kYes;
    struct Frame {
      NodeId id;
      std::size_t next = 0;
      bool yes = false;
    };
    std::vector<Frame> stack{{start, 0, graph_.node(start)->type().time_dependent()}};
    state_[start.index] = kVisiting;
    while (!stack.empty()) {
      Frame& top = stack.back();
      const std::span<const graph::Connection> inputs = graph_.node(top.id)->inputs();
      if (top.yes || top.next >= inputs.size()) {
        const bool yes = top.yes;
        state_[top.id.index] = yes ? kYes : kNo;
        stack.pop_back();
        if (yes && !stack.empty()) stack.back().yes = true;
        continue;
      }
      const NodeId source = inputs[top.next++].src.node;
      if (auto it = state_.find(source.index); it != state_.end()) {
        if (it->second == kYes) top.yes = true;
        continue;  // known, or on the stack (graphs are acyclic, so never)
      }
      state_[source.index] = kVisiting;
      stack.push_back({source, 0, graph_.node(source)->type().time_dependent()});
    }
    return state_[start.index] == kYes;
  }

 private:
  enum : std::uint8_t { kVisiting = 1, kNo = 2, kYes = 3 };
  const Graph& graph_;
  std::unordered_map<std::uint32_t, std::uint8_t> state_;
};

// ---- clips -------------------------------------------------------------------

struct ClipList {
  NodeId node;  // the animClips node; invalid when the scene has none
  std::vector<anim::Clip> clips;
  int active = 0;
};

AttrIndex attr_named(const Graph& g, NodeId node, std::string_view name) {
  return g.node(node)->type().attr_find(name);
}

Result<ClipList> read_clips(Graph& g) {
  ClipList list;
  list.node = anim::find_clips_node(g);
  if (!list.node.is_valid()) return list;
  Result<std::vector<anim::Clip>> clips = anim::clips_of(g, list.node);
  if (!clips) return clips.status();
  list.clips = std::move(*clips);
  list.active = static_cast<int>(value_as<std::int64_t>(g, list.node, anim::clips_attr::kActiveClip));
  return list;
}

// The keys of a time curve that play in one clip: [begin, end), or none (the
// curve then outputs its restValue).
struct KeySpan {
  std::size_t begin = 0, end = 0;
  bool rest = false;
  std::size_t size() const { return end - begin; }
};

// `clip` is the clip being exported (-1: the scene as it is). A curve whose
// `clip` input is fed by the clips node follows it; another keeps its own.
KeySpan keys_playing(Graph& g, NodeId curve, std::size_t key_count, const ClipList& clips, int clip) {
  const AttrIndex offsets_attr = attr_named(g, curve, "clipOffsets");
  const AttrIndex clip_attr = attr_named(g, curve, "clip");
  if (offsets_attr == graph::kNoAttr || clip_attr == graph::kNoAttr) return {0, key_count, false};
  const auto& offsets = value_as<std::vector<std::int64_t>>(g, curve, offsets_attr);
  if (offsets.empty()) return {0, key_count, false};
  std::int64_t c = value_as<std::int64_t>(g, curve, clip_attr);
  if (clip >= 0 && clips.node.is_valid()) {
    const std::optional<Plug> source = g.source(Plug{curve, clip_attr, -1});
    if (source && source->node == clips.node) c = clip;
  }
  if (c < 0 || static_cast<std::size_t>(c) + 1 >= offsets.size()) return {0, 0, true};
  const std::int64_t begin = offsets[static_cast<std::size_t>(c)], end = offsets[static_cast<std::size_t>(c) + 1];
  if (begin < 0 || end <= begin || static_cast<std::size_t>(end) > key_count) return {0, 0, true};
  return {static_cast<std::size_t>(begin), static_cast<std::size_t>(end), false};
}

template <typename T>
std::span<const T> sub(const std::vector<T>& values, const KeySpan& keys) {
  if (values.empty()) return {};
  return std::span<const T>(values).subspan(keys.begin, keys.size());
}

// A scalar animCurve's keys of one clip, read from its (pulled) attributes.
anim::CurveArrays curve_arrays(const Node& n, const KeySpan& keys) {
  namespace a = anim::curve_attr;
  anim::CurveArrays arrays;
  arrays.times = sub(std::get<std::vector<double>>(n.value(a::kKeyTimes)), keys);
  arrays.values = sub(std::get<std::vector<double>>(n.value(a::kKeyValues)), keys);
  arrays.in_types = sub(std::get<std::vector<std::int64_t>>(n.value(a::kInTangentType)), keys);
  arrays.out_types = sub(std::get<std::vector<std::int64_t>>(n.value(a::kOutTangentType)), keys);
  arrays.in_slopes = sub(std::get<std::vector<double>>(n.value(a::kInSlope)), keys);
  arrays.out_slopes = sub(std::get<std::vector<double>>(n.value(a::kOutSlope)), keys);
  arrays.in_weights = sub(std::get<std::vector<double>>(n.value(a::kInWeight)), keys);
  arrays.out_weights = sub(std::get<std::vector<double>>(n.value(a::kOutWeight)), keys);
  arrays.settings.weighted = std::get<bool>(n.value(a::kWeighted));
  arrays.settings.pre_infinity = static_cast<anim::Infinity>(std::get<std::int64_t>(n.value(a::kPreInfinity)));
  arrays.settings.post_infinity = static_cast<anim::Infinity>(std::get<std::int64_t>(n.value(a::kPostInfinity)));
  return arrays;
}

// True when the curve is a straight line between every pair of keys.
bool curve_is_linear(const anim::CurveArrays& arrays) {
  const auto linear = static_cast<std::int64_t>(anim::TangentType::kLinear);
  if (arrays.times.size() < 2) return true;
  if (arrays.in_types.empty() || arrays.out_types.empty()) return false;  // auto by default
  for (std::size_t k = 0; k + 1 < arrays.times.size(); ++k)
    if (arrays.out_types[k] != linear || arrays.in_types[k + 1] != linear) return false;
  return true;
}

// True when the curve holds each key's value until the next key.
bool curve_is_step(const anim::CurveArrays& arrays) {
  const auto step = static_cast<std::int64_t>(anim::TangentType::kStep);
  if (arrays.times.size() < 2) return true;
  if (arrays.out_types.empty()) return false;
  for (std::size_t k = 0; k + 1 < arrays.times.size(); ++k)
    if (arrays.out_types[k] != step) return false;
  return true;
}

// ---- buffers -----------------------------------------------------------------

// Accessors over one buffer, every view 4-byte aligned. Non-finite floats
// are refused: the first one is kept in error() with what was being written.
class BufferBuilder {
 public:
  explicit BufferBuilder(tinygltf::Model& model) : model_(model) {}

  std::vector<unsigned char>& bytes() { return bytes_; }
  const std::string& error() const { return error_; }

  // `values` flattened, `components` per element; bounds: write min/max.
  int floats(std::span<const double> values, int type, int components, int target, bool bounds,
             const std::string& what) {
    std::vector<float> data(values.size());
    for (std::size_t i = 0; i < values.size(); ++i) {
      data[i] = static_cast<float>(values[i]);
      if (!std::isfinite(data[i]) && error_.empty())
        error_ = what + ": value " + number(values[i]) + " is not a finite 32-bit float";
    }
    const std::size_t count = components ? values.size() / static_cast<std::size_t>(components) : 0;
    tinygltf::Accessor accessor;
    accessor.bufferView = view(data.data(), data.size() * sizeof(float), target);
    accessor.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
    accessor.count = count;
    accessor.type = type;
    if (bounds && count > 0) {
      accessor.minValues.assign(static_cast<std::size_t>(components), std::numeric_limits<double>::infinity());
      accessor.maxValues.assign(static_cast<std::size_t>(components), -std::numeric_limits<double>::infinity());
      for (std::size_t i = 0; i < data.size(); ++i) {
        const std::size_t c = i % static_cast<std::size_t>(components);
        accessor.minValues[c] = std::min(accessor.minValues[c], static_cast<double>(data[i]));
        accessor.maxValues[c] = std::max(accessor.maxValues[c], static_cast<double>(data[i]));
      }
    }
    model_.accessors.push_back(std::move(accessor));
    return static_cast<int>(model_.accessors.size()) - 1;
  }

  template <typename T>
  int integers(std::span<const T> values, int component_type, int type, std::size_t count, int target) {
    tinygltf::Accessor accessor;
    accessor.bufferView = view(values.data(), values.size() * sizeof(T), target);
    accessor.componentType = component_type;
    accessor.count = count;
    accessor.type = type;
    model_.accessors.push_back(std::move(accessor));
    return static_cast<int>(model_.accessors.size()) - 1;
  }

  // Float accessors holding the same numbers are written once (baked
  // channels share their times).
  int shared_times(std::span<const double> times, const std::string& what) {
    std::vector<float> key(times.begin(), times.end());
    if (auto it = shared_.find(key); it != shared_.end()) return it->second;
    const int index = floats(times, TINYGLTF_TYPE_SCALAR, 1, 0, true, what);
    shared_.emplace(std::move(key), index);
    return index;
  }

 private:
  int view(const void* data, std::size_t size, int target) {
    while (bytes_.size() % 4 != 0) bytes_.push_back(0);
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = bytes_.size();
    view.byteLength = size;
    view.target = target;
    const auto* begin = static_cast<const unsigned char*>(data);
    bytes_.insert(bytes_.end(), begin, begin + size);
    model_.bufferViews.push_back(std::move(view));
    return static_cast<int>(model_.bufferViews.size()) - 1;
  }

  tinygltf::Model& model_;
  std::vector<unsigned char> bytes_;
  std::string error_;
  std::map<std::vector<float>, int> shared_;
};

std::vector<double> flatten(std::span<const Vec3> points) {
  std::vector<double> out;
  out.reserve(points.size() * 3);
  for (const Vec3& p : points) out.insert(out.end(), {p.x(), p.y(), p.z()});
  return out;
}

// ---- the exporter ------------------------------------------------------------

struct ExportNode {
  NodeId id;
  int parent = -1;        // glTF index of the parent, -1 for a root
  bool detached = false;  // a skinned mesh moved to the root: its transform is its world matrix
  std::vector<int> children;
  std::size_t skeleton = 0;  // index in the compiled Skeleton
  math::Decomposed rest;     // local (world when detached) at the export time
  Mat4 rest_matrix = Mat4::Identity();
  bool has_shear = false;
  bool under_shear = false;  // the parent's glTF frame lost shear (rest_pose): direct keys would not place it
  int mesh = -1;  // index into Exporter::meshes_
  bool animated = false;
  int merged_into = -1;  // a mesh node written as the mesh of this node (index into nodes_), not as a node
  int owned_mesh = -1;   // the mesh written on this node for a merged mesh node (index into meshes_)
};

struct MeshExport {
  std::size_t node = 0;  // index into nodes_
  NodeId cluster;        // skinCluster, or invalid
  NodeId blend;          // blendShape whose targets are exported, or invalid
  std::vector<Vec3> points, normals;
  std::vector<std::int64_t> triangles;
  std::vector<std::vector<Vec3>> targets;  // dense deltas
  std::vector<double> weights;             // default morph weights
  int skin = -1;                           // index into skins_
  std::size_t sets = 0;                    // JOINTS_n / WEIGHTS_n sets
  std::vector<std::uint16_t> joints;       // per vertex, sets * 4
  std::vector<float> joint_weights;        // per vertex, sets * 4
};

struct SkinExport {
  NodeId cluster;
  std::vector<int> joints;  // glTF node indices
  std::vector<Mat4> inverse_bind;
};

struct Channel {
  int node = -1;  // glTF node
  Path path = Path::kTranslation;
  const char* interpolation = "LINEAR";
  std::vector<double> times;
  std::vector<double> values;  // flattened: 3, 4 or target-count numbers per key (x3 for cubic splines)
};

struct AnimationExport {
  std::string name;
  std::vector<Channel> channels;
};

// A transform channel written from a track's own keys.
struct DirectTrack {
  std::size_t node = 0;  // index into nodes_
  Path path = Path::kTranslation;
  NodeId curve;
  Quat pre = Quat::Identity(), post = Quat::Identity();  // rotation = pre * key * post
};

// A mesh's morph weights written from scalar curves.
struct DirectWeights {
  std::size_t mesh = 0;
  std::vector<NodeId> curves;  // per target; invalid: not animated
};

class Exporter {
 public:
  Exporter(scene::Scene& scene, const GltfExportOptions& options, GltfExportReport& report)
      : scene_(scene), g_(scene.graph()), options_(options), report_(report), time_(scene.graph()) {}

  Status run(const fs::path& out, bool binary) {
    g_.evaluate_all();
    Result<ClipList> clips = read_clips(g_);
    if (!clips) return clips.status();
    clips_ = std::move(*clips);
    if (Status s = collect_nodes(); !s) return s;
    if (Status s = collect_meshes(); !s) return s;
    merge_mesh_nodes();
    if (Status s = rest_pose(); !s) return s;
    analyse_animation();
    apply_rest_values();
    const bool bake = options_.frames || options_.bake || !bake_reason_.empty();
    if (bake) {
      report_.baked = true;
      report_.bake_reason = options_.frames ? "requested (frames " + number(options_.frames->first) + ":" +
                                                  number(options_.frames->second) + ")"
                            : options_.bake ? "requested"
                                            : bake_reason_;
      if (Status s = bake_all(); !s) return s;
    } else if (Status s = direct_all(); !s) {
      return s;
    }
    return write(out, binary);
  }

 private:
  // ---- nodes ----

  Status collect_nodes() {
    Result<scene::Skeleton> skeleton = scene::Skeleton::compile(scene_);
    if (!skeleton) return skeleton.status();
    skeleton_ = std::move(*skeleton);
    std::unordered_map<std::uint32_t, std::size_t> in_skeleton;
    for (std::size_t i = 0; i < skeleton_.size(); ++i) in_skeleton[skeleton_.nodes()[i].index] = i;
    for (NodeId id : scene_.hierarchy()) {
      ExportNode n;
      n.id = id;
      n.skeleton = in_skeleton.at(id.index);
      index_[id.index] = static_cast<int>(nodes_.size());
      nodes_.push_back(std::move(n));
    }
    return Status::ok();
  }

  int gltf_index(NodeId id) const {
    auto it = index_.find(id.index);
    return it == index_.end() ? -1 : it->second;
  }
  const std::string& name(NodeId id) const { return g_.node(id)->name(); }

  // Parents and children once skinned meshes are known to be detached, and
  // every node's transform at the export time.
  Status rest_pose() {
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
      ExportNode& n = nodes_[i];
      const NodeId parent = g_.parent(n.id);
      if (parent.is_valid() && !n.detached) {
        n.parent = gltf_index(parent);
        nodes_[static_cast<std::size_t>(n.parent)].children.push_back(static_cast<int>(i));
      }
    }
    std::vector<Mat4> local(skeleton_.size()), world(skeleton_.size());
    if (Status s = skeleton_.evaluate(scene_, local, world); !s) return s;
    Placement placement(nodes_.size());
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
      ExportNode& n = nodes_[i];
      n.rest = place(i, local, world, placement);
      n.under_shear = n.parent >= 0 && placement.displaced[static_cast<std::size_t>(n.parent)];
      n.rest_matrix = math::trs_matrix(n.rest.translate, n.rest.rotation, n.rest.scale);
      // A rotated matrix decomposes to scales a rounding away from 1: write
      // those as 1 (and leave them out of the file).
      for (int k = 0; k < 3; ++k)
        if (std::abs(n.rest.scale[k] - 1.0) <= kUnitScaleTolerance) n.rest.scale[k] = 1.0;
      n.rest.rotation.normalize();
      if (n.rest.rotation.w() < 0) n.rest.rotation.coeffs() *= -1.0;
      n.has_shear = n.rest.shear.cwiseAbs().maxCoeff() > kShearTolerance;
      if (n.rest.shear.cwiseAbs().maxCoeff() > kVisibleShear)
        report_.notes.push_back(name(n.id) + ": its shear (up to " + number(n.rest.shear.cwiseAbs().maxCoeff()) +
                                ") is left out, since glTF nodes hold translation, rotation and scale only; "
                                "nodes keep their positions, and mesh points and skinned vertices their place");
    }
    compensate_shear(world, placement);
    return check_skinned_placement(world);
  }

  // glTF nodes hold translation, rotation and scale only (the validator
  // refuses a `matrix` that is not TRS), so shear cannot be written. Each
  // node's glTF transform is the TRS part of what puts it at its world
  // matrix under its parent's glTF world matrix: every node keeps its world
  // position, and a frame loses the shear it has or inherits. `written`
  // holds the glTF world matrix of the nodes whose frame differs from their
  // world matrix (`displaced`).
  struct Placement {
    explicit Placement(std::size_t n) : written(n, Mat4::Identity()), displaced(n, 0) {}
    std::vector<Mat4> written;
    std::vector<char> displaced;
  };

  // Node i's glTF transform (nodes in parent-first order).
  math::Decomposed place(std::size_t i, std::span<const Mat4> local, std::span<const Mat4> world, Placement& p) const {
    const ExportNode& n = nodes_[i];
    const bool under_displaced = n.parent >= 0 && p.displaced[static_cast<std::size_t>(n.parent)];
    const Mat4 wanted = under_displaced ? Mat4(p.written[static_cast<std::size_t>(n.parent)].inverse() * world[n.skeleton])
                        : n.detached    ? world[n.skeleton]
                                        : local[n.skeleton];
    const math::Decomposed d = math::decompose(wanted);
    p.displaced[i] = d.shear.cwiseAbs().maxCoeff() > kShearTolerance;
    if (p.displaced[i]) {
      const Mat4 parent = n.parent >= 0 && !n.detached
                              ? (under_displaced ? p.written[static_cast<std::size_t>(n.parent)] : world[nodes_[static_cast<std::size_t>(n.parent)].skeleton])
                              : Mat4(Mat4::Identity());
      p.written[i] = parent * math::trs_matrix(d.translate, d.rotation, d.scale);
    }
    return d;
  }

  // What shear dropped at the export time moves back into the data: a
  // displaced mesh's points (and normals, morph deltas) get the difference
  // between its world matrix and its glTF one; a displaced joint's inverse
  // bind matrices the same, so skinned vertices land where rigel puts them.
  void compensate_shear(std::span<const Mat4> world, const Placement& p) {
    for (MeshExport& m : meshes_) {
      if (m.cluster.is_valid() || !p.displaced[m.node]) continue;
      const Mat4 c = p.written[m.node].inverse() * world[nodes_[m.node].skeleton];
      const Eigen::Matrix3d linear = c.topLeftCorner<3, 3>();
      const Eigen::Matrix3d normal = linear.inverse().transpose();
      for (Vec3& v : m.points) v = linear * v + c.topRightCorner<3, 1>();
      for (Vec3& v : m.normals) v = (normal * v).normalized();
      for (auto& target : m.targets)
        for (Vec3& v : target) v = linear * v;
    }
    for (SkinExport& s : skins_) {
      for (std::size_t k = 0; k < s.joints.size(); ++k) {
        const auto j = static_cast<std::size_t>(s.joints[k]);
        if (p.displaced[j]) s.inverse_bind[k] = p.written[j].inverse() * world[nodes_[j].skeleton] * s.inverse_bind[k];
      }
    }
  }

  // glTF draws a skinned mesh in world space; rigel's skinCluster writes
  // inverse(geomMatrix) * skinned points, drawn at the mesh's world matrix.
  Status check_skinned_placement(std::span<const Mat4> world) {
    for (const MeshExport& m : meshes_) {
      if (!m.cluster.is_valid()) continue;
      const ExportNode& n = nodes_[m.node];
      const Mat4& geom = value_as<Mat4>(g_, m.cluster, ops::skin_cluster_attr::kGeomMatrix);
      if (!near_matrix(world[n.skeleton], geom, kGeomTolerance)) {
        std::string when = report_.baked ? " at time " + number(g_.time()) + " s" : "";
        return error(ErrorCode::kInvalidArgument,
                     name(n.id) + ": the world matrix of this skinned mesh differs from " + name(m.cluster) +
                         ".geomMatrix" + when +
                         "; glTF draws skinned meshes in world space, so export needs them equal (set " +
                         name(m.cluster) + ".geomMatrix to the mesh's world matrix, or move the mesh)");
      }
    }
    return Status::ok();
  }

  // ---- meshes ----

  // The node feeding `plug` when it is `attr` of a node of `type`.
  NodeId fed_by(const Plug& plug, const char* type, AttrIndex attr) const {
    const std::optional<Plug> source = g_.source(plug);
    if (!source || source->attr != attr || source->element >= 0 || type_of(g_, source->node) != type) return NodeId{};
    return source->node;
  }

  Status collect_meshes() {
    namespace ma = scene::mesh_attr;
    namespace sa = ops::skin_cluster_attr;
    namespace ba = ops::blend_shape_attr;
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
      const NodeId id = nodes_[i].id;
      if (type_of(g_, id) != scene::kMeshType) continue;
      MeshExport m;
      m.node = i;
      m.cluster = fed_by(Plug{id, ma::kPoints, -1}, ops::kSkinClusterType, sa::kOutPoints);
      std::vector<Vec3> points;
      if (m.cluster.is_valid()) {
        m.blend = fed_by(Plug{m.cluster, sa::kBindPoints, -1}, ops::kBlendShapeType, ba::kOutPoints);
        points = value_as<std::vector<Vec3>>(g_, m.cluster, sa::kBindPoints);
        m.normals = value_as<std::vector<Vec3>>(g_, m.cluster, sa::kBindNormals);
      } else {
        m.blend = fed_by(Plug{id, ma::kPoints, -1}, ops::kBlendShapeType, ba::kOutPoints);
        points = value_as<std::vector<Vec3>>(g_, id, ma::kPoints);
        m.normals = value_as<std::vector<Vec3>>(g_, id, ma::kNormals);
      }
      m.points = m.blend.is_valid() ? value_as<std::vector<Vec3>>(g_, m.blend, ba::kBasePoints) : std::move(points);
      m.triangles = value_as<std::vector<std::int64_t>>(g_, id, ma::kTriangles);
      if (m.points.empty() || m.triangles.empty()) {
        report_.notes.push_back(name(id) + ": a mesh without " + (m.points.empty() ? "points" : "triangles") +
                                " is written as a plain node");
        continue;
      }
      if (m.normals.size() != m.points.size()) {
        if (!m.normals.empty())
          report_.notes.push_back(name(id) + ": " + std::to_string(m.normals.size()) + " normals for " +
                                  std::to_string(m.points.size()) + " points are left out");
        m.normals.clear();
      }
      if (Status s = check_triangles(id, m); !s) return s;
      if (m.blend.is_valid()) {
        if (Status s = collect_targets(m); !s) return s;
      }
      if (m.cluster.is_valid()) {
        nodes_[i].detached = true;
        if (Status s = collect_skin(m); !s) return s;
      }
      nodes_[i].mesh = static_cast<int>(meshes_.size());
      meshes_.push_back(std::move(m));
    }
    return Status::ok();
  }

  // A mesh node the glTF importer made (tag gltf.node: the name of the node
  // its glTF mesh hung on) goes back onto that node as its mesh, so import
  // -> export keeps the node tree and names: when the node exists and has
  // no mesh of its own or merged already, the mesh node has no children, is
  // no skin's joint, and either is skinned (glTF ignores a skinned node's
  // transform) or sits right under that node with an identity transform
  // that nothing animates.
  void merge_mesh_nodes() {
    for (std::size_t k = 0; k < meshes_.size(); ++k) {
      const MeshExport& m = meshes_[k];
      const NodeId id = nodes_[m.node].id;
      const std::string* tag = g_.node(id)->tag_find(kTagGltfNode);
      if (!tag) continue;
      const NodeId owner = g_.find(*tag);
      const int o = owner.is_valid() ? gltf_index(owner) : -1;
      if (o < 0 || owner == id) continue;
      ExportNode& target = nodes_[static_cast<std::size_t>(o)];
      if (target.mesh >= 0 || target.owned_mesh >= 0 || target.merged_into >= 0) continue;
      if (!g_.children(id).empty() || is_skin_joint(id)) continue;
      if (!m.cluster.is_valid()) {
        if (g_.parent(id) != owner || !static_identity(*g_.node(id))) continue;
      }
      nodes_[m.node].merged_into = o;
      target.owned_mesh = static_cast<int>(k);
    }
  }

  bool is_skin_joint(NodeId id) const {
    for (const SkinExport& s : skins_)
      for (int j : s.joints)
        if (nodes_[static_cast<std::size_t>(j)].id == id) return true;
    return false;
  }

  // An identity local transform that no connection drives.
  bool static_identity(const Node& n) const {
    for (const graph::Connection& c : n.inputs())
      if (shapes_matrix(n, c.dst.attr)) return false;
    return std::get<Mat4>(g_.evaluate(n.id(), xf::kMatrix)) == Mat4::Identity() &&
           std::get<Mat4>(n.value(xf::kOffsetParentMatrix)) == Mat4::Identity();
  }

  Status check_triangles(NodeId id, const MeshExport& m) const {
    const std::string where = name(id) + ".triangles";
    if (m.triangles.size() % 3 != 0)
      return error(ErrorCode::kInvalidArgument,
                   where + ": " + std::to_string(m.triangles.size()) + " indices is not a whole number of triangles");
    if (m.points.size() >= std::numeric_limits<std::uint32_t>::max())
      return error(ErrorCode::kInvalidArgument, name(id) + ".points: too many points for glTF's 32-bit indices");
    for (std::size_t k = 0; k < m.triangles.size(); ++k) {
      if (m.triangles[k] < 0 || static_cast<std::uint64_t>(m.triangles[k]) >= m.points.size())
        return error(ErrorCode::kInvalidArgument, where + "[" + std::to_string(k) + "]: index " +
                                                      std::to_string(m.triangles[k]) + " is not one of the " +
                                                      std::to_string(m.points.size()) + " points");
    }
    return Status::ok();
  }

  // The blendShape's targets as dense deltas over the base points.
  Status collect_targets(MeshExport& m) {
    namespace ba = ops::blend_shape_attr;
    const std::string& b = name(m.blend);
    const auto& deltas = value_as<std::vector<Vec3>>(g_, m.blend, ba::kTargetDeltas);
    const auto& offsets = value_as<std::vector<std::int64_t>>(g_, m.blend, ba::kTargetOffsets);
    const auto& indices = value_as<std::vector<std::int64_t>>(g_, m.blend, ba::kTargetIndices);
    const auto& weights = value_as<std::vector<double>>(g_, m.blend, ba::kWeights);
    if (offsets.empty()) return Status::ok();
    if (offsets.front() != 0 || static_cast<std::uint64_t>(offsets.back()) != deltas.size() ||
        !std::is_sorted(offsets.begin(), offsets.end()))
      return error(ErrorCode::kInvalidArgument, b + ".targetOffsets: must rise from 0 to the " +
                                                    std::to_string(deltas.size()) + " targetDeltas");
    if (!indices.empty() && indices.size() != deltas.size())
      return error(ErrorCode::kInvalidArgument, b + ".targetIndices: " + std::to_string(indices.size()) +
                                                    " indices for " + std::to_string(deltas.size()) + " deltas");
    const std::size_t count = offsets.size() - 1;
    for (std::size_t t = 0; t < count; ++t) {
      const auto begin = static_cast<std::size_t>(offsets[t]), end = static_cast<std::size_t>(offsets[t + 1]);
      std::vector<Vec3> dense(m.points.size(), Vec3::Zero());
      if (indices.empty() && end - begin != m.points.size())
        return error(ErrorCode::kInvalidArgument, b + ".targetDeltas: dense target " + std::to_string(t) + " has " +
                                                      std::to_string(end - begin) + " deltas for " +
                                                      std::to_string(m.points.size()) + " points");
      for (std::size_t k = begin; k < end; ++k) {
        const std::int64_t v = indices.empty() ? static_cast<std::int64_t>(k - begin) : indices[k];
        if (v < 0 || static_cast<std::uint64_t>(v) >= m.points.size())
          return error(ErrorCode::kInvalidArgument, b + ".targetIndices[" + std::to_string(k) + "]: vertex " +
                                                        std::to_string(v) + " is not one of the " +
                                                        std::to_string(m.points.size()) + " points");
        dense[static_cast<std::size_t>(v)] += deltas[k];
      }
      m.targets.push_back(std::move(dense));
    }
    m.weights.assign(count, 0.0);
    std::copy_n(weights.begin(), std::min(count, weights.size()), m.weights.begin());
    return Status::ok();
  }

  Status collect_skin(MeshExport& m) {
    namespace sa = ops::skin_cluster_attr;
    const std::string& c = name(m.cluster);
    // A skinCluster shared by several meshes is one glTF skin.
    for (std::size_t s = 0; s < skins_.size(); ++s)
      if (skins_[s].cluster == m.cluster) m.skin = static_cast<int>(s);
    const auto& joint_matrices = value_as<std::vector<Mat4>>(g_, m.cluster, sa::kJointMatrices);
    if (m.skin < 0) {
      SkinExport skin;
      skin.cluster = m.cluster;
      std::size_t count = joint_matrices.size();
      std::map<std::int32_t, NodeId> sources;
      for (const graph::Connection& conn : g_.node(m.cluster)->inputs()) {
        if (conn.dst.attr != sa::kJointMatrices) continue;
        if (conn.dst.element < 0)
          return error(ErrorCode::kInvalidArgument,
                       c + ".jointMatrices: fed as a whole by " + describe(g_, conn.src) +
                           "; export needs each element fed by a joint's worldMatrix");
        if (conn.src.attr != xf::kWorldMatrix || conn.src.element >= 0 || !scene_.is_transform(conn.src.node))
          return error(ErrorCode::kInvalidArgument, c + ".jointMatrices[" + std::to_string(conn.dst.element) +
                                                        "]: fed by " + describe(g_, conn.src) +
                                                        ", not by a transform's worldMatrix");
        sources[conn.dst.element] = conn.src.node;
        count = std::max(count, static_cast<std::size_t>(conn.dst.element) + 1);
      }
      std::map<int, std::size_t> seen;
      for (std::size_t j = 0; j < count; ++j) {
        auto it = sources.find(static_cast<std::int32_t>(j));
        if (it == sources.end())
          return error(ErrorCode::kInvalidArgument, c + ".jointMatrices[" + std::to_string(j) +
                                                        "]: not fed by a joint's worldMatrix (glTF skins name "
                                                        "their joints)");
        const int joint = gltf_index(it->second);
        if (auto [at, fresh] = seen.emplace(joint, j); !fresh)
          return error(ErrorCode::kInvalidArgument,
                       c + ".jointMatrices[" + std::to_string(j) + "]: " + name(it->second) +
                           " also feeds jointMatrices[" + std::to_string(at->second) + "]; glTF joints are unique");
        skin.joints.push_back(joint);
      }
      const auto& bind_pre = value_as<std::vector<Mat4>>(g_, m.cluster, sa::kBindPreMatrices);
      for (std::size_t j = 0; j < count; ++j)
        skin.inverse_bind.push_back(j < bind_pre.size() ? bind_pre[j] : Mat4(Mat4::Identity()));
      if (std::int64_t method = value_as<std::int64_t>(g_, m.cluster, sa::kMethod); method != 0)
        report_.notes.push_back(c + ": dual quaternion skinning is written as glTF's linear blend skinning");
      m.skin = static_cast<int>(skins_.size());
      skins_.push_back(std::move(skin));
    }

    const std::size_t joint_count = skins_[static_cast<std::size_t>(m.skin)].joints.size();
    if (joint_count > ops::kMaxSkinJoints)
      return error(ErrorCode::kInvalidArgument, c + ".jointMatrices: " + std::to_string(joint_count) +
                                                    " joints; glTF's JOINTS_n hold at most 65536");
    const ops::SkinInfluenceView view{value_as<std::vector<std::int64_t>>(g_, m.cluster, sa::kInfluenceOffsets),
                                      value_as<std::vector<std::int64_t>>(g_, m.cluster, sa::kInfluenceJoints),
                                      value_as<std::vector<double>>(g_, m.cluster, sa::kInfluenceWeights)};
    ops::SkinBuildOptions options;
    options.joint_count = joint_count;
    options.normalize = true;  // glTF's weights sum to 1
    options.fixed_layout = false;
    ops::SkinBuildReport build_report;
    Result<ops::Skin> skin = ops::build_skin(view, options, &build_report);
    if (!skin) return skin.status().with_context(c + ".influenceWeights");
    if (skin->vertex_count() != m.points.size())
      return error(ErrorCode::kInvalidArgument, c + ".influenceOffsets: weights for " +
                                                    std::to_string(skin->vertex_count()) + " vertices, but " +
                                                    std::to_string(m.points.size()) + " bindPoints");
    if (!value_as<bool>(g_, m.cluster, sa::kNormalizeWeights) && !build_report.renormalized.empty())
      report_.notes.push_back(c + ": " + std::to_string(build_report.renormalized.size()) +
                              " vertices' weights do not sum to 1 and normalizeWeights is off; glTF normalises them");

    m.sets = std::max<std::size_t>(1, (skin->max_influences() + 3) / 4);
    const std::size_t stride = m.sets * 4;
    m.joints.assign(m.points.size() * stride, 0);
    m.joint_weights.assign(m.points.size() * stride, 0.0f);
    std::vector<std::pair<float, std::uint16_t>> influences;
    for (std::size_t v = 0; v < m.points.size(); ++v) {
      influences.clear();
      for (std::uint32_t k = skin->offsets()[v]; k < skin->offsets()[v + 1]; ++k)
        influences.emplace_back(skin->weights()[k], skin->joints()[k]);
      // Largest first; equal weights by joint, so the file is deterministic.
      std::sort(influences.begin(), influences.end(),
                [](const auto& a, const auto& b) { return a.first != b.first ? a.first > b.first : a.second < b.second; });
      for (std::size_t k = 0; k < influences.size(); ++k) {
        m.joints[v * stride + k] = influences[k].second;
        m.joint_weights[v * stride + k] = influences[k].first;
      }
    }
    return Status::ok();
  }

  // ---- animation: what can be written directly ----

  void bake_because(std::string reason) {
    if (bake_reason_.empty()) bake_reason_ = std::move(reason);
  }

  // Whether an attribute of a transform takes part in its local matrix.
  static bool shapes_matrix(const Node& n, AttrIndex attr) {
    if (attr < xf::kCount) return attr != xf::kParentMatrix && attr != xf::kVisibility && n.type().is_input(attr);
    return n.type().name() == scene::kJointType && attr == scene::joint_attr::kJointOrient;
  }

  // True when the node's local matrix is translate * rotation * scale of its
  // channels: no shear, pivots or offset parent matrix.
  static bool is_plain(const Node& n) {
    const Vec3 zero = Vec3::Zero();
    return std::get<Vec3>(n.value(xf::kShear)) == zero && std::get<Vec3>(n.value(xf::kRotatePivot)) == zero &&
           std::get<Vec3>(n.value(xf::kRotatePivotTranslate)) == zero &&
           std::get<Vec3>(n.value(xf::kScalePivot)) == zero &&
           std::get<Vec3>(n.value(xf::kScalePivotTranslate)) == zero &&
           std::get<Mat4>(n.value(xf::kOffsetParentMatrix)) == Mat4::Identity();
  }

  // The node's rotation is pre * rotateQuaternion * post (math::compose:
  // jointOrient * rotation * rotateAxis).
  static std::pair<Quat, Quat> rotation_frame(const Node& n) {
    const Quat post =
        math::euler_to_quat(math::to_radians(std::get<Vec3>(n.value(xf::kRotateAxis))), math::RotateOrder::kXYZ);
    Quat pre = Quat::Identity();
    if (n.type().name() == scene::kJointType)
      pre = math::euler_to_quat(math::to_radians(std::get<Vec3>(n.value(scene::joint_attr::kJointOrient))),
                                math::RotateOrder::kXYZ);
    return {pre, post};
  }

  // The track that feeds a translate, scale or rotateQuaternion channel of
  // `n` as a whole, with the channel's glTF path; invalid when none does.
  std::pair<NodeId, Path> track_feeding(const Node& n, const graph::Connection& c) const {
    const bool whole = c.dst.element < 0 && c.dst.component < 0 && c.src.element < 0 && c.src.component < 0;
    if (!whole || c.src.attr != anim::track_attr::kOutput) return {NodeId{}, Path::kTranslation};
    const bool quaternion_mode = xf::is_quaternion_mode(n);
    const std::string& type = type_of(g_, c.src.node);
    if (type == anim::kAnimCurveVec3Type && c.dst.attr == xf::kTranslate) return {c.src.node, Path::kTranslation};
    if (type == anim::kAnimCurveVec3Type && c.dst.attr == xf::kScale) return {c.src.node, Path::kScale};
    if (type == anim::kAnimCurveQuatType && c.dst.attr == xf::kRotateQuaternion && quaternion_mode)
      return {c.src.node, Path::kRotation};
    return {NodeId{}, Path::kTranslation};
  }

  // A channel fed by a clip curve rests at the curve's restValue when no
  // clip plays it: what the glTF importer keeps of a node's own TRS. That,
  // not the pose at the export time, is the node's transform in the file.
  void apply_rest_values() {
    for (ExportNode& en : nodes_) {
      const Node& n = *g_.node(en.id);
      if (en.detached || !is_plain(n)) continue;
      bool changed = false;
      for (const graph::Connection& c : n.inputs()) {
        const auto [curve_id, path] = track_feeding(n, c);
        if (!curve_id.is_valid()) continue;
        const Node& curve = *g_.node(curve_id);
        const AttrIndex rest = curve.type().attr_find("restValue");
        const AttrIndex offsets = curve.type().attr_find("clipOffsets");
        if (rest == graph::kNoAttr || offsets == graph::kNoAttr ||
            std::get<std::vector<std::int64_t>>(curve.value(offsets)).empty())
          continue;
        changed = true;
        if (path == Path::kTranslation) en.rest.translate = std::get<Vec3>(curve.value(rest));
        if (path == Path::kScale) en.rest.scale = std::get<Vec3>(curve.value(rest));
        if (path == Path::kRotation) {
          const auto [pre, post] = rotation_frame(n);
          const Quat q = std::get<Quat>(curve.value(rest));
          en.rest.rotation = (q.norm() > 1e-6 ? Quat(pre * q.normalized() * post) : Quat(pre * post)).normalized();
          if (en.rest.rotation.w() < 0) en.rest.rotation.coeffs() *= -1.0;
        }
      }
      if (changed) en.rest_matrix = math::trs_matrix(en.rest.translate, en.rest.rotation, en.rest.scale);
    }
  }

  // Empty when the curve's keys can be written as they are; else why not.
  std::string curve_problem(NodeId curve, bool scalar) {
    const Node& n = *g_.node(curve);
    const AttrIndex error_attr = scalar ? AttrIndex{anim::curve_attr::kError} : AttrIndex{anim::track_attr::kError};
    const auto& message = value_as<std::string>(g_, curve, error_attr);
    if (!message.empty()) return n.name() + " has keys it cannot use (" + message + ")";
    const AttrIndex clip_attr = n.type().attr_find("clip");
    for (const graph::Connection& c : n.inputs())
      if (c.dst.attr != clip_attr) return g_.plug_name(c.dst) + " is driven by " + describe(g_, c.src);
    const AttrIndex times_attr = scalar ? AttrIndex{anim::curve_attr::kKeyTimes} : AttrIndex{anim::track_attr::kKeyTimes};
    const auto& times = std::get<std::vector<double>>(n.value(times_attr));
    for (std::size_t k = 0; k < times.size(); ++k) {
      if (times[k] < 0.0) return n.name() + ".keyTimes[" + std::to_string(k) + "] is negative (glTF times are not)";
      if (k > 0 && times[k] > times[k - 1] && static_cast<float>(times[k]) <= static_cast<float>(times[k - 1]))
        return n.name() + ".keyTimes[" + std::to_string(k) + "] is too close to the key before for 32-bit times";
    }
    if (scalar) {
      const auto pre = std::get<std::int64_t>(n.value(anim::curve_attr::kPreInfinity));
      const auto post = std::get<std::int64_t>(n.value(anim::curve_attr::kPostInfinity));
      if (pre != 0 || post != 0) return n.name() + " repeats or extends beyond its keys (pre/post infinity)";
    }
    return {};
  }

  void analyse_animation() {
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
      const ExportNode& en = nodes_[i];
      const Node& n = *g_.node(en.id);
      const bool quaternion_mode = xf::is_quaternion_mode(n);
      bool animated = false;
      for (const graph::Connection& c : n.inputs()) {
        const AttrIndex attr = c.dst.attr;
        if (!shapes_matrix(n, attr) || !time_.of(c.src.node)) continue;
        if ((attr == xf::kRotate && quaternion_mode) || (attr == xf::kRotateQuaternion && !quaternion_mode)) continue;
        animated = true;
        const auto [curve_id, path] = track_feeding(n, c);
        if (!curve_id.is_valid()) {
          if (attr == xf::kRotate && type_of(g_, c.src.node) == anim::kAnimCurveVec3Type)
            bake_because(g_.plug_name(c.dst) + " is animated with Euler angles by " + describe(g_, c.src));
          else
            bake_because(g_.plug_name(c.dst) + " is driven by " + describe(g_, c.src));
          continue;
        }
        if (std::string why = curve_problem(curve_id, false); !why.empty()) {
          bake_because(why);
          continue;
        }
        if (en.under_shear) {
          bake_because(n.name() + " is animated below a sheared node, whose shear glTF cannot carry");
          continue;
        }
        DirectTrack t;
        t.node = i;
        t.path = path;
        t.curve = curve_id;
        if (path == Path::kRotation) std::tie(t.pre, t.post) = rotation_frame(n);
        direct_tracks_.push_back(t);
      }
      if (animated && !is_plain(n))
        bake_because(n.name() + " is animated and has shear, pivots or an offsetParentMatrix, which glTF's "
                                "translation/rotation/scale channels cannot carry");
      const NodeId parent = g_.parent(en.id);
      if (en.detached && parent.is_valid() && (animated || time_.of(parent)))
        bake_because(n.name() + " is a skinned mesh that moves with its parent " + name(parent) +
                     " (a glTF skinned mesh node is a root)");
    }

    namespace ba = ops::blend_shape_attr;
    for (std::size_t m = 0; m < meshes_.size(); ++m) {
      const MeshExport& mesh = meshes_[m];
      if (!mesh.blend.is_valid() || mesh.targets.empty()) continue;
      DirectWeights w;
      w.mesh = m;
      w.curves.assign(mesh.targets.size(), NodeId{});
      bool animated = false;
      for (const graph::Connection& c : g_.node(mesh.blend)->inputs()) {
        if (!time_.of(c.src.node)) continue;
        if (c.dst.attr != ba::kWeights) {
          report_.notes.push_back(g_.plug_name(c.dst) + " changes over time; the targets are written as they are at "
                                                        "the export time");
          continue;
        }
        if (c.dst.element < 0 || static_cast<std::size_t>(c.dst.element) >= w.curves.size()) {
          if (c.dst.element < 0) bake_because(g_.plug_name(c.dst) + " is driven as a whole by " + describe(g_, c.src));
          continue;
        }
        animated = true;
        if (type_of(g_, c.src.node) != anim::kAnimCurveType || c.src.attr != anim::curve_attr::kOutput ||
            c.src.component >= 0) {
          bake_because(g_.plug_name(c.dst) + " is driven by " + describe(g_, c.src));
          continue;
        }
        if (std::string why = curve_problem(c.src.node, true); !why.empty()) {
          bake_because(why);
          continue;
        }
        w.curves[static_cast<std::size_t>(c.dst.element)] = c.src.node;
      }
      if (animated) direct_weights_.push_back(std::move(w));
    }
  }

  // ---- animation: direct ----

  // The clips to export: every clip of the clips node, or the scene as it is.
  std::vector<int> clip_indices() const {
    std::vector<int> result;
    for (std::size_t c = 0; c < clips_.clips.size(); ++c) result.push_back(static_cast<int>(c));
    if (result.empty()) result.push_back(-1);
    return result;
  }
  std::string animation_name(int clip) const {
    return clip >= 0 ? clips_.clips[static_cast<std::size_t>(clip)].name : "animation";
  }

  Status direct_all() {
    if (direct_tracks_.empty() && direct_weights_.empty()) return Status::ok();
    for (int clip : clip_indices()) {
      AnimationExport a;
      a.name = animation_name(clip);
      for (const DirectTrack& t : direct_tracks_) direct_track(t, clip, a);
      for (const DirectWeights& w : direct_weights_) direct_weights(w, clip, a);
      if (!a.channels.empty()) animations_.push_back(std::move(a));
    }
    return Status::ok();
  }

  Vec3 rest_vec(const ExportNode& n, Path path) const { return path == Path::kScale ? n.rest.scale : n.rest.translate; }

  void direct_track(const DirectTrack& t, int clip, AnimationExport& a) {
    namespace ta = anim::track_attr;
    const ExportNode& en = nodes_[t.node];
    const Node& curve = *g_.node(t.curve);
    const auto& times = std::get<std::vector<double>>(curve.value(ta::kKeyTimes));
    const KeySpan keys = keys_playing(g_, t.curve, times.size(), clips_, clip);
    Channel ch;
    ch.node = static_cast<int>(t.node);
    ch.path = t.path;
    const auto interpolation = static_cast<anim::Interpolation>(std::get<std::int64_t>(curve.value(ta::kInterpolation)));
    ch.interpolation = interpolation == anim::Interpolation::kStep          ? "STEP"
                       : interpolation == anim::Interpolation::kCubicSpline ? "CUBICSPLINE"
                                                                             : "LINEAR";
    const bool cubic = interpolation == anim::Interpolation::kCubicSpline;
    const double start = clip >= 0 ? clips_.clips[static_cast<std::size_t>(clip)].start : 0.0;

    if (t.path == Path::kRotation) {
      auto convert = [&](const Quat& q, bool normalize) {
        const Quat r(t.pre * (normalize ? q.normalized() : q) * t.post);
        ch.values.insert(ch.values.end(), {r.x(), r.y(), r.z(), r.w()});
      };
      if (keys.size() == 0) {
        // No keys play: the curve's constant value (restValue, or the identity).
        const AttrIndex rest_attr = curve.type().attr_find("restValue");
        const Quat q = keys.rest && rest_attr != graph::kNoAttr ? std::get<Quat>(curve.value(rest_attr)) : Quat::Identity();
        if (near_quat(Quat(t.pre * q.normalized() * t.post), en.rest.rotation, kConstantTolerance)) return;
        ch.interpolation = "LINEAR";
        ch.times = {start};
        convert(q, true);
      } else {
        const auto values = sub(std::get<std::vector<Quat>>(curve.value(ta::kKeyValues)), keys);
        const auto in = sub(std::get<std::vector<Quat>>(curve.value(ta::kInTangents)), keys);
        const auto out = sub(std::get<std::vector<Quat>>(curve.value(ta::kOutTangents)), keys);
        ch.times.assign(times.begin() + static_cast<std::ptrdiff_t>(keys.begin),
                        times.begin() + static_cast<std::ptrdiff_t>(keys.end));
        for (std::size_t k = 0; k < values.size(); ++k) {
          if (cubic) convert(in[k], false);
          convert(values[k], true);
          if (cubic) convert(out[k], false);
        }
      }
    } else {
      auto convert = [&](const Vec3& v) { ch.values.insert(ch.values.end(), {v.x(), v.y(), v.z()}); };
      if (keys.size() == 0) {
        const AttrIndex rest_attr = curve.type().attr_find("restValue");
        const Vec3 v = keys.rest && rest_attr != graph::kNoAttr ? std::get<Vec3>(curve.value(rest_attr)) : Vec3::Zero();
        if (near_vec(v, rest_vec(en, t.path), kConstantTolerance)) return;
        ch.interpolation = "LINEAR";
        ch.times = {start};
        convert(v);
      } else {
        const auto values = sub(std::get<std::vector<Vec3>>(curve.value(ta::kKeyValues)), keys);
        const auto in = sub(std::get<std::vector<Vec3>>(curve.value(ta::kInTangents)), keys);
        const auto out = sub(std::get<std::vector<Vec3>>(curve.value(ta::kOutTangents)), keys);
        ch.times.assign(times.begin() + static_cast<std::ptrdiff_t>(keys.begin),
                        times.begin() + static_cast<std::ptrdiff_t>(keys.end));
        for (std::size_t k = 0; k < values.size(); ++k) {
          if (cubic) convert(in[k]);
          convert(values[k]);
          if (cubic) convert(out[k]);
        }
      }
    }
    a.channels.push_back(std::move(ch));
  }

  void direct_weights(const DirectWeights& w, int clip, AnimationExport& a) {
    const MeshExport& mesh = meshes_[w.mesh];
    const std::size_t targets = mesh.targets.size();
    const double fps = g_.fps();
    // Per target: the keys that play, or a constant.
    std::vector<anim::CurveArrays> arrays(targets);
    std::vector<std::optional<double>> constant(targets);
    std::set<double> times;
    bool linear = true, step = true;
    for (std::size_t t = 0; t < targets; ++t) {
      if (!w.curves[t].is_valid()) {
        constant[t] = mesh.weights[t];
        continue;
      }
      const Node& curve = *g_.node(w.curves[t]);
      const auto& key_times = std::get<std::vector<double>>(curve.value(anim::curve_attr::kKeyTimes));
      const KeySpan keys = keys_playing(g_, w.curves[t], key_times.size(), clips_, clip);
      if (keys.size() == 0) {
        const AttrIndex rest_attr = curve.type().attr_find("restValue");
        constant[t] = keys.rest && rest_attr != graph::kNoAttr ? std::get<double>(curve.value(rest_attr)) : 0.0;
        continue;
      }
      arrays[t] = curve_arrays(curve, keys);
      times.insert(arrays[t].times.begin(), arrays[t].times.end());
      linear = linear && curve_is_linear(arrays[t]);
      step = step && curve_is_step(arrays[t]);
    }
    if (times.empty()) {
      // Nothing plays: one key when the constants differ from the defaults.
      bool same = true;
      for (std::size_t t = 0; t < targets; ++t) same = same && std::abs(*constant[t] - mesh.weights[t]) <= kConstantTolerance;
      if (same) return;
      times.insert(clip >= 0 ? clips_.clips[static_cast<std::size_t>(clip)].start : 0.0);
    }
    step = step && !linear;  // keyless or single-key curves are both; LINEAR says it plainly
    if (!linear && !step) {
      // Maya tangents are curved between keys: add every frame between them.
      const double first = *times.begin(), last = *times.rbegin();
      for (double f = std::ceil(first * fps); f / fps < last; f += 1.0) times.insert(f / fps);
    }
    Channel ch;
    ch.node = static_cast<int>(mesh.node);
    ch.path = Path::kWeights;
    ch.interpolation = step ? "STEP" : "LINEAR";
    ch.times.assign(times.begin(), times.end());
    // Frames added next to keys can be too close to them for 32-bit times.
    ch.times.erase(std::unique(ch.times.begin(), ch.times.end(),
                               [](double x, double y) { return static_cast<float>(x) == static_cast<float>(y); }),
                   ch.times.end());
    for (double t : ch.times)
      for (std::size_t k = 0; k < targets; ++k)
        ch.values.push_back(constant[k] ? *constant[k] : anim::evaluate_arrays(arrays[k], t));
    a.channels.push_back(std::move(ch));
  }

  // ---- animation: baked ----

  // Frames [first, last] as times in seconds: every whole step from first,
  // and last itself.
  Result<std::vector<double>> frame_times(double first, double last) const {
    if ((last - first) > kMaxFrames)
      return error(ErrorCode::kInvalidArgument, "frames " + number(first) + ":" + number(last) + ": more than " +
                                                    number(kMaxFrames) + " frames to bake");
    std::vector<double> times;
    const double fps = g_.fps();
    for (double f = first; f <= last + 1e-9; f += 1.0) times.push_back(f / fps);
    if (times.empty() || times.back() < last / fps - 1e-9 / fps) times.push_back(last / fps);
    // glTF times are 32-bit floats and must increase: a last frame a
    // fraction past a whole one replaces it when the two round together.
    for (std::size_t k = times.size() - 1; k > 0; --k)
      if (static_cast<float>(times[k]) <= static_cast<float>(times[k - 1])) times.erase(times.begin() + static_cast<std::ptrdiff_t>(k) - 1);
    return times;
  }

  // The default range without clips: the time curves' keys, out to whole frames.
  std::pair<double, double> key_range() {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (NodeId id : g_.nodes()) {
      const std::string& type = type_of(g_, id);
      if (type != anim::kAnimCurveType && type != anim::kAnimCurveVec3Type && type != anim::kAnimCurveQuatType) continue;
      const auto& times = std::get<std::vector<double>>(g_.node(id)->value(0));  // keyTimes, first in both layouts
      for (double t : times) {
        if (!std::isfinite(t)) continue;
        lo = std::min(lo, t);
        hi = std::max(hi, t);
      }
    }
    if (lo > hi) return {0.0, 0.0};
    const double fps = g_.fps();
    const double first = std::max(0.0, std::floor(lo * fps + 1e-9));
    return {first, std::max(first, std::ceil(hi * fps - 1e-9))};
  }

  // Every key time of the scene's time curves, sorted, once each.
  std::vector<double> key_times() const {
    std::vector<double> keys;
    for (NodeId id : g_.nodes()) {
      const std::string& type = type_of(g_, id);
      if (type != anim::kAnimCurveType && type != anim::kAnimCurveVec3Type && type != anim::kAnimCurveQuatType) continue;
      const auto& times = std::get<std::vector<double>>(g_.node(id)->value(0));  // keyTimes, first in both layouts
      for (double t : times)
        if (std::isfinite(t)) keys.push_back(t);
    }
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    return keys;
  }

  // A bake samples the frames asked for and every key time between the
  // first and the last of them: a key between two frames (a glTF clip's
  // times are seconds) keeps its value. Times that 32-bit floats cannot tell
  // apart are written once (the earlier).
  static void add_key_times(std::vector<double>& times, const std::vector<double>& keys) {
    if (times.empty()) return;
    const double first = times.front(), last = times.back();
    const auto begin = std::lower_bound(keys.begin(), keys.end(), first);
    const auto end = std::upper_bound(keys.begin(), keys.end(), last);
    if (begin == end) return;
    std::vector<double> merged;
    merged.reserve(times.size() + static_cast<std::size_t>(end - begin));
    std::merge(times.begin(), times.end(), begin, end, std::back_inserter(merged));
    merged.erase(std::unique(merged.begin(), merged.end(),
                             [](double x, double y) { return static_cast<float>(x) == static_cast<float>(y); }),
                 merged.end());
    times = std::move(merged);
  }

  struct BakeJob {
    std::string name;
    int clip = -1;  // make this clip active first; -1: leave it
    std::vector<double> times;
  };

  Status bake_all() {
    std::vector<BakeJob> jobs;
    const double fps = g_.fps();
    if (options_.frames) {
      Result<std::vector<double>> times = frame_times(options_.frames->first, options_.frames->second);
      if (!times) return times.status();
      const int active = clips_.clips.empty() ? -1 : clips_.active;
      jobs.push_back({animation_name(active), -1, std::move(*times)});
      report_.first_frame = options_.frames->first;
      report_.last_frame = options_.frames->second;
    } else if (!clips_.clips.empty()) {
      for (std::size_t c = 0; c < clips_.clips.size(); ++c) {
        Result<std::vector<double>> times = frame_times(clips_.clips[c].start * fps, clips_.clips[c].end * fps);
        if (!times) return times.status();
        jobs.push_back({clips_.clips[c].name, static_cast<int>(c), std::move(*times)});
      }
      report_.first_frame = clips_.clips.front().start * fps;
      report_.last_frame = clips_.clips.front().end * fps;
    } else {
      const auto [first, last] = key_range();
      Result<std::vector<double>> times = frame_times(first, last);
      if (!times) return times.status();
      jobs.push_back({"animation", -1, std::move(*times)});
      report_.first_frame = first;
      report_.last_frame = last;
    }
    const std::vector<double> keys = key_times();
    for (BakeJob& job : jobs) add_key_times(job.times, keys);
    std::size_t total = 0, done = 0;
    for (const BakeJob& job : jobs) total += job.times.size();

    // Baking moves time and switches clips; both are put back afterwards
    // (the clip switch is rolled back, so it leaves no undo step).
    const double saved_time = g_.time();
    graph::Transaction transaction(g_, "export glTF (bake)");
    Status status;
    for (const BakeJob& job : jobs) {
      if (job.clip >= 0) {
        status = g_.set_value(Plug{clips_.node, anim::clips_attr::kActive, -1}, std::int64_t{job.clip});
        if (!status) break;
      }
      status = bake(job, done, total);
      if (!status) break;
    }
    transaction.rollback();
    g_.set_time(saved_time);
    g_.evaluate_all();
    return status;
  }

  Status bake(const BakeJob& job, std::size_t& done, std::size_t total) {
    const std::size_t frames = job.times.size();
    const std::size_t count = nodes_.size();
    std::vector<Vec3> translate(frames * count), scale(frames * count);
    std::vector<Quat> rotate(frames * count);
    std::vector<bool> sheared(count, false);
    std::vector<std::vector<double>> weights(meshes_.size());
    std::vector<Mat4> local(skeleton_.size()), world(skeleton_.size());
    Placement placement(count);
    for (std::size_t f = 0; f < frames; ++f) {
      g_.set_time(job.times[f]);
      g_.evaluate_all();
      if (Status s = skeleton_.evaluate(scene_, local, world); !s) return s;
      if (Status s = check_skinned_placement(world); !s) return s;
      for (std::size_t i = 0; i < count; ++i) {
        const ExportNode& n = nodes_[i];
        math::Decomposed d = place(i, local, world, placement);
        if (d.shear.cwiseAbs().maxCoeff() > kShearTolerance) sheared[i] = true;
        Quat q = d.rotation.normalized();
        const Quat& previous = f > 0 ? rotate[(f - 1) * count + i] : n.rest.rotation;
        if (previous.dot(q) < 0.0) q.coeffs() *= -1.0;  // keep the sign continuous
        translate[f * count + i] = d.translate;
        rotate[f * count + i] = q;
        scale[f * count + i] = d.scale;
      }
      for (std::size_t m = 0; m < meshes_.size(); ++m) {
        const MeshExport& mesh = meshes_[m];
        if (mesh.targets.empty()) continue;
        const auto& w = value_as<std::vector<double>>(g_, mesh.blend, ops::blend_shape_attr::kWeights);
        for (std::size_t t = 0; t < mesh.targets.size(); ++t) weights[m].push_back(t < w.size() ? w[t] : 0.0);
      }
      ++done;
      if (options_.progress) options_.progress(static_cast<double>(done) / static_cast<double>(total));
    }

    AnimationExport a;
    a.name = job.name;
    auto channel = [&](std::size_t node, Path path) {
      Channel ch;
      ch.node = static_cast<int>(node);
      ch.path = path;
      ch.times = job.times;
      return ch;
    };
    for (std::size_t i = 0; i < count; ++i) {
      const ExportNode& n = nodes_[i];
      bool moved_t = false, moved_r = false, moved_s = false;
      for (std::size_t f = 0; f < frames; ++f) {
        moved_t = moved_t || !near_vec(translate[f * count + i], n.rest.translate, kConstantTolerance);
        moved_r = moved_r || !near_quat(rotate[f * count + i], n.rest.rotation, kConstantTolerance);
        moved_s = moved_s || !near_vec(scale[f * count + i], n.rest.scale, kConstantTolerance);
      }
      if (moved_t) {
        Channel ch = channel(i, Path::kTranslation);
        for (std::size_t f = 0; f < frames; ++f) {
          const Vec3& v = translate[f * count + i];
          ch.values.insert(ch.values.end(), {v.x(), v.y(), v.z()});
        }
        a.channels.push_back(std::move(ch));
      }
      if (moved_r) {
        Channel ch = channel(i, Path::kRotation);
        for (std::size_t f = 0; f < frames; ++f) {
          const Quat& q = rotate[f * count + i];
          ch.values.insert(ch.values.end(), {q.x(), q.y(), q.z(), q.w()});
        }
        a.channels.push_back(std::move(ch));
      }
      if (moved_s) {
        Channel ch = channel(i, Path::kScale);
        for (std::size_t f = 0; f < frames; ++f) {
          const Vec3& v = scale[f * count + i];
          ch.values.insert(ch.values.end(), {v.x(), v.y(), v.z()});
        }
        a.channels.push_back(std::move(ch));
      }
      if (sheared[i] && (moved_t || moved_r || moved_s))
        report_.notes.push_back(name(n.id) + ": shear is left out of its baked animation (glTF animates "
                                             "translation, rotation and scale only)");
    }
    for (std::size_t m = 0; m < meshes_.size(); ++m) {
      const MeshExport& mesh = meshes_[m];
      if (mesh.targets.empty()) continue;
      bool moved = false;
      for (std::size_t k = 0; k < weights[m].size(); ++k)
        moved = moved || std::abs(weights[m][k] - mesh.weights[k % mesh.targets.size()]) > kConstantTolerance;
      if (!moved) continue;
      Channel ch = channel(mesh.node, Path::kWeights);
      ch.values = std::move(weights[m]);
      a.channels.push_back(std::move(ch));
    }
    if (!a.channels.empty()) animations_.push_back(std::move(a));
    return Status::ok();
  }

  // ---- the file ----

  Status write(const fs::path& out, bool binary) {
    tinygltf::Model model;
    model.asset.version = "2.0";
    model.asset.generator = "rigel";
    BufferBuilder buffer(model);

    // Merged mesh nodes (merge_mesh_nodes) are no glTF node: every index
    // into nodes_ goes through `out` (a merged one: its owner's).
    std::vector<int> index_out(nodes_.size(), -1);
    int written = 0;
    for (std::size_t i = 0; i < nodes_.size(); ++i)
      if (nodes_[i].merged_into < 0) index_out[i] = written++;
    for (std::size_t i = 0; i < nodes_.size(); ++i)
      if (nodes_[i].merged_into >= 0) index_out[i] = index_out[static_cast<std::size_t>(nodes_[i].merged_into)];
    for (AnimationExport& a : animations_) {
      // A merged mesh node's own transform channels have no node to go to
      // (its transform is identity, or ignored when skinned); its morph
      // weights go to its owner, which holds the mesh.
      std::erase_if(a.channels, [&](const Channel& ch) {
        return nodes_[static_cast<std::size_t>(ch.node)].merged_into >= 0 && ch.path != Path::kWeights;
      });
      for (Channel& ch : a.channels) nodes_[static_cast<std::size_t>(ch.node)].animated = true;
    }
    animations_.erase(std::remove_if(animations_.begin(), animations_.end(),
                                     [](const AnimationExport& a) { return a.channels.empty(); }),
                      animations_.end());

    for (const ExportNode& n : nodes_) {
      if (n.merged_into >= 0) continue;
      tinygltf::Node node;
      node.name = name(n.id);
      // The node's rigel uuid, so a client (the web app) maps glTF nodes back
      // to scene nodes whatever their names become.
      node.extras = tinygltf::Value(tinygltf::Value::Object{{"uuid", tinygltf::Value(g_.node(n.id)->uuid().str())}});
      for (int c : n.children)
        if (nodes_[static_cast<std::size_t>(c)].merged_into < 0) node.children.push_back(index_out[static_cast<std::size_t>(c)]);
      {  // TRS, never `matrix`: shear was dropped (rest_pose)
        if (n.rest.translate != Vec3::Zero()) node.translation = {n.rest.translate.x(), n.rest.translate.y(), n.rest.translate.z()};
        const Quat& q = n.rest.rotation;
        if (q.coeffs() != Quat::Identity().coeffs()) node.rotation = {q.x(), q.y(), q.z(), q.w()};
        if (n.rest.scale != Vec3::Ones()) node.scale = {n.rest.scale.x(), n.rest.scale.y(), n.rest.scale.z()};
      }
      if (const int mesh = n.mesh >= 0 ? n.mesh : n.owned_mesh; mesh >= 0) {
        const MeshExport& m = meshes_[static_cast<std::size_t>(mesh)];
        node.mesh = static_cast<int>(model.meshes.size());
        node.skin = m.skin;
        model.meshes.push_back(write_mesh(m, buffer));
      }
      model.nodes.push_back(std::move(node));
    }

    // glTF wants a skin's joints under one common root; rigel lets them sit
    // in separate trees. Such trees go under one added identity node.
    const std::vector<int> grouped = roots_to_group();
    if (!grouped.empty()) {
      tinygltf::Node group;
      group.name = unused_name("skeleton_root");
      for (int r : grouped) group.children.push_back(index_out[static_cast<std::size_t>(r)]);
      model.nodes.push_back(std::move(group));
      report_.notes.push_back("the joints of a skin sit in " + std::to_string(grouped.size()) +
                              " separate trees; glTF asks for one common root, so '" + model.nodes.back().name +
                              "' (identity) holds them");
    }

    for (const SkinExport& s : skins_) {
      tinygltf::Skin skin;
      skin.name = name(s.cluster);
      for (int j : s.joints) skin.joints.push_back(index_out[static_cast<std::size_t>(j)]);
      std::vector<double> matrices;
      for (const Mat4& m : s.inverse_bind) matrices.insert(matrices.end(), m.data(), m.data() + 16);
      skin.inverseBindMatrices =
          buffer.floats(matrices, TINYGLTF_TYPE_MAT4, 16, 0, false, name(s.cluster) + ".bindPreMatrices");
      model.skins.push_back(std::move(skin));
    }

    for (const AnimationExport& a : animations_) {
      tinygltf::Animation animation;
      animation.name = a.name;
      for (const Channel& ch : a.channels) {
        const std::string what = "animation '" + a.name + "', " + name(nodes_[static_cast<std::size_t>(ch.node)].id) +
                                 " " + path_name(ch.path);
        tinygltf::AnimationSampler sampler;
        sampler.interpolation = ch.interpolation;
        sampler.input = buffer.shared_times(ch.times, what + " times");
        if (ch.path == Path::kWeights)
          sampler.output = buffer.floats(ch.values, TINYGLTF_TYPE_SCALAR, 1, 0, false, what);
        else if (ch.path == Path::kRotation)
          sampler.output = buffer.floats(ch.values, TINYGLTF_TYPE_VEC4, 4, 0, false, what);
        else
          sampler.output = buffer.floats(ch.values, TINYGLTF_TYPE_VEC3, 3, 0, false, what);
        tinygltf::AnimationChannel channel;
        channel.sampler = static_cast<int>(animation.samplers.size());
        channel.target_node = index_out[static_cast<std::size_t>(ch.node)];
        channel.target_path = path_name(ch.path);
        animation.samplers.push_back(std::move(sampler));
        animation.channels.push_back(std::move(channel));
        ++report_.channel_count;
      }
      model.animations.push_back(std::move(animation));
    }

    // Materials, textures, uv sets and colours of the meshes (gltf_materials.h).
    gltf_look::LookWriter looks(g_, model, buffer.bytes(), report_.notes);
    for (std::size_t k = 0; k < written_meshes_.size() && k < model.meshes.size(); ++k) {
      if (Status s = looks.write(written_meshes_[k], static_cast<int>(k)); !s) return s;
    }

    if (!buffer.error().empty()) return error(ErrorCode::kInvalidArgument, buffer.error());
    if (binary && buffer.bytes().size() > std::numeric_limits<std::uint32_t>::max() - 4096u)
      return error(ErrorCode::kInvalidArgument, out.string() + ": more than 4 GiB of data, beyond what .glb holds");
    if (!buffer.bytes().empty()) {
      tinygltf::Buffer data;
      data.data = std::move(buffer.bytes());
      model.buffers.push_back(std::move(data));
    }
    if (!nodes_.empty()) {
      tinygltf::Scene gltf_scene;
      for (std::size_t i = 0; i < nodes_.size(); ++i) {
        const bool in_group = std::find(grouped.begin(), grouped.end(), static_cast<int>(i)) != grouped.end();
        if (nodes_[i].parent < 0 && !in_group && nodes_[i].merged_into < 0) gltf_scene.nodes.push_back(index_out[i]);
      }
      if (!grouped.empty()) gltf_scene.nodes.push_back(written);
      model.scenes.push_back(std::move(gltf_scene));
      model.defaultScene = 0;
    }

    // tinygltf writes to a stream (buffers embedded for .gltf, the BIN chunk
    // for .glb); the bytes then go through the atomic writer, which checks
    // every write (tinygltf's own file writer does not) and renames.
    std::ostringstream stream(std::ios::binary);
    tinygltf::TinyGLTF gltf;
    if (!gltf.WriteGltfSceneToStream(&model, stream, !binary, binary) || !stream)
      return error(ErrorCode::kIoError, out.string() + ": tinygltf could not serialise the model");
    if (Status s = write_file_atomic(out, stream.str()); !s) return s;

    report_.node_count = model.nodes.size();
    report_.mesh_count = model.meshes.size();
    report_.skin_count = model.skins.size();
    report_.animation_count = model.animations.size();
    return Status::ok();
  }

  // The roots of the trees holding some skin's joints, when one skin's
  // joints are in more than one tree (all such roots, in node order).
  std::vector<int> roots_to_group() const {
    std::set<int> group;
    for (const SkinExport& s : skins_) {
      std::set<int> tops;
      for (int j : s.joints) {
        while (nodes_[static_cast<std::size_t>(j)].parent >= 0) j = nodes_[static_cast<std::size_t>(j)].parent;
        tops.insert(j);
      }
      if (tops.size() > 1) group.insert(tops.begin(), tops.end());
    }
    return std::vector<int>(group.begin(), group.end());
  }

  // `wanted`, or wanted1, wanted2, ...: a name no scene node has.
  std::string unused_name(const std::string& wanted) const {
    std::string candidate = wanted;
    for (int k = 1; g_.find(candidate).is_valid(); ++k) candidate = wanted + std::to_string(k);
    return candidate;
  }

  tinygltf::Mesh write_mesh(const MeshExport& m, BufferBuilder& buffer) {
    const std::string& mesh_name = name(nodes_[m.node].id);
    written_meshes_.push_back(nodes_[m.node].id);  // the caller pushes this mesh onto model.meshes next
    tinygltf::Mesh mesh;
    mesh.name = mesh_name;
    tinygltf::Primitive primitive;
    primitive.mode = TINYGLTF_MODE_TRIANGLES;
    primitive.attributes["POSITION"] = buffer.floats(flatten(m.points), TINYGLTF_TYPE_VEC3, 3,
                                                     TINYGLTF_TARGET_ARRAY_BUFFER, true, mesh_name + " points");
    if (!m.normals.empty())
      primitive.attributes["NORMAL"] = buffer.floats(flatten(m.normals), TINYGLTF_TYPE_VEC3, 3,
                                                     TINYGLTF_TARGET_ARRAY_BUFFER, false, mesh_name + " normals");
    // 65535 is the primitive-restart value, which glTF indices must not hold.
    if (m.points.size() <= 65535) {
      std::vector<std::uint16_t> indices(m.triangles.begin(), m.triangles.end());
      primitive.indices = buffer.integers(std::span<const std::uint16_t>(indices), TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                                          TINYGLTF_TYPE_SCALAR, indices.size(), TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    } else {
      std::vector<std::uint32_t> indices(m.triangles.begin(), m.triangles.end());
      primitive.indices = buffer.integers(std::span<const std::uint32_t>(indices), TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT,
                                          TINYGLTF_TYPE_SCALAR, indices.size(), TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    }
    if (m.skin >= 0) {
      const std::size_t joint_count = skins_[static_cast<std::size_t>(m.skin)].joints.size();
      const std::size_t stride = m.sets * 4;
      for (std::size_t set = 0; set < m.sets; ++set) {
        std::vector<double> weights;
        std::vector<std::uint16_t> joints16;
        std::vector<std::uint8_t> joints8;
        for (std::size_t v = 0; v < m.points.size(); ++v) {
          for (std::size_t k = 0; k < 4; ++k) {
            const std::size_t at = v * stride + set * 4 + k;
            weights.push_back(m.joint_weights[at]);
            joints16.push_back(m.joints[at]);
            joints8.push_back(static_cast<std::uint8_t>(m.joints[at]));
          }
        }
        const std::string suffix = "_" + std::to_string(set);
        primitive.attributes["JOINTS" + suffix] =
            joint_count <= 256
                ? buffer.integers(std::span<const std::uint8_t>(joints8), TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                                  TINYGLTF_TYPE_VEC4, m.points.size(), TINYGLTF_TARGET_ARRAY_BUFFER)
                : buffer.integers(std::span<const std::uint16_t>(joints16), TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                                  TINYGLTF_TYPE_VEC4, m.points.size(), TINYGLTF_TARGET_ARRAY_BUFFER);
        primitive.attributes["WEIGHTS" + suffix] = buffer.floats(weights, TINYGLTF_TYPE_VEC4, 4, TINYGLTF_TARGET_ARRAY_BUFFER,
                                                                 false, mesh_name + " weights");
      }
    }
    for (std::size_t t = 0; t < m.targets.size(); ++t) {
      std::map<std::string, int> target;
      target["POSITION"] = buffer.floats(flatten(m.targets[t]), TINYGLTF_TYPE_VEC3, 3, TINYGLTF_TARGET_ARRAY_BUFFER,
                                         true, mesh_name + " morph target " + std::to_string(t));
      primitive.targets.push_back(std::move(target));
    }
    mesh.weights = m.weights;
    mesh.primitives.push_back(std::move(primitive));
    return mesh;
  }

  scene::Scene& scene_;
  Graph& g_;
  const GltfExportOptions& options_;
  GltfExportReport& report_;
  TimeDependence time_;
  ClipList clips_;
  scene::Skeleton skeleton_;
  std::vector<ExportNode> nodes_;
  std::unordered_map<std::uint32_t, int> index_;  // NodeId::index -> glTF node
  std::vector<MeshExport> meshes_;
  std::vector<SkinExport> skins_;
  std::vector<DirectTrack> direct_tracks_;
  std::vector<DirectWeights> direct_weights_;
  std::string bake_reason_;
  std::vector<AnimationExport> animations_;
  std::vector<NodeId> written_meshes_;  // the mesh node of each glTF mesh, in model.meshes order
};

}  // namespace

Status export_gltf(scene::Scene& scene, const std::filesystem::path& out, const GltfExportOptions& options,
                   GltfExportReport* report) {
  const std::string ext = lower(out.extension().string());
  if (ext != ".glb" && ext != ".gltf")
    return error(ErrorCode::kInvalidArgument,
                 out.string() + ": unsupported file type '" + ext + "' (glTF export writes .glb or .gltf)");
  if (options.frames) {
    const auto [first, last] = *options.frames;
    if (!std::isfinite(first) || !std::isfinite(last))
      return error(ErrorCode::kInvalidArgument, "frames: must be finite numbers");
    if (first > last)
      return error(ErrorCode::kInvalidArgument,
                   "frames " + number(first) + ":" + number(last) + ": the first frame is after the last");
    if (first < 0.0)
      return error(ErrorCode::kInvalidArgument,
                   "frames: " + number(first) + " is before frame 0 (glTF animation times are not negative)");
  }
  GltfExportReport local;
  GltfExportReport& r = report ? *report : local;
  r = GltfExportReport{};
  Exporter exporter(scene, options, r);
  return exporter.run(out, ext == ".glb");
}

}  // namespace rigel::io
