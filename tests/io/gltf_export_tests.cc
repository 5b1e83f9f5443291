// Tests of the glTF exporter (io/gltf_export.h). Every file written is read
// back with tinygltf directly, not with rigel's importer, and held to values
// computed by hand; world matrices are recomputed from the file's TRS with
// plain Eigen (no rigel maths). The round trips through rigel's importer
// come last.

#include "rigel/io/gltf_export.h"

#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "io_test_util.h"
#include "rigel/io/bvh.h"
#include "rigel/io/bvh_import.h"
#include "rigel/io/gltf_import.h"
#include "rigel/io/scene_file.h"
#include "rigel/math/transform.h"
#include "rigel/ops/anim/clips.h"
#include "rigel/ops/anim/nodes.h"
#include "rigel/ops/anim/track.h"
#include "rigel/ops/deform/nodes.h"
#include "rigel/ops/registry.h"
#include "rigel/scene/transform_types.h"

namespace rigel::io {
namespace {

using namespace rigel::io::testing;  // NOLINT: test helpers
namespace xf = scene::xform;
using graph::AttrIndex;

const double kS = std::sqrt(0.5);

// ---- reading glTF back with tinygltf ------------------------------------------

tinygltf::Model load_model(const fs::path& path) {
  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string err, warn;
  const bool ok = path.extension() == ".glb" ? loader.LoadBinaryFromFile(&model, &err, &warn, path.string())
                                             : loader.LoadASCIIFromFile(&model, &err, &warn, path.string());
  EXPECT_TRUE(ok) << "tinygltf should load " << path << ": " << err;
  EXPECT_TRUE(warn.empty()) << "tinygltf should not warn about " << path << ": " << warn;
  return model;
}

// Every number of an accessor, flattened, whatever its component type.
std::vector<double> accessor_values(const tinygltf::Model& model, int index) {
  std::vector<double> out;
  const tinygltf::Accessor& a = model.accessors.at(static_cast<std::size_t>(index));
  const tinygltf::BufferView& v = model.bufferViews.at(static_cast<std::size_t>(a.bufferView));
  const tinygltf::Buffer& b = model.buffers.at(static_cast<std::size_t>(v.buffer));
  const int components = tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(a.type));
  const int size = tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(a.componentType));
  const std::size_t stride = v.byteStride ? v.byteStride : static_cast<std::size_t>(components * size);
  const unsigned char* base = b.data.data() + v.byteOffset + a.byteOffset;
  for (std::size_t i = 0; i < a.count; ++i) {
    for (int c = 0; c < components; ++c) {
      const unsigned char* p = base + i * stride + static_cast<std::size_t>(c * size);
      switch (a.componentType) {
        case TINYGLTF_COMPONENT_TYPE_FLOAT: {
          float f;
          std::memcpy(&f, p, 4);
          out.push_back(f);
          break;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: out.push_back(*p); break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
          std::uint16_t s;
          std::memcpy(&s, p, 2);
          out.push_back(s);
          break;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
          std::uint32_t u;
          std::memcpy(&u, p, 4);
          out.push_back(u);
          break;
        }
        default: ADD_FAILURE() << "unexpected component type " << a.componentType;
      }
    }
  }
  return out;
}

int node_index(const tinygltf::Model& model, const std::string& name) {
  for (std::size_t i = 0; i < model.nodes.size(); ++i)
    if (model.nodes[i].name == name) return static_cast<int>(i);
  ADD_FAILURE() << "the file should have a node named " << name;
  return -1;
}

std::vector<double> or_default(const std::vector<double>& v, std::vector<double> fallback) { return v.empty() ? fallback : v; }

// Channel of an animation targeting (node, path), or nullptr.
const tinygltf::AnimationChannel* channel_find(const tinygltf::Animation& a, int node, const std::string& path) {
  for (const auto& c : a.channels)
    if (c.target_node == node && c.target_path == path) return &c;
  return nullptr;
}

void expect_values(const std::vector<double>& actual, const std::vector<double>& expected, double tolerance,
                   const std::string& what) {
  ASSERT_EQ(actual.size(), expected.size()) << what << ": number count";
  for (std::size_t i = 0; i < actual.size(); ++i)
    EXPECT_NEAR(actual[i], expected[i], tolerance) << what << "[" << i << "]";
}

// The local matrix of a glTF node (TRS or matrix), in plain Eigen.
Eigen::Matrix4d gltf_local(const std::vector<double>& t, const std::vector<double>& r, const std::vector<double>& s) {
  Eigen::Affine3d m = Eigen::Translation3d(t[0], t[1], t[2]) * Eigen::Quaterniond(r[3], r[0], r[1], r[2]).normalized() *
                      Eigen::Scaling(s[0], s[1], s[2]);
  return m.matrix();
}

// World matrices of every node of `model` with `animation`'s samples number
// `key` overriding the nodes' TRS (every channel must have that key).
std::vector<Eigen::Matrix4d> gltf_world_at_key(const tinygltf::Model& model, const tinygltf::Animation* animation,
                                               std::size_t key) {
  const std::size_t n = model.nodes.size();
  std::vector<std::vector<double>> t(n), r(n), s(n);
  std::vector<int> parent(n, -1);
  for (std::size_t i = 0; i < n; ++i) {
    const tinygltf::Node& node = model.nodes[i];
    EXPECT_TRUE(node.matrix.empty()) << node.name << " should be written as TRS";
    t[i] = or_default(node.translation, {0, 0, 0});
    r[i] = or_default(node.rotation, {0, 0, 0, 1});
    s[i] = or_default(node.scale, {1, 1, 1});
    for (int c : node.children) parent[static_cast<std::size_t>(c)] = static_cast<int>(i);
  }
  if (animation) {
    for (const auto& c : animation->channels) {
      const auto& sampler = animation->samplers[static_cast<std::size_t>(c.sampler)];
      const std::vector<double> values = accessor_values(model, sampler.output);
      const std::size_t width = c.target_path == "rotation" ? 4 : 3;
      std::vector<double> v(values.begin() + static_cast<std::ptrdiff_t>(key * width),
                            values.begin() + static_cast<std::ptrdiff_t>((key + 1) * width));
      auto& target = c.target_path == "translation" ? t : c.target_path == "rotation" ? r : s;
      target[static_cast<std::size_t>(c.target_node)] = v;
    }
  }
  std::vector<Eigen::Matrix4d> world(n);
  std::vector<bool> done(n, false);
  for (std::size_t pass = 0; pass < n; ++pass) {
    for (std::size_t i = 0; i < n; ++i) {
      if (done[i]) continue;
      const int p = parent[i];
      if (p >= 0 && !done[static_cast<std::size_t>(p)]) continue;
      const Eigen::Matrix4d local = gltf_local(t[i], r[i], s[i]);
      world[i] = p < 0 ? local : Eigen::Matrix4d(world[static_cast<std::size_t>(p)] * local);
      done[i] = true;
    }
  }
  return world;
}

// |a - b| within tolerance relative to the larger entry (at least 1).
::testing::AssertionResult matrices_near(const Eigen::Matrix4d& a, const Eigen::Matrix4d& b, double tolerance) {
  const double scale = std::max({1.0, a.cwiseAbs().maxCoeff(), b.cwiseAbs().maxCoeff()});
  const double diff = (a - b).cwiseAbs().maxCoeff();
  if (diff <= tolerance * scale) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "differ by " << diff << " (scale " << scale << ")\n" << a << "\nvs\n" << b;
}

Mat4 translation(double x, double y, double z) {
  Mat4 m = Mat4::Identity();
  m.block<3, 1>(0, 3) = Vec3(x, y, z);
  return m;
}

// ---- fixtures ------------------------------------------------------------------

std::unique_ptr<Scene> new_scene() { return std::make_unique<Scene>(ops::default_registry()); }

