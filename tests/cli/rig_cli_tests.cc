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
  EXPECT_EQ(a.out, "hero_arm_L_fk2\nhero_arm_L_fk0\n");
  EXPECT_EQ(rigel({"address", built, "hero:wing_L/fk[0]"}).exit_code, 1);

  // The metadata network's queries: the component of a node, a member by
  // role and index (getMetaNodeConnection), a child by rigId (getMetaChildById).
  CliRun of = rigel({"meta", built, "--of", "hero_arm_L_fk1", "--json"});
  ASSERT_EQ(of.exit_code, 0) << of;
  Json found = Json::parse(of.out)["results"][0];
  EXPECT_EQ(found["component"], "arm_L");
  EXPECT_EQ(found["side"], "L");
  EXPECT_EQ(found["metaType"], "limb");
  EXPECT_EQ(found["role"], "fk");
  EXPECT_EQ(found["index"], 1);
  EXPECT_EQ(found["address"], "hero:arm_L/joint[1]/fk[0]");
  CliRun conn = rigel({"meta", built, "--rig", "hero", "--component", "arm_L", "--connection", "fk", "--index", "2"});
  ASSERT_EQ(conn.exit_code, 0) << conn;
  EXPECT_EQ(conn.out.substr(0, conn.out.find(' ')), "hero_arm_L_fk2");
  std::string clavicle_id;
  for (const Json& c : summary["components"])
    if (c["name"] == "clavicle" && c["side"] == "L") clavicle_id = c["rigId"];
  ASSERT_FALSE(clavicle_id.empty());
  CliRun child = rigel({"meta", built, "--rig", "hero", "--component", "spine", "--child", clavicle_id, "--json"});
  ASSERT_EQ(child.exit_code, 0) << child;
  EXPECT_EQ(Json::parse(child.out)["results"][0]["component"], "clavicle_L");
  EXPECT_EQ(rigel({"meta", built, "--rig", "hero", "--component", "hip", "--child", clavicle_id}).exit_code, 1)
      << "a grandchild is not a child";
  EXPECT_EQ(rigel({"meta", built, "--of", "no_such_node"}).exit_code, 1);
  EXPECT_EQ(rigel({"meta", built, "--of", "spine.001"}).exit_code, 1) << "a joint is not part of the rig";
  EXPECT_EQ(rigel({"meta", built}).exit_code, 2);

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
  // The right arm and what hangs from it: its twist joints and the hand.
  std::vector<std::string> rebuilt = report["rebuilt"].get<std::vector<std::string>>();
  EXPECT_EQ(rebuilt.size(), 3u);
  EXPECT_EQ(rebuilt.front(), "arm_R");
  // Updated from another file, the rig follows that file and is up to date with it.
  CliRun after = rigel({"rigs", updated, "--json"});
  ASSERT_EQ(after.exit_code, 0) << after;
  const Json followed = Json::parse(after.out)["rigs"][0];
  EXPECT_EQ(fs::path(followed["definition"].get<std::string>()), fs::weakly_canonical(v2));
  EXPECT_FALSE(followed["outOfDate"].get<bool>()) << followed.dump(1);

  // Remove gives back the character exactly.
  const std::string removed = (dir.path() / "removed.rigel").string();
  CliRun r = rigel({"remove", updated, "--rig", "hero", "-o", removed});
  ASSERT_EQ(r.exit_code, 0) << r;
  EXPECT_TRUE(read_text(removed) == read_text(plain)) << "removing the rig gives back the file it was built on";
}

