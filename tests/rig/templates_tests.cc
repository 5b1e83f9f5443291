#include "rigel/rig/templates.h"

#include <gtest/gtest.h>

#include <random>
#include <set>
#include <string>
#include <vector>

#include "rigel/math/rotation.h"

namespace rigel::rig {
namespace {

using math::Vec3;
using math::Vec4;

// ---- building definitions in code ------------------------------------------

Guide guide(std::string name, std::string joint, Vec3 translate, Vec3 rotate) {
  Guide g;
  g.name = std::move(name);
  g.joint = std::move(joint);
  g.translate = translate;
  g.rotate = rotate;
  g.scale = Vec3(1, 1.5, 1);
  return g;
}

Component component(std::string type, std::string name, Side side, std::string attach = "") {
  Component c;
  c.type = std::move(type);
  c.name = std::move(name);
  c.side = side;
  c.rig_id = new_rig_id();
  c.attach = std::move(attach);
  return c;
}

// global > spine > {arm_L > hand_L > {index_L, thumb_L}, head}
Definition biped() {
  Definition rig;
  rig.name = "biped";
  rig.version = "2.3";
  Component global = component("global", "global", Side::kCenter);
  Component spine = component("spine", "spine", Side::kCenter);
  spine.guides = {guide("0", "hips", Vec3(0, 1, 0), Vec3(0, 0, 90)), guide("1", "chest", Vec3(0, 1.4, 0), Vec3(0, 0, 90))};
  Component arm = component("arm", "arm_L", Side::kLeft, "spine.END");
  arm.version = "1.4";
  arm.guides = {guide("start", "upperarm_L", Vec3(0.2, 1.4, 0.01), Vec3(10, -20, 30)),
                guide("mid", "lowerarm_L", Vec3(0.5, 1.4, -0.03), Vec3(170, 100, -30)),
                guide("end", "hand_L", Vec3(0.8, 1.4, 0), Vec3(-45, 0.5, 12.25))};
  arm.params = {{"stretch", true, {}}, {"twistJoints", std::int64_t{3}, {}}, {"softness", 0.25, {}},
                {"poleJoint", std::string("lowerarm_L"), {}}, {"poleOffset", Vec3(0, 0, -0.5), {}}};
  arm.controls = {{"fk", "circle", "blue", 0.3, {}}, {"ik", "cube", "#3366ff", 0.2, {}}};
  arm.features = {{"ik", true, {{"stretch", false, {}}}, {}}};
  arm.gui_location = std::make_pair(120.0, 40.0);
  Component hand = component("hand", "hand_L", Side::kLeft, "END");
  hand.guides = {guide("root", "hand_L", Vec3(0.8, 1.4, 0), Vec3(0, 0, 5))};
  Component index = component("finger", "index_L", Side::kLeft, "hand_L.root");
  index.guides = {guide("0", "index_01_L", Vec3(0.9, 1.41, 0.02), Vec3(1, 2, 3))};
  Component thumb = component("finger", "thumb_L", Side::kLeft, "arm_L.END");
  thumb.guides = {guide("0", "thumb_01_L", Vec3(0.85, 1.38, 0.05), Vec3(-60, 15, 40))};
  hand.children = {index, thumb};
  arm.children = {hand};
  Component head = component("head", "head", Side::kCenter, "END");
  spine.children = {arm, head};
  global.children = {spine};
  rig.components = {global};
  return rig;
}

// A second rig without arms to inject into.
Definition torso() {
  Definition rig;
  rig.name = "torso";
  Component global = component("global", "global", Side::kCenter);
  Component spine = component("spine", "spine", Side::kCenter);
  global.children = {spine};
  rig.components = {global};
  return rig;
}

const Component& by_name(const Definition& rig, std::string_view name) {
  const Component* c = rig.find_by_name(name);
  EXPECT_NE(c, nullptr) << "the rig has " << name;
  static const Component kNone;
  return c ? *c : kNone;
}

// ---- comparisons --------------------------------------------------------------

::testing::AssertionResult same_guides(const std::vector<Guide>& a, const std::vector<Guide>& b) {
  if (a.size() != b.size()) return ::testing::AssertionFailure() << a.size() << " vs " << b.size() << " guides";
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].name != b[i].name || a[i].joint != b[i].joint || a[i].translate != b[i].translate ||
        a[i].rotate != b[i].rotate || a[i].scale != b[i].scale)
      return ::testing::AssertionFailure() << "guide " << i << " (" << a[i].name << ") differs";
  }
  return ::testing::AssertionSuccess();
}

