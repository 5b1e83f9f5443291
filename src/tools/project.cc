// Rigging projects and assets (project.h).

#include "rigel/tools/project.h"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "rigel/base/log.h"
#include "rigel/io/diffable_json.h"
#include "rigel/io/json_depth.h"
#include "rigel/io/scene_file.h"

namespace rigel::tools {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

namespace {

const char* kCategories[][2] = {{"character", "characters"}, {"prop", "props"}};

Result<Json> read_json(const fs::path& file, const char* tag, int format, const char* what) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return Status(ErrorCode::kNotFound, file.string() + ": cannot be read");
  std::ostringstream text;
  text << in.rdbuf();
  const std::string s = text.str();
  Result<Json> parsed = io::parse_json(s, file.string(), 16);
  if (!parsed) return parsed.status();
  Json j = std::move(*parsed);
  if (!j.is_object() || !j.contains(tag) || !j[tag].is_number_integer() || j[tag].get<std::int64_t>() < 1)
    return Status(ErrorCode::kParseError, file.string() + ": not a rigel " + what + " file (no \"" + tag + "\": FORMAT)");
  if (j[tag].get<std::int64_t>() > format)
    return Status(ErrorCode::kFailedPrecondition, file.string() + ": made by a newer rigel (" + what + " format " +
                                                      std::to_string(j[tag].get<std::int64_t>()) + "; this rigel reads " +
                                                      std::to_string(format) + ")");
  for (const char* key : {"name"})
    if (!j.contains(key) || !j[key].is_string())
      return Status(ErrorCode::kParseError, file.string() + ": " + key + ": expected text");
  return j;
}

std::string text_of(const Json& j, const char* key) { return j.contains(key) && j[key].is_string() ? j[key].get<std::string>() : ""; }

Result<Asset> read_asset(const fs::path& file) {
  Result<Json> j = read_json(file, "rigelAsset", kProjectFormat, "asset");
  if (!j) return j.status();
  Asset a;
  a.dir = file.parent_path();
  a.name = (*j)["name"].get<std::string>();
  a.type = text_of(*j, "type");
  a.skeleton = text_of(*j, "skeleton");
  a.created = text_of(*j, "created");
  a.modified = text_of(*j, "modified");
  if (a.type != "character" && a.type != "prop")
    return Status(ErrorCode::kParseError, file.string() + ": type: expected \"character\" or \"prop\"");
  if (a.skeleton.find("..") != std::string::npos || fs::path(a.skeleton).is_absolute())
    return Status(ErrorCode::kParseError, file.string() + ": skeleton: a file inside the asset, got '" + a.skeleton + "'");
  return a;
}

Status write_asset(const Asset& a) {
  return io::write_file_atomic(a.dir / (a.name + kAssetExtension),
                               io::diffable_json(Json{{"rigelAsset", kProjectFormat},
                                                      {"name", a.name},
                                                      {"type", a.type},
                                                      {"skeleton", a.skeleton},
                                                      {"created", a.created},
                                                      {"modified", a.modified}}));
}

}  // namespace

std::string utc_now_iso() {
  const std::time_t t = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&t, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return text;
}

Status check_name(const std::string& name, const std::string& field) {
  const bool ok = !name.empty() && name.size() <= 64 && std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
  });
  if (ok) return Status::ok();
  return Status(ErrorCode::kInvalidArgument,
                field + ": '" + name + "' is not a name (1-64 letters, digits, '_' and '-')")
      .with_field(field);
}

