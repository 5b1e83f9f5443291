// Rig regression tests (rig_tests.h): poses recorded with the joints'
// world matrices under them, written as diffable JSON, and checked.

#include "rigel/tools/rig_tests.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <set>
#include <sstream>
#include <system_error>

#include <nlohmann/json.hpp>

#include "rigel/io/diffable_json.h"
#include "rigel/io/json_depth.h"
#include "rigel/io/scene_file.h"
#include "rigel/scene/transform_types.h"

namespace rigel::tools {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;
using math::Mat4;

constexpr const char* kFormat = "rigel rig tests";
constexpr int kVersion = 1;
constexpr std::size_t kMaxDepth = 32;
constexpr std::uintmax_t kMaxBytes = 256u << 20;
constexpr std::size_t kMaxFrames = 100000;
// A joint is stored with a pose when its world matrix differs from the
// base's by more than this (well under any tolerance a check uses).
constexpr double kSame = 1e-12;

// Every joint of the scene, by name, as evaluated now.
std::map<std::string, Mat4> joint_worlds(scene::Scene& scene) {
  std::map<std::string, Mat4> out;
  graph::Graph& g = scene.graph();
  for (graph::NodeId id : g.nodes())
    if (g.node(id)->type().name() == scene::kJointType) out[g.node(id)->name()] = scene.world_matrix(id);
  return out;
}

double difference(const Mat4& a, const Mat4& b) { return (a - b).cwiseAbs().maxCoeff(); }

// The joints of `now` that differ from `base`.
std::map<std::string, Mat4> changed(const std::map<std::string, Mat4>& now, const std::map<std::string, Mat4>& base) {
  std::map<std::string, Mat4> out;
  for (const auto& [name, m] : now) {
    const auto b = base.find(name);
    if (b == base.end() || difference(m, b->second) > kSame) out.emplace(name, m);
  }
  return out;
}

// `rest` with each control's translate moved and rotation turned: the
// entries of component `rig_id` ("" : every component).
Pose nudged(const Pose& rest, const std::string& rig_id, const RecordRigTestsOptions& o) {
  Pose p;
  p.rig = rest.rig;
  const math::Vec3 move = o.offset * math::Vec3(1.0, 0.6, -0.4);
  const math::Quat turn(Eigen::AngleAxisd(o.degrees * M_PI / 180.0, math::Vec3(1, 2, 3).normalized()));
  for (const PoseEntry& e : rest.entries) {
    if (!rig_id.empty() && e.rig_id != rig_id) continue;
    PoseEntry n = e;
    n.channels.clear();
    for (const PoseChannel& c : e.channels) {
      if (const auto* t = std::get_if<math::Vec3>(&c.value); t && c.attr == "translate")
        n.channels.push_back({c.attr, graph::Value(math::Vec3(*t + move))});
      else if (const auto* q = std::get_if<math::Quat>(&c.value); q && c.attr == "rotation")
        n.channels.push_back({c.attr, graph::Value(math::Quat((*q * turn).normalized()))});
    }
    if (!n.channels.empty()) p.entries.push_back(std::move(n));
  }
  return p;
}

Status apply(scene::Scene& scene, graph::NodeId rig, const Pose& pose) {
  if (pose.entries.empty()) return Status::ok();
  auto applied = apply_pose(scene.graph(), pose, rig, ApplyPoseOptions{});
  return applied ? Status::ok() : applied.status();
}

// ---- the file

Json matrix_json(const Mat4& m) {
  Json a = Json::array();
  for (int i = 0; i < 16; ++i) a.push_back(m.data()[i]);
  return a;
}

Json joints_json(const std::map<std::string, Mat4>& joints) {
  Json out = Json::object();
  for (const auto& [name, m] : joints) out[name] = matrix_json(m);
  return out;
}

Json pose_json(const Pose& pose) { return Json::parse(pose_to_json(pose)); }

// 12 significant digits: the file stays readable and small; a check's
// tolerance is far above what that rounds away.
std::string scalar(const Json& j) {
  if (j.is_number_float()) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.12g", j.get<double>());
    return buffer;
  }
  return j.dump(-1, ' ', false, Json::error_handler_t::replace);
}

// `pose` as the file will hold it (12 significant digits): what a check
// applies, so recording computes the joints under the same values.
Pose rounded(const Pose& pose) {
  io::DiffableJsonOptions options;
  options.scalar = scalar;
  auto back = pose_from_json(io::diffable_json(pose_json(pose), options), "rig tests");
  return back ? *back : pose;
}

