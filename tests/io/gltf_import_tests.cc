// Tests of the glTF importer (src/io/gltf_import.cc): the bundled characters
// against numbers read off their JSON, SimpleSkin posed and skinned by hand,
// synthetic files written here (every interpolation, morph targets, clips,
// matrices, names, buffers), malformed input (each refused with a message
// naming the element, none crashing), the Khronos validator's skin cases,
// and a bounded mutation fuzz.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "io_test_util.h"
#include "rigel/io/gltf_import.h"
#include "rigel/io/scene_file.h"
#include "rigel/math/transform.h"
#include "rigel/ops/anim/clips.h"
#include "rigel/ops/anim/nodes.h"
#include "rigel/ops/deform/nodes.h"
#include "rigel/ops/registry.h"
#include "rigel/scene/transform_types.h"
#include "../support/slow_build.h"

namespace rigel::io {
namespace {

using namespace rigel::io::testing;  // NOLINT: test helpers
using Json = nlohmann::json;
namespace sc = ops::skin_cluster_attr;
namespace bs = ops::blend_shape_attr;
namespace xf = scene::xform;

using rigel::testing::kSlowBuildDivisor;

fs::path gltf_dir() { return source_dir() / "tests" / "data" / "gltf"; }
fs::path invalid_dir() { return source_dir() / "tests" / "data" / "gltf_invalid"; }

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// ---- an imported scene, with lookups that fail the test when a name is missing ----

struct Imported {
  std::unique_ptr<Scene> scene;
  Graph& g() { return scene->graph(); }

