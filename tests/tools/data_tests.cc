// Skin weights and control shapes as data (tools/skin_weights.h,
// tools/shape_data.h) on the bundled body (10,037 vertices on the Rigify
// metarig's joints) and the biped built on the metarig: export and import
// round trips byte for byte; painted weights come back on a fresh copy of
// the body, on a copy with renamed joints (a name table) and mirrored;
// control shapes drawn by hand come back on a rebuilt rig; bad files are
// refused naming the file and place.

#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <string>

#include "rigel/ops/deform/nodes.h"
#include "rigel/rig/manager.h"
#include "rigel/rig/meta.h"
#include "rigel/rig/templates.h"
#include "rigel/tools/shape_data.h"
#include "rigel/tools/skin_weights.h"
#include "../io/io_test_util.h"
#include "tools_test_util.h"

namespace rigel::tools {
namespace {

namespace sc = ops::skin_cluster_attr;
using graph::NodeId;
using math::Vec3;

std::unique_ptr<scene::Scene> body() { return testing::import_character(testing::source("tests/data/gltf/rigify_human_body.glb")); }

// Weight of joint `name` at vertex v of the scene's first skin.
double weight_of(const SkinWeights& s, std::size_t v, const std::string& name) {
  double w = 0;
  for (std::int64_t k = s.offsets[v]; k < s.offsets[v + 1]; ++k)
    if (s.influences[static_cast<std::size_t>(s.joints[static_cast<std::size_t>(k)])].joint == name)
      w += s.weights[static_cast<std::size_t>(k)];
  return w;
}

// Paints vertex v fully onto joint index j (what a rigger's brush stroke leaves).
void paint(scene::Scene& s, std::size_t v, std::int64_t j) {
  graph::Graph& g = s.graph();
  NodeId skin;
  for (NodeId id : g.nodes())
    if (g.node(id)->type().name() == ops::kSkinClusterType) skin = id;
  auto offsets = std::get<std::vector<std::int64_t>>(g.evaluate(skin, sc::kInfluenceOffsets));
  auto joints = std::get<std::vector<std::int64_t>>(g.evaluate(skin, sc::kInfluenceJoints));
  auto weights = std::get<std::vector<double>>(g.evaluate(skin, sc::kInfluenceWeights));
  for (std::int64_t k = offsets[v]; k < offsets[v + 1]; ++k) {
    joints[static_cast<std::size_t>(k)] = k == offsets[v] ? j : joints[static_cast<std::size_t>(k)];
    weights[static_cast<std::size_t>(k)] = k == offsets[v] ? 1.0 : 0.0;
  }
  ASSERT_TRUE(g.set_value({skin, sc::kInfluenceJoints, -1}, graph::Value(joints)).is_ok());
  ASSERT_TRUE(g.set_value({skin, sc::kInfluenceWeights, -1}, graph::Value(weights)).is_ok());
}

TEST(SkinWeightsData, export_import_export_is_the_same_file) {
  auto s = body();
  ASSERT_TRUE(s);
  auto skins = capture_skin_weights(*s);
  ASSERT_TRUE(skins.is_ok()) << skins.status().message();
  ASSERT_FALSE(skins->empty());
  EXPECT_GT((*skins)[0].vertex_count(), 10000u);
  const std::string text = skin_weights_to_json(*skins);
  auto back = skin_weights_from_json(text, "body.weights.json");
  ASSERT_TRUE(back.is_ok()) << back.status().message();
  auto report = apply_skin_weights(*s, *back);
  ASSERT_TRUE(report.is_ok()) << report.status().message();
  EXPECT_TRUE(report->remapped.empty()) << "every joint by uuid";
  EXPECT_EQ(skin_weights_to_json(*capture_skin_weights(*s)), text) << "byte for byte";
}

TEST(SkinWeightsData, painted_weights_come_back_on_a_fresh_copy_and_a_renamed_one) {
  auto s = body();
  ASSERT_TRUE(s);
  paint(*s, 100, 3);
  paint(*s, 5000, 7);
  const auto painted = *capture_skin_weights(*s);
  const std::string file = skin_weights_to_json(painted);
  // A fresh import of the same character: other uuids, the same names.
  auto fresh = body();
  ASSERT_NE(skin_weights_to_json(*capture_skin_weights(*fresh)), file);
  auto r = apply_skin_weights(*fresh, *skin_weights_from_json(file, "f"));
  ASSERT_TRUE(r.is_ok()) << r.status().message();
  EXPECT_FALSE(r->remapped.empty()) << "matched by name";
  EXPECT_EQ(fresh->graph().undo_label(), "import skin weights");
  const auto got = *capture_skin_weights(*fresh);
  ASSERT_EQ(got[0].weights.size(), painted[0].weights.size());
  for (std::size_t k = 0; k < got[0].weights.size(); ++k) EXPECT_NEAR(got[0].weights[k], painted[0].weights[k], 1e-6);
  EXPECT_EQ(got[0].joints, painted[0].joints);

  // Renamed joints: refused without a table, matched with one.
  auto renamed = body();
  std::map<std::string, std::string> table;
  for (NodeId id : renamed->hierarchy()) {
    graph::Node* n = const_cast<graph::Node*>(renamed->graph().node(id));
    if (n->type().name() != scene::kJointType) continue;
    const std::string to = "jnt_" + n->name();
    table[n->name()] = to;
    ASSERT_TRUE(renamed->graph().rename(id, to).is_ok());
  }
  auto refused = apply_skin_weights(*renamed, *skin_weights_from_json(file, "f"));
  ASSERT_FALSE(refused.is_ok());
  EXPECT_EQ(refused.status().field(), "joints");
  WeightsImport by_table;
  by_table.rename = table;
  ASSERT_TRUE(apply_skin_weights(*renamed, *skin_weights_from_json(file, "f"), by_table).is_ok());
  const auto got2 = *capture_skin_weights(*renamed);
  for (std::size_t v : {std::size_t{100}, std::size_t{5000}, std::size_t{9000}})
    for (const SkinInfluence& inf : painted[0].influences)
      EXPECT_NEAR(weight_of(got2[0], v, "jnt_" + inf.joint), weight_of(painted[0], v, inf.joint), 1e-6) << v << " " << inf.joint;
  // And by position on a skeleton named otherwise, without a table.
  auto nearest = body();
  for (NodeId id : nearest->hierarchy()) {
    if (nearest->graph().node(id)->type().name() != scene::kJointType) continue;
    ASSERT_TRUE(nearest->graph().rename(id, "j" + nearest->graph().node(id)->uuid().str().substr(0, 8)).is_ok());
  }
  WeightsImport by_place;
  by_place.nearest = true;
  ASSERT_TRUE(apply_skin_weights(*nearest, *skin_weights_from_json(file, "f"), by_place).is_ok());
  // Each joint onto one at its place (joints that share a place, as the
  // hips and the spine's root do, are told apart only by name).
  const auto placed = capture_skin_weights(*nearest)->front();
  ASSERT_EQ(placed.joints.size(), painted[0].joints.size());
  for (std::size_t k = 0; k < placed.joints.size(); ++k)
    EXPECT_LT((placed.influences[static_cast<std::size_t>(placed.joints[k])].bind -
               painted[0].influences[static_cast<std::size_t>(painted[0].joints[k])].bind).norm(), 1e-9) << k;
}

TEST(SkinWeightsData, mirrored_weights_are_the_other_side_s) {
  auto s = body();
  ASSERT_TRUE(s);
  const auto before = *capture_skin_weights(*s);
  WeightsImport mirror;
  mirror.mirror = true;
  ASSERT_TRUE(apply_skin_weights(*s, before, mirror).is_ok());
  const auto after = *capture_skin_weights(*s);
  // The body is symmetric: a left-hand vertex now has the weights the
  // right hand's had, and the left hand's joints carry what the right's did.
  graph::Graph& g = s->graph();
  NodeId skin;
  for (NodeId id : g.nodes())
    if (g.node(id)->type().name() == ops::kSkinClusterType) skin = id;
  const auto points = std::get<std::vector<Vec3>>(g.evaluate(skin, sc::kBindPoints));
  std::size_t checked = 0;
  for (std::size_t v = 0; v < points.size(); v += 97) {
    // The vertex at the mirror image (to within the mesh's symmetry).
    std::size_t u = 0;
    double best = 1e9;
    for (std::size_t w = 0; w < points.size(); ++w) {
      const double d = (points[w] - Vec3(-points[v].x(), points[v].y(), points[v].z())).squaredNorm();
      if (d < best) best = d, u = w;
    }
    for (const SkinInfluence& inf : before[0].influences) {
      if (inf.joint.empty()) continue;
      EXPECT_NEAR(weight_of(after[0], v, rig::mirror_name(inf.joint)), weight_of(before[0], u, inf.joint), 1e-6) << v;
    }
    ++checked;
  }
  EXPECT_GT(checked, 50u);
}

// The arrays in a binary side file (the format data.weights: binary): the
// same weights back exactly, export after import the same pair of files,
// a repaint's export replacing the side file (the old one gone), and a
// side file changed, cut short, missing or named outside the folder refused
// naming the weights file and the member.
TEST(SkinWeightsData, binary_side_file_round_trips_and_is_checked) {
  namespace fs = std::filesystem;
  using io::testing::read_text;
  using io::testing::write_text;
  io::testing::TempDir dir;
  auto s = body();
  ASSERT_TRUE(s);
  paint(*s, 100, 3);
  const auto painted = *capture_skin_weights(*s);
  const fs::path file = dir.path() / "body.weights.json";
  ASSERT_TRUE(write_skin_weights(file, painted, WeightsFormat::kBinary).is_ok());
  const std::string json = read_text(file);
  const auto side_files = [&] {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(dir.path()))
      if (e.path().extension() == ".bin") out.push_back(e.path().filename().string());
    return out;
  };
  ASSERT_EQ(side_files().size(), 1u);
  const std::string side = side_files()[0];
  EXPECT_TRUE(side.starts_with("body.weights.") && side.size() == std::string("body.weights.12345678.bin").size()) << side;
  EXPECT_NE(json.find("\"binary\""), std::string::npos);
  EXPECT_EQ(json.find("\"vertices\""), std::string::npos) << "the arrays are in the side file";
  EXPECT_LT(json.size() * 20, skin_weights_to_json(painted).size()) << "the JSON keeps the influences only";

