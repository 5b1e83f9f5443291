#include "rigel/io/gltf_export.h"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "gltf_exporter.h"

namespace rigel::io {
namespace gltf_exporter {
namespace {

double max_abs(const Mat4& m) { return m.cwiseAbs().maxCoeff(); }

}  // namespace

bool near_matrix(const Mat4& a, const Mat4& b, double tolerance) {
  return math::is_near(a, b, tolerance * std::max({1.0, max_abs(a), max_abs(b)}));
}

bool near_vec(const Vec3& a, const Vec3& b, double tolerance) {
  const double scale = std::max({1.0, a.cwiseAbs().maxCoeff(), b.cwiseAbs().maxCoeff()});
  return (a - b).cwiseAbs().maxCoeff() <= tolerance * scale;
}

bool near_quat(const Quat& a, const Quat& b, double tolerance) {
  const double plus = (a.coeffs() - b.coeffs()).cwiseAbs().maxCoeff();
  const double minus = (a.coeffs() + b.coeffs()).cwiseAbs().maxCoeff();
  return std::min(plus, minus) <= tolerance;
}

std::string type_of(const Graph& g, NodeId id) { return g.node(id)->type().name(); }

std::string describe(const Graph& g, const Plug& plug) { return g.plug_name(plug) + " (" + type_of(g, plug.node) + ")"; }

Status Exporter::run(const fs::path& out, bool binary) {
  g_.evaluate_all();
  Result<ClipList> clips = read_clips(g_);
  if (!clips) return clips.status();
  clips_ = std::move(*clips);
  if (Status s = collect_nodes(); !s) return s;
  if (Status s = collect_meshes(); !s) return s;
  collect_skeleton_skin();
  merge_mesh_nodes();
  if (Status s = rest_pose(); !s) return s;
  analyse_animation();
  apply_rest_values();
  // A deform-only export bakes: its nodes' glTF transforms are relative to
  // other nodes than their channels are.
  const bool bake = options_.frames || options_.bake || options_.deform_only || !bake_reason_.empty();
  if (bake) {
    report_.baked = true;
    report_.bake_reason = options_.frames ? "requested (frames " + number(options_.frames->first) + ":" +
                                                number(options_.frames->second) + ")"
                          : options_.bake        ? "requested"
                          : options_.deform_only ? "deform-only"
                                                 : bake_reason_;
    if (Status s = bake_all(); !s) return s;
  } else if (Status s = direct_all(); !s) {
    return s;
  }
  return write(out, binary);
}

}  // namespace gltf_exporter

namespace {

std::string lower(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

}  // namespace

Status export_gltf(scene::Scene& scene, const std::filesystem::path& out, const GltfExportOptions& options,
                   GltfExportReport* report) {
  const std::string ext = lower(out.extension().string());
  if (ext != ".glb" && ext != ".gltf")
    return error(ErrorCode::kInvalidArgument,
                 out.string() + ": unsupported file type '" + ext + "' (glTF export writes .glb or .gltf)");
  if (options.frames) {
    const auto [first, last] = *options.frames;
    if (!std::isfinite(first) || !std::isfinite(last))
      return error(ErrorCode::kInvalidArgument, "frames: must be finite numbers");
    if (first > last)
      return error(ErrorCode::kInvalidArgument,
                   "frames " + gltf_exporter::number(first) + ":" + gltf_exporter::number(last) + ": the first frame is after the last");
    if (first < 0.0)
      return error(ErrorCode::kInvalidArgument,
                   "frames: " + gltf_exporter::number(first) + " is before frame 0 (glTF animation times are not negative)");
  }
  GltfExportReport local;
  GltfExportReport& r = report ? *report : local;
  r = GltfExportReport{};
  gltf_exporter::Exporter exporter(scene, options, r);
  return exporter.run(out, ext == ".glb");
}

}  // namespace rigel::io