  NodeId id(const std::string& name) {
    const NodeId id = scene->graph().find(name);
    EXPECT_TRUE(id.is_valid()) << "the scene should have a node named '" << name << "'";
    return id;
  }
  std::string type(const std::string& name) {
    const NodeId n = id(name);
    return n.is_valid() ? g().node(n)->type().name() : "";
  }
  const graph::Value& value(const std::string& name, graph::AttrIndex attr) { return g().evaluate(id(name), attr); }
  template <typename T>
  T get(const std::string& name, graph::AttrIndex attr) {
    const NodeId n = id(name);
    if (!n.is_valid()) return T{};
    return std::get<T>(g().evaluate(n, attr));
  }
  Mat4 world(const std::string& name) {
    const NodeId n = id(name);
    return n.is_valid() ? scene->world_matrix(n) : Mat4::Identity();
  }
  std::string parent(const std::string& name) {
    const NodeId p = g().parent(id(name));
    return p.is_valid() ? g().node(p)->name() : "";
  }
  std::size_t count(const std::string& type_name) {
    std::size_t n = 0;
    for (NodeId node : g().nodes()) n += g().node(node)->type().name() == type_name;
    return n;
  }
  // The source of a connected input ("node.attr"), or "" when unconnected.
  std::string source(const std::string& name, graph::AttrIndex attr, std::int32_t element = -1) {
    std::optional<Plug> src = g().source(Plug{id(name), attr, element});
    return src ? g().plug_name(*src) : "";
  }
};

Imported import_ok(const fs::path& path, const GltfImportOptions& options = {}) {
  Result<std::unique_ptr<Scene>> r = import_gltf(path, options);
  EXPECT_TRUE(r.is_ok()) << path << " should import: " << r.status().message();
  Imported out;
  if (r.is_ok()) out.scene = std::move(*r);
  else out.scene = std::make_unique<Scene>();
  return out;
}

// The refusal's message; fails the test if the import succeeds.
std::string import_error(const fs::path& path) {
  Result<std::unique_ptr<Scene>> r = import_gltf(path);
  EXPECT_FALSE(r.is_ok()) << path << " should be refused";
  if (r.is_ok()) return "";
  EXPECT_EQ(r.status().message().rfind(path.string() + ": ", 0), 0u) << "a refusal names the file first: " << r.status().message();
  return r.status().message();
}

::testing::AssertionResult near(const Vec3& a, const Vec3& b, double tolerance) {
  if ((a - b).cwiseAbs().maxCoeff() <= tolerance) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "(" << a.transpose() << ") vs (" << b.transpose() << ")";
}

::testing::AssertionResult near(const Mat4& a, const Mat4& b, double tolerance) {
  if (math::is_near(a, b, tolerance)) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "\n" << a << "\nvs\n" << b;
}

// Same rotation (q and -q are one rotation).
::testing::AssertionResult same_rotation(const Quat& a, const Quat& b, double tolerance) {
  const double d = std::min((a.coeffs() - b.coeffs()).norm(), (a.coeffs() + b.coeffs()).norm());
  if (d <= tolerance) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "[" << a.coeffs().transpose() << "] vs [" << b.coeffs().transpose() << "]";
}

Quat about_z(double degrees) { return Quat(Eigen::AngleAxisd(math::to_radians(degrees), Vec3::UnitZ())); }

// ---- a glTF written by hand ---------------------------------------------------------

std::string base64(const std::string& bytes) {
  static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const auto n = (std::uint32_t{static_cast<unsigned char>(bytes[i])} << 16) |
                   (std::uint32_t{static_cast<unsigned char>(bytes[i + 1])} << 8) | static_cast<unsigned char>(bytes[i + 2]);
    for (int k = 3; k >= 0; --k) out += kAlphabet[(n >> (6 * k)) & 63];
  }
  if (i < bytes.size()) {
    std::uint32_t n = std::uint32_t{static_cast<unsigned char>(bytes[i])} << 16;
    if (i + 1 < bytes.size()) n |= std::uint32_t{static_cast<unsigned char>(bytes[i + 1])} << 8;
    out += kAlphabet[(n >> 18) & 63];
    out += kAlphabet[(n >> 12) & 63];
    out += i + 1 < bytes.size() ? kAlphabet[(n >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

// JSON plus one binary buffer that every accessor points into; written as a
// .gltf with the buffer embedded (or beside it) or as a .glb.
class GltfFile {
 public:
  Json doc = {{"asset", {{"version", "2.0"}}}};
  std::string bin;

  int view(const void* data, std::size_t size) {
    while (bin.size() % 4 != 0) bin += '\0';
    Json v = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", size}};
    bin.append(static_cast<const char*>(data), size);
    return push("bufferViews", v);
  }
  int accessor(const void* data, std::size_t size, std::size_t count, int component_type, const char* type, bool normalized = false) {
    Json a = {{"bufferView", view(data, size)}, {"componentType", component_type}, {"count", count}, {"type", type}};
    if (normalized) a["normalized"] = true;
    return push("accessors", a);
  }
  int floats(const std::vector<float>& v, const char* type) {
    return accessor(v.data(), v.size() * 4, v.size() / components(type), 5126, type);
  }
  int u16s(const std::vector<std::uint16_t>& v, const char* type) {
    return accessor(v.data(), v.size() * 2, v.size() / components(type), 5123, type);
  }
  int u8s(const std::vector<std::uint8_t>& v, const char* type, bool normalized = false) {
    return accessor(v.data(), v.size(), v.size() / components(type), 5121, type, normalized);
  }
  int push(const char* array, Json value) {
    doc[array].push_back(std::move(value));
    return static_cast<int>(doc[array].size()) - 1;
  }
  int node(Json value) { return push("nodes", std::move(value)); }

  Json with_buffer(const std::string& uri) const {
    Json d = doc;
    if (!bin.empty()) {
      d["buffers"] = Json::array({{{"byteLength", bin.size()}}});
      if (!uri.empty()) d["buffers"][0]["uri"] = uri;
    }
    return d;
  }
  std::string gltf_text() const { return with_buffer("data:application/octet-stream;base64," + base64(bin)).dump(1); }
  std::string glb_bytes() const {
    std::string json = with_buffer("").dump();
    while (json.size() % 4 != 0) json += ' ';
    std::string body = bin;
    while (body.size() % 4 != 0) body += '\0';
    std::string out;
    auto u32 = [&](std::uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
    const std::size_t total = 12 + 8 + json.size() + (body.empty() ? 0 : 8 + body.size());
    u32(0x46546C67);
    u32(2);
    u32(static_cast<std::uint32_t>(total));
    u32(static_cast<std::uint32_t>(json.size()));
    u32(0x4E4F534A);
    out += json;
    if (!body.empty()) {
      u32(static_cast<std::uint32_t>(body.size()));
      u32(0x004E4942);
      out += body;
    }
    return out;
  }
  fs::path write_gltf(const fs::path& dir, const std::string& name) const {
    write_text(dir / name, gltf_text());
    return dir / name;
  }
  fs::path write_glb(const fs::path& dir, const std::string& name) const {
    write_text(dir / name, glb_bytes());
    return dir / name;
  }
  // The buffer in a file beside the .gltf, named by `uri` (written to `file`).
  fs::path write_gltf_external(const fs::path& dir, const std::string& name, const std::string& uri, const std::string& file) const {
    write_text(dir / name, with_buffer(uri).dump(1));
    write_text(dir / file, bin);
    return dir / name;
  }

 private:
  static std::size_t components(const char* type) {
    const std::string t = type;
    return t == "SCALAR" ? 1 : t == "VEC2" ? 2 : t == "VEC3" ? 3 : t == "VEC4" ? 4 : 16;
  }
};

// One triangle in the z = 0 plane, on node 0 ("tri"), as a mesh named "shape".
GltfFile triangle_file() {
  GltfFile f;
  const int position = f.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3");
  f.push("meshes", {{"name", "shape"}, {"primitives", {{{"attributes", {{"POSITION", position}}}}}}});
  f.node({{"name", "tri"}, {"mesh", 0}});
  return f;
}

// Two joints (root at the origin, tip 1 up) skinning a triangle: vertex 0
// on the root, 1 on the tip, 2 half and half. Node 2 holds the mesh.
GltfFile skinned_file() {
  GltfFile f;
  f.node({{"name", "root"}, {"children", {1}}});
  f.node({{"name", "tip"}, {"translation", {0, 1, 0}}});
  const int position = f.floats({1, 0, 0, 1, 1, 0, 1, 0.5f, 0}, "VEC3");
  const int joints = f.u8s({0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0}, "VEC4");
  const int weights = f.floats({1, 0, 0, 0, 1, 0, 0, 0, 0.5f, 0.5f, 0, 0}, "VEC4");
  const int ibm = f.floats({1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1,  //
                            1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -1, 0, 1},
                           "MAT4");
  f.push("meshes", {{"name", "skinned"},
                    {"primitives", {{{"attributes", {{"POSITION", position}, {"JOINTS_0", joints}, {"WEIGHTS_0", weights}}}}}}});
  f.push("skins", {{"joints", {0, 1}}, {"inverseBindMatrices", ibm}});
  f.node({{"name", "body"}, {"mesh", 0}, {"skin", 0}, {"translation", {5, 5, 5}}});
  return f;
}

// ---- the bundled characters ----------------------------------------------------------

struct CharacterFacts {
  const char* file;
  std::size_t nodes, joints;  // glTF nodes; how many some skin lists
  const char* mesh;           // the mesh node's name
  std::size_t vertices, triangles;
  std::size_t skin_joints;
  std::size_t curves;         // animated (node, path) pairs over all animations
  std::size_t clips;
};

// Counts read off the files' JSON with python3 (json + struct), independently
// of tinygltf and the importer.
const CharacterFacts kCharacters[] = {
    {"CesiumMan.glb", 22, 19, "Cesium_Man", 3273, 4672, 19, 57, 1},
    {"RiggedFigure.glb", 22, 19, "Proxy", 370, 256, 19, 57, 1},
    {"RiggedSimple.glb", 5, 2, "Cylinder", 96, 188, 2, 6, 1},
    {"SimpleSkin.gltf", 3, 2, "node_0_mesh", 10, 8, 2, 1, 1},
    {"assimp_simple_skin.gltf", 3, 2, "node_0_mesh", 10, 8, 2, 1, 1},
    // The mesh is called "Plane" like its node, which keeps the name (nodes come first).
    {"assimp_quad_skin.glb", 23, 10, "Plane1", 4, 2, 10, 0, 0},
    {"rigify_human_metarig.glb", 161, 159, "metarig_skin1", 3816, 1908, 159, 0, 0},
    {"rigify_human_rig_def_anim.glb", 162, 160, "rig_def_skin1", 3840, 1920, 160, 480, 1},
};

// The JSON of a .gltf or the JSON chunk of a .glb, read here without tinygltf.
Json file_json(const fs::path& path) {
  const std::string bytes = read_text(path);
  if (bytes.rfind("glTF", 0) == 0) {
    std::uint32_t length = 0;
    std::memcpy(&length, bytes.data() + 12, 4);
    return Json::parse(bytes.substr(20, length));
  }
  return Json::parse(bytes);
}

TEST(GltfImportCharacters, every_bundled_character_imports_with_the_files_counts_names_and_hierarchy) {
  for (const CharacterFacts& facts : kCharacters) {
    SCOPED_TRACE(facts.file);
    Imported s = import_ok(gltf_dir() / facts.file);
    EXPECT_EQ(s.count("joint"), facts.joints) << "a node becomes a joint when a skin lists it";
    EXPECT_EQ(s.count("transform"), facts.nodes - facts.joints) << "every other node is a transform";
    EXPECT_EQ(s.count("mesh"), 1u);
    EXPECT_EQ(s.count("skinCluster"), 1u);
    EXPECT_EQ(s.count("animCurveVec3") + s.count("animCurveQuat"), facts.curves) << "one curve per animated (node, path)";
    EXPECT_EQ(s.count("animClips"), facts.clips);
    EXPECT_EQ(s.type(facts.mesh), "mesh");
    EXPECT_EQ(s.get<std::vector<Vec3>>(facts.mesh, scene::mesh_attr::kPoints).size(), facts.vertices);
    EXPECT_EQ(s.get<std::vector<std::int64_t>>(facts.mesh, scene::mesh_attr::kTriangles).size(), 3 * facts.triangles);
    const std::string skin = std::string(facts.mesh) + "_skinCluster";
    EXPECT_EQ(s.get<std::vector<std::int64_t>>(skin, sc::kInfluenceOffsets).size(), facts.vertices + 1);
    EXPECT_EQ(s.get<std::vector<Mat4>>(skin, sc::kBindPreMatrices).size(), facts.skin_joints);
    EXPECT_EQ(s.source(skin, sc::kJointMatrices, static_cast<std::int32_t>(facts.skin_joints - 1)).empty(), false)
        << "the last joint feeds the last jointMatrices element";
    EXPECT_EQ(s.source(facts.mesh, scene::mesh_attr::kPoints), skin + ".outPoints");
    EXPECT_TRUE(s.parent(facts.mesh).empty()) << "a skinned mesh is a root: glTF ignores its node's transform";

    // Names and parents, node by node, from the JSON.
    const Json doc = file_json(gltf_dir() / facts.file);
    const Json& nodes = doc["nodes"];
    ASSERT_EQ(nodes.size(), facts.nodes);
    std::vector<std::string> names(nodes.size());
    for (std::size_t i = 0; i < nodes.size(); ++i) names[i] = nodes[i].value("name", "node_" + std::to_string(i));
    std::set<int> joints;
    for (const Json& skin_json : doc["skins"])
      for (const Json& j : skin_json["joints"]) joints.insert(j.get<int>());
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      EXPECT_EQ(s.type(names[i]), joints.count(static_cast<int>(i)) ? "joint" : "transform") << names[i];
      for (const Json& c : nodes[i].value("children", Json::array()))
        EXPECT_EQ(s.parent(names[c.get<std::size_t>()]), names[i]) << "children give the hierarchy";
    }
  }
}

TEST(GltfImportCharacters, simple_skin__joints_and_skinned_points_by_hand_at_rest_and_mid_animation) {
  Imported s = import_ok(gltf_dir() / "SimpleSkin.gltf");
  // Node 1 (translation 0 1 0) and its child node 2 are the joints; both
  // inverse bind matrices translate by (0, -1, 0).
  EXPECT_EQ(s.parent("node_2"), "node_1");
  EXPECT_TRUE(s.parent("node_0").empty());
  EXPECT_EQ(s.parent("node_0_mesh"), "");
  ASSERT_EQ(s.g().time(), 0.0);
  EXPECT_TRUE(near(s.world("node_1"), math::translation_matrix(Vec3(0, 1, 0)), 1e-12));
  EXPECT_TRUE(near(s.world("node_2"), math::translation_matrix(Vec3(0, 1, 0)), 1e-12)) << "key 0 is the identity rotation";
  const std::vector<Vec3> bind = {Vec3(-0.5, 0, 0), Vec3(0.5, 0, 0), Vec3(-0.5, 0.5, 0), Vec3(0.5, 0.5, 0), Vec3(-0.5, 1, 0),
                                  Vec3(0.5, 1, 0),  Vec3(-0.5, 1.5, 0), Vec3(0.5, 1.5, 0), Vec3(-0.5, 2, 0), Vec3(0.5, 2, 0)};
  std::vector<Vec3> points = s.get<std::vector<Vec3>>("node_0_mesh", scene::mesh_attr::kPoints);
  ASSERT_EQ(points.size(), 10u);
  for (std::size_t v = 0; v < 10; ++v) EXPECT_TRUE(near(points[v], bind[v], 1e-6)) << "at rest the skin gives POSITION, vertex " << v;

  // t = 1 s is key 2: (0, 0, 0.707, 0.707), 90 degrees about z exactly.
  // Vertex 8 (-0.5, 2) on joint 1 turns about (0, 1): (-1, 0.5). Vertex 4
  // (-0.5, 1), half and half: (-0.5, 1) and (0, 0.5) average to (-0.25, 0.75).
  s.g().set_time(1.0);
  EXPECT_TRUE(near(s.world("node_2"), math::trs_matrix(Vec3(0, 1, 0), about_z(90), Vec3::Ones()), 1e-7));
  points = s.get<std::vector<Vec3>>("node_0_mesh", scene::mesh_attr::kPoints);
  EXPECT_TRUE(near(points[8], Vec3(-1, 0.5, 0), 1e-6));
  EXPECT_TRUE(near(points[9], Vec3(-1, 1.5, 0), 1e-6));
  EXPECT_TRUE(near(points[4], Vec3(-0.25, 0.75, 0), 1e-6));
  EXPECT_TRUE(near(points[5], Vec3(0.25, 1.25, 0), 1e-6));
  EXPECT_TRUE(near(points[0], bind[0], 1e-6)) << "vertex 0 is all joint 1's, which does not move";

  // t = 0.25 s, half way from the identity to key 1 (0, 0, 0.383, 0.924):
  // slerp gives half the key's angle, atan2(0.383, 0.924) about z.
  s.g().set_time(0.25);
  const double theta = std::atan2(double{0.382999986410141f}, double{0.9240000247955322f});
  EXPECT_TRUE(same_rotation(s.get<Quat>("node_2", xf::kRotateQuaternion), Quat(Eigen::AngleAxisd(theta, Vec3::UnitZ())), 1e-6));
  points = s.get<std::vector<Vec3>>("node_0_mesh", scene::mesh_attr::kPoints);
  EXPECT_TRUE(near(points[8], Vec3(-0.5 * std::cos(theta) - std::sin(theta), -0.5 * std::sin(theta) + std::cos(theta) + 1, 0), 1e-6));
}

TEST(GltfImportCharacters, scale_option_scales_translations_positions_and_inverse_binds) {
  GltfImportOptions options;
  options.scale = 2.0;
  Imported s = import_ok(gltf_dir() / "SimpleSkin.gltf", options);
  EXPECT_TRUE(near(s.world("node_2"), math::translation_matrix(Vec3(0, 2, 0)), 1e-12));
  s.g().set_time(1.0);
  const std::vector<Vec3> points = s.get<std::vector<Vec3>>("node_0_mesh", scene::mesh_attr::kPoints);
  EXPECT_TRUE(near(points[8], Vec3(-2, 1, 0), 1e-6)) << "the posed skin is the unscaled one times 2";
  EXPECT_FALSE(import_gltf(gltf_dir() / "SimpleSkin.gltf", GltfImportOptions{.scale = -1.0, .registry = nullptr}).is_ok()) << "scale must be positive";
  EXPECT_FALSE(import_gltf(gltf_dir() / "SimpleSkin.gltf", GltfImportOptions{.scale = std::nan(""), .registry = nullptr}).is_ok());
}

TEST(GltfImportCharacters, cesium_man__weights_kept_as_stored_and_renormalised_when_skinning) {
  Imported s = import_ok(gltf_dir() / "CesiumMan.glb");
  const std::string skin = "Cesium_Man_skinCluster";
  EXPECT_TRUE(s.get<bool>(skin, sc::kNormalizeWeights));
  const auto offsets = s.get<std::vector<std::int64_t>>(skin, sc::kInfluenceOffsets);
  const auto joints = s.get<std::vector<std::int64_t>>(skin, sc::kInfluenceJoints);
  const auto weights = s.get<std::vector<double>>(skin, sc::kInfluenceWeights);
  ASSERT_EQ(offsets.size(), 3274u);
  std::size_t off = 0, worst = 0;
  double worst_deviation = 0;
  for (std::size_t v = 0; v + 1 < offsets.size(); ++v) {
    double sum = 0;
    for (auto k = offsets[v]; k < offsets[v + 1]; ++k) sum += weights[static_cast<std::size_t>(k)];
    if (std::abs(sum - 1) > 2e-3) ++off;
    if (std::abs(sum - 1) > worst_deviation) worst_deviation = std::abs(sum - 1), worst = v;
  }
  EXPECT_EQ(off, 210u) << "the file's 210 vertices whose weights do not sum to 1 are stored as they are";
  EXPECT_NEAR(worst_deviation, 0.815, 1e-3);

  // The worst vertex, skinned by hand with its weights divided by their sum.
  const auto bind = s.get<std::vector<Vec3>>(skin, sc::kBindPoints);
  const auto ibm = s.get<std::vector<Mat4>>(skin, sc::kBindPreMatrices);
  Vec3 expected = Vec3::Zero(), unnormalised = Vec3::Zero();
  double sum = 0;
  for (auto k = offsets[worst]; k < offsets[worst + 1]; ++k) sum += weights[static_cast<std::size_t>(k)];
  for (auto k = offsets[worst]; k < offsets[worst + 1]; ++k) {
    const auto j = static_cast<std::size_t>(joints[static_cast<std::size_t>(k)]);
    const std::optional<Plug> joint = s.g().source(Plug{s.id(skin), sc::kJointMatrices, static_cast<std::int32_t>(j)});
    ASSERT_TRUE(joint.has_value());
    const Vec3 p = (s.scene->world_matrix(joint->node) * ibm[j] * bind[worst].homogeneous()).head<3>();
    expected += weights[static_cast<std::size_t>(k)] / sum * p;
    unnormalised += weights[static_cast<std::size_t>(k)] * p;
  }
  const Vec3 skinned = s.get<std::vector<Vec3>>("Cesium_Man", scene::mesh_attr::kPoints)[worst];
  EXPECT_TRUE(near(skinned, expected, 1e-5)) << "the skin divides by the weight sum";
  EXPECT_GT((skinned - unnormalised).norm(), 1e-2) << "and that differs from the raw weights";
}

TEST(GltfImportCharacters, assimp_quad_skin__three_weight_sets_and_the_skinned_node_transform_ignored) {
  Imported s = import_ok(gltf_dir() / "assimp_quad_skin.glb");
  const std::string skin = "Plane1_skinCluster";
  // Non-zero weights per vertex over JOINTS_0..2 (python): 4 + 4 + 2, 4 + 1, 4, 4 + 1.
  EXPECT_EQ(s.get<std::vector<std::int64_t>>(skin, sc::kInfluenceOffsets), (std::vector<std::int64_t>{0, 10, 15, 19, 24}));
  const auto joints = s.get<std::vector<std::int64_t>>(skin, sc::kInfluenceJoints);
  const auto weights = s.get<std::vector<double>>(skin, sc::kInfluenceWeights);
  ASSERT_EQ(joints.size(), 24u);
  EXPECT_EQ(joints[8], 9) << "vertex 0's ninth influence comes from JOINTS_2";
  EXPECT_NEAR(weights[8], 0.0486, 1e-4);
  EXPECT_EQ(s.type("Plane"), "transform") << "the skinned node stays, as a transform";
  EXPECT_TRUE(near(s.world("Plane1"), Mat4::Identity(), 0)) << "the mesh node is a root with an identity transform";
  // joint world x inverse bind x POSITION (python), about 100 times the
  // positions: the node's own matrix (x100) is not applied a second time.
  const auto points = s.get<std::vector<Vec3>>("Plane1", scene::mesh_attr::kPoints);
  ASSERT_EQ(points.size(), 4u);
  EXPECT_TRUE(near(points[0], Vec3(-100, 4.602e-5, 100), 1e-3));
  EXPECT_TRUE(near(points[2], Vec3(100, -4.602e-5, -100.00001), 1e-3));
}

TEST(GltfImportCharacters, animation_becomes_one_clip_with_curves_on_the_channels) {
  Imported s = import_ok(gltf_dir() / "RiggedSimple.glb");
  const NodeId clips = ops::anim::find_clips_node(s.g());
  ASSERT_TRUE(clips.is_valid());
  EXPECT_EQ(s.g().node(clips)->name(), "clips");
  Result<std::vector<ops::anim::Clip>> list = ops::anim::clips_of(s.g(), clips);
  ASSERT_TRUE(list.is_ok()) << list.status().message();
  ASSERT_EQ(list->size(), 1u);
  EXPECT_EQ((*list)[0].name, "animation_0") << "an unnamed animation is animation_<index>";
  EXPECT_EQ(s.type("node_3_rotate"), "animCurveQuat");
  EXPECT_EQ(s.source("node_3", xf::kRotateQuaternion), "node_3_rotate.output");
  EXPECT_EQ(s.source("node_3_rotate", ops::anim::track_attr::kClip), "clips.activeClip");
  EXPECT_EQ(s.get<std::vector<std::int64_t>>("node_3_rotate", ops::anim::track_attr::kClipOffsets).size(), 2u);
}

TEST(GltfImportCharacters, imported_scenes_save_and_load_back_identically) {
  for (const char* file : {"SimpleSkin.gltf", "CesiumMan.glb", "rigify_human_rig_def_anim.glb"}) {
    SCOPED_TRACE(file);
    Imported s = import_ok(gltf_dir() / file);
    const std::string text = write_scene(*s.scene);
    Result<std::unique_ptr<Scene>> again = parse_scene(text, "resaved.rigel");
    ASSERT_TRUE(again.is_ok()) << again.status().message();
    EXPECT_TRUE(graphs_identical(s.g(), (*again)->graph())) << "the .rigel file holds everything the import made";
  }
}

// ---- synthetic files -------------------------------------------------------------------

// A node "n" whose translation, rotation and scale are animated with
// `interpolation`, keys at 0, 1 and 2 s. Cubic keys carry tangents chosen so
// that the middle of the first segment is easy to compute by hand.
fs::path trs_animation_file(const fs::path& dir, const std::string& interpolation) {
  GltfFile f;
  f.node({{"name", "n"}});
  const bool cubic = interpolation == "CUBICSPLINE";
  const int times = f.floats({0, 1, 2}, "SCALAR");
  const float s = std::sqrt(0.5f);
  std::vector<float> t = {0, 0, 0, 2, 0, 0, 2, 4, 0};
  std::vector<float> r = {0, 0, 0, 1, 0, 0, s, s, 0, 0, 1, 0};
  std::vector<float> sc = {1, 1, 1, 2, 2, 2, 2, 2, 4};
  if (cubic) {
    // in-tangent, value, out-tangent per key; translation key 0 leaves at
    // slope (4, 0, 0), scale key 0 at (2, 0, 0); rotations have zero tangents.
    t = {0, 0, 0, 0, 0, 0, 4, 0, 0, /**/ 0, 0, 0, 2, 0, 0, 0, 0, 0, /**/ 0, 0, 0, 2, 4, 0, 0, 0, 0};
    r = {0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, /**/ 0, 0, 0, 0, 0, 0, s, s, 0, 0, 0, 0, /**/ 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0};
    sc = {0, 0, 0, 1, 1, 1, 2, 0, 0, /**/ 0, 0, 0, 2, 2, 2, 0, 0, 0, /**/ 0, 0, 0, 2, 2, 4, 0, 0, 0};
  }
  const int tv = f.floats(t, "VEC3"), rv = f.floats(r, "VEC4"), sv = f.floats(sc, "VEC3");
  Json samplers = Json::array(), channels = Json::array();
  int k = 0;
  for (const auto& [output, path] : std::vector<std::pair<int, const char*>>{{tv, "translation"}, {rv, "rotation"}, {sv, "scale"}}) {
    samplers.push_back({{"input", times}, {"output", output}, {"interpolation", interpolation}});
    channels.push_back({{"sampler", k++}, {"target", {{"node", 0}, {"path", path}}}});
  }
  f.push("animations", {{"name", "move"}, {"samplers", samplers}, {"channels", channels}});
  return f.write_gltf(dir, interpolation + ".gltf");
}

struct Trs {
  Vec3 t;
  Quat r;
  Vec3 s;
};

Trs trs_at(Imported& s, double time) {
  s.g().set_time(time);
  return {s.get<Vec3>("n", xf::kTranslate), s.get<Quat>("n", xf::kRotateQuaternion), s.get<Vec3>("n", xf::kScale)};
}

TEST(GltfImportAnimation, step_holds_each_key_until_the_next) {
  TempDir dir;
  Imported s = import_ok(trs_animation_file(dir.path(), "STEP"));
  EXPECT_EQ(s.type("n_translate"), "animCurveVec3");
  EXPECT_EQ(s.get<std::int64_t>("n_translate", ops::anim::track_attr::kInterpolation), 0) << "step";
  Trs a = trs_at(s, 0.5);
  EXPECT_TRUE(near(a.t, Vec3(0, 0, 0), 1e-12));
  EXPECT_TRUE(same_rotation(a.r, Quat::Identity(), 1e-7));
  EXPECT_TRUE(near(a.s, Vec3(1, 1, 1), 1e-12));
  a = trs_at(s, 1.5);
  EXPECT_TRUE(near(a.t, Vec3(2, 0, 0), 1e-12));
  EXPECT_TRUE(same_rotation(a.r, about_z(90), 1e-7));
  EXPECT_TRUE(near(a.s, Vec3(2, 2, 2), 1e-12));
  a = trs_at(s, 5.0);
  EXPECT_TRUE(near(a.t, Vec3(2, 4, 0), 1e-12)) << "after the last key the last value holds";
  EXPECT_TRUE(same_rotation(a.r, about_z(180), 1e-7));
}

TEST(GltfImportAnimation, linear_interpolates_and_slerps) {
  TempDir dir;
  Imported s = import_ok(trs_animation_file(dir.path(), "LINEAR"));
  Trs a = trs_at(s, 0.5);
  EXPECT_TRUE(near(a.t, Vec3(1, 0, 0), 1e-12));
  EXPECT_TRUE(same_rotation(a.r, about_z(45), 1e-7));
  EXPECT_TRUE(near(a.s, Vec3(1.5, 1.5, 1.5), 1e-7));
  a = trs_at(s, 1.75);
  EXPECT_TRUE(near(a.t, Vec3(2, 3, 0), 1e-12));
  EXPECT_TRUE(same_rotation(a.r, about_z(157.5), 1e-7));
  EXPECT_TRUE(near(a.s, Vec3(2, 2, 3.5), 1e-7));
  EXPECT_TRUE(near(s.world("n"), math::trs_matrix(a.t, a.r, a.s), 1e-12)) << "the channels drive the node";
}

TEST(GltfImportAnimation, cubic_spline_uses_the_files_tangents_per_second) {
  TempDir dir;
  Imported s = import_ok(trs_animation_file(dir.path(), "CUBICSPLINE"));
  EXPECT_EQ(s.get<std::int64_t>("n_translate", ops::anim::track_attr::kInterpolation), 2) << "cubicSpline";
  // Hermite at the middle of [0, 1]: 0.5 v0 + 0.125 b0 + 0.5 v1 - 0.125 a1.
  const Trs a = trs_at(s, 0.5);
  EXPECT_NEAR(a.t.x(), 0.5 * 0 + 0.125 * 4 + 0.5 * 2 - 0.125 * 0, 1e-7);
  EXPECT_NEAR(a.s.x(), 0.5 * 1 + 0.125 * 2 + 0.5 * 2, 1e-7);
  EXPECT_NEAR(a.s.y(), 1.5, 1e-7);
  EXPECT_TRUE(same_rotation(a.r, about_z(45), 1e-7)) << "zero tangents: the normalised mean of the keys";
  const Trs b = trs_at(s, 2.0);
  EXPECT_TRUE(near(b.t, Vec3(2, 4, 0), 1e-7)) << "the curve passes through its keys";
}

// Two animations of a node "hip": "walk" moves it along x over 1 s, "jump"
// along y over 2 s and turns it; "walk" does not turn it.
GltfFile two_clip_file(const std::string& first_name, const std::string& second_name) {
  GltfFile f;
  f.node({{"name", "hip"}, {"translation", {0, 1, 0}}, {"rotation", {0, 0, 0, 1}}});
  const int t1 = f.floats({0, 1}, "SCALAR"), v1 = f.floats({0, 0, 0, 2, 0, 0}, "VEC3");
  const int t2 = f.floats({0.5f, 2.5f}, "SCALAR"), v2 = f.floats({0, 10, 0, 0, 14, 0}, "VEC3");
  const float s = std::sqrt(0.5f);
  const int r2 = f.floats({0, 0, 0, 1, 0, 0, s, s}, "VEC4");
  Json walk = {{"samplers", {{{"input", t1}, {"output", v1}}}}, {"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}}}}};
  Json jump = {{"samplers", {{{"input", t2}, {"output", v2}, {"interpolation", "STEP"}}, {{"input", t2}, {"output", r2}}}},
               {"channels",
                {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}},
                 {{"sampler", 1}, {"target", {{"node", 0}, {"path", "rotation"}}}}}}};
  if (!first_name.empty()) walk["name"] = first_name;
  if (!second_name.empty()) jump["name"] = second_name;
  f.push("animations", walk);
  f.push("animations", jump);
  return f;
}

TEST(GltfImportAnimation, two_animations_are_two_clips_in_one_curve_per_channel) {
  TempDir dir;
  Imported s = import_ok(two_clip_file("walk", "jump").write_gltf(dir.path(), "clips.gltf"));
  const NodeId clips = s.id("clips");
  Result<std::vector<ops::anim::Clip>> list = ops::anim::clips_of(s.g(), clips);
  ASSERT_TRUE(list.is_ok()) << list.status().message();
  ASSERT_EQ(list->size(), 2u);
  EXPECT_EQ((*list)[0].name, "walk");
  EXPECT_EQ((*list)[1].name, "jump");
  EXPECT_EQ((*list)[0].start, 0.0);
  EXPECT_EQ((*list)[0].end, 1.0);
  EXPECT_EQ((*list)[1].start, 0.5) << "a clip spans its keys";
  EXPECT_EQ((*list)[1].end, 2.5);
  EXPECT_EQ(s.count("animCurveVec3"), 1u) << "both clips' translation keys in one curve";
  // walk is LINEAR, jump's translation STEP: one curve is LINEAR, so jump's
  // step gets a hold key just before its second key (2 + 3 keys).
  EXPECT_EQ(s.get<std::vector<std::int64_t>>("hip_translate", ops::anim::track_attr::kClipOffsets),
            (std::vector<std::int64_t>{0, 2, 5}));

  s.g().set_time(0.5);
  EXPECT_TRUE(near(s.get<Vec3>("hip", xf::kTranslate), Vec3(1, 0, 0), 1e-12)) << "walk is active first";
  EXPECT_TRUE(same_rotation(s.get<Quat>("hip", xf::kRotateQuaternion), Quat::Identity(), 1e-12))
      << "walk does not animate the rotation: it stays at rest";
  ASSERT_TRUE(ops::anim::set_active_clip(s.g(), clips, 1).is_ok());
  s.g().set_time(1.5);
  EXPECT_TRUE(near(s.get<Vec3>("hip", xf::kTranslate), Vec3(0, 10, 0), 1e-12)) << "jump's STEP translation holds key 0";
  EXPECT_TRUE(same_rotation(s.get<Quat>("hip", xf::kRotateQuaternion), about_z(45), 1e-7)) << "jump's rotation, half way";
}

TEST(GltfImportAnimation, clip_names_are_made_unique_and_unnamed_ones_numbered) {
  TempDir dir;
  Imported same = import_ok(two_clip_file("run", "run").write_gltf(dir.path(), "same.gltf"));
  Result<std::vector<ops::anim::Clip>> list = ops::anim::clips_of(same.g(), same.id("clips"));
  ASSERT_TRUE(list.is_ok());
  EXPECT_EQ((*list)[0].name, "run");
  EXPECT_EQ((*list)[1].name, "run1");
  Imported unnamed = import_ok(two_clip_file("", "").write_gltf(dir.path(), "unnamed.gltf"));
  list = ops::anim::clips_of(unnamed.g(), unnamed.id("clips"));
  ASSERT_TRUE(list.is_ok());
  EXPECT_EQ((*list)[0].name, "animation_0");
  EXPECT_EQ((*list)[1].name, "animation_1");
}

TEST(GltfImportAnimation, clips_that_disagree_on_interpolation_are_converted) {
  // Clip 0 LINEAR, clip 1 CUBICSPLINE on one translation: LINEAR becomes an
  // exact cubic. Clip 2 STEP forces everything to LINEAR for the rotation.
  GltfFile f;
  f.node({{"name", "n"}});
  const int times = f.floats({0, 1, 2}, "SCALAR");
  const int linear = f.floats({0, 0, 0, 2, 0, 0, 2, 6, 0}, "VEC3");
  const int cubic = f.floats({0, 0, 0, 5, 0, 0, 0, 0, 0, /**/ 0, 0, 0, 7, 0, 0, 0, 0, 0, /**/ 0, 0, 0, 9, 0, 0, 0, 0, 0}, "VEC3");
  const float s = std::sqrt(0.5f);
  const int rot_linear = f.floats({0, 0, 0, 1, 0, 0, s, s, 0, 0, 1, 0}, "VEC4");
  auto anim = [&](int output, const char* interpolation, const char* path) {
    return Json{{"samplers", {{{"input", times}, {"output", output}, {"interpolation", interpolation}}}},
                {"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", path}}}}}}};
  };
  f.push("animations", anim(linear, "LINEAR", "translation"));
  f.push("animations", anim(cubic, "CUBICSPLINE", "translation"));
  f.push("animations", anim(rot_linear, "STEP", "rotation"));
  f.push("animations", anim(rot_linear, "LINEAR", "rotation"));
  TempDir dir;
  Imported scene = import_ok(f.write_gltf(dir.path(), "mixed.gltf"));
  EXPECT_EQ(scene.get<std::int64_t>("n_translate", ops::anim::track_attr::kInterpolation), 2) << "cubic for both clips";
  EXPECT_EQ(scene.get<std::int64_t>("n_rotate", ops::anim::track_attr::kInterpolation), 1) << "linear for step + linear";
  const NodeId clips = scene.id("clips");
  auto at = [&](int clip, double t) {
    EXPECT_TRUE(ops::anim::set_active_clip(scene.g(), clips, clip).is_ok());
    scene.g().set_time(t);
    return std::pair(scene.get<Vec3>("n", xf::kTranslate), scene.get<Quat>("n", xf::kRotateQuaternion));
  };
  EXPECT_TRUE(near(at(0, 0.5).first, Vec3(1, 0, 0), 1e-12)) << "the linear clip is still linear";
  EXPECT_TRUE(near(at(0, 1.25).first, Vec3(2, 1.5, 0), 1e-12));
  EXPECT_TRUE(near(at(1, 0.5).first, Vec3(6, 0, 0), 1e-12)) << "zero tangents: the mean of 5 and 7";
  EXPECT_TRUE(same_rotation(at(2, 0.5).second, Quat::Identity(), 1e-12)) << "step holds the key";
  EXPECT_TRUE(same_rotation(at(2, 0.99).second, Quat::Identity(), 1e-12)) << "up to just before the next key";
  EXPECT_TRUE(same_rotation(at(2, 1.0).second, about_z(90), 1e-7));
  EXPECT_TRUE(same_rotation(at(3, 0.5).second, about_z(45), 1e-7)) << "the linear clip slerps";
}

