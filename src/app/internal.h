#pragma once
// What the workspace's source files share (private to src/app).

#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include <vector>

#include "rigel/base/status.h"
#include "rigel/graph/graph.h"

namespace rigel::app::internal {

// A library refusal of a well-formed call: the scene cannot do it in its
// state (kFailedPrecondition); not-found, parse and I/O errors keep their
// codes. `field` (when given) names the input it concerns.
Status conflict(const Status& s, const std::string& field = {});

// Makes the folder a file is about to be saved in; a folder (or anything
// else that is not a file) where the file goes is the caller's fault.
Status make_parent(const std::filesystem::path& file, const std::string& field);

// A save that failed: where the caller said to write cannot take it
// (kFailedPrecondition naming `field`).
Status saved(const Status& s, const std::string& field);

// The version a file saved at `path` takes (definitions and graphs):
// `version` when it is newer than the file's (`version_of` the file there;
// nullopt when none can be read), else the file's own when `text_at(its
// version)` is the file's bytes (nothing changed), else the next one.
std::string version_to_save(const std::filesystem::path& path, const std::string& version,
                            const std::function<std::optional<std::string>()>& version_of,
                            const std::function<std::string(const std::string&)>& text_at);

// The built rig a call names (errors name "rig"): `name`, else the rig
// named `fallback` when there is one, else the scene's only rig (poses.cc,
// data.cc).
Result<graph::NodeId> rig_named(const graph::Graph& g, const std::string& name, const std::string& fallback = {});

}  // namespace rigel::app::internal

namespace rigel::app {
class Workspace;
namespace internal {
// The range an animator tool works over, checked (errors name "frames"):
// finite, first <= last, within kMaxFrame and within the clip when there
// is one (animate.cc).
Status check_frames(const Workspace& ws, double first, double last);
// The nodes whose keyable channels a channel box shows for `control`: the
// control, and for a built rig's control its component's nodes that hold
// keyable channels and are not transforms (the limb's fkIk switch, a
// foot's roll) (transfer.cc).
std::vector<graph::NodeId> channel_holders(const graph::Graph& g, graph::NodeId control);
}  // namespace internal
}  // namespace rigel::app
