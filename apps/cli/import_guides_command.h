#pragma once
// `rigel import-guides FILE.sgt [-o OUT.rig.xml] [--skeleton OUT.glb]`: an
// mGear guide template as a definition and the skeleton it implies
// (app/guide_import.h). main.cc registers it with
// add_import_guides_command() and runs it with run_import_guides_command().

#include <optional>
#include <string>

#include <CLI/CLI.hpp>

namespace rigel::cli {

struct ImportGuidesArgs {
  CLI::App* command = nullptr;
  std::string file, output, skeleton;
  bool json = false;
};

void add_import_guides_command(CLI::App& app, ImportGuidesArgs& args);
std::optional<int> run_import_guides_command(const ImportGuidesArgs& args);

}  // namespace rigel::cli
