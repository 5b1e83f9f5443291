// The rigel command line: a thin driver over the library (STYLE.md §8), one
// file per command group, each calling the app layer (app/workspace.h,
// app/scene_files.h) and printing its answer. Exit status: 0 success, 1
// invalid input, 2 usage error (DESIGN.md); helpers shared by the groups
// are in cli_util.h.

#include <iostream>
#include <optional>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "animate_commands.h"
#include "pipeline_commands.h"
#include "rigging_commands.h"
#include "settings_command.h"
#include "space_command.h"
#include "cli_util.h"
#include "check_command.h"
#include "import_guides_command.h"
#include "definition_commands.h"
#include "ephemeral_commands.h"
#include "key_commands.h"
#include "pose_command.h"
#include "poses_command.h"
#include "graph_commands.h"
#include "rig_commands.h"
#include "scene_commands.h"
#include "serve_command.h"
#include "transfer_command.h"
#include "rigel/tools/build_functions.h"

int main(int argc, char** argv) {
  CLI::App app{"rigel: a character-rigging engine that needs no host application"};
  app.require_subcommand(1);
  app.set_help_all_flag("--help-all", "Print help for every subcommand");
  std::string log_level;
  rigel::cli::add_log_level_option(app, log_level);

  // `inspect`, `eval`, `import`, `export`, `bake`: scene files.
  rigel::cli::SceneCommands scene;
  rigel::cli::add_scene_commands(app, scene);
  // `key`, `keys`, `tween`, `set`: keys and values on any rig's channels.
  rigel::cli::KeyCommands keys;
  rigel::cli::add_key_commands(app, keys);
  // `match`, `mirror`, `bind-pose`: the animator tools.
  rigel::cli::AnimateCommands animate;
  rigel::cli::add_animate_commands(app, animate);
  // `transfer`: keys from one component or character onto another.
  rigel::cli::TransferArgs transfer;
  rigel::cli::add_transfer_command(app, transfer);
  // `space`: a control's spaces.
  rigel::cli::SpaceCommand space;
  rigel::cli::add_space_command(app, space);
  // `playback`, `sets`: the scene's playback range and selection sets.
  rigel::cli::SettingsCommands settings;
  rigel::cli::add_settings_commands(app, settings);
  // `shape`, `align`, `locator`, `mirror-joints`: rigger actions.
  rigel::cli::RiggingCommands rigging;
  rigel::cli::add_rigging_commands(app, rigging);
  // `project`, `asset`, `config`: the rigging pipeline.
  rigel::cli::PipelineCommands pipeline;
  rigel::cli::add_pipeline_commands(app, pipeline);
  // `poses save|apply|list|remove`: the pose library.
  rigel::cli::PosesCommand poses;
  rigel::cli::add_poses_command(app, poses);
  // `check [record]`: rig regression tests.
  rigel::cli::CheckCommand check;
  rigel::cli::add_check_command(app, check);
  // `import-guides`: mGear guide templates as definitions.
  rigel::cli::ImportGuidesArgs import_guides;
  rigel::cli::add_import_guides_command(app, import_guides);
  // `ephemeral setup|relations|key|keys|scope|merge|unmerge`.
  rigel::cli::EphemeralCommands ephemeral;
  rigel::cli::add_ephemeral_commands(app, ephemeral);
  // `pose`: one drag of an ephemeral or a built rig's controls.
  rigel::cli::PoseArgs pose;
  rigel::cli::add_pose_command(app, pose);
  // `validate`, `components`, `schema`, `diff`: rig definitions.
  rigel::cli::DefinitionCommands definition;
  rigel::cli::add_definition_commands(app, definition);
  // `build`, `update`, `rigs`, `remove`, `address`: built rigs.
  rigel::cli::RigCommands rig;
  rigel::cli::add_rig_commands(app, rig);
  // `graph run|convert|validate`: build graphs.
  rigel::cli::GraphCommands graphs;
  rigel::cli::add_graph_commands(app, graphs);
  // `serve`: the web app and the JSON API.
  rigel::cli::ServeArgs serve;
  CLI::App* serve_cmd = rigel::cli::add_serve_command(app, serve);

  // Examples for the commands whose files do not set their own.
  const std::pair<std::vector<const char*>, const char*> examples[] = {
      {{"schema"}, "Examples:\n  rigel schema --json > rig.schema.json\n  rigel schema --xsd > rig.xsd"},
      {{"pose"}, "Examples:\n  rigel pose human.rigel --control hand.L --mode inverse --max-chain 3 --translate 0,0.15,0.1 -o posed.rigel\n"
                 "  rigel pose human.rigel --control spine.003 --select spine.004,spine.005 --mode forward --rotate 0,15,0 -o posed.rigel"},
      {{"ephemeral", "setup"}, "Examples:\n  rigel ephemeral setup tests/data/gltf/rigify_human_metarig.glb -o human.rigel\n"
                               "  rigel ephemeral setup walk.rigel --joints hips,spine,chest --shape-radius 0.05 -o walk_rig.rigel"},
      {{"ephemeral", "relations"}, "Examples:\n  rigel ephemeral relations human.rigel --json\n"
                                   "  rigel ephemeral relations human.rigel --add pair:hand.L_ctrl:hand.R_ctrl -o human2.rigel"},
      {{"ephemeral", "key"}, "Examples:\n  rigel ephemeral key human.rigel --control hand.L --frame 10 -o keyed.rigel\n"
                             "  rigel ephemeral key keyed.rigel --control hand.L --frame 10 --delete -o keyed.rigel"},
      {{"ephemeral", "keys"}, "Example:\n  rigel ephemeral keys keyed.rigel --control hand.L --json"},
      {{"ephemeral", "scope"}, "Examples:\n  rigel ephemeral scope human.rigel --rig ephemeralRig\n"
                               "  rigel ephemeral scope human.rigel --rig ephemeralRig --set controls -o human2.rigel"},
      {{"ephemeral", "merge"}, "Example:\n  rigel ephemeral merge scene.rigel --rigs hero_rig,sword_rig --carrier hand.R_ctrl --carried sword_rig -o merged.rigel"},
      {{"ephemeral", "unmerge"}, "Example:\n  rigel ephemeral unmerge merged.rigel --rig sword_rig -o apart.rigel"},
  };
  for (const auto& [path, text] : examples) {
    CLI::App* cmd = &app;
    for (const char* name : path) cmd = cmd->get_subcommand(name);
    cmd->footer(text);
  }

  // Graphs name build functions: the shipped ones are there before any file is read.
  rigel::tools::register_build_functions();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    int code = app.exit(e);
    return code == 0 ? 0 : rigel::cli::kExitUsage;
  }
  if (const std::optional<int> code = rigel::cli::apply_log_level(log_level)) return *code;
  try {
    if (const std::optional<int> code = rigel::cli::run_pipeline_commands(pipeline)) return *code;
    if (const std::optional<int> code = rigel::cli::run_scene_commands(scene)) return *code;
    if (const std::optional<int> code = rigel::cli::run_key_commands(keys)) return *code;
    if (const std::optional<int> code = rigel::cli::run_animate_commands(animate)) return *code;
    if (*transfer.command) return rigel::cli::run_transfer(transfer);
    if (const std::optional<int> code = rigel::cli::run_space_command(space)) return *code;
    if (const std::optional<int> code = rigel::cli::run_settings_commands(settings)) return *code;
    if (const std::optional<int> code = rigel::cli::run_rigging_commands(rigging)) return *code;
    if (const std::optional<int> code = rigel::cli::run_poses_command(poses)) return *code;
    if (const std::optional<int> code = rigel::cli::run_check_command(check)) return *code;
    if (const std::optional<int> code = rigel::cli::run_import_guides_command(import_guides)) return *code;
    if (const std::optional<int> code = rigel::cli::run_ephemeral_commands(ephemeral)) return *code;
    if (*pose.command) return rigel::cli::run_pose(pose);
    if (const std::optional<int> code = rigel::cli::run_definition_commands(definition)) return *code;
    if (const std::optional<int> code = rigel::cli::run_rig_commands(rig)) return *code;
    if (const std::optional<int> code = rigel::cli::run_graph_commands(graphs)) return *code;
    if (*serve_cmd) return rigel::cli::run_serve(serve);
  } catch (const std::exception& e) {
    // Nothing should throw past the library's Status results; if something
    // does, report it as an error instead of crashing.
    std::cerr << "rigel: internal error: " << e.what() << "\n";
    return rigel::cli::kExitInvalidInput;
  }
  return rigel::cli::kExitUsage;
}
