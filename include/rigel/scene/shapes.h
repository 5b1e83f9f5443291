// The control shape library and colour palette: what a control looks like
// (scene `control` nodes draw `shapePoints` as a polyline, closed or not, in
// `shapeColor`). Rig definitions name shapes and colours; components build
// their controls from here.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "rigel/math/types.h"

namespace rigel::scene {

// A shape as line strips in the control's local space, about unit size
// (radius / half-extent 1) before `size` scaling. Each strip is drawn as a
// polyline (closed when `closed`); a control node holds one strip, so
// multi-strip shapes (cube, sphere) are laid out as one continuous strip
// that retraces edges where needed.
struct ControlShape {
  std::vector<math::Vec3> points;
  bool closed = true;
};

// Names: circle, square, cube, sphere, diamond, cross, arrow, doubleArrow,
// fourArrow, fourArrowCircle, locator, pin, triangle. Case-sensitive.
std::vector<std::string> control_shape_names();
// The shape scaled by `size`; nullopt for an unknown name.
std::optional<ControlShape> control_shape(std::string_view name, double size = 1.0);

// Palette names (yellow, red, blue, green, cyan, magenta, orange, purple,
// pink, white, black, grey, lightBlue, darkBlue, lightGreen, darkGreen,
// darkRed, brown) or "#rrggbb": linear RGB in [0, 1]; nullopt otherwise.
std::vector<std::string> color_names();
std::optional<math::Vec3> color_from_name(std::string_view name);

}  // namespace rigel::scene
