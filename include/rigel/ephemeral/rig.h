#pragma once
// Ephemeral rigs (seeds 000 and 001): one control per joint, each driving its
// joint, and directed relations between the controls that a Session walks
// when the animator grabs controls (see session.h and docs/EPHEMERAL.md).
//
// What setup_ephemeral() builds, for every joint it is given:
// - a `control` named <joint><suffix>, parented like the joint (under the
//   control of the joint's parent joint, else under the joint's own parent),
//   holding the joint's channels (translate, rotate, rotateOrder, rotateMode,
//   rotateQuaternion, scale, shear, rotateAxis, offsetParentMatrix), so its
//   world matrix is the joint's;
// - connections control.{translate, rotate, rotateQuaternion, scale} ->
//   joint.{same}: the joint follows its control, keys live on the control;
//   connections that fed those joint channels (animation curves) are moved
//   onto the control (or dropped, keeping the current pose:
//   SetupOptions::keep_animation);
// - one `ephemeralRig` node listing the controls (by uuid, so renames never
//   break it) and the relations: forward parent -> child and inverse
//   child -> parent for every control whose parent is a control.
// Everything is one undo step.
//
// Controls mirror the joint hierarchy (the seed's future-work suggestion:
// "storing the controllers in a hierarchy ... would set the default state of
// the rig as forward"), so FK is free: forward mode writes the grabbed
// control only, and keys on control channels interpolate as FK.

#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/graph/graph.h"
#include "rigel/rig/definition.h"
#include "rigel/scene/scene.h"

namespace rigel::ephemeral {

using graph::Graph;
using graph::NodeId;

inline constexpr const char* kRigType = "ephemeralRig";

// Attributes of `ephemeralRig` (all storable inputs, no outputs):
namespace rig_attr {
enum : graph::AttrIndex {
  kControls = 0,   // string[]: uuids of the controls
  kRelationKind,   // int[]: RelationKind of relation i
  kRelationFrom,   // int[]: index into controls of relation i's driver
  kRelationTo,     // int[]: index into controls of relation i's driven control
  kKeyScope,       // enum character, controls: what a key keys (keying.h)
  kMergeGroup,     // string: rigs with the same non-empty group are merged (keying.h)
  kCarrier,        // string: uuid of the control of a merged rig that carries this rig's roots
  kCount
};
}

// A directed relation: `from` may drive `to`.
enum class RelationKind : std::int64_t {
  kForward = 0,  // parent drives child (walked in forward mode, and from whatever moves)
  kInverse = 1,  // child drives parent (walked by inverse and pseudo-inverse chains)
  kPair = 2,     // moves as one unit with (in every mode); groups are pairs both ways
  kMagnet = 3,   // extra magnet link (magnet mode walks forward, inverse, pair and magnet)
};
inline constexpr int kRelationKindCount = 4;
const char* relation_kind_name(RelationKind kind);
std::optional<RelationKind> relation_kind_from_name(std::string_view name);

struct Relation {
  RelationKind kind = RelationKind::kForward;
  NodeId from;
  NodeId to;
  friend bool operator==(const Relation&, const Relation&) = default;
};

// Adds the `ephemeralRig` type.
Status register_ephemeral_types(graph::Registry& registry);
// rig::default_registry() types (ops and the metadata network) plus the
// ephemeral types. Shared, immutable.
std::shared_ptr<const graph::Registry> default_registry();

struct SetupOptions {
  // Joints to rig; empty: every joint in the scene.
  std::vector<NodeId> joints;
  // Control name = joint name + suffix.
  std::string control_suffix = "_ctrl";
  // Name of the ephemeralRig node.
  std::string rig_name = "ephemeralRig";
  // true: connections into the joints' driven channels (animation curves)
  // move onto the controls. false: they are broken and the current values
  // kept (a pose to edit without keys).
  bool keep_animation = true;
  // Radius of the circle drawn for each control (its shapePoints), in the
  // control's space; 0 draws nothing. The circle is coloured by the side
  // the joint's name says (side_from_name): left blue, right red, centre
  // yellow, as the bundled biped's components colour theirs.
  double shape_radius = 0.0;
  // true: each circle sized from its joint's bones (a third of its shortest
  // bone to a child, a leaf's from its parent), shape_radius the largest
  // and a tenth of it the smallest: a face's or a hand's short bones get
  // small controls.
  bool size_from_bones = false;

  // The option at fault (kInvalidArgument, Status::field() its API name:
  // "shapeRadius" not a number >= 0, "controlSuffix" that makes control
  // names invalid, "rigName" not a valid node name). setup_ephemeral checks
  // it first; drivers call it to say which of their options is wrong.
  Status validate() const;
};

struct SetupResult {
  NodeId rig;
  std::vector<NodeId> joints;    // parent first
  std::vector<NodeId> controls;  // controls[i] drives joints[i]
};

// Builds an ephemeral rig (see the top of this file). Fails, changing
// nothing, when the scene has none of the joints, a joint has a joint orient,
// pivots or an offset parent matrix fed by a connection (controls have no
// joint orient; pivots are not supported by the solver), a joint already has
// a control, or a scene or registry lacks the ephemeralRig type.
Result<SetupResult> setup_ephemeral(scene::Scene& scene, const SetupOptions& options = {});

// ---- reading and editing relations (each edit is one undo step) -----------

// Every ephemeralRig node, in creation order.
std::vector<NodeId> rigs_find(const Graph& graph);
// The rig listing `control`; invalid when none.
NodeId rig_of(const Graph& graph, NodeId control);
// The control standing for `id`: itself when it is a control of an
// ephemeral rig, or the rig control driving a joint (selecting or keying a
// joint means its control); invalid otherwise.
NodeId control_of(const Graph& graph, NodeId id);
// The rig's controls that exist (stale uuids are skipped), in listed order.
std::vector<NodeId> rig_controls(const Graph& graph, NodeId rig);
// The rig's relations between existing controls.
Result<std::vector<Relation>> relations(const Graph& graph, NodeId rig);
// Adds a relation between two controls of `rig` (or adds `to`/`from` to the
// rig's control list when it is a control that is in no rig). Fails when it
// exists already, or from == to.
Status relation_add(Graph& graph, NodeId rig, const Relation& relation);
// Removes a relation; kNotFound when it does not exist.
Status relation_remove(Graph& graph, NodeId rig, const Relation& relation);
// Changes the kind of an existing relation.
Status relation_set_kind(Graph& graph, NodeId rig, const Relation& relation, RelationKind kind);
// Pair relations both ways between every two of `controls` (a group moves as
// one unit; more than two allowed). One undo step.
Status group_add(Graph& graph, NodeId rig, const std::vector<NodeId>& controls);

// The side a joint's name says, for colouring its control: after any
// "namespace:", the first of the tokens L/R, l/r, Left/Right, left/right and
// LEFT/RIGHT on a word boundary, as rig::mirror_name finds side tokens
// (rig::side_of_name): Rigify's thigh.L, f_index.01.L and ear.L.001,
// Mixamo's LeftArm and UpperArmLeft, hand-L and foot r; anything else
// (Leftover, Lower) is the centre.
using NameSide = rig::Side;
NameSide side_from_name(std::string_view name);

}  // namespace rigel::ephemeral
