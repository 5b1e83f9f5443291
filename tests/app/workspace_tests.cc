// The service layer through the library, no driver: each operation of
// app::Workspace once, on the bundled character (Rigify's metarig) with an
// ephemeral rig or the puppet rig built, in a temporary root folder.

#include "rigel/app/workspace.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <limits>
#include <fstream>
#include <memory>
#include <string>

#include "rigel/ephemeral/component.h"
#include "rigel/ephemeral/keying.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/io/gltf_import.h"
#include "rigel/io/scene_file.h"
#include "rigel/math/transform.h"
#include "rigel/rig/definition_io.h"
#include "rigel/rig/meta.h"
#include "../io/io_test_util.h"

namespace rigel::app {
namespace {

using io::testing::TempDir;

fs::path source_path(const std::string& relative) { return fs::path(RIGEL_SOURCE_DIR) / relative; }

std::unique_ptr<scene::Scene> character() {
  io::GltfImportOptions options;
  options.registry = ephemeral::default_registry();
  auto imported = io::import_gltf(source_path("tests/data/gltf/rigify_human_metarig.glb"), options);
  EXPECT_TRUE(imported.is_ok()) << imported.status().message();
  return std::move(*imported);
}

class AppWorkspace : public ::testing::Test {
 protected:
  // The character with an ephemeral rig (a control per joint).
  std::unique_ptr<Workspace> ephemeral_workspace() {
    auto scene = character();
    auto rig = ephemeral::setup_ephemeral(*scene);
    EXPECT_TRUE(rig.is_ok()) << rig.status().message();
    scene->graph().clear_history();
    return std::make_unique<Workspace>(std::move(scene), fs::path(), root(), ephemeral::components());
  }
  // The character with examples/puppet.rig.xml built.
  std::unique_ptr<Workspace> puppet_workspace() {
    auto ws = std::make_unique<Workspace>(character(), fs::path(), root(), ephemeral::components());
    auto added = ws->add_rig(source_path("examples/puppet.rig.xml"));
    EXPECT_TRUE(added.is_ok()) << added.status().message();
    ws->graph().clear_history();
    return ws;
  }
  fs::path root() {
    const fs::path r = dir_.path() / "root";
    fs::create_directories(r);
    return r;
  }
  NodeId id(Workspace& ws, const std::string& name) {
    const NodeId n = ws.graph().find(name);
    EXPECT_TRUE(n.is_valid()) << name;
    return n;
  }
  Vec3 world_t(Workspace& ws, NodeId n) { return ws.scene().world_matrix(n).block<3, 1>(0, 3); }