struct Reader {
  const std::string& source;
  Status bad(const std::string& where, const std::string& what) const {
    return Status(ErrorCode::kParseError, source + ": " + where + ": " + what).with_field("tests");
  }
  Result<Mat4> matrix(const Json& j, const std::string& where) const {
    if (!j.is_array() || j.size() != 16) return bad(where, "expected 16 numbers (a matrix, column-major)");
    Mat4 m;
    for (int i = 0; i < 16; ++i) {
      const Json& x = j[static_cast<std::size_t>(i)];
      if (!x.is_number() || !std::isfinite(x.get<double>())) return bad(where + "[" + std::to_string(i) + "]", "expected a finite number");
      m.data()[i] = x.get<double>();
    }
    return m;
  }
  Result<std::map<std::string, Mat4>> joints(const Json& doc, const std::string& key, const std::string& where) const {
    const auto it = doc.find(key);
    if (it == doc.end() || !it->is_object()) return bad(where + key, "expected an object {JOINT: [16 numbers]}");
    std::map<std::string, Mat4> out;
    for (const auto& [name, value] : it->items()) {
      auto m = matrix(value, where + key + "." + name);
      if (!m) return m.status();
      out.emplace(name, *m);
    }
    return out;
  }
  Result<Pose> pose(const Json& doc, const std::string& where) const {
    const auto it = doc.find("pose");
    if (it == doc.end() || !it->is_object()) return bad(where + "pose", "expected a pose object");
    return pose_from_json(it->dump(), source + ": " + where + "pose");
  }
};

}  // namespace

Result<RigTests> record_rig_tests(scene::Scene& scene, graph::NodeId rig, const RecordRigTestsOptions& o) {
  if (o.frames.size() > kMaxFrames)
    return Status(ErrorCode::kInvalidArgument, "more than " + std::to_string(kMaxFrames) + " frames").with_field("frames");
  for (double f : o.frames)
    if (!std::isfinite(f)) return Status(ErrorCode::kInvalidArgument, "a frame is not a finite number").with_field("frames");
  RigTests t;
  graph::Graph& g = scene.graph();
  if (!g.node(rig)) return Status(ErrorCode::kInvalidArgument, "no such rig").with_field("rig");
  t.rig = g.node(rig)->name();
  scene.set_frame(o.frames.empty() ? 0.0 : o.frames.front());
  auto rest = capture_pose(g, {rig}, "rest");
  if (!rest) return Status(rest.status()).with_field("rig");
  t.rig = rest->rig.empty() ? t.rig : rest->rig;
  t.rest = rounded(*rest);
  if (Status s = apply(scene, rig, t.rest); !s) return s;
  t.base = joint_worlds(scene);
  const auto add = [&](std::string name, double frame, Pose pose) -> Status {
    pose.name = name;
    pose = rounded(pose);
    scene.set_frame(frame);
    if (Status s = apply(scene, rig, t.rest); !s) return s;
    if (Status s = apply(scene, rig, pose); !s) return s;
    t.poses.push_back({std::move(name), frame, std::move(pose), changed(joint_worlds(scene), t.base)});
    return Status::ok();
  };
  if (o.frames.empty()) {
    Status s = add("rest", 0.0, Pose{"rest", t.rest.rig, {}});
    std::set<std::string> seen;
    for (const PoseEntry& e : t.rest.entries) {
      if (!s || !seen.insert(e.rig_id).second) continue;
      Pose p = nudged(t.rest, e.rig_id, o);
      if (!p.entries.empty()) s = add(e.component.empty() ? e.rig_id : e.component, 0.0, std::move(p));
    }
    if (s) s = add("all", 0.0, nudged(t.rest, "", o));
    if (!s) return s;
    return t;
  }
  for (double frame : o.frames) {
    scene.set_frame(frame);
    char name[48];
    std::snprintf(name, sizeof name, "frame_%g", frame);
    auto p = capture_pose(g, {rig}, name);
    if (!p) return Status(p.status()).with_field("rig");
    if (Status s = add(name, frame, std::move(*p)); !s) return s;
  }
  return t;
}

std::string rig_tests_to_json(const RigTests& t) {
  Json poses = Json::array();
  for (const RigTestPose& p : t.poses)
    poses.push_back(Json{{"name", p.name}, {"frame", p.frame}, {"pose", pose_json(p.pose)}, {"joints", joints_json(p.joints)}});
  const Json doc{{"format", kFormat},         {"version", kVersion},         {"rig", t.rig},
                 {"character", t.character},  {"base", joints_json(t.base)}, {"rest", pose_json(t.rest)},
                 {"poses", std::move(poses)}};
  io::DiffableJsonOptions options;
  options.scalar = scalar;
  return io::diffable_json(doc, options);
}

