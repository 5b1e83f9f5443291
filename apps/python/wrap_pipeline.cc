// rigel's pipeline in Python (tools/project.h, tools/config.h, base/log.h):
// module functions for projects, assets and settings, and the log level;
// Workspace's data managers (export and import of skin weights, control
// shapes, driven poses and correctives) and set-driven keys; import_data
// and asset_data_files (tools/data_files.h), what PyBuild.post() imports by
// default; batch runs over shots (tools/batch_run.h). Python values in,
// library calls, records out.

#include <cstdlib>
#include <map>
#include <optional>
#include <string>

#include "rigel/base/log.h"
#include "rigel/ops/anim/channel_keys.h"
#include "rigel/rig/meta.h"
#include "rigel/tools/batch_run.h"
#include "rigel/tools/config.h"
#include "rigel/tools/data_files.h"
#include "rigel/tools/project.h"
#include "rigel/tools/publish.h"
#include "rigel/ephemeral/component.h"
#include "wrap_workspace.h"

namespace rigel::python {

namespace {

tools::DrivenData driven_kind(bool correctives) {
  return correctives ? tools::DrivenData::kCorrectives : tools::DrivenData::kPoses;
}

// The settings of the project the current folder is in over the user's.
tools::Config current_settings() {
  std::filesystem::path file;
  if (auto p = tools::find_project(std::filesystem::current_path())) file = p->dir / tools::kProjectConfigFile;
  auto config = tools::Config::load(tools::user_config_path(), file);
  return config ? std::move(*config) : tools::Config();
}

// The `rigel` command line a batch job runs: `program`, else $RIGEL_CLI,
// else `rigel` on the PATH.
std::string rigel_program(const std::string& program) {
  if (!program.empty()) return program;
  if (const char* env = std::getenv("RIGEL_CLI"); env && *env) return env;
  if (const char* path = std::getenv("PATH")) {
    std::string dirs = path;
    for (std::size_t at = 0; at <= dirs.size();) {
      const std::size_t end = std::min(dirs.find(':', at), dirs.size());
      const std::filesystem::path candidate = std::filesystem::path(dirs.substr(at, end - at)) / "rigel";
      std::error_code ec;
      if (end > at && std::filesystem::is_regular_file(candidate, ec)) return candidate.string();
      at = end + 1;
    }
  }
  raise(Status(ErrorCode::kFailedPrecondition,
               "batch jobs run the rigel command line: put it on the PATH, set RIGEL_CLI, or pass program=")
            .with_field("program"));
  return {};
}

py::object batch_record(const tools::BatchOutcome& o) {
  py::list shots;
  for (const tools::BatchResult& r : o.report.shots) {
    py::dict d;
    d["shot"] = r.shot;
    d["status"] = r.status;
    d["exit"] = r.exit;
    d["seconds"] = r.seconds;
    d["log"] = r.log.string();
    d["output"] = r.output.string();
    shots.append(record(d));
  }
  py::dict d;
  d["operation"] = o.report.operation;
  d["jobs"] = o.report.jobs;
  d["seconds"] = o.report.seconds;
  d["failed"] = o.report.failed();
  d["ran"] = o.run.shots.size();
  d["report"] = o.report_path.string();
  d["shots"] = shots;
  return record(d);
}

py::object project_record(const tools::Project& p) {
  py::dict d;
  d["dir"] = p.dir.string();
  d["name"] = p.name;
  d["format"] = p.format;
  d["created"] = p.created;
  return record(d);
}

py::object asset_record(const tools::Asset& a) {
  py::dict d;
  d["dir"] = a.dir.string();
  d["name"] = a.name;
  d["type"] = a.type;
  d["skeleton"] = a.skeleton;
  d["published"] = tools::published_versions(a);
  d["created"] = a.created;
  d["modified"] = a.modified;
  return record(d);
}

py::object setting_value(const tools::SettingValue& v) {
  return std::visit([](const auto& x) { return py::cast(x); }, v);
}

tools::Project project_at(const std::string& dir) {
  return unwrap(dir.empty() ? tools::find_project(std::filesystem::current_path()) : tools::open_project(dir));
}

}  // namespace

// rigel.batch (tools/batch_run.h): `rigel batch` from a script.
static void def_batch(py::module_& m) {
  m.def(
      "batch",
          [](const std::string& operation, const std::vector<std::string>& shots, const std::string& output,
             const std::string& frames, std::optional<std::size_t> jobs, bool slurm, std::optional<std::string> partition,
             const std::string& report, const std::string& retry_failed, const std::string& program, py::object progress) {
            const tools::Config settings = current_settings();
            tools::BatchRequest r;
            r.operation = operation;
            r.shots = shots;
            r.output = output;
            r.frames = frames;
            r.report = report;
            r.retry_failed = retry_failed;
            r.parallel = jobs ? *jobs : static_cast<std::size_t>(settings.integer("batch.jobs"));
            r.slurm = slurm;
            r.partition = partition ? *partition : slurm ? settings.string("batch.partition") : std::string();
            r.program = rigel_program(program);
            std::function<void(const tools::BatchProgress&)> tell;
            std::optional<py::error_already_set> raised;  // the callback's first exception, raised once the jobs are done
            if (!progress.is_none())
              tell = [&progress, &raised](const tools::BatchProgress& p) {
                py::gil_scoped_acquire gil;
                if (raised) return;
                py::dict d;
                d["done"] = p.done;
                d["failed"] = p.failed;
                d["running"] = p.running;
                d["total"] = p.total;
                d["elapsed"] = p.elapsed;
                d["left"] = p.left;
                d["line"] = tools::progress_line(p);
                try {
                  progress(record(d));
                } catch (py::error_already_set& e) {
                  raised = std::move(e);
                }
              };
            Result<tools::BatchOutcome> outcome = [&] {
              py::gil_scoped_release released;  // the jobs run while Python goes on (progress takes it back)
              return tools::run_batch(r, tell);
            }();
            if (raised) throw std::move(*raised);
            return batch_record(unwrap(std::move(outcome)));
          },
          py::arg("operation"), py::arg("shots") = std::vector<std::string>{}, py::arg("output") = "", py::arg("frames") = "",
          py::arg("jobs") = py::none(), py::arg("slurm") = false, py::arg("partition") = py::none(), py::arg("report") = "",
          py::arg("retry_failed") = "", py::arg("program") = "", py::arg("progress") = py::none(),
          "Runs OPERATION (update, bake, export, validate) over SHOTS, one `rigel` process per shot (`rigel batch`): "
          "locally JOBS at a time (default: the setting batch.jobs), or as one Slurm job array with slurm=True; each "
          "output in OUTPUT, each log in OUTPUT/logs. retry_failed=REPORT reruns only the shots REPORT lists as failed "
          "and updates it. progress(record(done, failed, running, total, elapsed, left, line)) is called as shots start "
          "and end. Failed shots are in the report, not an exception; returns record(operation, jobs, seconds, failed, "
          "ran, report, shots: [record(shot, status, exit, seconds, log, output)]).");
}

void wrap_pipeline(py::module_& m) {
  m.def(
       "create_project", [](const std::string& dir, const std::string& name) { return project_record(unwrap(tools::create_project(dir, name))); },
       py::arg("dir"), py::arg("name") = "", "Makes DIR (empty or new) a rigging project; returns record(dir, name, format, created).")
      .def(
          "open_project", [](const std::string& dir) { return project_record(project_at(dir)); }, py::arg("dir") = "",
          "The project in DIR, or (DIR empty) the one the current folder is in.")
      .def(
          "create_asset",
          [](const std::string& name, const std::string& type, const std::string& skeleton, const std::string& project) {
            return asset_record(unwrap(tools::create_asset(project_at(project), name, type, skeleton)));
          },
          py::arg("name"), py::arg("type") = "character", py::arg("skeleton") = "", py::arg("project") = "",
          "Makes an asset (character or prop) in the project (default: the current folder's), copying a skeleton file "
          "into it; returns record(dir, name, type, skeleton, published, created, modified).")
      .def(
          "assets",
          [](const std::string& project) {
            py::list out;
            for (const tools::Asset& a : unwrap(tools::list_assets(project_at(project)))) out.append(asset_record(a));
            return out;
          },
          py::arg("project") = "", "The project's assets, by category then name.")
      .def(
          "open_asset",
          [](const std::string& name, const std::string& project) {
            if (name.empty()) return asset_record(unwrap(tools::find_asset(std::filesystem::current_path())));
            return asset_record(unwrap(tools::open_asset(project_at(project), name)));
          },
          py::arg("name") = "", py::arg("project") = "", "An asset by name, or (no name) the one the current folder is in.")
      .def(
          "settings",
          [](const std::string& project) {
            std::filesystem::path file;
            if (project.empty()) {
              if (auto p = tools::find_project(std::filesystem::current_path())) file = p->dir / tools::kProjectConfigFile;
            } else {
              file = std::filesystem::path(project) / tools::kProjectConfigFile;
            }
            py::dict out;
            for (const tools::Config::Entry& e : unwrap(tools::Config::load(tools::user_config_path(), file)).list()) {
              py::dict d;
              d["value"] = setting_value(e.value);
              d["source"] = tools::config_source_name(e.source);
              d["help"] = e.spec->help;
              out[py::str(e.spec->key)] = record(d);
            }
            return out;
          },
          py::arg("project") = "",
          "Every setting: {key: record(value, source: default|user|project, help)}, the project's (the current "
          "folder's by default) over the user's over the defaults.")
      .def(
          "set_setting",
          [](const std::string& key, const std::optional<std::string>& value, const std::string& file) {
            std::optional<std::string_view> v;
            if (value) v = *value;
            check(tools::Config::set(file.empty() ? tools::user_config_path() : std::filesystem::path(file), key, v));
          },
          py::arg("key"), py::arg("value"), py::arg("file") = "",
          "Sets (value None: removes) a setting in a settings file (default: the user's), checked against its spec.")
      .def(
          "publish",
          [](const std::string& name, const std::string& project) {
            const tools::Asset asset = name.empty() ? unwrap(tools::find_asset(std::filesystem::current_path()))
                                                    : unwrap(tools::open_asset(project_at(project), name));
            auto config = tools::Config::load(tools::user_config_path(), asset.dir.parent_path().parent_path() / tools::kProjectConfigFile);
            const tools::Config settings = config ? std::move(*config) : tools::Config();
            tools::PublishOptions o;
            o.naming_template = settings.string("naming.template");
            o.checks = settings.flag("publish.checks");
            o.rigel_version = "python";
            const tools::PublishReport r = unwrap(tools::publish_asset(asset, tools::components(), o));
            py::dict d;
            d["version"] = r.version;
            d["dir"] = r.dir.string();
            d["scene"] = r.scene.string();
            d["manifest"] = r.manifest.string();
            d["rigs"] = r.rigs;
            d["warnings"] = r.warnings;
            d["weights_vertices"] = r.weights_vertices;
            d["shapes_set"] = r.shapes_set;
            d["driven_curves"] = r.driven_curves;
            d["rest_error"] = r.rest_error;
            return record(d);
          },
          py::arg("name") = "", py::arg("project") = "",
          "Publishes an asset (NAME in the project, or the one the current folder is in): built from scratch, its "
          "data imported, checked, written as rig/vNNN; returns record(version, dir, scene, manifest, rigs, "
          "warnings, weights_vertices, shapes_set, driven_curves, rest_error).")
      .def(
          "import_data",
          [](const SceneRef& scene, const std::string& kind, const std::string& file, const std::string& rig) {
            graph::NodeId root;
            if (!rig.empty()) {
              root = rig::find_rig(scene->graph(), rig);
              if (!root.is_valid())
                raise(Status(ErrorCode::kNotFound, "rig: the scene has no rig '" + rig + "'").with_field("rig"));
            }
            const tools::DataFileReport r = unwrap(tools::import_data_file(*scene, root, kind, file));
            py::dict d;
            d["kind"] = r.kind;
            d["file"] = file;
            d["weights_vertices"] = r.weights_vertices;
            d["shapes_set"] = r.shapes_set;
            d["blend_shape_targets"] = r.blend_shape_targets;
            d["driven_curves"] = r.driven_curves;
            d["missing"] = r.missing;
            return record(d);
          },
          py::arg("scene"), py::arg("kind"), py::arg("file"), py::arg("rig") = "",
          "Imports a data file of KIND (weights, shapes, blendshapes, driven_poses, correctives) into SCENE: the same "
          "dispatcher as a definition's <data> and a publish. Shapes go onto RIG (default: the rig the file names). "
          "One undo step; returns record(kind, file, weights_vertices, shapes_set, blend_shape_targets, "
          "driven_curves, missing).")
      .def(
          "asset_data_files",
          [](const std::string& path) {
            py::list out;
            auto asset = tools::find_asset(path.empty() ? std::filesystem::current_path() : std::filesystem::path(path));
            if (!asset) return out;
            for (const tools::DataFile& f : tools::asset_data_files(*asset)) out.append(py::make_tuple(f.kind, f.file.string()));
            return out;
          },
          py::arg("path") = "",
          "The data files of the asset PATH is in (default: the current folder) that import_data reads, as (kind, "
          "file) pairs in import order (weights, then shapes; names sorted); empty when PATH is in no asset.")
      .def(
          "set_log_level",
          [](const std::string& level) {
            const auto l = log::level_from_name(level);
            if (!l) raise(Status(ErrorCode::kInvalidArgument, std::string("level: expected one of ") + log::level_names()).with_field("level"));
            log::set_level(*l);
          },
          py::arg("level"), "What rigel logs on stderr: trace, debug, info, warn, error or off.");
  def_batch(m);
}

// Workspace's set-driven keys, driven poses and correctives (tools/driven_poses.h).
static void def_driven_keys(WorkspaceClass& cls) {
  cls.def(
          "export_driven_poses",
          [](const WorkspaceRef& w, const std::string& file, bool correctives) {
            return unwrap(w.ws->export_driven_poses(driven_kind(correctives), file)).string();
          },
          py::arg("file"), py::arg("correctives") = false,
          "Writes every driven key of the kind (driven poses, or with `correctives` those driving blend shape weights "
          "and joints) to FILE (.drivenposes.json / .correctives.json); returns its path.")
      .def(
          "import_driven_poses",
          [](const WorkspaceRef& w, const std::string& file, bool correctives) {
            const tools::DrivenPosesReport r =
                edit(w, [&](app::Workspace& ws) { return unwrap(ws.import_driven_poses(driven_kind(correctives), file)); });
            py::dict d;
            d["curves"] = r.curves;
            d["created"] = r.created;
            d["keys"] = r.keys;
            return record(d);
          },
          py::arg("file"), py::arg("correctives") = false,
          "Recreates the driven keys of FILE (one undo step); returns record(curves, created, keys).")
      .def(
          "driven_poses",
          [](const WorkspaceRef& w, bool correctives) {
            const tools::DrivenPoseSet set = unwrap(w.ws->driven_poses(driven_kind(correctives)));
            py::list out;
            for (const tools::DrivenDriver& d : set.drivers)
              for (const tools::DrivenCurve& c : d.curves) {
                py::dict e;
                e["driver"] = d.driver;
                e["driven"] = c.driven;
                e["node"] = c.node;
                e["at"] = c.times;
                e["values"] = c.values;
                out.append(record(e));
              }
            return out;
          },
          py::arg("correctives") = false,
          "The driven keys of the kind: a list of record(driver, driven, node, at, values).")
      .def(
          "set_driven_key",
          [](const WorkspaceRef& w, const std::string& driver, const py::dict& driven, std::optional<double> at,
             const std::string& tangent) {
            tools::DrivenKeyRequest request;
            request.driver = driver;
            request.at = at;
            if (!tangent.empty()) {
              auto t = ops::anim::tangent_type_from_name(tangent);
              if (!t) raise(Status(ErrorCode::kInvalidArgument, "tangent: unknown tangent type '" + tangent + "'").with_field("tangent"));
              request.tangent = *t;
            }
            for (const auto& [k, v] : driven) {
              std::optional<double> value;
              if (!v.is_none()) value = v.cast<double>();
              request.driven.emplace_back(k.cast<std::string>(), value);
            }
            const tools::DrivenKeyReport r = edit(w, [&](app::Workspace& ws) { return unwrap(ws.set_driven_key(request)); });
            py::dict d;
            d["at"] = r.at;
            d["curves"] = r.curves;
            d["created"] = r.created;
            return record(d);
          },
          py::arg("driver"), py::arg("driven"), py::arg("at") = py::none(), py::arg("tangent") = "",
          "Keys a pose: at the driver's value (or `at`) each channel of `driven` ({channel: value or None for its "
          "value now}) gets a driven key. One undo step; returns record(at, curves, created).")
      .def(
          "remove_driven_keys",
          [](const WorkspaceRef& w, const std::vector<std::string>& driven) {
            edit(w, [&](app::Workspace& ws) { check(ws.remove_driven_keys(driven)); });
          },
          py::arg("driven"), "Removes the driven keys of the channels (each keeps its value now). One undo step.")
      .def(
          "create_pose_reader",
          [](const WorkspaceRef& w, const std::string& joint, py::handle axis) {
            const math::Vec3 a = vec3_from_python(axis, "axis");
            return edit(w, [&](app::Workspace& ws) {
              const graph::NodeId j = unwrap(ws.node(joint, "joint"));
              return ws.graph().node(unwrap(ws.create_pose_reader(j, a)))->name();
            });
          },
          py::arg("joint"), py::arg("axis") = py::make_tuple(1.0, 0.0, 0.0),
          "Makes a pose reader on JOINT (a corrective's driver): returns its name; drive with NAME.angle (the swing "
          "of `axis` from rest, degrees) or NAME.rotateX/Y/Z. One undo step.");
}

void def_data(WorkspaceClass& cls) {
  cls.def(
         "export_skin_weights",
         [](const WorkspaceRef& w, const std::string& file, const std::optional<std::string>& format) {
           const std::string f = format ? *format : current_settings().string("data.weights");
           return unwrap(w.ws->export_skin_weights(file, unwrap(tools::weights_format_named(f)))).string();
         },
         py::arg("file"), py::arg("format") = py::none(),
         "Writes every skinCluster's weights to FILE (.weights.json): format \"json\", or \"binary\" (the arrays in a "
         "side file beside it, with a checksum); None: the setting data.weights. Returns its path.")
      .def(
          "import_skin_weights",
          [](const WorkspaceRef& w, const std::string& file, const std::map<std::string, std::string>& rename, bool nearest,
             bool mirror) {
            tools::WeightsImport o;
            o.rename = rename;
            o.nearest = nearest;
            o.mirror = mirror;
            const tools::WeightsReport r = edit(w, [&](app::Workspace& ws) { return unwrap(ws.import_skin_weights(file, o)); });
            py::dict d;
            d["skins"] = r.skins;
            d["vertices"] = r.vertices;
            d["remapped"] = r.remapped;
            return record(d);
          },
          py::arg("file"), py::arg("rename") = std::map<std::string, std::string>{}, py::arg("nearest") = false,
          py::arg("mirror") = false,
          "Sets skin weights from FILE: joints by uuid, name (after `rename`), or the nearest; mirrored with `mirror`. "
          "One undo step; returns record(skins, vertices, remapped).")
      .def(
          "export_control_shapes",
          [](const WorkspaceRef& w, const std::string& file, const std::string& rig) {
            return unwrap(w.ws->export_control_shapes(rig, file)).string();
          },
          py::arg("file"), py::arg("rig") = "", "Writes a built rig's control shapes and colours to FILE (.shapes.json).")
      .def(
          "import_control_shapes",
          [](const WorkspaceRef& w, const std::string& file, const std::string& rig) {
            const tools::ShapesReport r = edit(w, [&](app::Workspace& ws) { return unwrap(ws.import_control_shapes(rig, file)); });
            py::dict d;
            d["set"] = r.set;
            d["missing"] = r.missing;
            return record(d);
          },
          py::arg("file"), py::arg("rig") = "",
          "Sets control shapes and colours from FILE by rigId, role and index (one undo step); returns record(set, missing).")
      .def(
          "export_blend_shapes",
          [](const WorkspaceRef& w, const std::string& file) { return unwrap(w.ws->export_blend_shapes(file)).string(); },
          py::arg("file"), "Writes every blendShape's targets and weights to FILE (.blendshapes.json); returns its path.")
      .def(
          "import_blend_shapes",
          [](const WorkspaceRef& w, const std::string& file) {
            const tools::BlendShapesReport r = edit(w, [&](app::Workspace& ws) { return unwrap(ws.import_blend_shapes(file)); });
            py::dict d;
            d["blend_shapes"] = r.blend_shapes;
            d["targets"] = r.targets;
            d["created"] = r.created;
            d["added"] = r.added;
            d["driven"] = r.driven;
            return record(d);
          },
          py::arg("file"),
          "Sets blend shape targets and weights from FILE by blendShape (else mesh) name, targets by name or index; a "
          "mesh without a blendShape gets one. One undo step; returns record(blend_shapes, targets, created, added, driven).");
  def_driven_keys(cls);
}

}  // namespace rigel::python
