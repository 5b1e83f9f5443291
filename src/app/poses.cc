// The workspace's pose library (workspace.h; tools/poses.h): library
// folders resolved as the workspace's other paths (confined to its root
// when it has one), rigs by name.

#include <string>

#include "internal.h"
#include "rigel/app/workspace.h"
#include "rigel/rig/meta.h"

namespace rigel::app {
namespace {

using internal::conflict;

}  // namespace

Result<tools::SavedPose> Workspace::save_pose(const std::string& library, const std::string& name,
                                              const std::string& rig, const std::vector<NodeId>& controls) {
  if (Status s = tools::check_pose_name(name); !s) return s;
  Result<fs::path> folder = resolve_path(library, "library");
  if (!folder) return folder.status();
  std::vector<NodeId> nodes = controls;
  if (nodes.empty() || !rig.empty()) {
    Result<NodeId> r = internal::rig_named(graph(), rig);
    if (!r) return r.status();
    for (NodeId c : nodes)
      if (rig::rig_of(graph(), c) != *r)
        return Status(ErrorCode::kInvalidArgument,
                      "controls: '" + graph().node(c)->name() + "' is not a control of rig '" + rig + "'")
            .with_field("controls");
    if (nodes.empty()) nodes.push_back(*r);
  }
  Result<tools::SavedPose> saved = tools::save_pose(graph(), nodes, name, *folder);
  if (!saved) return saved.status().field().empty() ? conflict(saved.status()) : saved.status();
  if (Status s = tools::save_pose_thumbnail(*scene_, *folder, name); !s) return s;
  return saved;
}

Result<tools::ApplyPoseReport> Workspace::apply_pose(const std::string& library, const std::string& name,
                                                     const std::string& rig, const tools::ApplyPoseOptions& options) {
  Result<fs::path> folder = resolve_path(library, "library");
  if (!folder) return folder.status();
  Result<tools::Pose> pose = tools::load_pose(*folder, name);
  if (!pose) return pose.status();
  Result<NodeId> target = internal::rig_named(graph(), rig, pose->rig);
  if (!target) return target.status();
  Result<tools::ApplyPoseReport> report = tools::apply_pose(graph(), *pose, *target, options);
  if (!report) return report.status().field().empty() ? conflict(report.status()) : report.status();
  if (!report->set.empty()) bump_revision();
  return report;
}

Result<std::vector<tools::PoseInfo>> Workspace::list_poses(const std::string& library) const {
  Result<fs::path> folder = resolve_path(library, "library");
  if (!folder) return folder.status();
  return tools::list_poses(*folder);
}

Result<std::string> Workspace::pose_thumbnail(const std::string& library, const std::string& name) const {
  Result<fs::path> folder = resolve_path(library, "library");
  if (!folder) return folder.status();
  return tools::load_pose_thumbnail(*folder, name);
}

Status Workspace::remove_pose(const std::string& library, const std::string& name) {
  Result<fs::path> folder = resolve_path(library, "library");
  if (!folder) return folder.status();
  return tools::remove_pose(*folder, name);
}

}  // namespace rigel::app
