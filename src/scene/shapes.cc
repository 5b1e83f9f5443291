#include "rigel/scene/shapes.h"

#include <array>
#include <cmath>
#include <string>
#include <utility>

#include "rigel/scene/transform_types.h"

namespace rigel::scene {
namespace {

using math::Vec3;

constexpr int kCircleSegments = 24;

// A point of the XZ plane (flat shapes), given as (x, z).
Vec3 flat(double x, double z) { return Vec3(x, 0.0, z); }

// Unit circle point at `step` of kCircleSegments: cos and sin of the angle
// (exact at the quarters, so the strips joining circles meet exactly).
std::pair<double, double> circle_point(int step) {
  switch (((step % kCircleSegments) + kCircleSegments) % kCircleSegments) {
    case 0: return {1.0, 0.0};
    case kCircleSegments / 4: return {0.0, 1.0};
    case kCircleSegments / 2: return {-1.0, 0.0};
    case 3 * kCircleSegments / 4: return {0.0, -1.0};
    default: break;
  }
  const double angle = 2.0 * math::kPi * step / kCircleSegments;
  return {std::cos(angle), std::sin(angle)};
}

ControlShape circle() {
  ControlShape s;
  for (int i = 0; i < kCircleSegments; ++i) {
    auto [c, n] = circle_point(i);
    s.points.push_back(flat(c, n));
  }
  return s;
}

ControlShape square() {
  return {{flat(1, 1), flat(1, -1), flat(-1, -1), flat(-1, 1)}, true};
}

ControlShape cube() {
  // Bottom loop, up one edge, top loop, then the three remaining vertical
  // edges, retracing a top or bottom edge between them.
  return {{Vec3(-1, -1, -1), Vec3(1, -1, -1), Vec3(1, -1, 1), Vec3(-1, -1, 1), Vec3(-1, -1, -1),  //
           Vec3(-1, 1, -1), Vec3(1, 1, -1), Vec3(1, 1, 1), Vec3(-1, 1, 1), Vec3(-1, 1, -1),       //
           Vec3(1, 1, -1), Vec3(1, -1, -1), Vec3(1, -1, 1), Vec3(1, 1, 1), Vec3(-1, 1, 1),        //
           Vec3(-1, -1, 1)},
          false};
}

ControlShape sphere() {
  ControlShape s{{}, false};
  // XZ circle from +X back to +X.
  for (int i = 0; i <= kCircleSegments; ++i) {
    auto [c, n] = circle_point(i);
    s.points.push_back(Vec3(c, 0, n));
  }
  // XY circle from +X around and on a quarter again to +Y (retraced).
  for (int i = 1; i <= kCircleSegments + kCircleSegments / 4; ++i) {
    auto [c, n] = circle_point(i);
    s.points.push_back(Vec3(c, n, 0));
  }
  // YZ circle from +Y back to +Y.
  for (int i = 1; i <= kCircleSegments; ++i) {
    auto [c, n] = circle_point(i);
    s.points.push_back(Vec3(0, c, n));  // step 0 is +Y
  }
  return s;
}

ControlShape diamond() { return {{flat(1, 0), flat(0, 1), flat(-1, 0), flat(0, -1)}, true}; }

ControlShape cross() {
  constexpr double t = 0.25;  // half the arm width
  return {{flat(t, 1), flat(t, t), flat(1, t), flat(1, -t), flat(t, -t), flat(t, -1), flat(-t, -1), flat(-t, -t),
           flat(-1, -t), flat(-1, t), flat(-t, t), flat(-t, 1)},
          true};
}

ControlShape arrow() {
  return {{flat(-0.3, -1), flat(0.3, -1), flat(0.3, 0), flat(0.7, 0), flat(0, 1), flat(-0.7, 0), flat(-0.3, 0)}, true};
}

ControlShape double_arrow() {
  return {{flat(0, 1), flat(0.6, 0.4), flat(0.25, 0.4), flat(0.25, -0.4), flat(0.6, -0.4), flat(0, -1),
           flat(-0.6, -0.4), flat(-0.25, -0.4), flat(-0.25, 0.4), flat(-0.6, 0.4)},
          true};
}

// Quarter turn in the XZ plane taking +Z to -X: (x, z) -> (-z, x).
std::pair<double, double> quarter_turn(std::pair<double, double> p) { return {-p.second, p.first}; }

ControlShape four_arrow() {
  constexpr double w = 0.15;  // half the shaft width
  constexpr double a = 0.6;   // where the head starts
  constexpr double h = 0.35;  // half the head width
  // The +Z arm from its right shaft corner to the inner corner that starts
  // the next arm; the other arms are quarter turns of it.
  std::array<std::pair<double, double>, 6> arm = {{{w, a}, {h, a}, {0, 1}, {-h, a}, {-w, a}, {-w, w}}};
  ControlShape s;
  for (int k = 0; k < 4; ++k) {
    for (auto& p : arm) {
      s.points.push_back(flat(p.first, p.second));
      p = quarter_turn(p);
    }
  }
  return s;
}

ControlShape four_arrow_circle() {
  constexpr double r = 0.6;   // circle radius
  constexpr double w = 0.1;   // half the shaft width
  constexpr double a = 0.8;   // where the head starts
  constexpr double h = 0.25;  // half the head width
  constexpr int kArcSegments = 5;
  const double delta = std::asin(w / r);  // half the angle the shaft cuts out of the circle
  const double c = r * std::cos(delta);
  // Exact axis directions (no cos(pi/2) residue): d outward, p along the circle.
  constexpr std::array<std::pair<double, double>, 4> kAxes = {{{1, 0}, {0, 1}, {-1, 0}, {0, -1}}};
  ControlShape s;
  for (int k = 0; k < 4; ++k) {
    const double phi = k * math::kPi / 2.0;
    const auto [dx, dz] = kAxes[k];
    const double px = -dz, pz = dx;
    auto at = [&](double along, double across) { return flat(along * dx + across * px, along * dz + across * pz); };
    s.points.push_back(at(c, -w));
    s.points.push_back(at(a, -w));
    s.points.push_back(at(a, -h));
    s.points.push_back(at(1, 0));
    s.points.push_back(at(a, h));
    s.points.push_back(at(a, w));
    s.points.push_back(at(c, w));
    // Arc to the next arrow (its first point closes the arc).
    const double from = phi + delta;
    const double to = phi + math::kPi / 2.0 - delta;
    for (int i = 1; i < kArcSegments; ++i) {
      const double angle = from + (to - from) * i / kArcSegments;
      s.points.push_back(flat(r * std::cos(angle), r * std::sin(angle)));
    }
  }
  return s;
}

ControlShape locator() {
  return {{Vec3(1, 0, 0), Vec3(-1, 0, 0), Vec3(0, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0), Vec3(0, 0, 0), Vec3(0, 0, 1),
           Vec3(0, 0, -1)},
          false};
}

ControlShape pin() {
  constexpr double radius = 0.25;
  constexpr double centre = 0.75;
  ControlShape s{{Vec3(0, 0, 0)}, false};
  // Circle in XY from its bottom (where the stick ends) around and back.
  for (int i = 0; i <= kCircleSegments; ++i) {
    auto [c, n] = circle_point(i - kCircleSegments / 4);  // step -quarter: (0, -1)
    s.points.push_back(Vec3(radius * c, centre + radius * n, 0));
  }
  return s;
}

ControlShape triangle() {
  const double x = std::sqrt(3.0) / 2.0;
  return {{flat(0, 1), flat(-x, -0.5), flat(x, -0.5)}, true};
}

struct ShapeEntry {
  const char* name;
  ControlShape (*build)();
};

constexpr std::array<ShapeEntry, 13> kShapes = {{
    {"circle", circle},
    {"square", square},
    {"cube", cube},
    {"sphere", sphere},
    {"diamond", diamond},
    {"cross", cross},
    {"arrow", arrow},
    {"doubleArrow", double_arrow},
    {"fourArrow", four_arrow},
    {"fourArrowCircle", four_arrow_circle},
    {"locator", locator},
    {"pin", pin},
    {"triangle", triangle},
}};

struct ColorEntry {
  const char* name;
  double r, g, b;
};

constexpr std::array<ColorEntry, 18> kColors = {{
    {"yellow", 1.0, 1.0, 0.0},
    {"red", 1.0, 0.0, 0.0},
    {"blue", 0.0, 0.0, 1.0},
    {"green", 0.0, 1.0, 0.0},
    {"cyan", 0.0, 1.0, 1.0},
    {"magenta", 1.0, 0.0, 1.0},
    {"orange", 1.0, 0.4, 0.0},
    {"purple", 0.45, 0.0, 0.9},
    {"pink", 1.0, 0.45, 0.65},
    {"white", 1.0, 1.0, 1.0},
    {"black", 0.0, 0.0, 0.0},
    {"grey", 0.5, 0.5, 0.5},
    {"lightBlue", 0.4, 0.7, 1.0},
    {"darkBlue", 0.0, 0.0, 0.5},
    {"lightGreen", 0.5, 1.0, 0.5},
    {"darkGreen", 0.0, 0.4, 0.0},
    {"darkRed", 0.5, 0.0, 0.0},
    {"brown", 0.4, 0.2, 0.05},
}};

int hex_digit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

}  // namespace

std::vector<std::string> control_shape_names() {
  std::vector<std::string> names;
  for (const ShapeEntry& e : kShapes) names.emplace_back(e.name);
  return names;
}

std::optional<ControlShape> control_shape(std::string_view name, double size) {
  if (!std::isfinite(size) || size <= 0.0) return std::nullopt;
  for (const ShapeEntry& e : kShapes) {
    if (name != e.name) continue;
    ControlShape shape = e.build();
    for (Vec3& p : shape.points) p *= size;
    return shape;
  }
  return std::nullopt;
}

std::vector<std::string> color_names() {
  std::vector<std::string> names;
  for (const ColorEntry& e : kColors) names.emplace_back(e.name);
  return names;
}

std::optional<math::Vec3> color_from_name(std::string_view name) {
  if (!name.empty() && name[0] == '#') {
    if (name.size() != 7) return std::nullopt;
    double rgb[3];
    for (int i = 0; i < 3; ++i) {
      const int hi = hex_digit(name[1 + 2 * i]);
      const int lo = hex_digit(name[2 + 2 * i]);
      if (hi < 0 || lo < 0) return std::nullopt;
      rgb[i] = (hi * 16 + lo) / 255.0;
    }
    return Vec3(rgb[0], rgb[1], rgb[2]);
  }
  for (const ColorEntry& e : kColors) {
    if (name == e.name) return Vec3(e.r, e.g, e.b);
  }
  return std::nullopt;
}

Status apply_control_shape(graph::Graph& graph, graph::NodeId control, std::string_view shape, double size,
                           std::string_view color) {
  const graph::Node* node = graph.node(control);
  if (node == nullptr) return error(ErrorCode::kNotFound, "apply_control_shape: no such node");
  if (node->type().name() != kControlType) {
    return error(ErrorCode::kNotFound,
                 "apply_control_shape: " + node->name() + " is a " + node->type().name() + ", not a control");
  }
  const std::string name = node->name();
  const std::string where = "apply_control_shape: " + name + ": ";
  if (!std::isfinite(size) || size <= 0.0) {
    return error(ErrorCode::kInvalidArgument, where + "size must be finite and positive, got " + std::to_string(size));
  }
  std::optional<ControlShape> points = control_shape(shape, size);
  if (!points) return error(ErrorCode::kInvalidArgument, where + "unknown shape '" + std::string(shape) + "'");
  std::optional<Vec3> rgb = color_from_name(color);
  if (!rgb) return error(ErrorCode::kInvalidArgument, where + "unknown colour '" + std::string(color) + "'");

  graph::Transaction transaction(graph, "apply control shape " + name);
  auto set = [&](graph::AttrIndex attr, graph::Value value) {
    return graph.set_value(graph::Plug{control, attr}, std::move(value));
  };
  Status status = set(control_attr::kShapePoints, std::move(points->points));
  if (status) status = set(control_attr::kShapeClosed, points->closed);
  if (status) status = set(control_attr::kShapeColor, *rgb);
  if (!status) {
    transaction.rollback();
    return status.with_context("apply_control_shape: " + name);
  }
  return Status::ok();
}

}  // namespace rigel::scene
