#pragma once
// Rigging projects and assets (seed 004 §4.6): a project is a folder with a
// `rigel.project.json` (its format version, name, creation time); each
// asset lives in a category folder (`characters/NAME`, `props/NAME`) with a
// `NAME.asset.json` (name, type, skeleton file, times) and the folders a
// rig is rebuilt from:
//
//   build/        definitions (.rig.xml, .rig.json), PyBuild scripts, build graphs
//   skeleton/     the character file
//   data/         weights/ shapes/ blendshapes/ driven_poses/ correctives/
//   poses/        the pose library
//   rig/          published rig versions (v001, v002, ...), never overwritten
//
// Files are diffable JSON written atomically. A project or asset file of a
// newer format is refused saying so; a malformed one names the file and
// place. Names are 1-64 letters, digits, '_' and '-'.

#include <filesystem>
#include <string>
#include <vector>

#include "rigel/base/status.h"

namespace rigel::tools {

inline constexpr int kProjectFormat = 1;
inline constexpr const char* kProjectFile = "rigel.project.json";
inline constexpr const char* kAssetExtension = ".asset.json";

struct Project {
  std::filesystem::path dir;
  std::string name;
  int format = kProjectFormat;
  std::string created;  // ISO 8601, UTC
};

struct Asset {
  std::filesystem::path dir;  // PROJECT/characters/NAME
  std::string name;
  std::string type;      // "character" or "prop"
  std::string skeleton;  // the character file, relative to dir ("skeleton/body.glb"; "" when none yet)
  std::string created, modified;
};

// The folder of each kind of asset data (under data/).
inline constexpr const char* kDataKinds[] = {"weights", "shapes", "blendshapes", "driven_poses", "correctives"};

// The time now as ISO 8601 in UTC ("2026-12-04T03:57:39Z"): what the
// pipeline's files record.
std::string utc_now_iso();

// kInvalidArgument naming `field` unless `name` is a safe project or asset name.
Status check_name(const std::string& name, const std::string& field);

// Makes DIR a project (DIR made as needed; refused when it is one already
// or holds anything but hidden files). `name` empty: DIR's name.
Result<Project> create_project(const std::filesystem::path& dir, const std::string& name = {});
// Reads DIR/rigel.project.json.
Result<Project> open_project(const std::filesystem::path& dir);
// The project `from` is in (it, or the nearest folder above it holding a
// project file); kNotFound when there is none.
Result<Project> find_project(const std::filesystem::path& from);

// A new asset in the project: its folders, its file and, given a skeleton
// file, a copy of it under skeleton/. kInvalidArgument naming "name" when
// it is taken or unsafe, "type" for a type other than character or prop,
// "skeleton" for a file that cannot be read.
Result<Asset> create_asset(const Project& project, const std::string& name, const std::string& type = "character",
                           const std::filesystem::path& skeleton = {});
// Every asset of the project, by category then name.
Result<std::vector<Asset>> list_assets(const Project& project);
// The asset named `name`; kNotFound naming "asset" when there is none.
Result<Asset> open_asset(const Project& project, const std::string& name);
// The asset `from` is in (it, or a folder above it holding NAME.asset.json
// under a project); kNotFound when there is none.
Result<Asset> find_asset(const std::filesystem::path& from);

// Published versions in rig/ (v001 ...), ascending.
std::vector<int> published_versions(const Asset& asset);

// What a command was given, resolved against an asset: an existing path as
// it is; otherwise a bare name (no folder in it) is looked up in the
// asset's folder for that kind, with or without the kind's extensions
// (definitions: build/NAME.rig.xml or .rig.json; characters: skeleton/
// NAME.glb or .gltf; pose libraries: poses/ itself for "poses" or
// poses/NAME; scenes: NAME.rigel in the asset). kNotFound naming `field`
// with the places looked in when nothing is there.
enum class AssetFile { kDefinition, kCharacter, kPoseLibrary, kScene };
Result<std::filesystem::path> resolve_in_asset(const Asset& asset, const std::string& given, AssetFile kind,
                                               const std::string& field);

}  // namespace rigel::tools
