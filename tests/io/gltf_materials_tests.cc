// How meshes look through glTF import, .rigel files and glTF export:
// materials, textures (image bytes), samplers, TEXCOORD_0/1 and COLOR_0.
// The files are read independently with tinygltf (its own image loader
// hands over the raw bytes), and every export is run through the Khronos
// validator (tools/validate-gltf.mjs) when node and the package are there.

#include <tiny_gltf.h>

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdlib>
#include <cstring>
#include <functional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "io_test_util.h"
#include "rigel/io/gltf_export.h"
#include "rigel/io/gltf_import.h"
#include "rigel/io/scene_file.h"
#include "rigel/scene/materials.h"

namespace rigel::io {
namespace {

using namespace testing;
namespace ma = scene::material_attr;
namespace ta = scene::texture_attr;
namespace la = scene::mesh_look_attr;

fs::path gltf_dir() { return source_dir() / "tests" / "data" / "gltf"; }

// The raw bytes of each image, as the file holds them (no decoding).
bool keep_bytes(tinygltf::Image* image, const int, std::string*, std::string*, int, int, const unsigned char* bytes, int size,
                void*) {
  image->image.assign(bytes, bytes + size);
  return true;
}

tinygltf::Model read_model(const fs::path& path) {
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(&keep_bytes, nullptr);
  tinygltf::Model model;
  std::string err, warn;
  const bool binary = path.extension() == ".glb";
  const bool ok = binary ? loader.LoadBinaryFromFile(&model, &err, &warn, path.string())
                         : loader.LoadASCIIFromFile(&model, &err, &warn, path.string());
  EXPECT_TRUE(ok) << path << ": " << err;
  return model;
}

// Accessor values as doubles (float, or normalized unsigned byte/short).
std::vector<double> accessor_values(const tinygltf::Model& m, int index) {
  const tinygltf::Accessor& a = m.accessors[static_cast<std::size_t>(index)];
  const tinygltf::BufferView& v = m.bufferViews[static_cast<std::size_t>(a.bufferView)];
  const int n = tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(a.type));
  const int size = tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(a.componentType));
  const std::size_t stride = v.byteStride ? v.byteStride : static_cast<std::size_t>(n * size);
  const unsigned char* base = m.buffers[static_cast<std::size_t>(v.buffer)].data.data() + v.byteOffset + a.byteOffset;
  std::vector<double> out;
  for (std::size_t e = 0; e < a.count; ++e) {
    for (int k = 0; k < n; ++k) {
      const unsigned char* p = base + e * stride + static_cast<std::size_t>(k * size);
      double x = 0;
      if (a.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT) {
        float f;
        std::memcpy(&f, p, 4);
        x = f;
      } else if (a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) {
        x = *p / 255.0;
      } else if (a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
        std::uint16_t u;
        std::memcpy(&u, p, 2);
        x = u / 65535.0;
      } else {
        ADD_FAILURE() << "unexpected component type " << a.componentType;
      }
      out.push_back(x);
    }
  }
  return out;
}

void expect_near_all(const std::vector<double>& a, const std::vector<double>& b, double tolerance, const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  double worst = 0;
  for (std::size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::abs(a[i] - b[i]));
  EXPECT_LE(worst, tolerance) << what;
}

// Runs the Khronos validator on `path`: 0 errors. Skipped (with a message)
// where node or the package is missing.
void expect_valid(const fs::path& path) {
  const fs::path tool = source_dir() / "tools" / "validate-gltf.mjs";
  if (!fs::exists(tool) || std::system("node --version > /dev/null 2>&1") != 0) {
    std::printf("(no glTF validator here: %s not checked)\n", path.string().c_str());
    return;
  }
  const std::string command = "node '" + tool.string() + "' '" + path.string() + "' > '" + path.string() + ".log' 2>&1";
  const int status = std::system(command.c_str());
  const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  if (code == 3) {
    std::printf("(gltf-validator package not installed: %s not checked)\n", path.string().c_str());
    return;
  }
  EXPECT_EQ(code, 0) << path << ": " << read_text(path.string() + ".log");
}

std::vector<unsigned char> bytes_of(const std::string& base64) {
  // The scene keeps base64; decode with tinygltf's rule through a data URI
  // would need its internals, so decode here (RFC 4648).
  auto value = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    return c == '+' ? 62 : c == '/' ? 63 : -1;
  };
  std::vector<unsigned char> out;
  std::uint32_t bits = 0;
  int have = 0;
  for (char c : base64) {
    if (c == '=') break;
    const int v = value(c);
    EXPECT_GE(v, 0) << "base64 character";
    bits = (bits << 6) | static_cast<std::uint32_t>(v);
    have += 6;
    if (have >= 8) {
      have -= 8;
      out.push_back(static_cast<unsigned char>((bits >> have) & 0xFF));
    }
  }
  return out;
}

