// The pose library's thumbnails (poses.h): the scene's skeletons drawn
// from the front as SVG lines, written beside the pose files.

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

#include "rigel/io/scene_file.h"
#include "rigel/scene/transform_types.h"
#include "rigel/tools/poses.h"

namespace rigel::tools {

namespace fs = std::filesystem;
using graph::NodeId;

namespace {

constexpr double kWidth = 96, kHeight = 128, kMargin = 6;

std::string num(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f", v);
  return std::string(text) == "-0.0" ? "0.0" : text;
}

}  // namespace

std::string skeleton_thumbnail_svg(scene::Scene& scene) {
  graph::Graph& g = scene.graph();
  std::vector<NodeId> joints;
  for (NodeId id : scene.hierarchy())
    if (g.node(id)->type().name() == scene::kJointType) joints.push_back(id);
  std::vector<math::Vec3> at;
  double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
  for (NodeId j : joints) {
    const math::Vec3 p = scene.world_matrix(j).block<3, 1>(0, 3);
    at.push_back(p);
    if (!p.allFinite()) continue;
    x0 = std::min(x0, p.x()), x1 = std::max(x1, p.x()), y0 = std::min(y0, p.y()), y1 = std::max(y1, p.y());
  }
  std::ostringstream out;
  out << "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 96 128\" width=\"96\" height=\"128\">\n";
  if (!joints.empty() && x1 >= x0) {
    const double span = std::max({x1 - x0, y1 - y0, 1e-9});
    const double scale = std::min((kWidth - 2 * kMargin) / std::max(x1 - x0, span * 1e-3),
                                  (kHeight - 2 * kMargin) / std::max(y1 - y0, span * 1e-3));
    const double cx = (x0 + x1) / 2, cy = (y0 + y1) / 2;
    auto sx = [&](const math::Vec3& p) { return num(kWidth / 2 + (p.x() - cx) * scale); };
    auto sy = [&](const math::Vec3& p) { return num(kHeight / 2 - (p.y() - cy) * scale); };
    out << "<g stroke=\"#d7e0ec\" stroke-width=\"1.5\" stroke-linecap=\"round\" fill=\"none\">\n";
    for (std::size_t i = 0; i < joints.size(); ++i) {
      const NodeId parent = g.parent(joints[i]);
      const auto p = std::find(joints.begin(), joints.end(), parent);
      if (p == joints.end()) continue;
      const math::Vec3& a = at[static_cast<std::size_t>(p - joints.begin())];
      const math::Vec3& b = at[i];
      if (!a.allFinite() || !b.allFinite()) continue;
      out << "<line x1=\"" << sx(a) << "\" y1=\"" << sy(a) << "\" x2=\"" << sx(b) << "\" y2=\"" << sy(b) << "\"/>\n";
    }
    out << "</g>\n";
  }
  out << "</svg>\n";
  return out.str();
}

Result<fs::path> pose_thumbnail_path(const fs::path& library, const std::string& name) {
  if (Status s = check_pose_name(name); !s) return s;
  if (library.empty()) return Status(ErrorCode::kInvalidArgument, "no pose library given").with_field("library");
  return library / (name + kPoseThumbnailExtension);
}

Status save_pose_thumbnail(scene::Scene& scene, const fs::path& library, const std::string& name) {
  Result<fs::path> path = pose_thumbnail_path(library, name);
  if (!path) return path.status();
  std::error_code ec;
  if (fs::is_symlink(fs::symlink_status(*path, ec)))
    return Status(ErrorCode::kInvalidArgument, path->string() + ": a symbolic link (thumbnails are written in the library only)")
        .with_field("name");
  if (Status s = io::write_file_atomic(*path, skeleton_thumbnail_svg(scene)); !s) return Status(s).with_field("library");
  return Status::ok();
}

Result<std::string> load_pose_thumbnail(const fs::path& library, const std::string& name) {
  Result<fs::path> path = pose_thumbnail_path(library, name);
  if (!path) return path.status();
  std::error_code ec;
  const fs::file_status st = fs::symlink_status(*path, ec);
  if (ec || !fs::is_regular_file(st))
    return Status(ErrorCode::kNotFound, "no thumbnail of pose '" + name + "' in the library " + library.string())
        .with_field("name");
  std::ifstream in(*path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in && !in.eof()) return Status(ErrorCode::kIoError, path->string() + ": cannot be read").with_field("name");
  return text.str();
}

}  // namespace rigel::tools