// A 3-joint chain (root, mid with a jointOrient, tip with scale) skinning a
// 4-point mesh with 2 influences per vertex, a linear translate track on
// root and a step quaternion track on mid. Everything is hand-checkable:
//   root: t (1,2,3) -> (1,4,3) over 1 s, rotation 90 deg about z
//   mid:  t (0,2,0), jointOrient 90 deg about z, keys I, Rx90, Rx180 at 0, 0.5, 1
//   tip:  t (0,1.5,0), scale 2
std::unique_ptr<Scene> chain_scene() {
  auto scene = new_scene();
  Builder b(*scene);
  const NodeId root = b.node(scene::kJointType, "root", 1);
  const NodeId mid = b.node(scene::kJointType, "mid", 2, root);
  const NodeId tip = b.node(scene::kJointType, "tip", 3, mid);
  const NodeId body = b.node(scene::kMeshType, "body", 4);
  const NodeId skin = b.node(ops::kSkinClusterType, "skin", 5);
  const NodeId root_t = b.node(ops::anim::kAnimCurveVec3Type, "root_t", 6);
  const NodeId mid_r = b.node(ops::anim::kAnimCurveQuatType, "mid_r", 7);

  b.set(root, "translate", Vec3(1, 2, 3));
  b.set(root, "rotateMode", std::int64_t{1});
  b.set(root, "rotateQuaternion", Quat(kS, 0, 0, kS));
  b.set(mid, "translate", Vec3(0, 2, 0));
  b.set(mid, "jointOrient", Vec3(0, 0, 90));
  b.set(mid, "rotateMode", std::int64_t{1});
  b.set(tip, "translate", Vec3(0, 1.5, 0));
  b.set(tip, "scale", Vec3(2, 2, 2));

  const std::vector<Vec3> points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  const std::vector<Vec3> normals(4, Vec3(0, 0, 1));
  b.set(body, "triangles", std::vector<std::int64_t>{0, 1, 2, 2, 1, 3});
  b.set(skin, "bindPoints", points);
  b.set(skin, "bindNormals", normals);
  b.set(skin, "bindPreMatrices", std::vector<Mat4>{translation(-1, -2, -3), translation(0, -4, 0), translation(0, -5.5, 0)});
  b.set(skin, "influenceOffsets", std::vector<std::int64_t>{0, 2, 4, 6, 7});
  b.set(skin, "influenceJoints", std::vector<std::int64_t>{0, 1, 1, 2, 2, 0, 0});
  b.set(skin, "influenceWeights", std::vector<double>{0.25, 0.75, 0.5, 0.5, 3.0, 1.0, 1.0});
  b.connect("root.worldMatrix", "skin.jointMatrices[0]");
  b.connect("mid.worldMatrix", "skin.jointMatrices[1]");
  b.connect("tip.worldMatrix", "skin.jointMatrices[2]");
  b.connect("skin.outPoints", "body.points");
  b.connect("skin.outNormals", "body.normals");

  b.set(root_t, "keyTimes", std::vector<double>{0, 1});
  b.set(root_t, "keyValues", std::vector<Vec3>{{1, 2, 3}, {1, 4, 3}});
  b.connect("root_t.output", "root.translate");
  b.set(mid_r, "keyTimes", std::vector<double>{0, 0.5, 1});
  b.set(mid_r, "keyValues", std::vector<Quat>{Quat::Identity(), Quat(kS, kS, 0, 0), Quat(0, 1, 0, 0)});
  b.set(mid_r, "interpolation", std::int64_t{static_cast<int>(ops::anim::Interpolation::kStep)});
  b.connect("mid_r.output", "mid.rotateQuaternion");
  return scene;
}

// ---- the chain: nodes, skin, direct animation -----------------------------------

class ChainExport : public ::testing::Test {
 protected:
  void SetUp() override {
    scene_ = chain_scene();
    path_ = dir_.path() / "chain.glb";
    const Status s = export_gltf(*scene_, path_, {}, &report_);
    ASSERT_TRUE(s.is_ok()) << s.message();
    EXPECT_VALID_GLTF(path_);
    model_ = load_model(path_);
  }
  TempDir dir_;
  std::unique_ptr<Scene> scene_;
  fs::path path_;
  GltfExportReport report_;
  tinygltf::Model model_;
};

TEST_F(ChainExport, nodes_names_hierarchy_and_trs) {
  ASSERT_EQ(model_.nodes.size(), 4u) << "one glTF node per transform node (root, mid, tip, body); curves and the "
                                        "skinCluster are not nodes";
  const auto& root = model_.nodes[0];
  const auto& mid = model_.nodes[1];
  const auto& tip = model_.nodes[2];
  const auto& body = model_.nodes[3];
  EXPECT_EQ(root.name, "root");
  EXPECT_EQ(mid.name, "mid");
  EXPECT_EQ(tip.name, "tip");
  EXPECT_EQ(body.name, "body");
  EXPECT_EQ(root.children, std::vector<int>{1});
  EXPECT_EQ(mid.children, std::vector<int>{2});
  EXPECT_TRUE(tip.children.empty());
  ASSERT_EQ(model_.scenes.size(), 1u);
  EXPECT_EQ(model_.scenes[0].nodes, (std::vector<int>{0, 3})) << "roots: the chain and the skinned mesh";

  expect_values(root.translation, {1, 2, 3}, 1e-15, "root.translation (the track's value at time 0)");
  expect_values(root.rotation, {0, 0, kS, kS}, 1e-15, "root.rotation (90 deg about z)");
  EXPECT_TRUE(root.scale.empty()) << "unit scale is left out";
  expect_values(mid.translation, {0, 2, 0}, 1e-15, "mid.translation");
  expect_values(mid.rotation, {0, 0, kS, kS}, 1e-15, "mid.rotation = jointOrient (z 90) * key 0 (identity)");
  expect_values(tip.translation, {0, 1.5, 0}, 1e-15, "tip.translation");
  EXPECT_TRUE(tip.rotation.empty());
  expect_values(tip.scale, {2, 2, 2}, 1e-15, "tip.scale");
  EXPECT_TRUE(body.translation.empty() && body.rotation.empty() && body.scale.empty() && body.matrix.empty())
      << "the skinned mesh sits at the world origin, as glTF draws skinned meshes";
  EXPECT_EQ(body.mesh, 0);
  EXPECT_EQ(body.skin, 0);
}

