// Private to rigel_io: the glTF exporter, turning a scene into a tinygltf
// model and then a .gltf or .glb (io/gltf_export.h documents the mapping).
// It collects the nodes to export (gltf_export_nodes.cc) and their meshes
// and skins (gltf_export_meshes.cc), decides whether animation can be
// written from the curves' own keys (gltf_export_animation.cc) or must be
// sampled frame by frame (gltf_export_bake.cc), and writes the model
// (gltf_export_write.cc).
#pragma once

#include <tiny_gltf.h>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <variant>
#include <vector>

#include "rigel/graph/graph.h"
#include "rigel/io/gltf_export.h"
#include "rigel/math/transform.h"
#include "rigel/ops/anim/clips.h"
#include "rigel/scene/scene.h"
#include "rigel/scene/skeleton.h"
#include "rigel/scene/transform_types.h"

#include "gltf_accessors.h"
#include "gltf_messages.h"

namespace rigel::io::gltf_exporter {

namespace fs = std::filesystem;
namespace xf = scene::xform;
namespace anim = ops::anim;
using gltf::BufferWriter;
using gltf::Path;
using gltf::path_name;
using graph::AttrIndex;
using graph::Graph;
using graph::Node;
using graph::NodeId;
using graph::Plug;
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

// A number as people write it: "12", "0.5", "1e-07".
inline std::string number(double value) { return gltf::number(value, 10); }

// Equal within `tolerance`, relative to the larger entry (at least 1).
bool near_matrix(const Mat4& a, const Mat4& b, double tolerance);
bool near_vec(const Vec3& a, const Vec3& b, double tolerance);
// q and -q are the same rotation.
bool near_quat(const Quat& a, const Quat& b, double tolerance);

std::string type_of(const Graph& g, NodeId id);

// "hips_rotate.output (animCurveVec3)"
std::string describe(const Graph& g, const Plug& plug);

template <typename T>
const T& value_as(Graph& g, NodeId node, AttrIndex attr) {
  return std::get<T>(g.evaluate(node, attr));
}

// Whether a node's outputs change with the graph's time: its type is
// time-dependent, or something upstream is. Memoised; iterative, so deep
// chains do not overflow the stack.
class TimeDependence {
 public:
  explicit TimeDependence(const Graph& graph) : graph_(graph) {}

  bool of(NodeId start);

 private:
  enum : std::uint8_t { kVisiting = 1, kNo = 2, kYes = 3 };
  const Graph& graph_;
  std::unordered_map<std::uint32_t, std::uint8_t> state_;
};

struct ClipList {
  NodeId node;  // the animClips node; invalid when the scene has none
  std::vector<anim::Clip> clips;
  int active = 0;
};

// The scene's clips, read from its animClips node (none without one).
Result<ClipList> read_clips(Graph& g);

struct ExportNode {
  NodeId id;
  int parent = -1;        // glTF index of the parent, -1 for a root
  bool detached = false;  // a skinned mesh moved to the root: its transform is its world matrix
  bool reparented = false;  // its scene parent is not exported: placed by world matrices under the nearest exported ancestor
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
  std::vector<std::string> target_names;   // the blendShape's targetNames (written as extras.targetNames)
  int skin = -1;                           // index into skins_
  std::size_t sets = 0;                    // JOINTS_n / WEIGHTS_n sets
  std::vector<std::uint16_t> joints;       // per vertex, sets * 4
  std::vector<float> joint_weights;        // per vertex, sets * 4
};

struct SkinExport {
  NodeId cluster;  // invalid for the skeleton skin (GltfExportOptions::skeleton_skin)
  std::vector<int> joints;  // glTF node indices
  std::vector<Mat4> inverse_bind;
  std::string name;  // the glTF skin's name: the cluster's, or "skeleton"
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

  Status run(const fs::path& out, bool binary);

 private:
  // ---- nodes ----

  Status collect_nodes();

  int gltf_index(NodeId id) const;
  // The "skeleton" skin of GltfExportOptions::skeleton_skin (after collect_meshes).
  void collect_skeleton_skin();
  const std::string& name(NodeId id) const { return g_.node(id)->name(); }

  // Parents and children once skinned meshes are known to be detached, and
  // every node's transform at the export time.
  Status rest_pose();

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
  math::Decomposed place(std::size_t i, std::span<const Mat4> local, std::span<const Mat4> world, Placement& p) const;

  // What shear dropped at the export time moves back into the data: a
  // displaced mesh's points (and normals, morph deltas) get the difference
  // between its world matrix and its glTF one; a displaced joint's inverse
  // bind matrices the same, so skinned vertices land where rigel puts them.
  void compensate_shear(std::span<const Mat4> world, const Placement& p);