::testing::AssertionResult same_data(const Component& a, const Component& b) {
  if (a.type != b.type || a.version != b.version) return ::testing::AssertionFailure() << a.name << ": type/version";
  if (!same_guides(a.guides, b.guides)) return ::testing::AssertionFailure() << a.name << ": " << same_guides(a.guides, b.guides).message();
  if (a.params.size() != b.params.size()) return ::testing::AssertionFailure() << a.name << ": param count";
  for (std::size_t i = 0; i < a.params.size(); ++i)
    if (a.params[i].name != b.params[i].name || !(a.params[i].value == b.params[i].value))
      return ::testing::AssertionFailure() << a.name << ": param " << a.params[i].name;
  if (a.controls.size() != b.controls.size()) return ::testing::AssertionFailure() << a.name << ": control count";
  for (std::size_t i = 0; i < a.controls.size(); ++i)
    if (a.controls[i].role != b.controls[i].role || a.controls[i].shape != b.controls[i].shape ||
        a.controls[i].color != b.controls[i].color || a.controls[i].size != b.controls[i].size)
      return ::testing::AssertionFailure() << a.name << ": control " << a.controls[i].role;
  if (a.features.size() != b.features.size()) return ::testing::AssertionFailure() << a.name << ": feature count";
  for (std::size_t i = 0; i < a.features.size(); ++i) {
    if (a.features[i].name != b.features[i].name || a.features[i].enabled != b.features[i].enabled ||
        a.features[i].switches.size() != b.features[i].switches.size())
      return ::testing::AssertionFailure() << a.name << ": feature " << a.features[i].name;
  }
  return ::testing::AssertionSuccess();
}

// Whole sub-trees equal in every field but rig ids (and `attach` of the
// roots, which injection sets).
::testing::AssertionResult same_except_ids(const Component& a, const Component& b, bool compare_attach = true) {
  if (a.name != b.name || a.side != b.side || a.gui_location != b.gui_location)
    return ::testing::AssertionFailure() << a.name << " vs " << b.name << ": name/side/gui location";
  if (compare_attach && a.attach != b.attach)
    return ::testing::AssertionFailure() << a.name << ": attach " << a.attach << " vs " << b.attach;
  if (auto r = same_data(a, b); !r) return r;
  if (a.children.size() != b.children.size()) return ::testing::AssertionFailure() << a.name << ": child count";
  for (std::size_t i = 0; i < a.children.size(); ++i)
    if (auto r = same_except_ids(a.children[i], b.children[i]); !r) return r;
  return ::testing::AssertionSuccess();
}

std::vector<std::string> ids_of(const Component& root) {
  std::vector<std::string> ids;
  Definition d;
  d.components = {root};
  for (const Component* c : d.all_components()) ids.push_back(c->rig_id);
  return ids;
}

// ---- extract -------------------------------------------------------------------

TEST(Templates, extract_takes_the_sub_tree_with_its_ids) {
  const Definition rig = biped();
  const Component& arm = by_name(rig, "arm_L");
  Result<Definition> templ = extract_template(rig, arm.rig_id);
  ASSERT_TRUE(templ.is_ok()) << templ.status().message();
  EXPECT_EQ(templ->name, "arm_L") << "named after the component";
  EXPECT_EQ(templ->version, "1.4") << "the component's version";
  ASSERT_EQ(templ->components.size(), 1u) << "one root: the arm";
  EXPECT_TRUE(same_except_ids(templ->components[0], arm)) << "the whole sub-tree, hand and fingers";
  EXPECT_EQ(ids_of(templ->components[0]), ids_of(arm)) << "unique ids are kept, so updates can match them";
  EXPECT_TRUE(templ->geometry.empty() && templ->features.empty()) << "rig-level data stays with the rig";
  EXPECT_EQ(templ->all_components().size(), 4u) << "arm, hand, index, thumb";
}