Result<Project> create_project(const fs::path& dir, const std::string& name) {
  const std::string n = name.empty() ? fs::absolute(dir).lexically_normal().filename().string() : name;
  if (Status s = check_name(n, "name"); !s) return s;
  std::error_code ec;
  if (fs::exists(dir / kProjectFile, ec))
    return Status(ErrorCode::kInvalidArgument, (dir / kProjectFile).string() + ": already a project").with_field("dir");
  if (fs::exists(dir, ec)) {
    if (!fs::is_directory(dir, ec)) return Status(ErrorCode::kInvalidArgument, dir.string() + ": not a folder").with_field("dir");
    for (const auto& e : fs::directory_iterator(dir, ec))
      if (e.path().filename().string().rfind('.', 0) != 0)
        return Status(ErrorCode::kInvalidArgument, dir.string() + ": not empty (a project starts in an empty folder)")
            .with_field("dir");
  }
  fs::create_directories(dir, ec);
  if (ec) return Status(ErrorCode::kIoError, dir.string() + ": " + ec.message()).with_field("dir");
  Project p{dir, n, kProjectFormat, utc_now_iso()};
  if (Status s = io::write_file_atomic(dir / kProjectFile,
                                       io::diffable_json(Json{{"rigelProject", kProjectFormat}, {"name", p.name}, {"created", p.created}}));
      !s)
    return s;
  log::debug("created project " + p.name + " in " + dir.string());
  return p;
}

Result<Project> open_project(const fs::path& dir) {
  Result<Json> j = read_json(dir / kProjectFile, "rigelProject", kProjectFormat, "project");
  if (!j) return j.status();
  Project p;
  p.dir = dir;
  p.name = (*j)["name"].get<std::string>();
  p.format = (*j)["rigelProject"].get<int>();
  p.created = text_of(*j, "created");
  return p;
}

Result<Project> find_project(const fs::path& from) {
  std::error_code ec;
  fs::path at = fs::absolute(from, ec).lexically_normal();
  if (fs::is_regular_file(at, ec)) at = at.parent_path();
  for (; !at.empty(); at = at.parent_path()) {
    if (fs::exists(at / kProjectFile, ec)) return open_project(at);
    if (at == at.root_path()) break;
  }
  return Status(ErrorCode::kNotFound, "not in a rigel project (no " + std::string(kProjectFile) + " in " +
                                          from.string() + " or above; rigel project new DIR makes one)");
}

Result<Asset> create_asset(const Project& project, const std::string& name, const std::string& type, const fs::path& skeleton) {
  if (Status s = check_name(name, "name"); !s) return s;
  const char* category = nullptr;
  for (const auto& c : kCategories)
    if (type == c[0]) category = c[1];
  if (!category)
    return Status(ErrorCode::kInvalidArgument, "type: '" + type + "' is not an asset type (character or prop)").with_field("type");
  if (open_asset(project, name)) return Status(ErrorCode::kInvalidArgument, "name: the project has an asset '" + name + "'").with_field("name");
  std::error_code ec;
  if (!skeleton.empty() && !fs::is_regular_file(skeleton, ec))
    return Status(ErrorCode::kInvalidArgument, "skeleton: " + skeleton.string() + ": not a file").with_field("skeleton");
  Asset a;
  a.dir = project.dir / category / name;
  a.name = name;
  a.type = type;
  a.created = a.modified = utc_now_iso();
  for (const char* sub : {"build", "skeleton", "poses", "rig"}) fs::create_directories(a.dir / sub, ec);
  for (const char* kind : kDataKinds) fs::create_directories(a.dir / "data" / kind, ec);
  if (ec) return Status(ErrorCode::kIoError, a.dir.string() + ": " + ec.message());
  if (!skeleton.empty()) {
    const fs::path to = a.dir / "skeleton" / skeleton.filename();
    fs::copy_file(skeleton, to, fs::copy_options::overwrite_existing, ec);
    if (ec) return Status(ErrorCode::kIoError, "skeleton: " + to.string() + ": " + ec.message()).with_field("skeleton");
    a.skeleton = (fs::path("skeleton") / skeleton.filename()).generic_string();
  }
  if (Status s = write_asset(a); !s) return s;
  log::debug("created " + type + " asset " + name + " in " + a.dir.string());
  return a;
}

