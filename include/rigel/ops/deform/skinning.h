#pragma once
// Skinning: bind-pose points and normals moved by weighted joint matrices.
// Three jobs (STYLE.md §3: spans in, spans out, validate() then run(), no
// allocation inside):
//
//   SkinningMatricesJob         per joint: world_to_mesh * joint_world * inverse_bind,
//                               in the forms the two skinning jobs read;
//   LinearBlendSkinningJob      p' = (sum_k w_k M_k) p;
//   DualQuaternionSkinningJob   p' = DQ-blend(rigid parts) applied to (sum_k w_k S_k) p.
//
// Both skinning jobs run on the whole mesh (run()), on a range of vertices
// (run(begin, end), for callers that split the work themselves: every vertex
// is independent, and a vertex gives the same bits whatever range it is run
// in), or on every core (run_parallel(), TBB). Vertex data is float (see
// skin.h for why); per-joint matrices are computed in double and rounded
// once.

#include <cstddef>
#include <span>

#include "rigel/math/types.h"
#include "rigel/ops/deform/skin.h"
#include "rigel/ops/deform/vertex.h"

namespace rigel::ops {

// A skinning matrix as the linear-blend kernels read it: the top three rows
// of an affine matrix in float, column-major, each column padded with a 0 to
// four floats. One 64-byte cache line, loaded whole by the vector kernels.
struct alignas(64) SkinMatrix {
  float m[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0};  // column c, row r at m[4 * c + r]

  // Rounds the top three rows of `matrix` to float (its last row is not read).
  static SkinMatrix from(const math::Mat4& matrix);
  // Back to double, last row 0 0 0 1.
  math::Mat4 to_mat4() const;
};

// A skinning matrix split for dual-quaternion skinning: M = [R t] * [S 0],
// the rigid part (R, t) as a unit dual quaternion and the rest, S = R^T A
// (scale and shear, applied in bind space before the rigid part), as a 3x3
// matrix. R is the rotation math::rigid_part() takes, so M == rigid * S
// exactly, whatever the shear. Double: computed per joint, read per vertex.
struct DualQuatSkinMatrix {
  double real[4] = {0, 0, 0, 1};                    // rotation quaternion, x y z w
  double dual[4] = {0, 0, 0, 0};                    // 0.5 * translation * rotation, x y z w
  double stretch[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};  // S, column-major
  bool has_stretch = false;                         // S differs from the identity by more than kStretchTolerance

  static constexpr double kStretchTolerance = 1e-9;
  static DualQuatSkinMatrix from(const math::Mat4& matrix);
};

// Per joint j: matrix = world_to_mesh * joint_world[j] * inverse_bind[j].
// inverse_bind ("bind pre-matrices") takes bind-pose points into the joint's
// space; joint_world takes them back out where the joint is now. glTF:
// skinned points are in the skeleton's space and the mesh node's own
// transform is ignored, so world_to_mesh stays the identity; set it to the
// inverse of the mesh's world matrix to get points in the mesh's local space
// (for a mesh whose transform is then applied on top, as in Maya).
struct SkinningMatricesJob {
  // Validates job parameters. Returns false:
  // - if joint_world and inverse_bind differ in size;
  // - if a non-empty output (matrices, linear, dual_quat) does not have
  //   exactly joint_world.size() entries;
  // - if world_to_mesh, a joint_world or an inverse_bind matrix is not
  //   affine (last row 0 0 0 1) or holds a NaN or infinity.
  // Empty outputs are skipped; a job with no output is valid and does nothing.
  bool validate() const;
  // Returns false if the job is not valid.
  bool run() const;

  // World matrix of each joint (skeleton space).
  std::span<const math::Mat4> joint_world;
  // Inverse of each joint's world matrix at bind time.
  std::span<const math::Mat4> inverse_bind;
  // Applied last (leftmost): see above.
  math::Mat4 world_to_mesh = math::Mat4::Identity();

  // Outputs, each optional. Double products.
  std::span<math::Mat4> matrices;
  // For LinearBlendSkinningJob.
  std::span<SkinMatrix> linear;
  // For DualQuaternionSkinningJob.
  std::span<DualQuatSkinMatrix> dual_quat;
};

// Linear blend skinning: p' = (sum_k w_k M_k) p, per vertex, with the skin's
// weights and joints. Normals, when asked for, go through the inverse
// transpose of the same blended 3x3 (computed as its cofactor matrix, sign
// of the determinant kept) and are normalised, so they stay perpendicular to
// the surface under scale and shear; a normal that comes out zero is written
// as zero. Uses the skin's fixed 4-influence layout when it has one (the
// results equal the general layout's); x86 CPUs with AVX-512 or AVX2 + FMA
// get a vector kernel chosen at run time.
struct LinearBlendSkinningJob {
  // Validates job parameters. Returns false:
  // - if skin is nullptr;
  // - if matrices has fewer than skin->joint_count() entries;
  // - if in_positions or out_positions does not have skin->vertex_count()
  //   entries;
  // - if in_normals is neither empty nor skin->vertex_count() long, or
  //   out_normals does not have in_normals' size;
  // - if an output overlaps an input or the other output.
  bool validate() const;
  // Skins every vertex. Returns false if the job is not valid.
  bool run() const;
  // Skins vertices [begin, end) only. Returns false if the job is not valid
  // or the range is not within [0, vertex_count].
  bool run(std::size_t begin, std::size_t end) const;
  // run() split over TBB's threads, `grain` vertices at least per task (0: a
  // default). The results equal run()'s bit for bit.
  bool run_parallel(std::size_t grain = 0) const;

  const Skin* skin = nullptr;
  // Indexed by the skin's joint indices (SkinningMatricesJob::linear).
  std::span<const SkinMatrix> matrices;
  // Bind-pose positions, in the space inverse_bind expects.
  std::span<const Vec3f> in_positions;
  std::span<Vec3f> out_positions;
  // Optional bind-pose normals and their output (both empty: no normals).
  std::span<const Vec3f> in_normals;
  std::span<Vec3f> out_normals;
};

// Dual quaternion skinning (Kavan et al. 2008) with scale: each joint's
// matrix is split into a rigid part (a unit dual quaternion) and a 3x3
// stretch S (DualQuatSkinMatrix). Per vertex, the stretches are blended
// linearly and applied to the bind position, then the dual quaternions are
// blended (each one's sign taken in the hemisphere of the vertex's first
// influence, so q and -q do not cancel), normalised and applied. Rigid
// joints keep the volume that linear blending loses under twist. When no
// joint has a stretch, that phase is skipped. Normals: the blended stretch's
// inverse transpose, then the rotation, then normalised. Computed in double
// per vertex, stored in float.
struct DualQuaternionSkinningJob {
  // Validates job parameters. Returns false in the cases
  // LinearBlendSkinningJob::validate() lists (with these matrices).
  bool validate() const;
  bool run() const;
  bool run(std::size_t begin, std::size_t end) const;
  bool run_parallel(std::size_t grain = 0) const;

  const Skin* skin = nullptr;
  // Indexed by the skin's joint indices (SkinningMatricesJob::dual_quat).
  std::span<const DualQuatSkinMatrix> matrices;
  std::span<const Vec3f> in_positions;
  std::span<Vec3f> out_positions;
  std::span<const Vec3f> in_normals;
  std::span<Vec3f> out_normals;
};

}  // namespace rigel::ops
