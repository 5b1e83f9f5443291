// The pose library's files (poses.h): LIBRARY/NAME.pose.json as diffable
// JSON, read back with every error naming the file and the place.

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <system_error>

#include <nlohmann/json.hpp>

#include "rigel/io/diffable_json.h"
#include "rigel/io/json_depth.h"
#include "rigel/io/scene_file.h"
#include "rigel/tools/poses.h"

namespace rigel::tools {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;
using math::Quat;
using math::Vec3;

constexpr const char* kFormat = "rigel pose";
constexpr int kVersion = 1;
constexpr std::size_t kMaxDepth = 16;
constexpr std::uintmax_t kMaxBytes = 64u << 20;

Json value_json(const graph::Value& v) {
  if (const auto* q = std::get_if<Quat>(&v)) return Json::array({q->x(), q->y(), q->z(), q->w()});
  if (const auto* x = std::get_if<Vec3>(&v)) return Json::array({x->x(), x->y(), x->z()});
  // A scalar may be infinite (a solver's maxStretch: no limit); JSON has no
  // infinity, so it is written as a string, as scene files write it.
  const double d = std::get<double>(v);
  if (std::isinf(d)) return Json(d > 0 ? "inf" : "-inf");
  return Json(d);
}

// Reading: each refusal names the file and the member's path.
struct Reader {
  const std::string& source;
  Status bad(const std::string& where, const std::string& what) const {
    return Status(ErrorCode::kParseError, source + ": " + where + ": " + what).with_field("name");
  }
  Result<std::string> text(const Json& j, const char* key, const std::string& where) const {
    auto it = j.find(key);
    if (it == j.end() || !it->is_string()) return bad(where + "." + key, "expected a string");
    return it->get<std::string>();
  }
  Result<double> number(const Json& j, const std::string& where) const {
    if (!j.is_number()) return bad(where, std::string("expected a number, got ") + j.type_name());
    const double v = j.get<double>();
    if (!std::isfinite(v)) return bad(where, "not a finite number");
    return v;
  }
  Result<graph::Value> channel(const std::string& attr, const Json& j, const std::string& where) const {
    if (j.is_string() && (j == "inf" || j == "-inf"))
      return graph::Value(j == "inf" ? std::numeric_limits<double>::infinity() : -std::numeric_limits<double>::infinity());
    if (!j.is_array()) {
      Result<double> v = number(j, where);
      if (!v) return v.status();
      return graph::Value(*v);
    }
    const std::size_t n = attr == "rotation" ? 4 : 3;
    if (j.size() != n) return bad(where, "expected " + std::to_string(n) + " numbers");
    double v[4] = {0, 0, 0, 0};
    for (std::size_t i = 0; i < n; ++i) {
      Result<double> x = number(j[i], where + "[" + std::to_string(i) + "]");
      if (!x) return x.status();
      v[i] = *x;
    }
    if (n == 3) return graph::Value(Vec3(v[0], v[1], v[2]));
    const Quat q(v[3], v[0], v[1], v[2]);
    if (q.norm() < 1e-9) return bad(where, "not a rotation (zero length)");
    // A unit quaternion as written stays bit for bit (read and written back:
    // the same text); one typed by hand is normalised.
    return graph::Value(std::abs(q.norm() - 1) < 1e-12 ? q : q.normalized());
  }
  Result<PoseEntry> entry(const Json& j, const std::string& where) const {
    if (!j.is_object()) return bad(where, "expected an object");
    PoseEntry e;
    for (auto [key, out] : {std::pair{"rigId", &e.rig_id}, {"role", &e.role}}) {
      Result<std::string> s = text(j, key, where);
      if (!s) return s.status();
      if (s->empty()) return bad(where + "." + key, "empty");
      *out = *s;
    }
    for (auto [key, out] : {std::pair{"component", &e.component}, {"side", &e.side}, {"type", &e.type}, {"node", &e.node}})
      if (auto it = j.find(key); it != j.end() && it->is_string()) *out = it->get<std::string>();
    auto index = j.find("index");
    if (index == j.end() || !index->is_number_integer() || index->get<std::int64_t>() < 0 ||
        index->get<std::int64_t>() > 1000000)
      return bad(where + ".index", "expected a whole number from 0");
    e.index = static_cast<int>(index->get<std::int64_t>());
    auto channels = j.find("channels");
    if (channels == j.end() || !channels->is_object() || channels->empty())
      return bad(where + ".channels", "expected an object of channel values");
    for (const auto& [attr, value] : channels->items()) {
      Result<graph::Value> v = channel(attr, value, where + ".channels." + attr);
      if (!v) return v.status();
      e.channels.push_back({attr, std::move(*v)});
    }
    return e;
  }
};

bool safe_char(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' || c == '.';
}

// The pose file at `path` when it is a plain file (not a link out of the
// library): kNotFound naming "name" when there is none.
Status check_file(const fs::path& path, const std::string& name) {
  std::error_code ec;
  const fs::file_status st = fs::symlink_status(path, ec);
  if (ec || !fs::exists(st))
    return Status(ErrorCode::kNotFound, "no pose '" + name + "' in the library " + path.parent_path().string())
        .with_field("name");
  if (fs::is_symlink(st))
    return Status(ErrorCode::kInvalidArgument, path.string() + ": a symbolic link (pose files are read in the library only)")
        .with_field("name");
  if (!fs::is_regular_file(st))
    return Status(ErrorCode::kInvalidArgument, path.string() + ": not a file").with_field("name");
  return Status::ok();
}

Result<Pose> read_file(const fs::path& path) {
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) return Status(ErrorCode::kIoError, path.string() + ": " + ec.message()).with_field("name");
  if (size > kMaxBytes) return Status(ErrorCode::kParseError, path.string() + ": over 64 MiB, not a pose").with_field("name");
  std::ifstream in(path, std::ios::binary);
  std::stringstream buffer;
  buffer << in.rdbuf();
  if (!in) return Status(ErrorCode::kIoError, path.string() + ": cannot be read").with_field("name");
  return pose_from_json(buffer.str(), path.string());
}

}  // namespace