TEST(Templates, extract_refuses_an_unknown_id) {
  const Definition rig = biped();
  Result<Definition> templ = extract_template(rig, new_rig_id());
  EXPECT_EQ(templ.status().code(), ErrorCode::kNotFound) << "no component has a fresh id";
  EXPECT_EQ(extract_template(rig, "").status().code(), ErrorCode::kNotFound) << "the empty id names nothing";
}

// ---- inject --------------------------------------------------------------------

TEST(Templates, extract_then_inject_gives_the_same_sub_tree_with_new_ids) {
  const Definition source = biped();
  const Component& arm = by_name(source, "arm_L");
  const Definition templ = *extract_template(source, arm.rig_id);
  Definition rig = torso();
  const std::string spine_id = by_name(rig, "spine").rig_id;
  ASSERT_TRUE(inject_template(rig, templ, spine_id, "END").is_ok());

  const Component& spine = by_name(rig, "spine");
  ASSERT_EQ(spine.children.size(), 1u) << "the arm is the spine's new child";
  const Component& injected = spine.children[0];
  EXPECT_EQ(injected.attach, "END") << "the root attaches where the caller said";
  EXPECT_TRUE(same_except_ids(injected, arm, false)) << "the same sub-tree";
  EXPECT_EQ(injected.children[0].children[1].attach, "arm_L.END") << "attach references inside are kept";
  std::set<std::string> ids;
  for (const Component* c : rig.all_components()) {
    EXPECT_TRUE(is_rig_id(c->rig_id)) << c->name << " has a valid id";
    EXPECT_TRUE(ids.insert(c->rig_id).second) << c->name << ": ids stay unique";
  }
  for (const std::string& id : ids_of(arm))
    EXPECT_EQ(rig.find_by_rig_id(id), nullptr) << "fresh ids by default, none from the template";
}

TEST(Templates, inject_twice_needs_new_names) {
  const Definition source = biped();
  const Definition templ = *extract_template(source, by_name(source, "arm_L").rig_id);
  Definition rig = torso();
  const std::string spine_id = by_name(rig, "spine").rig_id;
  ASSERT_TRUE(inject_template(rig, templ, spine_id, "END").is_ok());
  const std::size_t count = rig.all_components().size();

  Status again = inject_template(rig, templ, spine_id, "END");
  EXPECT_EQ(again.code(), ErrorCode::kAlreadyExists) << "the names are taken";
  EXPECT_NE(again.message().find("arm_L"), std::string::npos) << "names the clash: " << again.message();
  EXPECT_EQ(rig.all_components().size(), count) << "a refused injection changes nothing";

  InjectOptions suffixed;
  suffixed.name_suffix = "_2";
  ASSERT_TRUE(inject_template(rig, templ, spine_id, "END", suffixed).is_ok());
  EXPECT_EQ(rig.all_components().size(), count + 4) << "a second arm";
  for (const char* name : {"arm_L_2", "hand_L_2", "index_L_2", "thumb_L_2"})
    EXPECT_NE(rig.find_by_name(name), nullptr) << name << " injected under a suffixed name";
  EXPECT_EQ(by_name(rig, "thumb_L_2").attach, "arm_L_2.END") << "references inside the template follow the renaming";
  EXPECT_EQ(by_name(rig, "index_L_2").attach, "hand_L_2.root");
  EXPECT_EQ(by_name(rig, "arm_L_2").attach, "END");

  InjectOptions renamed;
  renamed.rename = [](std::string_view name) { return "extra_" + std::string(name); };
  ASSERT_TRUE(inject_template(rig, templ, spine_id, "END", renamed).is_ok());
  EXPECT_NE(rig.find_by_name("extra_hand_L"), nullptr) << "rename applies to every component";
  EXPECT_EQ(by_name(rig, "extra_thumb_L").attach, "extra_arm_L.END");

  InjectOptions collapse;
  collapse.rename = [](std::string_view) { return std::string("same"); };
  Status s = inject_template(rig, templ, spine_id, "END", collapse);
  EXPECT_EQ(s.code(), ErrorCode::kAlreadyExists) << "injected components may not share a name either";
  EXPECT_NE(s.message().find("same"), std::string::npos) << s.message();
  collapse.rename = [](std::string_view) { return std::string(); };
  EXPECT_EQ(inject_template(rig, templ, spine_id, "END", collapse).code(), ErrorCode::kInvalidArgument)
      << "an empty name is refused";
}

