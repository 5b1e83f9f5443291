#pragma once
// Channel samples a tool records frame by frame and then keys, each
// channel once (match.cc, mirror.cc). Internal to the tools layer.
#include <cstddef>
#include <span>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/graph/graph.h"
#include "rigel/math/rotation.h"
#include "rigel/math/transform.h"

namespace rigel::tools::internal {

// One transform's local channels (translate, rotation in its rotate mode,
// scale, shear), a sample per frame.
struct Track {
  graph::NodeId node;
  bool quaternion = false;
  math::RotateOrder order = math::RotateOrder::kXYZ;
  std::vector<math::Vec3> translate, euler, scale, shear;  // euler in degrees
  std::vector<math::Quat> rotation;
  bool sheared = false;  // some sample has a shear

  static Track of(graph::Graph& g, graph::NodeId node);
  // Appends `local` (the channels' matrix, under the offset parent),
  // Euler angles kept closest to the previous sample's.
  void push(const math::Mat4& local);
};

// One scalar channel, a sample per frame.
struct ValueTrack {
  graph::Plug plug;
  std::vector<double> values;
};

// Keys every track at `times` (one key per sample; `insert` false: the
// channels are set, or their keys there updated), shear only where a
// sample has some or the channel is keyed already. Adds the keys made to
// `keys`. Fails as ops::anim::write_channel_keys, with "what" in front.
Status write_tracks(graph::Graph& g, std::span<const double> times, const std::vector<Track>& tracks,
                    const std::vector<ValueTrack>& values, bool insert, std::size_t& keys, const char* what);

}  // namespace rigel::tools::internal