  // glTF draws a skinned mesh in world space; rigel's skinCluster writes
  // inverse(geomMatrix) * skinned points, drawn at the mesh's world matrix.
  Status check_skinned_placement(std::span<const Mat4> world);

  // ---- meshes ----

  // The node feeding `plug` when it is `attr` of a node of `type`.
  NodeId fed_by(const Plug& plug, const char* type, AttrIndex attr) const;

  Status collect_meshes();

  // A mesh node the glTF importer made (tag gltf.node: the name of the node
  // its glTF mesh hung on) goes back onto that node as its mesh, so import
  // -> export keeps the node tree and names: when the node exists and has
  // no mesh of its own or merged already, the mesh node has no children, is
  // no skin's joint, and either is skinned (glTF ignores a skinned node's
  // transform) or sits right under that node with an identity transform
  // that nothing animates.
  void merge_mesh_nodes();

  bool is_skin_joint(NodeId id) const;

  // An identity local transform that no connection drives.
  bool static_identity(const Node& n) const;

  Status check_triangles(NodeId id, const MeshExport& m) const;

  // The blendShape's targets as dense deltas over the base points.
  Status collect_targets(MeshExport& m);

  Status collect_skin(MeshExport& m);

  // ---- animation: what can be written directly ----

  void bake_because(std::string reason);

  // Whether an attribute of a transform takes part in its local matrix.
  static bool shapes_matrix(const Node& n, AttrIndex attr);

  // True when the node's local matrix is translate * rotation * scale of its
  // channels: no shear, pivots or offset parent matrix.
  static bool is_plain(const Node& n);

  // The node's rotation is pre * rotateQuaternion * post (math::compose:
  // jointOrient * rotation * rotateAxis).
  static std::pair<Quat, Quat> rotation_frame(const Node& n);

  // The track that feeds a translate, scale or rotateQuaternion channel of
  // `n` as a whole, with the channel's glTF path; invalid when none does.
  std::pair<NodeId, Path> track_feeding(const Node& n, const graph::Connection& c) const;

  // A channel fed by a clip curve rests at the curve's restValue when no
  // clip plays it: what the glTF importer keeps of a node's own TRS. That,
  // not the pose at the export time, is the node's transform in the file.
  void apply_rest_values();

  // Empty when the curve's keys can be written as they are; else why not.
  std::string curve_problem(NodeId curve, bool scalar);

  void analyse_animation();

  // ---- animation: direct ----

  // The clips to export: every clip of the clips node, or the scene as it is.
  std::vector<int> clip_indices() const;
  std::string animation_name(int clip) const;

  Status direct_all();

  Vec3 rest_vec(const ExportNode& n, Path path) const { return path == Path::kScale ? n.rest.scale : n.rest.translate; }

  void direct_track(const DirectTrack& t, int clip, AnimationExport& a);

  void direct_weights(const DirectWeights& w, int clip, AnimationExport& a);

  // ---- animation: baked ----

  // Frames [first, last] as times in seconds: every whole step from first,
  // and last itself.
  Result<std::vector<double>> frame_times(double first, double last) const;

  // The default range without clips: the time curves' keys, out to whole frames.
  std::pair<double, double> key_range();

  // Every key time of the scene's time curves, sorted, once each.
  std::vector<double> key_times() const;

  // A bake samples the frames asked for and every key time between the
  // first and the last of them: a key between two frames (a glTF clip's
  // times are seconds) keeps its value. Times that 32-bit floats cannot tell
  // apart are written once (the earlier).
  static void add_key_times(std::vector<double>& times, const std::vector<double>& keys);

  struct BakeJob {
    std::string name;
    int clip = -1;  // make this clip active first; -1: leave it
    std::vector<double> times;
  };

  Status bake_all();

  Status bake(const BakeJob& job, std::size_t& done, std::size_t total);

  // ---- the file ----

  Status write(const fs::path& out, bool binary);

  // The skins and the animations, their nodes numbered by `index_out` (the
  // glTF node of each entry of nodes_).
  void write_skins(tinygltf::Model& model, BufferWriter& buffer, std::span<const int> index_out);
  void write_animations(tinygltf::Model& model, BufferWriter& buffer, std::span<const int> index_out);

  // The roots of the trees holding some skin's joints, when one skin's
  // joints are in more than one tree (all such roots, in node order).
  std::vector<int> roots_to_group() const;

  // `wanted`, or wanted1, wanted2, ...: a name no scene node has.
  std::string unused_name(const std::string& wanted) const;

  tinygltf::Mesh write_mesh(const MeshExport& m, BufferWriter& buffer);

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

}  // namespace rigel::io::gltf_exporter
