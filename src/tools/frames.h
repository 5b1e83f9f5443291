#pragma once
// The frames a tool samples over a range (bake, match): first, first + 1,
// ..., and last, unless last is within the key tolerance of the frame
// before (then that one is taken at last). Internal to the tools layer.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/graph/graph.h"
#include "rigel/ops/anim/channel_keys.h"

namespace rigel::tools::internal {

// kInvalidArgument naming `what` when a frame is not finite, first > last,
// or the range holds more than a million frames.
inline Result<std::vector<double>> frames_between(const graph::Graph& g, double first, double last,
                                                  const std::string& what) {
  if (!std::isfinite(first) || !std::isfinite(last) || first > last)
    return error(ErrorCode::kInvalidArgument, what + ": frames must be finite, first <= last");
  if (last - first > 1e6) return error(ErrorCode::kInvalidArgument, what + ": more than a million frames");
  std::vector<double> frames;
  for (double f = first; f <= last + 1e-9; f += 1.0) frames.push_back(std::min(f, last));
  if (frames.back() < last - 1e-9) {
    if ((last - frames.back()) / g.fps() > ops::anim::kKeyTimeTolerance) frames.push_back(last);
    else frames.back() = last;
  }
  return frames;
}

}  // namespace rigel::tools::internal
