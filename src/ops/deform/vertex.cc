#include "rigel/ops/deform/vertex.h"

namespace rigel::ops {

void to_float(std::span<const math::Vec3> in, std::vector<Vec3f>& out) {
  out.resize(in.size());
  for (std::size_t i = 0; i < in.size(); ++i) out[i] = in[i].cast<float>();
}

void to_double(std::span<const Vec3f> in, std::vector<math::Vec3>& out) {
  out.resize(in.size());
  for (std::size_t i = 0; i < in.size(); ++i) out[i] = in[i].cast<double>();
}

}  // namespace rigel::ops
