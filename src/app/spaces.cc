// The workspace's space tools (workspace.h): list, add, switch and bake.

#include <string>

#include "internal.h"
#include "rigel/app/workspace.h"

namespace rigel::app {

using internal::conflict;

rig::ControlSpaces Workspace::spaces(NodeId control) const { return rig::spaces_of(*scene_, control); }

Result<int> Workspace::add_space(NodeId control, const std::string& name, NodeId target) {
  Result<int> index = rig::add_space(*scene_, control, name, target);
  if (!index) return index.status().field().empty() ? conflict(index.status()) : index.status();
  bump_revision();
  return index;
}

Result<tools::SpaceSwitchReport> Workspace::switch_space(NodeId control, const tools::SpaceSwitchOptions& options) {
  if (!rig::spaces_of(*scene_, control).node.is_valid())
    return Status(ErrorCode::kInvalidArgument,
                  "control: " + graph().node(control)->name() + " has no spaces (add one first)")
        .with_field("control");
  const double at = options.frame.value_or(scene_->frame());
  if (Status s = internal::check_frames(*this, options.first.value_or(at), options.last.value_or(at)); !s) return s;
  Result<tools::SpaceSwitchReport> report = tools::switch_space(*scene_, control, options);
  if (!report) return report.status().field().empty() ? conflict(report.status()) : report.status();
  bump_revision();
  return report;
}

}  // namespace rigel::app
