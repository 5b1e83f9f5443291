#include "rigel/ops/deform/nodes.h"

#include <algorithm>
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

// Below this many vertices a node skins on its own thread: the graph
// already runs independent nodes in parallel.
constexpr std::size_t kParallelVertices = 16384;

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

void compute_skin_cluster(ComputeContext& c) {
  namespace a = skin_cluster_attr;
  const auto& bind_points = c.get<std::vector<Vec3>>(a::kBindPoints);
  const auto& bind_normals = c.get<std::vector<Vec3>>(a::kBindNormals);
  const auto& joint_world = c.get<std::vector<Mat4>>(a::kJointMatrices);
  const auto& bind_pre = c.get<std::vector<Mat4>>(a::kBindPreMatrices);
  const Mat4& geom = c.get<Mat4>(a::kGeomMatrix);

  SkinBuildOptions options;
  options.joint_count = joint_world.size();
  options.normalize = c.get<bool>(a::kNormalizeWeights);
  options.fixed_layout = true;
  const SkinInfluenceView view{c.get<std::vector<std::int64_t>>(a::kInfluenceOffsets),
                               c.get<std::vector<std::int64_t>>(a::kInfluenceJoints),
                               c.get<std::vector<double>>(a::kInfluenceWeights)};
  Result<Skin> skin = build_skin(view, options);
  const bool normals_ok = bind_normals.empty() || bind_normals.size() == bind_points.size();
  if (!skin || skin->vertex_count() != bind_points.size() || !normals_ok) {
    pass_through_skin(c);
    return;
  }

  // Missing bind pre-matrices are the identity (an array's zero element).
  std::vector<Mat4> inverse_bind(
      bind_pre.begin(), bind_pre.begin() + static_cast<std::ptrdiff_t>(std::min(bind_pre.size(), joint_world.size())));
  inverse_bind.resize(joint_world.size(), Mat4::Identity());

  const bool dual_quaternion = c.get<std::int64_t>(a::kMethod) == 1;
  std::vector<SkinMatrix> linear;
  std::vector<DualQuatSkinMatrix> dual_quat;
  SkinningMatricesJob matrices;
  matrices.joint_world = joint_world;
  matrices.inverse_bind = inverse_bind;
  matrices.world_to_mesh = math::affine_inverse(geom);
  if (dual_quaternion) {
    dual_quat.resize(joint_world.size());
    matrices.dual_quat = dual_quat;
  } else {
    linear.resize(joint_world.size());
    matrices.linear = linear;
  }
  if (!matrices.run()) {  // a matrix that is not affine, or a singular geomMatrix
    pass_through_skin(c);
    return;
  }

  std::vector<Vec3f> in_points, out_points(bind_points.size()), in_normals, out_normals(bind_normals.size());
  to_float(bind_points, in_points);
  to_float(bind_normals, in_normals);
  const bool parallel = bind_points.size() >= kParallelVertices;
  bool ok = false;
  if (dual_quaternion) {
    DualQuaternionSkinningJob job;
    job.skin = &*skin;
    job.matrices = dual_quat;
    job.in_positions = in_points;
    job.out_positions = out_points;
    job.in_normals = in_normals;
    job.out_normals = out_normals;
    ok = parallel ? job.run_parallel() : job.run();
  } else {
    LinearBlendSkinningJob job;
    job.skin = &*skin;
    job.matrices = linear;
    job.in_positions = in_points;
    job.out_positions = out_points;
    job.in_normals = in_normals;
    job.out_normals = out_normals;
    ok = parallel ? job.run_parallel() : job.run();
  }
  if (!ok) {
    pass_through_skin(c);
    return;
  }
  to_double(out_points, std::get<std::vector<Vec3>>(c.output(a::kOutPoints)));
  to_double(out_normals, std::get<std::vector<Vec3>>(c.output(a::kOutNormals)));
}

// ---- blendShape --------------------------------------------------------------

void compute_blend_shape(ComputeContext& c) {
  namespace a = blend_shape_attr;
  const auto& base = c.get<std::vector<Vec3>>(a::kBasePoints);
  const auto& deltas = c.get<std::vector<Vec3>>(a::kTargetDeltas);
  const auto& offsets = c.get<std::vector<std::int64_t>>(a::kTargetOffsets);
  const auto& indices = c.get<std::vector<std::int64_t>>(a::kTargetIndices);
  const auto& weights = c.get<std::vector<double>>(a::kWeights);
  auto pass_through = [&] { c.output(a::kOutPoints) = base; };

  // Offsets: empty (no targets) or target_count + 1 entries, from 0 up to
  // the number of deltas; indices: empty or one per delta.
  const bool offsets_ok =
      offsets.empty() || (offsets.front() == 0 && static_cast<std::uint64_t>(offsets.back()) == deltas.size() &&
                          std::is_sorted(offsets.begin(), offsets.end()));
  if (!offsets_ok || (!indices.empty() && indices.size() != deltas.size())) {
    pass_through();
    return;
  }
  const std::size_t target_count = offsets.empty() ? 0 : offsets.size() - 1;
  std::vector<Vec3f> deltas_f;
  to_float(deltas, deltas_f);
  BlendShapeBuilder builder(base.size());
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
  if (!targets) {
    pass_through();
    return;
  }
  std::vector<float> weights_f(target_count, 0.0f);
  for (std::size_t t = 0; t < std::min(target_count, weights.size()); ++t)
    weights_f[t] = static_cast<float>(weights[t]);

  std::vector<Vec3f> points;
  to_float(base, points);
  BlendShapeJob job;
  job.targets = &*targets;
  job.base = points;
  job.weights = weights_f;
  job.out = points;  // in place
  const bool ok = base.size() >= kParallelVertices ? job.run_parallel() : job.run();
  if (!ok) {  // a weight that is NaN or infinite
    pass_through();
    return;
  }
  to_double(points, std::get<std::vector<Vec3>>(c.output(a::kOutPoints)));
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
