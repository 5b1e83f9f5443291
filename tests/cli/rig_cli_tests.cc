// `rigel build`, `rigs`, `update`, `remove`, `address` on the bundled biped
// example (examples/biped.rig.xml on Rigify's human metarig).
#include <filesystem>
#include <fstream>

#include "cli_test_util.h"

namespace rigel::cli::testing {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

std::string example() { return (fs::path(RIGEL_SOURCE_DIR) / "examples/biped.rig.xml").string(); }
std::string metarig() { return (fs::path(RIGEL_SOURCE_DIR) / "tests/data/gltf/rigify_human_metarig.glb").string(); }

TEST(CliRig, build_lists_updates_and_removes_the_biped) {
  TempDir dir;
  const std::string plain = (dir.path() / "plain.rigel").string();
  const std::string built = (dir.path() / "hero.rigel").string();
  ASSERT_EQ(rigel({"import", metarig(), "-o", plain}).exit_code, 0);

  CliRun b = rigel({"build", example(), "--character", plain, "-o", built, "--json"});
  ASSERT_EQ(b.exit_code, 0) << b;
  Json summary = Json::parse(b.out);
  EXPECT_EQ(summary["rig"], "hero");
  EXPECT_GE(summary["components"].size(), 10u);
  EXPECT_EQ(summary["steps"], summary["of"]);

  CliRun rigs = rigel({"rigs", built, "--json"});
  ASSERT_EQ(rigs.exit_code, 0) << rigs;
  Json list = Json::parse(rigs.out)["rigs"];
  ASSERT_EQ(list.size(), 1u);
  EXPECT_EQ(list[0]["name"], "hero");
  EXPECT_EQ(list[0]["version"], "1.0");
  EXPECT_FALSE(list[0]["outOfDate"].get<bool>());

  // The arm's last FK control, by address, and the same after a rename.
  CliRun a = rigel({"address", built, "hero:arm_L/fk[END]", "hero:arm_L/joint[0]/fk"});
  ASSERT_EQ(a.exit_code, 0) << a;
  EXPECT_EQ(a.out, "hero_arm_L_fk3\nhero_arm_L_fk0\n");
  EXPECT_EQ(rigel({"address", built, "hero:wing_L/fk[0]"}).exit_code, 1);

  // A newer definition on disk: one component changed.
  std::string text = read_text(example());
  const std::string rig_line = "<rig name=\"hero\" version=\"1.0\">";
  ASSERT_NE(text.find(rig_line), std::string::npos);
  text.replace(text.find(rig_line), rig_line.size(), "<rig name=\"hero\" version=\"1.1\">");
  const std::size_t arm = text.find("name=\"arm\" side=\"R\" version=\"1.0\"");
  ASSERT_NE(arm, std::string::npos);
  text.replace(arm, std::string("name=\"arm\" side=\"R\" version=\"1.0\"").size(), "name=\"arm\" side=\"R\" version=\"1.1\"");
  // (update needs no geometry: the scene holds the character)
  const std::string v2 = (dir.path() / "biped_v2.rig.xml").string();
  std::ofstream(v2) << text;
  const std::string updated = (dir.path() / "hero_v2.rigel").string();
  CliRun u = rigel({"update", built, "--rig", "hero", "--definition", v2, "-o", updated, "--json"});
  ASSERT_EQ(u.exit_code, 0) << u;
  Json report = Json::parse(u.out)["rigs"][0];
  EXPECT_EQ(report["from"], "1.0");
  EXPECT_EQ(report["to"], "1.1");
  // The right arm and the fingers that hang from it.
  std::vector<std::string> rebuilt = report["rebuilt"].get<std::vector<std::string>>();
  EXPECT_EQ(rebuilt.size(), 6u);
  EXPECT_EQ(rebuilt.front(), "arm_R");

  // Remove gives back the character exactly.
  const std::string removed = (dir.path() / "removed.rigel").string();
  CliRun r = rigel({"remove", updated, "--rig", "hero", "-o", removed});
  ASSERT_EQ(r.exit_code, 0) << r;
  EXPECT_TRUE(read_text(removed) == read_text(plain)) << "removing the rig gives back the file it was built on";
}

TEST(CliRig, bad_input_is_refused_with_the_place) {
  TempDir dir;
  const std::string out = (dir.path() / "x.rigel").string();
  const std::string bad = (fs::path(RIGEL_SOURCE_DIR) / "tests/data/rig/invalid_semantic.rig.xml").string();
  CliRun b = rigel({"build", bad, "--character", metarig(), "-o", out});
  EXPECT_EQ(b.exit_code, 1) << b;
  EXPECT_NE(b.err.find("invalid_semantic.rig.xml:"), std::string::npos) << b;
  EXPECT_FALSE(fs::exists(out));
  CliRun m = rigel({"build", example(), "--character", "/no/such/file.glb", "-o", out});
  EXPECT_EQ(m.exit_code, 1) << m;
  EXPECT_EQ(rigel({"build", example()}).exit_code, 2) << "-o is required";
  CliRun u = rigel({"update", metarig(), "-o", out});
  EXPECT_EQ(u.exit_code, 1) << u;
  EXPECT_EQ(rigel({"update", out, "--keep-keys", "sideways", "-o", out}).exit_code, 2);
}

}  // namespace
}  // namespace rigel::cli::testing
