// `rigel shape`, `rigel align`, `rigel locator`, `rigel mirror-joints`,
// `rigel driven-key` (see rigging_commands.h).

#include "rigging_commands.h"

#include <cstdlib>
#include <fstream>
#include <optional>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_util.h"
#include "rigel/app/workspace.h"
#include "rigel/ephemeral/component.h"
#include "rigel/ops/anim/channel_keys.h"
#include "rigel/tools/data_files.h"

namespace rigel::cli {
namespace {

using Json = nlohmann::ordered_json;

struct ShapeArgs {
  std::string scene, like, from, output;
  std::vector<std::string> controls;
  bool mirror = false, flip = false, opposite = false, shape_only = false, color_only = false, json = false;
};

struct AlignArgs {
  std::string scene, target, output;
  std::vector<std::string> nodes;
  bool position = false, rotation = false, json = false;
};

struct LocatorArgs {
  std::string scene, output;
  std::vector<std::string> at;
  double size = 0.1;
  bool json = false;
};

struct MirrorJointsArgs {
  std::string scene, output;
  std::vector<std::string> joints;
  bool update = false, json = false;
};

struct DrivenKeyArgs {
  std::string scene, driver, output, tangent, pose_reader;
  std::vector<double> axis;
  std::vector<std::string> set, remove;
  std::optional<double> at;
  bool list = false, json = false;
};

Json vec(const math::Vec3& v) { return Json::array({v.x(), v.y(), v.z()}); }

Json look_json(const tools::ControlLook& look) {
  Json points = Json::array();
  for (const math::Vec3& p : look.points) points.push_back(vec(p));
  return Json{{"points", points}, {"closed", look.closed}, {"color", vec(look.color)}};
}

// A look from a file: what `rigel shape --json` prints (the first
// control's shape), or a bare {"points", "closed", "color"}.
Result<tools::ControlLook> read_look(const std::string& path) {
  std::ifstream in(path);
  if (!in) return Status(ErrorCode::kNotFound, path + ": cannot read the file");
  std::stringstream text;
  text << in.rdbuf();
  const Json j = Json::parse(text.str(), nullptr, false);
  if (j.is_discarded()) return Status(ErrorCode::kInvalidArgument, path + ": not JSON");
  // `rigel shape --json`'s report (its first control's shape), one control's entry, or a bare shape.
  const Json& entry = j.is_object() && j.contains("controls") && j["controls"].is_array() && !j["controls"].empty()
                          ? j["controls"][0]
                          : j;
  const Json& s = entry.is_object() && entry.contains("shape") ? entry["shape"] : entry;
  auto bad = [&](const std::string& what) { return Status(ErrorCode::kInvalidArgument, path + ": " + what); };
  auto point = [&](const Json& p, math::Vec3& out) {
    if (!p.is_array() || p.size() != 3) return false;
    for (int i = 0; i < 3; ++i) {
      if (!p[static_cast<std::size_t>(i)].is_number()) return false;
      out[i] = p[static_cast<std::size_t>(i)].get<double>();
    }
    return true;
  };
  if (!s.is_object() || !s.contains("points") || !s["points"].is_array()) return bad("expected {\"points\": [[x, y, z], ...], \"closed\", \"color\"}");
  tools::ControlLook look;
  for (std::size_t i = 0; i < s["points"].size(); ++i) {
    math::Vec3 p;
    if (!point(s["points"][i], p)) return bad("points[" + std::to_string(i) + "]: expected [x, y, z]");
    look.points.push_back(p);
  }
  if (s.contains("closed")) {
    if (!s["closed"].is_boolean()) return bad("closed: expected true or false");
    look.closed = s["closed"].get<bool>();
  }
  if (s.contains("color") && !point(s["color"], look.color)) return bad("color: expected [r, g, b]");
  return look;
}

Result<std::vector<graph::NodeId>> resolve(const app::Workspace& ws, const std::vector<std::string>& refs,
                                           const std::string& scene, const std::string& option) {
  std::vector<graph::NodeId> out;
  for (const std::string& ref : refs) {
    auto id = ws.node(ref, option);
    if (!id) return Status(id.status().code(), scene + ": --" + option + ": " + id.status().message());
    out.push_back(*id);
  }
  return out;
}

Json names(const app::Workspace& ws, const std::vector<graph::NodeId>& ids) {
  Json out = Json::array();
  for (graph::NodeId id : ids) out.push_back(ws.graph().node(id)->name());
  return out;
}

int write(app::Workspace& ws, const std::string& output, const std::string& what) {
  if (auto saved = ws.save(output); !saved) return fail(saved.status());
  std::cerr << "rigel: " << what << "; wrote " << output << "\n";
  return 0;
}

int run_shape(const ShapeArgs& a) {
  const int edits = (!a.like.empty()) + (!a.from.empty()) + a.mirror + a.flip + a.opposite;
  if (edits > 1) return usage_error("give one of --like, --from, --mirror, --flip and --to-opposite");
  if ((edits == 1) != !a.output.empty()) return usage_error(edits ? "an edit writes a scene: give -o OUT" : "-o goes with an edit");
  if ((a.shape_only || a.color_only) && a.like.empty() && a.from.empty())
    return usage_error("--shape-only and --color-only go with --like or --from");
  if (a.shape_only && a.color_only) return usage_error("give --shape-only or --color-only, not both");
  auto scene = load(a.scene);
  if (!scene) return fail(scene.status());
  app::Workspace ws(std::move(*scene), a.scene, {}, tools::components());
  auto controls = resolve(ws, a.controls, a.scene, "control");
  if (!controls) return fail(controls.status());
  const std::string where = a.scene + ": ";
  Json report = Json::object();
  if (!a.like.empty() || !a.from.empty()) {
    if (!a.like.empty()) {
      if (auto from = ws.node(a.like, "like"); !from)
        return fail(Status(from.status().code(), where + "--like: " + from.status().message()));
    }
    Result<tools::ControlLook> look = !a.like.empty() ? ws.control_look(*ws.node(a.like, "like")) : read_look(a.from);
    if (!look) return fail(look.status().with_context(!a.like.empty() ? where + "--like" : "--from"));
    if (Status s = ws.paste_control_look(*controls, *look, {!a.color_only, !a.shape_only}); !s) return fail(s.with_context(where));
  } else if (a.mirror || a.flip) {
    if (Status s = ws.edit_control_shape(*controls, a.mirror ? tools::ShapeEdit::kMirror : tools::ShapeEdit::kFlip); !s)
      return fail(s.with_context(where + "--control"));
  } else if (a.opposite) {
    auto pairs = ws.mirror_shape_to_opposite(*controls);
    if (!pairs) return fail(pairs.status().with_context(where + "--control"));
    Json list = Json::array();
    for (const tools::MirroredShape& p : *pairs)
      list.push_back(Json{{"from", ws.graph().node(p.from)->name()}, {"to", ws.graph().node(p.to)->name()}});
    report["pairs"] = list;
  }
  Json shapes = Json::array();
  for (graph::NodeId id : *controls) {
    auto look = ws.control_look(id);
    if (!look) return fail(look.status().with_context(where + "--control"));
    shapes.push_back(Json{{"control", ws.graph().node(id)->name()}, {"shape", look_json(*look)}});
    if (!a.json)
      std::cout << ws.graph().node(id)->name() << ": " << look->points.size() << " points, "
                << (look->closed ? "closed" : "open") << ", colour " << number_text(look->color.x()) << " "
                << number_text(look->color.y()) << " " << number_text(look->color.z()) << "\n";
  }
  report["controls"] = shapes;
  if (a.json) std::cout << report.dump() << "\n";
  return edits ? write(ws, a.output, "control shapes edited") : 0;
}

int run_align(const AlignArgs& a) {
  auto scene = load(a.scene);
  if (!scene) return fail(scene.status());
  app::Workspace ws(std::move(*scene), a.scene, {}, tools::components());
  auto nodes = resolve(ws, a.nodes, a.scene, "node");
  if (!nodes) return fail(nodes.status());
  auto target = ws.node(a.target, "to");
  if (!target) return fail(Status(target.status().code(), a.scene + ": --to: " + target.status().message()));
  const bool both = !a.position && !a.rotation;
  auto moved = ws.align(*nodes, *target, a.position || both, a.rotation || both);
  if (!moved) return fail(moved.status().with_context(a.scene));
  if (a.json) std::cout << Json{{"moved", names(ws, *moved)}, {"target", a.target}}.dump() << "\n";
  else for (graph::NodeId id : *moved) std::cout << ws.graph().node(id)->name() << " -> " << a.target << "\n";
  return write(ws, a.output, "matched to " + a.target);
}

int run_locator(const LocatorArgs& a) {
  auto scene = load(a.scene);
  if (!scene) return fail(scene.status());
  app::Workspace ws(std::move(*scene), a.scene, {}, tools::components());
  auto at = resolve(ws, a.at, a.scene, "at");
  if (!at) return fail(at.status());
  auto made = ws.create_locators(*at, a.size);
  if (!made) return fail(made.status().with_context(a.scene + ": --" + (made.status().field() == "size" ? "size" : "at")));
  if (a.json) std::cout << Json{{"locators", names(ws, *made)}}.dump() << "\n";
  else for (graph::NodeId id : *made) std::cout << ws.graph().node(id)->name() << "\n";
  return write(ws, a.output, std::to_string(made->size()) + (made->size() == 1 ? " locator" : " locators"));
}

int run_mirror_joints(const MirrorJointsArgs& a) {
  auto scene = load(a.scene);
  if (!scene) return fail(scene.status());
  app::Workspace ws(std::move(*scene), a.scene, {}, tools::components());
  auto joints = resolve(ws, a.joints, a.scene, "joint");
  if (!joints) return fail(joints.status());
  tools::MirrorJointsOptions options;
  options.update_existing = a.update;
  auto report = ws.mirror_joints(*joints, options);
  if (!report) return fail(report.status().with_context(a.scene + ": --joint"));
  if (a.json) {
    std::cout << Json{{"created", names(ws, report->created)}, {"updated", names(ws, report->updated)}}.dump() << "\n";
  } else {
    for (graph::NodeId id : report->created) std::cout << "created " << ws.graph().node(id)->name() << "\n";
    for (graph::NodeId id : report->updated) std::cout << "updated " << ws.graph().node(id)->name() << "\n";
  }
  return write(ws, a.output, std::to_string(report->created.size()) + " joints created, " +
                                 std::to_string(report->updated.size()) + " updated");
}

// "CHANNEL=VALUE" or "CHANNEL" (its value now).
Result<std::pair<std::string, std::optional<double>>> driven_entry(const std::string& text) {
  const std::size_t eq = text.rfind('=');
  if (eq == std::string::npos) return std::pair<std::string, std::optional<double>>{text, std::nullopt};
  const std::string value = text.substr(eq + 1);
  char* end = nullptr;
  const double v = std::strtod(value.c_str(), &end);
  if (value.empty() || end != value.c_str() + value.size())
    return Status(ErrorCode::kInvalidArgument, "--set " + text + ": expected CHANNEL=NUMBER or CHANNEL");
  return std::pair<std::string, std::optional<double>>{text.substr(0, eq), v};
}

Json driven_json(const tools::DrivenPoseSet& set) {
  Json drivers = Json::array();
  for (const tools::DrivenDriver& d : set.drivers) {
    Json curves = Json::array();
    for (const tools::DrivenCurve& c : d.curves) curves.push_back(Json{{"node", c.node}, {"driven", c.driven}, {"at", c.times}, {"values", c.values}});
    drivers.push_back(Json{{"driver", d.driver}, {"curves", curves}});
  }
  return Json{{"kind", std::string(tools::driven_data_name(set.kind))}, {"drivers", drivers}};
}

int run_driven_key(const DrivenKeyArgs& a) {
  const int modes = (a.list ? 1 : 0) + (a.remove.empty() ? 0 : 1) + (a.set.empty() ? 0 : 1) + (a.pose_reader.empty() ? 0 : 1);
  if (modes != 1)
    return usage_error("driven-key: give --set CHANNEL[=VALUE]... with --driver, --remove CHANNEL..., --pose-reader JOINT, or --list");
  if (!a.axis.empty() && (a.pose_reader.empty() || a.axis.size() != 3)) return usage_error("--axis X,Y,Z goes with --pose-reader");
  if (!a.set.empty() && a.driver.empty()) return usage_error("driven-key --set: give --driver NODE.ATTR");
  if (!a.list && a.output.empty()) return usage_error("driven-key: give -o SCENE to write");
  auto scene = load(a.scene);
  if (!scene) return fail(scene.status());
  app::Workspace ws(std::move(*scene), a.scene, {}, ephemeral::components());
  if (a.list) {
    Json all = Json::array();
    for (tools::DrivenData kind : {tools::DrivenData::kPoses, tools::DrivenData::kCorrectives}) {
      auto set = ws.driven_poses(kind);
      if (!set) return fail(set.status().with_context(a.scene));
      all.push_back(driven_json(*set));
      if (a.json) continue;
      for (const tools::DrivenDriver& d : set->drivers)
        for (const tools::DrivenCurve& c : d.curves)
          std::cout << d.driver << " -> " << c.driven << "  (" << c.times.size() << " keys, " << tools::driven_data_name(kind) << ")\n";
    }
    if (a.json) std::cout << Json{{"drivenPoses", all[0]}, {"correctives", all[1]}}.dump() << "\n";
    return 0;
  }
  if (!a.pose_reader.empty()) {
    auto joint = ws.node(a.pose_reader, "pose-reader");
    if (!joint) return fail(joint.status().with_context(a.scene));
    const math::Vec3 axis = a.axis.empty() ? math::Vec3(1, 0, 0) : math::Vec3(a.axis[0], a.axis[1], a.axis[2]);
    auto reader = ws.create_pose_reader(*joint, axis);
    if (!reader) return fail(reader.status().with_context(a.scene + ": --pose-reader"));
    const std::string name = ws.graph().node(*reader)->name();
    if (a.json) std::cout << Json{{"reader", name}, {"angle", name + ".angle"}, {"rotate", name + ".rotate"}}.dump() << "\n";
    else std::cout << name << "\n";
    return write(ws, a.output, "a pose reader on " + a.pose_reader + " (drive with " + name + ".angle or .rotateX/Y/Z)");
  }
  if (!a.remove.empty()) {
    if (Status s = ws.remove_driven_keys(a.remove); !s) return fail(s.with_context(a.scene));
    if (a.json) std::cout << Json{{"removed", a.remove}}.dump() << "\n";
    return write(ws, a.output, std::to_string(a.remove.size()) + " driven keys removed");
  }
  tools::DrivenKeyRequest request;
  request.driver = a.driver;
  request.at = a.at;
  if (!a.tangent.empty()) {
    auto t = ops::anim::tangent_type_from_name(a.tangent);
    if (!t) return usage_error("--tangent '" + a.tangent + "': expected auto, linear, flat, spline, clamped, plateau, step or stepNext");
    request.tangent = *t;
  }
  for (const std::string& e : a.set) {
    auto entry = driven_entry(e);
    if (!entry) return usage_error(entry.status().message());
    request.driven.push_back(*entry);
  }
  auto report = ws.set_driven_key(request);
  if (!report) return fail(report.status().with_context(a.scene));
  if (a.json) std::cout << Json{{"at", report->at}, {"curves", report->curves}, {"created", report->created}}.dump() << "\n";
  return write(ws, a.output, "keyed " + std::to_string(report->curves.size()) + " driven channels at " + a.driver + " = " +
                                 Json(report->at).dump());
}

}  // namespace

struct RiggingCommands::State {
  CLI::App* shape = nullptr;
  CLI::App* align = nullptr;
  CLI::App* locator = nullptr;
  CLI::App* mirror_joints = nullptr;
  CLI::App* driven_key = nullptr;
  ShapeArgs shape_args;
  AlignArgs align_args;
  LocatorArgs locator_args;
  MirrorJointsArgs mirror_joints_args;
  DrivenKeyArgs driven_key_args;
};

RiggingCommands::RiggingCommands() : state_(std::make_unique<State>()) {}
RiggingCommands::~RiggingCommands() = default;

void add_rigging_commands(CLI::App& app, RiggingCommands& commands) {
  RiggingCommands::State& s = commands.state();
  ShapeArgs& sh = s.shape_args;
  s.shape = app.add_subcommand("shape", "Control shapes and colours: show, copy from a control or a file, mirror, flip, mirror to the other side");
  s.shape->footer(
      "Examples:\n  rigel shape shot.rigel --control hero_arm_L_ik --json > arm.json\n"
      "  rigel shape shot.rigel --control hero_leg_L_ik --like hero_arm_L_ik --shape-only -o shot.rigel\n"
      "  rigel shape shot.rigel --control hero_leg_R_ik --from arm.json -o shot.rigel\n"
      "  rigel shape shot.rigel --control hero_arm_L_pole --to-opposite -o shot.rigel");
  s.shape->add_option("SCENE", sh.scene, "Scene file (.rigel)")->required();
  s.shape->add_option("--control", sh.controls, "Controls (names, uuids or rig addresses)")->delimiter(',')->required();
  s.shape->add_option("--like", sh.like, "Paste this control's shape and colour onto them");
  s.shape->add_option("--from", sh.from, "Paste the shape in this JSON file (what --json prints)");
  s.shape->add_flag("--shape-only", sh.shape_only, "With --like/--from: the shape, not the colour");
  s.shape->add_flag("--color-only", sh.color_only, "With --like/--from: the colour, not the shape");
  s.shape->add_flag("--mirror", sh.mirror, "Mirror each shape over its local YZ plane (x -> -x)");
  s.shape->add_flag("--flip", sh.flip, "Flip each shape over: a half turn about its local Y");
  s.shape->add_flag("--to-opposite", sh.opposite, "Copy each shape onto the control on the other side, mirrored in the world");
  s.shape->add_option("-o,--output", sh.output, "Scene file to write (.rigel), with an edit");
  s.shape->add_flag("--json", sh.json, "Print the controls' shapes as JSON on stdout");

  AlignArgs& al = s.align_args;
  s.align = app.add_subcommand("align", "Match nodes' world position and/or rotation to another node's (match position / rotation)");
  s.align->footer("Examples:\n  rigel align shot.rigel --node hero_arm_L_ik --to prop_loc -o shot.rigel\n"
                  "  rigel align shot.rigel --node hand.L_ctrl --to cup_loc --position -o shot.rigel --json");
  s.align->add_option("SCENE", al.scene, "Scene file (.rigel)")->required();
  s.align->add_option("--node", al.nodes, "Nodes to move (names, uuids or rig addresses)")->delimiter(',')->required();
  s.align->add_option("--to", al.target, "The node to match")->required();
  s.align->add_flag("--position", al.position, "Match the position (with neither flag: both)");
  s.align->add_flag("--rotation", al.rotation, "Match the rotation (with neither flag: both)");
  s.align->add_option("-o,--output", al.output, "Scene file to write (.rigel)")->required();
  s.align->add_flag("--json", al.json, "Print a JSON report on stdout");

  LocatorArgs& lo = s.locator_args;
  s.locator = app.add_subcommand("locator", "Create a locator (a control drawn as a cross) at each node's position and rotation");
  s.locator->footer("Examples:\n  rigel locator shot.rigel --at hand.L -o shot.rigel\n"
                    "  rigel locator shot.rigel --at hero:arm_L/ik,spine --size 0.05 -o shot.rigel --json");
  s.locator->add_option("SCENE", lo.scene, "Scene file (.rigel)")->required();
  s.locator->add_option("--at", lo.at, "Nodes (names, uuids or rig addresses)")->delimiter(',')->required();
  s.locator->add_option("--size", lo.size, "Half-extent of the cross (default 0.1)");
  s.locator->add_option("-o,--output", lo.output, "Scene file to write (.rigel)")->required();
  s.locator->add_flag("--json", lo.json, "Print a JSON report on stdout");

  MirrorJointsArgs& mj = s.mirror_joints_args;
  s.mirror_joints = app.add_subcommand("mirror-joints", "Mirror joint chains to the other side, renaming .L/_L/Left to .R/_R/Right and back");
  s.mirror_joints->footer("Examples:\n  rigel mirror-joints char.rigel --joint wing.L -o char.rigel\n"
                          "  rigel mirror-joints char.rigel --joint upper_arm.L --update -o char.rigel --json");
  s.mirror_joints->add_option("SCENE", mj.scene, "Scene file (.rigel)")->required();
  s.mirror_joints->add_option("--joint", mj.joints, "Root joints of the chains (or their ephemeral controls)")->delimiter(',')->required();
  s.mirror_joints->add_flag("--update", mj.update, "Move joints that exist on the other side onto the mirror");
  s.mirror_joints->add_option("-o,--output", mj.output, "Scene file to write (.rigel)")->required();
  s.mirror_joints->add_flag("--json", mj.json, "Print a JSON report on stdout");

  DrivenKeyArgs& dk = s.driven_key_args;
  s.driven_key = app.add_subcommand("driven-key", "Set-driven keys: key a pose of driven channels at a driver's value, remove them, list them");
  s.driven_key->footer(
      "Examples:\n  rigel driven-key hero.rigel --driver hero_hand_L_ctrl.curl --at 10 --set hero_index_L_fk0.rotateZ=-60 "
      "--set hero_index_L_fk1.rotateZ=-70 -o hero.rigel\n"
      "  rigel driven-key hero.rigel --driver upper_arm.L.rotateX --at 90 --set body_blendShape.weights[0]=1 -o hero.rigel\n"
      "  rigel driven-key hero.rigel --pose-reader forearm.L --axis 0,1,0 -o hero.rigel\n"
      "  rigel driven-key hero.rigel --driver forearm.L_poseReader.angle --at 90 --set body_blendShape.weights[1]=1 -o hero.rigel\n"
      "  rigel driven-key hero.rigel --remove hero_index_L_fk0.rotateZ -o hero.rigel\n"
      "  rigel driven-key hero.rigel --list --json");
  s.driven_key->add_option("SCENE", dk.scene, "Scene file (.rigel)")->required();
  s.driven_key->add_option("--driver", dk.driver, "The driving channel (NODE.ATTR: a number, or one component as rotateX)");
  s.driven_key->add_option("--at", dk.at, "The driver's value of the pose (default: its value now)");
  s.driven_key->add_option("--set", dk.set, "A driven channel and its value at the pose (CHANNEL=VALUE; CHANNEL alone: its value now)");
  s.driven_key->add_option("--tangent", dk.tangent, "Tangent type of new keys (default auto)");
  s.driven_key->add_option("--remove", dk.remove, "Remove the driven keys of these channels (each keeps its value now)");
  s.driven_key->add_flag("--list", dk.list, "List the driven keys (driven poses and correctives)");
  s.driven_key->add_option("--pose-reader", dk.pose_reader, "Make a pose reader on this joint (a corrective's driver: READER.angle, READER.rotateX)");
  s.driven_key->add_option("--axis", dk.axis, "With --pose-reader: the axis whose swing .angle measures (default 1,0,0)")->delimiter(',');
  s.driven_key->add_option("-o,--output", dk.output, "Scene file to write (.rigel)");
  s.driven_key->add_flag("--json", dk.json, "Print a JSON report on stdout");
}

std::optional<int> run_rigging_commands(const RiggingCommands& commands) {
  const RiggingCommands::State& s = commands.state();
  if (*s.shape) return run_shape(s.shape_args);
  if (*s.align) return run_align(s.align_args);
  if (*s.locator) return run_locator(s.locator_args);
  if (*s.mirror_joints) return run_mirror_joints(s.mirror_joints_args);
  if (*s.driven_key) return run_driven_key(s.driven_key_args);
  return std::nullopt;
}

}  // namespace rigel::cli
