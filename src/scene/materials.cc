#include "rigel/scene/materials.h"

#include <cstdint>
#include <string>
#include <vector>

#include "rigel/math/types.h"

namespace rigel::scene {
namespace {

using graph::AttrSpec;
using graph::AttrType;
using graph::Value;
using graph::ValueType;

constexpr AttrType kMessage{ValueType::kMessage, false};
constexpr AttrType kInt{ValueType::kInt, false};
constexpr AttrType kDouble{ValueType::kDouble, false};
constexpr AttrType kDoubles{ValueType::kDouble, true};
constexpr AttrType kString{ValueType::kString, false};

AttrSpec message(std::string name) {
  AttrSpec a;
  a.name = std::move(name);
  a.type = kMessage;
  a.flags = graph::kInput;
  return a;
}

AttrSpec input(std::string name, AttrType type, Value value, std::uint32_t extra = 0) {
  return graph::input_attr(std::move(name), type, std::move(value), {}, extra);
}

// A texture slot: the texture (message) and the uv set it reads.
void slot(std::vector<AttrSpec>& attrs, const std::string& name) {
  attrs.push_back(message(name + "Texture"));
  attrs.push_back(input(name + "TexCoord", kInt, std::int64_t{0}));
}

}  // namespace

void add_mesh_look_attrs(graph::NodeTypeSpec& mesh) {
  mesh.attrs.push_back(input("uv0", kDoubles, std::vector<double>{}));
  mesh.attrs.push_back(input("uv1", kDoubles, std::vector<double>{}));
  mesh.attrs.push_back(input("colors", kDoubles, std::vector<double>{}));
  mesh.attrs.push_back(message("material"));
}

Status register_material_types(graph::Registry& registry) {
  graph::NodeTypeSpec material;
  material.name = kMaterialType;
  material.description = "A glTF metallic-roughness material; its message feeds mesh.material";
  std::vector<AttrSpec>& a = material.attrs;
  a.push_back(message("message"));
  a.push_back(input("baseColorFactor", kDoubles, std::vector<double>{1.0, 1.0, 1.0, 1.0}));
  slot(a, "baseColor");
  a.push_back(input("metallicFactor", kDouble, 1.0));
  a.push_back(input("roughnessFactor", kDouble, 1.0));
  slot(a, "metallicRoughness");
  slot(a, "normal");
  a.push_back(input("normalScale", kDouble, 1.0));
  slot(a, "occlusion");
  a.push_back(input("occlusionStrength", kDouble, 1.0));
  slot(a, "emissive");
  a.push_back(input("emissiveFactor", {ValueType::kDouble3, false}, math::Vec3(math::Vec3::Zero())));
  AttrSpec alpha_mode = input("alphaMode", {ValueType::kEnum, false}, std::int64_t{0});
  alpha_mode.enum_names = {"opaque", "mask", "blend"};
  a.push_back(std::move(alpha_mode));
  a.push_back(input("alphaCutoff", kDouble, 0.5));
  a.push_back(input("doubleSided", {ValueType::kBool, false}, false));
  if (Status s = registry.add(std::move(material)); !s) return s;

  graph::NodeTypeSpec texture;
  texture.name = kTextureType;
  texture.description = "A glTF texture: an image (base64 bytes) and its sampler; its message feeds material slots";
  texture.attrs = {message("message"),
                   input("image", kString, std::string(), graph::kHidden),
                   input("mimeType", kString, std::string()),
                   input("imageName", kString, std::string()),
                   input("magFilter", kInt, std::int64_t{0}),
                   input("minFilter", kInt, std::int64_t{0}),
                   input("wrapS", kInt, std::int64_t{10497}),
                   input("wrapT", kInt, std::int64_t{10497})};
  return registry.add(std::move(texture));
}

}  // namespace rigel::scene
