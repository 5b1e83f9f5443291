// Rig templates (seed 003 §4.8, §6.4, A.6): model-level operations that move
// parts of rig definitions between rigs. A template is a Definition of its
// own whose roots are the parts to reuse (an arm with its hand and fingers).
//
// Seed 003 links template joints to scene joints by "unique identifiers"
// generated at export; rigel's equivalent is the component's `rig_id`:
//   - extract: a component's sub-tree becomes a template, ids kept, so an
//     updated template can later be matched back to the rig it came from;
//   - inject ("Inject", A.6): the template's roots are added under a parent,
//     normally with fresh ids and unique names, so one template (an arm) can
//     go into one rig several times;
//   - update ("Update", A.6 / Rig Updater A.9): components whose ids match
//     the template's take the template's data and keep their place;
//   - mirror: a left template becomes a right one (names, sides, guides).
// Every operation works on the model only (no scene), and a failed call
// leaves the rig unchanged.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/rig/definition.h"

namespace rigel::rig {

// The sub-tree rooted at the component with `rig_id` as a template: name =
// the component's name, version = its version, components = {a copy of the
// sub-tree} with every rig id (and every other field, `attach` included)
// kept. Rig-level geometry and features are not part of it. kNotFound when
// no component has that id.
Result<Definition> extract_template(const Definition& rig, std::string_view rig_id);

struct InjectOptions {
  // Give every injected component a fresh rig id (new_rig_id()). Needed to
  // inject one template twice; false keeps the template's ids, so that
  // update_from_template can later match them (refused, kAlreadyExists,
  // when one of them is already in the rig).
  bool new_ids = true;
  // Renames every injected component: name -> rename(name) (when set), then
  // + name_suffix. Component names are unique within a rig, so a second
  // injection needs one of them. Attach references between injected
  // components ("OTHER.HOOK" where OTHER is a template component) follow
  // the renaming.
  std::string name_suffix;
  std::function<std::string(std::string_view)> rename;
};

// Adds copies of `templ`'s root components (with their sub-trees) as the
// last children of the component with `parent_rig_id`, or as the last roots
// when `parent_rig_id` is empty. Each injected root attaches at `attach`
// (empty: hook 0; see Component::attach). Fails, changing nothing:
//   kInvalidArgument  the template has no components, or a renamed name is
//                     empty, or (without new_ids) the template repeats a rig id;
//   kNotFound         no component has `parent_rig_id`;
//   kAlreadyExists    an injected name is already used in the rig or by
//                     another injected component (named in the message), or
//                     (without new_ids) an injected rig id is already in the rig.
Status inject_template(Definition& rig, const Definition& templ, std::string_view parent_rig_id,
                       std::string_view attach, const InjectOptions& options = {});

// Seed 003's "Update": every template component whose (non-empty) rig id is
// in the rig replaces that component's data: type, version, params,
// guides, controls and features. The rig component keeps its name, side,
// attach, node editor position, place in the tree and children (children
// that are also in the template are updated in their own right; template
// components not in the rig are ignored). Fails, changing nothing:
// kInvalidArgument when the template repeats a rig id, kNotFound when none
// of its ids is in the rig (the wrong template, most likely).
Status update_from_template(Definition& rig, const Definition& templ);

// Left <-> right mirroring.
//
// Names: every occurrence of a side token is swapped for its counterpart
// (each pair works both ways), in the component name, the guides' `joint`
// names, the `attach` reference and the template's name. The string is
// scanned left to right; at each position the pairs are tried in order
// (first then second token of each); a token matches when it appears there
// case-sensitively and sits on a word boundary:
//   - before it: the start of the string, a character that is not a letter
//     or digit, or the token itself starts with such a character ("_L",
//     ".L"), or the token starts upper case after a lower-case letter or a
//     digit (camelCase: "armLeft");
//   - after it: the end of the string, a character that is not a letter, or
//     an upper-case letter when the token ends lower case ("leftArm").
// So "arm_L" -> "arm_R", "hand.L.END" -> "hand.R.END", "leftArm" ->
// "rightArm", "upperLeftArm" -> "upperRightArm", "finger_l1" ->
// "finger_r1", while "arm_Leg", "cleft", "Leftover" and "spine_LOW" stay.
// A matched token is replaced and the scan continues after it. With pairs
// whose two tokens have the same case at both ends (the defaults), mirroring
// twice gives the original string back. Guide roles (Guide::name),
// parameters and control styles are copied unchanged.
//
// Geometry: the mirror plane is YZ (x -> -x). A guide's translate becomes
// (-x, y, z); its rotation R (Euler XYZ degrees) becomes M R M with
// M = diag(-1, 1, 1), which in Euler XYZ is exactly (rx, -ry, -rz) (M
// commutes with rotations about X and reverses those about Y and Z), so
// mirroring twice gives the angles back bit for bit; scale is unchanged.
// Sides: L <-> R, C stays.
struct MirrorOptions {
  std::vector<std::pair<std::string, std::string>> side_tokens = {
      {".L", ".R"}, {"_L", "_R"}, {"Left", "Right"}, {"left", "right"}, {"_l", "_r"}};
  // Keep the rig ids; false (default) gives every component a fresh one, so
  // the mirror can be injected beside its original.
  bool keep_ids = false;
};

// A string with its side tokens swapped (the rule above).
std::string mirror_name(std::string_view name, const MirrorOptions& options = {});
// The side a name's first side token says (mirror_name's scan and word
// boundaries): kLeft for the first token of a pair, kRight for the second;
// nullopt when the name has none.
std::optional<Side> side_of_name(std::string_view name, const MirrorOptions& options = {});
// The component and its children mirrored.
Component mirror_component(const Component& component, const MirrorOptions& options = {});
// Every component mirrored; the template's name mirrored; version,
// geometry and features copied.
Definition mirror_template(const Definition& templ, const MirrorOptions& options = {});

}  // namespace rigel::rig