TEST_F(ChainExport, skin_joints_inverse_bind_matrices_and_weights) {
  ASSERT_EQ(model_.skins.size(), 1u);
  const auto& skin = model_.skins[0];
  EXPECT_EQ(skin.name, "skin");
  EXPECT_EQ(skin.joints, (std::vector<int>{0, 1, 2})) << "jointMatrices[i]'s source node, in index order";
  expect_values(accessor_values(model_, skin.inverseBindMatrices),
                {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -1, -2, -3, 1,  //
                 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -4, 0, 1,    //
                 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -5.5, 0, 1},
                0, "inverseBindMatrices (bindPreMatrices, column-major)");

  ASSERT_EQ(model_.meshes.size(), 1u);
  ASSERT_EQ(model_.meshes[0].primitives.size(), 1u);
  const auto& p = model_.meshes[0].primitives[0];
  EXPECT_EQ(p.mode, TINYGLTF_MODE_TRIANGLES);
  EXPECT_EQ(p.attributes.count("JOINTS_1"), 0u) << "no vertex has more than 4 influences";
  expect_values(accessor_values(model_, p.attributes.at("POSITION")), {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0}, 0,
                "POSITION = bindPoints");
  const auto& position = model_.accessors[static_cast<std::size_t>(p.attributes.at("POSITION"))];
  EXPECT_EQ(position.minValues, (std::vector<double>{0, 0, 0}));
  EXPECT_EQ(position.maxValues, (std::vector<double>{1, 1, 0}));
  expect_values(accessor_values(model_, p.attributes.at("NORMAL")), {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}, 0, "NORMAL");
  expect_values(accessor_values(model_, p.indices), {0, 1, 2, 2, 1, 3}, 0, "indices");
  EXPECT_EQ(model_.accessors[static_cast<std::size_t>(p.indices)].componentType, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
  EXPECT_EQ(model_.accessors[static_cast<std::size_t>(p.attributes.at("JOINTS_0"))].componentType,
            TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE)
      << "3 joints fit in bytes";
  // Sorted by weight (ties by joint), normalised, padded with zeros.
  expect_values(accessor_values(model_, p.attributes.at("JOINTS_0")), {1, 0, 0, 0, 1, 2, 0, 0, 2, 0, 0, 0, 0, 0, 0, 0}, 0,
                "JOINTS_0");
  expect_values(accessor_values(model_, p.attributes.at("WEIGHTS_0")),
                {0.75, 0.25, 0, 0, 0.5, 0.5, 0, 0, 0.75, 0.25, 0, 0, 1, 0, 0, 0}, 1e-7,
                "WEIGHTS_0 (vertex 2's 3 and 1 normalised to 0.75 and 0.25)");
}

TEST_F(ChainExport, tracks_are_written_directly_with_their_keys) {
  EXPECT_FALSE(report_.baked) << "linear and step tracks on translate and rotateQuaternion need no baking: "
                              << report_.bake_reason;
  ASSERT_EQ(model_.animations.size(), 1u);
  const auto& a = model_.animations[0];
  EXPECT_EQ(a.name, "animation");
  ASSERT_EQ(a.channels.size(), 2u);

  const auto* t = channel_find(a, 0, "translation");
  ASSERT_NE(t, nullptr) << "root's translation channel";
  const auto& ts = a.samplers[static_cast<std::size_t>(t->sampler)];
  EXPECT_EQ(ts.interpolation, "LINEAR");
  expect_values(accessor_values(model_, ts.input), {0, 1}, 0, "root translation times");
  expect_values(accessor_values(model_, ts.output), {1, 2, 3, 1, 4, 3}, 0, "root translation values");
  EXPECT_EQ(model_.accessors[static_cast<std::size_t>(ts.input)].minValues, std::vector<double>{0});
  EXPECT_EQ(model_.accessors[static_cast<std::size_t>(ts.input)].maxValues, std::vector<double>{1});

  const auto* r = channel_find(a, 1, "rotation");
  ASSERT_NE(r, nullptr) << "mid's rotation channel";
  const auto& rs = a.samplers[static_cast<std::size_t>(r->sampler)];
  EXPECT_EQ(rs.interpolation, "STEP");
  expect_values(accessor_values(model_, rs.input), {0, 0.5, 1}, 0, "mid rotation times");
  // jointOrient (z 90) folded in: Rz90 * I, Rz90 * Rx90 (120 deg about (1,1,1)), Rz90 * Rx180 (180 about (1,1,0)).
  expect_values(accessor_values(model_, rs.output), {0, 0, kS, kS, 0.5, 0.5, 0.5, 0.5, kS, kS, 0, 0}, 1e-7,
                "mid rotation values");
}

TEST_F(ChainExport, world_matrices_from_the_file_match_the_scene_at_every_key) {
  const auto& a = model_.animations.at(0);
  // Keys: both channels' samplers have a key at 0 and 1; translation is
  // linear, so at 0.5 it is half way. Check 0 and 1 from keys directly.
  for (double time : {0.0, 1.0}) {
    scene_->graph().set_time(time);
    // The translation sampler has keys {0, 1}, the rotation sampler {0, 0.5, 1}.
    std::vector<Eigen::Matrix4d> world;
    {
      std::vector<double> tr = accessor_values(model_, a.samplers[static_cast<std::size_t>(channel_find(a, 0, "translation")->sampler)].output);
      std::vector<double> rot = accessor_values(model_, a.samplers[static_cast<std::size_t>(channel_find(a, 1, "rotation")->sampler)].output);
      const std::size_t tk = time == 0.0 ? 0 : 1, rk = time == 0.0 ? 0 : 2;
      const Eigen::Matrix4d root = gltf_local({tr[tk * 3], tr[tk * 3 + 1], tr[tk * 3 + 2]}, model_.nodes[0].rotation, {1, 1, 1});
      const Eigen::Matrix4d mid = gltf_local(model_.nodes[1].translation,
                                             {rot[rk * 4], rot[rk * 4 + 1], rot[rk * 4 + 2], rot[rk * 4 + 3]}, {1, 1, 1});
      const Eigen::Matrix4d tip = gltf_local(model_.nodes[2].translation, {0, 0, 0, 1}, model_.nodes[2].scale);
      world = {root, root * mid, root * mid * tip};
    }
    const char* names[] = {"root", "mid", "tip"};
    for (int j = 0; j < 3; ++j) {
      EXPECT_TRUE(matrices_near(world[static_cast<std::size_t>(j)],
                                scene_->world_matrix(scene_->graph().find(names[j])), 1e-7))
          << names[j] << " at " << time << " s";
    }
  }
}

TEST_F(ChainExport, gltf_and_glb_both_load_and_hold_the_same_model) {
  const fs::path gltf_path = dir_.path() / "chain.gltf";
  ASSERT_TRUE(export_gltf(*scene_, gltf_path).is_ok());
  EXPECT_VALID_GLTF(gltf_path);
  const std::string text = read_text(gltf_path);
  const std::string binary = read_text(path_);
  EXPECT_EQ(text.substr(0, 1), "{") << ".gltf is JSON";
  EXPECT_NE(text.find("data:application/octet-stream;base64,"), std::string::npos) << "with the buffer embedded";
  EXPECT_EQ(binary.substr(0, 4), "glTF") << ".glb starts with the binary magic";
  tinygltf::Model json = load_model(gltf_path);
  ASSERT_EQ(json.nodes.size(), model_.nodes.size());
  ASSERT_EQ(json.accessors.size(), model_.accessors.size());
  for (std::size_t i = 0; i < json.accessors.size(); ++i)
    EXPECT_EQ(accessor_values(json, static_cast<int>(i)), accessor_values(model_, static_cast<int>(i))) << "accessor " << i;
  EXPECT_TRUE(fs::exists(dir_.path() / "chain.gltf") && dir_.entries().size() == 2u)
      << "no .bin file beside the .gltf, no temporary file left";
}

// ---- more influences, cubic splines, morph targets -------------------------------

TEST(GltfExport, a_vertex_with_six_influences_gets_two_joint_sets) {
  auto scene = new_scene();
  Builder b(*scene);
  // Names built with append: GCC 12 warns falsely (-Wrestrict) on "j" + ...
  auto joint_name = [](int j) { return std::string("j").append(std::to_string(j)); };
  for (int j = 0; j < 6; ++j) b.node(scene::kJointType, joint_name(j), 10 + j);
  const NodeId mesh = b.node(scene::kMeshType, "m", 1);
  const NodeId skin = b.node(ops::kSkinClusterType, "sc", 2);
  for (int j = 0; j < 6; ++j)
    b.connect(joint_name(j).append(".worldMatrix"), std::string("sc.jointMatrices[").append(std::to_string(j)).append("]"));
  b.set(skin, "bindPoints", std::vector<Vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  b.set(skin, "influenceOffsets", std::vector<std::int64_t>{0, 6, 7, 8});
  b.set(skin, "influenceJoints", std::vector<std::int64_t>{0, 1, 2, 3, 4, 5, 3, 4});
  b.set(skin, "influenceWeights", std::vector<double>{1, 2, 3, 4, 5, 6, 1, 1});
  b.set(mesh, "triangles", std::vector<std::int64_t>{0, 1, 2});
  b.connect("sc.outPoints", "m.points");
  TempDir dir;
  GltfExportReport report;
  ASSERT_TRUE(export_gltf(*scene, dir.path() / "six.gltf", {}, &report).is_ok());
  EXPECT_VALID_GLTF(dir.path() / "six.gltf");
  tinygltf::Model model = load_model(dir.path() / "six.gltf");
  // The six joints are six roots; glTF wants a skin's joints under one root.
  ASSERT_EQ(model.nodes.size(), 8u) << "six joints, the mesh, and the added common root";
  EXPECT_EQ(model.nodes[7].name, "skeleton_root");
  EXPECT_EQ(model.nodes[7].children, (std::vector<int>{0, 1, 2, 3, 4, 5}));
  EXPECT_TRUE(model.nodes[7].translation.empty() && model.nodes[7].rotation.empty() && model.nodes[7].matrix.empty());
  EXPECT_EQ(model.scenes.at(0).nodes, (std::vector<int>{6, 7})) << "roots: the mesh and the group";
  EXPECT_EQ(report.notes.size(), 1u) << "the added node is reported";
  const auto& p = model.meshes.at(0).primitives.at(0);
  ASSERT_EQ(p.attributes.count("JOINTS_1"), 1u) << "six influences need a second set";
  ASSERT_EQ(p.attributes.count("WEIGHTS_1"), 1u);
  EXPECT_EQ(p.attributes.count("JOINTS_2"), 0u);
  const double w = 1.0 / 21.0;  // the weights 1..6 sum to 21
  expect_values(accessor_values(model, p.attributes.at("JOINTS_0")), {5, 4, 3, 2, 3, 0, 0, 0, 4, 0, 0, 0}, 0, "JOINTS_0");
  expect_values(accessor_values(model, p.attributes.at("WEIGHTS_0")), {6 * w, 5 * w, 4 * w, 3 * w, 1, 0, 0, 0, 1, 0, 0, 0},
                1e-7, "WEIGHTS_0");
  expect_values(accessor_values(model, p.attributes.at("JOINTS_1")), {1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0}, 0, "JOINTS_1");
  expect_values(accessor_values(model, p.attributes.at("WEIGHTS_1")), {2 * w, 1 * w, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0}, 1e-7,
                "WEIGHTS_1");
}

TEST(GltfExport, cubic_spline_tracks_keep_their_tangents) {
  auto scene = new_scene();
  Builder b(*scene);
  const NodeId j = b.node(scene::kJointType, "j", 1);
  const NodeId curve = b.node(ops::anim::kAnimCurveVec3Type, "j_scale", 2);
  b.set(curve, "keyTimes", std::vector<double>{0, 1});
  b.set(curve, "keyValues", std::vector<Vec3>{{1, 1, 1}, {2, 2, 2}});
  b.set(curve, "inTangents", std::vector<Vec3>{{0, 0, 0}, {3, 3, 3}});
  b.set(curve, "outTangents", std::vector<Vec3>{{1, 1, 1}, {0, 0, 0}});
  b.set(curve, "interpolation", std::int64_t{static_cast<int>(ops::anim::Interpolation::kCubicSpline)});
  b.connect("j_scale.output", "j.scale");
  TempDir dir;
  GltfExportReport report;
  ASSERT_TRUE(export_gltf(*scene, dir.path() / "cubic.glb", {}, &report).is_ok());
  EXPECT_VALID_GLTF(dir.path() / "cubic.glb");
  EXPECT_FALSE(report.baked);
  tinygltf::Model model = load_model(dir.path() / "cubic.glb");
  const auto& a = model.animations.at(0);
  ASSERT_EQ(a.channels.size(), 1u);
  const auto& s = a.samplers.at(0);
  EXPECT_EQ(a.channels[0].target_path, "scale");
  EXPECT_EQ(s.interpolation, "CUBICSPLINE");
  expect_values(accessor_values(model, s.output), {0, 0, 0, 1, 1, 1, 1, 1, 1, 3, 3, 3, 2, 2, 2, 0, 0, 0}, 0,
                "in-tangent, value, out-tangent per key");
  // glTF's Hermite at t = 0.5 (spec Appendix C): 0.5 v0 + 0.125 b0 + 0.5 v1 - 0.125 a1 = 1.25.
  scene->graph().set_time(0.5);
  const Vec3 scale = std::get<Vec3>(scene->graph().evaluate(j, xf::kScale));
  EXPECT_NEAR(scale.x(), 1.25, 1e-12) << "the scene plays the same spline the file describes";
}

TEST(GltfExport, blend_shapes_become_morph_targets_with_a_weights_channel) {
  auto scene = new_scene();
  Builder b(*scene);
  const NodeId face = b.node(scene::kMeshType, "face", 1);
  const NodeId bs = b.node(ops::kBlendShapeType, "bs", 2);
  const NodeId w1 = b.node(ops::anim::kAnimCurveType, "w1", 3);
  b.set(bs, "basePoints", std::vector<Vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  // Target 0 dense (3 deltas), target 1 sparse (one delta, on vertex 2).
  b.set(bs, "targetDeltas", std::vector<Vec3>{{0, 0, 1}, {0, 0, 2}, {0, 0, 3}, {5, 0, 0}});
  b.set(bs, "targetOffsets", std::vector<std::int64_t>{0, 3, 4});
  b.set(bs, "targetIndices", std::vector<std::int64_t>{0, 1, 2, 2});
  b.set(bs, "weights", std::vector<double>{0.5, 0.0});
  b.set(face, "triangles", std::vector<std::int64_t>{0, 1, 2});
  b.connect("bs.outPoints", "face.points");
  const auto linear = static_cast<std::int64_t>(ops::anim::TangentType::kLinear);
  b.set(w1, "keyTimes", std::vector<double>{0, 1});
  b.set(w1, "keyValues", std::vector<double>{0, 1});
  b.set(w1, "inTangentType", std::vector<std::int64_t>{linear, linear});
  b.set(w1, "outTangentType", std::vector<std::int64_t>{linear, linear});
  b.connect("w1.output", "bs.weights[1]");

  TempDir dir;
  GltfExportReport report;
  ASSERT_TRUE(export_gltf(*scene, dir.path() / "face.glb", {}, &report).is_ok());
  EXPECT_VALID_GLTF(dir.path() / "face.glb");
  EXPECT_FALSE(report.baked) << report.bake_reason;
  tinygltf::Model model = load_model(dir.path() / "face.glb");
  const auto& mesh = model.meshes.at(0);
  EXPECT_EQ(mesh.weights, (std::vector<double>{0.5, 0.0})) << "default weights: the blendShape's at the export time";
  const auto& p = mesh.primitives.at(0);
  expect_values(accessor_values(model, p.attributes.at("POSITION")), {0, 0, 0, 1, 0, 0, 0, 1, 0}, 0, "basePoints");
  ASSERT_EQ(p.targets.size(), 2u);
  expect_values(accessor_values(model, p.targets[0].at("POSITION")), {0, 0, 1, 0, 0, 2, 0, 0, 3}, 0, "target 0");
  expect_values(accessor_values(model, p.targets[1].at("POSITION")), {0, 0, 0, 0, 0, 0, 5, 0, 0}, 0,
                "target 1, made dense");
  const auto& a = model.animations.at(0);
  ASSERT_EQ(a.channels.size(), 1u);
  EXPECT_EQ(a.channels[0].target_path, "weights");
  EXPECT_EQ(a.channels[0].target_node, node_index(model, "face"));
  const auto& s = a.samplers.at(0);
  EXPECT_EQ(s.interpolation, "LINEAR");
  expect_values(accessor_values(model, s.input), {0, 1}, 0, "the curve's key times (linear tangents: no more needed)");
  expect_values(accessor_values(model, s.output), {0.5, 0, 0.5, 1}, 0, "per key: target 0 (constant), target 1");

  // With Maya's default (auto) tangents the curve bends between keys: every
  // frame in between is sampled (24 fps: 25 samples over 1 s).
  b.set(w1, "inTangentType", std::vector<std::int64_t>{});
  b.set(w1, "outTangentType", std::vector<std::int64_t>{});
  b.set(w1, "keyValues", std::vector<double>{0, 1});
  ASSERT_TRUE(export_gltf(*scene, dir.path() / "face_auto.glb").is_ok());
  EXPECT_VALID_GLTF(dir.path() / "face_auto.glb");
  tinygltf::Model curved = load_model(dir.path() / "face_auto.glb");
  const auto& cs = curved.animations.at(0).samplers.at(0);
  const std::vector<double> times = accessor_values(curved, cs.input);
  const std::vector<double> values = accessor_values(curved, cs.output);
  ASSERT_EQ(times.size(), 25u);
  for (std::size_t k = 0; k < times.size(); ++k) {
    scene->graph().set_time(times[k]);
    const double expected = std::get<double>(scene->graph().evaluate(w1, ops::anim::curve_attr::kOutput));
    EXPECT_NEAR(values[k * 2 + 1], expected, 1e-7) << "sample " << k;
  }

  // Step tangents (what the importer makes of glTF STEP keys) stay STEP.
  const auto step = static_cast<std::int64_t>(ops::anim::TangentType::kStep);
  b.set(w1, "outTangentType", std::vector<std::int64_t>{step, step});
  ASSERT_TRUE(export_gltf(*scene, dir.path() / "face_step.glb").is_ok());
  EXPECT_VALID_GLTF(dir.path() / "face_step.glb");
  tinygltf::Model stepped = load_model(dir.path() / "face_step.glb");
  const auto& ss = stepped.animations.at(0).samplers.at(0);
  EXPECT_EQ(ss.interpolation, "STEP");
  expect_values(accessor_values(stepped, ss.input), {0, 1}, 0, "step keys need no frames in between");
  expect_values(accessor_values(stepped, ss.output), {0.5, 0, 0.5, 1}, 0, "step values");
}

// ---- baking ----------------------------------------------------------------------

// The BVH fixture cut to its first `frames` rows, imported.
std::unique_ptr<Scene> bvh_scene(std::uint32_t frames) {
  Result<BvhFile> file = load_bvh((source_dir() / "tests" / "data" / "bvh" / "cmu_131_01.bvh").string());
  EXPECT_TRUE(file.is_ok()) << file.status().message();
  if (!file) return nullptr;
  file->frame_count = frames;
  file->motion.resize(std::size_t{frames} * file->channel_count);
  Result<std::unique_ptr<Scene>> scene = import_bvh(*file);
  EXPECT_TRUE(scene.is_ok()) << scene.status().message();
  return scene ? std::move(*scene) : nullptr;
}

TEST(GltfExport, blend_shape_target_names_are_written_as_mesh_extras_and_read_back) {
  auto scene = new_scene();
  Builder b(*scene);
  b.node(scene::kMeshType, "face", 1);
  const NodeId bs = b.node(ops::kBlendShapeType, "bs", 2);
  b.set(bs, "basePoints", std::vector<Vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  b.set(bs, "targetDeltas", std::vector<Vec3>{{0, 0, 1}, {5, 0, 0}});
  b.set(bs, "targetOffsets", std::vector<std::int64_t>{0, 1, 2});
  b.set(bs, "targetIndices", std::vector<std::int64_t>{0, 2});
  b.set(bs, "targetNames", std::vector<std::string>{"up", "side"});
  b.set(scene->graph().find("face"), "triangles", std::vector<std::int64_t>{0, 1, 2});
  b.connect("bs.outPoints", "face.points");
  TempDir dir;
  ASSERT_TRUE(export_gltf(*scene, dir.path() / "face.glb").is_ok());
  EXPECT_VALID_GLTF(dir.path() / "face.glb");
  tinygltf::Model model = load_model(dir.path() / "face.glb");
  const tinygltf::Value& extras = model.meshes.at(0).extras;
  ASSERT_TRUE(extras.IsObject() && extras.Has("targetNames")) << "the common convention for morph target names";
  const tinygltf::Value& names = extras.Get("targetNames");
  ASSERT_TRUE(names.IsArray());
  ASSERT_EQ(names.ArrayLen(), 2u);
  EXPECT_EQ(names.Get(0).Get<std::string>(), "up");
  EXPECT_EQ(names.Get(1).Get<std::string>(), "side");

  Result<std::unique_ptr<Scene>> back = import_gltf(dir.path() / "face.glb");
  ASSERT_TRUE(back.is_ok()) << back.status().message();
  Graph& g = (*back)->graph();
  NodeId shape;
  for (NodeId id : g.nodes())
    if (g.node(id)->type().name() == ops::kBlendShapeType) shape = id;
  ASSERT_TRUE(shape.is_valid());
  EXPECT_EQ(std::get<std::vector<std::string>>(g.evaluate(shape, ops::blend_shape_attr::kTargetNames)),
            (std::vector<std::string>{"up", "side"}));

  // Unnamed targets write no extras.
  b.set(bs, "targetNames", std::vector<std::string>{});
  ASSERT_TRUE(export_gltf(*scene, dir.path() / "plain.glb").is_ok());
  EXPECT_FALSE(load_model(dir.path() / "plain.glb").meshes.at(0).extras.Has("targetNames"));
}

TEST(GltfExport, bvh_euler_tracks_bake_and_world_matrices_match_the_scene) {
  auto scene = bvh_scene(5);
  ASSERT_TRUE(scene);
  TempDir dir;
  GltfExportReport report;
  std::vector<double> progress;
  GltfExportOptions options;
  options.progress = [&](double f) { progress.push_back(f); };
  const Status s = export_gltf(*scene, dir.path() / "walk.glb", options, &report);
  ASSERT_TRUE(s.is_ok()) << s.message();
  EXPECT_TRUE(report.baked) << "Euler rotate tracks cannot be written as glTF channels";
  EXPECT_NE(report.bake_reason.find("Euler"), std::string::npos) << report.bake_reason;
  EXPECT_EQ(report.first_frame, 0.0);
  EXPECT_EQ(report.last_frame, 4.0) << "the keys' range: rows 0..4";
  ASSERT_EQ(progress.size(), 5u) << "one progress call per baked frame";
  EXPECT_EQ(progress.back(), 1.0);
  EXPECT_DOUBLE_EQ(scene->graph().time(), 0.0) << "baking puts the time back";

  tinygltf::Model model = load_model(dir.path() / "walk.glb");
  ASSERT_EQ(model.animations.size(), 1u);
  const auto& a = model.animations[0];
  for (const auto& c : a.channels) {
    const auto& sampler = a.samplers[static_cast<std::size_t>(c.sampler)];
    EXPECT_EQ(sampler.interpolation, "LINEAR");
    expect_values(accessor_values(model, sampler.input), {0, 1 / 120.0, 2 / 120.0, 3 / 120.0, 4 / 120.0}, 1e-8,
                  "times of " + model.nodes[static_cast<std::size_t>(c.target_node)].name);
  }
  EXPECT_EQ(channel_find(a, node_index(model, "LeftToe_end"), "translation"), nullptr)
      << "an end site never moves: no channel for its constant translation";
  ASSERT_EQ(model.nodes.size(), scene->hierarchy().size());
  for (std::size_t f = 0; f < 5; ++f) {
    scene->set_frame(static_cast<double>(f));
    const std::vector<Eigen::Matrix4d> world = gltf_world_at_key(model, &a, f);
    for (std::size_t i = 0; i < model.nodes.size(); ++i) {
      const NodeId id = scene->graph().find(model.nodes[i].name);
      EXPECT_TRUE(matrices_near(world[i], scene->world_matrix(id), 1e-6)) << model.nodes[i].name << " at frame " << f;
    }
  }
}

TEST(GltfExport, explicit_frames_bake_that_range) {
  auto scene = bvh_scene(5);
  ASSERT_TRUE(scene);
  TempDir dir;
  GltfExportOptions options;
  options.frames = std::pair{1.0, 3.0};
  GltfExportReport report;
  ASSERT_TRUE(export_gltf(*scene, dir.path() / "walk.gltf", options, &report).is_ok());
  EXPECT_VALID_GLTF(dir.path() / "walk.gltf");
  EXPECT_TRUE(report.baked);
  EXPECT_NE(report.bake_reason.find("requested"), std::string::npos) << report.bake_reason;
  tinygltf::Model model = load_model(dir.path() / "walk.gltf");
  const auto& a = model.animations.at(0);
  ASSERT_FALSE(a.channels.empty());
  expect_values(accessor_values(model, a.samplers[0].input), {1 / 120.0, 2 / 120.0, 3 / 120.0}, 1e-8, "frames 1..3 (32-bit times)");
}

TEST(GltfExport, requested_bake_of_direct_tracks_samples_every_frame) {
  auto scene = chain_scene();
  TempDir dir;
  GltfExportOptions options;
  options.bake = true;
  GltfExportReport report;
  ASSERT_TRUE(export_gltf(*scene, dir.path() / "baked.glb", options, &report).is_ok());
  EXPECT_VALID_GLTF(dir.path() / "baked.glb");
  EXPECT_TRUE(report.baked);
  tinygltf::Model model = load_model(dir.path() / "baked.glb");
  const auto& a = model.animations.at(0);
  EXPECT_EQ(a.channels.size(), 2u) << "only root's translation and mid's rotation change";
  const auto* t = channel_find(a, 0, "translation");
  ASSERT_NE(t, nullptr);
  const std::vector<double> times = accessor_values(model, a.samplers[static_cast<std::size_t>(t->sampler)].input);
  const std::vector<double> values = accessor_values(model, a.samplers[static_cast<std::size_t>(t->sampler)].output);
  ASSERT_EQ(times.size(), 25u) << "frames 0..24 at 24 fps: the keys' range";
  EXPECT_NEAR(values[12 * 3 + 1], 3.0, 1e-6) << "root's y half way at frame 12";
}

// A bake samples the union of the frames and the keys' own times: a key
// between two frames (glTF clips keep seconds) keeps its value.
TEST(GltfExport, baking_samples_every_key_between_frames_too) {
  auto scene = new_scene();
  Builder b(*scene);
  b.node(scene::kJointType, "j", 1);
  const NodeId curve = b.node(ops::anim::kAnimCurveVec3Type, "j_t", 2);
  const NodeId spin = b.node(ops::anim::kAnimCurveVec3Type, "j_r", 3);
  // Keys on no frame (24 fps), one a hair after frame 1, one on frame 12.
  const std::vector<double> key_times = {0.0, 0.02, 1.0 / 24 + 1e-6, 0.1, 0.5};
  const std::vector<Vec3> key_values = {{0, 0, 0}, {0, 1, 0}, {0, -0.5, 0}, {0, 0.25, 0}, {0, 2, 0}};
  b.set(curve, "keyTimes", key_times);
  b.set(curve, "keyValues", key_values);
  b.connect("j_t.output", "j.translate");
  b.set(spin, "keyTimes", std::vector<double>{0.0, 0.03, 0.5});  // Euler angles: the export bakes by itself
  b.set(spin, "keyValues", std::vector<Vec3>{{0, 0, 0}, {0, 0, 40}, {0, 0, 0}});
  b.connect("j_r.output", "j.rotate");
  for (const bool requested : {false, true}) {
    SCOPED_TRACE(requested ? "--frames 0:12" : "automatic bake");
    TempDir dir;
    GltfExportOptions options;
    if (requested) options.frames = std::pair{0.0, 12.0};
    GltfExportReport report;
    ASSERT_TRUE(export_gltf(*scene, dir.path() / "keys.glb", options, &report).is_ok());
    EXPECT_VALID_GLTF(dir.path() / "keys.glb");
    ASSERT_TRUE(report.baked);
    tinygltf::Model model = load_model(dir.path() / "keys.glb");
    const auto& a = model.animations.at(0);
    const auto* t = channel_find(a, 0, "translation");
    ASSERT_NE(t, nullptr);
    const std::vector<double> times = accessor_values(model, a.samplers[static_cast<std::size_t>(t->sampler)].input);
    const std::vector<double> values = accessor_values(model, a.samplers[static_cast<std::size_t>(t->sampler)].output);
    for (std::size_t k = 0; k < key_times.size(); ++k) {
      auto at = std::find_if(times.begin(), times.end(), [&](double x) { return std::abs(x - key_times[k]) < 1e-7; });
      ASSERT_NE(at, times.end()) << "a sample at key " << k << " (" << key_times[k] << " s)";
      EXPECT_NEAR(values[3 * static_cast<std::size_t>(at - times.begin()) + 1], key_values[k].y(), 1e-6) << "key " << k;
    }
    EXPECT_NEAR(*std::max_element(times.begin(), times.end()), 0.5, 1e-7);
    for (int f = 0; f <= 12; ++f)
      EXPECT_NE(std::find_if(times.begin(), times.end(), [&](double x) { return std::abs(x - f / 24.0) < 1e-7; }), times.end())
          << "and every frame, " << f;
    EXPECT_TRUE(std::is_sorted(times.begin(), times.end()) &&
                std::adjacent_find(times.begin(), times.end(), [](double x, double y) { return !(static_cast<float>(x) < static_cast<float>(y)); }) == times.end())
        << "32-bit times increase";
    const auto* r = channel_find(a, 0, "rotation");
    ASSERT_NE(r, nullptr);
    const std::vector<double> rt = accessor_values(model, a.samplers[static_cast<std::size_t>(r->sampler)].input);
    const std::vector<double> rv = accessor_values(model, a.samplers[static_cast<std::size_t>(r->sampler)].output);
    auto at = std::find_if(rt.begin(), rt.end(), [](double x) { return std::abs(x - 0.03) < 1e-7; });
    ASSERT_NE(at, rt.end());
    const std::size_t k = static_cast<std::size_t>(at - rt.begin());
    EXPECT_NEAR(std::abs(rv[4 * k + 2]), std::sin(math::to_radians(20.0)), 1e-6) << "40 degrees about z at the key";
  }
}

// ---- clips ----------------------------------------------------------------------

// tests/data/scenes/two_clips.rigel (hip translating in clips "walk", 0..1 s,
// and "jump", 0..2 s) plus a rotation keyed in "walk" only, resting at 90
// degrees about z.
std::unique_ptr<Scene> two_clips() {
  Result<std::unique_ptr<Scene>> scene = load_scene(scenes_dir() / "two_clips.rigel");
  EXPECT_TRUE(scene.is_ok()) << scene.status().message();
  if (!scene) return nullptr;
  Scene& s = **scene;
  Builder b(s);
  const NodeId hip = s.graph().find("hip");
  const NodeId rotate = b.node(ops::anim::kAnimCurveQuatType, "hip_rotate", 50);
  b.set(hip, "rotateMode", std::int64_t{1});
  b.set(rotate, "keyTimes", std::vector<double>{0, 1});
  b.set(rotate, "keyValues", std::vector<Quat>{Quat::Identity(), Quat(kS, kS, 0, 0)});
  b.set(rotate, "clipOffsets", std::vector<std::int64_t>{0, 2, 2});
  b.set(rotate, "restValue", Quat(kS, 0, 0, kS));
  b.connect("clips.activeClip", "hip_rotate.clip");
  b.connect("hip_rotate.output", "hip.rotateQuaternion");
  s.graph().clear_history();
  return std::move(*scene);
}

TEST(GltfExport, every_clip_becomes_an_animation_with_its_own_keys) {
  auto scene = two_clips();
  ASSERT_TRUE(scene);
  TempDir dir;
  GltfExportReport report;
  ASSERT_TRUE(export_gltf(*scene, dir.path() / "clips.glb", {}, &report).is_ok());
  EXPECT_VALID_GLTF(dir.path() / "clips.glb");
  EXPECT_FALSE(report.baked) << report.bake_reason;
  tinygltf::Model model = load_model(dir.path() / "clips.glb");
  const auto& hip = model.nodes.at(0);
  EXPECT_TRUE(hip.translation.empty()) << "the rest value (restValue 0), not walk's pose at time 0";
  expect_values(hip.rotation, {0, 0, kS, kS}, 1e-15, "hip's rotation at rest: hip_rotate.restValue");
  ASSERT_EQ(model.animations.size(), 2u);
  const auto& walk = model.animations[0];
  const auto& jump = model.animations[1];
  EXPECT_EQ(walk.name, "walk");
  EXPECT_EQ(jump.name, "jump");
  ASSERT_EQ(walk.channels.size(), 2u) << "walk moves and turns the hip";
  const auto* wt = channel_find(walk, 0, "translation");
  ASSERT_NE(wt, nullptr);
  expect_values(accessor_values(model, walk.samplers[static_cast<std::size_t>(wt->sampler)].input), {0, 1}, 0, "walk times");
  expect_values(accessor_values(model, walk.samplers[static_cast<std::size_t>(wt->sampler)].output), {0, 0, 0, 2, 0, 0}, 0,
                "walk translation");
  const auto* wr = channel_find(walk, 0, "rotation");
  ASSERT_NE(wr, nullptr);
  expect_values(accessor_values(model, walk.samplers[static_cast<std::size_t>(wr->sampler)].output),
                {0, 0, 0, 1, kS, 0, 0, kS}, 1e-7, "walk rotation");
  ASSERT_EQ(jump.channels.size(), 1u) << "jump has no rotation keys: the hip rests, which the node's rotation says";
  expect_values(accessor_values(model, jump.samplers[0].input), {0, 2}, 0, "jump times");
  expect_values(accessor_values(model, jump.samplers[0].output), {10, 0, 0, 14, 0, 0}, 0, "jump translation");
}

TEST(GltfExport, baking_clips_plays_each_over_its_range_and_restores_the_scene) {
  auto scene = two_clips();
  ASSERT_TRUE(scene);
  Graph& g = scene->graph();
  g.set_time(0.25);
  TempDir dir;
  GltfExportOptions options;
  options.bake = true;
  GltfExportReport report;
  ASSERT_TRUE(export_gltf(*scene, dir.path() / "clips.glb", options, &report).is_ok());
  EXPECT_VALID_GLTF(dir.path() / "clips.glb");
  EXPECT_TRUE(report.baked);
  EXPECT_EQ(g.time(), 0.25) << "the time is put back";
  EXPECT_EQ(std::get<std::int64_t>(g.node(g.find("clips"))->value(ops::anim::clips_attr::kActive)), 0)
      << "the active clip is put back";
  EXPECT_FALSE(g.can_undo()) << "switching clips to bake leaves no undo step";
  tinygltf::Model model = load_model(dir.path() / "clips.glb");
  ASSERT_EQ(model.animations.size(), 2u);
  const auto& walk = model.animations[0];
  const auto& jump = model.animations[1];
  EXPECT_EQ(walk.name, "walk");
  EXPECT_EQ(jump.name, "jump");
  EXPECT_EQ(walk.channels.size(), 2u);
  ASSERT_EQ(jump.channels.size(), 1u) << "the rotation rests during jump";
  const std::vector<double> times = accessor_values(model, jump.samplers[0].input);
  const std::vector<double> values = accessor_values(model, jump.samplers[0].output);
  ASSERT_EQ(times.size(), 49u) << "jump: frames 0..48 at 24 fps";
  EXPECT_NEAR(values[24 * 3], 12.0, 1e-6) << "half way through jump";
  EXPECT_NEAR(values[48 * 3], 14.0, 1e-6);
  EXPECT_EQ(accessor_values(model, walk.samplers[0].input).size(), 25u) << "walk: frames 0..24";
}

// ---- errors and the atomic write -------------------------------------------------

TEST(GltfExport, a_failed_export_leaves_an_existing_file_untouched) {
  auto scene = chain_scene();
  TempDir dir;
  const fs::path out = dir.path() / "out.glb";
  write_text(out, "keep me");
  Builder b(*scene);
  b.set(scene->graph().find("body"), "triangles", std::vector<std::int64_t>{0, 1, 9});
  const Status s = export_gltf(*scene, out);
  ASSERT_FALSE(s.is_ok());
  EXPECT_NE(s.message().find("body.triangles[2]"), std::string::npos) << "names the node and attribute: " << s.message();
  EXPECT_EQ(read_text(out), "keep me");
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"out.glb"}) << "no temporary file left";

  const Status missing = export_gltf(*scene, dir.path() / "no" / "such" / "dir.glb");
  EXPECT_FALSE(missing.is_ok()) << "a folder that does not exist";

  b.set(scene->graph().find("body"), "triangles", std::vector<std::int64_t>{0, 1, 2});
  ASSERT_TRUE(export_gltf(*scene, out).is_ok());
  EXPECT_VALID_GLTF(out);
  EXPECT_EQ(read_text(out).substr(0, 4), "glTF") << "a successful export replaces the file";
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"out.glb"});
}

