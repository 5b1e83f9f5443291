// The rig commands of `rigel` (see rig_commands.h): build, update, rigs,
// remove, address.

#include "rig_commands.h"

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_util.h"
#include "pipeline_commands.h"
#include "rigel/app/rig_files.h"
#include "rigel/app/workspace.h"
#include "rigel/ephemeral/component.h"
#include "rigel/io/scene_file.h"
#include "rigel/rig/build.h"
#include "rigel/rig/component.h"
#include "rigel/rig/definition_io.h"
#include "rigel/rig/manager.h"
#include "rigel/rig/meta.h"
#include "rigel/scene/transform_types.h"
#include "rigel/tools/data_files.h"
#include "rigel/tools/publish.h"

namespace rigel::cli {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;
using graph::NodeId;

// Every component class rigel has (the rig layer's and `ephemeral`), with the
// data importer a definition's <data> needs (tools/data_files.h).
const rig::ComponentFactory& factory() { return tools::components(); }

// Reads and checks a definition; prints every problem (file:line:column).
std::optional<rig::Definition> read_definition(const std::string& path) {
  auto def = rig::read_definition(path);
  if (!def) {
    const std::string& problems = def.status().message();
    const auto count = std::count(problems.begin(), problems.end(), '\n') + 1;
    std::cerr << problems << "\n" << "rigel: " << path << ": " << count << (count == 1 ? " error\n" : " errors\n");
    return std::nullopt;
  }
  return std::move(*def);
}

// A scene file held for one command (the app layer's operations), saved by
// the command to its --output.
Result<std::unique_ptr<app::Workspace>> open_workspace(const std::string& path) {
  auto scene = load(path);
  if (!scene) return scene.status();
  return std::make_unique<app::Workspace>(std::move(*scene), path, fs::path(), factory());
}

void print_json(const Json& j) { std::cout << j.dump(2, ' ', false, Json::error_handler_t::replace) << "\n"; }

}  // namespace

// ---- build ---------------------------------------------------------------

int run_build(const BuildArgs& given) {
  // Inside an asset: bare names are its definitions and skeletons, and its
  // skeleton is the default character.
  BuildArgs args = given;
  args.definition = in_current_asset(args.definition, tools::AssetFile::kDefinition);
  args.character = args.character.empty() ? current_asset_skeleton() : in_current_asset(args.character, tools::AssetFile::kCharacter);
  std::optional<rig::Definition> def = read_definition(args.definition);
  if (!def) return kExitInvalidInput;
  app::BuildFileOptions options;
  options.character = args.character;
  options.steps = args.steps;
  options.edit_mode = args.edit_mode;
  options.naming_template = settings().string("naming.template");
  const bool progress = !args.json && isatty(2);
  if (progress) options.progress = [](int step, int of) { std::cerr << "\rrigel: building " << step << "/" << of << std::flush; };
  std::vector<rig::Diagnostic> missing;
  auto built = app::build_rig_file(*def, args.definition, factory(), options, &missing);
  if (progress) std::cerr << "\n";
  if (!built) {
    const Status& s = built.status();
    if (s.field() == "character") return usage_error(args.definition + ": the definition names no geometry; give --character");
    if (s.field() == "steps") return usage_error(s.message());
    if (s.field() == "guides") {
      // Every guide joint the character lacks, each at its place.
      Json errors = Json::array();
      for (const rig::Diagnostic& d : missing) {
        std::cerr << d.str() << "\n";
        errors.push_back(Json{{"file", d.file}, {"line", d.where.line}, {"column", d.where.column}, {"message", d.message}});
      }
      std::cerr << "rigel: " << s.message() << "\n";
      if (args.json) {
        const std::string character = app::rig_character(*def, args.definition, args.character).string();
        print_json(Json{{"rig", def->name}, {"character", character}, {"errors", errors}});
      }
      return kExitInvalidInput;
    }
    return fail(s);
  }
  if (Status s = io::save_scene(*built->scene, args.output); !s) return fail(s);
  const std::string character = built->character.string();
  if (args.json) {
    Json comps = Json::array();
    for (const app::BuiltComponent& c : built->components)
      comps.push_back(Json{{"name", c.name}, {"side", rig::side_name(c.side)}, {"type", c.type}, {"rigId", c.rig_id}});
    print_json(Json{{"rig", built->rig},
                    {"version", built->version},
                    {"steps", built->steps},
                    {"of", built->of},
                    {"components", comps},
                    {"nodes", built->nodes},
                    {"output", args.output}});
  } else {
    std::cerr << "rigel: built " << built->rig << " " << built->version << " (" << built->components.size()
              << " components, " << built->steps << "/" << built->of << " steps, " << built->nodes << " nodes) on "
              << character << " into " << args.output << "\n";
  }
  return 0;
}