NodeId only_node_of_type(const Graph& g, const std::string& type) {
  NodeId found;
  int count = 0;
  for (NodeId id : g.nodes()) {
    if (g.node(id)->type().name() == type) {
      found = id;
      ++count;
    }
  }
  EXPECT_EQ(count, 1) << "nodes of type " << type;
  return found;
}

std::vector<NodeId> nodes_of_type(const Graph& g, const std::string& type) {
  std::vector<NodeId> out;
  for (NodeId id : g.nodes())
    if (g.node(id)->type().name() == type) out.push_back(id);
  return out;
}

template <typename T>
const T& value(const Graph& g, NodeId node, graph::AttrIndex attr) {
  return std::get<T>(g.node(node)->value(attr));
}

NodeId source_node(const Graph& g, NodeId node, graph::AttrIndex attr) {
  std::optional<Plug> src = g.source(Plug{node, attr, -1});
  return src ? src->node : NodeId{};
}

// ---- the scene types ----

TEST(MeshLook, mesh_attribute_constants_match_the_registered_names) {
  auto registry = scene::default_registry();
  const graph::NodeType* mesh = registry->find(scene::kMeshType);
  ASSERT_NE(mesh, nullptr);
  EXPECT_EQ(mesh->attr(la::kUv0).name, "uv0");
  EXPECT_EQ(mesh->attr(la::kUv1).name, "uv1");
  EXPECT_EQ(mesh->attr(la::kColors).name, "colors");
  EXPECT_EQ(mesh->attr(la::kMaterial).name, "material");
  const graph::NodeType* material = registry->find(scene::kMaterialType);
  ASSERT_NE(material, nullptr);
  EXPECT_EQ(material->attr_count(), ma::kCount + 1u) << "+ metaParent";
  EXPECT_EQ(material->attr(ma::kDoubleSided).name, "doubleSided");
  EXPECT_EQ(material->attr(ma::kEmissiveTexCoord).name, "emissiveTexCoord");
  const graph::NodeType* texture = registry->find(scene::kTextureType);
  ASSERT_NE(texture, nullptr);
  EXPECT_EQ(texture->attr_count(), ta::kCount + 1u);
  EXPECT_EQ(texture->attr(ta::kWrapT).name, "wrapT");
}

// ---- CesiumMan: a textured, skinned character ----

class CesiumMan : public ::testing::Test {
 protected:
  void SetUp() override {
    source_ = read_model(gltf_dir() / "CesiumMan.glb");
    auto imported = import_gltf(gltf_dir() / "CesiumMan.glb");
    ASSERT_TRUE(imported.is_ok()) << imported.status().message();
    scene_ = std::move(*imported);
  }
  tinygltf::Model source_;
  std::unique_ptr<Scene> scene_;
};

TEST_F(CesiumMan, import_keeps_the_material_texture_and_uvs) {
  const Graph& g = scene_->graph();
  ASSERT_EQ(source_.materials.size(), 1u);
  ASSERT_EQ(source_.images.size(), 1u);
  const NodeId mesh = only_node_of_type(g, scene::kMeshType);
  const NodeId material = only_node_of_type(g, scene::kMaterialType);
  const NodeId texture = only_node_of_type(g, scene::kTextureType);
  ASSERT_TRUE(mesh.is_valid() && material.is_valid() && texture.is_valid());
  EXPECT_EQ(source_node(g, mesh, la::kMaterial), material) << "the mesh is assigned its material";
  EXPECT_EQ(source_node(g, material, ma::kBaseColorTexture), texture) << "the base colour is the texture";

  const tinygltf::Material& m = source_.materials[0];
  EXPECT_EQ(g.node(material)->name(), m.name);
  EXPECT_EQ(value<std::vector<double>>(g, material, ma::kBaseColorFactor), m.pbrMetallicRoughness.baseColorFactor);
  EXPECT_EQ(value<double>(g, material, ma::kMetallicFactor), m.pbrMetallicRoughness.metallicFactor);
  EXPECT_EQ(value<double>(g, material, ma::kRoughnessFactor), m.pbrMetallicRoughness.roughnessFactor);
  EXPECT_EQ(value<bool>(g, material, ma::kDoubleSided), m.doubleSided);

  const tinygltf::Image& image = source_.images[0];
  EXPECT_EQ(bytes_of(value<std::string>(g, texture, ta::kImage)), image.image) << "the image's bytes, unchanged";
  EXPECT_GT(image.image.size(), 1000u);
  EXPECT_EQ(value<std::string>(g, texture, ta::kMimeType), image.mimeType);

  const tinygltf::Primitive& prim = source_.meshes[0].primitives[0];
  expect_near_all(value<std::vector<double>>(g, mesh, la::kUv0), accessor_values(source_, prim.attributes.at("TEXCOORD_0")), 0.0,
                  "uv0 is TEXCOORD_0");
  EXPECT_EQ(value<std::vector<double>>(g, mesh, la::kUv0).size(), 2 * std::get<std::vector<Vec3>>(
                                                                         scene_->graph().evaluate(mesh, scene::mesh_attr::kPoints)).size())
      << "one uv per point, aligned with the skinned points";
}