std::string pose_to_json(const Pose& pose) {
  Json entries = Json::array();
  for (const PoseEntry& e : pose.entries) {
    Json channels = Json::object();
    for (const PoseChannel& c : e.channels) channels[c.attr] = value_json(c.value);
    entries.push_back(Json{{"rigId", e.rig_id},   {"role", e.role}, {"index", e.index}, {"component", e.component},
                           {"side", e.side},      {"type", e.type}, {"node", e.node},   {"channels", std::move(channels)}});
  }
  const Json doc{{"format", kFormat}, {"version", kVersion}, {"name", pose.name}, {"rig", pose.rig},
                 {"entries", std::move(entries)}};
  return io::diffable_json(doc);
}

Result<Pose> pose_from_json(std::string_view text, const std::string& source) {
  if (const std::size_t deep = io::json_too_deep(text, kMaxDepth); deep != std::string_view::npos)
    return Status(ErrorCode::kParseError, source + ":" + io::line_column(text, deep) + ": nested too deeply for a pose")
        .with_field("name");
  Json doc;
  try {
    doc = Json::parse(text);
  } catch (const Json::parse_error& e) {
    std::string what = e.what();
    if (const std::size_t colon = what.find(": "); colon != std::string::npos) what = what.substr(colon + 2);
    return Status(ErrorCode::kParseError, source + ":" + io::line_column(text, e.byte == 0 ? 0 : e.byte - 1) + ": " + what)
        .with_field("name");
  } catch (const Json::exception& e) {
    return Status(ErrorCode::kParseError, source + ": " + e.what()).with_field("name");
  }
  const Reader r{source};
  if (!doc.is_object()) return r.bad("the document", "expected an object");
  Result<std::string> format = r.text(doc, "format", "the document");
  if (!format) return format.status();
  if (*format != kFormat) return r.bad("format", "'" + *format + "' is not a rigel pose");
  auto version = doc.find("version");
  if (version == doc.end() || !version->is_number_integer())
    return r.bad("version", "expected a whole number");
  if (version->get<std::int64_t>() > kVersion)
    return r.bad("version", "version " + std::to_string(version->get<std::int64_t>()) +
                                " is newer than this rigel reads (" + std::to_string(kVersion) + ")");
  Pose pose;
  for (auto [key, out] : {std::pair{"name", &pose.name}, {"rig", &pose.rig}}) {
    Result<std::string> s = r.text(doc, key, "the document");
    if (!s) return s.status();
    *out = *s;
  }
  const auto entries = doc.find("entries");
  if (entries == doc.end() || !entries->is_array()) return r.bad("entries", "expected an array");
  for (std::size_t i = 0; i < entries->size(); ++i) {
    Result<PoseEntry> e = r.entry((*entries)[i], "entries[" + std::to_string(i) + "]");
    if (!e) return e.status();
    pose.entries.push_back(std::move(*e));
  }
  return pose;
}

