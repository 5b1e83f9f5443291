// Procedural builds (seed 003): a rig is the result of an ordered list of
// steps, each with a construct and a destruct, that can be stepped forward
// and back like a VCR, switched by features, and rebuilt in part.
//
// The plan: the rig's own step ("rig": metaRoot and groups), then every
// component (parents before children, and after any component whose hook it
// attaches to) with its steps in declared order; a component's first step
// ("meta") makes its metaComponent. A step's construct runs through a
// BuildContext; everything it does to the graph is recorded (nodes made,
// connections made or broken, values, names and tags changed on nodes that
// existed before) and the record is saved on the component's meta node
// (`buildRecord`), so the destruct is exact and works in a later process:
// construct all then destruct all gives back the scene file byte for byte.
//
// Components are C++ classes registered by type in a ComponentFactory
// (component.h); the factory also instances the class of a built component
// from its meta node's metaType.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/graph/graph.h"
#include "rigel/math/types.h"
#include "rigel/ops/constraints/nodes.h"
#include "rigel/rig/definition.h"
#include "rigel/rig/schema.h"
#include "rigel/scene/scene.h"

namespace rigel::rig {

using graph::NodeId;

class BuildContext;
class ComponentFactory;

// One step of a component's build.
struct Step {
  std::string name;
  std::string feature;      // runs only while this feature is enabled ("" = always)
  std::string switch_name;  // ... and this switch of it
  std::function<Status(BuildContext&)> construct;
};

// A step in a build's plan.
struct PlannedStep {
  int component = -1;       // index into Build::components(); -1 = the rig's own step
  std::string step;         // step name
  std::string feature, switch_name;
  bool enabled = true;      // false: passed over (its feature or switch is off)
  std::string label() const;  // "arm_L/controls"
};

struct BuildOptions {
  // Rig edit mode (seed 002): the rig is an instance in its default pose
  // (controls zeroed, no animation) whose control moves are edits of the
  // definition (Build::edits). Kept on the metaRoot (`editMode`), so a
  // later Build of the same rig follows what the scene says.
  bool edit_mode = false;
};

// What moving controls in rig edit mode does to the definition.
struct Edits {
  Definition definition;             // guides moved, versions bumped
  std::vector<std::string> changed;  // rigIds of components with moved guides
  std::vector<std::string> ignored;  // controls moved that stand for no guide (names)
};

// The version after `version`: its last number plus one ("1.0" -> "1.1",
// "2" -> "3", "1.0.9" -> "1.0.10"); ".1" appended when it ends in no number.
std::string next_version(std::string_view version);

class Build {
 public:
  // Plans `definition` for `scene` (whose registry must hold the rig types:
  // rig::default_registry() or above). If the scene already holds a rig of
  // the same name, the build continues from what its metaRoot says was
  // built; otherwise nothing is built yet (position 0). Fails on an invalid
  // definition (validate()), an unknown component class, an attach cycle.
  static Result<std::unique_ptr<Build>> open(scene::Scene& scene, Definition definition,
                                             const ComponentFactory& factory, BuildOptions options = {});
  // Continues the rig `rig_name` of the scene from the definition it was
  // built from (kept on its metaRoot).
  static Result<std::unique_ptr<Build>> reopen(scene::Scene& scene, std::string_view rig_name,
                                               const ComponentFactory& factory, BuildOptions options = {});
  ~Build();

  const Definition& definition() const { return definition_; }
  // Components in build order.
  const std::vector<const Component*>& components() const { return components_; }
  const std::vector<PlannedStep>& plan() const { return plan_; }
  // Steps done: plan()[0 .. position) are constructed (or passed over), as
  // the scene's metaRoot says at the last operation.
  int position() const { return position_; }
  scene::Scene& scene() { return scene_; }
  NodeId root() const;  // the metaRoot (invalid at position 0)

  // Each call is one undo step. A construct that fails is rolled back (its
  // partial work undone) and the position stays; the error names the step.
  Status forward();
  Status back();
  Status go_to(int position);
  Status build_all() { return go_to(static_cast<int>(plan_.size())); }
  // Destructs everything; the metaManager goes too when no rig is left.
  Status remove();

  // Feature switches (seed 003): changes the definition's rig-level feature
  // and rebuilds from the first step whose enabled state changes.
  Status set_feature(std::string_view feature, bool enabled, std::string_view switch_name = {});

