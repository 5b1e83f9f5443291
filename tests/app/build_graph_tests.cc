// Build graphs through the app layer: `rigel graph convert` of the example
// biped (every component type, the ephemeral jaw included) builds the same
// rig as the definition on its character.
#include <unistd.h>

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "../rig/rig_test_util.h"
#include "rigel/app/rig_files.h"
#include "rigel/rig/manager.h"
#include "rigel/tools/data_files.h"

namespace rigel {
namespace {

namespace fs = std::filesystem;

// Every occurrence of `from` in `text` replaced by `to`.
std::string replaced(std::string text, const std::string& from, const std::string& to) {
  for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
    text.replace(at, from.size(), to);
  return text;
}

TEST(AppBuildGraph, the_converted_biped_builds_the_definitions_rig) {
  const fs::path definition = fs::path(RIGEL_SOURCE_DIR) / "examples/biped.rig.xml";
  const fs::path dir = fs::temp_directory_path() / ("rigel_app_graph_" + std::to_string(::getpid()));
  fs::create_directories(dir / "graphs");
  const fs::path graph = dir / "graphs/biped.build.json";
  auto converted = app::convert_definition_file(definition, graph);
  ASSERT_TRUE(converted.is_ok()) << converted.status().message();
  // The geometry is found from the graph's own folder.
  auto from_graph_def = rig::read_definition(graph);
  ASSERT_TRUE(from_graph_def.is_ok()) << from_graph_def.status().message();
  auto from_def = rig::read_definition(definition);
  ASSERT_TRUE(from_def.is_ok());
  auto a = app::build_rig_file(*from_def, definition, tools::components());
  auto b = app::build_rig_file(*from_graph_def, graph, tools::components());
  ASSERT_TRUE(a.is_ok()) << a.status().message();
  ASSERT_TRUE(b.is_ok()) << b.status().message();
  EXPECT_EQ(b->components.size(), a->components.size());
  EXPECT_EQ(b->nodes, a->nodes);
  std::string worst;
  EXPECT_LT(rig::testing::pose_error(*b->scene, rig::testing::joint_worlds(*a->scene), &worst), 1e-9) << worst;
  // Node for node, metadata included, but for the file each was built from
  // (and the geometry's path from it).
  const std::string from_definition = rig::testing::normalized(*a->scene);
  const std::string from_graph =
      replaced(replaced(rig::testing::normalized(*b->scene), graph.string(), definition.string()),
               converted->rig.geometry.at(0).file, from_def->geometry.at(0).file);
  EXPECT_TRUE(from_graph == from_definition) << rig::testing::first_difference(from_graph, from_definition);
  // A graph name is required of the output.
  EXPECT_EQ(app::convert_definition_file(definition, dir / "biped.json").status().field(), "output");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace rigel
