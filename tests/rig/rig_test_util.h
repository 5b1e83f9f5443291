#pragma once
// Helpers shared by the rig layer's tests: a rig built on the metarig,
// joint poses and their differences, comparing scenes built twice (uuids
// differ, names do not) and short messages where texts differ.
#include <filesystem>
#include <map>
#include <memory>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "rigel/io/gltf_import.h"
#include "rigel/io/scene_file.h"
#include "rigel/rig/build.h"
#include "rigel/rig/definition.h"
#include "rigel/rig/component.h"
#include "rigel/rig/meta.h"
#include "rigel/scene/scene.h"
#include "rigel/scene/transform_types.h"

namespace rigel::rig::testing {

using graph::NodeId;

// Rigify's human metarig (tests/data/gltf), over `registry` (the rig layer's
// by default), with an empty undo history.
inline std::unique_ptr<scene::Scene> metarig(std::shared_ptr<const graph::Registry> registry = default_registry()) {
  io::GltfImportOptions options;
  options.registry = std::move(registry);
  auto imported =
      io::import_gltf(std::filesystem::path(RIGEL_SOURCE_DIR) / "tests/data/gltf/rigify_human_metarig.glb", options);
  EXPECT_TRUE(imported.is_ok()) << imported.status().message();
  if (!imported) return nullptr;
  return std::move(*imported);
}

// A guide placed at a joint of the character.
inline Guide at_joint(std::string joint) {
  Guide g;
  g.joint = std::move(joint);
  return g;
}

// A component of `type` with a fresh rigId, on the centre side.
inline Component make_component(std::string type, std::string name, std::vector<Guide> guides,
                                std::vector<Param> params = {}) {
  Component c;
  c.type = std::move(type);
  c.name = std::move(name);
  c.rig_id = new_rig_id();
  c.guides = std::move(guides);
  c.params = std::move(params);
  return c;
}

inline Param make_param(std::string name, ParamValue value) {
  Param p;
  p.name = std::move(name);
  p.value = std::move(value);
  return p;
}

// Every joint's world matrix, by name.
inline std::map<std::string, math::Mat4> joint_worlds(scene::Scene& s) {
  std::map<std::string, math::Mat4> out;
  for (NodeId id : s.graph().nodes())
    if (s.graph().node(id)->type().name() == scene::kJointType) out[s.graph().node(id)->name()] = s.world_matrix(id);
  return out;
}

// The largest difference of any joint's world matrix from `before`, over the
// joints not in `skip`; the joint that differs most goes to `worst`.
inline double pose_error(scene::Scene& s, const std::map<std::string, math::Mat4>& before, std::string* worst,
                         const std::set<std::string>& skip = {}) {
  double most = 0.0;
  for (const auto& [name, w] : joint_worlds(s)) {
    auto it = before.find(name);
    if (it == before.end() || skip.count(name)) continue;
    const double e = (w - it->second).cwiseAbs().maxCoeff();
    if (e > most) {
      most = e;
      *worst = name;
    }
  }
  return most;
}

// The node at a rig address ("rig:component/role"), or an invalid id and a
// test failure that names the address.
inline NodeId at(scene::Scene& s, const std::string& address) {
  Result<NodeId> id = resolve_address(s.graph(), address);
  EXPECT_TRUE(id.is_ok()) << address << ": " << id.status().message();
  return id ? *id : NodeId{};
}

// A rig built on the metarig, with what the metarig was before the build.
struct BuiltRig {
  std::unique_ptr<scene::Scene> scene;
  std::unique_ptr<Build> build;           // null when the build failed
  std::map<std::string, math::Mat4> rest;  // joint world matrices before the build
  std::string before;                      // the scene's text before the build
  graph::Graph& g() { return scene->graph(); }
};

// Builds every component of `d` on a fresh metarig into `r` (a BuiltRig or a
// test's own struct derived from it); failures are test failures.
inline void build_on_metarig(BuiltRig& r, Definition d) {
  r.scene = metarig();
  if (!r.scene) return;
  r.rest = joint_worlds(*r.scene);
  r.before = io::write_scene(*r.scene);
  auto opened = Build::open(*r.scene, std::move(d), builtin_components());
  EXPECT_TRUE(opened.is_ok()) << opened.status().message();
  if (!opened) return;
  r.build = std::move(*opened);
  const Status s = r.build->build_all();
  EXPECT_TRUE(s.is_ok()) << s.message();
  if (!s) r.build.reset();
}

inline BuiltRig built_rig(Definition d) {
  BuiltRig r;
  build_on_metarig(r, std::move(d));
  return r;
}

// The scene's text with every uuid replaced by the name of its node, so two
// builds that made the same nodes compare equal.
inline std::string normalized(scene::Scene& scene) {
  std::string text = io::write_scene(scene);
  std::map<std::string, std::string> names;
  for (NodeId id : scene.graph().nodes()) names[scene.graph().node(id)->uuid().str()] = scene.graph().node(id)->name();
  // Canonical uuids: 8-4-4-4-12 lower-case hex (no std::regex: GCC 12 warns inside it at -O1).
  auto is_uuid_at = [&](std::size_t i) {
    if (i + 36 > text.size()) return false;
    for (std::size_t k = 0; k < 36; ++k) {
      const char c = text[i + k];
      if (k == 8 || k == 13 || k == 18 || k == 23) {
        if (c != '-') return false;
      } else if (!((c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'))) {
        return false;
      }
    }
    return true;
  };
  std::string out;
  for (std::size_t i = 0; i < text.size();) {
    if (is_uuid_at(i)) {
      auto n = names.find(text.substr(i, 36));
      out += n != names.end() ? "<" + n->second + ">" : "<?>";
      i += 36;
    } else {
      out += text[i++];
    }
  }
  return out;
}

// Where two texts first differ (the line of each), for short failure messages.
inline std::string first_difference(const std::string& a, const std::string& b) {
  std::size_t i = 0;
  while (i < a.size() && i < b.size() && a[i] == b[i]) ++i;
  if (i == a.size() && i == b.size()) return "identical";
  auto line_at = [](const std::string& t, std::size_t at) {
    const std::size_t start = t.rfind('\n', at == 0 ? 0 : at - 1);
    const std::size_t s = start == std::string::npos ? 0 : start + 1;
    return t.substr(s, std::min<std::size_t>(t.find('\n', at) - s, 200));
  };
  return "first difference at byte " + std::to_string(i) + ":\n  " + line_at(a, i) + "\n  " + line_at(b, i);
}

// From a complete build: back to every index (the last first) and forward
// again; each time the scene (uuids written as names) must be the straight
// build's.
inline void expect_stepping_gives_the_straight_build(Build& build, scene::Scene& scene) {
  const std::string straight = normalized(scene);
  for (int k = static_cast<int>(build.plan().size()) - 1; k >= 0; --k) {
    ASSERT_TRUE(build.go_to(k).is_ok()) << k;
    ASSERT_TRUE(build.build_all().is_ok()) << k;
    const std::string now = normalized(scene);
    ASSERT_TRUE(now == straight) << "back to step " << k << " and forward again: " << first_difference(now, straight);
  }
}

}  // namespace rigel::rig::testing