TEST_F(CesiumMan, rigel_file_round_trip_is_identical) {
  TempDir dir;
  ASSERT_TRUE(save_scene(*scene_, dir.path() / "a.rigel").is_ok());
  auto loaded = load_scene(dir.path() / "a.rigel");
  ASSERT_TRUE(loaded.is_ok()) << loaded.status().message();
  ASSERT_TRUE(save_scene(**loaded, dir.path() / "b.rigel").is_ok());
  EXPECT_EQ(read_text(dir.path() / "a.rigel"), read_text(dir.path() / "b.rigel")) << "load(save(s)) saves the same text";
  const Graph& g = (*loaded)->graph();
  const NodeId texture = only_node_of_type(g, scene::kTextureType);
  EXPECT_EQ(bytes_of(value<std::string>(g, texture, ta::kImage)), source_.images[0].image) << "the image survives the file";
  const NodeId mesh = only_node_of_type(g, scene::kMeshType);
  EXPECT_EQ(source_node(g, mesh, la::kMaterial), only_node_of_type(g, scene::kMaterialType));
  EXPECT_EQ(value<std::vector<double>>(g, mesh, la::kUv0), value<std::vector<double>>(scene_->graph(), scene_->graph().find(g.node(mesh)->name()), la::kUv0));
}

TEST_F(CesiumMan, export_keeps_the_texture_material_and_uvs) {
  TempDir dir;
  const fs::path out = dir.path() / "cesium.glb";
  GltfExportReport report;
  ASSERT_TRUE(export_gltf(*scene_, out, {}, &report).is_ok());
  const tinygltf::Model model = read_model(out);
  ASSERT_EQ(model.images.size(), 1u);
  EXPECT_EQ(model.images[0].image, source_.images[0].image) << "the same image bytes";
  EXPECT_EQ(model.images[0].mimeType, source_.images[0].mimeType);
  ASSERT_EQ(model.materials.size(), 1u);
  const tinygltf::Material& a = model.materials[0];
  const tinygltf::Material& b = source_.materials[0];
  EXPECT_EQ(a.name, b.name);
  expect_near_all(a.pbrMetallicRoughness.baseColorFactor, b.pbrMetallicRoughness.baseColorFactor, 1e-12, "baseColorFactor");
  EXPECT_EQ(a.pbrMetallicRoughness.metallicFactor, b.pbrMetallicRoughness.metallicFactor);
  EXPECT_EQ(a.pbrMetallicRoughness.roughnessFactor, b.pbrMetallicRoughness.roughnessFactor);
  EXPECT_EQ(a.doubleSided, b.doubleSided);
  EXPECT_EQ(a.alphaMode, b.alphaMode);
  ASSERT_GE(a.pbrMetallicRoughness.baseColorTexture.index, 0);
  const tinygltf::Texture& t = model.textures[static_cast<std::size_t>(a.pbrMetallicRoughness.baseColorTexture.index)];
  EXPECT_EQ(t.source, 0);
  ASSERT_EQ(model.meshes.size(), 1u);
  const tinygltf::Primitive& p = model.meshes[0].primitives[0];
  EXPECT_EQ(p.material, 0);
  ASSERT_TRUE(p.attributes.count("TEXCOORD_0"));
  expect_near_all(accessor_values(model, p.attributes.at("TEXCOORD_0")),
                  accessor_values(source_, source_.meshes[0].primitives[0].attributes.at("TEXCOORD_0")), 1e-6, "TEXCOORD_0");
  // The sampler, as the file had it.
  const tinygltf::Texture& st = source_.textures[0];
  if (st.sampler >= 0) {
    const tinygltf::Sampler& s0 = source_.samplers[static_cast<std::size_t>(st.sampler)];
    const bool default_sampler = s0.magFilter < 0 && s0.minFilter < 0 && s0.wrapS == 10497 && s0.wrapT == 10497;
    if (!default_sampler) {
      ASSERT_GE(t.sampler, 0);
      const tinygltf::Sampler& s1 = model.samplers[static_cast<std::size_t>(t.sampler)];
      EXPECT_EQ(s1.magFilter, s0.magFilter);
      EXPECT_EQ(s1.minFilter, s0.minFilter);
      EXPECT_EQ(s1.wrapS, s0.wrapS);
      EXPECT_EQ(s1.wrapT, s0.wrapT);
    }
  }
  expect_valid(out);

  // And once more: import the export, export again: the same look.
  auto again = import_gltf(out);
  ASSERT_TRUE(again.is_ok()) << again.status().message();
  const fs::path out2 = dir.path() / "cesium2.gltf";
  ASSERT_TRUE(export_gltf(**again, out2).is_ok());
  const tinygltf::Model model2 = read_model(out2);
  ASSERT_EQ(model2.images.size(), 1u);
  EXPECT_EQ(model2.images[0].image, source_.images[0].image) << "a .gltf carries the image too (in its embedded buffer)";
  ASSERT_EQ(model2.materials.size(), 1u);
  EXPECT_EQ(model2.meshes[0].primitives[0].material, 0);
  expect_valid(out2);
}

