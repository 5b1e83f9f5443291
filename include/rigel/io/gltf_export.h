#pragma once
// glTF 2.0 export: a scene's transform hierarchy, meshes, skins, morph
// targets and animation, written as .glb (binary) or .gltf (JSON with the
// buffer embedded), atomically. What `rigel export` runs.
//
// The mapping (what a glTF viewer then shows is what rigel evaluates):
//
// - Every transform-type node (transform, joint, control, locator, mesh)
//   becomes a glTF node with its name and `extras.uuid` (the rigel uuid),
//   children in creation order, except a mesh node the glTF importer made
//   (tag gltf.node, kTagGltfNode in gltf_import.h): its mesh goes back on the
//   node that tag names, so import -> export keeps the node tree and names,
//   when that node has no mesh of its own (the first such mesh node wins),
//   the mesh node has no children and is no joint, and it is skinned (glTF
//   ignores a skinned node's transform) or sits under that node with an
//   identity transform nothing animates. Its own transform channels are
//   dropped (identity, or ignored when skinned); morph weights follow. Its
//   local transform (offsetParentMatrix * matrix, evaluated at the scene's
//   current time) is written as translation / rotation / scale, never as
//   `matrix` (glTF allows only TRS matrices, and animates TRS only). Shear
//   cannot be carried: each node's TRS is the one that puts it at its world
//   position under its parent's glTF transform, so every node keeps its
//   world position and a frame loses the shear it has or inherits; an
//   unskinned mesh's points (normals, morph deltas) and a skin's inverse
//   bind matrices take up the difference, so vertices land where rigel puts
//   them (exact at the export time; baked frames place every node the same
//   way, keeping the corrections made at the export time).
//   Shear above 1e-4 is listed in the report's notes; a node animated by
//   direct keys below a sheared node makes the export bake.
//   Non-transform nodes (curves, deformers, constraints, ...) are not
//   written; their effect is, through animation.
// - A `mesh` node with points and triangles gets a glTF mesh of one
//   triangle primitive: POSITION (with min/max), NORMAL when the normals
//   match the points, indices as UNSIGNED_SHORT when every index fits below
//   65535, else UNSIGNED_INT. Points are the evaluated `points`, except:
//   * points fed by a blendShape's outPoints: the blendShape's basePoints,
//     and one morph target per blendShape target (sparse targets made
//     dense), with the blendShape's weights as the mesh's default weights
//     and its targetNames (when any is set) as the mesh's
//     extras.targetNames;
//   * a skinned mesh (points fed by a skinCluster's outPoints): the
//     skinCluster's bindPoints / bindNormals (or, when bindPoints is fed by
//     a blendShape, that blendShape's basePoints and targets), and a glTF
//     skin: joints are the transform nodes whose worldMatrix feeds
//     jointMatrices[i], in index order; inverseBindMatrices are
//     bindPreMatrices (identity where missing); JOINTS_n / WEIGHTS_n hold
//     each vertex's influences sorted by weight, largest first, normalised to
//     sum to 1 and padded with zeros, four per set (a vertex with six
//     influences makes JOINTS_0 and JOINTS_1); JOINTS_n are bytes up to 256
//     joints, else 16-bit. glTF wants a skin's joints under one common
//     root: when they sit in separate trees, one identity node named
//     "skeleton_root" (suffixed if taken) is added above those trees.
//   glTF draws a skinned mesh at sum(w * J * B * p) in world space and
//   ignores its node's transform, while a skinCluster's outPoints are
//   inverse(geomMatrix) * sum(w * J * B * p) in the mesh's local space: the
//   two agree exactly when the mesh node's world matrix equals geomMatrix.
//   The exporter checks that (within 1e-9, at the export time and at every
//   baked frame) and fails naming the mesh and the skinCluster otherwise: no
//   correction can be folded into joints or inverse bind matrices, since it
//   would have to apply after the joint matrices. A skinned mesh's glTF
//   node is a root (as the glTF validator asks) whose transform is the mesh
//   node's world matrix (identity in what the glTF importer makes), so
//   children it may have keep their world placement; when such a mesh has
//   a parent and moves (its own channels or its parent's), the export bakes.
// - Animation, in one of two ways:
//   * direct (the default when possible, lossless): an animCurveVec3 feeding
//     translate or scale, an animCurveQuat feeding rotateQuaternion (with
//     rotateMode quaternion), become channels with the track's own keys and
//     interpolation (STEP, LINEAR, CUBICSPLINE with its tangents); a joint's
//     jointOrient and a rotateAxis are folded into the rotation keys
//     (JO * q * RA, exact for every interpolation). Nodes with pivots, shear
//     or an offsetParentMatrix, curves with negative key times or keys too
//     close for 32-bit times, and curves whose own inputs are driven, are
//     baked instead. Scalar animCurve nodes
//     feeding blendShape.weights[i] become one `weights` channel per mesh,
//     sampled at the union of the curves' key times: STEP when every curve
//     has step tangents, else LINEAR (plus every frame between the keys
//     when a curve is not linear between them, Maya's curved tangents).
//   * baked (options.frames, options.bake, or automatically when something
//     animated cannot be written directly: Euler rotation tracks, Maya
//     curves on single channels, driven keys, constraints, IK, ...; the
//     report says why): each frame from A to B at the scene's frame rate,
//     and every key time of the scene's time curves between them (so a key
//     between frames keeps its value; times 32-bit floats cannot tell apart
//     are written once), is evaluated and every node's local translation, rotation (sign kept
//     continuous from frame to frame) and scale recorded, and every exported
//     blendShape's weights; LINEAR channels are written for those that
//     change over the range, or whose constant value differs from the
//     node's static value. Without frames, the range is the union of the
//     key ranges of the scene's time curves (animCurve, animCurveVec3,
//     animCurveQuat), rounded out to whole frames, starting at 0 at the
//     earliest (glTF times are not negative).
//   Clips (an animClips node, see ops/anim/clips.h): every clip becomes its
//   own glTF animation named after it; direct channels take each curve's
//   keys of that clip, baking makes each clip active in turn and bakes its
//   start..end (with options.frames: only the active clip, over those
//   frames). Without clips there is one animation, "animation".
//   The static transform of a channel fed by a clip curve is the curve's
//   restValue (the node's own TRS in an imported glTF), so what a viewer
//   shows with no animation playing survives import -> export.
//   Baking changes the scene's time and active clip and puts both back.
// - A mesh's uv0/uv1, colors and material (scene/materials.h) become
//   TEXCOORD_0/1, COLOR_0 and the primitive's material, with its textures,
//   samplers and images (each written once); docs/ARCHITECTURE.md, "How
//   meshes look", lists what is left out with a note.
// - Units, axes and times are written as they are (seconds, the scene's
//   units); rigel and glTF share right-handed Y-up axes.

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/scene/scene.h"

