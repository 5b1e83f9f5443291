#include "rigel/ops/util/space.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "rigel/graph/graph.h"
#include "rigel/math/transform.h"
#include "rigel/math/types.h"

namespace rigel::ops::util {
namespace {

using graph::AttrType;
using graph::ValueType;
using math::Mat4;
namespace a = space_attr;

constexpr AttrType kMatrix{ValueType::kMatrix, false};
constexpr AttrType kMatrixArray{ValueType::kMatrix, true};

bool invertible(const Mat4& m) {
  const double det = m.topLeftCorner<3, 3>().determinant();
  const double scale = m.topLeftCorner<3, 3>().cwiseAbs().maxCoeff();
  return m.allFinite() && std::isfinite(det) && scale > 0 && std::abs(det) > 1e-12 * scale * scale * scale;
}

void compute_space_switch(graph::ComputeContext& c) {
  const double space = c.get<double>(a::kSpace);
  const auto& names = c.get<std::vector<std::string>>(a::kSpaceNames);
  const auto& targets = c.get<std::vector<Mat4>>(a::kTargetWorldMatrix);
  const auto& offsets = c.get<std::vector<Mat4>>(a::kTargetOffset);
  const Mat4& parent = c.get<Mat4>(a::kParentMatrix);
  const Mat4& rest = c.get<Mat4>(a::kRestOffset);
  const int k = space_index(space, static_cast<int>(names.size()));
  c.set(a::kSpaceIndex, static_cast<std::int64_t>(k));
  if (!std::isfinite(space) || !invertible(parent)) {
    c.set(a::kOutMatrix, rest);
    c.set(a::kError, std::string(std::isfinite(space) ? "parentMatrix is singular or not finite"
                                                      : "space is not finite"));
    return;
  }
  const auto at = [&](const std::vector<Mat4>& list) {
    return static_cast<std::size_t>(k) < list.size() ? list[static_cast<std::size_t>(k)] : Mat4(Mat4::Identity());
  };
  c.set(a::kOutMatrix, Mat4(math::affine_inverse(parent) * at(targets) * at(offsets) *
                            c.get<Mat4>(a::kCompensationMatrix) * rest));
  c.set(a::kError, std::string());
}

}  // namespace

int space_index(double space, int count) {
  if (count <= 0 || !std::isfinite(space)) return 0;
  return static_cast<int>(std::clamp(std::round(space), 0.0, static_cast<double>(count - 1)));
}

Status register_space_types(graph::Registry& registry) {
  const std::vector<std::string> outs = {"outMatrix", "spaceIndex", "error"};
  graph::NodeTypeSpec spec;
  spec.name = kSpaceSwitchType;
  spec.description = "The parent space a control follows: outMatrix for its offsetParentMatrix";
  spec.attrs = {graph::input_attr("space", {ValueType::kDouble, false}, 0.0, outs, graph::kKeyable),
                graph::input_attr("spaceNames", {ValueType::kString, true}, std::vector<std::string>{}, outs),
                graph::input_attr("targetWorldMatrix", kMatrixArray, std::vector<Mat4>{}, outs),
                graph::input_attr("targetOffset", kMatrixArray, std::vector<Mat4>{}, outs),
                graph::input_attr("parentMatrix", kMatrix, Mat4(Mat4::Identity()), outs),
                graph::input_attr("compensationMatrix", kMatrix, Mat4(Mat4::Identity()), outs),
                graph::input_attr("restOffset", kMatrix, Mat4(Mat4::Identity()), outs),
                graph::output_attr("outMatrix", kMatrix),
                graph::output_attr("spaceIndex", {ValueType::kInt, false}),
                graph::output_attr("error", {ValueType::kString, false}, graph::kHidden)};
  spec.compute = compute_space_switch;
  return registry.add(std::move(spec));
}

}  // namespace rigel::ops::util