// ---- a synthetic file: two uv sets, vertex colours, every texture slot ----

const std::vector<unsigned char> kPng = {
    0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44, 0x52, 0x00, 0x00, 0x00,
    0x02, 0x00, 0x00, 0x00, 0x01, 0x08, 0x02, 0x00, 0x00, 0x00, 0x7b, 0x40, 0xe8, 0xdd, 0x00, 0x00, 0x00, 0x10, 0x49,
    0x44, 0x41, 0x54, 0x78, 0x9c, 0x63, 0xf8, 0xdf, 0xc0, 0xc0, 0xc0, 0xf0, 0xbf, 0x01, 0x00, 0x0c, 0x7f, 0x02, 0xff,
    0xfe, 0xc9, 0x8e, 0x50, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82};

struct Synthetic {
  tinygltf::Model model;
  std::vector<double> uv0 = {0, 0, 1, 0, 0, 1, 1, 1};
  std::vector<double> uv1;                                  // normalized unsigned shorts
  std::vector<double> colors = {1, 0, 0, 1, 0, 1, 0, 0.5, 0, 0, 1, 1, 0.2, 0.4, 0.6, 0.8};
  std::vector<std::uint8_t> color_bytes;                    // the same, normalized unsigned bytes
};

template <typename T>
int add_accessor(tinygltf::Model& m, const std::vector<T>& data, int component, int type, bool normalized, std::size_t count) {
  tinygltf::Buffer& buffer = m.buffers[0];
  while (buffer.data.size() % 4) buffer.data.push_back(0);
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = buffer.data.size();
  view.byteLength = data.size() * sizeof(T);
  const auto* p = reinterpret_cast<const unsigned char*>(data.data());
  buffer.data.insert(buffer.data.end(), p, p + view.byteLength);
  m.bufferViews.push_back(view);
  tinygltf::Accessor a;
  a.bufferView = static_cast<int>(m.bufferViews.size()) - 1;
  a.componentType = component;
  a.type = type;
  a.normalized = normalized;
  a.count = count;
  m.accessors.push_back(a);
  return static_cast<int>(m.accessors.size()) - 1;
}

// A quad with TEXCOORD_0 (float), TEXCOORD_1 (normalized unsigned short),
// COLOR_0 (VEC4, float or normalized bytes) and a material using every slot.
Synthetic synthetic(bool byte_colors) {
  Synthetic s;
  tinygltf::Model& m = s.model;
  m.asset.version = "2.0";
  m.buffers.resize(1);
  const std::vector<float> points = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
  const std::vector<float> normals = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
  const std::vector<std::uint16_t> indices = {0, 1, 2, 2, 1, 3};
  const std::vector<std::uint16_t> uv1 = {0, 65535, 32768, 0, 65535, 65535, 100, 200};
  for (std::uint16_t u : uv1) s.uv1.push_back(u / 65535.0);
  tinygltf::Primitive prim;
  prim.attributes["POSITION"] = add_accessor(m, points, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, false, 4);
  m.accessors.back().minValues = {0, 0, 0};
  m.accessors.back().maxValues = {1, 1, 0};
  prim.attributes["NORMAL"] = add_accessor(m, normals, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, false, 4);
  const std::vector<float> uv0(s.uv0.begin(), s.uv0.end());
  prim.attributes["TEXCOORD_0"] = add_accessor(m, uv0, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, false, 4);
  prim.attributes["TEXCOORD_1"] = add_accessor(m, uv1, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_VEC2, true, 4);
  if (byte_colors) {
    for (double& c : s.colors) {
      s.color_bytes.push_back(static_cast<std::uint8_t>(std::lround(c * 255)));
      c = s.color_bytes.back() / 255.0;
    }
    prim.attributes["COLOR_0"] = add_accessor(m, s.color_bytes, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_TYPE_VEC4, true, 4);
  } else {
    const std::vector<float> colors(s.colors.begin(), s.colors.end());
    for (std::size_t i = 0; i < colors.size(); ++i) s.colors[i] = colors[i];
    prim.attributes["COLOR_0"] = add_accessor(m, colors, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC4, false, 4);
  }
  prim.indices = add_accessor(m, indices, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_SCALAR, false, 6);
  prim.material = 0;
  prim.mode = TINYGLTF_MODE_TRIANGLES;
  tinygltf::Mesh mesh;
  mesh.name = "quad";
  mesh.primitives.push_back(prim);
  m.meshes.push_back(mesh);
  tinygltf::Node node;
  node.name = "quadNode";
  node.mesh = 0;
  m.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes = {0};
  m.scenes.push_back(scene);
  m.defaultScene = 0;

  // The image in a bufferView, one sampler, two textures on it.
  tinygltf::Buffer& buffer = m.buffers[0];
  while (buffer.data.size() % 4) buffer.data.push_back(0);
  tinygltf::BufferView iv;
  iv.buffer = 0;
  iv.byteOffset = buffer.data.size();
  iv.byteLength = kPng.size();
  buffer.data.insert(buffer.data.end(), kPng.begin(), kPng.end());
  m.bufferViews.push_back(iv);
  tinygltf::Image image;
  image.name = "checker";
  image.mimeType = "image/png";
  image.bufferView = static_cast<int>(m.bufferViews.size()) - 1;
  m.images.push_back(image);
  tinygltf::Sampler sampler;
  sampler.magFilter = TINYGLTF_TEXTURE_FILTER_NEAREST;
  sampler.minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR;
  sampler.wrapS = TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
  sampler.wrapT = TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT;
  m.samplers.push_back(sampler);
  tinygltf::Texture t0;
  t0.name = "albedo";
  t0.source = 0;
  t0.sampler = 0;
  tinygltf::Texture t1;
  t1.source = 0;
  m.textures = {t0, t1};

  tinygltf::Material mat;
  mat.name = "paint";
  mat.pbrMetallicRoughness.baseColorFactor = {0.8, 0.6, 0.4, 0.9};
  mat.pbrMetallicRoughness.metallicFactor = 0.25;
  mat.pbrMetallicRoughness.roughnessFactor = 0.75;
  mat.pbrMetallicRoughness.baseColorTexture.index = 0;
  mat.pbrMetallicRoughness.baseColorTexture.texCoord = 1;
  mat.pbrMetallicRoughness.metallicRoughnessTexture.index = 1;
  mat.normalTexture.index = 1;
  mat.normalTexture.scale = 0.5;
  mat.occlusionTexture.index = 0;
  mat.occlusionTexture.strength = 0.7;
  mat.emissiveTexture.index = 1;
  mat.emissiveTexture.texCoord = 1;
  mat.emissiveFactor = {0.1, 0.2, 0.3};
  mat.alphaMode = "MASK";
  mat.alphaCutoff = 0.3;
  mat.doubleSided = true;
  m.materials.push_back(mat);
  return s;
}