namespace rigel::io {

struct GltfExportOptions {
  // Bake frames [first, last] (scene frames, at the scene's fps; first <= last,
  // first >= 0). Implies baking.
  std::optional<std::pair<double, double>> frames;
  // Bake even when every channel could be written directly (over `frames`,
  // or the default range).
  bool bake = false;
  // The deform skeleton only (seed 004's baker, skeleton mode; what a game
  // engine imports): every transform whose worldMatrix feeds a
  // skinCluster's jointMatrices (in a scene without skins: every joint) and
  // every mesh; controls, rig groups, helper joints and everything else are
  // left out. A node whose parent is left out hangs from its nearest
  // exported ancestor (or the root), placed by world matrices, so every
  // joint keeps its world matrix (shear aside, as always). Implies baking.
  bool deform_only = false;
  // A scene without skinClusters: its joints become one glTF skin named
  // "skeleton" (inverse bind matrices: the joints' world matrices at export,
  // inverted) that no mesh uses, so a reader (rigel's importer among them)
  // keeps them as joints rather than plain nodes. What `rigel import-guides`
  // writes its skeleton with. Ignored when the scene has a skinned mesh.
  bool skeleton_skin = false;
  // Called while baking with the fraction done, in [0, 1]; may be empty.
  std::function<void(double)> progress;
};

// What an export wrote; filled on success.
struct GltfExportReport {
  std::size_t node_count = 0;
  std::size_t mesh_count = 0;
  std::size_t skin_count = 0;
  std::size_t animation_count = 0;
  std::size_t channel_count = 0;  // over every animation
  bool baked = false;
  // Why it baked: "requested (--frames)" / "requested" or the first channel
  // that cannot be written directly ("hips.rotate is animated with Euler
  // angles by hips_rotate (animCurveVec3)"). Empty when not baked.
  std::string bake_reason;
  double first_frame = 0.0, last_frame = 0.0;  // the baked range, when baked
  // Things the file cannot carry and that were left out or changed (shear on
  // an animated node, a mesh without triangles, ...), one sentence each.
  std::vector<std::string> notes;
};

// Writes `scene` to `out`: binary glTF for ".glb", JSON glTF with the buffer
// embedded as a data URI for ".gltf" (the extension's case is ignored).
// Atomic: the file is written beside `out` and renamed over it, so a failed
// export leaves an existing file as it was. Fails, naming the node and
// attribute, on: another extension; frames that are not finite, negative or
// reversed; a mesh whose triangles are not a multiple of 3 or index beyond
// its points; a skinCluster whose weights do not validate, whose
// jointMatrices[i] is not fed by a transform's worldMatrix, or whose mesh's
// world matrix differs from its geomMatrix; data too large for glTF's
// 32-bit sizes; a write the operating system refuses.
Status export_gltf(scene::Scene& scene, const std::filesystem::path& out, const GltfExportOptions& options = {},
                   GltfExportReport* report = nullptr);

}  // namespace rigel::io
