#pragma once
// Keys and poses on ephemeral rigs (seed 000's future work: key the controls
// directly, not locators; seed 001's keying groups and merged characters).
//
// Keys live on control channels: translate, and rotate (Euler controls) or
// rotateQuaternion (quaternion controls). An Euler channel is keyed by one
// `animCurve` per component (ctrl.translateX <- curve.output); a quaternion
// rotation by an `animCurveQuat`, a translation may also be an
// `animCurveVec3` (what glTF import and setup_ephemeral's keep_animation
// bring). Curves that hold several clips are edited in the active clip.
//
// Keying scope (the `keyScope` attribute of each ephemeralRig, shown by
// `rigel pose` and `rigel ephemeral keys`): `character` (default) makes the
// character a keying group: a key on any of its controls keys every
// control of the character, and of the characters merged with it, at that
// time, so all share key times and a key is a pose. `controls` keys only
// the controls named.
//
// Merging (for ephemeral interaction, e.g. a prop carried by a hand for part
// of a shot): merged characters share a `mergeGroup`; body mode moves them
// together and the keying group spans them. A merged character may name a
// `carrier`, a control of another character of its group: the carrier then
// drives the character's root controls (a forward relation, and inverse back
// up), so the prop follows the hand in every mode. Unmerging clears both;
// the keys already set keep the carried poses.
//
// Every edit here is one undo step.

#include <optional>
#include <string_view>
#include <utility>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/ephemeral/rig.h"
#include "rigel/graph/value.h"

namespace rigel::ephemeral {

enum class KeyScope : std::int64_t { kCharacter = 0, kControls = 1 };
// "character", "controls".
const char* key_scope_name(KeyScope scope);
std::optional<KeyScope> key_scope_from_name(std::string_view name);

KeyScope key_scope(const Graph& graph, NodeId rig);
Status set_key_scope(Graph& graph, NodeId rig, KeyScope scope);

// ---- merging -----------------------------------------------------------------

// Puts `rigs` (two or more ephemeralRig nodes) in one merge group; a rig
// already merged elsewhere brings its group along.
Status merge_characters(Graph& graph, const std::vector<NodeId>& rigs);
// Takes `rig` out of its group (clearing its carrier, and the carrier of any
// rig of the group that pointed into it). Ok when it was not merged.
Status unmerge_character(Graph& graph, NodeId rig);
// `rig` and every rig merged with it, in creation order.
std::vector<NodeId> merged_rigs(const Graph& graph, NodeId rig);
// Makes `carrier` (a control of another character of rig's merge group)
// carry rig's root controls; an invalid id clears it.
Status set_carrier(Graph& graph, NodeId rig, NodeId carrier);
// Rig's carrier control; invalid when none (or it is no longer merged).
NodeId carrier_of(const Graph& graph, NodeId rig);
// The relations carriers add: carrier -> each root control of the carried
// rig (forward) and back (inverse). Sessions walk them with the rigs' own.
std::vector<Relation> carrier_relations(const Graph& graph);

// ---- keys --------------------------------------------------------------------

// A key within kKeyFrameTolerance frames of a time is the key at that time,
// wherever keys are looked up by time (has_key_now, write_channel, set_key,
// delete_key, key_times; the CLI, the server's key routes and Python all go
// through these): glTF clips store times in float seconds, so CesiumMan's
// key at frame 38 sits at frame 37.999921. A drag or key at frame 38 edits
// that key (its time is kept). Keys of one curve closer than this are one
// key for lookups (the nearest is edited).
inline constexpr double kKeyFrameTolerance = 1e-3;
// kKeyFrameTolerance in seconds at the graph's frame rate (never below
// ops::anim::kKeyTimeTolerance, 1e-6 s).
double key_time_tolerance(const Graph& graph);

// What a key on `controls` keys: with scope `character`, every control of
// their characters and the characters merged with them; with `controls`,
// the controls themselves. Joints stand for their controls. Rig order.
std::vector<NodeId> keying_set(const Graph& graph, const std::vector<NodeId>& controls);

// Keys keying_set(controls) at the graph's time with their current values:
// a key at that time is updated, otherwise one is inserted; channels with no
// curve get one. Fails, changing nothing, when a channel is driven by
// something that is not a curve (a constraint, say).
Status set_key(Graph& graph, const std::vector<NodeId>& controls);
// Removes the keys of keying_set(controls) at the graph's time; a curve left
// without keys is deleted and its channel keeps its current value.
// kNotFound when none of them has a key there.
Status delete_key(Graph& graph, const std::vector<NodeId>& controls);
// Removes the key at the graph's time (within key_time_tolerance()) from
// the curves driving channel `attr` of `node` (any keyed channel of any
// node; tools/keys.h deletes through it); a curve left without keys is
// deleted and the channel keeps its current value. `removed` says whether
// there was a key. Not a transaction of its own: callers group the channels.
Status delete_channel_key(Graph& graph, NodeId node, graph::AttrIndex attr, bool& removed);
// delete_channel_key on each (node, attribute), one undo step; kNotFound,
// changing nothing, when none of them has a key at the graph's time.
Status delete_channel_keys(Graph& graph, const std::vector<std::pair<NodeId, graph::AttrIndex>>& channels);
// Sorted key times (seconds) of the channels of keying_set(controls); times
// within key_time_tolerance() of the one before are listed once.
std::vector<double> key_times(const Graph& graph, const std::vector<NodeId>& controls);
// True when `control` has a key at the graph's time (within
// key_time_tolerance()).
bool has_key_now(const Graph& graph, NodeId control);
// True when a channel of `control` is driven by a curve.
bool is_keyed(const Graph& graph, NodeId control);

// Writes `value` into a control channel (attr translate, rotate or
// rotateQuaternion). Free channels are set. Keyed channels: the key at the
// graph's time (within key_time_tolerance(); its time is kept) takes the
// value; with no key there, one is inserted when `insert`, else
// kInvalidArgument naming the channel and the frame. Channels driven by
// anything else, or component curves of one channel whose keys near the
// time are more than 1e-6 s apart: kInvalidArgument naming the channel.
Status write_channel(Graph& graph, NodeId control, graph::AttrIndex attr, const graph::Value& value, bool insert);

}  // namespace rigel::ephemeral
