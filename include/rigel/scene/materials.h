#pragma once
// How a mesh looks: node types `material` and `texture`, and the mesh
// attributes that carry texture coordinates, vertex colours and the
// material assignment. They mirror glTF 2.0's core material model, so a
// character imported from glTF keeps its look through `.rigel` files and
// export (docs/ARCHITECTURE.md, "glTF interchange").
//
// - mesh (transform_types.h) ends with: uv0, uv1 (double arrays, u v per
//   point: TEXCOORD_0 / TEXCOORD_1, glTF's convention, v down from the
//   image's top), colors (double array, r g b a per point, linear, COLOR_0)
//   and material (message, fed by a material's `message`). Arrays that do
//   not hold one element per point are ignored by the exporter (with a
//   note), as normals are. Skinning and blend shapes move points and never
//   change the topology, so these stay aligned with the points.
// - material: the pbrMetallicRoughness factors and textures, normal,
//   occlusion and emissive textures, alphaMode, alphaCutoff, doubleSided.
//   A texture slot is a message input fed by a texture's `message`, with
//   its texCoord (which uv set) beside it.
// - texture: one glTF texture with its image and sampler folded in: the
//   image's bytes (base64 in `image`, so a .rigel file stays one
//   self-contained file), mimeType, the image's name, and the sampler's
//   magFilter / minFilter (glTF's codes, 0 = unset) and wrapS / wrapT.

#include "rigel/base/status.h"
#include "rigel/graph/node_type.h"
#include "rigel/scene/transform_types.h"

namespace rigel::scene {

inline constexpr const char* kMaterialType = "material";
inline constexpr const char* kTextureType = "texture";

// The mesh attributes after mesh_attr::kTriangles (transform_types.cc
// appends them in this order; scene tests hold it).
namespace mesh_look_attr {
enum : AttrIndex { kUv0 = mesh_attr::kCount, kUv1, kColors, kMaterial, kCount };
}

namespace material_attr {
enum : AttrIndex {
  kMessage = 0,                 // message: feeds mesh.material
  kBaseColorFactor,             // double[4], default 1 1 1 1
  kBaseColorTexture,            // message, fed by texture.message
  kBaseColorTexCoord,           // int
  kMetallicFactor,              // double, default 1
  kRoughnessFactor,             // double, default 1
  kMetallicRoughnessTexture,    // message
  kMetallicRoughnessTexCoord,   // int
  kNormalTexture,               // message
  kNormalTexCoord,              // int
  kNormalScale,                 // double, default 1
  kOcclusionTexture,            // message
  kOcclusionTexCoord,           // int
  kOcclusionStrength,           // double, default 1
  kEmissiveTexture,             // message
  kEmissiveTexCoord,            // int
  kEmissiveFactor,              // double3, default 0 0 0
  kAlphaMode,                   // enum opaque mask blend
  kAlphaCutoff,                 // double, default 0.5
  kDoubleSided,                 // bool
  kCount
};
}

namespace texture_attr {
enum : AttrIndex {
  kMessage = 0,  // message: feeds a material's texture slots
  kImage,        // string: the image file's bytes, base64 (RFC 4648, padded)
  kMimeType,     // string: image/png, image/jpeg, ...
  kImageName,    // string
  kMagFilter,    // int: 0 (unset), 9728 NEAREST, 9729 LINEAR
  kMinFilter,    // int: 0 (unset) or glTF's six codes
  kWrapS,        // int: 10497 REPEAT (default), 33071 CLAMP_TO_EDGE, 33648 MIRRORED_REPEAT
  kWrapT,        // int
  kCount
};
}

// Adds `material` and `texture` to `registry` (register_scene_types calls it).
Status register_material_types(graph::Registry& registry);

// Appends the look attributes (mesh_look_attr, in order) to the mesh type.
void add_mesh_look_attrs(graph::NodeTypeSpec& mesh);

}  // namespace rigel::scene
