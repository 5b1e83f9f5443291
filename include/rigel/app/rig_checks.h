#pragma once
// Rig regression tests from files (`rigel check`, `rigel check record`,
// Python's rigel.record_rig_tests / rigel.check_rig; tools/rig_tests.h): a
// definition built onto its character, or a scene's rig, recorded into
// RIG.rigtest.json and checked against it.

#include <filesystem>
#include <memory>
#include <string>

#include "rigel/base/status.h"
#include "rigel/graph/graph.h"
#include "rigel/rig/component.h"
#include "rigel/scene/scene.h"
#include "rigel/tools/rig_tests.h"

namespace rigel::app {

namespace fs = std::filesystem;

// What a check runs on.
struct RigUnderTest {
  std::unique_ptr<scene::Scene> scene;
  graph::NodeId rig;   // its metaRoot
  std::string name;    // the rig's name
  fs::path character;  // what a definition was built on ("" for a scene)
  bool definition = false;
};

// `file`: a definition (.rig.xml, .rig.json, .build.json) built onto
// `character` (empty: its geometry), or a scene (.rigel) holding rig `rig`
// (empty: its only rig). kInvalidArgument naming "rig" when the scene has
// no such rig, none, or several and none is named; "character" when a
// definition names no geometry and none is given; the definition's
// problems (kInvalidArgument, every one) or the scene's.
Result<RigUnderTest> open_rig_under_test(const fs::path& file, const fs::path& character, const std::string& rig,
                                         const rig::ComponentFactory& factory);

struct RecordedRigTests {
  fs::path output;
  tools::RigTests tests;
};
// Records `file`'s rig (as open_rig_under_test opens it) into `output`
// (empty: beside a definition, tools::rig_tests_path; a scene needs one:
// kInvalidArgument naming "output"), atomically. The character is kept
// relative to the output's folder.
Result<RecordedRigTests> record_rig_tests_file(const fs::path& file, const fs::path& output, const fs::path& character,
                                               const std::string& rig, const tools::RecordRigTestsOptions& options,
                                               const rig::ComponentFactory& factory);

struct RigCheck {
  fs::path tests;      // the file checked against
  std::string rig;
  fs::path character;  // what a definition was built on
  tools::RigTestReport report;
};
// Checks `file`'s rig against `tests` (empty: beside a definition; a scene
// needs one: kInvalidArgument naming "tests"). A definition is built onto
// `character`, else the tests' character (relative to the tests file),
// else its geometry; the rig is `rig`, else the tests' rig.
Result<RigCheck> check_rig_tests_file(const fs::path& file, const fs::path& tests, const fs::path& character,
                                      const std::string& rig, double tolerance, const rig::ComponentFactory& factory);

}  // namespace rigel::app