fs::path write_model(const tinygltf::Model& model, const fs::path& path) {
  tinygltf::TinyGLTF writer;
  const bool binary = path.extension() == ".glb";
  EXPECT_TRUE(writer.WriteGltfSceneToFile(&model, path.string(), true, true, true, binary)) << path;
  return path;
}

void expect_synthetic_look(const Graph& g, const Synthetic& s, const std::string& context) {
  SCOPED_TRACE(context);
  const NodeId mesh = only_node_of_type(g, scene::kMeshType);
  const NodeId material = only_node_of_type(g, scene::kMaterialType);
  ASSERT_TRUE(mesh.is_valid() && material.is_valid());
  expect_near_all(value<std::vector<double>>(g, mesh, la::kUv0), s.uv0, 1e-6, "uv0");
  expect_near_all(value<std::vector<double>>(g, mesh, la::kUv1), s.uv1, 1e-6, "uv1");
  expect_near_all(value<std::vector<double>>(g, mesh, la::kColors), s.colors, 1e-6, "colors");
  EXPECT_EQ(source_node(g, mesh, la::kMaterial), material);
  expect_near_all(value<std::vector<double>>(g, material, ma::kBaseColorFactor), {0.8, 0.6, 0.4, 0.9}, 1e-12, "baseColorFactor");
  EXPECT_DOUBLE_EQ(value<double>(g, material, ma::kMetallicFactor), 0.25);
  EXPECT_DOUBLE_EQ(value<double>(g, material, ma::kRoughnessFactor), 0.75);
  EXPECT_DOUBLE_EQ(value<double>(g, material, ma::kNormalScale), 0.5);
  EXPECT_DOUBLE_EQ(value<double>(g, material, ma::kOcclusionStrength), 0.7);
  EXPECT_DOUBLE_EQ(value<double>(g, material, ma::kAlphaCutoff), 0.3);
  EXPECT_EQ(value<std::int64_t>(g, material, ma::kAlphaMode), 1) << "MASK";
  EXPECT_TRUE(value<bool>(g, material, ma::kDoubleSided));
  const Vec3 emissive = value<Vec3>(g, material, ma::kEmissiveFactor);
  EXPECT_NEAR((emissive - Vec3(0.1, 0.2, 0.3)).norm(), 0.0, 1e-12);
  EXPECT_EQ(value<std::int64_t>(g, material, ma::kBaseColorTexCoord), 1);
  EXPECT_EQ(value<std::int64_t>(g, material, ma::kEmissiveTexCoord), 1);
  EXPECT_EQ(value<std::int64_t>(g, material, ma::kNormalTexCoord), 0);
  const std::vector<NodeId> textures = nodes_of_type(g, scene::kTextureType);
  ASSERT_EQ(textures.size(), 2u) << "one texture node per glTF texture";
  const NodeId albedo = source_node(g, material, ma::kBaseColorTexture);
  ASSERT_TRUE(albedo.is_valid());
  EXPECT_EQ(source_node(g, material, ma::kOcclusionTexture), albedo);
  const NodeId other = source_node(g, material, ma::kNormalTexture);
  EXPECT_NE(other, albedo);
  EXPECT_EQ(source_node(g, material, ma::kMetallicRoughnessTexture), other);
  EXPECT_EQ(source_node(g, material, ma::kEmissiveTexture), other);
  EXPECT_EQ(bytes_of(value<std::string>(g, albedo, ta::kImage)), kPng);
  EXPECT_EQ(value<std::string>(g, albedo, ta::kMimeType), "image/png");
  EXPECT_EQ(value<std::string>(g, albedo, ta::kImageName), "checker");
  EXPECT_EQ(value<std::int64_t>(g, albedo, ta::kMagFilter), 9728);
  EXPECT_EQ(value<std::int64_t>(g, albedo, ta::kMinFilter), 9987);
  EXPECT_EQ(value<std::int64_t>(g, albedo, ta::kWrapS), 33071);
  EXPECT_EQ(value<std::int64_t>(g, albedo, ta::kWrapT), 33648);
  EXPECT_EQ(value<std::int64_t>(g, other, ta::kWrapS), 10497) << "no sampler: repeat";
}