Result<RigTests> rig_tests_from_json(std::string_view text, const std::string& source) {
  auto parsed = io::parse_json(text, source, kMaxDepth);
  if (!parsed) return Status(parsed.status()).with_field("tests");
  const Json& doc = *parsed;
  const Reader r{source};
  if (!doc.is_object()) return r.bad("the document", "expected an object");
  if (doc.value("format", std::string()) != kFormat) return r.bad("format", std::string("expected \"") + kFormat + "\"");
  const auto version = doc.find("version");
  if (version == doc.end() || !version->is_number_integer() || version->get<std::int64_t>() > kVersion)
    return r.bad("version", "expected a whole number up to " + std::to_string(kVersion));
  RigTests t;
  for (auto [key, out] : {std::pair{"rig", &t.rig}, {"character", &t.character}}) {
    const auto it = doc.find(key);
    if (it == doc.end() || !it->is_string()) return r.bad(key, "expected a string");
    *out = it->get<std::string>();
  }
  auto base = r.joints(doc, "base", "");
  if (!base) return base.status();
  t.base = std::move(*base);
  const auto rest = doc.find("rest");
  if (rest == doc.end() || !rest->is_object()) return r.bad("rest", "expected a pose object");
  auto rest_pose = pose_from_json(rest->dump(), source + ": rest");
  if (!rest_pose) return rest_pose.status();
  t.rest = std::move(*rest_pose);
  const auto poses = doc.find("poses");
  if (poses == doc.end() || !poses->is_array()) return r.bad("poses", "expected an array");
  for (std::size_t i = 0; i < poses->size(); ++i) {
    const Json& p = (*poses)[i];
    const std::string where = "poses[" + std::to_string(i) + "].";
    if (!p.is_object()) return r.bad(where.substr(0, where.size() - 1), "expected an object");
    RigTestPose out;
    if (!p.contains("name") || !p["name"].is_string()) return r.bad(where + "name", "expected a string");
    out.name = p["name"].get<std::string>();
    if (!p.contains("frame") || !p["frame"].is_number() || !std::isfinite(p["frame"].get<double>()))
      return r.bad(where + "frame", "expected a finite number");
    out.frame = p["frame"].get<double>();
    auto pose = r.pose(p, where);
    if (!pose) return pose.status();
    out.pose = std::move(*pose);
    auto joints = r.joints(p, "joints", where);
    if (!joints) return joints.status();
    out.joints = std::move(*joints);
    t.poses.push_back(std::move(out));
  }
  return t;
}

Result<RigTests> load_rig_tests(const fs::path& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec))
    return Status(ErrorCode::kNotFound, path.string() + ": no such rig tests file").with_field("tests");
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec || size > kMaxBytes)
    return Status(ErrorCode::kParseError, path.string() + ": over 256 MiB or unreadable, not rig tests").with_field("tests");
  std::ifstream in(path, std::ios::binary);
  std::stringstream buffer;
  buffer << in.rdbuf();
  if (!in) return Status(ErrorCode::kIoError, path.string() + ": cannot be read").with_field("tests");
  return rig_tests_from_json(buffer.str(), path.string());
}

Status save_rig_tests(const RigTests& tests, const fs::path& path) {
  if (Status s = io::write_file_atomic(path, rig_tests_to_json(tests)); !s) return Status(s).with_field("output");
  return Status::ok();
}

fs::path rig_tests_path(const fs::path& definition) {
  const std::string name = definition.filename().string();
  for (const char* ext : {".rig.xml", ".rig.json", ".build.json"})
    if (name.size() > std::string_view(ext).size() && name.ends_with(ext))
      return definition.parent_path() / (name.substr(0, name.size() - std::string_view(ext).size()) + kRigTestExtension);
  return definition.parent_path() / (name + kRigTestExtension);
}

Result<RigTestReport> check_rig_tests(scene::Scene& scene, graph::NodeId rig, const RigTests& t, double tolerance) {
  if (!std::isfinite(tolerance) || tolerance < 0)
    return Status(ErrorCode::kInvalidArgument, "the tolerance must be a finite number from 0").with_field("tolerance");
  if (!scene.graph().node(rig)) return Status(ErrorCode::kInvalidArgument, "no such rig").with_field("rig");
  RigTestReport report;
  for (const RigTestPose& p : t.poses) {
    ++report.poses;
    scene.set_frame(p.frame);
    Status s = apply(scene, rig, t.rest);
    if (s) s = apply(scene, rig, p.pose);
    if (!s) {
      report.mismatches.push_back({p.name, "", 0.0, "cannot be applied: " + s.message()});
      continue;
    }
    const std::map<std::string, Mat4> now = joint_worlds(scene);
    for (const auto& [name, base] : t.base) {
      const auto expected = p.joints.find(name);
      const Mat4& want = expected != p.joints.end() ? expected->second : base;
      const auto got = now.find(name);
      ++report.joints;
      if (got == now.end()) {
        report.mismatches.push_back({p.name, name, 0.0, "no such joint in the scene"});
        continue;
      }
      const double e = difference(got->second, want);
      report.max_error = std::max(report.max_error, std::isfinite(e) ? e : INFINITY);
      if (!(e <= tolerance)) report.mismatches.push_back({p.name, name, e, ""});
    }
  }
  return report;
}

}  // namespace rigel::tools
