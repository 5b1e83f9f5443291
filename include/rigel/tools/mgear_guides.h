#pragma once
// mGear Shifter guide templates (.sgt) as rig definitions (issue 21): a
// studio's guides, authored for Maya, read as rigel components and the
// skeleton they imply, so they need not be re-authored.
//
// A template is JSON: `guide_root` (rig-wide parameters: rig_name, the
// side colours), `components_list` (names, in the template's order) and
// `components_dict`, one entry per component: `param_values` (comp_type,
// comp_name, comp_side, comp_index, colours and the type's own values),
// `tra` (guide locator -> 4x4 world matrix, Maya's row-major layout with
// the translation in the last row), `parent_fullName` (the parent
// component, null at the root) and `parent_localName` (the parent's locator
// it hangs from).
//
// What each mGear type becomes (docs/RIG.md, "mGear guides", has the table
// with the parameters carried): control_01 -> control, meta_01 -> meta,
// chain_01 / chain_spring_01 -> fkChain (mode 0) or ikChain, shoulder_01 ->
// fkChain (the clavicle), arm_2jnt_01..04 -> limb (arm), leg_2jnt_01..02 ->
// limb (leg), spine_ik_01 / spine_S_shape_01 -> spine (splineIK),
// neck_ik_01 -> neck, foot_bk_01 -> foot, eye_01 -> eye, mouth_01 -> mouth,
// squash_01 -> squash.
// Names, sides and indices carry over (mGear's arm_L0 becomes arm_L; the
// index joins the name where a name repeats on a side: finger_L2 ->
// finger2_L), and so do parents (the parent's locator becomes the hook the
// child attaches to), colours (mGear's Maya colour indices or RGB, per
// component or from the guide's side colours, on the FK and IK roles) and
// the parameters with a counterpart. Every other parameter, every guide
// locator without a counterpart (a neck's spline tangents) and every
// component of another type is listed in the report by name, never dropped
// silently; the children of a component left out hang from its parent.
//
// The skeleton: joints at the guide locators, as mGear builds them (a chain
// joint per locator, `division` joints from a spine's root to its eff),
// named COMPONENT_LOCATOR (arm_L0_elbow; interior spine joints
// spine_C0_1 ...), parented along each component and to the joint of the
// parent's locator, in the template's units and axes (Y up), with identity
// orientations. Components whose guides are joints name them; pivots and
// plain controls take the locator's matrix as values.
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "rigel/base/status.h"
#include "rigel/graph/graph.h"
#include "rigel/math/types.h"
#include "rigel/rig/definition.h"
#include "rigel/scene/scene.h"

namespace rigel::tools {

struct GuideJoint {
  std::string name;
  std::string parent;  // "" for a root
  math::Vec3 position = math::Vec3::Zero();
};

// What became of one mGear component.
struct MgearComponentReport {
  std::string mgear;       // "arm_L0"
  std::string mgear_type;  // "arm_2jnt_01"
  std::string rigel_type;  // "limb"; "" when it could not be mapped
  std::string rigel_name;  // the component's full name, "arm_L"
  std::string problem;     // why it could not be mapped
  std::vector<std::string> unmapped_params;  // parameters with no counterpart
  std::vector<std::string> unmapped_guides;  // locators with no counterpart
  std::vector<std::string> notes;            // what was approximated
  // Each locator with a counterpart and where it went: "joint NAME" or
  // "guide NAME" (values).
  std::map<std::string, std::string> guides;
  bool mapped() const { return !rigel_type.empty(); }
};

struct MgearImport {
  rig::Definition definition;
  std::vector<GuideJoint> joints;  // parents before children
  std::vector<MgearComponentReport> components;  // in the template's order
  std::vector<std::string> unmapped_components() const;  // their mGear names
};

// kParseError for text that is not JSON; kInvalidArgument naming the
// component (and the key or locator) for a malformed template: no
// components_dict, a listed component missing from it, no param_values or
// comp_type, a tra entry that is not a 4x4 matrix of numbers, a parent that
// is not a component, parents in a cycle, a locator the type needs missing.
// `source` names the file in messages.
Result<MgearImport> import_mgear_guides(std::string_view text, const std::string& source);
Result<MgearImport> import_mgear_guides_file(const std::filesystem::path& file);

// The skeleton as a scene of joints (world = the locators' positions).
Result<std::unique_ptr<scene::Scene>> guide_skeleton_scene(const MgearImport& imported,
                                                           std::shared_ptr<const graph::Registry> registry);

// The report as JSON: {rig, components: [{mgear, mgearType, rigel,
// rigelType, problem?, guides, unmappedParams, unmappedGuides, notes}],
// unmapped: [mGear names], joints}.
nlohmann::ordered_json mgear_report_json(const MgearImport& imported);

}  // namespace rigel::tools
