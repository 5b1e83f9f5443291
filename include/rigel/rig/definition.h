// Rig definitions (seed 002): a rig described as a versioned tree of
// components, independent of any scene. One model, two syntaxes:
// `.rig.xml` (pugixml) and `.rig.json` (nlohmann-json); definition_io.h reads
// and writes both, losslessly either way. docs/RIG.md describes the format.
//
// Nesting is parenting: a child component attaches to a hook (attach point)
// its parent publishes (seed 002's ParentJoint index, Luna's hook), or, with
// `attach = "OTHER.HOOK"`, to a hook of another component of the rig.
// Components are matched across versions by `rig_id` (a UUID v4), never by
// name.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "rigel/math/types.h"
#include "rigel/rig/version.h"

namespace rigel::rig {

// Where an element came from in its file (1-based; 0 = not from a file).
struct SourceLocation {
  int line = 0;
  int column = 0;
  friend bool operator==(const SourceLocation&, const SourceLocation&) = default;
};

enum class Side { kCenter, kLeft, kRight };
const char* side_name(Side side);  // "C", "L", "R"
std::optional<Side> side_from_name(std::string_view name);
Side mirror_side(Side side);  // L <-> R, C stays

// A parameter's value, typed by the component's schema (schema.h).
using ParamValue = std::variant<bool, std::int64_t, double, std::string, math::Vec3>;

struct Param {
  std::string name;
  ParamValue value;
  SourceLocation where;
};

// A guide: where one of the component's joints or controls goes. Either a
// joint of the character (`joint`, by name: joint placement comes from the
// skeleton) or an explicit world transform (metres, degrees Euler XYZ).
struct Guide {
  std::string name;  // role in the component ("root", "start", "0", ...); may be empty
  std::string joint;  // character joint to take the location from; empty = use the values
  math::Vec3 translate = math::Vec3::Zero();
  math::Vec3 rotate = math::Vec3::Zero();
  math::Vec3 scale = math::Vec3::Ones();
  SourceLocation where;
};

// Shape and colour of one control role of a component ("main", "fk", "ik",
// "pole", ...); roles a definition leaves out take the schema's defaults.
struct ControlStyle {
  std::string role;
  std::string shape;  // scene/shapes.h library name
  std::string color;  // palette name or "#rrggbb"
  double size = 1.0;
  SourceLocation where;
};

// A switch of a feature (seed 003): a secondary name turning part of it on/off.
struct FeatureSwitch {
  std::string name;
  bool enabled = true;
  SourceLocation where;
};

// Features group build steps (seed 003): a step that names feature F (and
// optionally switch S of it) runs only while F (and S) are enabled. Features
// set on the rig apply to every component; a component's own override them.
struct Feature {
  std::string name;
  bool enabled = true;
  std::vector<FeatureSwitch> switches;
  SourceLocation where;
};

struct Component {
  std::string type;
  std::string name;
  Side side = Side::kCenter;
  std::string version = "1.0";
  std::string rig_id;  // UUID v4 text, as written
  std::string attach;  // hook of the parent ("0", "END", "hips") or "OTHER.HOOK"; empty = hook 0
  // rigIds of other components it builds after, besides its parent and
  // attach target: what it reads from them (a build graph's data flow),
  // so an update that rebuilds one of them rebuilds it too.
  std::vector<std::string> after;
  std::vector<Guide> guides;
  std::vector<ControlStyle> controls;
  std::vector<Param> params;
  std::vector<Feature> features;
  std::optional<std::pair<double, double>> gui_location;  // node editor position
  std::vector<Component> children;
  SourceLocation where;

  const Param* param(std::string_view name) const;
  const ControlStyle* control(std::string_view role) const;
  // "name_SIDE" ("arm_L"), or the name alone on the centre side ("spine"):
  // its nodes' names start with it (after the rig's name), and addresses
  // and lookups name a component by it.
  std::string full_name() const;
};

// Geometry the rig is built on: a character file (glTF/.rigel), relative to
// the definition's folder, and optionally the name of a mesh in it.
struct Geometry {
  std::string file;
  std::string name;
  SourceLocation where;
};

// Hand-made data a build imports after the components are built (seed 004
// §4.9-4.10): its last step, "data", imports each entry in order. `file` is
// relative to the definition's folder, as geometry is; `kind` is one of
// kDataImportKinds (tools/project.h's data folders).
struct DataImport {
  std::string kind;
  std::string file;
  SourceLocation where;
};
inline constexpr const char* kDataImportKinds[] = {"weights", "shapes", "blendshapes", "driven_poses", "correctives"};
bool is_data_import_kind(std::string_view kind);

struct Definition {
  std::string name;
  std::string version = "1.0";
  std::vector<Geometry> geometry;
  std::vector<Feature> features;
  std::vector<DataImport> data;  // imported in order by the build's last step
  std::vector<Component> components;  // roots (usually one: the global component)
  std::optional<std::pair<double, double>> gui_location;
  std::string source;  // file it was read from, for messages; "" when built in code
  SourceLocation where;

  // Depth-first, parents before children, in file order.
  std::vector<const Component*> all_components() const;
  const Component* find_by_rig_id(std::string_view rig_id) const;
  const Component* find_by_name(std::string_view name) const;
  Component* find_by_rig_id(std::string_view rig_id);
};

// A fresh random UUID v4 in canonical text (8-4-4-4-12, lower case).
std::string new_rig_id();
// 32 hex digits, with or without the four dashes, version nibble 4, variant 8-b.
bool is_rig_id(std::string_view text);

}  // namespace rigel::rig