TEST(GltfExport, bad_requests_are_refused_with_the_reason) {
  auto scene = chain_scene();
  TempDir dir;
  const Status ext = export_gltf(*scene, dir.path() / "x.obj");
  EXPECT_FALSE(ext.is_ok());
  EXPECT_NE(ext.message().find(".obj"), std::string::npos) << ext.message();
  GltfExportOptions reversed;
  reversed.frames = std::pair{5.0, 2.0};
  EXPECT_FALSE(export_gltf(*scene, dir.path() / "x.glb", reversed).is_ok());
  GltfExportOptions negative;
  negative.frames = std::pair{-1.0, 2.0};
  EXPECT_FALSE(export_gltf(*scene, dir.path() / "x.glb", negative).is_ok());
  GltfExportOptions nan;
  nan.frames = std::pair{std::nan(""), 2.0};
  EXPECT_FALSE(export_gltf(*scene, dir.path() / "x.glb", nan).is_ok());
  EXPECT_TRUE(dir.entries().empty());
}

TEST(GltfExport, a_skinned_mesh_away_from_its_geom_matrix_is_refused) {
  auto scene = chain_scene();
  Builder b(*scene);
  b.set(scene->graph().find("body"), "translate", Vec3(5, 0, 0));
  TempDir dir;
  const Status s = export_gltf(*scene, dir.path() / "x.glb");
  ASSERT_FALSE(s.is_ok()) << "glTF would draw the mesh 5 units away from where rigel draws it";
  EXPECT_NE(s.message().find("body"), std::string::npos) << s.message();
  EXPECT_NE(s.message().find("skin.geomMatrix"), std::string::npos) << s.message();

  // A geomMatrix that says where the mesh is makes the two agree again.
  b.set(scene->graph().find("skin"), "geomMatrix", translation(5, 0, 0));
  GltfExportReport report;
  const Status ok = export_gltf(*scene, dir.path() / "x.glb", {}, &report);
  ASSERT_TRUE(ok.is_ok()) << ok.message();
  tinygltf::Model model = load_model(dir.path() / "x.glb");
  expect_values(model.nodes.at(3).translation, {5, 0, 0}, 0,
                "the skinned mesh's node keeps its world transform (glTF ignores it for the mesh)");
}