TEST(CliRig, edit_mode_writes_moved_guides_back_with_versions_bumped) {
  TempDir dir;
  const std::string plain = (dir.path() / "plain.rigel").string();
  const std::string built = (dir.path() / "edit.rigel").string();
  const std::string edited = (dir.path() / "edited.rigel").string();
  const std::string def_out = (dir.path() / "edited.rig.xml").string();
  ASSERT_EQ(rigel({"import", metarig(), "-o", plain}).exit_code, 0);
  CliRun b = rigel({"build", example(), "--character", plain, "--edit-mode", "-o", built});
  ASSERT_EQ(b.exit_code, 0) << b;

  // The left breast's control (a `simple` component), 5 cm along its bone.
  CliRun e = rigel({"edit", built, "--move", "hero:chest/main[0]=0,0.05,0", "--definition-out", def_out, "-o", edited,
                    "--keep-editing", "--json"});
  ASSERT_EQ(e.exit_code, 0) << e;
  Json report = Json::parse(e.out);
  EXPECT_EQ(report["version"], "1.1");
  ASSERT_EQ(report["changed"].size(), 1u);
  EXPECT_EQ(report["changed"][0]["name"], "chest");
  EXPECT_EQ(report["changed"][0]["version"], "1.1");
  // The written definition is valid and holds the guide's new place.
  CliRun v = rigel({"validate", def_out});
  EXPECT_EQ(v.exit_code, 0) << v;
  const std::string text = read_text(def_out);
  EXPECT_NE(text.find("<rig name=\"hero\" version=\"1.1\">"), std::string::npos);
  // The control stood at its joint, so the move is the guide's offset in the joint's space.
  EXPECT_NE(text.find("<guide joint=\"breast.L\" translate=\"0 0.05 0\"/>"), std::string::npos) << text;
  EXPECT_NE(text.find("<guide joint=\"breast.R\"/>"), std::string::npos);
  // The rebuilt global control stands there, zeroed: nothing is left to write back.
  CliRun again = rigel({"edit", edited, "--definition-out", def_out, "-o", edited, "--json"});
  ASSERT_EQ(again.exit_code, 0) << again;
  EXPECT_TRUE(Json::parse(again.out)["changed"].empty());
  EXPECT_FALSE(Json::parse(again.out)["editMode"].get<bool>()) << "committing leaves edit mode";
  // The rig now points at the definition it was written to, and is up to date with it.
  CliRun listed = rigel({"rigs", edited, "--json"});
  ASSERT_EQ(listed.exit_code, 0) << listed;
  const Json rig_entry = Json::parse(listed.out)["rigs"][0];
  EXPECT_EQ(fs::path(rig_entry["definition"].get<std::string>()), fs::weakly_canonical(def_out));
  EXPECT_FALSE(rig_entry["outOfDate"].get<bool>()) << rig_entry.dump(1);
  EXPECT_FALSE(rig_entry["editMode"].get<bool>());
  EXPECT_EQ(rig_entry["version"], "1.1");

  // A rig built for animation is not in edit mode; bad moves name themselves.
  const std::string anim = (dir.path() / "anim.rigel").string();
  ASSERT_EQ(rigel({"build", example(), "--character", plain, "-o", anim}).exit_code, 0);
  CliRun refused = rigel({"edit", anim, "-o", edited});
  EXPECT_EQ(refused.exit_code, 1) << refused;
  EXPECT_NE(refused.err.find("not in edit mode"), std::string::npos) << refused;
  CliRun bad = rigel({"edit", built, "--move", "hero:chest/main[0]=1,2", "-o", edited});
  EXPECT_EQ(bad.exit_code, 1) << bad;
  EXPECT_NE(bad.err.find("--move 'hero:chest/main[0]=1,2'"), std::string::npos) << bad;
  CliRun missing = rigel({"edit", built, "--move", "hero:wing_L/fk[0]=1,2,3", "-o", edited});
  EXPECT_EQ(missing.exit_code, 1) << missing;
}

// Runs `rigel ARGS...` in folder `dir` (the current directory matters to
// the test).
CliRun rigel_in(const fs::path& dir, const std::vector<std::string>& args) { return rigel(args, dir); }

TEST(CliRig, the_definition_path_does_not_depend_on_the_current_directory) {
  TempDir dir;
  // Built from the source folder with the definition named relative to it,
  // the scene written elsewhere.
  CliRun b = rigel_in(RIGEL_SOURCE_DIR, {"build", "examples/biped.rig.xml", "-o", (dir.path() / "hero.rigel").string()});
  ASSERT_EQ(b.exit_code, 0) << b;
  CliRun rigs = rigel_in(dir.path(), {"rigs", "hero.rigel", "--json"});
  ASSERT_EQ(rigs.exit_code, 0) << rigs;
  const Json r = Json::parse(rigs.out)["rigs"][0];
  EXPECT_EQ(r["definitionVersion"], "1.0") << r.dump(1);
  EXPECT_TRUE(r["definitionFound"].get<bool>());
  EXPECT_EQ(fs::path(r["definition"].get<std::string>()), fs::weakly_canonical(example()));
  CliRun u = rigel_in(dir.path(), {"update", "hero.rigel", "-o", "h2.rigel"});
  EXPECT_EQ(u.exit_code, 0) << u;
  EXPECT_TRUE(contains(u.err, "up to date")) << u;

  // A definition that is gone is said so, naming it.
  const fs::path copy = dir.path() / "defs" / "biped.rig.xml";
  fs::create_directories(copy.parent_path());
  std::ofstream(copy) << read_text(example());
  const std::string plain = (dir.path() / "plain.rigel").string();
  ASSERT_EQ(rigel({"import", metarig(), "-o", plain}).exit_code, 0);
  ASSERT_EQ(rigel({"build", copy.string(), "--character", plain, "-o", (dir.path() / "moved.rigel").string()}).exit_code, 0);
  fs::remove(copy);
  CliRun missing = rigel_in(dir.path(), {"rigs", "moved.rigel"});
  EXPECT_EQ(missing.exit_code, 0) << missing;
  EXPECT_TRUE(contains(missing.out, "definition missing")) << missing;
  CliRun refused = rigel_in(dir.path(), {"update", "moved.rigel", "-o", "m2.rigel"});
  EXPECT_EQ(refused.exit_code, 1) << refused;
  EXPECT_TRUE(contains(refused.err, "defs/biped.rig.xml: cannot be read")) << refused;
}

