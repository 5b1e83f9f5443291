// The pose library (tools/poses.h) on the biped of examples/biped.rig.xml
// built on the metarig: a pose saved on one character applies to another
// built from the same definition and to the first rebuilt with a renamed
// component; a mirrored apply is the mirror of the applied pose; fractions
// blend from the current pose; files round-trip, diff line by line, and bad
// input is refused naming what is wrong, changing nothing.

#include "rigel/tools/poses.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "rigel/math/rotation.h"
#include "rigel/ops/ik/nodes.h"
#include "rigel/rig/manager.h"
#include "rigel/rig/meta.h"
#include "rigel/scene/transform_types.h"
#include "rigel/tools/keys.h"
#include "rigel/tools/mirror.h"
#include "../io/io_test_util.h"
#include "tools_test_util.h"

namespace rigel::tools {
namespace {

namespace fs = std::filesystem;
using graph::NodeId;
using graph::Plug;
using graph::Value;
using math::Mat4;
using math::Quat;
using math::Vec3;
using testing::at;
namespace xform = scene::xform;

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream b;
  b << in.rdbuf();
  return b.str();
}

// The biped definition with `edit` applied, written into `dir` (without its
// geo line: the fixture imports the character itself).
fs::path edited_biped(const fs::path& dir, const std::string& file, std::string (*edit)(std::string)) {
  std::string text = read_text(testing::source("examples/biped.rig.xml"));
  const std::size_t geo = text.find("<geo ");
  text.erase(geo, text.find('\n', geo) - geo);
  const fs::path out = dir / file;
  std::ofstream(out) << edit(std::move(text));
  return out;
}

std::string rename_left_arm(std::string t) {
  const std::string from = R"(name="arm" side="L")";
  t.replace(t.find(from), from.size(), R"(name="wing" side="L")");
  return t;
}

// Every rigId's first digit changed: a rig that looks the same and is not.
std::string other_rig_ids(std::string t) {
  for (std::size_t at = t.find("rigId=\""); at != std::string::npos; at = t.find("rigId=\"", at + 1)) {
    char& c = t[at + 7];
    c = c == 'f' ? '0' : c == '9' ? 'a' : static_cast<char>(c + 1);
  }
  return t;
}

const std::vector<std::string> kPosed = {"hero:arm_L/fk[0]", "hero:arm_L/fk[1]", "hero:arm_L/ik", "hero:arm_R/fk[1]",
                                         "hero:leg_L/ik",    "hero:foot_L/foot", "hero:hip/main", "hero:global/main"};

// An asymmetric pose: controls turned, moved and scaled, the left arm's
// switch half way and the right one at IK.
void pose_character(scene::Scene& s) {
  graph::Graph& g = s.graph();
  int i = 0;
  for (const std::string& a : kPosed) {
    const NodeId c = at(g, a);
    ++i;
    ASSERT_TRUE(g.set_value(Plug{c, xform::kRotate, -1}, Value(Vec3(7.0 * i, -11.0 + 3 * i, 5.0 - 2 * i))).is_ok()) << a;
    ASSERT_TRUE(g.set_value(Plug{c, xform::kTranslate, -1}, Value(Vec3(0.01 * i, -0.02, 0.015 * i))).is_ok()) << a;
  }
  ASSERT_TRUE(g.set_value(Plug{at(g, "hero:arm_L/fk[0]"), xform::kScale, -1}, Value(Vec3(1.1, 0.9, 1.05))).is_ok());
  const NodeId sw = at(g, "hero:arm_L/fkIkSwitch");
  ASSERT_TRUE(g.set_value(Plug{sw, g.node(sw)->type().attr_find("fkIk"), -1}, Value(0.5)).is_ok());
}

NodeId hero(const graph::Graph& g) { return rig::find_rig(g, "hero"); }

std::vector<NodeId> controls_of(const graph::Graph& g) {
  std::vector<NodeId> out;
  for (NodeId meta : rig::rig_components(g, hero(g)))
    for (NodeId m : rig::meta_members(g, meta))
      if (g.node(m)->type().name() == scene::kControlType) out.push_back(m);
  return out;
}

// The controls' world positions by address (names play no part).
std::map<std::string, Vec3> positions(scene::Scene& s) {
  std::map<std::string, Vec3> out;
  for (NodeId c : controls_of(s.graph())) out[*rig::address_of(s.graph(), c)] = s.world_matrix(c).topRightCorner<3, 1>();
  return out;
}

double worst(const std::map<std::string, Vec3>& a, const std::map<std::string, Vec3>& b) {
  double w = 0;
  for (const auto& [k, p] : a) {
    auto it = b.find(k);
    if (it == b.end()) return 1e300;
    w = std::max(w, (p - it->second).norm());
  }
  return a.size() == b.size() ? w : 1e300;
}

Pose character_pose(scene::Scene& s, const std::string& name = "shot") {
  auto p = capture_pose(s.graph(), {hero(s.graph())}, name);
  EXPECT_TRUE(p.is_ok()) << p.status().message();
  return p ? *p : Pose{};
}

TEST(Poses, a_pose_applies_to_another_character_built_from_the_same_definition) {
  auto a = testing::built_rig(), b = testing::built_rig();
  pose_character(*a);
  const Pose pose = character_pose(*a);
  EXPECT_EQ(pose.rig, "hero");
  EXPECT_GT(pose.entries.size(), controls_of(a->graph()).size() / 2) << "the whole character";
  EXPECT_GT(worst(positions(*a), positions(*b)), 1e-3) << "the second character is at rest";
  auto r = apply_pose(b->graph(), pose, hero(b->graph()), {});
  ASSERT_TRUE(r.is_ok()) << r.status().message();
  EXPECT_LT(worst(positions(*a), positions(*b)), 1e-9);
  const NodeId sw = at(b->graph(), "hero:arm_L/fkIkSwitch");
  EXPECT_EQ(std::get<double>(b->graph().evaluate(sw, b->graph().node(sw)->type().attr_find("fkIk"))), 0.5);
  EXPECT_EQ(b->graph().undo_label(), "apply pose 'shot'") << "one undo step";
  ASSERT_TRUE(b->graph().undo());
  EXPECT_GT(worst(positions(*a), positions(*b)), 1e-3) << "undone: back at rest";
}

TEST(Poses, a_pose_still_applies_after_its_rig_is_rebuilt_with_a_renamed_component) {
  io::testing::TempDir dir;
  auto a = testing::built_rig(), b = testing::built_rig();
  pose_character(*a);
  const Pose pose = character_pose(*a);
  ASSERT_TRUE(apply_pose(b->graph(), pose, hero(b->graph()), {}).is_ok());
  const fs::path renamed = edited_biped(dir.path(), "renamed.rig.xml", rename_left_arm);
  auto u = rig::update_rig(*a, "hero", ephemeral::components(), renamed, true);
  ASSERT_TRUE(u.is_ok()) << u.status().message();
  graph::Graph& g = a->graph();
  ASSERT_TRUE(rig::find_component(g, hero(g), "wing_L").is_valid()) << "the component is renamed";
  ASSERT_TRUE(at(g, "hero:wing_L/fk[0]").is_valid());
  auto r = apply_pose(g, pose, hero(g), {});
  ASSERT_TRUE(r.is_ok()) << r.status().message();
  // Same rigIds, roles and indices: the same world pose as the other character.
  std::map<std::string, Vec3> pa = positions(*a), pb = positions(*b);
  for (auto& [k, p] : pb)
    if (k.rfind("hero:arm_L/", 0) == 0) pa.emplace(k, pa.at("hero:wing_L/" + k.substr(11)));
  for (auto it = pa.begin(); it != pa.end();) it = it->first.rfind("hero:wing_L/", 0) == 0 ? pa.erase(it) : std::next(it);
  EXPECT_LT(worst(pa, pb), 1e-9);
}

// Channels of the nodes set, as matrices (transforms) or values.
std::map<std::string, std::vector<double>> channel_values(graph::Graph& g, const std::vector<NodeId>& nodes) {
  std::map<std::string, std::vector<double>> out;
  for (NodeId n : nodes) {
    std::vector<double>& v = out[*rig::address_of(g, n)];
    if (g.node(n)->type().world_output() != graph::kNoAttr) {
      const Mat4 m = std::get<Mat4>(g.evaluate(n, xform::kMatrix));
      v.assign(m.data(), m.data() + 16);
    }
    for (graph::AttrIndex a : keyable_attrs(*g.node(n)))
      if (const auto* d = std::get_if<double>(&g.evaluate(n, a))) v.push_back(*d);
  }
  return out;
}

double worst_values(const std::map<std::string, std::vector<double>>& a, const std::map<std::string, std::vector<double>>& b) {
  double w = 0;
  for (const auto& [k, v] : a) {
    const std::vector<double>& u = b.at(k);
    if (u.size() != v.size()) return 1e300;
    for (std::size_t i = 0; i < v.size(); ++i) w = std::max(w, std::abs(v[i] - u[i]));
  }
  return w;
}

TEST(Poses, a_mirrored_apply_is_the_mirror_of_the_applied_pose) {
  auto a = testing::built_rig(), mirrored = testing::built_rig(), flipped = testing::built_rig();
  pose_character(*a);
  const Pose pose = character_pose(*a);
  ApplyPoseOptions o;
  o.mirrored = true;
  auto r = apply_pose(mirrored->graph(), pose, hero(mirrored->graph()), o);
  ASSERT_TRUE(r.is_ok()) << r.status().message();
  EXPECT_FALSE(r->unpaired.empty()) << "the ears (an ikChain and a tail) have no pair";
  EXPECT_GT(r->set.size(), 40u) << "both sides and the centre";
  ASSERT_TRUE(apply_pose(flipped->graph(), pose, hero(flipped->graph()), {}).is_ok());
  MirrorOptions flip;
  flip.all = true;
  flip.flip = true;
  flip.key = false;
  ASSERT_TRUE(mirror(*flipped, flip).is_ok());
  std::vector<NodeId> same;
  for (NodeId n : r->set) same.push_back(at(flipped->graph(), *rig::address_of(mirrored->graph(), n)));
  EXPECT_LT(worst_values(channel_values(mirrored->graph(), r->set), channel_values(flipped->graph(), same)), 1e-9);
  // The right arm's switch took the left one's value.
  const NodeId sw = at(mirrored->graph(), "hero:arm_R/fkIkSwitch");
  EXPECT_EQ(std::get<double>(mirrored->graph().evaluate(sw, mirrored->graph().node(sw)->type().attr_find("fkIk"))), 0.5);
}

TEST(Poses, a_fraction_blends_from_the_current_pose) {
  auto a = testing::built_rig(), b = testing::built_rig();
  graph::Graph& ga = a->graph();
  const NodeId fk0 = at(ga, "hero:arm_L/fk[0]");
  ASSERT_TRUE(ga.set_value(Plug{fk0, xform::kRotate, -1}, Value(Vec3(40, 0, 0))).is_ok());
  ASSERT_TRUE(ga.set_value(Plug{fk0, xform::kTranslate, -1}, Value(Vec3(0.1, 0, -0.2))).is_ok());
  pose_character(*a);  // fk0 moved again: take the controls' values now
  const Vec3 t = std::get<Vec3>(ga.evaluate(fk0, xform::kTranslate));
  const math::RotateOrder order =
      static_cast<math::RotateOrder>(std::get<std::int64_t>(ga.evaluate(fk0, xform::kRotateOrder)));
  const Quat q = math::euler_to_quat(math::to_radians(std::get<Vec3>(ga.evaluate(fk0, xform::kRotate))), order);
  const Pose pose = character_pose(*a);
  graph::Graph& g = b->graph();
  const auto rest = positions(*b);
  ApplyPoseOptions o;
  o.fraction = 0;
  ASSERT_TRUE(apply_pose(g, pose, hero(g), o).is_ok());
  EXPECT_EQ(worst(positions(*b), rest), 0) << "fraction 0 changes nothing";
  EXPECT_FALSE(g.can_undo()) << "and makes no undo step";
  o.fraction = 0.5;
  ASSERT_TRUE(apply_pose(g, pose, hero(g), o).is_ok());
  const NodeId b0 = at(g, "hero:arm_L/fk[0]");
  EXPECT_LT((std::get<Vec3>(g.evaluate(b0, xform::kTranslate)) - 0.5 * t).norm(), 1e-12) << "translate: halfway";
  const Quat half = math::euler_to_quat(math::to_radians(std::get<Vec3>(g.evaluate(b0, xform::kRotate))), order);
  EXPECT_LT(half.angularDistance(Quat::Identity().slerp(0.5, q)), 1e-9) << "rotation: slerp halfway";
  EXPECT_NEAR(half.angularDistance(Quat::Identity()), 0.5 * q.angularDistance(Quat::Identity()), 1e-9);
  ASSERT_TRUE(g.undo());
  o.fraction = 1;
  ASSERT_TRUE(apply_pose(g, pose, hero(g), o).is_ok());
  EXPECT_LT(worst(positions(*b), positions(*a)), 1e-9) << "fraction 1 is the whole pose";
  o.fraction = 1.5;
  auto over = apply_pose(g, pose, hero(g), o);
  ASSERT_FALSE(over.is_ok());
  EXPECT_EQ(over.status().field(), "fraction");
}

TEST(Poses, a_selection_applies_only_to_its_controls_and_keys_when_asked) {
  auto a = testing::built_rig(), b = testing::built_rig();
  pose_character(*a);
  const Pose pose = character_pose(*a);
  graph::Graph& g = b->graph();
  const NodeId fk0 = at(g, "hero:arm_L/fk[0]"), ik = at(g, "hero:leg_L/ik");
  ApplyPoseOptions o;
  o.controls = {fk0};
  o.key = true;
  g.set_time(10 / g.fps());
  auto r = apply_pose(g, pose, hero(g), o);
  ASSERT_TRUE(r.is_ok()) << r.status().message();
  ASSERT_EQ(r->set, std::vector<NodeId>{fk0});
  EXPECT_EQ(r->keyed, r->channels);
  EXPECT_EQ(std::get<Vec3>(g.evaluate(ik, xform::kTranslate)), Vec3::Zero()) << "outside the selection";
  const auto keys = keys_of(g, {Channel{fk0, xform::kTranslate}});
  ASSERT_FALSE(keys.empty());
  EXPECT_NEAR(keys[0].times.at(0) * g.fps(), 10, 1e-9);
  // A keyed channel takes a key at the time even when not asked to key:
  // a set value would not hold against its curve.
  g.set_time(20 / g.fps());
  o.key = false;
  o.fraction = 0.5;
  auto again = apply_pose(g, pose, hero(g), o);
  ASSERT_TRUE(again.is_ok());
  EXPECT_EQ(again->keyed, again->channels);
  EXPECT_EQ(keys_of(g, {Channel{fk0, xform::kTranslate}}).at(0).times.size(), 2u);
}

TEST(Poses, save_list_and_remove_round_trip_in_diffable_files) {
  io::testing::TempDir dir;
  const fs::path library = dir.path() / "poses";
  auto a = testing::built_rig();
  pose_character(*a);
  graph::Graph& g = a->graph();
  // An infinite channel (a solver's maxStretch: no limit) is written as
  // "inf" (JSON has no infinity) and read back as infinity.
  ASSERT_TRUE(g.set_value(Plug{at(g, "hero:leg_L/ikSolver"), ops::ik::two_bone_attr::kMaxStretch, -1},
                          Value(std::numeric_limits<double>::infinity()))
                  .is_ok());
  auto saved = save_pose(g, {hero(g)}, "shot", library);
  ASSERT_TRUE(saved.is_ok()) << saved.status().message();
  EXPECT_EQ(saved->path, library / "shot.pose.json");
  const std::string text = read_text(saved->path);
  EXPECT_NE(text.find("\n  \"rig\": \"hero\",\n"), std::string::npos) << text.substr(0, 400);
  EXPECT_NE(text.find("\n      \"rigId\": \"8e81973e-0bec-47b0-b898-d190f9ebdacc\",\n"), std::string::npos)
      << "one member per line";
  EXPECT_NE(text.find("\n        \"translate\": ["), std::string::npos) << "a vector on its line";
  EXPECT_NE(text.find("\"maxStretch\": \"inf\""), std::string::npos) << "infinity as a string";
  // A selection given in any order gives the same file.
  const std::vector<NodeId> sel = {at(g, "hero:leg_L/ik"), at(g, "hero:arm_L/fk[1]"), at(g, "hero:arm_L/fk[0]")};
  ASSERT_TRUE(save_pose(g, sel, "sel", library).is_ok());
  ASSERT_TRUE(save_pose(g, {sel[2], sel[0], sel[1]}, "sel2", library).is_ok());
  std::string one = read_text(library / "sel.pose.json"), two = read_text(library / "sel2.pose.json");
  two.replace(two.find("\"sel2\""), 6, "\"sel\"");
  EXPECT_EQ(one, two);
  auto loaded = load_pose(library, "shot");
  ASSERT_TRUE(loaded.is_ok()) << loaded.status().message();
  EXPECT_EQ(pose_to_json(*loaded), text) << "read and written back: the same text";
  auto list = list_poses(library);
  ASSERT_TRUE(list.is_ok());
  ASSERT_EQ(list->size(), 3u);
  EXPECT_EQ((*list)[0].name, "sel");
  EXPECT_EQ((*list)[0].entries, 3u);
  EXPECT_EQ((*list)[2].name, "shot");
  EXPECT_EQ((*list)[2].rig, "hero");
  ASSERT_TRUE(remove_pose(library, "sel2").is_ok());
  EXPECT_FALSE(fs::exists(library / "sel2.pose.json"));
  auto gone = remove_pose(library, "sel2");
  EXPECT_EQ(gone.code(), ErrorCode::kNotFound);
  EXPECT_EQ(list_poses(library)->size(), 2u);
}

TEST(Poses, bad_input_is_refused_naming_the_thing_and_changing_nothing) {
  io::testing::TempDir dir;
  const fs::path library = dir.path() / "poses";
  auto a = testing::built_rig();
  pose_character(*a);
  graph::Graph& g = a->graph();
  ASSERT_TRUE(save_pose(g, {hero(g)}, "shot", library).is_ok());
  // Unsafe names: nothing outside the library is read or written.
  for (const std::string name : {"../escape", "a/b", "a\\b", ".hidden", "", "x y"}) {
    auto s = save_pose(g, {hero(g)}, name, library);
    ASSERT_FALSE(s.is_ok()) << name;
    EXPECT_EQ(s.status().field(), "name") << name;
    EXPECT_EQ(load_pose(library, name).status().field(), "name") << name;
  }
  EXPECT_FALSE(fs::exists(dir.path() / "escape.pose.json"));
  EXPECT_FALSE(fs::exists(library / "a"));
  auto unknown = load_pose(library, "nope");
  EXPECT_EQ(unknown.status().code(), ErrorCode::kNotFound);
  EXPECT_NE(unknown.status().message().find("nope"), std::string::npos);
  // Malformed files name the file and the place.
  std::ofstream(library / "broken.pose.json") << "{\n  \"format\": \"rigel pose\",\n  \"version\": 1,\n  oops\n}\n";
  auto broken = load_pose(library, "broken");
  ASSERT_FALSE(broken.is_ok());
  EXPECT_NE(broken.status().message().find("broken.pose.json:4:"), std::string::npos) << broken.status().message();
  std::string text = read_text(library / "shot.pose.json");
  const std::size_t rot = text.find("\"rotation\": [");
  text.replace(text.find('[', rot), text.find(']', rot) - text.find('[', rot) + 1, "[0, 0, 1]");
  std::ofstream(library / "bad.pose.json") << text;
  auto bad = load_pose(library, "bad");
  ASSERT_FALSE(bad.is_ok());
  EXPECT_NE(bad.status().message().find("bad.pose.json: entries[0].channels.rotation: expected 4 numbers"), std::string::npos)
      << bad.status().message();
  auto list = list_poses(library);
  ASSERT_TRUE(list.is_ok());
  EXPECT_FALSE((*list)[0].error.empty()) << "the bad file is listed with its error";
  // A pose of another rig: same names, other rigIds.
  auto other = testing::built_rig(edited_biped(dir.path(), "other.rig.xml", other_rig_ids));
  graph::Graph& go = other->graph();
  const std::size_t nodes = go.nodes().size();
  const Pose pose = *load_pose(library, "shot");
  auto wrong = apply_pose(go, pose, hero(go), {});
  ASSERT_FALSE(wrong.is_ok());
  EXPECT_EQ(wrong.status().field(), "rig");
  EXPECT_NE(wrong.status().message().find(pose.entries[0].rig_id), std::string::npos) << wrong.status().message();
  EXPECT_NE(wrong.status().message().find(pose.entries[0].role), std::string::npos) << wrong.status().message();
  EXPECT_FALSE(go.can_undo());
  EXPECT_EQ(go.nodes().size(), nodes);
  // A selection the pose does not cover, or that is not a rig's control.
  auto b = testing::built_rig();
  ApplyPoseOptions o;
  o.controls = {b->graph().find("hand.L")};
  auto stray = apply_pose(b->graph(), pose, hero(b->graph()), o);
  ASSERT_FALSE(stray.is_ok());
  EXPECT_EQ(stray.status().field(), "controls");
  EXPECT_NE(stray.status().message().find("hand.L"), std::string::npos) << stray.status().message();
  EXPECT_FALSE(b->graph().can_undo());
  auto joint = capture_pose(g, {g.find("hand.L")}, "x");
  ASSERT_FALSE(joint.is_ok());
  EXPECT_EQ(joint.status().field(), "controls");
}

}  // namespace
}  // namespace rigel::tools