namespace {

// ---- update --------------------------------------------------------------

struct UpdateArgs {
  std::string scene;
  std::string rig;         // "" = every rig
  std::string definition;  // "" = each rig's definitionPath
  bool force = false;
  std::string keep_keys = "local";
  std::string output;
  bool json = false;
};

int run_update(const UpdateArgs& args) {
  auto ws = open_workspace(args.scene);
  if (!ws) return fail(ws.status());
  graph::Graph& g = (*ws)->graph();
  std::vector<NodeId> rigs;
  if (args.rig.empty()) {
    rigs = rig::list_rigs(g);
  } else {
    if (Status s = (*ws)->check_rig(args.rig, false); !s) return fail(s.with_context(args.scene));
    rigs.push_back(rig::find_rig(g, args.rig));
  }
  if (rigs.empty()) return fail(error(ErrorCode::kNotFound, args.scene + ": the scene holds no rig"));
  if (!args.definition.empty() && rigs.size() > 1)
    return usage_error("--definition applies to one rig: name it with --rig");
  Json report = Json::array();
  const auto keep = args.keep_keys == "world" ? rig::Build::KeepKeys::kWorld : rig::Build::KeepKeys::kLocal;
  const bool progress = !args.json && rigs.size() > 1 && isatty(2);
  for (std::size_t i = 0; i < rigs.size(); ++i) {
    const std::string name = rig::meta_string(g, rigs[i], "rigName");
    if (progress) std::cerr << "rigel: updating " << name << " (" << (i + 1) << "/" << rigs.size() << ")\n";
    auto r = (*ws)->update_rig(name, args.definition, args.force, keep);
    if (!r) return fail(r.status().with_context(args.scene));
    report.push_back(Json{{"rig", r->rig}, {"from", r->from}, {"to", r->to}, {"definition", r->definition},
                          {"rebuilt", r->rebuilt}});
    if (args.json) continue;
    if (!r->updated) {
      std::cerr << "rigel: " << name << " " << r->from << " is up to date with " << r->definition << "\n";
    } else {
      std::cerr << "rigel: " << name << " " << r->from << " -> " << r->to << ": rebuilt " << r->rebuilt.size()
                << " component(s)";
      for (std::size_t k = 0; k < r->rebuilt.size(); ++k) std::cerr << (k ? ", " : ": ") << r->rebuilt[k];
      std::cerr << "\n";
    }
  }
  if (auto s = (*ws)->save(args.output); !s) return fail(s.status());
  if (args.json) print_json(Json{{"rigs", report}, {"output", args.output}});
  return 0;
}

// ---- rigs ----------------------------------------------------------------

struct RigsArgs {
  std::vector<std::string> scenes;
  bool json = false;
  bool check = false;  // exit 1 when a rig is out of date (definition or published version)
};

// Whether every rig is up to date: its definition found and not newer, its
// published version the newest.
bool rigs_current(const Json& list) {
  for (const Json& r : list) {
    if (!r["definitionFound"].get<bool>() || r["outOfDate"].get<bool>()) return false;
    if (r.contains("published") && r["published"]["outOfDate"].get<bool>()) return false;
  }
  return true;
}

// The rigs report with where each published rig came from (tools/publish.h).
Json rigs_with_published(const graph::Graph& g) {
  Json list = rig::rigs_report(g);
  for (const tools::PublishedRig& p : tools::published_rigs(g))
    for (Json& r : list)
      if (r["name"] == p.rig)
        r["published"] = Json{{"asset", p.asset}, {"version", p.version}, {"newest", p.newest}, {"outOfDate", p.out_of_date()}};
  return list;
}

int run_rigs_of(const std::string& path, bool json, Json* all, bool check) {
  auto scene = load(path);
  if (!scene) return fail(scene.status());
  const Json list = rigs_with_published((*scene)->graph());
  const int code = check && !rigs_current(list) ? kExitInvalidInput : 0;
  if (code) std::cerr << "rigel: " << path << ": a rig is out of date\n";
  if (json) {
    if (all) all->push_back(Json{{"scene", path}, {"rigs", list}, {"current", rigs_current(list)}});
    else print_json(Json{{"rigs", list}, {"current", rigs_current(list)}});
    return code;
  }
  if (all) std::cout << path << ":\n";
  if (list.empty()) std::cout << "no rigs\n";
  for (const Json& r : list) {
    std::cout << r["name"].get<std::string>() << " " << r["version"].get<std::string>() << "  "
              << r["definition"].get<std::string>();
    if (r.contains("published")) {
      const Json& p = r["published"];
      std::cout << "  (published " << p["asset"].get<std::string>() << " v" << p["version"].get<int>();
      if (p["outOfDate"].get<bool>()) std::cout << "; out of date: the newest is v" << p["newest"].get<int>();
      if (p["newest"].get<int>() == 0) std::cout << "; its asset is not where the scene says";
      std::cout << ")";
    }
    if (!r["definitionFound"].get<bool>())
      std::cout << "  (definition missing: " << r["definitionProblem"].get<std::string>() << ")";
    else if (r["outOfDate"].get<bool>())
      std::cout << "  (out of date: definition on disk " << r["definitionVersion"].get<std::string>() << ")";
    std::cout << "\n";
    for (const Json& c : r["components"]) {
      std::cout << "  " << c["name"].get<std::string>() << " (" << c["type"].get<std::string>() << " "
                << c["version"].get<std::string>() << ")  " << c["rigId"].get<std::string>();
      if (c["state"] == "changed")
        std::cout << "  out of date: definition has " << c["definitionVersion"].get<std::string>();
      else if (c["state"] == "removed")
        std::cout << "  out of date: not in the definition";
      std::cout << "\n";
    }
    for (const Json& c : r["added"])
      std::cout << "  " << c["name"].get<std::string>() << " (" << c["type"].get<std::string>() << " "
                << c["definitionVersion"].get<std::string>() << ")  " << c["rigId"].get<std::string>()
                << "  out of date: in the definition, not built\n";
  }
  return code;
}

// Several scenes (shots): each one's rigs, and which are older than their
// asset's newest published version.
int run_rigs(const RigsArgs& args) {
  if (args.scenes.size() == 1) return run_rigs_of(args.scenes[0], args.json, nullptr, args.check);
  Json all = Json::array();
  int code = 0;
  for (const std::string& s : args.scenes) code = std::max(code, run_rigs_of(s, args.json, &all, args.check));
  if (args.json) print_json(Json{{"scenes", all}});
  return code;
}

// ---- remove --------------------------------------------------------------

struct RemoveArgs {
  std::string scene;
  std::string rig;
  std::string output;
  bool json = false;
};

int run_remove(const RemoveArgs& args) {
  auto ws = open_workspace(args.scene);
  if (!ws) return fail(ws.status());
  if (Status s = (*ws)->remove_rig(args.rig); !s) return fail(s.with_context(args.scene));
  if (auto s = (*ws)->save(args.output); !s) return fail(s.status());
  if (args.json) print_json(Json{{"removed", args.rig}, {"output", args.output}});
  else std::cerr << "rigel: removed " << args.rig << " into " << args.output << "\n";
  return 0;
}

// ---- meta ----------------------------------------------------------------

struct MetaArgs {
  std::string scene;
  std::vector<std::string> nodes;  // --of NODE: the component that built it
  std::string rig;                 // with --child / --connection
  std::string component;           // rigId or name (--connection); "" = the rig
  std::string child;               // --child RIGID (getMetaChildById, under --component or the rig)
  std::string connection;          // --connection ROLE (getMetaNodeConnection)
  int index = 0;
  bool json = false;
};

Json meta_json(const graph::Graph& g, NodeId meta) {
  Json j{{"meta", g.node(meta)->name()},
         {"metaType", rig::meta_string(g, meta, "metaType")},
         {"rig", rig::meta_string(g, rig::rig_of(g, meta), "rigName")}};
  if (g.node(meta)->type().name() == rig::kMetaComponentType) {
    j["component"] = rig::meta_string(g, meta, "componentName");
    j["side"] = rig::meta_string(g, meta, "side");
    j["rigId"] = rig::meta_string(g, meta, "rigId");
    j["version"] = rig::meta_string(g, meta, "version");
  }
  return j;
}

int run_meta(const MetaArgs& args) {
  auto scene = load(args.scene);
  if (!scene) return fail(scene.status());
  const graph::Graph& g = (*scene)->graph();
  if (args.nodes.empty() && args.child.empty() && args.connection.empty())
    return usage_error("meta: give --of NODE, --child RIGID or --connection ROLE");
  Json out = Json::array();
  for (const std::string& name : args.nodes) {
    const NodeId id = g.find(name);
    if (!id.is_valid()) return fail(error(ErrorCode::kNotFound, args.scene + ": no node '" + name + "'"));
    const NodeId meta = rig::component_of(g, id);
    if (!meta.is_valid())
      return fail(error(ErrorCode::kNotFound, args.scene + ": '" + name + "' is not part of a rig"));
    Json j = meta_json(g, meta);
    j["node"] = name;
    const graph::Node& n = *g.node(id);
    if (const std::string* role = n.tag_find(rig::kTagRole)) j["role"] = *role;
    if (const std::string* index = n.tag_find(rig::kTagIndex)) j["index"] = std::stoi(*index);
    if (Result<std::string> a = rig::address_of(g, id); a) j["address"] = *a;
    out.push_back(j);
  }
  if (!args.child.empty() || !args.connection.empty()) {
    if (args.rig.empty()) return usage_error("meta: --child and --connection need --rig");
    const NodeId root = rig::find_rig(g, args.rig);
    if (!root.is_valid()) return fail(error(ErrorCode::kNotFound, args.scene + ": no rig '" + args.rig + "'"));
    NodeId meta = root;
    if (!args.component.empty()) {
      meta = rig::find_component(g, root, args.component);
      if (!meta.is_valid())
        return fail(error(ErrorCode::kNotFound, args.rig + ": no component '" + args.component + "'"));
    }
    if (!args.child.empty()) {
      const NodeId c = rig::get_meta_child_by_id(g, meta, args.child);
      if (!c.is_valid())
        return fail(error(ErrorCode::kNotFound, g.node(meta)->name() + ": no child component with rigId " + args.child));
      out.push_back(meta_json(g, c));
    }
    if (!args.connection.empty()) {
      Result<NodeId> n = rig::get_meta_connection(g, meta, args.connection, args.index);
      if (!n) return fail(n.status().with_context(args.scene));
      Json j = meta_json(g, meta);
      j["node"] = g.node(*n)->name();
      j["type"] = g.node(*n)->type().name();
      j["role"] = args.connection;
      j["index"] = args.index;
      out.push_back(j);
    }
  }
  if (args.json) {
    print_json(Json{{"results", out}});
    return 0;
  }
  for (const Json& j : out) {
    if (j.contains("node")) std::cout << j["node"].get<std::string>() << "  ";
    std::cout << j["rig"].get<std::string>();
    if (j.contains("component"))
      std::cout << ":" << j["component"].get<std::string>() << " (" << j["metaType"].get<std::string>() << " "
                << j["version"].get<std::string>() << ", rigId " << j["rigId"].get<std::string>() << ")";
    if (j.contains("role")) std::cout << "  role " << j["role"].get<std::string>();
    std::cout << "\n";
  }
  return 0;
}

// ---- edit ----------------------------------------------------------------

struct EditArgs {
  std::string scene;
  std::string rig;                  // "" = the scene's only rig
  std::vector<std::string> moves;   // ADDRESS=X,Y,Z (translate, metres)
  std::vector<std::string> turns;   // ADDRESS=X,Y,Z (rotate, degrees)
  std::string definition_out;       // "" = the rig's definition path
  std::string output;
  bool keep_editing = false;        // stay in rig edit mode after committing
  bool json = false;
};

// Sets `attr` of the control ADDRESS names from "ADDRESS=X,Y,Z".
Status apply_channel(graph::Graph& g, const std::string& spec, graph::AttrIndex attr, const char* option) {
  const std::size_t eq = spec.rfind('=');
  if (eq == std::string::npos)
    return error(ErrorCode::kInvalidArgument, std::string(option) + " '" + spec + "': expected ADDRESS=X,Y,Z");
  const std::optional<math::Vec3> v = parse_vec3(spec.substr(eq + 1));
  if (!v) return error(ErrorCode::kInvalidArgument, std::string(option) + " '" + spec + "': X,Y,Z must be three numbers");
  Result<NodeId> id = rig::resolve_address(g, spec.substr(0, eq));
  if (!id) return id.status().with_context(option);
  if (g.node(*id)->type().name() != scene::kControlType)
    return error(ErrorCode::kInvalidArgument, std::string(option) + " '" + spec + "': '" + g.node(*id)->name() + "' is not a control");
  return g.set_value(graph::Plug{*id, attr, -1}, graph::Value(*v));
}

int run_edit(const EditArgs& args) {
  auto ws = open_workspace(args.scene);
  if (!ws) return fail(ws.status());
  graph::Graph& g = (*ws)->graph();
  std::string rig_name = args.rig;
  if (rig_name.empty()) {
    const std::vector<NodeId> rigs = rig::list_rigs(g);
    if (rigs.size() != 1)
      return usage_error(args.scene + ": has " + std::to_string(rigs.size()) + " rigs; name one with --rig");
    rig_name = rig::meta_string(g, rigs.front(), "rigName");
  }
  if (Status s = (*ws)->check_rig(rig_name, false); !s) return fail(s.with_context(args.scene));
  for (const std::string& m : args.moves)
    if (Status s = apply_channel(g, m, scene::xform::kTranslate, "--move"); !s) return fail(s);
  for (const std::string& t : args.turns)
    if (Status s = apply_channel(g, t, scene::xform::kRotate, "--turn"); !s) return fail(s);
  // Committing records where the definition goes (the rig is then up to
  // date with it) and leaves edit mode unless --keep-editing.
  Result<app::CommitReport> edits = (*ws)->commit_edits(rig_name, args.definition_out, args.keep_editing);
  if (!edits) {
    if (args.definition_out.empty() && edits.status().field() == "definitionOut" &&
        edits.status().code() == ErrorCode::kInvalidArgument)
      return usage_error(rig_name + " has no definition path; give --definition-out");
    return fail(edits.status().with_context(args.scene));
  }
  const std::string out_def = edits->definition_path.string();
  if (auto s = (*ws)->save(args.output); !s) return fail(s.status());
  if (args.json) {
    Json changed = Json::array();
    for (const std::string& id : edits->changed) {
      const rig::Component* c = edits->definition.find_by_rig_id(id);
      changed.push_back(Json{{"rigId", id}, {"name", c ? c->name : ""}, {"version", c ? c->version : ""}});
    }
    print_json(Json{{"rig", rig_name},
                    {"version", edits->definition.version},
                    {"changed", changed},
                    {"ignored", edits->ignored},
                    {"definition", edits->changed.empty() ? Json(nullptr) : Json(out_def)},
                    {"editMode", edits->edit_mode},
                    {"output", args.output}});
  } else if (edits->changed.empty()) {
    std::cerr << "rigel: " << rig_name << ": no guide moved; the definition is unchanged\n";
  } else {
    std::cerr << "rigel: " << rig_name << " " << edits->definition.version << ": " << edits->changed.size()
              << " component(s) with moved guides, written to " << out_def << "; rebuilt into " << args.output << "\n";
  }
  for (const std::string& n : edits->ignored)
    std::cerr << "rigel: warning: '" << n << "' was moved but stands for no guide; not written back\n";
  return 0;
}

// ---- address -------------------------------------------------------------

struct AddressArgs {
  std::string scene;
  std::vector<std::string> addresses;
  bool json = false;
};

int run_address(const AddressArgs& args) {
  auto scene = load(args.scene);
  if (!scene) return fail(scene.status());
  const graph::Graph& g = (*scene)->graph();
  Json out = Json::array();
  for (const std::string& a : args.addresses) {
    Result<NodeId> id = rig::resolve_address(g, a);
    if (!id) return fail(id.status().with_context(args.scene));
    const graph::Node& n = *g.node(*id);
    if (args.json) {
      out.push_back(Json{{"address", a}, {"node", n.name()}, {"type", n.type().name()}, {"uuid", n.uuid().str()}});
    } else {
      std::cout << n.name() << "\n";
    }
  }
  if (args.json) print_json(Json{{"addresses", out}});
  return 0;
}

}  // namespace