  // Which components an update rebuilds.
  enum class Rebuild {
    kChanged,       // whose own data (type, params, guides, controls, attach, features, version) differs
    kNewerVersion,  // whose version differs (seed 002's update)
    kAll,           // every one (--force)
  };
  // Replaces the definition and rebuilds only what changed (by rigId): such
  // a component is destructed and constructed again, with the components
  // that hang from it; components added or removed are built or destructed;
  // nothing else is touched. Connections into the rebuilt controls from
  // outside the rig (animation curves) re-attach to the new controls with
  // the same role and index, values as they were. Returns the rigIds rebuilt
  // or removed. One undo step; on failure nothing changes.
  //
  // How keys on the rebuilt controls are kept (seed 002's update option):
  // kLocal keeps the curves as they are (the values, in the new controls'
  // rest space); kWorld converts them so each keyed control is, at each of
  // its key times, where it was in the world before the update (within
  // 1e-6): controls are converted parents first, a channel keyed at some of
  // the times gets keys at all of them, a free channel that must vary gets
  // curves. Fails, changing nothing, when a control cannot be put back (its
  // new parent space singular, pivots set, a channel driven by a
  // non-curve) or misses by more than 1e-6, naming the control and frame.
  enum class KeepKeys { kLocal, kWorld };
  Result<std::vector<std::string>> rebuild_changed(Definition definition, Rebuild when = Rebuild::kChanged,
                                                   KeepKeys keep = KeepKeys::kLocal);

  // ---- rig edit mode (seed 002) ----
  bool edit_mode() const { return options_.edit_mode; }
  // Enters or leaves rig edit mode on a built rig: it is built again from
  // its first step in that mode (controls zeroed in edit mode). One undo
  // step; on failure nothing changes.
  Status set_edit_mode(bool on);
  // The definition with each guide moved as its controls were moved: a
  // control made at guide i (tagged guide=i) whose rest R is the guide's
  // place G (within 1e-7) and that stands at W moves guide i to W, so the
  // rebuilt rig stands where the edited one does. A control made elsewhere
  // for a guide (a pole, a limb's switch, an eye's aim, a foot's ground
  // control) stands for no guide: moved, it is listed in Edits::ignored. A guide with a joint keeps it and
  // takes the move as its offset in the joint's space; other guides take it
  // as their values. Changed components and the rig get next_version().
  // Controls of classes that are not editable() are left out.
  // Rest poses come from zeroing every control in a transaction that is
  // rolled back: the scene is left as it was. Fails when the rig is not in
  // edit mode or not fully built, or when two controls of one guide were
  // moved differently (naming them).
  Result<Edits> edits();
  // edits(), then rebuild_changed() with it: the moved components are built
  // again at their new guides, controls zeroed. When guides moved and
  // `definition_path` is given, the rig records it as its definition path
  // (where the caller saves Edits::definition), so the rig is up to date with
  // that file. `leave_edit_mode`: then the rig is built again for animation
  // (set_edit_mode(false)). One undo step; on failure nothing changes.
  Result<Edits> commit_edits(const std::string& definition_path = {}, bool leave_edit_mode = false);

 private:
  Build(scene::Scene& scene, Definition definition, const ComponentFactory& factory, BuildOptions options);
  Status replan();
  // Re-reads the position and the step records from the scene (the truth:
  // undo, redo or another Build may have changed it).
  Status sync();
  Status construct(int index);
  Status destruct(int index);
  Status save_state(const std::string& owner);  // owner: rigId, "" = the rig

