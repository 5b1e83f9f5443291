#pragma once
// Graph node types of the deformers: skinCluster and blendShape. They hold
// their data in attributes (what files store), convert it per evaluation and
// call the jobs of skinning.h and blend_shape.h, where the maths lives.
//
// Per evaluation a node copies its array inputs to float, compiles the skin
// or the targets, runs the job and copies the result back to double3[]: for
// 100,000 points x 4 influences a skinCluster evaluation takes about 6 ms
// (bench/deform_bench.cc), against 0.17 ms for the skinning job itself.
// Callers that evaluate a mesh every frame (playback, export) can call the
// jobs directly with a Skin built once. (A node cannot keep a compiled Skin
// between evaluations: values are the closed set graph::Value holds, and
// compute does not see which inputs changed.)
//
// Neither node has an error output: with data it cannot use (weights that do
// not validate, counts that do not match) a node passes its input points
// through unchanged, so a half-wired rig shows its rest shape.

#include "rigel/base/status.h"
#include "rigel/graph/node_type.h"

namespace rigel::ops {

inline constexpr const char* kSkinClusterType = "skinCluster";
inline constexpr const char* kBlendShapeType = "blendShape";

// skinCluster: outPoints = skinned bindPoints.
namespace skin_cluster_attr {
enum : graph::AttrIndex {
  kBindPoints = 0,    // double3[]: bind-pose points, in the space bindPreMatrices expect
  kBindNormals,       // double3[]: optional bind-pose normals (empty: outNormals is empty)
  kJointMatrices,     // matrix[]: joint world matrices; connect joint.worldMatrix -> jointMatrices[i]
  kBindPreMatrices,   // matrix[]: inverse bind matrices (missing elements are the identity)
  kGeomMatrix,        // matrix: world matrix of the deformed mesh; its inverse is applied last,
                      // so outPoints are in the mesh's local space (identity: skeleton space, glTF)
  kInfluenceOffsets,  // int[]: vertex_count + 1 offsets into influenceJoints / influenceWeights
  kInfluenceJoints,   // int[]: joint index (into jointMatrices) of each influence
  kInfluenceWeights,  // double[]: weight of each influence
  kNormalizeWeights,  // bool, default true: weights divided by their sum per vertex
  kMethod,            // enum linear (default), dualQuaternion
  kOutPoints,         // output double3[]
  kOutNormals,        // output double3[]
  kCount
};
}  // namespace skin_cluster_attr

// blendShape: outPoints = basePoints + sum_t weights[t] * delta_t.
namespace blend_shape_attr {
enum : graph::AttrIndex {
  kBasePoints = 0,  // double3[]
  kTargetDeltas,    // double3[]: every target's deltas, one after the other
  kTargetOffsets,   // int[]: target_count + 1 offsets into targetDeltas
  kTargetIndices,   // int[]: vertex of each delta (sparse targets); empty: every target is
                    // dense, one delta per base point, in order
  kWeights,         // double[], keyable: weight of each target (missing: 0)
  kTargetNames,     // string[]: name of each target (missing or "": unnamed); read from a glTF
                    // mesh's extras.targetNames, what blend shape data files match targets by
  kOutPoints,       // output double3[]
  kCount
};
}  // namespace blend_shape_attr

// Adds skinCluster and blendShape to `registry`.
Status register_deform_types(graph::Registry& registry);

}  // namespace rigel::ops
