#pragma once
// What the tools tests share: a character imported over the registry the
// CLI uses, the biped of examples/biped.rig.xml built on it, and built
// nodes by nameless address.
#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <string>

#include "rigel/ephemeral/component.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/io/gltf_import.h"
#include "rigel/rig/manager.h"
#include "rigel/rig/meta.h"
#include "rigel/scene/transform_types.h"

namespace rigel::tools::testing {

namespace fs = std::filesystem;

inline fs::path source(const std::string& relative) { return fs::path(RIGEL_SOURCE_DIR) / relative; }

inline std::unique_ptr<scene::Scene> import_character(const fs::path& path) {
  io::GltfImportOptions options;
  options.registry = ephemeral::default_registry();
  auto imported = io::import_gltf(path, options);
  EXPECT_TRUE(imported.is_ok()) << path << ": " << imported.status().message();
  return imported ? std::move(*imported) : nullptr;
}

// `definition` (default: the biped) built on `character` (default: the
// metarig), history cleared. `unit_scales`: the joints' scales set to
// exactly 1 first (the metarig's are single precision, 1 +- 3e-6).
inline std::unique_ptr<scene::Scene> built_rig(const fs::path& definition = source("examples/biped.rig.xml"),
                                               const fs::path& character = source("tests/data/gltf/rigify_human_metarig.glb"),
                                               bool unit_scales = false) {
  auto s = import_character(character);
  if (!s) return nullptr;
  if (unit_scales) {
    for (graph::NodeId id : s->hierarchy()) {
      if (s->graph().node(id)->type().name() == scene::kJointType) {
        EXPECT_TRUE(s->graph()
                        .set_value(graph::Plug{id, scene::xform::kScale, -1}, graph::Value(math::Vec3(math::Vec3::Ones())))
                        .is_ok());
      }
    }
  }
  auto added = rig::add_rig(*s, definition, ephemeral::components());
  EXPECT_TRUE(added.is_ok()) << added.status().message();
  s->graph().clear_history();
  return s;
}

inline graph::NodeId at(const graph::Graph& g, const std::string& address) {
  auto id = rig::resolve_address(g, address);
  EXPECT_TRUE(id.is_ok()) << address << ": " << id.status().message();
  return id ? *id : graph::NodeId{};
}

}  // namespace rigel::tools::testing