TEST(Templates, inject_keeping_ids_refuses_ids_already_in_the_rig) {
  const Definition source = biped();
  const Definition templ = *extract_template(source, by_name(source, "arm_L").rig_id);
  Definition rig = torso();
  InjectOptions keep;
  keep.new_ids = false;
  ASSERT_TRUE(inject_template(rig, templ, "", "", keep).is_ok()) << "ids the rig does not have yet";
  EXPECT_EQ(rig.components.size(), 2u) << "empty parent: a new root";
  EXPECT_EQ(rig.components[1].rig_id, templ.components[0].rig_id) << "ids kept";

  keep.name_suffix = "_2";
  const std::size_t count = rig.all_components().size();
  Status s = inject_template(rig, templ, "", "", keep);
  EXPECT_EQ(s.code(), ErrorCode::kAlreadyExists) << "the second injection would repeat the ids";
  EXPECT_NE(s.message().find(templ.components[0].rig_id), std::string::npos) << "names the id: " << s.message();
  EXPECT_EQ(rig.all_components().size(), count) << "nothing changed";
  keep.new_ids = true;
  EXPECT_TRUE(inject_template(rig, templ, "", "", keep).is_ok()) << "with new ids it goes in";
}

TEST(Templates, inject_refuses_bad_input) {
  const Definition source = biped();
  const Definition templ = *extract_template(source, by_name(source, "arm_L").rig_id);
  Definition rig = torso();
  EXPECT_EQ(inject_template(rig, templ, new_rig_id(), "END").code(), ErrorCode::kNotFound) << "unknown parent";
  EXPECT_EQ(inject_template(rig, Definition{}, "", "").code(), ErrorCode::kInvalidArgument) << "empty template";
  Definition repeated = templ;
  repeated.components[0].children[0].rig_id = repeated.components[0].rig_id;
  InjectOptions keep;
  keep.new_ids = false;
  EXPECT_EQ(inject_template(rig, repeated, "", "", keep).code(), ErrorCode::kInvalidArgument)
      << "a template that repeats an id cannot keep its ids";
  EXPECT_EQ(rig.all_components().size(), 2u) << "nothing changed";
}

// ---- update ---------------------------------------------------------------------

