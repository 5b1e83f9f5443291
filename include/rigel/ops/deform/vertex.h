#pragma once
// Vertex data of the deformers: float xyz, packed (12 bytes, no padding), so
// a span of them is the flat float array glTF buffers and GPU uploads use.

#include <Eigen/Core>
#include <span>
#include <vector>

#include "rigel/math/types.h"

namespace rigel::ops {

using Vec3f = Eigen::Vector3f;
static_assert(sizeof(Vec3f) == 3 * sizeof(float), "deformer kernels read Vec3f spans as packed float triples");

// Conversions at the graph boundary, where points are double3[]. The output
// is resized to the input's size.
void to_float(std::span<const math::Vec3> in, std::vector<Vec3f>& out);
void to_double(std::span<const Vec3f> in, std::vector<math::Vec3>& out);

}  // namespace rigel::ops
