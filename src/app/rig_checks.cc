// Rig regression tests from files (rig_checks.h).

#include "rigel/app/rig_checks.h"

#include "rigel/app/rig_files.h"
#include "rigel/app/scene_files.h"
#include "rigel/rig/build_graph.h"
#include "rigel/rig/manager.h"
#include "rigel/rig/meta.h"

namespace rigel::app {
namespace {

bool is_definition(const fs::path& file) {
  const std::string name = file.filename().string();
  return name.ends_with(".rig.xml") || name.ends_with(".rig.json") || rig::is_build_graph_path(file);
}

// The rig named `name` in `scene` (empty: its only one).
Result<graph::NodeId> rig_in(const scene::Scene& scene, const std::string& name, const fs::path& file) {
  const graph::Graph& g = scene.graph();
  if (!name.empty()) {
    const graph::NodeId r = rig::find_rig(g, name);
    if (!r.is_valid()) return Status(ErrorCode::kInvalidArgument, file.string() + ": no rig named '" + name + "'").with_field("rig");
    return r;
  }
  const std::vector<graph::NodeId> roots = rig::list_rigs(g);
  if (roots.size() == 1) return roots.front();
  return Status(ErrorCode::kInvalidArgument,
                file.string() + (roots.empty() ? ": the scene has no rig" : ": the scene has several rigs: name one"))
      .with_field("rig");
}

}  // namespace

Result<RigUnderTest> open_rig_under_test(const fs::path& file, const fs::path& character, const std::string& rig,
                                         const rig::ComponentFactory& factory) {
  RigUnderTest out;
  if (is_definition(file)) {
    auto def = rig::read_definition(file);
    if (!def) return def.status();
    BuildFileOptions options;
    options.character = character;
    auto built = build_rig_file(*def, file, factory, options);
    if (!built) return built.status();
    out.scene = std::move(built->scene);
    out.character = built->character;
    out.definition = true;
  } else {
    auto scene = open_scene(file);
    if (!scene) return scene.status();
    out.scene = std::move(*scene);
  }
  auto r = rig_in(*out.scene, out.definition ? std::string() : rig, file);
  if (!r) return r.status();
  out.rig = *r;
  out.name = rig::meta_string(out.scene->graph(), out.rig, "rigName");
  return out;
}

Result<RecordedRigTests> record_rig_tests_file(const fs::path& file, const fs::path& output, const fs::path& character,
                                               const std::string& rig, const tools::RecordRigTestsOptions& options,
                                               const rig::ComponentFactory& factory) {
  if (output.empty() && !is_definition(file))
    return Status(ErrorCode::kInvalidArgument, "a scene's tests need a file to go to (-o)").with_field("output");
  const fs::path to = output.empty() ? tools::rig_tests_path(file) : output;
  auto under = open_rig_under_test(file, character, rig, factory);
  if (!under) return under.status();
  auto tests = tools::record_rig_tests(*under->scene, under->rig, options);
  if (!tests) return tests.status();
  if (!under->character.empty()) {
    const fs::path folder = to.parent_path().empty() ? fs::path(".") : to.parent_path();
    tests->character = fs::relative(fs::absolute(under->character), fs::absolute(folder)).generic_string();
  }
  if (Status s = tools::save_rig_tests(*tests, to); !s) return s;
  return RecordedRigTests{to, std::move(*tests)};
}

Result<RigCheck> check_rig_tests_file(const fs::path& file, const fs::path& tests_path, const fs::path& character,
                                      const std::string& rig, double tolerance, const rig::ComponentFactory& factory) {
  if (tests_path.empty() && !is_definition(file))
    return Status(ErrorCode::kInvalidArgument, "a scene is checked against a tests file (--tests)").with_field("tests");
  RigCheck out;
  out.tests = tests_path.empty() ? tools::rig_tests_path(file) : tests_path;
  auto tests = tools::load_rig_tests(out.tests);
  if (!tests) return tests.status();
  fs::path on = character;
  if (on.empty() && !tests->character.empty()) on = out.tests.parent_path() / tests->character;
  auto under = open_rig_under_test(file, on, rig.empty() ? tests->rig : rig, factory);
  if (!under) return under.status();
  auto report = tools::check_rig_tests(*under->scene, under->rig, *tests, tolerance);
  if (!report) return report.status();
  out.rig = under->name;
  out.character = under->character;
  out.report = std::move(*report);
  return out;
}

}  // namespace rigel::app