TEST(Templates, update_replaces_data_by_id_and_keeps_place_and_children) {
  Definition rig = biped();
  Definition templ = *extract_template(rig, by_name(rig, "arm_L").rig_id);
  // The rig grows a child of its own under the arm, and the template changes.
  Component extra = component("finger", "pinky_L", Side::kLeft, "END");
  rig.find_by_rig_id(by_name(rig, "arm_L").rig_id)->children.push_back(extra);
  Component& t_arm = templ.components[0];
  t_arm.type = "arm2";
  t_arm.version = "1.5";
  t_arm.name = "renamed_in_template";
  t_arm.attach = "START";
  t_arm.side = Side::kRight;
  t_arm.params = {{"stretch", false, {}}};
  t_arm.guides[1].translate = Vec3(0.55, 1.3, -0.1);
  t_arm.controls = {{"fk", "square", "red", 0.5, {}}};
  t_arm.features.clear();
  t_arm.children[0].guides[0].rotate = Vec3(0, 0, 10);  // the hand changes too
  Component only_in_template = component("finger", "ring_L", Side::kLeft, "END");
  t_arm.children[0].children.push_back(only_in_template);
  const Definition before = rig;

  ASSERT_TRUE(update_from_template(rig, templ).is_ok());
  const Component& arm = by_name(rig, "arm_L");
  EXPECT_TRUE(same_data(arm, t_arm)) << "type, version, params, guides, controls and features replaced";
  EXPECT_EQ(arm.name, "arm_L") << "the rig keeps its name";
  EXPECT_EQ(arm.attach, "spine.END") << "and its attach";
  EXPECT_EQ(arm.side, Side::kLeft) << "and its side";
  EXPECT_EQ(arm.gui_location, by_name(before, "arm_L").gui_location) << "and its node editor position";
  EXPECT_EQ(&by_name(rig, "spine").children[0], &arm) << "and its place";
  ASSERT_EQ(arm.children.size(), 2u) << "children kept: the hand and the rig's own pinky";
  EXPECT_EQ(arm.children[1].name, "pinky_L") << "a child the template does not know stays";
  EXPECT_TRUE(same_guides(arm.children[0].guides, t_arm.children[0].guides)) << "the hand, matched by id, is updated";
  EXPECT_EQ(rig.find_by_name("ring_L"), nullptr) << "template components not in the rig are not added";
  EXPECT_TRUE(same_except_ids(by_name(rig, "head"), by_name(before, "head"))) << "the rest is untouched";
}

TEST(Templates, update_refuses_a_template_that_matches_nothing) {
  Definition rig = biped();
  Definition other = biped();  // same shape, different ids
  const Definition templ = *extract_template(other, by_name(other, "arm_L").rig_id);
  EXPECT_EQ(update_from_template(rig, templ).code(), ErrorCode::kNotFound) << "no id in common";
  Definition repeated = *extract_template(rig, by_name(rig, "arm_L").rig_id);
  repeated.components[0].children[0].rig_id = repeated.components[0].rig_id;
  repeated.components[0].children[0].type = "changed";
  EXPECT_EQ(update_from_template(rig, repeated).code(), ErrorCode::kInvalidArgument) << "repeated ids are ambiguous";
  EXPECT_EQ(by_name(rig, "hand_L").type, "hand") << "nothing changed";
}

// ---- mirror ----------------------------------------------------------------------

TEST(Templates, mirror_name_swaps_side_tokens_on_word_boundaries) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"arm_L", "arm_R"},
      {"arm_R", "arm_L"},
      {"arm.L", "arm.R"},
      {"hand.L.END", "hand.R.END"},
      {"leftArm", "rightArm"},
      {"rightArm", "leftArm"},
      {"upperLeftArm", "upperRightArm"},
      {"arm_Left", "arm_Right"},
      {"arm_left_02", "arm_right_02"},
      {"finger_l1", "finger_r1"},
      {"L_arm_L", "L_arm_R"},  // a prefix without separator-led token is not one of the defaults
      {"arm_L_ik_L", "arm_R_ik_R"},
      {"arm_Leg", "arm_Leg"},
      {"cleft", "cleft"},
      {"Leftover", "Leftover"},
      {"spine_LOW", "spine_LOW"},
      {"spine", "spine"},
      {"", ""},
  };
  for (const auto& [name, mirrored] : cases) {
    EXPECT_EQ(mirror_name(name), mirrored) << name;
    EXPECT_EQ(mirror_name(mirror_name(name)), name) << name << " mirrored twice";
  }
  MirrorOptions custom;
  custom.side_tokens = {{"Lf", "Rt"}};
  EXPECT_EQ(mirror_name("armLf", custom), "armRt") << "configurable pairs";
  EXPECT_EQ(mirror_name("arm_L", custom), "arm_L") << "only the configured pairs";
}

Definition arm_template() {
  const Definition rig = biped();
  Definition templ = *extract_template(rig, by_name(rig, "arm_L").rig_id);
  return templ;
}