  auto back = read_skin_weights(file);
  ASSERT_TRUE(back.is_ok()) << back.status().message();
  ASSERT_EQ(back->size(), painted.size());
  EXPECT_EQ((*back)[0].offsets, painted[0].offsets);
  EXPECT_EQ((*back)[0].joints, painted[0].joints);
  EXPECT_EQ((*back)[0].weights, painted[0].weights) << "float64 in the side file: exact";
  EXPECT_EQ(skin_weights_to_json(*back), skin_weights_to_json(painted)) << "the same weights as the JSON format";

  // Imported onto a fresh copy and exported again: the same pair, byte for byte.
  auto fresh = body();
  ASSERT_TRUE(apply_skin_weights(*fresh, *back).is_ok());
  const std::string side_bytes = read_text(dir.path() / side);
  ASSERT_TRUE(write_skin_weights(file, *capture_skin_weights(*fresh), WeightsFormat::kBinary).is_ok());
  EXPECT_EQ(side_files(), std::vector<std::string>{side});
  EXPECT_EQ(read_text(dir.path() / side), side_bytes);
  // (the fresh copy's joints have other uuids: the JSON differs only there)
  ASSERT_TRUE(write_skin_weights(file, painted, WeightsFormat::kBinary).is_ok());
  EXPECT_EQ(read_text(file), json) << "byte for byte";

