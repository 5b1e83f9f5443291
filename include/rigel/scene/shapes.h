// The control shape library and colour palette: what a control looks like
// (scene `control` nodes draw `shapePoints` as a polyline, closed or not, in
// `shapeColor`). Rig definitions name shapes and colours; components build
// their controls from here.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/graph/graph.h"
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
//
// Every shape fits the unit box (largest |coordinate| exactly 1) and is
// centred on the origin except `pin`. Flat shapes lie in the XZ plane (Y up,
// like Maya's default controls), pointing along +Z where they point:
//   circle           24 segments, radius 1, closed.
//   square           corners (±1, 0, ±1), closed.
//   cube             the 12 edges of [-1, 1]^3 as one open strip of 16 points
//                    (three edges are drawn twice: a cube has no Euler path).
//   sphere           three orthogonal unit circles (XZ, XY, YZ, 24 segments
//                    each) as one open strip; a quarter of the XY circle is
//                    retraced to reach the YZ circle.
//   diamond          flat rhombus (±1, 0, 0), (0, 0, ±1), closed.
//   cross            plus-sign outline, arms 1/2 wide, closed.
//   arrow            one arrow outline pointing +Z, tail at z = -1, closed.
//   doubleArrow      arrow outline pointing both ways along Z, closed.
//   fourArrow        four arrows along ±X and ±Z from a common centre, closed.
//   fourArrowCircle  a circle of radius 0.6 with four arrowheads pointing
//                    out along ±X and ±Z (tips at 1), closed.
//   locator          three axis lines through the origin, ±1 along X, Y and
//                    Z, one open strip (the strip passes back through the
//                    origin between axes).
//   pin              exception to the flat rule: a stick from the origin up
//                    +Y to y = 0.5 topped by a circle of radius 0.25 in the
//                    XY plane (facing +Z, the front view), open; the top is
//                    at y = 1.
//   triangle         equilateral, inscribed in the unit circle, a corner at
//                    +Z, closed.
std::vector<std::string> control_shape_names();
// The shape scaled by `size` (every point multiplied by it, so sizes scale
// exactly); nullopt for an unknown name or a size that is not finite and
// positive.
std::optional<ControlShape> control_shape(std::string_view name, double size = 1.0);

// Palette names (yellow, red, blue, green, cyan, magenta, orange, purple,
// pink, white, black, grey, lightBlue, darkBlue, lightGreen, darkGreen,
// darkRed, brown) or "#rrggbb": linear RGB in [0, 1]; nullopt otherwise.
// Names are case-sensitive; hex digits are not. "#rrggbb" is taken as is
// (each byte / 255), with no sRGB decoding. "#rgb", a missing '#' or any
// non-hex digit is refused.
std::vector<std::string> color_names();
std::optional<math::Vec3> color_from_name(std::string_view name);

// Sets `control`'s shapePoints, shapeClosed and shapeColor from a shape name,
// size and colour name, as one undo step. kNotFound when `control` is not a
// live `control` node; kInvalidArgument naming an unknown shape or colour or
// a bad size (nothing is changed then). Fails, rolled back, when one of the
// three attributes is fed by a connection.
Status apply_control_shape(graph::Graph& graph, graph::NodeId control, std::string_view shape, double size,
                           std::string_view color);

}  // namespace rigel::scene
