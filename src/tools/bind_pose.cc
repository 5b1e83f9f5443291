// Bind pose resets (bind_pose.h).

#include "rigel/tools/bind_pose.h"

#include <algorithm>
#include <string>

#include "rigel/ephemeral/rig.h"
#include "rigel/math/types.h"
#include "rigel/ops/anim/channel_keys.h"
#include "rigel/ops/util/space.h"
#include "rigel/rig/meta.h"
#include "rigel/scene/transform_types.h"
#include "rigel/tools/keys.h"

namespace rigel::tools {
namespace {

using graph::NodeId;
using graph::Plug;
using graph::Value;
namespace xform = scene::xform;

bool is_built_control(const graph::Graph& g, NodeId id) {
  return g.node(id)->type().name() == scene::kControlType && rig::component_of(g, id).is_valid() &&
         !ephemeral::control_of(g, id).is_valid();
}

// The controls and other bind-tagged nodes under `node`.
Status expand(const graph::Graph& g, NodeId node, std::vector<NodeId>& out) {
  auto add = [&](NodeId id) {
    if (std::find(out.begin(), out.end(), id) == out.end()) out.push_back(id);
  };
  const graph::Node* n = g.node(node);
  if (!n) return Status(ErrorCode::kNotFound, "bind pose: no such node (stale handle)").with_field("controls");
  const std::string& type = n->type().name();
  std::vector<NodeId> metas;
  if (type == rig::kMetaRootType) {
    metas.push_back(node);
    for (NodeId c : rig::rig_components(g, node)) metas.push_back(c);
  } else if (type == rig::kMetaComponentType) {
    metas.push_back(node);
  } else if (is_built_control(g, node)) {
    add(node);
    return Status::ok();
  } else {
    return Status(ErrorCode::kInvalidArgument,
                  "bind pose: '" + n->name() + "' is not a built rig's control, component or rig")
        .with_field("controls");
  }
  for (NodeId m : metas)
    for (NodeId member : rig::meta_members(g, m))
      if (is_built_control(g, member) || g.node(member)->tag_find(rig::kTagBind)) add(member);
  return Status::ok();
}

}  // namespace

Result<BindPoseReport> reset_bind_pose(graph::Graph& g, const std::vector<NodeId>& nodes, bool key) {
  if (nodes.empty()) return Status(ErrorCode::kInvalidArgument, "bind pose: nothing given").with_field("controls");
  std::vector<NodeId> targets;
  for (NodeId n : nodes)
    if (Status s = expand(g, n, targets); !s) return s;
  BindPoseReport report;
  graph::Transaction tx(g, "bind pose");
  auto write = [&](NodeId node, graph::AttrIndex attr, const Value& v) -> Status {
    if (driven_otherwise(g, node, attr)) return Status::ok();  // follows something else (a foot's fkIk its limb's)
    Status s = ops::anim::write_channel_key(g, node, attr, v, g.time(), key);
    if (s) ++report.channels;
    return s;
  };
  for (NodeId id : targets) {
    const graph::Node& n = *g.node(id);
    Status s;
    if (n.type().name() == scene::kControlType) {
      s = write(id, xform::kTranslate, Value(math::Vec3(math::Vec3::Zero())));
      if (s && xform::is_quaternion_mode(n)) s = write(id, xform::kRotateQuaternion, Value(math::Quat(math::Quat::Identity())));
      else if (s) s = write(id, xform::kRotate, Value(math::Vec3(math::Vec3::Zero())));
      if (s) s = write(id, xform::kScale, Value(math::Vec3(math::Vec3::Ones())));
      if (s && std::get<math::Vec3>(g.evaluate(id, xform::kShear)) != math::Vec3::Zero())
        s = write(id, xform::kShear, Value(math::Vec3(math::Vec3::Zero())));
    } else {
      for (const auto& [attr, value] : rig::bind_values(g, id)) {
        const graph::AttrIndex a = n.type().attr_find(attr);
        if (a == graph::kNoAttr) continue;
        if (s) s = write(id, a, Value(value));
      }
      // A space switch's compensation goes back to the identity with it.
      if (n.type().name() == ops::util::kSpaceSwitchType)
        for (const graph::Connection& c : n.inputs()) {
          if (c.dst.attr != ops::util::space_attr::kCompensationMatrix) continue;
          const Value zero(math::Vec3(math::Vec3::Zero()));
          for (graph::AttrIndex a : {xform::kTranslate, xform::kRotate, xform::kShear})
            if (s) s = write(c.src.node, a, zero);
          if (s) s = write(c.src.node, xform::kScale, Value(math::Vec3(math::Vec3::Ones())));
        }
    }
    if (!s) {
      tx.rollback();
      return s.with_context("bind pose");
    }
    report.set.push_back(id);
  }
  return report;
}

}  // namespace rigel::tools
