#include "rigel/ops/util/nodes.h"

#include <cmath>

#include "rigel/graph/graph.h"
#include "rigel/math/types.h"
#include "rigel/ops/util/blend.h"
#include "rigel/ops/util/finger.h"
#include "rigel/ops/util/foot.h"
#include "rigel/ops/util/space.h"
#include "rigel/ops/util/twist.h"

namespace rigel::ops::util {
namespace {

using graph::AttrType;
using graph::ValueType;
using math::Mat4;

constexpr AttrType kMatrix{ValueType::kMatrix, false};

enum : graph::AttrIndex { kInputMatrix = 0, kOffsetMatrix, kOutputMatrix, kError };

void compute_inverse(graph::ComputeContext& c) {
  const Mat4 m = c.get<Mat4>(kInputMatrix) * c.get<Mat4>(kOffsetMatrix);
  const double det = m.topLeftCorner<3, 3>().determinant();
  const double scale = m.topLeftCorner<3, 3>().cwiseAbs().maxCoeff();
  if (!std::isfinite(det) || !m.allFinite() || std::abs(det) <= 1e-12 * scale * scale * scale || scale == 0) {
    c.set(kOutputMatrix, Mat4(Mat4::Identity()));
    c.set(kError, std::string("inputMatrix * offsetMatrix is singular or not finite"));
    return;
  }
  c.set(kOutputMatrix, Mat4(m.inverse()));
  c.set(kError, std::string());
}

}  // namespace

Status register_util_types(graph::Registry& registry) {
  graph::NodeTypeSpec spec;
  spec.name = kInverseMatrixType;
  spec.description = "outputMatrix = (inputMatrix * offsetMatrix)^-1";
  spec.attrs = {graph::input_attr("inputMatrix", kMatrix, Mat4(Mat4::Identity()), {"outputMatrix", "error"}),
                graph::input_attr("offsetMatrix", kMatrix, Mat4(Mat4::Identity()), {"outputMatrix", "error"}),
                graph::output_attr("outputMatrix", kMatrix),
                graph::output_attr("error", {ValueType::kString, false}, graph::kHidden)};
  spec.compute = compute_inverse;
  if (Status s = registry.add(std::move(spec)); !s) return s;
  if (Status s = register_blend_types(registry); !s) return s;
  if (Status s = register_finger_types(registry); !s) return s;
  if (Status s = register_foot_types(registry); !s) return s;
  if (Status s = register_space_types(registry); !s) return s;
  return register_twist_types(registry);
}

}  // namespace rigel::ops::util
