// The metadata network (seed 002 §4.2.1 and Appendix B; Luna's MetaNode,
// seed 004 §4.8): graph nodes that describe a built rig and link it to
// everything it is made of, so that tools find things by meaning, never by
// name.
//
//   metaManager   one per scene; `metaRoots` -> each metaRoot.metaParent
//   metaRoot      one per built rig: rigName, version, definitionPath, the
//                 definition as built (JSON), the build position;
//                 `metaChildren` -> root components' metaParent, `members` ->
//                 the rig-level nodes it built (groups)
//   metaComponent one per component: metaType (the component type, which
//                 picks the C++ class: component.h), componentName, side,
//                 version, rigId, tags; `metaChildren` -> child components,
//                 `members` -> every node the component built
//
// Every node type has a `metaParent` message input (graph/node_type.h), so a
// node belongs to at most one meta node, and `component_of` is one lookup.
// Built nodes also carry tags: rig.role, rig.index, rig.step, rig.guide and
// rig.hook (build.h), which addresses and get_meta_connection read.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/graph/graph.h"
#include "rigel/math/types.h"

namespace rigel::rig {

using graph::Graph;
using graph::NodeId;

inline constexpr const char* kMetaManagerType = "metaManager";
inline constexpr const char* kMetaRootType = "metaRoot";
inline constexpr const char* kMetaComponentType = "metaComponent";

// Tags on every node a build makes.
inline constexpr const char* kTagRole = "rig.role";    // what it is for the component ("fk", "ikHandle")
inline constexpr const char* kTagIndex = "rig.index";  // its index among the role's nodes
inline constexpr const char* kTagStep = "rig.step";    // the build step that made it
inline constexpr const char* kTagGuide = "rig.guide";  // the guide (joint label) it belongs to, if any
inline constexpr const char* kTagHook = "rig.hook";    // the hook index it publishes, if it is one
// On every control: its world matrix as built (its rest: channels zero),
// 16 numbers row by row. What mirroring relates the two sides by.
inline constexpr const char* kTagRestWorld = "rig.restWorld";
// On the other keyable nodes a build makes (a limb's fkIkSwitch, a foot's
// reverseFoot): their keyable scalars' values as built, "attr=value;...".
// What a bind pose reset gives back.
inline constexpr const char* kTagBind = "rig.bind";

// Adds metaManager, metaRoot and metaComponent to `registry`.
Status register_rig_types(graph::Registry& registry);
// Every type of the layers below plus the rig layer's.
std::shared_ptr<const graph::Registry> default_registry();

bool is_meta_node(const Graph& graph, NodeId node);
// The manager (invalid when the scene has none).
NodeId meta_manager(const Graph& graph);
// The rigs in the scene (seed 002's listMetaRoots), in creation order.
std::vector<NodeId> list_rigs(const Graph& graph);
// The metaRoot whose rigName is `name` (invalid when none).
NodeId find_rig(const Graph& graph, std::string_view name);

// The meta node a node or meta node hangs from (source of its metaParent).
NodeId meta_parent(const Graph& graph, NodeId node);
// Component meta nodes directly under a metaRoot or metaComponent, in
// creation order.
std::vector<NodeId> meta_children(const Graph& graph, NodeId meta);
// Every node a meta node's `members` links to, in creation order.
std::vector<NodeId> meta_members(const Graph& graph, NodeId meta);
// Those of them that are controls.
std::vector<NodeId> meta_controls(const Graph& graph, NodeId meta);
// The child component meta node with that rigId (seed 002's getMetaChildById,
// direct children only); invalid when none.
NodeId get_meta_child_by_id(const Graph& graph, NodeId meta, std::string_view rig_id);
// Any component of a rig by rigId or by component name; invalid when none.
NodeId find_component(const Graph& graph, NodeId rig, std::string_view rig_id_or_name);
// Every component meta node of a rig, parents first.
std::vector<NodeId> rig_components(const Graph& graph, NodeId rig);
// Seed 002's getMetaNodeConnection: the `index`-th member with tag rig.role
// (or rig.step) == `role`, by rig.index; kNotFound naming what is missing.
Result<NodeId> get_meta_connection(const Graph& graph, NodeId meta, std::string_view role, int index = 0);
// The meta node (metaComponent or metaRoot) that built `node`; invalid when
// the node is not part of a rig.
NodeId component_of(const Graph& graph, NodeId node);
// The metaRoot above a meta node or built node; invalid when none.
NodeId rig_of(const Graph& graph, NodeId node);

// A string / int attribute of a meta node ("" / 0 when absent).
std::string meta_string(const Graph& graph, NodeId meta, std::string_view attr);

// A control's world matrix as built (kTagRestWorld); nullopt for a node
// without one (not a built control, or built before rigel recorded it).
std::optional<math::Mat4> rest_world(const Graph& graph, NodeId control);
std::string rest_world_text(const math::Mat4& world);
// A node's kTagBind values (empty without the tag).
std::vector<std::pair<std::string, double>> bind_values(const Graph& graph, NodeId node);

// The control on the other side (mirroring): the same role and index in
// the component of the same type and name on the opposite side (L <-> R)
// of the same rig, found by the metadata, never by node names; a centre
// component's control is its own pair. kInvalidArgument naming the control
// when it is not a built rig's control, or when the other side lacks the
// component or the control.
Result<NodeId> mirror_pair(const Graph& graph, NodeId control);

// Nameless addressing (seed 003 §4.6): `RIG:COMPONENT[/joint[J]]/NAME[I]`
// where RIG is a rigName, COMPONENT a component name or rigId, joint[J]
// keeps the nodes built for guide J, NAME is a role or a step, and J and I
// are indices or START, MIDDLE, END (I defaults to 0). `RIG:COMPONENT` is the
// component's meta node, `RIG:` the metaRoot. Node names play no part, so a
// rename never breaks an address. Errors name the part that did not resolve.
Result<NodeId> resolve_address(const Graph& graph, std::string_view address);
// The address of a built node (the inverse of resolve_address).
Result<std::string> address_of(const Graph& graph, NodeId node);

}  // namespace rigel::rig
