// The workspace's data managers (workspace.h): skin weights, control
// shapes, blend shapes, driven poses and correctives exported to files and
// imported back (tools/skin_weights.h, tools/shape_data.h,
// tools/blendshape_data.h, tools/driven_poses.h), the files confined to the
// root when there is one; and set-driven keys.

#include <fstream>
#include <sstream>
#include <string>

#include "internal.h"
#include "rigel/app/workspace.h"
#include "rigel/io/scene_file.h"
#include "rigel/rig/meta.h"

namespace rigel::app {

using internal::conflict;

namespace {

Result<std::string> read_text(const fs::path& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return Status(ErrorCode::kNotFound, "file: " + path.string() + ": no such file").with_field("file");
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in && !in.eof()) return Status(ErrorCode::kIoError, "file: " + path.string() + ": cannot be read").with_field("file");
  return text.str();
}

Status write_text(const fs::path& path, const std::string& text) {
  if (Status s = internal::make_parent(path, "file"); !s) return s;
  return internal::saved(io::write_file_atomic(path, text), "file");
}

}  // namespace

Result<fs::path> Workspace::export_skin_weights(const std::string& file, tools::WeightsFormat format) {
  Result<fs::path> path = resolve_path(file, "file");
  if (!path) return path.status();
  auto skins = tools::capture_skin_weights(*scene_);
  if (!skins) return conflict(skins.status());
  if (Status s = internal::make_parent(*path, "file"); !s) return s;
  if (Status s = internal::saved(tools::write_skin_weights(*path, *skins, format), "file"); !s) return s;
  return path;
}

Result<tools::WeightsReport> Workspace::import_skin_weights(const std::string& file, const tools::WeightsImport& options) {
  Result<fs::path> path = resolve_path(file, "file");
  if (!path) return path.status();
  Result<std::string> text = read_text(*path);
  if (!text) return text.status();
  auto skins = tools::skin_weights_from_json(*text, path->string(), tools::side_files_beside(*path));
  if (!skins) return Status(skins.status()).with_field("file");
  auto report = tools::apply_skin_weights(*scene_, *skins, options);
  if (!report) return report.status().field().empty() ? conflict(report.status()) : report.status();
  bump_revision();
  return report;
}

Result<fs::path> Workspace::export_control_shapes(const std::string& rig, const std::string& file) {
  Result<fs::path> path = resolve_path(file, "file");
  if (!path) return path.status();
  Result<NodeId> r = internal::rig_named(graph(), rig);
  if (!r) return r.status();
  auto shapes = tools::capture_control_shapes(graph(), *r);
  if (!shapes) return shapes.status();
  if (Status s = write_text(*path, tools::control_shapes_to_json(*shapes)); !s) return s;
  return path;
}

Result<tools::ShapesReport> Workspace::import_control_shapes(const std::string& rig, const std::string& file) {
  Result<fs::path> path = resolve_path(file, "file");
  if (!path) return path.status();
  Result<std::string> text = read_text(*path);
  if (!text) return text.status();
  auto shapes = tools::control_shapes_from_json(*text, path->string());
  if (!shapes) return Status(shapes.status()).with_field("file");
  Result<NodeId> r = internal::rig_named(graph(), rig.empty() ? shapes->rig : rig);
  if (!r) return r.status();
  auto report = tools::apply_control_shapes(graph(), *r, *shapes);
  if (!report) return report.status().field().empty() ? conflict(report.status()) : report.status();
  bump_revision();
  return report;
}

Result<fs::path> Workspace::export_blend_shapes(const std::string& file) {
  Result<fs::path> path = resolve_path(file, "file");
  if (!path) return path.status();
  auto sets = tools::capture_blend_shapes(graph());
  if (!sets) return conflict(sets.status());
  if (Status s = write_text(*path, tools::blend_shapes_to_json(*sets)); !s) return s;
  return path;
}

Result<tools::BlendShapesReport> Workspace::import_blend_shapes(const std::string& file) {
  Result<fs::path> path = resolve_path(file, "file");
  if (!path) return path.status();
  Result<std::string> text = read_text(*path);
  if (!text) return text.status();
  auto sets = tools::blend_shapes_from_json(*text, path->string());
  if (!sets) return Status(sets.status()).with_field("file");
  auto report = tools::apply_blend_shapes(graph(), *sets);
  if (!report) return report.status().field().empty() ? conflict(report.status()) : report.status();
  bump_revision();
  return report;
}

Result<fs::path> Workspace::export_driven_poses(tools::DrivenData kind, const std::string& file) {
  Result<fs::path> path = resolve_path(file, "file");
  if (!path) return path.status();
  auto poses = tools::capture_driven_poses(graph(), kind);
  if (!poses) return poses.status();
  if (Status s = write_text(*path, tools::driven_poses_to_json(*poses)); !s) return s;
  return path;
}

Result<tools::DrivenPosesReport> Workspace::import_driven_poses(tools::DrivenData kind, const std::string& file) {
  Result<fs::path> path = resolve_path(file, "file");
  if (!path) return path.status();
  Result<std::string> text = read_text(*path);
  if (!text) return text.status();
  auto poses = tools::driven_poses_from_json(*text, path->string(), kind);
  if (!poses) return Status(poses.status()).with_field("file");
  auto report = tools::apply_driven_poses(graph(), *poses);
  if (!report) return conflict(report.status());
  bump_revision();
  return report;
}

Result<tools::DrivenPoseSet> Workspace::driven_poses(tools::DrivenData kind) { return tools::capture_driven_poses(graph(), kind); }

namespace {
// "driver ..." or "driven channel ...": the request's field the error is about.
Status driven_key_error(const Status& s) {
  if (s.message().rfind("driver", 0) == 0) return Status(s).with_field("driver");
  if (s.message().rfind("driven channel", 0) == 0 || s.message().rfind("set driven key", 0) == 0)
    return Status(s).with_field("driven");
  return s;
}
}  // namespace

Result<tools::DrivenKeyReport> Workspace::set_driven_key(const tools::DrivenKeyRequest& request) {
  auto report = tools::set_driven_key(graph(), request);
  if (!report) return driven_key_error(report.status());
  bump_revision();
  return report;
}

Result<NodeId> Workspace::create_pose_reader(NodeId joint, const math::Vec3& axis) {
  auto reader = tools::create_pose_reader(graph(), joint, axis);
  if (!reader) return reader.status();
  bump_revision();
  return reader;
}

Status Workspace::remove_driven_keys(const std::vector<std::string>& driven) {
  if (Status s = tools::remove_driven_keys(graph(), driven); !s) return driven_key_error(s);
  bump_revision();
  return Status::ok();
}

}  // namespace rigel::app
