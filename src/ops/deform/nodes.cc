#include "rigel/ops/deform/nodes.h"

#include <algorithm>
#include <array>
#include <optional>
#include <vector>

#include "rigel/graph/graph.h"
#include "rigel/math/transform.h"
#include "rigel/ops/deform/blend_shape.h"
#include "rigel/ops/deform/skinning.h"

namespace rigel::ops {
namespace {

using graph::AttrSpec;
using graph::AttrType;
using graph::ComputeContext;
using graph::Value;
using graph::ValueType;
using math::Mat4;
using math::Vec3;

// From this many vertices a node splits its mesh into tasks of
// kParallelGrain vertices (oneTBB): a mesh is usually skinned after its
// whole rig, alone, so the other cores are idle then. Below it one task is
// cheaper than waking others (a task costs about a microsecond; 2,048
// vertices with normals, about five).
constexpr std::size_t kParallelVertices = 4096;
constexpr std::size_t kParallelGrain = 2048;

AttrSpec input(std::string name, AttrType type, Value value, std::uint32_t extra = 0) {
  return graph::input_attr(std::move(name), type, std::move(value), {}, extra);
}

AttrSpec output(std::string name, AttrType type) { return graph::output_attr(std::move(name), type); }

constexpr AttrType kPoints{ValueType::kDouble3, true};
constexpr AttrType kMatrices{ValueType::kMatrix, true};
constexpr AttrType kInts{ValueType::kInt, true};
constexpr AttrType kDoubles{ValueType::kDouble, true};

// ---- skinCluster -------------------------------------------------------------

void pass_through_skin(ComputeContext& c) {
  namespace a = skin_cluster_attr;
  c.output(a::kOutPoints) = c.get<std::vector<Vec3>>(a::kBindPoints);
  c.output(a::kOutNormals) = c.get<std::vector<Vec3>>(a::kBindNormals);
}

// What a skinCluster keeps between evaluations: the compiled skin (float
// weights, fixed or CSR layout) and the bind points and normals in float,
// each rebuilt only when an input it was made from was written since. A
// pose change (new joint matrices) then costs the skinning matrices and the
// kernel, not a rebuild of 10,000 vertices' influences.
struct SkinClusterCache final : graph::NodeCache {
  // Versions of offsets, joints, weights, normalizeWeights and the joint
  // count the skin was built from; `built` false: nothing built yet.
  bool built = false;
  std::array<std::uint64_t, 4> skin_versions{};
  std::size_t joint_count = 0;
  std::optional<Skin> skin;  // empty: the influences are invalid
  bool points_built = false;
  std::uint64_t points_version = 0, normals_version = 0;
  std::vector<Vec3f> in_points, in_normals, out_points, out_normals;
  std::vector<Mat4> inverse_bind;
  std::vector<SkinMatrix> linear;
  std::vector<DualQuatSkinMatrix> dual_quat;
};

// The cache's skin, rebuilt when the influences or the joint count changed.
const Skin* cached_skin(ComputeContext& c, SkinClusterCache& cache, std::size_t joint_count) {
  namespace a = skin_cluster_attr;
  const std::array<std::uint64_t, 4> versions = {c.version(a::kInfluenceOffsets), c.version(a::kInfluenceJoints),
                                                 c.version(a::kInfluenceWeights), c.version(a::kNormalizeWeights)};
  if (!cache.built || versions != cache.skin_versions || joint_count != cache.joint_count) {
    SkinBuildOptions options;
    options.joint_count = joint_count;
    options.normalize = c.get<bool>(a::kNormalizeWeights);
    options.fixed_layout = true;
    const SkinInfluenceView view{c.get<std::vector<std::int64_t>>(a::kInfluenceOffsets),
                                 c.get<std::vector<std::int64_t>>(a::kInfluenceJoints),
                                 c.get<std::vector<double>>(a::kInfluenceWeights)};
    Result<Skin> skin = build_skin(view, options);
    cache.skin.reset();
    if (skin) cache.skin.emplace(std::move(*skin));
    cache.built = true;
    cache.skin_versions = versions;
    cache.joint_count = joint_count;
  }
  return cache.skin ? &*cache.skin : nullptr;
}

void compute_skin_cluster(ComputeContext& c) {
  namespace a = skin_cluster_attr;
  const auto& bind_points = c.get<std::vector<Vec3>>(a::kBindPoints);
  const auto& bind_normals = c.get<std::vector<Vec3>>(a::kBindNormals);
  const auto& joint_world = c.get<std::vector<Mat4>>(a::kJointMatrices);
  const auto& bind_pre = c.get<std::vector<Mat4>>(a::kBindPreMatrices);
  const Mat4& geom = c.get<Mat4>(a::kGeomMatrix);

  SkinClusterCache& cache = c.cache<SkinClusterCache>();
  const Skin* skin = cached_skin(c, cache, joint_world.size());
  const bool normals_ok = bind_normals.empty() || bind_normals.size() == bind_points.size();
  if (!skin || skin->vertex_count() != bind_points.size() || !normals_ok) {
    pass_through_skin(c);
    return;
  }
  if (!cache.points_built || cache.points_version != c.version(a::kBindPoints) ||
      cache.normals_version != c.version(a::kBindNormals)) {
    to_float(bind_points, cache.in_points);
    to_float(bind_normals, cache.in_normals);
    cache.out_points.resize(cache.in_points.size());
    cache.out_normals.resize(cache.in_normals.size());
    cache.points_built = true;
    cache.points_version = c.version(a::kBindPoints);
    cache.normals_version = c.version(a::kBindNormals);
  }

  // Missing bind pre-matrices are the identity (an array's zero element).
  cache.inverse_bind.assign(bind_pre.begin(),
                            bind_pre.begin() + static_cast<std::ptrdiff_t>(std::min(bind_pre.size(), joint_world.size())));
  cache.inverse_bind.resize(joint_world.size(), Mat4::Identity());

  const bool dual_quaternion = c.get<std::int64_t>(a::kMethod) == 1;
  SkinningMatricesJob matrices;
  matrices.joint_world = joint_world;
  matrices.inverse_bind = cache.inverse_bind;
  matrices.world_to_mesh = math::affine_inverse(geom);
  if (dual_quaternion) {
    cache.dual_quat.resize(joint_world.size());
    matrices.dual_quat = cache.dual_quat;
  } else {
    cache.linear.resize(joint_world.size());
    matrices.linear = cache.linear;
  }
  if (!matrices.run()) {  // a matrix that is not affine, or a singular geomMatrix
    pass_through_skin(c);
    return;
  }

  const bool parallel = bind_points.size() >= kParallelVertices;
  bool ok = false;
  if (dual_quaternion) {
    DualQuaternionSkinningJob job;
    job.skin = skin;
    job.matrices = cache.dual_quat;
    job.in_positions = cache.in_points;
    job.out_positions = cache.out_points;
    job.in_normals = cache.in_normals;
    job.out_normals = cache.out_normals;
    ok = parallel ? job.run_parallel(kParallelGrain) : job.run();
  } else {
    LinearBlendSkinningJob job;
    job.skin = skin;
    job.matrices = cache.linear;
    job.in_positions = cache.in_points;
    job.out_positions = cache.out_points;
    job.in_normals = cache.in_normals;
    job.out_normals = cache.out_normals;
    ok = parallel ? job.run_parallel(kParallelGrain) : job.run();
  }
  if (!ok) {
    pass_through_skin(c);
    return;
  }
  to_double(cache.out_points, std::get<std::vector<Vec3>>(c.output(a::kOutPoints)));
  to_double(cache.out_normals, std::get<std::vector<Vec3>>(c.output(a::kOutNormals)));
}

// ---- blendShape --------------------------------------------------------------

// What a blendShape keeps between evaluations: its targets compiled in
// float, rebuilt only when the deltas, offsets, indices or the base's size
// changed (animating the weights costs the kernel alone).
struct BlendShapeCache final : graph::NodeCache {
  bool built = false;
  std::array<std::uint64_t, 3> versions{};
  std::size_t base_size = 0;
  std::optional<BlendShapeTargets> targets;  // empty: the targets are invalid
  std::size_t target_count = 0;
  std::vector<float> weights;
  std::vector<Vec3f> points;
};

// The cache's targets, rebuilt when their inputs changed; nullptr when they
// are invalid (offsets or indices that do not fit the deltas).
const BlendShapeTargets* cached_targets(ComputeContext& c, BlendShapeCache& cache, std::size_t base_size) {
  namespace a = blend_shape_attr;
  const std::array<std::uint64_t, 3> versions = {c.version(a::kTargetDeltas), c.version(a::kTargetOffsets),
                                                 c.version(a::kTargetIndices)};
  if (cache.built && versions == cache.versions && base_size == cache.base_size)
    return cache.targets ? &*cache.targets : nullptr;
  cache.built = true;
  cache.versions = versions;
  cache.base_size = base_size;
  cache.targets.reset();
  cache.target_count = 0;
  const auto& deltas = c.get<std::vector<Vec3>>(a::kTargetDeltas);
  const auto& offsets = c.get<std::vector<std::int64_t>>(a::kTargetOffsets);
  const auto& indices = c.get<std::vector<std::int64_t>>(a::kTargetIndices);
  // Offsets: empty (no targets) or target_count + 1 entries, from 0 up to
  // the number of deltas; indices: empty or one per delta.
  const bool offsets_ok =
      offsets.empty() || (offsets.front() == 0 && static_cast<std::uint64_t>(offsets.back()) == deltas.size() &&
                          std::is_sorted(offsets.begin(), offsets.end()));
  if (!offsets_ok || (!indices.empty() && indices.size() != deltas.size())) return nullptr;
  const std::size_t target_count = offsets.empty() ? 0 : offsets.size() - 1;
  std::vector<Vec3f> deltas_f;
  to_float(deltas, deltas_f);
  BlendShapeBuilder builder(base_size);
  for (std::size_t t = 0; t < target_count; ++t) {
    const auto begin = static_cast<std::size_t>(offsets[t]);
    const auto count = static_cast<std::size_t>(offsets[t + 1]) - begin;
    const std::span<const Vec3f> target(deltas_f.data() + begin, count);
    if (indices.empty())
      builder.add_dense_target(target);
    else
      builder.add_sparse_target(std::span<const std::int64_t>(indices.data() + begin, count), target);
  }
  Result<BlendShapeTargets> targets = builder.build();
  if (!targets) return nullptr;
  cache.targets.emplace(std::move(*targets));
  cache.target_count = target_count;
  return &*cache.targets;
}

void compute_blend_shape(ComputeContext& c) {
  namespace a = blend_shape_attr;
  const auto& base = c.get<std::vector<Vec3>>(a::kBasePoints);
  const auto& weights = c.get<std::vector<double>>(a::kWeights);
  auto pass_through = [&] { c.output(a::kOutPoints) = base; };

  BlendShapeCache& cache = c.cache<BlendShapeCache>();
  const BlendShapeTargets* targets = cached_targets(c, cache, base.size());
  if (!targets) {
    pass_through();
    return;
  }
  cache.weights.assign(cache.target_count, 0.0f);
  for (std::size_t t = 0; t < std::min(cache.target_count, weights.size()); ++t)
    cache.weights[t] = static_cast<float>(weights[t]);

  to_float(base, cache.points);
  BlendShapeJob job;
  job.targets = targets;
  job.base = cache.points;
  job.weights = cache.weights;
  job.out = cache.points;  // in place
  const bool ok = base.size() >= kParallelVertices ? job.run_parallel(kParallelGrain) : job.run();
  if (!ok) {  // a weight that is NaN or infinite
    pass_through();
    return;
  }
  to_double(cache.points, std::get<std::vector<Vec3>>(c.output(a::kOutPoints)));
}

}  // namespace

Status register_deform_types(graph::Registry& registry) {
  {
    namespace a = skin_cluster_attr;
    graph::NodeTypeSpec spec;
    spec.name = kSkinClusterType;
    spec.description = "Skins points with joint matrices: linear blend or dual quaternion";
    AttrSpec method = input("method", {ValueType::kEnum, false}, std::int64_t{0});
    method.enum_names = {"linear", "dualQuaternion"};
    spec.attrs = {
        input("bindPoints", kPoints, std::vector<Vec3>{}),
        input("bindNormals", kPoints, std::vector<Vec3>{}),
        input("jointMatrices", kMatrices, std::vector<Mat4>{}),
        input("bindPreMatrices", kMatrices, std::vector<Mat4>{}),
        input("geomMatrix", {ValueType::kMatrix, false}, Mat4(Mat4::Identity())),
        input("influenceOffsets", kInts, std::vector<std::int64_t>{0}),
        input("influenceJoints", kInts, std::vector<std::int64_t>{}),
        input("influenceWeights", kDoubles, std::vector<double>{}),
        input("normalizeWeights", {ValueType::kBool, false}, true),
        method,
        output("outPoints", kPoints),
        output("outNormals", kPoints),
    };
    for (graph::AttrIndex i = 0; i < a::kOutPoints; ++i) spec.attrs[i].affects = {"outPoints", "outNormals"};
    spec.compute = compute_skin_cluster;
    if (Status s = registry.add(std::move(spec)); !s) return s;
  }
  {
    namespace a = blend_shape_attr;
    graph::NodeTypeSpec spec;
    spec.name = kBlendShapeType;
    spec.description = "Adds weighted target deltas to points (morph targets)";
    spec.attrs = {
        input("basePoints", kPoints, std::vector<Vec3>{}),
        input("targetDeltas", kPoints, std::vector<Vec3>{}),
        input("targetOffsets", kInts, std::vector<std::int64_t>{}),
        input("targetIndices", kInts, std::vector<std::int64_t>{}),
        input("weights", kDoubles, std::vector<double>{}, graph::kKeyable),
        input("targetNames", {ValueType::kString, true}, std::vector<std::string>{}),
        output("outPoints", kPoints),
    };
    // Names are data for people and tools; they change no point.
    for (graph::AttrIndex i = 0; i < a::kTargetNames; ++i) spec.attrs[i].affects = {"outPoints"};
    spec.compute = compute_blend_shape;
    if (Status s = registry.add(std::move(spec)); !s) return s;
  }
  return Status::ok();
}

}  // namespace rigel::ops