TEST(CliRig, a_components_version_bump_alone_is_out_of_date_and_rebuilt) {
  TempDir dir;
  std::string text = read_text(example());
  const std::string arm = "name=\"arm\" side=\"L\" version=\"1.0\"";
  ASSERT_NE(text.find(arm), std::string::npos);
  const fs::path def = dir.path() / "hero.rig.xml";
  const std::string plain = (dir.path() / "plain.rigel").string();
  const std::string built = (dir.path() / "hero.rigel").string();
  ASSERT_EQ(rigel({"import", metarig(), "-o", plain}).exit_code, 0);
  std::ofstream(def) << text;
  ASSERT_EQ(rigel({"build", def.string(), "--character", plain, "-o", built}).exit_code, 0);
  text.replace(text.find(arm), arm.size(), "name=\"arm\" side=\"L\" version=\"1.1\"");
  std::ofstream(def, std::ios::trunc) << text;
  CliRun rigs = rigel({"rigs", built, "--json"});
  ASSERT_EQ(rigs.exit_code, 0) << rigs;
  const Json r = Json::parse(rigs.out)["rigs"][0];
  EXPECT_TRUE(r["outOfDate"].get<bool>());
  for (const Json& c : r["components"]) EXPECT_EQ(c["outOfDate"].get<bool>(), c["name"] == "arm_L") << c.dump();
  CliRun listed = rigel({"rigs", built});
  EXPECT_TRUE(contains(listed.out, "out of date: definition has 1.1")) << listed;
  CliRun u = rigel({"update", built, "-o", (dir.path() / "h2.rigel").string(), "--json"});
  ASSERT_EQ(u.exit_code, 0) << u;
  const std::vector<std::string> rebuilt = Json::parse(u.out)["rigs"][0]["rebuilt"].get<std::vector<std::string>>();
  ASSERT_FALSE(rebuilt.empty());
  EXPECT_EQ(rebuilt.front(), "arm_L");
}

TEST(CliRig, a_moved_pole_is_not_written_into_a_guide) {
  TempDir dir;
  const std::string built = (dir.path() / "e.rigel").string();
  const std::string def_out = (dir.path() / "p.rig.xml").string();
  ASSERT_EQ(rigel({"build", example(), "--edit-mode", "-o", built}).exit_code, 0);
  CliRun e = rigel({"edit", built, "--move", "hero:arm_L/pole=0,0.1,0", "--definition-out", def_out, "-o",
                    (dir.path() / "e2.rigel").string(), "--json"});
  ASSERT_EQ(e.exit_code, 0) << e;
  const Json report = Json::parse(e.out);
  EXPECT_TRUE(report["changed"].empty()) << report.dump(1);
  ASSERT_EQ(report["ignored"].size(), 1u) << report.dump(1);
  EXPECT_EQ(report["ignored"][0], "hero_arm_L_pole");
  EXPECT_FALSE(fs::exists(def_out)) << "nothing to write";
}

TEST(CliRig, every_missing_guide_joint_is_reported_with_its_place) {
  TempDir dir;
  std::string text = read_text(example());
  for (const std::string joint : {"forearm.L", "hand.R"}) {
    const std::string attr = "joint=\"" + joint + "\"";
    const std::size_t at = text.find(attr);
    ASSERT_NE(at, std::string::npos);
    text.replace(at, attr.size(), "joint=\"no_" + joint + "\"");
  }
  const fs::path def = dir.path() / "missing.rig.xml";
  std::ofstream(def) << text;
  const std::string out = (dir.path() / "x.rigel").string();
  CliRun b = rigel({"build", def.string(), "--character", metarig(), "-o", out, "--json"});
  EXPECT_EQ(b.exit_code, 1) << b;
  EXPECT_TRUE(contains(b.err, "missing.rig.xml:")) << b;
  EXPECT_TRUE(contains(b.err, "no joint 'no_forearm.L'")) << b;
  EXPECT_TRUE(contains(b.err, "no joint 'no_hand.R'")) << b;
  ASSERT_FALSE(b.out.empty()) << b;
  const Json errors = Json::parse(b.out)["errors"];
  ASSERT_EQ(errors.size(), 2u) << b;
  for (const Json& e : errors) EXPECT_GT(e["line"].get<int>(), 0) << e.dump();
  EXPECT_FALSE(fs::exists(out));
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
