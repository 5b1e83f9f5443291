#pragma once
// glTF 2.0 import: a .gltf (JSON, buffers embedded or in files beside it) or
// a .glb (binary container) becomes a scene of joints, transforms, meshes,
// skin and blend-shape deformers, materials and textures, and animation
// clips. The file is read with tinygltf (images are kept as bytes, never
// decoded), after the importer's own checks; nothing in a file can crash it.
//
// What each glTF object becomes (the glTF exporter relies on this mapping):
//
// Nodes. Every glTF node becomes one scene node, created in file order: a
// `joint` when some skin lists it in `joints`, else a `transform`. Names are
// kept; an unnamed node is `node_<index>`; characters a rigel name cannot
// hold (whitespace, control characters, '[' and ']') become '_'; a name
// already taken gets the graph's numeric suffix ("arm" -> "arm1", in file
// order). The hierarchy follows `children` (siblings end up in file order).
// TRS goes to translate, rotateMode = quaternion + rotateQuaternion
// (glTF's [x, y, z, w], normalised on use), scale. A `matrix` is decomposed
// exactly into translate, rotateQuaternion, scale and shear (math::decompose:
// m = T R SH S; a negative determinant becomes a negative scale x). It must
// be affine (last row 0 0 0 1).
//
// Meshes. Each primitive of a node's mesh becomes a `mesh` node (points =
// POSITION, normals = NORMAL, triangles). Its name is the glTF mesh's name,
// else `<node>_mesh`, with the primitive index appended when the mesh has
// more than one primitive. Its tag "gltf.node" (kTagGltfNode) holds the
// name of the scene node made from the glTF node that holds the mesh: the
// exporter writes the mesh back on that node, so import -> export keeps the
// node tree. Modes: TRIANGLES as they are, TRIANGLE_STRIP and
// TRIANGLE_FAN converted to triangles; POINTS and LINES primitives make no
// mesh node (their data is still checked). A primitive without POSITION
// makes no mesh node (glTF: clients skip it). Non-indexed primitives get
// indices 0..n-1. TEXCOORD_0/1 go to uv0/uv1, COLOR_0 to colors (RGBA), the
// primitive's material to a `material` node (with `texture` nodes holding
// the image bytes) connected to mesh.material: scene/materials.h, and
// docs/ARCHITECTURE.md ("How meshes look") for what is kept and refused.
// Other attributes (TEXCOORD_2 and above, COLOR_1 and above, TANGENT) are
// not imported.
// - Unskinned: the mesh node is a child of its glTF node's transform, with
//   an identity local transform.
// - Skinned (the glTF node has `skin`): the mesh node is a root with an
//   identity transform, because glTF ignores a skinned mesh node's own
//   transform and its parents' (joint world x inverse bind x vertex is in
//   scene space already). A `skinCluster` named `<mesh>_skinCluster` gets
//   bindPoints = POSITION, bindNormals = NORMAL, jointMatrices[i] connected
//   from the worldMatrix of skin.joints[i], bindPreMatrices = the inverse
//   bind matrices (identity when the skin has none), geomMatrix identity,
//   the influences of every JOINTS_n/WEIGHTS_n set (zero weights dropped,
//   repeated joints merged), normalizeWeights on (old exporters leave sums
//   that are not 1); its outPoints and outNormals feed the mesh's points
//   and normals. A joint index is checked only where its weight is not zero.
//   A vertex whose weights are all zero (valid glTF: sums of 1 are a
//   "should") follows the glTF node that holds the mesh: it is bound with
//   weight 1 to one more joint matrix, jointMatrices[joint count], fed by
//   that node's worldMatrix (bindPreMatrices identity there), and the import
//   warns, naming the vertices. A mesh with JOINTS_n used by a node without
//   `skin` is imported unskinned.
// - Morph targets: a `blendShape` named `<mesh>_blendShape` with basePoints
//   = POSITION, dense targetDeltas from each target's POSITION (a target
//   without POSITION has zero deltas; NORMAL and TANGENT deltas are not
//   imported), weights = the node's `weights`, else the mesh's, else 0,
//   and targetNames = the mesh's extras.targetNames (the common convention;
//   names that are not one string per target are left out, with a warning).
//   Its outPoints feed the skinCluster's bindPoints when skinned, else the
//   mesh's points.
//
// Animations. Every glTF animation is a clip; a file with animations gets
// one `animClips` node named `clips` (clipNames: the animation's name, else
// `animation_<index>`, made unique with a numeric suffix; clipStarts and
// clipEnds: the first and last key time of the animation's samplers; the
// first clip active). Each animated (node, path) gets ONE curve node holding
// the keys of every clip (clipOffsets), with `clip` connected from
// clips.activeClip and restValue = the node's value from the file, so a
// clip that does not animate the channel leaves it at rest:
// - translation, scale: `animCurveVec3` named `<node>_translate` /
//   `<node>_scale`, driving translate / scale;
// - rotation: `animCurveQuat` named `<node>_rotate`, driving rotateQuaternion;
// - weights: one scalar `animCurve` per morph target, `<node>_weight<i>`,
//   connected to weights[i] of every blendShape of the node. STEP keys get
//   step tangents, LINEAR keys linear tangents, CUBICSPLINE keys fixed
//   tangents whose slopes are glTF's in/out tangents (per second).
// Times stay in seconds (the scene keeps 24 fps). A vec3/quaternion curve
// has one interpolation for all its clips: when the clips of one channel
// disagree, LINEAR vec3 keys are converted exactly to CUBICSPLINE (tangents
// = the segment slopes) if the others are cubic; otherwise everything
// becomes LINEAR, STEP segments holding their value up to 1e-4 of the
// segment before the next key and CUBICSPLINE segments sampled 16 times
// per segment (an approximation, and the only one the importer makes).
// Channels whose target has no `node` (an extension's target) are skipped.
//
// Checks. Every problem fails the import with a Status whose message is
// "<file>: <element>: <what>", the element a JSON-pointer-like path:
//   "meshes[0].primitives[1].attributes.JOINTS_0: accessor 7 has 20
//    elements, POSITION has 24", "nodes[3].children[0]: node 9 does not
//   exist", "nodes[2]: node is its own ancestor (cycle 2 -> 5 -> 2)",
//   "accessors[4]: NaN in element 12", "buffers[0]: missing (uri 'x.bin'
//   not found)", "animations[0].samplers[2].input: times not increasing at
//   key 5".
// Refused: JSON that is not glTF 2.x (types, required members, indices
// out of range, empty top-level arrays, JSON nested deeper than 128
// levels); a .glb whose header or chunks do not fit the file; missing or
// short buffers; buffer views and accessors reaching outside their data;
// component types a semantic does not allow; NaN or infinite numbers;
// attribute counts that differ from POSITION's; indices not below the
// vertex count; a node with two parents; cycles; a skin whose joints repeat
// or have no common root, or whose `skeleton` is not a common root; too few
// inverse bind matrices, or (in a skin some node uses) ones that are not
// affine; a skin on a node without a mesh or on a mesh
// without JOINTS_0; a skinned mesh in a scene without its joints; a joint
// index not below the skin's joint count; negative weights; animation
// times that are not increasing; output counts that do not match the
// input; a (node, path) animated twice by one animation; required
// extensions that change geometry (Draco, meshopt). tinygltf's own load
// errors come prefixed with the file path. An accessor without a buffer
// view (all zeros) may have at most 2^24 elements. Transforms whose
// numbers overflow together (a matrix of 1e308, scales multiplying past a
// double's range: any non-finite local or world matrix or decomposition)
// are refused naming the node.
//
// External files. A buffer's URI is a data: URI or a file name relative to
// the glTF file's folder; it must stay inside that folder once decoded
// (%20 escapes) and once every symbolic link is resolved. Refused without
// reading or measuring the file: absolute paths, URIs with a scheme (file:,
// http:), ".." that climbs out, links that lead out. Messages never quote
// numbers read from a buffer (indices, joints, weights, times, matrices):
// a buffer is a file, and its bytes stay private; they name the element
// and the rule broken ("indices: element 2 is not below the vertex count 3").

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/scene/scene.h"

namespace rigel::io {

// The tag on an imported mesh node naming the node its glTF mesh
// hangs on; see "Meshes" above and gltf_export.h.
inline constexpr const char* kTagGltfNode = "gltf.node";

struct GltfImportOptions {
  // Multiplies translations (node TRS and matrices, translation keys and
  // tangents), positions, morph deltas and the translations of inverse bind
  // matrices: a uniform change of units. Must be positive and finite.
  double scale = 1.0;
  // The node types the scene is built over; null: ops::default_registry().
  // A registry given must hold those types (a higher layer's superset, such
  // as ephemeral::default_registry(), so rigs can be built on the result).
  std::shared_ptr<const graph::Registry> registry;
  // Where the importer says what it did that the file did not ask for in so
  // many words (one sentence each, naming the element); may be null.
  std::vector<std::string>* warnings = nullptr;
};

// Reads a .gltf or .glb (told apart by content: a .glb starts with the
// magic "glTF"; external buffers are resolved relative to the file's
// folder) and builds a scene over the options' registry. The undo history
// of the new scene is empty.
Result<std::unique_ptr<scene::Scene>> import_gltf(const std::filesystem::path& path,
                                                  const GltfImportOptions& options = {});

}  // namespace rigel::io