class SyntheticLook : public ::testing::TestWithParam<bool> {};

TEST_P(SyntheticLook, import_save_load_export_keep_uv_sets_colours_and_material) {
  TempDir dir;
  const Synthetic s = synthetic(GetParam());
  const fs::path file = write_model(s.model, dir.path() / "quad.gltf");
  auto imported = import_gltf(file);
  ASSERT_TRUE(imported.is_ok()) << imported.status().message();
  expect_synthetic_look((*imported)->graph(), s, "imported");

  ASSERT_TRUE(save_scene(**imported, dir.path() / "quad.rigel").is_ok());
  auto loaded = load_scene(dir.path() / "quad.rigel");
  ASSERT_TRUE(loaded.is_ok()) << loaded.status().message();
  expect_synthetic_look((*loaded)->graph(), s, "loaded from .rigel");

  for (const char* name : {"out.glb", "out.gltf"}) {
    const fs::path out = dir.path() / name;
    ASSERT_TRUE(export_gltf(**loaded, out).is_ok());
    expect_valid(out);
    const tinygltf::Model model = read_model(out);
    ASSERT_EQ(model.meshes.size(), 1u);
    const tinygltf::Primitive& p = model.meshes[0].primitives[0];
    expect_near_all(accessor_values(model, p.attributes.at("TEXCOORD_0")), s.uv0, 1e-6, "TEXCOORD_0");
    expect_near_all(accessor_values(model, p.attributes.at("TEXCOORD_1")), s.uv1, 1e-6, "TEXCOORD_1");
    expect_near_all(accessor_values(model, p.attributes.at("COLOR_0")), s.colors, 1e-6, "COLOR_0 (alpha not 1: VEC4)");
    EXPECT_EQ(model.images.size(), 1u) << "two textures on one image: the image is stored once";
    EXPECT_EQ(model.textures.size(), 2u);
    ASSERT_EQ(model.materials.size(), 1u);
    EXPECT_EQ(model.materials[0].pbrMetallicRoughness.baseColorTexture.texCoord, 1);
    EXPECT_EQ(model.materials[0].alphaMode, "MASK");
    auto again = import_gltf(out);
    ASSERT_TRUE(again.is_ok()) << again.status().message();
    expect_synthetic_look((*again)->graph(), s, std::string("re-imported from ") + name);
  }
}

INSTANTIATE_TEST_SUITE_P(FloatAndByteColours, SyntheticLook, ::testing::Values(false, true));

TEST(MeshLookImport, opaque_rgb_colours_stay_rgb_and_a_missing_material_is_refused) {
  TempDir dir;
  Synthetic s = synthetic(false);
  // COLOR_0 as VEC3: alpha 1 in the scene, VEC3 again in the export.
  const std::vector<float> rgb = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0.5f, 0.5f, 0.5f};
  s.model.meshes[0].primitives[0].attributes["COLOR_0"] =
      add_accessor(s.model, rgb, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, false, 4);
  auto imported = import_gltf(write_model(s.model, dir.path() / "rgb.gltf"));
  ASSERT_TRUE(imported.is_ok()) << imported.status().message();
  const NodeId mesh = only_node_of_type((*imported)->graph(), scene::kMeshType);
  const auto& colors = value<std::vector<double>>((*imported)->graph(), mesh, la::kColors);
  ASSERT_EQ(colors.size(), 16u);
  EXPECT_EQ(colors[3], 1.0);
  EXPECT_EQ(colors[13], 0.5);
  ASSERT_TRUE(export_gltf(**imported, dir.path() / "rgb_out.glb").is_ok());
  const tinygltf::Model out = read_model(dir.path() / "rgb_out.glb");
  EXPECT_EQ(out.accessors[static_cast<std::size_t>(out.meshes[0].primitives[0].attributes.at("COLOR_0"))].type, TINYGLTF_TYPE_VEC3);

  s.model.meshes[0].primitives[0].material = 3;
  auto bad = import_gltf(write_model(s.model, dir.path() / "bad.gltf"));
  ASSERT_FALSE(bad.is_ok());
  EXPECT_NE(bad.status().message().find("meshes[0].primitives[0].material: material 3 does not exist"), std::string::npos)
      << bad.status().message();
}