TEST(GltfExport, a_joint_matrix_not_fed_by_a_joint_is_refused) {
  auto scene = chain_scene();
  ASSERT_TRUE(scene->graph().disconnect_input(*scene->graph().plug_find("skin.jointMatrices[1]")).is_ok());
  TempDir dir;
  const Status s = export_gltf(*scene, dir.path() / "x.glb");
  ASSERT_FALSE(s.is_ok());
  EXPECT_NE(s.message().find("skin.jointMatrices[1]"), std::string::npos) << s.message();
}

// ---- round trips through rigel's importer ----------------------------------------

// ---- shear: glTF nodes are TRS only --------------------------------------------

// Skinned positions the way a glTF viewer computes them: sum of w * J * IBM * p.
std::vector<Vec3> gltf_skinned_points(const tinygltf::Model& model, const std::vector<Eigen::Matrix4d>& world, int mesh_node) {
  const tinygltf::Node& node = model.nodes.at(static_cast<std::size_t>(mesh_node));
  const tinygltf::Primitive& prim = model.meshes.at(static_cast<std::size_t>(node.mesh)).primitives.at(0);
  const tinygltf::Skin& skin = model.skins.at(static_cast<std::size_t>(node.skin));
  const std::vector<double> p = accessor_values(model, prim.attributes.at("POSITION"));
  const std::vector<double> j = accessor_values(model, prim.attributes.at("JOINTS_0"));
  const std::vector<double> w = accessor_values(model, prim.attributes.at("WEIGHTS_0"));
  const std::vector<double> ibm = accessor_values(model, skin.inverseBindMatrices);
  std::vector<Vec3> out;
  for (std::size_t v = 0; v < p.size() / 3; ++v) {
    Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
    for (std::size_t k = 0; k < 4; ++k) {
      const auto joint = static_cast<std::size_t>(j[4 * v + k]);
      const Eigen::Matrix4d bind = Eigen::Map<const Eigen::Matrix4d>(std::vector<double>(ibm.begin() + 16 * joint, ibm.begin() + 16 * joint + 16).data());
      m += w[4 * v + k] * world[static_cast<std::size_t>(skin.joints[joint])] * bind;
    }
    out.push_back((m * Eigen::Vector4d(p[3 * v], p[3 * v + 1], p[3 * v + 2], 1.0)).head<3>());
  }
  return out;
}

