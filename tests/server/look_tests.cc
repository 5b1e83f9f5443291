// GET /api/character.glb carries the character's look: CesiumMan's
// material, its texture's image bytes and its uv set, so the web viewport
// (three.js GLTFLoader) draws it textured rather than grey.

#include <cstdint>
#include <cstring>
#include <string>

#include "server_test_util.h"

namespace rigel::server {
namespace {

// The JSON and BIN chunks of a .glb.
struct Glb {
  Json json;
  std::string bin;
};

Glb parse_glb(const std::string& bytes) {
  Glb out;
  auto u32 = [&](std::size_t at) {
    std::uint32_t v = 0;
    if (at + 4 <= bytes.size()) std::memcpy(&v, bytes.data() + at, 4);
    return std::size_t{v};
  };
  EXPECT_EQ(bytes.substr(0, 4), "glTF");
  const std::size_t json_length = u32(12);
  out.json = Json::parse(bytes.substr(20, json_length));
  const std::size_t bin_at = 20 + json_length;
  if (bin_at + 8 <= bytes.size()) out.bin = bytes.substr(bin_at + 8, u32(bin_at));
  return out;
}

// The bytes of image `index` (held in a bufferView of the BIN chunk).
std::string image_bytes(const Glb& glb, std::size_t index) {
  const Json& image = glb.json.at("images").at(index);
  const Json& view = glb.json.at("bufferViews").at(image.at("bufferView").get<std::size_t>());
  return glb.bin.substr(view.value("byteOffset", std::size_t{0}), view.at("byteLength").get<std::size_t>());
}

TEST(ServerApi, CharacterGlbCarriesTheMaterialAndTexture) {
  Served s;
  s.root = s.dir->path() / "root";
  fs::create_directories(s.root);
  io::GltfImportOptions options;
  options.registry = ephemeral::default_registry();
  auto imported = io::import_gltf(source_path("tests/data/gltf/CesiumMan.glb"), options);
  ASSERT_TRUE(imported.is_ok()) << imported.status().message();
  s.workspace = std::make_unique<Workspace>(std::move(*imported), fs::path(), s.root, ephemeral::components());

  Response r = s.request("GET", "/api/character.glb", "");
  ASSERT_EQ(r.status, 200);
  const Glb served = parse_glb(r.body);
  const Glb source = parse_glb(read_text(source_path("tests/data/gltf/CesiumMan.glb")));
  ASSERT_EQ(served.json.value("images", Json::array()).size(), 1u) << served.json.dump().substr(0, 400);
  const std::string image = image_bytes(source, 0);
  ASSERT_GT(image.size(), 1000u);
  EXPECT_EQ(image_bytes(served, 0), image) << "the texture's image, byte for byte";
  EXPECT_EQ(served.json["images"][0]["mimeType"], source.json["images"][0]["mimeType"]);
  ASSERT_EQ(served.json.value("materials", Json::array()).size(), 1u);
  EXPECT_EQ(served.json["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["index"], 0);
  EXPECT_EQ(served.json["textures"][0]["source"], 0);
  const Json& primitive = served.json["meshes"][0]["primitives"][0];
  EXPECT_EQ(primitive["material"], 0);
  EXPECT_TRUE(primitive["attributes"].contains("TEXCOORD_0"));
  // What the page loads is a valid glTF file.
  const fs::path file = s.root / "served.glb";
  io::testing::write_text(file, r.body);
  EXPECT_VALID_GLTF(file);
}

}  // namespace
}  // namespace rigel::server