void expect_mirrored_twice_is_original(const Component& a, const Component& b) {
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.side, b.side) << a.name;
  EXPECT_EQ(a.attach, b.attach) << a.name;
  ASSERT_EQ(a.guides.size(), b.guides.size()) << a.name;
  for (std::size_t i = 0; i < a.guides.size(); ++i) {
    EXPECT_EQ(a.guides[i].joint, b.guides[i].joint) << a.name;
    EXPECT_EQ(a.guides[i].translate, b.guides[i].translate) << a.name << " guide " << i << " translate exactly";
    EXPECT_LE((a.guides[i].rotate - b.guides[i].rotate).cwiseAbs().maxCoeff(), 1e-9)
        << a.name << " guide " << i << " rotate";
  }
  EXPECT_TRUE(same_data(a, b)) << a.name;
  ASSERT_EQ(a.children.size(), b.children.size());
  for (std::size_t i = 0; i < a.children.size(); ++i) expect_mirrored_twice_is_original(a.children[i], b.children[i]);
}

TEST(Templates, mirror_swaps_sides_names_and_reflects_guides) {
  const Definition templ = arm_template();
  const Definition mirrored = mirror_template(templ);
  EXPECT_EQ(mirrored.name, "arm_R");
  EXPECT_EQ(mirrored.version, templ.version);
  const Component& arm = mirrored.components[0];
  const Component& source = templ.components[0];
  EXPECT_EQ(arm.name, "arm_R");
  EXPECT_EQ(arm.side, Side::kRight);
  EXPECT_EQ(arm.attach, "spine.END") << "a centre attach reference has nothing to swap";
  EXPECT_EQ(arm.guides[0].name, "start") << "guide roles stay";
  EXPECT_EQ(arm.guides[0].joint, "upperarm_R") << "guide joints swap";
  EXPECT_EQ(arm.guides[0].translate, Vec3(-0.2, 1.4, 0.01)) << "x -> -x";
  EXPECT_EQ(arm.guides[0].scale, source.guides[0].scale) << "scale stays";
  EXPECT_EQ(arm.children[0].name, "hand_R");
  EXPECT_EQ(arm.children[0].children[0].attach, "hand_R.root") << "attach references swap";
  EXPECT_EQ(arm.children[0].children[1].attach, "arm_R.END");
  EXPECT_FALSE(same_guides(arm.guides, source.guides)) << "guides differ";
  ASSERT_EQ(arm.params.size(), source.params.size());
  for (std::size_t i = 0; i < arm.params.size(); ++i)
    EXPECT_TRUE(arm.params[i].value == source.params[i].value) << "parameters are copied: " << arm.params[i].name;
  EXPECT_EQ(arm.controls[0].color, "blue") << "control styles are copied";

  Component centre = component("spine", "spine", Side::kCenter);
  EXPECT_EQ(mirror_component(centre).side, Side::kCenter) << "C stays C";
}

TEST(Templates, mirror_twice_gives_the_original_back) {
  const Definition templ = arm_template();
  const Definition twice = mirror_template(mirror_template(templ));
  EXPECT_EQ(twice.name, templ.name);
  expect_mirrored_twice_is_original(twice.components[0], templ.components[0]);
  std::set<std::string> original_ids;
  for (const Component* c : templ.all_components()) original_ids.insert(c->rig_id);
  for (const Component* c : twice.all_components()) {
    EXPECT_TRUE(is_rig_id(c->rig_id)) << c->name;
    EXPECT_EQ(original_ids.count(c->rig_id), 0u) << c->name << ": fresh ids by default";
  }
  MirrorOptions keep;
  keep.keep_ids = true;
  const Definition kept = mirror_template(templ, keep);
  EXPECT_EQ(kept.components[0].rig_id, templ.components[0].rig_id) << "keep_ids keeps them";
}

