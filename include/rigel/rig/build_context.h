// What a build step's construct works with (build.h): a BuildContext gives
// the component's parameters, guides and earlier nodes, and makes nodes,
// controls, groups and constraints that the build records and links to the
// component's meta node.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
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
  math::Vec3 param_vec3(std::string_view name) const;
  // Any parameter's value: the definition's, else the schema's default
  // (nullptr for a name the type does not have).
  const ParamValue* param_value(std::string_view name) const;
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
  std::string naming_;  // BuildOptions::naming_template
};

}  // namespace rigel::rig
