#pragma once
// Rig regression tests (issue 21, after Unreal's ControlRigTestData): a
// built rig's poses (its controls' values, at frames), each with the world
// matrices the scene's joints had under it, recorded once and checked after
// any change to the rig's definition, its components or rigel itself. A
// mismatch names the pose, the joint and the error, so a rig that many
// shots depend on is tested for what it does, not only for how it is made.
//
// Recording makes the poses one of two ways:
//   - generated (no frames given): `rest` (every control as built), one
//     pose per component whose controls have a translate or rotation (each
//     such control moved by a fixed offset and turned by a fixed rotation,
//     the rest left at rest), and `all` (every control moved so at once),
//     all at frame 0: what a definition built on its character records;
//   - played (frames given): one pose per frame, every control's values as
//     the scene's animation gives them there: what a shot records.
//
// Checking applies the first pose's values (`rest`) and then each pose's
// (poses are resolved by rigId, role and index, as the pose library does:
// tools/poses.h), at its frame, and compares every recorded joint's world
// matrix with the one recorded (largest element difference).
//
// The file, RIG.rigtest.json (beside the definition: biped.rig.xml ->
// biped.rigtest.json), is diffable JSON: the rig's name, the character it
// was recorded on (relative to the file), `base` (every joint's world
// matrix under the rest pose, 16 numbers column-major), `rest` (a pose as
// the pose library writes it) and `poses`, each with its name, frame, the
// controls it sets and the joints whose world matrix differs from `base`
// under it. Numbers keep 12 significant digits.

#include <cstddef>
#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/graph/graph.h"
#include "rigel/math/types.h"
#include "rigel/scene/scene.h"
#include "rigel/tools/poses.h"

namespace rigel::tools {

inline constexpr const char* kRigTestExtension = ".rigtest.json";

struct RigTestPose {
  std::string name;
  double frame = 0;
  Pose pose;  // the controls it sets (after the rest pose's)
  // The joints whose world matrix under this pose differs from `base`.
  std::map<std::string, math::Mat4> joints;
};

struct RigTests {
  std::string rig;        // the rig's name
  std::string character;  // the character it was recorded on ("" for a scene), relative to the file
  Pose rest;              // every control's values under the first pose
  std::map<std::string, math::Mat4> base;  // every joint's world matrix under the rest pose
  std::vector<RigTestPose> poses;
};

struct RecordRigTestsOptions {
  // Empty: generated poses at frame 0. Else one pose per frame, as the
  // scene plays (each finite, at most 100,000 of them).
  std::vector<double> frames;
  double offset = 0.05;   // a generated pose's move of each control (scene units, along (1, 0.6, -0.4))
  double degrees = 20.0;  // and its turn (about (1, 2, 3))
};

// Records `rig` (its metaRoot) in `scene`. kInvalidArgument naming "rig"
// when it has no control with a keyable channel, "frames" for a frame that
// is not finite or too many frames. Leaves the scene at the last pose (the
// caller's to keep or drop).
Result<RigTests> record_rig_tests(scene::Scene& scene, graph::NodeId rig, const RecordRigTestsOptions& options = {});

std::string rig_tests_to_json(const RigTests& tests);
// kParseError naming the file and the place ("hero.rigtest.json:3:7: ..."
// for syntax, "hero.rigtest.json: poses[2].joints.hand.L: ..." for content).
Result<RigTests> rig_tests_from_json(std::string_view text, const std::string& source);
// Reads a file (at most 256 MiB): kNotFound naming "tests" when there is none.
Result<RigTests> load_rig_tests(const std::filesystem::path& path);
// Writes atomically; kIoError naming "output".
Status save_rig_tests(const RigTests& tests, const std::filesystem::path& path);
// The tests file of a definition: biped.rig.xml -> biped.rigtest.json
// (likewise .rig.json and .build.json); another name gets the extension
// added.
std::filesystem::path rig_tests_path(const std::filesystem::path& definition);

struct RigTestMismatch {
  std::string pose, joint;
  double error = 0;     // the largest element difference of its world matrix
  std::string problem;  // "" for a difference; else what went wrong ("no such joint", "cannot be applied: ...")
};

struct RigTestReport {
  std::size_t poses = 0, joints = 0;  // checked
  double max_error = 0;               // over every joint of every pose
  std::vector<RigTestMismatch> mismatches;
  bool ok() const { return mismatches.empty(); }
};

// Checks `tests` against `rig` (its metaRoot) in `scene`: every pose, every
// joint; a joint off by more than `tolerance`, a joint the scene lacks, or
// a pose that cannot be applied (a component or control gone) is a
// mismatch. kInvalidArgument naming "tolerance" for a negative or
// non-finite one. The scene is left at the last pose.
Result<RigTestReport> check_rig_tests(scene::Scene& scene, graph::NodeId rig, const RigTests& tests,
                                      double tolerance = 1e-6);

}  // namespace rigel::tools