TEST(MeshLookImport, bad_references_and_types_are_refused_naming_the_element) {
  TempDir dir;
  struct Case {
    std::function<void(tinygltf::Model&)> edit;
    std::string message;
  };
  const std::vector<Case> cases = {
      {[](tinygltf::Model& m) { m.materials[0].normalTexture.index = 7; }, "materials[0].normalTexture.index: texture 7 does not exist"},
      {[](tinygltf::Model& m) { m.textures[1].source = 4; }, "textures[1].source: image 4 does not exist"},
      {[](tinygltf::Model& m) { m.textures[0].sampler = 2; }, "textures[0].sampler: sampler 2 does not exist"},
      {[](tinygltf::Model& m) { m.materials[0].pbrMetallicRoughness.metallicFactor = 2; },
       "materials[0].pbrMetallicRoughness.metallicFactor: must be in [0, 1]"},
      {[](tinygltf::Model& m) {
         m.meshes[0].primitives[0].attributes["TEXCOORD_0"] = m.meshes[0].primitives[0].attributes["NORMAL"];
       },
       "meshes[0].primitives[0].attributes.TEXCOORD_0: accessors[1] is not VEC2"},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    Synthetic s = synthetic(false);
    cases[i].edit(s.model);
    auto r = import_gltf(write_model(s.model, dir.path() / ("case" + std::to_string(i) + ".gltf")));
    ASSERT_FALSE(r.is_ok()) << cases[i].message;
    EXPECT_NE(r.status().message().find(cases[i].message), std::string::npos) << r.status().message();
  }
}

TEST(MeshLookImport, image_files_are_read_only_inside_the_gltf_folder) {
  TempDir dir;
  fs::create_directories(dir.path() / "inner");
  write_text(dir.path() / "inner" / "tex.png", std::string(kPng.begin(), kPng.end()));
  write_text(dir.path() / "secret.png", std::string(kPng.begin(), kPng.end()));
  fs::create_symlink(dir.path() / "secret.png", dir.path() / "inner" / "link.png");
  for (const auto& [uri, ok] : std::vector<std::pair<std::string, bool>>{
           {"tex.png", true}, {"../secret.png", false}, {"link.png", false}, {"/etc/passwd", false}, {"missing.png", false}}) {
    Synthetic s = synthetic(false);
    s.model.images[0].bufferView = -1;
    s.model.images[0].uri = uri;
    const fs::path file = dir.path() / "inner" / "quad.gltf";
    // tinygltf's writer would try to copy the image; write the JSON with the uri by hand.
    tinygltf::TinyGLTF writer;
    writer.SetImageWriter(nullptr, nullptr);
    std::ostringstream stream;
    ASSERT_TRUE(writer.WriteGltfSceneToStream(&s.model, stream, true, false));
    write_text(file, stream.str());
    auto r = import_gltf(file);
    EXPECT_EQ(r.is_ok(), ok) << uri << ": " << (r.is_ok() ? "" : r.status().message());
    if (r.is_ok()) {
      const NodeId albedo = source_node((*r)->graph(), only_node_of_type((*r)->graph(), scene::kMaterialType), ma::kBaseColorTexture);
      EXPECT_EQ(bytes_of(value<std::string>((*r)->graph(), albedo, ta::kImage)), kPng);
      EXPECT_EQ(value<std::string>((*r)->graph(), albedo, ta::kMimeType), "image/png") << "from the bytes when the file says nothing";
    } else {
      EXPECT_NE(r.status().message().find("images[0].uri"), std::string::npos) << r.status().message();
      EXPECT_EQ(r.status().message().find("\x89PNG"), std::string::npos) << "never echoes file bytes";
    }
  }
}

