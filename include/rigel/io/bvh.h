#pragma once
// BVH motion capture files: the hierarchy (offsets, channels in any order)
// and the motion table, parsed into plain data. Importing into a scene is a
// separate step (units and axes are kept as in the file).

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/math/types.h"

namespace rigel::io {

enum class BvhChannel : std::uint8_t { kXposition, kYposition, kZposition, kXrotation, kYrotation, kZrotation };

struct BvhJoint {
  std::string name;               // "End Site" joints get "<parent>_end"
  std::int32_t parent = -1;       // index in BvhFile::joints, parents first
  math::Vec3 offset = math::Vec3::Zero();
  std::vector<BvhChannel> channels;  // in file order
  std::uint32_t first_channel = 0;   // column of channels[0] in a motion row
  bool end_site = false;
  std::uint32_t line = 0;            // where the joint is declared
};

struct BvhFile {
  std::vector<BvhJoint> joints;
  std::uint32_t channel_count = 0;  // columns per motion row
  std::uint32_t frame_count = 0;
  double frame_time = 0.0;          // seconds per frame
  std::vector<double> motion;       // frame_count rows of channel_count values, degrees for rotations

  double value(std::uint32_t frame, std::uint32_t column) const { return motion[std::size_t{frame} * channel_count + column]; }
};

// The ranges a BVH file's MOTION header must keep: Frames from 0 to 10^8,
// Frame Time from 0.0001 s to 1000 s (10,000 down to 0.001 frames per
// second, the scene's frame rate).
constexpr double kBvhMaxFrames = 1e8;
constexpr double kBvhMinFrameTime = 1e-4;
constexpr double kBvhMaxFrameTime = 1e3;

// Parses BVH text. Errors name the place: "walk.bvh:12: expected '{' after JOINT Hips".
// Refuses: missing sections, unbalanced braces, unknown channel names,
// repeated channels, non-finite numbers, Frames or a Frame Time outside the
// ranges above (the message names the range and the value), a motion table
// whose size differs from Frames x channels, more than 100,000 joints or
// nesting deeper than 1,000.
Result<BvhFile> parse_bvh(std::string_view text, const std::string& source);
Result<BvhFile> load_bvh(const std::string& path);

// The rotate order ("xyz" ... as math::RotateOrder) that the joint's rotation
// channels spell: BVH lists rotations outermost first, so "Z X Y" applies Y
// first and is rigel's kYXZ. Missing axes are zero and are placed last.
int bvh_rotate_order(const BvhJoint& joint);

}  // namespace rigel::io