TEST(GltfExport, shear_is_never_written_as_a_matrix_and_what_hangs_below_keeps_its_place) {
  auto scene = new_scene();
  Builder b(*scene);
  // A sheared transform with a joint chain and an unskinned mesh below it.
  const NodeId sheared = b.node(scene::kTransformType, "sheared", 1);
  const NodeId child = b.node(scene::kJointType, "child", 2, sheared);
  const NodeId grand = b.node(scene::kJointType, "grand", 3, child);
  const NodeId plate = b.node(scene::kMeshType, "plate", 4, sheared);
  b.set(sheared, "translate", Vec3(1, 0, 0));
  b.set(sheared, "rotate", Vec3(10, 20, 30));
  b.set(sheared, "scale", Vec3(1, 2, 0.5));
  b.set(sheared, "shear", Vec3(0.5, 0.25, -0.3));
  b.set(child, "translate", Vec3(0, 1, 0));
  b.set(child, "rotate", Vec3(0, 0, 30));
  b.set(child, "shear", Vec3(0.1, 0, 0));
  b.set(grand, "translate", Vec3(0, 1, 0.5));
  b.set(plate, "points", std::vector<Vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  b.set(plate, "normals", std::vector<Vec3>(3, Vec3(0, 0, 1)));
  b.set(plate, "triangles", std::vector<std::int64_t>{0, 1, 2});
  // A sheared joint skinning a mesh.
  const NodeId bone = b.node(scene::kJointType, "bone", 5);
  const NodeId tipbone = b.node(scene::kJointType, "tipbone", 6, bone);
  const NodeId body = b.node(scene::kMeshType, "body", 7);
  const NodeId skin = b.node(ops::kSkinClusterType, "skin", 8);
  b.set(bone, "translate", Vec3(0, 2, 0));
  b.set(bone, "shear", Vec3(0, 0.4, 0));
  b.set(tipbone, "translate", Vec3(0, 1, 0));
  b.set(body, "triangles", std::vector<std::int64_t>{0, 1, 2});
  b.set(skin, "bindPoints", std::vector<Vec3>{{0, 2, 0}, {1, 2.5, 0}, {0, 3, 1}});
  b.set(skin, "bindPreMatrices", std::vector<Mat4>{translation(0, -2.5, 0), translation(0, -3, 0)});
  b.set(skin, "influenceOffsets", std::vector<std::int64_t>{0, 1, 3, 4});
  b.set(skin, "influenceJoints", std::vector<std::int64_t>{0, 0, 1, 1});
  b.set(skin, "influenceWeights", std::vector<double>{1, 0.5, 0.5, 1});
  b.connect("bone.worldMatrix", "skin.jointMatrices[0]");
  b.connect("tipbone.worldMatrix", "skin.jointMatrices[1]");
  b.connect("skin.outPoints", "body.points");
  (void)body;
  (void)skin;

  TempDir dir;
  const fs::path out = dir.path() / "sheared.glb";
  GltfExportReport report;
  ASSERT_TRUE(export_gltf(*scene, out, {}, &report).is_ok());
  EXPECT_VALID_GLTF(out);
  tinygltf::Model model = load_model(out);
  const std::vector<Eigen::Matrix4d> world = gltf_world_at_key(model, nullptr, 0);  // fails on any `matrix`
  // Every node keeps its world position (its frame loses the shear it has
  // or inherits: a TRS node cannot hold it).
  for (NodeId id : {sheared, child, grand, bone, tipbone}) {
    const std::string& n = scene->graph().node(id)->name();
    const Mat4 truth = scene->world_matrix(id);
    const Eigen::Matrix4d& file = world[static_cast<std::size_t>(node_index(model, n))];
    EXPECT_LT((file.topRightCorner<3, 1>() - truth.topRightCorner<3, 1>()).norm(), 1e-5) << n << " keeps its world position";
  }
  // The mesh under the sheared transform: its points land where rigel draws them.
  {
    const int node = node_index(model, "plate");
    const auto& prim = model.meshes.at(static_cast<std::size_t>(model.nodes[static_cast<std::size_t>(node)].mesh)).primitives.at(0);
    const std::vector<double> p = accessor_values(model, prim.attributes.at("POSITION"));
    const auto& truth_points = std::get<std::vector<Vec3>>(scene->graph().evaluate(plate, scene::mesh_attr::kPoints));
    for (std::size_t v = 0; v < 3; ++v) {
      const Eigen::Vector4d in_file = world[static_cast<std::size_t>(node)] * Eigen::Vector4d(p[3 * v], p[3 * v + 1], p[3 * v + 2], 1);
      const Vec3 truth = (scene->world_matrix(plate) * truth_points[v].homogeneous()).head<3>();
      EXPECT_LT((in_file.head<3>() - truth).norm(), 1e-5) << "plate point " << v;
    }
  }
  // The skinned mesh: glTF's skinning of the file equals rigel's skinned points.
  {
    const auto& truth_points = std::get<std::vector<Vec3>>(scene->graph().evaluate(body, scene::mesh_attr::kPoints));
    const std::vector<Vec3> file_points = gltf_skinned_points(model, world, node_index(model, "body"));
    ASSERT_EQ(file_points.size(), truth_points.size());
    for (std::size_t v = 0; v < truth_points.size(); ++v)
      EXPECT_LT((file_points[v] - truth_points[v]).norm(), 1e-5) << "skinned point " << v;
  }
  bool noted = false;
  for (const std::string& note : report.notes) noted |= note.rfind("sheared: its shear", 0) == 0;
  EXPECT_TRUE(noted) << "the report says the shear is left out";
}

// import -> export -> import -> export of every bundled character keeps the
// node tree: the same scene nodes (name, type, parent) after each import,
// and the same glTF nodes (count, names, parents) as the original file.
TEST(GltfExport, round_trips_keep_the_node_tree_and_names_of_every_bundled_character) {
  using Tree = std::vector<std::tuple<std::string, std::string, std::string>>;  // name, type, parent
  auto scene_tree = [](Scene& sc) {
    Tree out;
    for (NodeId id : sc.graph().nodes()) {
      if (!sc.is_transform(id)) continue;
      const NodeId p = sc.graph().parent(id);
      out.emplace_back(sc.graph().node(id)->name(), sc.graph().node(id)->type().name(), p.is_valid() ? sc.graph().node(p)->name() : "");
    }
    std::sort(out.begin(), out.end());
    return out;
  };
  // glTF nodes as (name, parent name), unnamed ones named as the importer does.
  auto file_tree = [](const tinygltf::Model& model) {
    std::vector<std::pair<std::string, std::string>> out;
    std::vector<int> parent(model.nodes.size(), -1);
    for (std::size_t i = 0; i < model.nodes.size(); ++i)
      for (int c : model.nodes[i].children) parent[static_cast<std::size_t>(c)] = static_cast<int>(i);
    auto name = [&](std::size_t i) { return model.nodes[i].name.empty() ? "node_" + std::to_string(i) : model.nodes[i].name; };
    for (std::size_t i = 0; i < model.nodes.size(); ++i)
      out.emplace_back(name(i), parent[i] < 0 ? std::string() : name(static_cast<std::size_t>(parent[i])));
    std::sort(out.begin(), out.end());
    return out;
  };
  for (const auto& entry : fs::directory_iterator(source_dir() / "tests" / "data" / "gltf")) {
    const std::string ext = entry.path().extension().string();
    if (ext != ".glb" && ext != ".gltf") continue;
    SCOPED_TRACE(entry.path().filename().string());
    TempDir dir;
    Result<std::unique_ptr<Scene>> first = import_gltf(entry.path());
    ASSERT_TRUE(first.is_ok()) << first.status().message();
    const auto original = file_tree(load_model(entry.path()));
    const Tree tree = scene_tree(**first);
    std::unique_ptr<Scene> current = std::move(*first);
    for (int trip = 1; trip <= 2; ++trip) {
      SCOPED_TRACE("round trip " + std::to_string(trip));
      const fs::path out = dir.path() / ("trip" + std::to_string(trip) + ".glb");
      ASSERT_TRUE(export_gltf(*current, out).is_ok());
      EXPECT_VALID_GLTF(out);
      EXPECT_EQ(file_tree(load_model(out)), original) << "the file's nodes, names and parents";
      Result<std::unique_ptr<Scene>> next = import_gltf(out);
      ASSERT_TRUE(next.is_ok()) << next.status().message();
      EXPECT_EQ(scene_tree(**next), tree) << "the imported scene's nodes, names, types and parents";
      current = std::move(*next);
    }
  }
}

fs::path gltf_data(const std::string& name) { return source_dir() / "tests" / "data" / "gltf" / name; }

// A channel's value when no clip plays it: the curve's restValue when a
// clip curve feeds it, else the attribute.
template <typename T>
T rest_value(Graph& g, NodeId node, AttrIndex attr) {
  if (std::optional<Plug> src = g.source(Plug{node, attr, -1})) {
    const AttrIndex rest = g.node(src->node)->type().attr_find("restValue");
    if (rest != graph::kNoAttr) return std::get<T>(g.node(src->node)->value(rest));
  }
  return std::get<T>(g.node(node)->value(attr));
}

std::vector<NodeId> nodes_of_type(const Graph& g, const char* type) {
  std::vector<NodeId> out;
  for (NodeId id : g.nodes())
    if (g.node(id)->type().name() == type) out.push_back(id);
  return out;
}

// Per vertex: joint name -> normalised weight.
std::vector<std::map<std::string, double>> skin_weights(Graph& g, NodeId cluster) {
  namespace sa = ops::skin_cluster_attr;
  const auto& offsets = std::get<std::vector<std::int64_t>>(g.evaluate(cluster, sa::kInfluenceOffsets));
  const auto& joints = std::get<std::vector<std::int64_t>>(g.evaluate(cluster, sa::kInfluenceJoints));
  const auto& weights = std::get<std::vector<double>>(g.evaluate(cluster, sa::kInfluenceWeights));
  std::vector<std::map<std::string, double>> out;
  for (std::size_t v = 0; v + 1 < offsets.size(); ++v) {
    std::map<std::string, double> w;
    double sum = 0;
    for (auto k = offsets[v]; k < offsets[v + 1]; ++k) sum += weights[static_cast<std::size_t>(k)];
    for (auto k = offsets[v]; k < offsets[v + 1]; ++k) {
      const auto source = g.source(Plug{cluster, sa::kJointMatrices, static_cast<std::int32_t>(joints[static_cast<std::size_t>(k)])});
      const std::string name = source ? g.node(source->node)->name() : "?";
      if (weights[static_cast<std::size_t>(k)] != 0) w[name] += weights[static_cast<std::size_t>(k)] / sum;
    }
    out.push_back(std::move(w));
  }
  return out;
}

class RoundTrip : public ::testing::TestWithParam<const char*> {};

TEST_P(RoundTrip, import_export_import_keeps_joints_weights_and_motion) {
  const fs::path source = gltf_data(GetParam());
  Result<std::unique_ptr<Scene>> first = import_gltf(source);
  ASSERT_TRUE(first.is_ok()) << first.status().message();
  Scene& a = **first;
  TempDir dir;
  const fs::path out = dir.path() / "round.glb";
  GltfExportReport report;
  const Status s = export_gltf(a, out, {}, &report);
  ASSERT_TRUE(s.is_ok()) << s.message();
  EXPECT_VALID_GLTF(out);
  EXPECT_FALSE(report.baked) << "imported glTF animation is written back directly: " << report.bake_reason;
  Result<std::unique_ptr<Scene>> second = import_gltf(out);
  ASSERT_TRUE(second.is_ok()) << second.status().message();
  Scene& b = **second;
  Graph& ga = a.graph();
  Graph& gb = b.graph();

  // Joints: names, parents, rest TRS.
  const std::vector<NodeId> joints = nodes_of_type(ga, scene::kJointType);
  ASSERT_FALSE(joints.empty());
  EXPECT_EQ(joints.size(), nodes_of_type(gb, scene::kJointType).size());
  for (NodeId ja : joints) {
    const std::string& name = ga.node(ja)->name();
    const NodeId jb = gb.find(name);
    ASSERT_TRUE(jb.is_valid()) << "joint " << name << " should come back";
    EXPECT_EQ(gb.node(jb)->type().name(), scene::kJointType) << name;
    const NodeId pa = ga.parent(ja), pb = gb.parent(jb);
    EXPECT_EQ(pa.is_valid() ? ga.node(pa)->name() : "", pb.is_valid() ? gb.node(pb)->name() : "") << name << "'s parent";
    const Vec3 ta = rest_value<Vec3>(ga, ja, xf::kTranslate), tb = rest_value<Vec3>(gb, jb, xf::kTranslate);
    const Vec3 sa = rest_value<Vec3>(ga, ja, xf::kScale), sb = rest_value<Vec3>(gb, jb, xf::kScale);
    const Quat qa = rest_value<Quat>(ga, ja, xf::kRotateQuaternion).normalized();
    const Quat qb = rest_value<Quat>(gb, jb, xf::kRotateQuaternion).normalized();
    EXPECT_LE((ta - tb).norm(), 1e-9 * std::max(1.0, ta.norm())) << name << " rest translate";
    EXPECT_LE((sa - sb).norm(), 1e-9) << name << " rest scale";
    EXPECT_GE(std::abs(qa.dot(qb)), 1 - 1e-12) << name << " rest rotation";
  }

  // Skinned meshes, in creation order: the same normalised weights per vertex.
  const std::vector<NodeId> clusters_a = nodes_of_type(ga, ops::kSkinClusterType);
  const std::vector<NodeId> clusters_b = nodes_of_type(gb, ops::kSkinClusterType);
  ASSERT_EQ(clusters_a.size(), clusters_b.size());
  for (std::size_t c = 0; c < clusters_a.size(); ++c) {
    const auto wa = skin_weights(ga, clusters_a[c]);
    const auto wb = skin_weights(gb, clusters_b[c]);
    ASSERT_EQ(wa.size(), wb.size()) << "vertex count of skin " << c;
    for (std::size_t v = 0; v < wa.size(); ++v) {
      ASSERT_EQ(wa[v].size(), wb[v].size()) << "influences of vertex " << v;
      for (const auto& [joint, weight] : wa[v]) {
        ASSERT_EQ(wb[v].count(joint), 1u) << "vertex " << v << " joint " << joint;
        EXPECT_NEAR(wb[v].at(joint), weight, 1e-6) << "vertex " << v << " joint " << joint;
      }
    }
  }

  EXPECT_FALSE(clusters_a.empty()) << "every fixture is skinned";

  // Clips: the same names and time ranges (times pass through 32-bit floats).
  const NodeId clips_a = ops::anim::find_clips_node(ga), clips_b = ops::anim::find_clips_node(gb);
  ASSERT_TRUE(clips_a.is_valid() && clips_b.is_valid()) << "every fixture is animated";
  Result<std::vector<ops::anim::Clip>> list_a = ops::anim::clips_of(ga, clips_a), list_b = ops::anim::clips_of(gb, clips_b);
  ASSERT_TRUE(list_a.is_ok() && list_b.is_ok());
  ASSERT_EQ(list_a->size(), list_b->size());
  for (std::size_t c = 0; c < list_a->size(); ++c) {
    EXPECT_EQ((*list_a)[c].name, (*list_b)[c].name);
    EXPECT_NEAR((*list_a)[c].start, (*list_b)[c].start, 1e-6);
    EXPECT_NEAR((*list_a)[c].end, (*list_b)[c].end, 1e-6);
  }

  // Motion: joint world matrices and skinned points at several times.
  bool moves = false;
  for (double time : {0.0, 0.3, 0.77, 1.5}) {
    ga.set_time(0.0);
    const Mat4 at_zero = a.world_matrix(joints.back());
    ga.set_time(time);
    moves = moves || !math::is_near(at_zero, a.world_matrix(joints.back()), 1e-6);
    ga.set_time(time);
    gb.set_time(time);
    for (NodeId ja : joints) {
      const NodeId jb = gb.find(ga.node(ja)->name());
      EXPECT_TRUE(matrices_near(a.world_matrix(ja), b.world_matrix(jb), 1e-6))
          << ga.node(ja)->name() << " at " << time << " s";
    }
    for (std::size_t c = 0; c < clusters_a.size(); ++c) {
      const auto& pa = std::get<std::vector<Vec3>>(ga.evaluate(clusters_a[c], ops::skin_cluster_attr::kOutPoints));
      const auto& pb = std::get<std::vector<Vec3>>(gb.evaluate(clusters_b[c], ops::skin_cluster_attr::kOutPoints));
      ASSERT_EQ(pa.size(), pb.size());
      double size = 1.0, worst = 0.0;
      for (std::size_t v = 0; v < pa.size(); ++v) {
        size = std::max(size, pa[v].cwiseAbs().maxCoeff());
        worst = std::max(worst, (pa[v] - pb[v]).cwiseAbs().maxCoeff());
      }
      EXPECT_LE(worst, 1e-6 * size) << "skinned points of skin " << c << " at " << time << " s";
    }
  }
  EXPECT_TRUE(moves) << "the last joint should move over the sampled times, or the comparison proves little";
}

INSTANTIATE_TEST_SUITE_P(GltfExport, RoundTrip, ::testing::Values("CesiumMan.glb", "RiggedSimple.glb", "SimpleSkin.gltf"),
                         [](const auto& info) {
                           std::string name = info.param;
                           for (char& c : name)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return name;
                         });

}  // namespace
}  // namespace rigel::io
