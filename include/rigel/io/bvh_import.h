#pragma once
// Brings a parsed BVH file into a scene: one joint per BVH joint (End Sites
// included, as leaf joints), rotate orders from the channel order, and the
// motion as linear animCurveVec3 tracks driving translate and rotate.

#include <memory>

#include "rigel/io/bvh.h"
#include "rigel/scene/scene.h"

namespace rigel::io {

struct BvhImportOptions {
  // Multiplies offsets and position channels: units stay as in the file
  // unless asked (e.g. 0.0254 for inches to metres).
  double scale = 1.0;
  // Skip End Site joints.
  bool skip_end_sites = false;
  // The node types the scene is built over; null: ops::default_registry()
  // (a registry given must hold those types).
  std::shared_ptr<const graph::Registry> registry;
};

// The scene's frame rate comes from Frame Time (snapped to a whole number
// of frames per second when within 0.1% of one, so 0.0083333 s is 120 fps),
// and motion row i is at frame i (time i / fps): the first row is time 0.
Result<std::unique_ptr<scene::Scene>> import_bvh(const BvhFile& file, const BvhImportOptions& options = {});

}  // namespace rigel::io