struct RigCommands::State {
  CLI::App* build_cmd = nullptr;
  CLI::App* update_cmd = nullptr;
  CLI::App* rigs_cmd = nullptr;
  CLI::App* remove_cmd = nullptr;
  CLI::App* address_cmd = nullptr;
  BuildArgs build;
  UpdateArgs update;
  RigsArgs rigs;
  RemoveArgs remove;
  AddressArgs address;
  CLI::App* edit_cmd = nullptr;
  EditArgs edit;
  CLI::App* meta_cmd = nullptr;
  MetaArgs meta;
};

RigCommands::RigCommands() : state_(std::make_unique<State>()) {}
RigCommands::~RigCommands() = default;

void add_rig_commands(CLI::App& app, RigCommands& commands) {
  RigCommands::State& s = commands.state();
  s.build_cmd = app.add_subcommand("build", "Build a rig definition onto a character");
  s.build_cmd->footer(
      "Example:\n  rigel build examples/biped.rig.xml -o hero.rigel\n"
      "  rigel build arm.rig.json --character tests/data/gltf/rigify_human_metarig.glb --steps 5 -o partial.rigel");
  s.build_cmd->add_option("DEFINITION", s.build.definition, "Rig definition (.rig.xml, .rig.json) or build graph (.build.json)")->required();
  s.build_cmd->add_option("--character", s.build.character,
                          "Character to build on (.glb, .gltf, .bvh, .rigel); default: the definition's geometry");
  s.build_cmd->add_option("-o,--output", s.build.output, "Scene file to write (.rigel)")->required();
  s.build_cmd->add_option("--steps", s.build.steps, "Stop after this many steps (seed 003's VCR)")->check(CLI::NonNegativeNumber);
  s.build_cmd->add_flag("--edit-mode", s.build.edit_mode,
                        "Build in rig edit mode (seed 002): moving controls edits the definition (rigel edit)");
  s.build_cmd->add_flag("--json", s.build.json, "Print a JSON summary on stdout");

  s.update_cmd = app.add_subcommand("update", "Rebuild the components of rigs whose definition changed, keeping animation");
  s.update_cmd->footer(
      "Example:\n  rigel update shot.rigel -o shot_v2.rigel\n"
      "  rigel update shot.rigel --rig hero --definition hero_v2.rig.xml --force -o shot_v2.rigel");
  s.update_cmd->add_option("SCENE", s.update.scene, "Scene file (.rigel)")->required();
  s.update_cmd->add_option("--rig", s.update.rig, "Only this rig (default: every rig)");
  s.update_cmd->add_option("--definition", s.update.definition, "Use this definition instead of the rig's definition path");
  s.update_cmd->add_flag("--force", s.update.force, "Rebuild every component, whatever its version");
  s.update_cmd->add_option("--keep-keys", s.update.keep_keys,
                           "local: keys keep their values on the rebuilt controls (by rigId and control role); "
                           "world: keys are converted so keyed controls keep their world positions")
      ->check(CLI::IsMember({"local", "world"}));
  s.update_cmd->add_option("-o,--output", s.update.output, "Scene file to write (.rigel)")->required();
  s.update_cmd->add_flag("--json", s.update.json, "Print a JSON report on stdout");

  s.rigs_cmd = app.add_subcommand("rigs", "List the rigs in a scene: definition, version, components (the Rig Manager)");
  s.rigs_cmd->footer("Example:\n  rigel rigs shot.rigel --json");
  s.rigs_cmd->add_option("SCENE", s.rigs.scenes, "Scene files (.rigel): each one's rigs, published ones checked against their asset's newest version")->required();
  s.rigs_cmd->add_flag("--json", s.rigs.json, "Print JSON on stdout");
  s.rigs_cmd->add_flag("--check", s.rigs.check, "Exit 1 when a rig is out of date (its definition, or a newer published version)");

  s.remove_cmd = app.add_subcommand("remove", "Remove a rig: exactly what its metadata network links to");
  s.remove_cmd->footer("Example:\n  rigel remove shot.rigel --rig hero -o clean.rigel");
  s.remove_cmd->add_option("SCENE", s.remove.scene, "Scene file (.rigel)")->required();
  s.remove_cmd->add_option("--rig", s.remove.rig, "The rig to remove")->required();
  s.remove_cmd->add_option("-o,--output", s.remove.output, "Scene file to write (.rigel)")->required();
  s.remove_cmd->add_flag("--json", s.remove.json, "Print a JSON summary on stdout");

  s.address_cmd = app.add_subcommand("address", "Resolve nameless addresses (RIG:COMPONENT[/joint[J]]/NAME[I]) to nodes");
  s.address_cmd->footer("Example:\n  rigel address hero.rigel 'hero:arm_L/fk[END]' 'hero:arm_L/joint[1]/fk'");
  s.address_cmd->add_option("SCENE", s.address.scene, "Scene file (.rigel)")->required();
  s.address_cmd->add_option("ADDRESS", s.address.addresses, "Addresses")->required();
  s.address_cmd->add_flag("--json", s.address.json, "Print JSON on stdout");

  s.edit_cmd = app.add_subcommand(
      "edit", "Rig edit mode: move controls of a rig built with --edit-mode; their guides are written back into the "
              "definition (versions bumped) and the moved components are rebuilt there");
  s.edit_cmd->footer(
      "Example:\n  rigel build hero.rig.xml --edit-mode -o edit.rigel\n"
      "  rigel edit edit.rigel --move 'hero:arm_L/fk[0]=0,0.02,0' --turn 'hero:arm_L/fk[1]=0,0,15' -o edit.rigel");
  s.edit_cmd->add_option("SCENE", s.edit.scene, "Scene file (.rigel) with a rig in edit mode")->required();
  s.edit_cmd->add_option("--rig", s.edit.rig, "The rig (default: the scene's only rig)");
  s.edit_cmd->add_option("--move", s.edit.moves, "ADDRESS=X,Y,Z: set a control's translate (metres) before writing back");
  s.edit_cmd->add_option("--turn", s.edit.turns, "ADDRESS=X,Y,Z: set a control's rotate (degrees) before writing back");
  s.edit_cmd->add_option("--definition-out", s.edit.definition_out,
                         "Where to save the edited definition (default: the rig's definition path)");
  s.edit_cmd->add_option("-o,--output", s.edit.output, "Scene file to write (.rigel)")->required();
  s.edit_cmd->add_flag("--keep-editing", s.edit.keep_editing,
                       "Stay in rig edit mode after writing back (default: the rig is rebuilt for animation)");
  s.edit_cmd->add_flag("--json", s.edit.json, "Print a JSON report on stdout");

  s.meta_cmd = app.add_subcommand(
      "meta", "Query the metadata network: the component that built a node, a child by rigId, a member by role");
  s.meta_cmd->footer(
      "Example:\n  rigel meta hero.rigel --of hero_arm_L_fk1 --json\n"
      "  rigel meta hero.rigel --rig hero --component arm_L --connection fk --index 2\n"
      "  rigel meta hero.rigel --rig hero --component torso --child 92020764-9e98-4b38-bd6c-0e26a5ed53f5");
  s.meta_cmd->add_option("SCENE", s.meta.scene, "Scene file (.rigel)")->required();
  s.meta_cmd->add_option("--of", s.meta.nodes, "The component (meta node) that built this node (findComponent)");
  s.meta_cmd->add_option("--rig", s.meta.rig, "The rig for --child and --connection");
  s.meta_cmd->add_option("--component", s.meta.component, "A component (rigId or name) of --rig; default: the rig itself");
  s.meta_cmd->add_option("--child", s.meta.child, "A direct child component by rigId (getMetaChildById)");
  s.meta_cmd->add_option("--connection", s.meta.connection, "A member by role or step (getMetaNodeConnection)");
  s.meta_cmd->add_option("--index", s.meta.index, "The member's index for --connection")->check(CLI::NonNegativeNumber);
  s.meta_cmd->add_flag("--json", s.meta.json, "Print JSON on stdout");
}

std::optional<int> run_rig_commands(const RigCommands& commands) {
  const RigCommands::State& s = commands.state();
  if (*s.build_cmd) return run_build(s.build);
  if (*s.update_cmd) return run_update(s.update);
  if (*s.rigs_cmd) return run_rigs(s.rigs);
  if (*s.remove_cmd) return run_remove(s.remove);
  if (*s.address_cmd) return run_address(s.address);
  if (*s.edit_cmd) return run_edit(s.edit);
  if (*s.meta_cmd) return run_meta(s.meta);
  return std::nullopt;
}

}  // namespace rigel::cli
