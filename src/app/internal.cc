#include "internal.h"

#include <fstream>
#include <sstream>

#include "rigel/rig/meta.h"
#include "rigel/rig/version.h"

namespace rigel::app::internal {

namespace fs = std::filesystem;

Status conflict(const Status& s, const std::string& field) {
  if (s) return s;
  const ErrorCode code = s.code() == ErrorCode::kNotFound || s.code() == ErrorCode::kParseError ||
                                 s.code() == ErrorCode::kIoError
                             ? s.code()
                             : ErrorCode::kFailedPrecondition;
  return Status(code, s.message()).with_field(field.empty() ? s.field() : field);
}

std::string version_to_save(const fs::path& path, const std::string& version,
                            const std::function<std::optional<std::string>()>& version_of,
                            const std::function<std::string(const std::string&)>& text_at) {
  std::error_code ec;
  if (!fs::exists(path, ec)) return version;
  const std::optional<std::string> old = version_of();
  const std::string old_version = old ? *old : version;
  if (rig::compare_versions(version, old_version) > 0) return version;
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return !old || text.str() != text_at(old_version) ? rig::next_version(old_version) : old_version;
}

Status make_parent(const fs::path& file, const std::string& field) {
  std::error_code ec;
  const fs::file_status st = fs::status(file, ec);
  if (fs::exists(st) && !fs::is_regular_file(st)) {
    return Status(ErrorCode::kInvalidArgument,
                  field + ": '" + file.string() + "' is " + (fs::is_directory(st) ? "a folder" : "not a file"))
        .with_field(field);
  }
  if (file.has_parent_path()) {
    fs::create_directories(file.parent_path(), ec);
    if (ec) {
      return Status(ErrorCode::kFailedPrecondition,
                    field + ": cannot make " + file.parent_path().string() + ": " + ec.message())
          .with_field(field);
    }
  }
  return Status::ok();
}

Status saved(const Status& s, const std::string& field) {
  if (s) return s;
  const bool keep = s.code() == ErrorCode::kNotFound || s.code() == ErrorCode::kParseError;
  return Status(keep ? s.code() : ErrorCode::kFailedPrecondition, s.message()).with_field(field);
}

// The rig a pose call names: `name`, or the scene's only rig when empty.
Result<graph::NodeId> rig_named(const graph::Graph& g, const std::string& name, const std::string& fallback) {
  if (!name.empty()) {
    const graph::NodeId r = rig::find_rig(g, name);
    if (!r.is_valid()) return Status(ErrorCode::kNotFound, "rig: no built rig '" + name + "' in the scene").with_field("rig");
    return r;
  }
  if (!fallback.empty())
    if (const graph::NodeId r = rig::find_rig(g, fallback); r.is_valid()) return r;
  const std::vector<graph::NodeId> rigs = rig::list_rigs(g);
  if (rigs.size() == 1) return rigs[0];
  return Status(ErrorCode::kInvalidArgument, rigs.empty() ? std::string("rig: the scene holds no built rig")
                                                          : "rig: the scene holds " + std::to_string(rigs.size()) +
                                                                " rigs; name one")
      .with_field("rig");
}

}  // namespace rigel::app::internal