Result<std::vector<Asset>> list_assets(const Project& project) {
  std::vector<Asset> out;
  std::error_code ec;
  for (const auto& c : kCategories) {
    const fs::path folder = project.dir / c[1];
    if (!fs::is_directory(folder, ec)) continue;
    std::vector<fs::path> dirs;
    for (const auto& e : fs::directory_iterator(folder, ec))
      if (e.is_directory(ec)) dirs.push_back(e.path());
    std::sort(dirs.begin(), dirs.end());
    for (const fs::path& d : dirs) {
      const fs::path file = d / (d.filename().string() + kAssetExtension);
      if (!fs::exists(file, ec)) continue;
      Result<Asset> a = read_asset(file);
      if (!a) return a.status();
      out.push_back(std::move(*a));
    }
  }
  return out;
}

Result<Asset> open_asset(const Project& project, const std::string& name) {
  if (Status s = check_name(name, "asset"); !s) return s;
  std::error_code ec;
  for (const auto& c : kCategories) {
    const fs::path file = project.dir / c[1] / name / (name + kAssetExtension);
    if (fs::exists(file, ec)) return read_asset(file);
  }
  return Status(ErrorCode::kNotFound, "asset: the project " + project.name + " has no asset '" + name + "'").with_field("asset");
}

Result<Asset> find_asset(const fs::path& from) {
  std::error_code ec;
  fs::path at = fs::absolute(from, ec).lexically_normal();
  if (fs::is_regular_file(at, ec)) at = at.parent_path();
  for (; !at.empty(); at = at.parent_path()) {
    if (fs::exists(at / kProjectFile, ec)) break;  // the project's own folder holds no asset
    const fs::path file = at / (at.filename().string() + kAssetExtension);
    if (fs::exists(file, ec)) return read_asset(file);
    if (at == at.root_path()) break;
  }
  return Status(ErrorCode::kNotFound, "not in an asset's folder (" + from.string() + ")");
}

std::vector<int> published_versions(const Asset& asset) {
  std::vector<int> out;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(asset.dir / "rig", ec)) {
    const std::string n = e.path().filename().string();
    if (n.size() >= 4 && n[0] == 'v' && std::all_of(n.begin() + 1, n.end(), [](char c) { return c >= '0' && c <= '9'; }))
      out.push_back(std::stoi(n.substr(1)));
  }
  std::sort(out.begin(), out.end());
  return out;
}

Result<fs::path> resolve_in_asset(const Asset& asset, const std::string& given, AssetFile kind, const std::string& field) {
  std::error_code ec;
  if (fs::exists(given, ec) || given.find('/') != std::string::npos || given.find('\\') != std::string::npos)
    return fs::path(given);
  std::vector<fs::path> tries;
  switch (kind) {
    case AssetFile::kDefinition:
      tries = {asset.dir / "build" / given, asset.dir / "build" / (given + ".rig.xml"), asset.dir / "build" / (given + ".rig.json")};
      break;
    case AssetFile::kCharacter:
      tries = {asset.dir / "skeleton" / given, asset.dir / "skeleton" / (given + ".glb"), asset.dir / "skeleton" / (given + ".gltf")};
      break;
    case AssetFile::kPoseLibrary:
      tries = given == "poses" ? std::vector<fs::path>{asset.dir / "poses"} : std::vector<fs::path>{asset.dir / "poses" / given};
      break;
    case AssetFile::kScene: tries = {asset.dir / given, asset.dir / (given + ".rigel")}; break;
  }
  for (const fs::path& p : tries)
    if (fs::exists(p, ec)) return p;
  std::string places;
  for (const fs::path& p : tries) places += (places.empty() ? "" : ", ") + p.string();
  return Status(ErrorCode::kNotFound, field + ": no '" + given + "' here or in asset " + asset.name + " (" + places + ")")
      .with_field(field);
}

}  // namespace rigel::tools