TEST(MeshLookExport, what_gltf_cannot_carry_is_left_out_with_a_note) {
  TempDir dir;
  const Synthetic s = synthetic(false);
  auto imported = import_gltf(write_model(s.model, dir.path() / "quad.gltf"));
  ASSERT_TRUE(imported.is_ok()) << imported.status().message();
  Graph& g = (*imported)->graph();
  const NodeId mesh = only_node_of_type(g, scene::kMeshType);
  // uv0 with 3 numbers for 4 points: left out, and so uv1 (glTF numbers sets
  // from 0) and the material (it reads uv set 1).
  ASSERT_TRUE(g.set_value(Plug{mesh, la::kUv0, -1}, std::vector<double>{0.0, 1.0, 2.0}).is_ok());
  ASSERT_TRUE(g.set_value(Plug{mesh, la::kColors, -1}, std::vector<double>(16, 2.0)).is_ok());
  const fs::path out = dir.path() / "out.glb";
  GltfExportReport report;
  ASSERT_TRUE(export_gltf(**imported, out, {}, &report).is_ok());
  auto noted = [&](const std::string& text) {
    for (const std::string& n : report.notes)
      if (n.find(text) != std::string::npos) return true;
    return false;
  };
  EXPECT_TRUE(noted("quad.uv0: 3 numbers for 4 points (2 per point expected) are left out"));
  EXPECT_TRUE(noted("quad.uv1: left out"));
  EXPECT_TRUE(noted("reads uv set 1, which the mesh lacks"));
  EXPECT_TRUE(noted("quad.colors: values outside [0, 1] are clamped"));
  const tinygltf::Model model = read_model(out);
  const tinygltf::Primitive& p = model.meshes[0].primitives[0];
  EXPECT_FALSE(p.attributes.count("TEXCOORD_0"));
  EXPECT_FALSE(p.attributes.count("TEXCOORD_1"));
  EXPECT_EQ(p.material, -1);
  expect_near_all(accessor_values(model, p.attributes.at("COLOR_0")), std::vector<double>(12, 1.0), 0.0, "clamped, RGB");
  expect_valid(out);

  // A texture whose image is not PNG or JPEG, and a broken base64 image.
  ASSERT_TRUE(g.set_value(Plug{mesh, la::kUv0, -1}, s.uv0).is_ok());
  const NodeId material = only_node_of_type(g, scene::kMaterialType);
  ASSERT_TRUE(g.set_value(Plug{material, ma::kBaseColorTexCoord, -1}, std::int64_t{0}).is_ok());
  ASSERT_TRUE(g.set_value(Plug{material, ma::kEmissiveTexCoord, -1}, std::int64_t{0}).is_ok());
  const NodeId albedo = source_node(g, material, ma::kBaseColorTexture);
  ASSERT_TRUE(g.set_value(Plug{albedo, ta::kMimeType, -1}, std::string("image/webp")).is_ok());
  report = {};
  ASSERT_TRUE(export_gltf(**imported, out, {}, &report).is_ok());
  EXPECT_TRUE(noted("image/webp is left out")) << "the webp texture is dropped";
  const tinygltf::Model model2 = read_model(out);
  ASSERT_EQ(model2.materials.size(), 1u);
  EXPECT_EQ(model2.meshes[0].primitives[0].material, 0) << "uv0 again: the material is written";
  EXPECT_EQ(model2.materials[0].pbrMetallicRoughness.baseColorTexture.index, -1);
  EXPECT_GE(model2.materials[0].normalTexture.index, 0);
  expect_valid(out);
  ASSERT_TRUE(g.set_value(Plug{albedo, ta::kImage, -1}, std::string("not*base64")).is_ok());
  ASSERT_TRUE(g.set_value(Plug{albedo, ta::kMimeType, -1}, std::string("image/png")).is_ok());
  const Status bad = export_gltf(**imported, out);
  ASSERT_FALSE(bad.is_ok());
  EXPECT_NE(bad.message().find(".image"), std::string::npos) << bad.message();
}

// ---- every bundled character ----

TEST(MeshLookBundled, every_character_imports_and_exports_with_its_materials) {
  TempDir dir;
  for (const auto& entry : fs::directory_iterator(gltf_dir())) {
    const fs::path path = entry.path();
    if (path.extension() != ".glb" && path.extension() != ".gltf") continue;
    SCOPED_TRACE(path.filename().string());
    const tinygltf::Model source = read_model(path);
    auto imported = import_gltf(path);
    ASSERT_TRUE(imported.is_ok()) << imported.status().message();
    const fs::path out = dir.path() / (path.stem().string() + ".glb");
    ASSERT_TRUE(export_gltf(**imported, out).is_ok());
    expect_valid(out);
    const tinygltf::Model model = read_model(out);
    std::set<int> used;
    for (const auto& mesh : source.meshes)
      for (const auto& prim : mesh.primitives)
        if (prim.material >= 0 && prim.attributes.count("POSITION") && (prim.mode < 0 || prim.mode >= 4)) used.insert(prim.material);
    EXPECT_EQ(model.materials.size(), used.size()) << "every material a mesh uses";
    std::size_t uv_source = 0, uv_out = 0;
    for (const auto& mesh : source.meshes)
      for (const auto& prim : mesh.primitives) uv_source += prim.attributes.count("TEXCOORD_0");
    for (const auto& mesh : model.meshes)
      for (const auto& prim : mesh.primitives) uv_out += prim.attributes.count("TEXCOORD_0");
    EXPECT_EQ(uv_out, uv_source) << "every uv set";
  }
}

}  // namespace
}  // namespace rigel::io