  scene::Scene& scene_;
  Definition definition_;
  const ComponentFactory& factory_;
  BuildOptions options_;
  std::vector<const Component*> components_;
  std::vector<std::vector<Step>> steps_;  // per component
  std::vector<PlannedStep> plan_;
  int position_ = 0;
  struct Records;
  std::unique_ptr<Records> records_;
  friend class BuildContext;
};

// A constraint for BuildContext::constrain to make: its type, targets and
// the channels of the driven it drives, and where its parent space (the
// constraint's parentInverseMatrix) comes from.
struct ConstraintSpec {
  enum class Space {
    kParent,    // inverse(driven's parent world * driven's offsetParentMatrix), live
    kNode,      // inverse(space_node's world * driven's offsetParentMatrix), live
    kIdentity,  // the identity: the outputs are the targets' world
  };
  const char* type = ops::constraints::kParentConstraintType;
  std::string role;        // the constraint node's role
  std::string space_role;  // its parent space node's role; empty: role + "Space"
  std::vector<NodeId> targets;
  std::vector<double> weights;  // empty: 1 each
  bool maintain_offset = true;  // not for aim constraints (their offset moves the target)
  std::vector<const char*> channels;  // "translate", "rotate", "scale" of the driven
  Space space = Space::kParent;
  NodeId space_node;  // kNode
};

// What a step's construct works with. Everything it changes goes through
// the graph while a recorder watches, so a step may call any rigel API
// (ops::ik::setup_two_bone_ik, Scene::reparent, ...), not only these helpers.
class BuildContext {
 public:
  scene::Scene& scene() { return scene_; }
  graph::Graph& graph() { return scene_.graph(); }
  const Definition& definition() const { return definition_; }
  const Component& component() const { return *component_; }
  const ComponentSchema& schema() const { return *schema_; }
  // The rig's name and the component's full name ("arm_L"): node name prefix.
  const std::string& rig_name() const { return definition_.name; }
  std::string full_name() const;
  NodeId meta() const { return meta_; }
  NodeId root() const { return root_; }
  const std::string& step() const { return step_; }
  bool edit_mode() const { return edit_mode_; }

  // Parameters, with the schema's defaults.
  bool param_bool(std::string_view name) const;
  std::int64_t param_int(std::string_view name) const;
  double param_double(std::string_view name) const;
  std::string param_string(std::string_view name) const;  // string and enum
  // A control role's look: the definition's, else the schema's.
  ControlStyle control_style(std::string_view role) const;

  int guide_count() const { return static_cast<int>(component_->guides.size()); }
  // The scene joint guide i names (kNotFound naming it when it has none or
  // the scene has no such node).
  Result<NodeId> guide_joint(int i);
  // Guide i as a world matrix: its joint's world matrix, else its values.
  Result<math::Mat4> guide_world(int i);

  // Makes a node named PREFIX_role[index], tagged (role, index, step, guide)
  // and linked to this component's meta node. `parent` may be invalid.
  Result<NodeId> create(std::string_view type, std::string_view role, int index = -1, int guide = -1,
                        NodeId parent = {});
  // Links a node made through another API (setup_spline_ik,
  // ephemeral::setup_ephemeral) to this component as create() does: tags
  // (role, index, step, guide) and the meta node's `members`.
  Status link(NodeId node, std::string_view role, int index = -1, int guide = -1);
  // A control at `world`, zeroed (its offsetParentMatrix holds the place, its
  // channels are 0/1), with the role's shape, colour and size.
  Result<NodeId> create_control(std::string_view role, int index, int guide, const math::Mat4& world, NodeId parent);
  // A group (transform) at `world`, zeroed likewise.
  Result<NodeId> create_group(std::string_view role, int index, const math::Mat4& world, NodeId parent);
  // Makes `driven` (a node of the character, e.g. a joint) follow `driver`
  // keeping its current offset: a parentConstraint whose parent space follows
  // the driven's parent (constrain() with role "drive").
  Status drive(NodeId driver, NodeId driven);
  // Makes a constraint as `spec` says, driving `driven`'s channels (any
  // input already connected to them is disconnected). The constraint's
  // rest values and Euler channels are the driven's as they are now (past
  // its joint orient, in its rotate order), and a driven in quaternion
  // rotate mode is switched to Euler. Errors name the component and role.
  Result<NodeId> constrain(const ConstraintSpec& spec, NodeId driven, int index = -1);

  // Nodes this component made in earlier steps, by role (in index order).
  std::vector<NodeId> nodes(std::string_view role) const;
  NodeId node(std::string_view role, int index = 0) const;
  // Publishes `node` as hook `index` (hook names: the schema's hook_names()).
  Status publish_hook(int index, NodeId node);
  // Where this component hangs: the hook of its parent (or of the component
  // its attach names) it attaches to; the rig's controls group for a root.
  NodeId attach_node() const;
  // The rig's groups: "controls" (controls hang here), "noTransform".
  NodeId rig_group(std::string_view role) const;

 private:
  friend class Build;
  BuildContext(scene::Scene& scene, const Definition& definition) : scene_(scene), definition_(definition) {}
  scene::Scene& scene_;
  const Definition& definition_;
  const Component* component_ = nullptr;
  const ComponentSchema* schema_ = nullptr;
  NodeId meta_, root_, attach_;
  std::string step_;
  bool edit_mode_ = false;
};

}  // namespace rigel::rig