namespace rigel::tools {
namespace {

// The thumbnail: one line per joint with a parent joint, inside the
// picture, the same bytes for the same pose and other bytes for another;
// written beside the pose, listed, read back and removed with it.
TEST(PoseThumbnails, a_front_view_of_the_skeleton_in_the_pose) {
  auto s = testing::built_rig();
  ASSERT_TRUE(s);
  graph::Graph& g = s->graph();
  std::size_t bones = 0;
  for (graph::NodeId id : s->hierarchy())
    if (g.node(id)->type().name() == scene::kJointType && g.node(g.parent(id)) &&
        g.node(g.parent(id))->type().name() == scene::kJointType)
      ++bones;
  const std::string rest = skeleton_thumbnail_svg(*s);
  std::size_t lines = 0;
  for (std::size_t at = rest.find("<line "); at != std::string::npos; at = rest.find("<line ", at + 1)) ++lines;
  EXPECT_EQ(lines, bones);
  EXPECT_EQ(rest.rfind("<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 96 128\"", 0), 0u);
  // Every coordinate inside the picture.
  for (const char* attr : {"x1=\"", "x2=\"", "y1=\"", "y2=\""})
    for (std::size_t at = rest.find(attr); at != std::string::npos; at = rest.find(attr, at + 1)) {
      const double v = std::stod(rest.substr(at + 4));
      EXPECT_GE(v, 0.0);
      EXPECT_LE(v, attr[0] == 'x' ? 96.0 : 128.0);
    }
  EXPECT_EQ(skeleton_thumbnail_svg(*s), rest) << "the same pose, the same bytes";
  ASSERT_TRUE(g.set_value({testing::at(g, "hero:arm_L/fk[0]"), xform::kRotate}, graph::Value(Vec3(0, 0, 70))).is_ok());
  EXPECT_NE(skeleton_thumbnail_svg(*s), rest) << "another pose, another picture";

  io::testing::TempDir dir;
  const fs::path library = dir.path() / "poses";
  ASSERT_TRUE(save_pose(g, {rig::find_rig(g, "hero")}, "raised", library).is_ok());
  ASSERT_TRUE(save_pose_thumbnail(*s, library, "raised").is_ok());
  EXPECT_EQ(*load_pose_thumbnail(library, "raised"), skeleton_thumbnail_svg(*s));
  auto list = list_poses(library);
  ASSERT_TRUE(list.is_ok());
  ASSERT_EQ(list->size(), 1u) << "the thumbnail is not a pose";
  EXPECT_TRUE(list->front().thumbnail);
  ASSERT_TRUE(remove_pose(library, "raised").is_ok());
  EXPECT_FALSE(fs::exists(library / "raised.pose.svg"));
  EXPECT_EQ(load_pose_thumbnail(library, "raised").status().field(), "name");
  EXPECT_EQ(save_pose_thumbnail(*s, library, "../x").field(), "name");
}

}  // namespace
}  // namespace rigel::tools