  TempDir dir_;
};

TEST_F(AppWorkspace, euler_degrees_apply_x_first_about_world_axes) {
  const Vec3 deg(30, -45, 60);
  const Vec3 r = deg * (M_PI / 180.0);
  const Quat expected(Eigen::AngleAxisd(r.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(r.y(), Vec3::UnitY()) *
                      Eigen::AngleAxisd(r.x(), Vec3::UnitX()));
  EXPECT_NEAR(std::abs(rotation_from_euler_degrees(deg).dot(expected)), 1.0, 1e-12);
}

TEST_F(AppWorkspace, paths_are_confined_to_the_root) {
  Workspace ws(character(), fs::path(), root(), ephemeral::components());
  EXPECT_TRUE(ws.resolve_path("shots/a.rigel", "path").is_ok());
  for (const std::string bad : {"/etc/passwd", "../outside.rigel", "a/../../b", ""}) {
    auto r = ws.resolve_path(bad, "path");
    ASSERT_FALSE(r.is_ok()) << bad;
    EXPECT_EQ(r.status().code(), ErrorCode::kInvalidArgument) << bad;
    EXPECT_EQ(r.status().field(), "path");
  }
  // Without a root, paths are taken as given (the CLI's and Python's users name their files).
  Workspace free(character(), fs::path(), fs::path(), ephemeral::components());
  EXPECT_EQ(*free.resolve_path("/tmp/x.rigel", "path"), fs::path("/tmp/x.rigel"));
}

TEST_F(AppWorkspace, nodes_and_controls_resolve_by_name_or_uuid) {
  auto ws = ephemeral_workspace();
  const NodeId hand = id(*ws, "hand.L");
  const NodeId control = ephemeral::control_of(ws->graph(), hand);
  EXPECT_EQ(*ws->control("hand.L", "c"), control) << "a joint stands for its control";
  EXPECT_EQ(*ws->control(ws->graph().node(control)->uuid().str(), "c"), control);
  auto missing = ws->control("nobody", "controls[1]");
  EXPECT_EQ(missing.status().code(), ErrorCode::kNotFound);
  EXPECT_EQ(missing.status().field(), "controls[1]");
  auto rig_node = ws->control("ephemeralRig", "c");
  EXPECT_EQ(rig_node.status().code(), ErrorCode::kInvalidArgument);
  EXPECT_NE(rig_node.status().message().find("not a control"), std::string::npos);
  EXPECT_EQ(ws->all_controls().size(), ws->controls().size());
  EXPECT_EQ(ws->nodes().size(), ws->scene().hierarchy().size());
}

TEST_F(AppWorkspace, options_are_validated_once_for_every_driver) {
  auto ws = ephemeral_workspace();
  ephemeral::SessionOptions o;
  struct Bad {
    const char* field;
    std::function<void(ephemeral::SessionOptions&)> set;
  };
  for (const Bad& b : {Bad{"magnetFraction", [](auto& x) { x.magnet_fraction = 0; }},
                       Bad{"magnetFraction", [](auto& x) { x.magnet_fraction = 1.5; }},
                       Bad{"magnetRadius", [](auto& x) { x.magnet_radius = -1; }},
                       Bad{"magnetRadius", [](auto& x) { x.magnet_radius = std::numeric_limits<double>::infinity(); }},
                       Bad{"maxChain", [](auto& x) { x.max_chain = -1; }},
                       Bad{"maxChain", [](auto& x) { x.max_chain = 1001; }},
                       Bad{"magnetMinWeight", [](auto& x) { x.magnet_min_weight = 1; }},
                       Bad{"fabrikIterations", [](auto& x) { x.fabrik_iterations = 0; }}}) {
    ephemeral::SessionOptions bad = o;
    b.set(bad);
    const std::uint64_t revision = ws->revision();
    const Status s = ws->set_options(bad);
    ASSERT_FALSE(s.is_ok()) << b.field;
    EXPECT_EQ(s.code(), ErrorCode::kInvalidArgument);
    EXPECT_EQ(s.field(), b.field);
    EXPECT_EQ(ws->revision(), revision) << "a refused call changes nothing";
  }
  o.max_chain = 3;
  ASSERT_TRUE(ws->set_options(o).is_ok());
  EXPECT_EQ(ws->session().options().max_chain, 3);
}

TEST_F(AppWorkspace, drag_moves_an_ephemeral_rig_and_reports_what_moved) {
  auto ws = ephemeral_workspace();
  const NodeId hand = id(*ws, "hand.L");
  const Vec3 before = world_t(*ws, hand);
  ws->set_mode(ephemeral::Mode::kInverse);
  auto r = ws->drag_to(*ws->control("hand.L", "control"), before + Vec3(0, 0.05, 0.05), std::nullopt);
  ASSERT_TRUE(r.is_ok()) << r.status().message();
  EXPECT_LT((world_t(*ws, hand) - (before + Vec3(0, 0.05, 0.05))).norm(), 1e-6);
  EXPECT_FALSE(r->moved.empty());
  EXPECT_LT(r->moved.size(), ws->scene().hierarchy().size()) << "only what moved";
  EXPECT_FALSE(r->moved_controls.empty());
  ASSERT_EQ(r->dragged.size(), 1u);
  ws->release();
  // One undo step for the gesture.
  auto undone = ws->undo();
  ASSERT_TRUE(undone.is_ok());
  EXPECT_LT((world_t(*ws, hand) - before).norm(), 1e-12);
  EXPECT_TRUE(ws->redo().is_ok());
  EXPECT_FALSE(ws->redo().is_ok()) << "nothing more to redo";
  EXPECT_EQ(ws->redo().status().code(), ErrorCode::kFailedPrecondition);
}

TEST_F(AppWorkspace, drag_moves_a_built_rigs_controls_directly) {
  auto ws = puppet_workspace();
  NodeId control;
  for (NodeId c : ws->all_controls()) {
    control = c;
    break;
  }
  ASSERT_TRUE(control.is_valid());
  const Vec3 before = world_t(*ws, control);
  ws->select({control});
  auto r = ws->drag(ephemeral::Delta{Vec3(0.1, 0, 0), Quat::Identity(), Vec3::Ones()});
  ASSERT_TRUE(r.is_ok()) << r.status().message();
  EXPECT_LT((world_t(*ws, control) - (before + Vec3(0.1, 0, 0))).norm(), 1e-9);
  EXPECT_TRUE(r->notes.empty());
  EXPECT_EQ(r->dragged, std::vector<NodeId>{control});
  // Scale is body mode's.
  auto scaled = ws->drag(ephemeral::Delta{Vec3::Zero(), Quat::Identity(), Vec3(2, 2, 2)});
  EXPECT_EQ(scaled.status().code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(scaled.status().field(), "scale");
}

TEST_F(AppWorkspace, drag_motions_are_checked_once_for_every_driver) {
  auto ws = ephemeral_workspace();
  const NodeId c = *ws->control("hand.L", "c");
  ws->select({c});
  const double inf = std::numeric_limits<double>::infinity();
  struct Bad {
    ephemeral::Delta delta;
    const char* field;
  };
  for (const Bad& b : {Bad{{Vec3(inf, 0, 0), Quat::Identity(), Vec3::Ones()}, "translate"},
                       Bad{{Vec3::Zero(), Quat(0, 0, 0, 0), Vec3::Ones()}, "rotate"},
                       Bad{{Vec3::Zero(), Quat(std::nan(""), 0, 0, 1), Vec3::Ones()}, "rotate"},
                       Bad{{Vec3::Zero(), Quat::Identity(), Vec3(1, 2, 1)}, "scale"}}) {
    auto r = ws->drag(b.delta);
    EXPECT_EQ(r.status().code(), ErrorCode::kInvalidArgument) << b.field << ": " << r.status().message();
    EXPECT_EQ(r.status().field(), b.field);
  }
  ws->set_mode(ephemeral::Mode::kBody);
  EXPECT_EQ(ws->drag({Vec3::Zero(), Quat::Identity(), Vec3(1, -1, 1)}).status().field(), "scale");
  // A rotation of any length is normalised: twice the identity turns nothing.
  const Vec3 before = world_t(*ws, id(*ws, "hand.L"));
  ws->set_mode(ephemeral::Mode::kForward);
  ASSERT_TRUE(ws->drag({Vec3::Zero(), Quat(2, 0, 0, 0), Vec3::Ones()}).is_ok());
  EXPECT_LT((world_t(*ws, id(*ws, "hand.L")) - before).norm(), 1e-12);
  EXPECT_EQ(ws->drag_to(c, std::nullopt, Quat(0, 0, 0, 0)).status().field(), "to.q");
  EXPECT_EQ(ws->drag_to(c, Vec3(inf, 0, 0), std::nullopt).status().field(), "to.t");
}

TEST_F(AppWorkspace, drag_with_nothing_selected_is_refused) {
  auto ws = ephemeral_workspace();
  auto r = ws->drag(ephemeral::Delta{});
  EXPECT_EQ(r.status().code(), ErrorCode::kFailedPrecondition);
  EXPECT_EQ(r.status().field(), "controls");
}

TEST_F(AppWorkspace, time_is_range_checked) {
  auto ws = ephemeral_workspace();
  ASSERT_TRUE(ws->set_frame(12).is_ok());
  EXPECT_DOUBLE_EQ(ws->scene().frame(), 12);
  EXPECT_EQ(ws->set_frame(2e6).field(), "frame");
  EXPECT_EQ(ws->set_time(std::nan("")).field(), "time");
  EXPECT_EQ(ws->set_time(1e9).code(), ErrorCode::kInvalidArgument);
  EXPECT_DOUBLE_EQ(ws->scene().frame(), 12) << "refused times change nothing";
}

TEST_F(AppWorkspace, keys_set_report_and_delete) {
  auto ws = ephemeral_workspace();
  const NodeId c = *ws->control("hand.L", "c");
  ASSERT_TRUE(ws->set_frame(5).is_ok());
  auto k = ws->set_key({c});
  ASSERT_TRUE(k.is_ok()) << k.status().message();
  EXPECT_EQ(k->frames, std::vector<double>{5});
  EXPECT_EQ(k->scope, "character");
  EXPECT_EQ(k->set.size(), ws->all_controls().size()) << "scope character: every control is keyed";
  EXPECT_EQ(ws->summary().range[1], 5);
  auto d = ws->delete_key({c});
  ASSERT_TRUE(d.is_ok());
  EXPECT_TRUE(d->frames.empty());
  EXPECT_EQ(ws->set_key({}).status().code(), ErrorCode::kFailedPrecondition);
}

TEST_F(AppWorkspace, save_is_atomic_and_makes_folders) {
  auto ws = ephemeral_workspace();
  EXPECT_EQ(ws->save().status().field(), "path") << "no file yet";
  auto saved = ws->save(root() / "shots" / "a.rigel");
  ASSERT_TRUE(saved.is_ok()) << saved.status().message();
  EXPECT_TRUE(fs::is_regular_file(*saved));
  EXPECT_EQ(ws->scene_path(), *saved);
  fs::create_directories(root() / "folder.rigel");
  EXPECT_EQ(ws->save(root() / "folder.rigel").status().code(), ErrorCode::kInvalidArgument);
}

TEST_F(AppWorkspace, rigs_step_to_zero_and_back) {
  auto ws = puppet_workspace();
  std::vector<RigEntry> rigs = ws->rigs();
  ASSERT_EQ(rigs.size(), 1u);
  const int steps = rigs[0].steps;
  ASSERT_GT(steps, 1);
  auto r = ws->step_rig("puppet", 0);
  ASSERT_TRUE(r.is_ok()) << r.status().message();
  EXPECT_EQ(r->position, 0);
  EXPECT_FALSE(rig::find_rig(ws->graph(), "puppet").is_valid());
  rigs = ws->rigs();
  ASSERT_EQ(rigs.size(), 1u);
  EXPECT_TRUE(rigs[0].unbuilt) << "the workspace keeps a rig at step 0";
  EXPECT_EQ(ws->check_rig("puppet", false).code(), ErrorCode::kFailedPrecondition);
  r = ws->step_rig("puppet", std::nullopt, steps + 5);
  ASSERT_TRUE(r.is_ok());
  EXPECT_EQ(r->position, steps) << "by clamps";
  EXPECT_EQ(ws->step_rig("puppet", steps + 1).status().field(), "to");
  EXPECT_EQ(ws->check_rig("nobody", true).code(), ErrorCode::kNotFound);
}

TEST_F(AppWorkspace, edit_mode_and_remove) {
  auto ws = puppet_workspace();
  auto on = ws->set_edit_mode("puppet", true);
  ASSERT_TRUE(on.is_ok()) << on.status().message();
  EXPECT_TRUE(*on);
  auto committed = ws->commit_edits("puppet", root() / "puppet_edit.rig.xml");
  ASSERT_TRUE(committed.is_ok()) << committed.status().message();
  EXPECT_TRUE(committed->changed.empty()) << "no guide moved";
  EXPECT_FALSE(committed->edit_mode);
  ASSERT_TRUE(ws->remove_rig("puppet").is_ok());
  EXPECT_TRUE(ws->rigs().empty());
  EXPECT_EQ(ws->remove_rig("puppet").code(), ErrorCode::kNotFound);
}

TEST_F(AppWorkspace, definitions_check_build_rebuild_and_save_with_a_new_version) {
  auto ws = puppet_workspace();
  auto def = ws->definition("puppet");
  ASSERT_TRUE(def.is_ok()) << def.status().message();
  const std::string text = rig::write_definition(*def, rig::Syntax::kJson);
  CheckedDefinition checked = ws->check_definition(text, rig::Syntax::kJson, "definition");
  ASSERT_TRUE(checked.problems.empty()) << checked.problems.front().str();
  CheckedDefinition broken = ws->check_definition("{\"rig\": 3}", rig::Syntax::kJson, "definition");
  EXPECT_FALSE(broken.problems.empty());
  // The same definition: a live rebuild changes nothing.
  auto rebuilt = ws->build_definition(checked.definition);
  ASSERT_TRUE(rebuilt.is_ok()) << rebuilt.status().message();
  EXPECT_TRUE(rebuilt->rebuilt.empty());
  // Saved twice: the same content keeps its version, other content gets the next one.
  const fs::path path = root() / "defs" / "puppet.rig.json";
  auto first = ws->save_definition(checked.definition, path);
  ASSERT_TRUE(first.is_ok()) << first.status().message();
  EXPECT_EQ(first->version, checked.definition.version);
  EXPECT_EQ(ws->save_definition(checked.definition, path)->version, checked.definition.version);
  rig::Definition changed = checked.definition;
  changed.gui_location = std::make_pair(10.0, 20.0);
  EXPECT_EQ(ws->save_definition(changed, path)->version, rig::next_version(checked.definition.version));
  EXPECT_EQ(ws->save_definition(changed, root() / "x.txt").status().field(), "path");
}

TEST_F(AppWorkspace, add_rig_reports_every_problem_before_building) {
  Workspace ws(character(), fs::path(), root(), ephemeral::components());
  EXPECT_EQ(ws.add_rig(root() / "none.rig.xml").status().code(), ErrorCode::kNotFound);
  std::ofstream(root() / "bad.rig.xml") << "<rig name='x'><component type='nope'/></rig>";
  auto bad = ws.add_rig(root() / "bad.rig.xml");
  EXPECT_EQ(bad.status().code(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(bad.status().field(), "definition");
  EXPECT_TRUE(ws.rigs().empty());
}

TEST_F(AppWorkspace, every_change_moves_the_revision) {
  auto ws = ephemeral_workspace();
  std::uint64_t r = ws->revision();
  auto moved = [&] {
    const bool m = ws->revision() > r;
    r = ws->revision();
    return m;
  };
  ws->select({*ws->control("hand.L", "c")});
  EXPECT_TRUE(moved());
  ws->set_mode(ephemeral::Mode::kForward);
  EXPECT_TRUE(moved());
  ASSERT_TRUE(ws->set_frame(3).is_ok());
  EXPECT_TRUE(moved());
  ASSERT_TRUE(ws->drag(ephemeral::Delta{Vec3(0, 0.01, 0), Quat::Identity(), Vec3::Ones()}).is_ok());
  EXPECT_TRUE(moved());
  ws->release();
  EXPECT_TRUE(moved());
  (void)ws->summary();
  (void)ws->pose(Space::kWorld);
  EXPECT_FALSE(moved()) << "reports change nothing";
}

}  // namespace
}  // namespace rigel::app