Status check_pose_name(const std::string& name) {
  auto refuse = [&](const std::string& why) {
    return Status(ErrorCode::kInvalidArgument, "pose name '" + name + "': " + why).with_field("name");
  };
  if (name.empty()) return refuse("empty");
  if (name.size() > 128) return refuse("longer than 128 characters");
  if (name[0] == '.') return refuse("starts with '.'");
  for (char c : name)
    if (!safe_char(c))
      return refuse(c == '/' || c == '\\' ? "a path separator (a pose is named within its library)"
                                          : "only letters, digits, '_', '-' and '.' may name a pose");
  return Status::ok();
}

Result<fs::path> pose_path(const fs::path& library, const std::string& name) {
  if (Status s = check_pose_name(name); !s) return s;
  if (library.empty()) return Status(ErrorCode::kInvalidArgument, "no pose library given").with_field("library");
  return library / (name + kPoseExtension);
}

Result<SavedPose> save_pose(graph::Graph& graph, const std::vector<graph::NodeId>& nodes, const std::string& name,
                            const fs::path& library) {
  Result<fs::path> path = pose_path(library, name);
  if (!path) return path.status();
  Result<Pose> pose = capture_pose(graph, nodes, name);
  if (!pose) return pose.status();
  std::error_code ec;
  fs::create_directories(library, ec);
  if (ec || !fs::is_directory(library))
    return Status(ErrorCode::kIoError, "pose library " + library.string() + ": " +
                                           (ec ? ec.message() : std::string("not a folder")))
        .with_field("library");
  if (fs::is_symlink(fs::symlink_status(*path, ec)))
    return Status(ErrorCode::kInvalidArgument, path->string() + ": a symbolic link (pose files are written in the library only)")
        .with_field("name");
  if (Status s = io::write_file_atomic(*path, pose_to_json(*pose)); !s) return Status(s).with_field("library");
  return SavedPose{*path, pose->entries.size()};
}

Result<Pose> load_pose(const fs::path& library, const std::string& name) {
  Result<fs::path> path = pose_path(library, name);
  if (!path) return path.status();
  if (Status s = check_file(*path, name); !s) return s;
  return read_file(*path);
}

Result<std::vector<PoseInfo>> list_poses(const fs::path& library) {
  std::error_code ec;
  if (!fs::is_directory(library, ec))
    return Status(ErrorCode::kNotFound, "no pose library " + library.string()).with_field("library");
  std::vector<PoseInfo> out;
  const std::string ext = kPoseExtension;
  for (fs::directory_iterator it(library, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string file = it->path().filename().string();
    if (file.size() <= ext.size() || file.compare(file.size() - ext.size(), ext.size(), ext) != 0) continue;
    PoseInfo info;
    info.name = file.substr(0, file.size() - ext.size());
    if (!check_pose_name(info.name)) continue;
    if (Status s = check_file(it->path(), info.name); !s) {
      info.error = s.message();
    } else if (Result<Pose> pose = read_file(it->path()); !pose) {
      info.error = pose.status().message();
    } else {
      info.rig = pose->rig;
      info.entries = pose->entries.size();
    }
    info.thumbnail = fs::is_regular_file(library / (info.name + kPoseThumbnailExtension), ec);
    ec.clear();
    out.push_back(std::move(info));
  }
  if (ec) return Status(ErrorCode::kIoError, "pose library " + library.string() + ": " + ec.message()).with_field("library");
  std::sort(out.begin(), out.end(), [](const PoseInfo& a, const PoseInfo& b) { return a.name < b.name; });
  return out;
}

Status remove_pose(const fs::path& library, const std::string& name) {
  Result<fs::path> path = pose_path(library, name);
  if (!path) return path.status();
  std::error_code ec;
  const fs::file_status st = fs::symlink_status(*path, ec);
  if (ec || !fs::exists(st))
    return Status(ErrorCode::kNotFound, "no pose '" + name + "' in the library " + library.string()).with_field("name");
  if (!fs::is_regular_file(st) && !fs::is_symlink(st))
    return Status(ErrorCode::kInvalidArgument, path->string() + ": not a file").with_field("name");
  if (!fs::remove(*path, ec) || ec)
    return Status(ErrorCode::kIoError, path->string() + ": " + (ec ? ec.message() : std::string("not removed")))
        .with_field("name");
  const fs::path thumbnail = library / (name + kPoseThumbnailExtension);
  if (fs::is_regular_file(fs::symlink_status(thumbnail, ec)) && (!fs::remove(thumbnail, ec) || ec))
    return Status(ErrorCode::kIoError, thumbnail.string() + ": " + (ec ? ec.message() : std::string("not removed")))
        .with_field("name");
  return Status::ok();
}

}  // namespace rigel::tools