  // A repaint: a new side file, the old one removed once the pair is written.
  paint(*s, 200, 5);
  ASSERT_TRUE(write_skin_weights(file, *capture_skin_weights(*s), WeightsFormat::kBinary).is_ok());
  ASSERT_EQ(side_files().size(), 1u);
  EXPECT_NE(side_files()[0], side);
  EXPECT_NEAR(weight_of((*read_skin_weights(file))[0], 200, painted[0].influences[5].joint), 1.0, 1e-12);
  // Back to JSON: the side file goes too.
  ASSERT_TRUE(write_skin_weights(file, painted, WeightsFormat::kJson).is_ok());
  EXPECT_TRUE(side_files().empty());
  EXPECT_EQ(read_text(file), skin_weights_to_json(painted));

  // Refused: a changed byte, a short file, a missing one, a path elsewhere,
  // and a side file with nothing to read it.
  ASSERT_TRUE(write_skin_weights(file, painted, WeightsFormat::kBinary).is_ok());
  const fs::path bin = dir.path() / side_files()[0];
  std::string bytes = read_text(bin);
  const auto refused = [&](const std::string& member) {
    auto r = read_skin_weights(file);
    EXPECT_FALSE(r.is_ok()) << member;
    if (r.is_ok()) return;
    EXPECT_NE(r.status().message().find(file.string()), std::string::npos) << r.status().message();
    EXPECT_NE(r.status().message().find(member), std::string::npos) << r.status().message();
  };
  bytes[bytes.size() / 2] ^= 0x10;
  write_text(bin, bytes);
  refused("binary.checksum");
  write_text(bin, bytes.substr(0, bytes.size() - 8));
  refused("binary.bytes");
  fs::remove(bin);
  refused("binary.file");
  std::string outside = json;
  outside.replace(outside.find(side), side.size(), "../" + side);
  write_text(file, outside);
  refused("not a plain file name");
  EXPECT_NE(skin_weights_from_json(json, "w.json").status().message().find("nothing reads one"), std::string::npos);
  EXPECT_EQ(weights_format_named("xml").status().field(), "format");
}

TEST(SkinWeightsData, bad_files_and_mismatches_are_refused) {
  auto s = body();
  ASSERT_TRUE(s);
  EXPECT_NE(skin_weights_from_json("{\"rigelWeights\": 1,\n \"skins\": [}", "w.json").status().message().find("w.json:2:"), std::string::npos);
  EXPECT_NE(skin_weights_from_json(R"({"rigelWeights": 1, "skins": [{"skin": "a", "mesh": "b", "influences": [], "vertices": [[0, 1]]}]})", "w.json")
                .status().message().find("skins[0].vertices[0]"),
            std::string::npos);
  EXPECT_EQ(skin_weights_from_json(R"({"rigelWeights": 9, "skins": []})", "w.json").status().code(), ErrorCode::kFailedPrecondition);
  auto skins = *capture_skin_weights(*s);
  skins[0].offsets.resize(101);
  auto r = apply_skin_weights(*s, skins);
  ASSERT_FALSE(r.is_ok());
  EXPECT_EQ(r.status().field(), "skin");
  EXPECT_NE(r.status().message().find("100 vertices in the file"), std::string::npos);
  scene::Scene empty;
  EXPECT_FALSE(capture_skin_weights(empty).is_ok());
}

TEST(ControlShapesData, hand_drawn_shapes_come_back_on_a_rebuilt_rig) {
  auto s = testing::built_rig();
  ASSERT_TRUE(s);
  graph::Graph& g = s->graph();
  const NodeId rig = rig::find_rig(g, "hero");
  const NodeId ik = testing::at(g, "hero:arm_L/ik");
  ControlLook drawn{{Vec3(0, 0, 0), Vec3(0.1, 0.2, 0.05), Vec3(-0.1, 0.1, 0)}, false, Vec3(0.2, 0.9, 0.4)};
  ASSERT_TRUE(paste_control_look(g, {ik}, drawn).is_ok());
  auto shapes = capture_control_shapes(g, rig);
  ASSERT_TRUE(shapes.is_ok()) << shapes.status().message();
  EXPECT_GT(shapes->controls.size(), 50u);
  const std::string file = control_shapes_to_json(*shapes);
  // A rebuild from scratch: the shapes as the definition says, then the file's.
  auto fresh = testing::built_rig();
  const NodeId fresh_rig = rig::find_rig(fresh->graph(), "hero");
  EXPECT_NE(control_look(fresh->graph(), testing::at(fresh->graph(), "hero:arm_L/ik"))->points, drawn.points);
  auto back = control_shapes_from_json(file, "hero.shapes.json");
  ASSERT_TRUE(back.is_ok()) << back.status().message();
  auto r = apply_control_shapes(fresh->graph(), fresh_rig, *back);
  ASSERT_TRUE(r.is_ok()) << r.status().message();
  EXPECT_EQ(r->set, shapes->controls.size());
  EXPECT_TRUE(r->missing.empty());
  const ControlLook got = *control_look(fresh->graph(), testing::at(fresh->graph(), "hero:arm_L/ik"));
  EXPECT_EQ(got.points, drawn.points);
  EXPECT_EQ(got.color, drawn.color);
  EXPECT_FALSE(got.closed);
  EXPECT_EQ(control_shapes_to_json(*capture_control_shapes(fresh->graph(), fresh_rig)), file) << "byte for byte";
  // A file naming a component the rig lacks: reported, the rest set.
  back->controls[0].rig_id = "00000000-0000-0000-0000-000000000000";
  r = apply_control_shapes(fresh->graph(), fresh_rig, *back);
  ASSERT_TRUE(r.is_ok());
  EXPECT_EQ(r->missing.size(), 1u);
  EXPECT_NE(control_shapes_from_json("{\"rigelShapes\": 1, \"rig\": \"hero\", \"controls\": [{\"rigId\": 3}]}", "s.json")
                .status().message().find("controls[0].rigId"),
            std::string::npos);
}

}  // namespace
}  // namespace rigel::tools