TEST(GltfImportMorph, targets_become_a_blend_shape_with_animated_weights) {
  GltfFile f = triangle_file();
  const int d0 = f.floats({0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3");  // everything up 1 in z
  const int d1 = f.floats({2, 0, 0, 0, 0, 0, 0, 0, 0}, "VEC3");  // vertex 0 along x by 2
  f.doc["meshes"][0]["primitives"][0]["targets"] = {{{"POSITION", d0}}, {{"POSITION", d1}}};
  f.doc["meshes"][0]["weights"] = {0.5, 0};
  const int times = f.floats({0, 1}, "SCALAR");
  const int values = f.floats({0, 0, 1, 0.5f}, "SCALAR");  // key 0: (0, 0), key 1: (1, 0.5)
  f.push("animations", {{"samplers", {{{"input", times}, {"output", values}}}},
                        {"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "weights"}}}}}}});
  TempDir dir;
  Imported s = import_ok(f.write_gltf(dir.path(), "morph.gltf"));
  EXPECT_EQ(s.type("shape_blendShape"), "blendShape");
  EXPECT_EQ(s.parent("shape"), "tri") << "an unskinned mesh sits under its node's transform";
  EXPECT_EQ(s.source("shape", scene::mesh_attr::kPoints), "shape_blendShape.outPoints");
  EXPECT_EQ(s.source("shape_blendShape", bs::kWeights, 1), "tri_weight1.output");
  EXPECT_EQ(s.get<double>("tri_weight0", ops::anim::anim_curve_attr::kRestValue), 0.5) << "the rest weight is the mesh's";
  s.g().set_time(0.5);  // weights (0.5, 0.25): vertex 0 = (0, 0, 0) + 0.5 (0, 0, 1) + 0.25 (2, 0, 0)
  auto points = s.get<std::vector<Vec3>>("shape", scene::mesh_attr::kPoints);
  ASSERT_EQ(points.size(), 3u);
  EXPECT_TRUE(near(points[0], Vec3(0.5, 0, 0.5), 1e-6));
  EXPECT_TRUE(near(points[1], Vec3(1, 0, 0.5), 1e-6));
  s.g().set_time(2.0);
  points = s.get<std::vector<Vec3>>("shape", scene::mesh_attr::kPoints);
  EXPECT_TRUE(near(points[0], Vec3(1, 0, 1), 1e-6)) << "weights (1, 0.5) after the last key";
}

TEST(GltfImportMorph, target_names_come_from_the_mesh_extras) {
  GltfFile f = triangle_file();
  const int d0 = f.floats({0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3");
  const int d1 = f.floats({2, 0, 0, 0, 0, 0, 0, 0, 0}, "VEC3");
  f.doc["meshes"][0]["primitives"][0]["targets"] = {{{"POSITION", d0}}, {{"POSITION", d1}}};
  f.doc["meshes"][0]["extras"] = {{"targetNames", {"lift", "stretch"}}};
  TempDir dir;
  std::vector<std::string> warnings;
  GltfImportOptions options;
  options.warnings = &warnings;
  Imported s = import_ok(f.write_gltf(dir.path(), "named.gltf"), options);
  EXPECT_EQ(s.get<std::vector<std::string>>("shape_blendShape", bs::kTargetNames), (std::vector<std::string>{"lift", "stretch"}));
  EXPECT_TRUE(warnings.empty());
  // Names that do not fit the targets leave them unnamed, with a warning.
  f.doc["meshes"][0]["extras"] = {{"targetNames", {"lift"}}};
  Imported one = import_ok(f.write_gltf(dir.path(), "short.gltf"), options);
  EXPECT_TRUE(one.get<std::vector<std::string>>("shape_blendShape", bs::kTargetNames).empty());
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_TRUE(contains(warnings[0], "meshes[0].extras.targetNames: expected 2 names")) << warnings[0];
  f.doc["meshes"][0]["extras"] = {{"targetNames", {"lift", 3}}};
  Imported mixed = import_ok(f.write_gltf(dir.path(), "mixed.gltf"), options);
  EXPECT_TRUE(mixed.get<std::vector<std::string>>("shape_blendShape", bs::kTargetNames).empty());
  EXPECT_EQ(warnings.size(), 2u);
}

TEST(GltfImportMorph, cubic_weights_and_a_skinned_morph_feed_the_skin) {
  GltfFile f = skinned_file();
  const int d0 = f.floats({0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3");
  f.doc["meshes"][0]["primitives"][0]["targets"] = {{{"POSITION", d0}}};
  const int times = f.floats({0, 1}, "SCALAR");
  // in, value, out per key: 0 leaving at slope 2, 1 arriving flat.
  const int values = f.floats({0, 0, 2, 0, 1, 0}, "SCALAR");
  f.push("animations", {{"samplers", {{{"input", times}, {"output", values}, {"interpolation", "CUBICSPLINE"}}}},
                        {"channels", {{{"sampler", 0}, {"target", {{"node", 2}, {"path", "weights"}}}}}}});
  TempDir dir;
  Imported s = import_ok(f.write_glb(dir.path(), "skinned_morph.glb"));
  EXPECT_EQ(s.source("skinned_skinCluster", sc::kBindPoints), "skinned_blendShape.outPoints");
  s.g().set_time(0.5);  // weight: 0.125 * 2 + 0.5 * 1 = 0.75
  EXPECT_NEAR(s.get<double>("body_weight0", ops::anim::curve_attr::kOutput), 0.75, 1e-12);
  const auto points = s.get<std::vector<Vec3>>("skinned", scene::mesh_attr::kPoints);
  ASSERT_EQ(points.size(), 3u);
  EXPECT_TRUE(near(points[0], Vec3(1, 0, 0.75), 1e-6)) << "morphed, then skinned (at rest)";
  EXPECT_TRUE(near(s.world("skinned"), Mat4::Identity(), 0)) << "the node's own translation (5, 5, 5) is ignored";
}

TEST(GltfImportSkin, a_skinned_triangle_follows_its_joints) {
  GltfFile f = skinned_file();
  TempDir dir;
  Imported s = import_ok(f.write_gltf(dir.path(), "skin.gltf"));
  ASSERT_TRUE(s.g().set_value(Plug{s.id("tip"), xf::kRotateQuaternion}, about_z(90)).is_ok());
  // tip at (0, 1) turns 90 degrees: (1, 1) -> (0, 2); (1, 0.5) half way:
  // 0.5 (1, 0.5) + 0.5 (0.5, 2) = (0.75, 1.25).
  const auto points = s.get<std::vector<Vec3>>("skinned", scene::mesh_attr::kPoints);
  EXPECT_TRUE(near(points[0], Vec3(1, 0, 0), 1e-6));
  EXPECT_TRUE(near(points[1], Vec3(0, 2, 0), 1e-6));
  EXPECT_TRUE(near(points[2], Vec3(0.75, 1.25, 0), 1e-6));
}

TEST(GltfImportNodes, a_matrix_is_decomposed_exactly_shear_included) {
  // M = T(1, 2, 3) R_z(90) SH(xy = 0.5) S(2, 3, 4), column-major.
  Mat4 shear = Mat4::Identity();
  shear(0, 1) = 0.5;
  const Mat4 m = math::translation_matrix(Vec3(1, 2, 3)) * math::rotation_matrix(about_z(90)) * shear *
                 math::scale_matrix(Vec3(2, 3, 4));
  GltfFile f;
  f.node({{"name", "m"}, {"matrix", std::vector<double>(m.data(), m.data() + 16)}});
  TempDir dir;
  Imported s = import_ok(f.write_gltf(dir.path(), "matrix.gltf"));
  EXPECT_TRUE(near(s.world("m"), m, 1e-12));
  EXPECT_TRUE(near(s.get<Vec3>("m", xf::kTranslate), Vec3(1, 2, 3), 1e-12));
  EXPECT_TRUE(near(s.get<Vec3>("m", xf::kScale), Vec3(2, 3, 4), 1e-12));
  EXPECT_TRUE(near(s.get<Vec3>("m", xf::kShear), Vec3(0.5, 0, 0), 1e-12));
  EXPECT_EQ(s.get<std::int64_t>("m", xf::kRotateMode), 1) << "quaternion mode";

  GltfFile projective;
  projective.node({{"matrix", {1, 0, 0, 0.5, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}}});
  const std::string message = import_error(projective.write_gltf(dir.path(), "projective.gltf"));
  EXPECT_TRUE(contains(message, "nodes[0].matrix: not an affine transform")) << message;
}

TEST(GltfImportNodes, names_unnamed_duplicates_and_characters_a_name_cannot_hold) {
  GltfFile f;
  f.node({{"children", {1, 2, 3}}});
  f.node({{"name", "arm"}});
  f.node({{"name", "arm"}});
  f.node({{"name", "my arm[1]"}});
  const int position = f.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3");
  f.push("meshes", {{"primitives", {{{"attributes", {{"POSITION", position}}}}, {{"attributes", {{"POSITION", position}}}, {"mode", 0}}}}});
  f.doc["nodes"][1]["mesh"] = 0;
  TempDir dir;
  Imported s = import_ok(f.write_gltf(dir.path(), "names.gltf"));
  EXPECT_EQ(s.type("node_0"), "transform") << "unnamed: node_<index>";
  EXPECT_EQ(s.parent("arm"), "node_0");
  EXPECT_EQ(s.parent("arm1"), "node_0") << "a duplicate gets the numeric suffix, in file order";
  EXPECT_EQ(s.parent("my_arm_1_"), "node_0") << "space and brackets become '_'";
  EXPECT_EQ(s.type("arm_mesh_0"), "mesh") << "unnamed mesh: <node>_mesh, plus the primitive index when there are several";
  EXPECT_EQ(s.parent("arm_mesh_0"), "arm");
  EXPECT_EQ(s.count("mesh"), 1u) << "the POINTS primitive makes no mesh node";
}

TEST(GltfImportMeshes, strips_fans_normals_and_sparse_accessors) {
  GltfFile f;
  const int position = f.floats({0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0}, "VEC3");
  const int normal = f.floats({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3");
  const int indices = f.u16s({0, 1, 2, 3}, "SCALAR");
  f.push("meshes", {{"name", "strip"}, {"primitives", {{{"attributes", {{"POSITION", position}, {"NORMAL", normal}}}, {"indices", indices}, {"mode", 5}}}}});
  f.push("meshes", {{"name", "fan"}, {"primitives", {{{"attributes", {{"POSITION", position}}}, {"mode", 6}}}}});
  // A sparse POSITION: zeros but vertex 2 at (5, 6, 7).
  const std::vector<std::uint8_t> sparse_index = {2};
  const std::vector<float> sparse_value = {5, 6, 7};
  const int iv = f.view(sparse_index.data(), 1), vv = f.view(sparse_value.data(), 12);
  const int sparse = f.push("accessors", {{"componentType", 5126}, {"count", 3}, {"type", "VEC3"},
                                          {"sparse", {{"count", 1}, {"indices", {{"bufferView", iv}, {"componentType", 5121}}},
                                                      {"values", {{"bufferView", vv}}}}}});
  f.push("meshes", {{"name", "sparse"}, {"primitives", {{{"attributes", {{"POSITION", sparse}}}}}}});
  f.node({{"mesh", 0}});
  f.node({{"mesh", 1}});
  f.node({{"mesh", 2}});
  TempDir dir;
  Imported s = import_ok(f.write_glb(dir.path(), "modes.glb"));
  EXPECT_EQ(s.get<std::vector<std::int64_t>>("strip", scene::mesh_attr::kTriangles), (std::vector<std::int64_t>{0, 1, 2, 1, 3, 2}))
      << "a strip alternates its winding";
  EXPECT_EQ(s.get<std::vector<std::int64_t>>("fan", scene::mesh_attr::kTriangles), (std::vector<std::int64_t>{1, 2, 0, 2, 3, 0}))
      << "a fan turns around vertex 0";
  EXPECT_EQ(s.get<std::vector<Vec3>>("strip", scene::mesh_attr::kNormals).size(), 4u);
  const auto points = s.get<std::vector<Vec3>>("sparse", scene::mesh_attr::kPoints);
  ASSERT_EQ(points.size(), 3u);
  EXPECT_TRUE(near(points[0], Vec3::Zero(), 0));
  EXPECT_TRUE(near(points[2], Vec3(5, 6, 7), 0));
  EXPECT_EQ(s.get<std::vector<std::int64_t>>("sparse", scene::mesh_attr::kTriangles), (std::vector<std::int64_t>{0, 1, 2}))
      << "no indices: 0..n-1";
}

TEST(GltfImportBuffers, external_buffers_resolve_beside_the_file) {
  TempDir dir;
  GltfFile f = triangle_file();
  fs::create_directories(dir.path() / "sub");
  Imported s = import_ok(f.write_gltf_external(dir.path() / "sub", "ext.gltf", "my%20data.bin", "my data.bin"));
  EXPECT_TRUE(near(s.get<std::vector<Vec3>>("shape", scene::mesh_attr::kPoints)[1], Vec3(1, 0, 0), 0));
  fs::remove(dir.path() / "sub" / "my data.bin");
  const std::string message = import_error(dir.path() / "sub" / "ext.gltf");
  EXPECT_TRUE(contains(message, "buffers[0]: missing (uri 'my%20data.bin' not found)")) << message;
  write_text(dir.path() / "sub" / "my data.bin", "short");
  const std::string short_message = import_error(dir.path() / "sub" / "ext.gltf");
  EXPECT_TRUE(contains(short_message, "buffers[0]: 'my%20data.bin' has 5 bytes, byteLength says 36")) << short_message;
}

// ---- malformed input --------------------------------------------------------------------

// Writes `doc` (with f's buffer embedded) and returns the refusal's message.
std::string refuse(const TempDir& dir, const Json& doc, const std::string& name = "bad.gltf") {
  write_text(dir.path() / name, doc.dump());
  return import_error(dir.path() / name);
}

TEST(GltfImportMalformed, bad_indices_name_the_element) {
  TempDir dir;
  GltfFile f = skinned_file();
  const Json good = f.with_buffer("data:application/octet-stream;base64," + base64(f.bin));
  struct Case {
    const char* pointer;
    Json value;
    const char* expected;
  };
  const std::vector<Case> cases = {
      {"/nodes/0/children/0", 9, "nodes[0].children[0]: node 9 does not exist"},
      {"/nodes/0/children/0", -1, "nodes[0].children[0]: node -1 does not exist"},
      {"/nodes/2/mesh", 4, "nodes[2].mesh: mesh 4 does not exist"},
      {"/nodes/2/skin", "0", "nodes[2].skin: must be an index (an integer), not a string \"0\""},
      {"/meshes/0/primitives/0/attributes/POSITION", 99, "meshes[0].primitives[0].attributes.POSITION: accessor 99 does not exist"},
      {"/bufferViews/0/buffer", 5, "bufferViews[0].buffer: buffer 5 does not exist"},
      {"/skins/0/joints/1", 7, "skins[0].joints[1]: node 7 does not exist"},
      {"/skins/0/inverseBindMatrices", 50, "skins[0].inverseBindMatrices: accessor 50 does not exist"},
      {"/accessors/0/count", 30, "accessors[0]: 30 elements need 360 bytes of bufferViews[0], which has 36"},
      {"/accessors/0/componentType", 5130, "accessors[0].componentType: 5130 is not a glTF component type"},
      {"/bufferViews/0/byteLength", 100000, "bufferViews[0]: bytes 0..100000 reach past the end of buffer 0"},
      {"/nodes/1/translation", Json::array({0, 1}), "nodes[1].translation: must have 3 numbers, not 2"},
      {"/skins", Json::array(), "skins: must not be empty"},
      {"/asset/version", "1.0", "asset.version: '1.0' (rigel reads glTF 2.x)"},
  };
  for (const Case& c : cases) {
    Json doc = good;
    doc[Json::json_pointer(c.pointer)] = c.value;
    const std::string message = refuse(dir, doc);
    EXPECT_TRUE(contains(message, c.expected)) << c.pointer << " = " << c.value.dump() << ": " << message;
  }
}

TEST(GltfImportMalformed, hierarchy_cycles_and_two_parents) {
  TempDir dir;
  GltfFile f;
  for (int i = 0; i < 6; ++i) f.node({{"name", std::string("n").append(std::to_string(i))}});
  Json doc = f.doc;
  doc["nodes"][2]["children"] = {5};
  doc["nodes"][5]["children"] = {2};
  EXPECT_TRUE(contains(refuse(dir, doc), "nodes[2]: node is its own ancestor (cycle 2 -> 5 -> 2)"));
  doc = f.doc;
  doc["nodes"][4]["children"] = {4};
  EXPECT_TRUE(contains(refuse(dir, doc), "nodes[4]: node is its own ancestor (cycle 4 -> 4)"));
  doc = f.doc;
  doc["nodes"][1]["children"] = {3};
  doc["nodes"][2]["children"] = {0, 3};
  EXPECT_TRUE(contains(refuse(dir, doc), "nodes[2].children[1]: node 3 already has parent node 1"));
  doc = f.doc;
  doc["scenes"] = {{{"nodes", {0, 3}}}};
  doc["nodes"][0]["children"] = {3};
  EXPECT_TRUE(contains(refuse(dir, doc), "scenes[0].nodes[1]: node 3 is not a root"));
}

TEST(GltfImportMalformed, bad_numbers_in_the_buffers) {
  TempDir dir;
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  {
    GltfFile f = triangle_file();
    std::memcpy(f.bin.data() + 4 * 4, &nan, 4);  // vertex 1, y
    const std::string message = import_error(f.write_glb(dir.path(), "nan_position.glb"));
    EXPECT_TRUE(contains(message, "meshes[0].primitives[0].attributes.POSITION: accessors[0]: NaN in element 1")) << message;
  }
  {
    GltfFile f = skinned_file();
    std::memcpy(f.bin.data() + f.doc["bufferViews"][3]["byteOffset"].get<std::size_t>() + 16 * 4 + 13 * 4, &inf, 4);
    const std::string message = import_error(f.write_gltf(dir.path(), "inf_ibm.gltf"));
    EXPECT_TRUE(contains(message, "skins[0].inverseBindMatrices: accessors[3]: an infinite value in element 1")) << message;
  }
  {
    GltfFile f = skinned_file();
    f.bin[f.doc["bufferViews"][1]["byteOffset"].get<std::size_t>() + 4] = 2;  // vertex 1 on joint 2 of 2
    const std::string message = import_error(f.write_gltf(dir.path(), "joint_range.gltf"));
    EXPECT_TRUE(contains(message, "meshes[0].primitives[0].attributes.JOINTS_0: element 1 has a joint index not below the joint count 2"))
        << message;
  }
  {
    GltfFile f = skinned_file();
    const float minus = -1;
    std::memcpy(f.bin.data() + f.doc["bufferViews"][2]["byteOffset"].get<std::size_t>() + 16 * 2 + 4, &minus, 4);
    const std::string message = import_error(f.write_gltf(dir.path(), "negative.gltf"));
    EXPECT_TRUE(contains(message, "WEIGHTS_0: element 2 has a negative weight")) << message;
  }
  {
    GltfFile f = triangle_file();
    const int indices = f.u16s({0, 1, 7}, "SCALAR");
    f.doc["meshes"][0]["primitives"][0]["indices"] = indices;
    const std::string message = import_error(f.write_gltf(dir.path(), "index.gltf"));
    EXPECT_TRUE(contains(message, "meshes[0].primitives[0].indices: element 2 is not below the vertex count 3")) << message;
  }
  {
    GltfFile f = triangle_file();
    const int normal = f.floats({0, 0, 1, 0, 0, 1}, "VEC3");
    f.doc["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = normal;
    const std::string message = import_error(f.write_gltf(dir.path(), "count.gltf"));
    EXPECT_TRUE(contains(message, "meshes[0].primitives[0].attributes.NORMAL: accessor 1 has 2 elements, POSITION has 3")) << message;
  }
}

TEST(GltfImportMalformed, animations_with_bad_times_counts_and_targets) {
  TempDir dir;
  const fs::path good = trs_animation_file(dir.path(), "LINEAR");
  const Json doc = Json::parse(read_text(good));
  {
    Json d = doc;
    d["accessors"][0]["count"] = 2;  // times: 2 keys, outputs still 3
    EXPECT_TRUE(contains(refuse(dir, d), "animations[0].samplers[0].output: accessors[1] has 3 elements, 2 keys need 2"));
    d = doc;
    d["animations"][0]["channels"][1]["target"]["path"] = "translation";
    EXPECT_TRUE(contains(refuse(dir, d), "animations[0].channels[1]: node 0 translation is also animated by channels[0]"));
    d = doc;
    d["animations"][0]["channels"][1]["target"]["path"] = "weights";
    EXPECT_TRUE(contains(refuse(dir, d), "animations[0].channels[1].target: node 0 has no morph targets to animate"));
    d = doc;
    d["animations"][0]["samplers"][0]["interpolation"] = "SMOOTH";
    EXPECT_TRUE(contains(refuse(dir, d), "animations[0].samplers[0].interpolation: 'SMOOTH' is not LINEAR, STEP or CUBICSPLINE"));
    d = doc;
    d["animations"][0]["samplers"][1]["output"] = 0;
    EXPECT_TRUE(contains(refuse(dir, d), "animations[0].samplers[1].output: accessors[0] is SCALAR of FLOAT; VEC4 of FLOAT"));
  }
  {
    GltfFile f;
    f.node({{"name", "n"}});
    const int times = f.floats({0, 1, 1, 2, 3, 2.5f}, "SCALAR");
    const int values = f.floats(std::vector<float>(18, 0.0f), "VEC3");
    f.push("animations", {{"samplers", {{{"input", times}, {"output", values}}}},
                          {"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "scale"}}}}}}});
    const std::string message = import_error(f.write_gltf(dir.path(), "times.gltf"));
    EXPECT_TRUE(contains(message, "animations[0].samplers[0].input: times not increasing at key 2")) << message;
  }
  {
    // A channel aimed by an extension (no node) is skipped, not refused.
    Json d = doc;
    d["animations"][0]["channels"][2]["target"].erase("node");
    d["animations"][0]["channels"][2]["target"]["path"] = "pointer";
    write_text(dir.path() / "pointer.gltf", d.dump());
    Imported s = import_ok(dir.path() / "pointer.gltf");
    EXPECT_EQ(s.count("animCurveVec3"), 1u) << "translation only: the scale channel had no node";
  }
}

TEST(GltfImportMalformed, skins_on_the_wrong_nodes_and_bad_inverse_binds) {
  TempDir dir;
  GltfFile f = skinned_file();
  const Json good = f.with_buffer("data:application/octet-stream;base64," + base64(f.bin));
  Json d = good;
  d["nodes"][2].erase("mesh");
  EXPECT_TRUE(contains(refuse(dir, d), "nodes[2].skin: a skin needs a mesh on the node"));
  d = good;
  d["skins"][0]["joints"] = {0, 0};
  EXPECT_TRUE(contains(refuse(dir, d), "skins[0].joints[1]: node 0 is also joints[0]"));
  d = good;
  d["nodes"][0].erase("children");
  EXPECT_TRUE(contains(refuse(dir, d), "skins[0].joints: the joints have no common root"));
  d = good;
  d["skins"][0]["skeleton"] = 1;
  EXPECT_TRUE(contains(refuse(dir, d), "skins[0].skeleton: node 1 is not a common root of the joints"));
  d = good;
  d["accessors"][3]["count"] = 1;
  EXPECT_TRUE(contains(refuse(dir, d), "skins[0].inverseBindMatrices: accessors[3] has 1 matrices for 2 joints"));
  d = good;
  d["meshes"][0]["primitives"][0]["attributes"].erase("WEIGHTS_0");
  EXPECT_TRUE(contains(refuse(dir, d), "meshes[0].primitives[0].attributes: JOINTS_0 has no WEIGHTS_0"));
}

TEST(GltfImportMalformed, truncated_and_broken_containers) {
  TempDir dir;
  const std::string glb = read_text(gltf_dir() / "RiggedSimple.glb");
  for (std::size_t cut : {std::size_t{0}, std::size_t{3}, std::size_t{11}, std::size_t{19}, std::size_t{100}, glb.size() / 2, glb.size() - 1}) {
    write_text(dir.path() / "cut.glb", glb.substr(0, cut));
    const std::string message = import_error(dir.path() / "cut.glb");
    EXPECT_TRUE(contains(message, cut < 4 ? "not glTF" : "truncated")) << "cut at " << cut << ": " << message;
  }
  write_text(dir.path() / "syntax.gltf", "{\"asset\": {\"version\": \"2.0\"}, \"nodes\": [");
  EXPECT_TRUE(contains(import_error(dir.path() / "syntax.gltf"), "JSON syntax error"));
  write_text(dir.path() / "deep.gltf", "{\"asset\": {\"version\": \"2.0\", \"extras\": " + std::string(100000, '[') +
                                           std::string(100000, ']') + "}}");
  EXPECT_TRUE(contains(import_error(dir.path() / "deep.gltf"), "JSON nested deeper than 128 levels"));
  write_text(dir.path() / "text.glb", "hello");
  EXPECT_TRUE(contains(import_error(dir.path() / "text.glb"), "not glTF"));
  Result<std::unique_ptr<Scene>> missing = import_gltf(dir.path() / "nowhere.glb");
  ASSERT_FALSE(missing.is_ok());
  EXPECT_EQ(missing.status().code(), ErrorCode::kNotFound);
  Json draco = {{"asset", {{"version", "2.0"}}}, {"extensionsRequired", {"KHR_draco_mesh_compression"}}};
  EXPECT_TRUE(contains(refuse(dir, draco), "extensionsRequired[0]: 'KHR_draco_mesh_compression' is not supported"));
}

TEST(GltfImportBuffers, a_glb_whose_json_chunk_is_padded_with_nuls_imports) {
  std::string glb = triangle_file().glb_bytes();
  std::uint32_t json_length = 0, total = 0;
  std::memcpy(&json_length, glb.data() + 12, 4);
  std::memcpy(&total, glb.data() + 8, 4);
  glb.insert(20 + json_length, std::string(4, '\0'));
  json_length += 4;
  total += 4;
  std::memcpy(glb.data() + 12, &json_length, 4);
  std::memcpy(glb.data() + 8, &total, 4);
  TempDir dir;
  write_text(dir.path() / "nul.glb", glb);
  Imported s = import_ok(dir.path() / "nul.glb");
  EXPECT_EQ(s.count("mesh"), 1u);
}

TEST(GltfImportMalformed, images_are_never_decoded) {
  // A broken embedded picture does not stop the character from loading.
  GltfFile f = triangle_file();
  f.doc["images"] = {{{"uri", "data:image/png;base64,!!!!"}}, {{"uri", "missing.png"}}};
  TempDir dir;
  Imported s = import_ok(f.write_gltf(dir.path(), "images.gltf"));
  EXPECT_EQ(s.count("mesh"), 1u);
}

// ---- the Khronos validator's skin cases ---------------------------------------------------

TEST(GltfImportValidator, every_file_the_validator_calls_invalid_is_refused_naming_the_element) {
  std::size_t invalid = 0, valid = 0;
  for (const auto& entry : fs::directory_iterator(invalid_dir())) {
    const fs::path path = entry.path();
    if (path.extension() != ".gltf") continue;
    SCOPED_TRACE(path.filename().string());
    const Json report = Json::parse(read_text(path.string() + ".report.json"));
    bool has_error = false;
    for (const Json& m : report["issues"]["messages"]) has_error |= m["severity"] == 0;
    Result<std::unique_ptr<Scene>> r = import_gltf(path);
    if (has_error) {
      ++invalid;
      ASSERT_FALSE(r.is_ok()) << "the validator reports an error, so the importer should refuse it";
      const std::string& message = r.status().message();
      EXPECT_EQ(message.rfind(path.string() + ": ", 0), 0u) << message;
      const std::string rest = message.substr(path.string().size() + 2);
      EXPECT_NE(rest.find(": "), std::string::npos) << "the message names an element, then what is wrong: " << message;
    } else if (r.is_ok()) {
      ++valid;
    }
  }
  EXPECT_EQ(invalid, 18u) << "18 of the 24 files hold an error in their report";
  EXPECT_GE(valid, 3u) << "skin__valid, skin__custom_property and node__node_skinned_mesh_without_skin import";
}

TEST(GltfImportValidator, the_messages_match_what_the_validator_found) {
  const std::map<std::string, std::string> expected = {
      {"mesh__unequal_joints.gltf", "meshes[0].primitives[0].attributes: JOINTS_1 has no WEIGHTS_1"},
      {"mesh_data__joints_no_weights.gltf", "bufferViews[0]: bytes 0..32 reach past the end of buffer 0 (16 bytes)"},
      // Also has a joint index out of range; the weights are read first.
      {"mesh_data__joints_weights_complex.gltf", "meshes[0].primitives[0].attributes.WEIGHTS_1: element 1 has a negative weight"},
      {"node__node_skin_without_skinned_mesh.gltf", "nodes[0].skin: meshes[0].primitives[0] has no JOINTS_0"},
      {"node__skin_with_no_mesh.gltf", "nodes[0].skin: a skin needs a mesh on the node"},
      {"node__unresolved_skin.gltf", "nodes[0].skin: skin 0 does not exist"},
      {"skin__buffer_view_bytestride.gltf", "buffers[0]: no uri"},
      {"skin__empty_array.gltf", "skins: must not be empty"},
      {"skin__empty_joints_array.gltf", "skins[0].joints: must not be empty"},
      {"skin__empty_object.gltf", "skins[0]: 'joints' is missing"},
      {"skin__ibm_invalid_count.gltf", "skins[2].inverseBindMatrices: accessors[0] has 2 matrices for 3 joints"},
      {"skin__ibm_invalid_format.gltf", "skins[0].inverseBindMatrices: accessors[0] is MAT3 of FLOAT; MAT4 of FLOAT expected"},
      {"skin__no_common_root.gltf", "skins[0].joints: the joints have no common root"},
      {"skin__no_joints_in_scene.gltf", "nodes[2]: its skinned mesh is in scenes[0], which does not hold its joints"},
      {"skin__skeleton_invalid.gltf", "skins[0].skeleton: node 2 is not a common root of the joints"},
      {"skin__unresolved_ibm.gltf", "skins[0].inverseBindMatrices: accessor 0 does not exist"},
      {"skin__unresolved_joint.gltf", "skins[0].joints[0]: node 0 does not exist"},
      {"skin__unresolved_skeleton.gltf", "skins[0].skeleton: node 1 does not exist"},
  };
  for (const auto& [file, part] : expected) {
    const std::string message = import_error(invalid_dir() / file);
    EXPECT_TRUE(contains(message, part)) << file << ": " << message;
  }
}

// ---- fuzz ------------------------------------------------------------------------------------

std::string mutate(std::string bytes, std::mt19937& rng) {
  const int edits = 1 + static_cast<int>(rng() % 4);
  for (int e = 0; e < edits && !bytes.empty(); ++e) {
    const std::size_t at = rng() % bytes.size();
    switch (rng() % 5) {
      case 0: bytes[at] = static_cast<char>(rng()); break;                  // a random byte
      case 1: bytes[at] = static_cast<char>(bytes[at] ^ (1 << (rng() % 8))); break;  // a bit flip
      case 2: bytes.resize(at); break;                                       // truncated
      case 3: bytes.erase(at, 1 + rng() % 8); break;                         // bytes removed
      default: bytes.insert(at, std::string(1 + rng() % 4, "0123456789-.e[]{}\",:"[rng() % 20])); break;
    }
  }
  return bytes;
}

TEST(GltfImportFuzz, random_mutations_of_a_glb_and_a_gltf_import_or_fail_cleanly) {
  TempDir dir;
  GltfFile morph = skinned_file();
  const int d0 = morph.floats({0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3");
  morph.doc["meshes"][0]["primitives"][0]["targets"] = {{{"POSITION", d0}}};
  const std::vector<std::pair<std::string, std::string>> inputs = {
      {"fuzz.glb", read_text(gltf_dir() / "RiggedSimple.glb")},
      {"fuzz.gltf", read_text(gltf_dir() / "SimpleSkin.gltf")},
      {"fuzz2.glb", morph.glb_bytes()},
  };
  const char* override_iterations = std::getenv("RIGEL_FUZZ_ITERATIONS");
  const int iterations = override_iterations ? std::atoi(override_iterations) : 300 / kSlowBuildDivisor;
  int loaded = 0, refused = 0;
  for (std::size_t k = 0; k < inputs.size(); ++k) {
    std::mt19937 rng(1234u + static_cast<unsigned>(k));
    const fs::path path = dir.path() / inputs[k].first;
    for (int i = 0; i < iterations; ++i) {
      write_text(path, mutate(inputs[k].second, rng));
      Result<std::unique_ptr<Scene>> r = import_gltf(path);
      if (!r.is_ok()) {
        ++refused;
        ASSERT_EQ(r.status().message().rfind(path.string() + ": ", 0), 0u)
            << inputs[k].first << " iteration " << i << ": a refusal names the file: " << r.status().message();
        continue;
      }
      ++loaded;
      (*r)->graph().evaluate_all(graph::Execution::kSerial);  // whatever loaded also evaluates
    }
  }
  RecordProperty("loaded", loaded);
  RecordProperty("refused", refused);
  EXPECT_GT(refused, 0);
  EXPECT_GT(loaded, 0) << "some mutations (inside numbers or names) still import";
}

void collect_pointers(const Json& j, const Json::json_pointer& at, std::vector<Json::json_pointer>& out) {
  if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it) {
      out.push_back(at / it.key());
      collect_pointers(it.value(), at / it.key(), out);
    }
  } else if (j.is_array()) {
    for (std::size_t i = 0; i < j.size(); ++i) {
      out.push_back(at / i);
      collect_pointers(j[i], at / i, out);
    }
  }
}

TEST(GltfImportFuzz, every_member_replaced_by_every_json_kind_imports_or_fails_cleanly) {
  // A file that uses most of what the importer reads: a skin, a morph target,
  // animated weights and translation, a scene.
  GltfFile f = skinned_file();
  const int d0 = f.floats({0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3");
  f.doc["meshes"][0]["primitives"][0]["targets"] = {{{"POSITION", d0}}};
  const int times = f.floats({0, 1}, "SCALAR");
  const int weights = f.floats({0, 1}, "SCALAR");
  const int moves = f.floats({0, 0, 0, 1, 0, 0}, "VEC3");
  f.push("animations", {{"name", "a"},
                        {"samplers", {{{"input", times}, {"output", weights}}, {{"input", times}, {"output", moves}, {"interpolation", "STEP"}}}},
                        {"channels",
                         {{{"sampler", 0}, {"target", {{"node", 2}, {"path", "weights"}}}},
                          {{"sampler", 1}, {"target", {{"node", 1}, {"path", "translation"}}}}}}});
  f.doc["scenes"] = {{{"nodes", {0, 2}}}};
  f.doc["scene"] = 0;
  Json base = f.with_buffer("data:application/octet-stream;base64," + base64(f.bin));
  std::vector<Json::json_pointer> pointers;
  collect_pointers(base, Json::json_pointer(), pointers);
  const std::vector<Json> replacements = {nullptr, true, 0, -1, 1, 2.5, 1e300, 4294967296.0, "", "x",
                                          Json::array(), Json::object(), Json::array({1, 2, 3}), Json::array({"x"})};
  TempDir dir;
  const fs::path path = dir.path() / "field.gltf";
  int checked = 0, loaded = 0;
  for (std::size_t p = 0; p < pointers.size(); p += kSlowBuildDivisor > 1 ? 3 : 1) {
    if (pointers[p].to_string() == "/buffers/0/uri") continue;  // the data itself: covered by the byte fuzz
    for (std::size_t r = 0; r <= replacements.size(); ++r) {
      Json doc = base;
      std::string what;
      if (r == replacements.size()) {
        if (!doc[pointers[p].parent_pointer()].is_object()) continue;
        doc[pointers[p].parent_pointer()].erase(pointers[p].back());
        what = pointers[p].to_string() + " erased";
      } else {
        doc[pointers[p]] = replacements[r];
        what = pointers[p].to_string() + " = " + replacements[r].dump();
      }
      write_text(path, doc.dump());
      Result<std::unique_ptr<Scene>> result = import_gltf(path);
      ++checked;
      if (!result.is_ok()) {
        ASSERT_EQ(result.status().message().rfind(path.string() + ": ", 0), 0u) << what << ": " << result.status().message();
        continue;
      }
      ++loaded;
      (*result)->graph().evaluate_all(graph::Execution::kSerial);
    }
  }
  EXPECT_GT(checked, 500);
  EXPECT_GT(loaded, 0) << "names, for one, take any string";
}

TEST(GltfImport, the_scene_is_built_over_the_registry_given) {
  auto registry = std::make_shared<graph::Registry>();
  ASSERT_TRUE(scene::register_scene_types(*registry).is_ok());
  ASSERT_TRUE(ops::register_ops_types(*registry).is_ok());
  GltfImportOptions options;
  options.registry = registry;
  auto imported = import_gltf(gltf_dir() / "RiggedSimple.glb", options);
  ASSERT_TRUE(imported.is_ok()) << imported.status().message();
  EXPECT_EQ(&(*imported)->graph().registry(), registry.get());
  EXPECT_FALSE((*imported)->graph().can_undo());
  // The same character as over the default registry, node for node.
  auto plain = import_gltf(gltf_dir() / "RiggedSimple.glb");
  ASSERT_TRUE(plain.is_ok()) << plain.status().message();
  auto names = [](scene::Scene& sc) {
    std::vector<std::string> out;
    for (graph::NodeId id : sc.graph().nodes()) out.push_back(sc.graph().node(id)->name());
    return out;
  };
  EXPECT_EQ(names(**imported), names(**plain));
  // A registry without the types the importer makes is an error, not a crash.
  options.registry = std::make_shared<graph::Registry>();
  EXPECT_FALSE(import_gltf(gltf_dir() / "RiggedSimple.glb", options).is_ok());
}

// ---- external files stay inside the file's folder (security) ---------------------------

// A .gltf in dir/sub whose buffer is `uri`, with a byteLength of `length`.
fs::path gltf_with_uri(const fs::path& folder, const std::string& uri, std::size_t length) {
  GltfFile f = triangle_file();
  Json doc = f.with_buffer(uri);
  doc["buffers"][0]["byteLength"] = length;
  write_text(folder / "x.gltf", doc.dump());
  return folder / "x.gltf";
}

TEST(GltfImportBuffers, uris_that_leave_the_files_folder_are_refused_before_anything_is_read) {
  TempDir dir;
  const fs::path sub = dir.path() / "sub";
  fs::create_directories(sub / "inner");
  // A file outside the folder whose bytes would make a valid buffer: only
  // the folder rule can stop it (its size even matches byteLength).
  GltfFile f = triangle_file();
  write_text(dir.path() / "secret.bin", f.bin);
  const std::size_t size = f.bin.size();
  struct Case {
    std::string uri;
    const char* expected;
  };
  const std::vector<Case> cases = {
      {"../secret.bin", "reaches outside the glTF file's folder"},
      {"inner/../../secret.bin", "reaches outside the glTF file's folder"},
      {"%2E%2E/secret.bin", "reaches outside the glTF file's folder"},
      {"../../../../../../../../etc/passwd", "reaches outside the glTF file's folder"},
      {"/etc/passwd", "is an absolute path"},
      {(dir.path() / "secret.bin").string(), "is an absolute path"},
      {"%2Fetc%2Fpasswd", "is an absolute path"},
      {"file:///etc/passwd", "has a scheme"},
      {"file:../secret.bin", "has a scheme"},
      {"http://example.com/x.bin", "has a scheme"},
  };
  for (const Case& c : cases) {
    for (std::size_t length : {size, std::size_t{3}}) {
      const std::string message = import_error(gltf_with_uri(sub, c.uri, length));
      EXPECT_TRUE(contains(message, "buffers[0]: uri '")) << c.uri << ": " << message;
      EXPECT_TRUE(contains(message, c.expected)) << c.uri << ": " << message;
      EXPECT_FALSE(contains(message, "bytes")) << "nothing about the file it names, not even its size: " << message;
    }
  }
  // Symbolic links: a linked file, a linked folder, a link in a subfolder,
  // all leading out; resolved before the folder rule is applied.
  fs::create_symlink(dir.path() / "secret.bin", sub / "link.bin");
  fs::create_directory_symlink(dir.path(), sub / "up");
  fs::create_symlink("../../secret.bin", sub / "inner" / "rel.bin");
  for (const char* uri : {"link.bin", "up/secret.bin", "inner/rel.bin"}) {
    for (std::size_t length : {size, std::size_t{3}}) {
      const std::string message = import_error(gltf_with_uri(sub, uri, length));
      EXPECT_TRUE(contains(message, "leads outside the glTF file's folder")) << uri << ": " << message;
      EXPECT_FALSE(contains(message, "bytes")) << message;
    }
  }
  // Inside the folder: plain names, subfolders, escapes, and a link that
  // stays inside all import.
  write_text(sub / "inner" / "my data.bin", f.bin);
  fs::create_symlink("inner/my data.bin", sub / "inside.bin");
  for (const char* uri : {"inner/my%20data.bin", "./inner/my data.bin", "inner/./my%20data.bin", "inside.bin",
                          "inner/../inner/my%20data.bin"}) {
    Result<std::unique_ptr<Scene>> r = import_gltf(gltf_with_uri(sub, uri, size));
    EXPECT_TRUE(r.is_ok()) << uri << ": " << r.status().message();
  }
}

TEST(GltfImportBuffers, refusals_never_quote_numbers_read_from_a_buffer) {
  // A buffer is a file: a message quoting its values would disclose the
  // bytes of whatever file it is. Messages name the element and the rule.
  TempDir dir;
  // What follows the file's name: the temporary folder's name holds the
  // process id, whose digits may be any of the numbers looked for.
  const auto import_error = [](const fs::path& path) {
    const std::string message = ::rigel::io::import_error(path);
    return message.rfind(path.string() + ": ", 0) == 0 ? message.substr(path.string().size() + 2) : message;
  };
  {
    GltfFile f = triangle_file();
    f.doc["meshes"][0]["primitives"][0]["indices"] = f.u16s({0, 1, 114}, "SCALAR");
    const std::string message = import_error(f.write_gltf(dir.path(), "index.gltf"));
    EXPECT_TRUE(contains(message, "indices: element 2 is not below the vertex count 3")) << message;
    EXPECT_FALSE(contains(message, "114")) << message;
  }
  {
    GltfFile f = skinned_file();
    f.bin[f.doc["bufferViews"][1]["byteOffset"].get<std::size_t>() + 4] = 77;  // vertex 1 on joint 77
    const std::string message = import_error(f.write_gltf(dir.path(), "joint.gltf"));
    EXPECT_TRUE(contains(message, "element 1 has a joint index not below the joint count 2")) << message;
    EXPECT_FALSE(contains(message, "77")) << message;
  }
  {
    GltfFile f = skinned_file();
    const float minus = -0.625f;
    std::memcpy(f.bin.data() + f.doc["bufferViews"][2]["byteOffset"].get<std::size_t>() + 4, &minus, 4);
    const std::string message = import_error(f.write_gltf(dir.path(), "weight.gltf"));
    EXPECT_FALSE(contains(message, "625")) << message;
  }
  {
    GltfFile f = skinned_file();
    const float last = 7.5f;  // an inverse bind matrix whose last row is not 0 0 0 1
    std::memcpy(f.bin.data() + f.doc["bufferViews"][3]["byteOffset"].get<std::size_t>() + 3 * 4, &last, 4);
    const std::string message = import_error(f.write_gltf(dir.path(), "ibm.gltf"));
    EXPECT_TRUE(contains(message, "matrix 0 is not affine")) << message;
    EXPECT_FALSE(contains(message, "7.5")) << message;
  }
  {
    GltfFile f = triangle_file();
    const int input = f.floats({0.0f, 2.25f, 1.125f}, "SCALAR");
    const int output = f.floats({0, 0, 0, 0, 1, 0, 0, 2, 0}, "VEC3");
    f.push("animations", {{"samplers", {{{"input", input}, {"output", output}}}},
                          {"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}}}}});
    const std::string message = import_error(f.write_gltf(dir.path(), "times.gltf"));
    EXPECT_TRUE(contains(message, "times not increasing at key 2")) << message;
    EXPECT_FALSE(contains(message, "2.25") || contains(message, "1.125")) << message;
  }
}

// ---- numbers that overflow together --------------------------------------------------------

TEST(GltfImportNodes, transforms_that_overflow_are_refused_naming_the_node) {
  TempDir dir;
  {
    GltfFile f;
    f.node({{"name", "huge"}, {"matrix", {1e308, 0, 0, 0, 0, 1e308, 0, 0, 0, 0, 1e308, 0, 0, 0, 0, 1}}});
    const std::string message = import_error(f.write_gltf(dir.path(), "matrix.gltf"));
    EXPECT_TRUE(contains(message, "nodes[0] ('huge'): ")) << message;
    EXPECT_TRUE(contains(message, "overflows")) << message;
  }
  {
    // Each scale is finite; their product is not: the deepest node is named.
    GltfFile f;
    f.node({{"name", "a"}, {"scale", {1e100, 1e100, 1e100}}, {"children", {1}}});
    f.node({{"name", "b"}, {"children", {2}}});
    f.node({{"name", "c"}, {"scale", {1e200, 1, 1}}});
    const std::string message = import_error(f.write_gltf(dir.path(), "chain.gltf"));
    EXPECT_TRUE(contains(message, "nodes[2] ('c'): its world matrix overflows")) << message;
  }
  {
    GltfFile f;
    f.node({{"name", "far"}, {"translation", {1e308, 0, 0}}, {"children", {1}}});
    f.node({{"name", "farther"}, {"translation", {1e308, 0, 0}}});
    const std::string message = import_error(f.write_gltf(dir.path(), "translation.gltf"));
    EXPECT_TRUE(contains(message, "nodes[1] ('farther'): its world matrix overflows")) << message;
  }
  {
    // Large but representable all the way down: imports.
    GltfFile f;
    f.node({{"name", "big"}, {"scale", {1e50, 1e50, 1e50}}, {"translation", {1e150, 0, 0}}, {"children", {1}}});
    f.node({{"name", "bigger"}, {"scale", {1e50, 1e50, 1e50}}});
    Imported s = import_ok(f.write_gltf(dir.path(), "large.gltf"));
    EXPECT_TRUE(s.world("bigger").allFinite());
  }
}

// ---- vertices without a weight -----------------------------------------------------------

TEST(GltfImportValidator, vertices_without_a_weight_follow_the_mesh_node_with_a_warning) {
  // Valid per the validator (weights summing to 1 is a SHOULD); all their
  // weights are zero (accessors without a buffer view).
  struct Case {
    const char* file;
    Vec3 expected;  // where every vertex (at the origin in the file) ends up: the mesh node's world position
  };
  for (const Case& c : {Case{"skin__ignored_local_transform.gltf", Vec3(1, 2, 3)}, Case{"skin__ignored_parent_transform.gltf", Vec3(1, 2, 3)}}) {
    SCOPED_TRACE(c.file);
    std::vector<std::string> warnings;
    GltfImportOptions options;
    options.warnings = &warnings;
    Imported s = import_ok(invalid_dir() / c.file, options);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_TRUE(contains(warnings[0], "meshes[0].primitives[0]: vertices 0, 1, 2 have no joint weight above zero")) << warnings[0];
    EXPECT_TRUE(contains(warnings[0], "follow the mesh's node 'node_")) << warnings[0];
    for (NodeId id : s.g().nodes()) {
      if (s.g().node(id)->type().name() != scene::kMeshType) continue;
      const auto& points = std::get<std::vector<Vec3>>(s.g().evaluate(id, scene::mesh_attr::kPoints));
      ASSERT_EQ(points.size(), 3u);
      for (const Vec3& p : points) EXPECT_TRUE(near(p, c.expected, 1e-12));
    }
  }
  // Without a warnings list the import still succeeds.
  EXPECT_TRUE(import_gltf(invalid_dir() / "skin__ignored_local_transform.gltf").is_ok());
}

TEST(GltfImportSkin, unweighted_vertices_follow_the_mesh_node_as_it_moves_and_weighted_ones_their_joints) {
  TempDir dir;
  GltfFile f = skinned_file();
  // Vertex 2 loses its weights.
  const float zero[4] = {0, 0, 0, 0};
  std::memcpy(f.bin.data() + f.doc["bufferViews"][2]["byteOffset"].get<std::size_t>() + 16 * 2, zero, 16);
  std::vector<std::string> warnings;
  GltfImportOptions options;
  options.warnings = &warnings;
  Imported s = import_ok(f.write_gltf(dir.path(), "unweighted.gltf"), options);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_TRUE(contains(warnings[0], "vertices 2 have no joint weight above zero")) << warnings[0];
  EXPECT_TRUE(contains(warnings[0], "'body'")) << warnings[0];
  const std::string mesh = "skinned";
  auto points = [&] { return std::get<std::vector<Vec3>>(s.g().evaluate(s.id(mesh), scene::mesh_attr::kPoints)); };
  EXPECT_TRUE(near(points()[2], Vec3(6, 5.5, 5), 1e-12)) << "body's translation (5, 5, 5) applied to (1, 0.5, 0)";
  EXPECT_TRUE(near(points()[0], Vec3(1, 0, 0), 1e-12)) << "vertex 0 stays on its joint";
  ASSERT_TRUE(s.g().set_value(Plug{s.id("body"), xf::kTranslate, -1}, Vec3(0, 0, 0)).is_ok());
  EXPECT_TRUE(near(points()[2], Vec3(1, 0.5, 0), 1e-12));
}

}  // namespace
}  // namespace rigel::io
