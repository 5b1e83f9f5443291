#pragma once
// Animation clips: the named animations of a character (a glTF file's
// `animations`), one of them active at a time.
//
// An animClips node lists the clips (name, start and end time in seconds)
// and publishes the active clip's index on `activeClip`; every curve that
// holds keys of several clips (clipOffsets, see nodes.h) has its `clip`
// input connected from it. Switching clips is one set_value on `active`:
// undoable, saved with the scene, and it dirties exactly the clip curves.
//
// The glTF importer makes one animClips node, named "clips", when a file
// has any animation; `rigel eval --clip NAME|INDEX` and the exporter use
// the functions below.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/graph/graph.h"

namespace rigel::ops::anim {

inline constexpr const char* kAnimClipsType = "animClips";

namespace clips_attr {
enum : graph::AttrIndex {
  kClipNames = 0,  // string[]: one per clip, unique, not empty
  kClipStarts,     // double[]: seconds, one per clip
  kClipEnds,       // double[]: seconds, one per clip, >= start
  kActive,         // int: index of the active clip
  kActiveClip,     // output int: `active` clamped to [0, clip count - 1] (0 with no clips)
  kError,          // output string, hidden: why the clip list is invalid, or empty
  kCount
};
}  // namespace clips_attr

struct Clip {
  std::string name;
  double start = 0.0;  // seconds
  double end = 0.0;    // seconds
};

// Adds animClips to `registry` (register_anim_types calls it).
Status register_clip_types(graph::Registry& registry);

// The clips of an animClips node, or the first problem with its lists
// ("clipEnds[1]: 0.5 is before clipStarts[1] 1", "clipNames: 3 names for
// 2 starts", "clipNames[2]: 'walk' is also clipNames[0]").
Result<std::vector<Clip>> clips_of(const graph::Graph& graph, graph::NodeId clips_node);

// The scene's animClips node: the first one created, or an invalid id when
// there is none.
graph::NodeId find_clips_node(const graph::Graph& graph);

// Resolves a clip given by name or, failing that, by decimal index, as the
// CLI's --clip takes it. Fails naming the choices ("no clip 'run'; clips:
// walk, idle").
Result<int> resolve_clip(const graph::Graph& graph, graph::NodeId clips_node, std::string_view name_or_index);

// Makes clip `index` active (an attribute edit: undoable).
Status set_active_clip(graph::Graph& graph, graph::NodeId clips_node, int index);

}  // namespace rigel::ops::anim
