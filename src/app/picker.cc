// The workspace's picker (workspace.h, PickerGroup): controls grouped by
// rig and component (or ephemeral region), each group placed by body part
// and side. A built rig's component says its type and side; an ephemeral
// rig's controls have only their joints' names, read as Rigify, Mixamo and
// glTF files spell them (".L", "_L", "Left", "l_").

#include <algorithm>
#include <array>
#include <cctype>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "rigel/app/workspace.h"
#include "rigel/rig/meta.h"

namespace rigel::app {
namespace {

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

// The words of a name: runs of letters and digits ("DEF-upper_arm.L" ->
// def, upper, arm, l).
std::vector<std::string> tokens(const std::string& text) {
  std::vector<std::string> out(1);
  for (char c : text) {
    if (std::isalnum(static_cast<unsigned char>(c))) {
      out.back() += c;
    } else if (!out.back().empty()) {
      out.emplace_back();
    }
  }
  if (out.back().empty()) out.pop_back();
  return out;
}

// Whether a word of `text` starts or ends with one of `words`, or holds one
// of four letters or more ("forearm" has arm, not ear; "lefthandindex1" has hand).
bool has(const std::string& text, std::initializer_list<const char*> words) {
  for (const std::string& t : tokens(text))
    for (const char* w : words) {
      const std::string_view word(w);
      if (t.starts_with(word) || t.ends_with(word) || (word.size() >= 4 && t.find(word) != std::string::npos)) return true;
    }
  return false;
}

// The side a joint or control name says: a .L / _L / -L / Left suffix or an
// L_ / l_ / left prefix; 'C' without one.
char side_of_name(std::string_view name) {
  std::string n(name.substr(name.find(':') == std::string_view::npos ? 0 : name.find(':') + 1));
  for (const char* strip : {"_ctrl", "_control", "_ik", "_fk"})
    if (n.size() > std::string_view(strip).size() && n.ends_with(strip)) n.resize(n.size() - std::string_view(strip).size());
  const std::string l = lower(n);
  auto ends = [&](std::initializer_list<const char*> list) {
    return std::any_of(list.begin(), list.end(), [&](const char* s) { return l.ends_with(s); });
  };
  auto starts = [&](std::initializer_list<const char*> list) {
    return std::any_of(list.begin(), list.end(), [&](const char* s) { return l.starts_with(s); });
  };
  // Rigify's ".L.001" and "_L1": the side before a trailing number.
  std::string core = l;
  while (!core.empty() && (std::isdigit(static_cast<unsigned char>(core.back())) || core.back() == '.')) core.pop_back();
  auto core_ends = [&](const char* s) { return core.ends_with(s); };
  if (ends({".l", "_l", "-l", "left"}) || core_ends(".l") || core_ends("_l") || starts({"l_", "left"})) return 'L';
  if (ends({".r", "_r", "-r", "right"}) || core_ends(".r") || core_ends("_r") || starts({"r_", "right"})) return 'R';
  return 'C';
}

// The body part a name (a component type and name, or a joint name) says.
std::string part_of(const std::string& text) {
  const std::string t = lower(text);
  if (has(t, {"face", "head", "neck", "jaw", "eye", "lid", "brow", "lip", "nose", "ear", "tongue", "teeth", "cheek",
               "chin", "temple", "forehead", "mouth"}))
    return "head";
  if (has(t, {"hand", "finger", "thumb", "index", "middle", "ring", "pinky", "palm"})) return "hand";
  if (has(t, {"tail"})) return "tail";
  if (has(t, {"foot", "toe", "heel", "leg", "thigh", "shin", "knee", "calf"})) return "leg";
  if (has(t, {"arm", "shoulder", "clav", "elbow", "wrist"})) return "arm";
  if (has(t, {"spine", "chest", "hip", "pelvis", "torso", "waist", "breast", "belly", "back"})) return "torso";
  if (has(t, {"global", "root", "world", "main", "master"})) return "root";
  return "other";
}

int part_order(const std::string& part) {
  static const std::array<const char*, 8> kOrder = {"head", "arm", "hand", "torso", "leg", "tail", "root", "other"};
  for (std::size_t i = 0; i < kOrder.size(); ++i)
    if (part == kOrder[i]) return static_cast<int>(i);
  return static_cast<int>(kOrder.size());
}

int side_order(char side) { return side == 'R' ? 0 : side == 'C' ? 1 : 2; }

std::string built_label(const graph::Graph& g, NodeId control) {
  const graph::Node& n = *g.node(control);
  const std::string* role = n.tag_find(rig::kTagRole);
  if (!role) return n.name();
  const std::string* index = n.tag_find(rig::kTagIndex);
  return index ? *role + " " + *index : *role;
}

}  // namespace

std::vector<PickerGroup> Workspace::picker() const {
  const graph::Graph& g = graph();
  std::vector<PickerGroup> out;
  std::map<std::pair<std::string, std::string>, std::size_t> index;  // (rig, group) -> out[i]
  for (const ControlEntry& c : controls()) {
    PickerGroup p;
    p.rig = c.rig;
    p.name = c.group;
    const NodeId component = c.ephemeral ? NodeId() : rig::component_of(g, c.node);
    if (component.is_valid() && component != rig::rig_of(g, c.node)) {
      const std::string side = rig::meta_string(g, component, "side");
      p.side = side == "L" ? 'L' : side == "R" ? 'R' : 'C';
      p.part = part_of(rig::meta_string(g, component, "metaType") + " " + c.group);
    } else {
      // An ephemeral control: a face's or a hand's region is a group of its
      // own; any other control goes by its joint's part and side.
      const std::string region_part = c.group == c.rig ? std::string() : part_of(c.group);
      if (region_part == "head" || region_part == "hand") {
        p.part = region_part;
        p.side = side_of_name(c.group);
      } else {
        const std::string name = g.node(c.node)->name();
        p.part = part_of(name);
        p.side = side_of_name(name);
        p.name = p.part + (p.side == 'C' ? "" : std::string("_") + p.side);
      }
    }
    auto [it, added] = index.emplace(std::make_pair(p.rig, p.name), out.size());
    if (added) out.push_back(p);
    std::string label = c.ephemeral ? g.node(c.node)->name() : built_label(g, c.node);
    if (c.ephemeral && label.ends_with("_ctrl")) label.resize(label.size() - 5);
    out[it->second].controls.push_back({c.node, label});
  }
  std::stable_sort(out.begin(), out.end(), [](const PickerGroup& a, const PickerGroup& b) {
    if (a.rig != b.rig) return a.rig < b.rig;
    if (part_order(a.part) != part_order(b.part)) return part_order(a.part) < part_order(b.part);
    return side_order(a.side) < side_order(b.side);
  });
  return out;
}

}  // namespace rigel::app
