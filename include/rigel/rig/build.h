// Procedural builds (seed 003): a rig is the result of an ordered list of
// steps, each with a construct and a destruct, that can be stepped forward
// and back like a VCR, switched by features, and rebuilt in part.
//
// The plan: the rig's own step ("rig": metaRoot and groups), then every
// component (parents before children, and after any component whose hook it
// attaches to) with its steps in declared order; a component's first step
// ("meta") makes its metaComponent. When the definition names data
// (Definition::data), the plan ends with the rig's step "data": each entry
// imported in order by the factory's data importer (component.h), so a
// rebuild from scratch gives the hand-made work back. A step's construct runs through a
// BuildContext; everything it does to the graph is recorded (nodes made,
// connections made or broken, values, names and tags changed on nodes that
// existed before) and the record is saved on the component's meta node
// (`buildRecord`), so the destruct is exact and works in a later process:
// construct all then destruct all gives back the scene file byte for byte.
//
// Components are C++ classes registered by type in a ComponentFactory
// (component.h); the factory also instances the class of a built component
// from its meta node's metaType. What a construct works with is its
// BuildContext (build_context.h).
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/graph/graph.h"
#include "rigel/rig/build_context.h"
#include "rigel/rig/definition.h"
#include "rigel/rig/version.h"
#include "rigel/scene/scene.h"

namespace rigel::rig {

using graph::NodeId;

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
  // How built nodes are named (the setting naming.template): {rig},
  // {component} ("arm_L"), {name} ("arm"), {side} ("L"), {role} and
  // {index}; a token that comes out empty (no component, no index) takes
  // one '_' beside it with it. Empty: "{rig}_{component}_{role}{index}".
  // Kept on the metaRoot (`namingTemplate`), so later steps, rebuilds and
  // updates name alike.
  std::string naming_template;
};

// A node's name under `naming_template` (BuildOptions; empty: the default).
std::string built_node_name(const std::string& naming_template, const std::string& rig, const std::string& component,
                            const std::string& name, const std::string& side, const std::string& role, int index);

// What moving controls in rig edit mode does to the definition.
struct Edits {
  Definition definition;             // guides moved, versions bumped
  std::vector<std::string> changed;  // rigIds of components with moved guides
  std::vector<std::string> ignored;  // controls moved that stand for no guide (names)
};

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
  // nothing else is touched, but the data step (when the old or new
  // definition names data) is destructed first and done again last, so an
  // update re-imports the data. Connections into the rebuilt controls from
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
  // What it builds with (edit mode, naming template), as the metaRoot says.
  const BuildOptions& options() const { return options_; }
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

}  // namespace rigel::rig
