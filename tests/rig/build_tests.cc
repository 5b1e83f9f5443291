// Procedural builds on a real character (Rigify's human metarig): records
// and exact destructs, stepping, persistence, the metadata network,
// addresses, partial rebuilds that keep animation.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>

#include <nlohmann/json.hpp>

#include "rig_test_util.h"
#include "rigel/io/gltf_import.h"
#include "rigel/io/scene_file.h"
#include "rigel/math/transform.h"
#include "rigel/ops/anim/channel_keys.h"
#include "rigel/ops/anim/nodes.h"
#include "rigel/rig/build.h"
#include "rigel/rig/component.h"
#include "rigel/rig/meta.h"
#include "rigel/scene/transform_types.h"

namespace rigel::rig {
namespace {

namespace fs = std::filesystem;
using testing::first_difference;
using testing::normalized;
using testing::at_joint;
using testing::metarig;
using graph::Plug;
using math::Mat4;
using math::Vec3;
namespace xform = scene::xform;


Component component(std::string type, std::string name, Side side, std::vector<Guide> guides) {
  Component c;
  c.type = std::move(type);
  c.name = std::move(name);
  c.side = side;
  c.rig_id = new_rig_id();
  c.guides = std::move(guides);
  return c;
}

// global -> hip (spine) -> fkChain torso (spine.001 .. spine.003)
//   -> arm_L (shoulder.L, upper_arm.L, forearm.L, hand.L) at the torso's END
//   -> arm_R likewise
Definition biped() {
  Definition d;
  d.name = "hero";
  d.version = "1.0";
  Component global = component("global", "global", Side::kCenter, {Guide{}});
  Component hip = component("hip", "hip", Side::kCenter, {at_joint("spine")});
  Component torso = component("fkChain", "torso", Side::kCenter,
                              {at_joint("spine.001"), at_joint("spine.002"), at_joint("spine.003")});
  Component arm_l = component("fkChain", "arm", Side::kLeft,
                              {at_joint("shoulder.L"), at_joint("upper_arm.L"), at_joint("forearm.L"), at_joint("hand.L")});
  arm_l.attach = "END";
  Component arm_r = component("fkChain", "arm", Side::kRight,
                              {at_joint("shoulder.R"), at_joint("upper_arm.R"), at_joint("forearm.R"), at_joint("hand.R")});
  arm_r.attach = "END";
  torso.children = {arm_l, arm_r};
  hip.children = {torso};
  global.children = {hip};
  d.components = {global};
  return d;
}

Vec3 position(scene::Scene& s, NodeId id) { return s.world_matrix(id).topRightCorner<3, 1>(); }

TEST(RigBuild, plan_orders_parents_first_with_steps_in_declared_order) {
  auto scene = metarig();
  ASSERT_TRUE(scene);
  auto b = Build::open(*scene, biped(), builtin_components());
  ASSERT_TRUE(b.is_ok()) << b.status().message();
  std::vector<std::string> labels;
  for (const PlannedStep& p : (*b)->plan())
    labels.push_back((p.component < 0 ? std::string("rig") : (*b)->components()[p.component]->name) + "/" + p.step);
  const std::vector<std::string> expected = {"rig/rig",       "global/meta",   "global/control", "hip/meta",
                                             "hip/control",   "hip/drive",     "torso/meta",     "torso/controls",
                                             "torso/drive",   "arm/meta",      "arm/controls",   "arm/drive",
                                             "arm/meta",      "arm/controls",  "arm/drive"};
  EXPECT_EQ(labels, expected);
  EXPECT_EQ((*b)->position(), 0);
}

TEST(RigBuild, construct_all_then_destruct_all_gives_back_the_file_byte_for_byte) {
  auto scene = metarig();
  ASSERT_TRUE(scene);
  const std::string before = io::write_scene(*scene);
  auto b = Build::open(*scene, biped(), builtin_components());
  ASSERT_TRUE(b.is_ok()) << b.status().message();
  ASSERT_TRUE((*b)->build_all().is_ok());
  graph::Graph& g = scene->graph();
  ASSERT_EQ(list_rigs(g).size(), 1u);
  // The arm's FK controls drive the arm: turning the shoulder control moves the hand.
  NodeId shoulder = *resolve_address(g, "hero:arm_L/fk[0]");
  NodeId hand = g.find("hand.L");
  const Vec3 hand_before = position(*scene, hand);
  ASSERT_TRUE(g.set_value(Plug{shoulder, xform::kRotate, -1}, graph::Value(Vec3(0, 0, 40))).is_ok());
  EXPECT_GT((position(*scene, hand) - hand_before).norm(), 0.05);
  ASSERT_TRUE(g.set_value(Plug{shoulder, xform::kRotate, -1}, graph::Value(Vec3(0, 0, 0))).is_ok());
  EXPECT_LT((position(*scene, hand) - hand_before).norm(), 1e-9) << "controls at zero: the rest pose";
  ASSERT_TRUE((*b)->remove().is_ok());
  {
    const std::string after = io::write_scene(*scene);
    EXPECT_TRUE(after == before) << first_difference(after, before);
  }
}

TEST(RigBuild, stepping_back_and_forward_from_every_index_gives_the_straight_build) {
  auto scene = metarig();
  ASSERT_TRUE(scene);
  auto b = Build::open(*scene, biped(), builtin_components());
  ASSERT_TRUE(b.is_ok());
  Build& build = **b;
  ASSERT_TRUE(build.build_all().is_ok());
  const std::string straight = normalized(*scene);
  testing::expect_stepping_gives_the_straight_build(build, *scene);
  // Undo and redo of a step keep the build in step with the scene.
  ASSERT_TRUE(scene->graph().undo());
  ASSERT_TRUE(build.forward().is_ok());
  const std::string redone = normalized(*scene);
  EXPECT_TRUE(redone == straight) << first_difference(redone, straight);
}

TEST(RigBuild, a_saved_build_is_removed_exactly_by_a_later_process) {
  auto scene = metarig();
  ASSERT_TRUE(scene);
  const std::string before = io::write_scene(*scene);
  const Definition def = biped();
  {
    auto b = Build::open(*scene, def, builtin_components());
    ASSERT_TRUE(b.is_ok());
    ASSERT_TRUE((*b)->build_all().is_ok());
  }
  auto reloaded = io::parse_scene(io::write_scene(*scene), "built", default_registry());
  ASSERT_TRUE(reloaded.is_ok()) << reloaded.status().message();
  // Another definition of the same rig name is refused: its ids do not match.
  EXPECT_EQ(Build::open(**reloaded, biped(), builtin_components()).status().code(), ErrorCode::kInvalidArgument);
  auto b = Build::open(**reloaded, def, builtin_components());
  ASSERT_TRUE(b.is_ok()) << b.status().message();
  EXPECT_EQ((*b)->position(), static_cast<int>((*b)->plan().size()));
  ASSERT_TRUE((*b)->remove().is_ok());
  const std::string after = io::write_scene(**reloaded);
  EXPECT_TRUE(after == before) << first_difference(after, before);

}

TEST(RigMeta, network_links_every_built_node_and_answers_queries) {
  auto scene = metarig();
  ASSERT_TRUE(scene);
  Definition def = biped();
  auto b = Build::open(*scene, def, builtin_components());
  ASSERT_TRUE(b.is_ok());
  ASSERT_TRUE((*b)->build_all().is_ok());
  graph::Graph& g = scene->graph();
  NodeId root = find_rig(g, "hero");
  ASSERT_TRUE(root.is_valid());
  EXPECT_EQ(meta_parent(g, root), meta_manager(g));
  EXPECT_EQ(meta_string(g, root, "version"), "1.0");
  std::vector<NodeId> comps = rig_components(g, root);
  ASSERT_EQ(comps.size(), 5u);
  const Component& global = def.components[0];
  NodeId global_meta = get_meta_child_by_id(g, root, global.rig_id);
  ASSERT_TRUE(global_meta.is_valid());
  EXPECT_EQ(meta_string(g, global_meta, "metaType"), "global");
  const Component& arm = def.components[0].children[0].children[0].children[0];
  NodeId arm_meta = find_component(g, root, arm.rig_id);
  ASSERT_TRUE(arm_meta.is_valid());
  EXPECT_EQ(meta_string(g, arm_meta, "componentName"), "arm_L");
  EXPECT_FALSE(get_meta_child_by_id(g, root, arm.rig_id).is_valid()) << "getMetaChildById looks at direct children";
  Result<NodeId> fk2 = get_meta_connection(g, arm_meta, "fk", 2);
  ASSERT_TRUE(fk2.is_ok());
  EXPECT_EQ(component_of(g, *fk2), arm_meta);
  EXPECT_EQ(rig_of(g, *fk2), root);
  EXPECT_EQ(get_meta_connection(g, arm_meta, "fk", 9).status().code(), ErrorCode::kNotFound);
  Result<const ComponentClass*> cls = builtin_components().class_of(g, arm_meta);
  ASSERT_TRUE(cls.is_ok());
  EXPECT_EQ((*cls)->type(), "fkChain");
  // Every node the build made hangs from a meta node.
  for (NodeId id : g.nodes()) {
    const std::string& type = g.node(id)->type().name();
    if (g.node(id)->tag_find(kTagStep)) {
      EXPECT_TRUE(component_of(g, id).is_valid()) << g.node(id)->name();
    }
    if (type == scene::kControlType) {
      EXPECT_TRUE(rig_of(g, id) == root) << g.node(id)->name();
    }
  }
}

TEST(RigMeta, addresses_resolve_without_names_and_survive_renames) {
  auto scene = metarig();
  ASSERT_TRUE(scene);
  auto b = Build::open(*scene, biped(), builtin_components());
  ASSERT_TRUE(b.is_ok());
  ASSERT_TRUE((*b)->build_all().is_ok());
  graph::Graph& g = scene->graph();
  Result<NodeId> end = resolve_address(g, "hero:arm_L/fk[END]");
  ASSERT_TRUE(end.is_ok()) << end.status().message();
  EXPECT_EQ(*end, *resolve_address(g, "hero:arm_L/fk[3]"));
  EXPECT_EQ(*resolve_address(g, "hero:arm_L/joint[MIDDLE]/fk"), *resolve_address(g, "hero:arm_L/fk[1]"));
  EXPECT_EQ(*address_of(g, *end), "hero:arm_L/joint[3]/fk[0]");
  ASSERT_TRUE(g.rename(*end, "renamed_by_an_animator").is_ok());
  EXPECT_EQ(*resolve_address(g, "hero:arm_L/fk[END]"), *end);
  EXPECT_EQ(resolve_address(g, "hero:leg_L/fk[0]").status().code(), ErrorCode::kNotFound);
  EXPECT_EQ(resolve_address(g, "villain:arm_L/fk[0]").status().code(), ErrorCode::kNotFound);
  EXPECT_EQ(resolve_address(g, "hero:arm_L/fk[9]").status().code(), ErrorCode::kNotFound);
  EXPECT_EQ(resolve_address(g, "no colon").status().code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(*resolve_address(g, "hero:"), find_rig(g, "hero"));
}

TEST(RigBuild, rebuilding_one_changed_component_keeps_the_rest_and_its_keys) {
  auto scene = metarig();
  ASSERT_TRUE(scene);
  Definition def = biped();
  auto b = Build::open(*scene, def, builtin_components());
  ASSERT_TRUE(b.is_ok());
  ASSERT_TRUE((*b)->build_all().is_ok());
  graph::Graph& g = scene->graph();
  // Key a torso control and an arm control (animation curves from outside the rig).
  auto key = [&](const std::string& address) {
    NodeId control = *resolve_address(g, address);
    Result<NodeId> curve = g.create_node(ops::anim::kAnimCurveVec3Type, "curve_" + std::to_string(control.index));
    EXPECT_TRUE(curve.is_ok());
    EXPECT_TRUE(g.connect(Plug{*curve, g.node(*curve)->type().attr_find("output"), -1},
                          Plug{control, xform::kRotate, -1})
                    .is_ok());
    return *curve;
  };
  NodeId torso_curve = key("hero:torso/fk[1]");
  NodeId arm_curve = key("hero:arm_L/fk[2]");
  NodeId torso_control = *resolve_address(g, "hero:torso/fk[1]");
  NodeId arm_r_control = *resolve_address(g, "hero:arm_R/fk[0]");
  const std::string torso_uuid = g.node(torso_control)->uuid().str();
  const std::string arm_r_uuid = g.node(arm_r_control)->uuid().str();

  Definition next = def;
  Component& arm_l = next.components[0].children[0].children[0].children[0];
  arm_l.version = "1.1";
  arm_l.controls.push_back(ControlStyle{"fk", "square", "red", 0.5, {}});
  auto rebuilt = (*b)->rebuild_changed(next, Build::Rebuild::kNewerVersion);
  ASSERT_TRUE(rebuilt.is_ok()) << rebuilt.status().message();
  EXPECT_EQ(*rebuilt, std::vector<std::string>{arm_l.rig_id}) << "only the arm";
  EXPECT_EQ(g.node(*resolve_address(g, "hero:torso/fk[1]"))->uuid().str(), torso_uuid);
  EXPECT_EQ(g.node(*resolve_address(g, "hero:arm_R/fk[0]"))->uuid().str(), arm_r_uuid);
  // The curves drive the same controls (the arm's is a new node with the same role and index).
  NodeId new_arm = *resolve_address(g, "hero:arm_L/fk[2]");
  EXPECT_EQ(g.source(Plug{torso_control, xform::kRotate, -1})->node, torso_curve);
  ASSERT_TRUE(g.source(Plug{new_arm, xform::kRotate, -1}).has_value());
  EXPECT_EQ(g.source(Plug{new_arm, xform::kRotate, -1})->node, arm_curve);
  EXPECT_EQ(std::get<Vec3>(g.node(new_arm)->value(scene::control_attr::kShapeColor)), Vec3(1, 0, 0));
  EXPECT_EQ(meta_string(g, find_component(g, find_rig(g, "hero"), arm_l.rig_id), "version"), "1.1");
  // One undo step: undo gives back the old arm.
  ASSERT_TRUE(g.undo());
  EXPECT_EQ(meta_string(g, find_component(g, find_rig(g, "hero"), arm_l.rig_id), "version"), "1.0");
}

// Keys the arm_L FK controls (rotate at three times, translate of fk[1] at
// two) and the torso's fk[1]; then moves and turns arm_L's upper-arm guide
// (its controls get a new rest) and updates with `keep`. Returns the world
// matrix of each keyed arm control at each key time, before and after.
struct KeptWorlds {
  std::vector<Mat4> before, after;
  std::vector<double> torso_values_before, torso_values_after;
};
KeptWorlds update_with_moved_guide(Build::KeepKeys keep) {
  KeptWorlds out;
  auto scene = metarig();
  EXPECT_TRUE(scene);
  if (!scene) return out;
  Definition def = biped();
  auto b = Build::open(*scene, def, builtin_components());
  EXPECT_TRUE(b.is_ok());
  EXPECT_TRUE((*b)->build_all().is_ok());
  graph::Graph& g = scene->graph();
  const std::vector<double> times = {0.0, 0.5, 1.25};
  std::vector<std::string> keyed = {"hero:arm_L/fk[0]", "hero:arm_L/fk[1]", "hero:arm_L/fk[2]", "hero:arm_L/fk[3]"};
  for (std::size_t c = 0; c < keyed.size(); ++c) {
    NodeId control = *resolve_address(g, keyed[c]);
    for (std::size_t i = 0; i < times.size(); ++i) {
      const Vec3 rotate(10.0 * (i + 1) + c, -7.0 * i + 3.0 * c, 25.0 * (i % 2) - c);
      EXPECT_TRUE(ops::anim::write_channel_key(g, control, xform::kRotate, rotate, times[i], true).is_ok());
    }
  }
  NodeId fk1 = *resolve_address(g, "hero:arm_L/fk[1]");
  EXPECT_TRUE(ops::anim::write_channel_key(g, fk1, xform::kTranslate, Vec3(0.01, 0, 0), 0.0, true).is_ok());
  EXPECT_TRUE(ops::anim::write_channel_key(g, fk1, xform::kTranslate, Vec3(0, 0.02, -0.01), 1.25, true).is_ok());
  NodeId torso = *resolve_address(g, "hero:torso/fk[1]");
  EXPECT_TRUE(ops::anim::write_channel_key(g, torso, xform::kRotate, Vec3(5, 6, 7), 0.5, true).is_ok());
  auto torso_values = [&] {
    std::vector<double> v;
    for (const graph::Connection& c : g.node(*resolve_address(g, "hero:torso/fk[1]"))->inputs()) {
      if (ops::anim::curve_kind(g, c.src.node) != ops::anim::CurveKind::kScalar) continue;
      for (double x : std::get<std::vector<double>>(g.node(c.src.node)->value(ops::anim::curve_attr::kKeyValues)))
        v.push_back(x);
    }
    return v;
  };
  auto worlds = [&] {
    std::vector<Mat4> w;
    for (double t : times) {
      g.set_time(t);
      for (const std::string& a : keyed) w.push_back(scene->world_matrix(*resolve_address(g, a)));
    }
    g.set_time(0);
    return w;
  };
  out.before = worlds();
  out.torso_values_before = torso_values();

  Definition next = def;
  Component& arm_l = next.components[0].children[0].children[0].children[0];
  arm_l.version = "1.1";
  Guide moved;  // the upper arm's place, moved 3 cm and turned
  const Mat4 upper = scene->world_matrix(g.find("upper_arm.L"));
  moved.translate = upper.topRightCorner<3, 1>() + Vec3(0.02, 0.03, -0.01);
  moved.rotate = Vec3(10, 20, 30);
  arm_l.guides[1] = moved;
  auto rebuilt = (*b)->rebuild_changed(next, Build::Rebuild::kNewerVersion, keep);
  EXPECT_TRUE(rebuilt.is_ok()) << rebuilt.status().message();
  EXPECT_EQ(rebuilt.is_ok() ? *rebuilt : std::vector<std::string>{}, std::vector<std::string>{arm_l.rig_id});
  out.after = worlds();
  out.torso_values_after = torso_values();
  return out;
}

double largest_miss(const std::vector<Mat4>& a, const std::vector<Mat4>& b) {
  double miss = 0;
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) miss = std::max(miss, (a[i] - b[i]).cwiseAbs().maxCoeff());
  return miss;
}

TEST(RigBuild, keep_keys_world_keeps_keyed_controls_of_changed_components_in_place) {
  KeptWorlds world = update_with_moved_guide(Build::KeepKeys::kWorld);
  ASSERT_EQ(world.before.size(), 12u);
  ASSERT_EQ(world.after.size(), 12u);
  EXPECT_LE(largest_miss(world.before, world.after), 1e-6);
  // Keys on the unchanged torso: identical bit for bit.
  ASSERT_FALSE(world.torso_values_before.empty());
  EXPECT_EQ(world.torso_values_before, world.torso_values_after);

  // Keeping local values instead leaves the controls where the new rest puts
  // them: the conversion is what keeps them (the test can fail).
  KeptWorlds local = update_with_moved_guide(Build::KeepKeys::kLocal);
  EXPECT_GT(largest_miss(local.before, local.after), 1e-3);
  EXPECT_EQ(local.torso_values_before, local.torso_values_after);
}

TEST(RigEdit, moved_controls_write_their_guides_back_and_bump_versions) {
  auto scene = metarig();
  ASSERT_TRUE(scene);
  Definition def = biped();
  BuildOptions options;
  options.edit_mode = true;
  auto b = Build::open(*scene, def, builtin_components(), options);
  ASSERT_TRUE(b.is_ok());
  ASSERT_TRUE((*b)->build_all().is_ok());
  graph::Graph& g = scene->graph();
  NodeId fk1 = *resolve_address(g, "hero:arm_L/fk[1]");
  const std::string torso_uuid = g.node(*resolve_address(g, "hero:torso/fk[1]"))->uuid().str();
  const Mat4 upper = scene->world_matrix(g.find("upper_arm.L"));
  const Mat4 fk1_rest = scene->world_matrix(fk1);
  const Mat4 fk2_rest = scene->world_matrix(*resolve_address(g, "hero:arm_L/fk[2]"));
  ASSERT_TRUE(g.set_value(Plug{fk1, xform::kTranslate, -1}, Vec3(0.0, 0.05, 0.0)).is_ok());
  ASSERT_TRUE(g.set_value(Plug{fk1, xform::kRotate, -1}, Vec3(0.0, 0.0, 30.0)).is_ok());
  const Mat4 fk1_moved = scene->world_matrix(fk1);
  const Mat4 fk2_moved = scene->world_matrix(*resolve_address(g, "hero:arm_L/fk[2]"));
  const std::string text_before = io::write_scene(*scene);
  // The control's move in its own rest frame: T(0, 0.05, 0) * Rz(30).
  const Mat4 local = scene->local_matrix(fk1);
  const double c = std::cos(M_PI / 6), s = std::sin(M_PI / 6);
  EXPECT_NEAR(local(0, 0), c, 1e-12);
  EXPECT_NEAR(local(1, 0), s, 1e-12);
  EXPECT_NEAR(local(1, 3), 0.05, 1e-12);

  auto e = (*b)->edits();
  ASSERT_TRUE(e.is_ok()) << e.status().message();
  const std::string text_after = io::write_scene(*scene);
  EXPECT_TRUE(text_after == text_before) << "edits() leaves the scene as it was: " << first_difference(text_before, text_after);
  const Component* arm = e->definition.find_by_rig_id(def.components[0].children[0].children[0].children[0].rig_id);
  ASSERT_TRUE(arm);
  EXPECT_EQ(e->changed, std::vector<std::string>{arm->rig_id}) << "fk[2] moved with fk[1], both in arm_L";
  EXPECT_EQ(arm->version, "1.1");
  EXPECT_EQ(e->definition.version, "1.1");
  // Guide 1 keeps its joint and takes the move as its offset from it.
  EXPECT_EQ(arm->guides[1].joint, "upper_arm.L");
  math::TransformParts parts;
  parts.translate = arm->guides[1].translate;
  parts.rotate = math::to_radians(arm->guides[1].rotate);
  parts.scale = arm->guides[1].scale;
  const Mat4 guide1 = upper * math::compose(parts);
  // The control was at its guide (the joint): the guide now stands where the control does.
  EXPECT_TRUE(math::is_near(fk1_rest, upper, 1e-9));
  EXPECT_TRUE(math::is_near(guide1, fk1_moved, 1e-9));
  EXPECT_TRUE(e->ignored.empty());

  auto committed = (*b)->commit_edits();
  ASSERT_TRUE(committed.is_ok()) << committed.status().message();
  NodeId new_fk1 = *resolve_address(g, "hero:arm_L/fk[1]");
  EXPECT_TRUE(math::is_near(scene->world_matrix(new_fk1), fk1_moved, 1e-9)) << "rebuilt where it was moved to";
  EXPECT_TRUE(math::is_near(scene->local_matrix(new_fk1), Mat4::Identity(), 1e-12)) << "zeroed";
  // fk[2]'s guide is an offset from forearm.L, whose float32 world matrix has
  // a little shear that guides cannot hold: within 1e-6, not 1e-9.
  EXPECT_TRUE(math::is_near(scene->world_matrix(*resolve_address(g, "hero:arm_L/fk[2]")), fk2_moved, 1e-6));
  EXPECT_FALSE(math::is_near(fk2_moved, fk2_rest, 1e-3));
  EXPECT_EQ(g.node(*resolve_address(g, "hero:torso/fk[1]"))->uuid().str(), torso_uuid) << "the rest is untouched";
  EXPECT_EQ((*b)->definition().version, "1.1");
  EXPECT_EQ(meta_string(g, find_rig(g, "hero"), "version"), "1.1");
  // Nothing moved now: no further edits.
  auto again = (*b)->edits();
  ASSERT_TRUE(again.is_ok());
  EXPECT_TRUE(again->changed.empty());
}

TEST(RigEdit, a_rig_not_in_edit_mode_refuses_edits) {
  auto scene = metarig();
  ASSERT_TRUE(scene);
  auto b = Build::open(*scene, biped(), builtin_components());
  ASSERT_TRUE(b.is_ok());
  ASSERT_TRUE((*b)->build_all().is_ok());
  auto e = (*b)->edits();
  ASSERT_FALSE(e.is_ok());
  EXPECT_NE(e.status().message().find("not in edit mode"), std::string::npos) << e.status().message();
}

TEST(RigBuild, refuses_unknown_types_cycles_and_missing_hooks_naming_them) {
  auto scene = metarig();
  ASSERT_TRUE(scene);
  Definition d = biped();
  d.components[0].children[0].type = "wing";
  auto b = Build::open(*scene, d, builtin_components());
  ASSERT_FALSE(b.is_ok());
  EXPECT_NE(b.status().message().find("wing"), std::string::npos);

  d = biped();
  Component& hip = d.components[0].children[0];
  hip.attach = "torso.0";  // the hip hangs from the torso, which hangs from the hip
  b = Build::open(*scene, d, builtin_components());
  ASSERT_FALSE(b.is_ok());
  EXPECT_EQ(b.status().code(), ErrorCode::kCycle);
  EXPECT_NE(b.status().message().find("torso"), std::string::npos) << b.status().message();

  d = biped();
  d.components[0].children[0].children[0].children[0].attach = "wrist";
  b = Build::open(*scene, d, builtin_components());
  ASSERT_FALSE(b.is_ok());
  EXPECT_NE(b.status().message().find("wrist"), std::string::npos);
}

TEST(RigBuild, a_failing_step_is_rolled_back_and_names_itself) {
  auto scene = metarig();
  ASSERT_TRUE(scene);
  Definition d = biped();
  d.components[0].children[0].children[0].guides[1].joint = "no_such_joint";
  auto b = Build::open(*scene, d, builtin_components());
  ASSERT_TRUE(b.is_ok());
  Status s = (*b)->build_all();
  ASSERT_FALSE(s.is_ok());
  EXPECT_NE(s.message().find("torso/controls"), std::string::npos) << s.message();
  EXPECT_NE(s.message().find("no_such_joint"), std::string::npos) << s.message();
  const int stopped = (*b)->position();
  EXPECT_EQ((*b)->plan()[stopped].step, "controls");
  EXPECT_FALSE(scene->graph().find("hero_torso_fk0").is_valid()) << "the failed step's first control is rolled back";
  EXPECT_TRUE(scene->graph().find("hero_hip_main").is_valid()) << "earlier steps stay";
}

}  // namespace
}  // namespace rigel::rig
