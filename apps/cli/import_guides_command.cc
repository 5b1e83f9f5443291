// `rigel import-guides` (import_guides_command.h): prints what the app
// layer's import did, component by component.

#include "import_guides_command.h"

#include <filesystem>
#include <iostream>

#include <nlohmann/json.hpp>

#include "cli_util.h"
#include "rigel/app/guide_import.h"

namespace rigel::cli {
namespace {

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

int run(const ImportGuidesArgs& args) {
  std::filesystem::path output = args.output;
  if (output.empty()) {
    std::string stem = std::filesystem::path(args.file).stem().string();
    if (stem.empty()) stem = "guides";
    output = stem + ".rig.xml";
  }
  auto imported = app::import_guides_file(args.file, output, args.skeleton);
  if (!imported) {
    const Status& s = imported.status();
    if (s.field() == "output" || s.field() == "skeleton") return usage_error(s.message());
    return fail(s);
  }
  const tools::MgearImport& m = imported->imported;
  const std::vector<std::string> unmapped = m.unmapped_components();
  if (args.json) {
    nlohmann::ordered_json report = tools::mgear_report_json(m);
    report["definition"] = imported->definition.string();
    report["skeleton"] = imported->skeleton.string();
    std::cout << report.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) << "\n";
  } else {
    for (const tools::MgearComponentReport& c : m.components) {
      if (!c.mapped()) {
        std::cerr << "rigel: " << c.mgear << " (" << c.mgear_type << "): not imported: " << c.problem << "\n";
        continue;
      }
      std::cerr << "  " << c.mgear << " (" << c.mgear_type << ") -> " << c.rigel_name << " (" << c.rigel_type << ")\n";
      if (!c.unmapped_guides.empty()) std::cerr << "      guides without a counterpart: " << joined(c.unmapped_guides) << "\n";
      if (!c.unmapped_params.empty()) std::cerr << "      parameters without a counterpart: " << joined(c.unmapped_params) << "\n";
      for (const std::string& n : c.notes) std::cerr << "      note: " << n << "\n";
    }
    std::cerr << "rigel: " << (m.components.size() - unmapped.size()) << " of " << m.components.size()
              << " components imported into " << imported->definition.string() << "; " << m.joints.size()
              << " joints written to " << imported->skeleton.string() << "\n";
    if (!unmapped.empty()) std::cerr << "rigel: not imported: " << joined(unmapped) << "\n";
  }
  return unmapped.empty() ? 0 : kExitInvalidInput;
}

}  // namespace

void add_import_guides_command(CLI::App& app, ImportGuidesArgs& args) {
  args.command = app.add_subcommand("import-guides", "Import an mGear guide template (.sgt) as a rig definition and "
                                                     "the skeleton its guides imply");
  args.command->footer(
      "Writes the definition and the skeleton (joints at the guide locators); the definition names the skeleton as\n"
      "its geometry, so `rigel build OUT.rig.xml` builds it. Every component, guide locator and parameter without a\n"
      "rigel counterpart is listed. Exit 1 when a component could not be imported (the files are still written).\n"
      "Examples:\n  rigel import-guides biped.sgt                      # biped.rig.xml and biped.glb here\n"
      "  rigel import-guides biped.sgt -o rigs/hero.rig.json --skeleton rigs/hero_skeleton.glb --json");
  args.command->add_option("FILE", args.file, "mGear guide template (.sgt, JSON)")->required();
  args.command->add_option("-o,--output", args.output, "Definition to write, NAME.rig.xml or NAME.rig.json (default: "
                                                      "FILE's name with .rig.xml, in the current folder)");
  args.command->add_option("--skeleton", args.skeleton, "Skeleton to write, .glb or .gltf (default: NAME.glb beside "
                                                        "the definition)");
  args.command->add_flag("--json", args.json, "Print the report as JSON on stdout");
}

std::optional<int> run_import_guides_command(const ImportGuidesArgs& args) {
  if (!args.command || !*args.command) return std::nullopt;
  return run(args);
}

}  // namespace rigel::cli