TEST(Templates, mirrored_rotation_is_m_r_m) {
  const math::Mat3 m = Vec3(-1, 1, 1).asDiagonal();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> angle(-360.0, 360.0);
  std::vector<Vec3> rotations = {Vec3(10, -20, 30), Vec3(170, 100, -30), Vec3(0, 90, 0), Vec3(0, -90, 45),
                                 Vec3(180, 0, 0), Vec3(0, 0, 0)};
  for (int i = 0; i < 200; ++i) rotations.emplace_back(angle(rng), angle(rng), angle(rng));
  for (const Vec3& degrees : rotations) {
    Component c = component("arm", "arm_L", Side::kLeft);
    c.guides = {guide("0", "", Vec3(1, 2, 3), degrees)};
    const Vec3 mirrored = mirror_component(c).guides[0].rotate;
    const math::Mat3 r = math::euler_to_matrix(math::to_radians(degrees), math::RotateOrder::kXYZ);
    const math::Mat3 expected = m * r * m;
    const math::Mat3 got = math::euler_to_matrix(math::to_radians(mirrored), math::RotateOrder::kXYZ);
    EXPECT_LE((got - expected).cwiseAbs().maxCoeff(), 1e-12) << "rotate " << degrees.transpose();
    EXPECT_NEAR(got.determinant(), 1.0, 1e-12) << "still a rotation";
    // The whole guide transform reflects: M (T R) M.
    math::Mat4 local = math::Mat4::Identity(), mirrored_local = math::Mat4::Identity();
    local.topLeftCorner<3, 3>() = r;
    local.topRightCorner<3, 1>() = c.guides[0].translate;
    mirrored_local.topLeftCorner<3, 3>() = got;
    mirrored_local.topRightCorner<3, 1>() = mirror_component(c).guides[0].translate;
    const math::Mat4 m4 = Vec4(-1, 1, 1, 1).asDiagonal();
    EXPECT_LE((mirrored_local - m4 * local * m4).cwiseAbs().maxCoeff(), 1e-12) << "the guide's matrix is M X M";
  }
}

TEST(Templates, mirrored_template_injects_beside_the_original) {
  Definition rig = biped();
  const Definition templ = arm_template();
  const Definition right = mirror_template(templ);
  const std::string spine_id = by_name(rig, "spine").rig_id;
  InjectOptions keep;
  keep.new_ids = false;  // the mirror already has fresh ids
  ASSERT_TRUE(inject_template(rig, right, spine_id, "END", keep).is_ok());
  EXPECT_EQ(by_name(rig, "arm_R").side, Side::kRight);
  EXPECT_EQ(by_name(rig, "thumb_R").attach, "arm_R.END");
  EXPECT_EQ(by_name(rig, "arm_R").rig_id, right.components[0].rig_id);
}

}  // namespace
}  // namespace rigel::rig

namespace rigel::rig {
namespace {

// `after` names components by rigId: fresh ids for a mirror or an injected
// copy take the names with them, and ids outside the copy stay.
TEST(Templates, fresh_ids_carry_what_builds_after_what) {
  Definition d;
  d.name = "r";
  Component root;
  root.type = "global";
  root.name = "global";
  root.rig_id = new_rig_id();
  Component x, y;
  x.type = y.type = "fkChain";
  x.name = "x_L";
  y.name = "y_L";
  x.rig_id = new_rig_id();
  y.rig_id = new_rig_id();
  const std::string outside = new_rig_id();
  y.after = {x.rig_id, outside};
  root.children = {x, y};
  d.components = {root};
  const Definition mirrored = mirror_template(d);
  const Component& mx = mirrored.components[0].children[0];
  const Component& my = mirrored.components[0].children[1];
  EXPECT_NE(mx.rig_id, x.rig_id);
  EXPECT_EQ(my.after, (std::vector<std::string>{mx.rig_id, outside}));
  Definition target;
  target.name = "t";
  ASSERT_TRUE(inject_template(target, d, "", "", InjectOptions{}).is_ok());
  const Component& ix = target.components[0].children[0];
  EXPECT_EQ(target.components[0].children[1].after, (std::vector<std::string>{ix.rig_id, outside}));
}

}  // namespace
}  // namespace rigel::rig
