// The IK setup functions (nodes.h): check a chain, copy its rest data into
// a solver node and make the connections, as one undo step.

#include "rigel/ops/ik/nodes.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <optional>
#include <utility>
#include <string>
#include <vector>

#include "ik_math.h"
#include "rigel/graph/graph.h"
#include "rigel/math/transform.h"
#include "rigel/ops/ik/ccd.h"
#include "rigel/ops/ik/fabrik.h"
#include "rigel/ops/ik/spline_ik.h"
#include "rigel/ops/ik/two_bone_ik.h"
#include "rigel/scene/transform_types.h"

namespace rigel::ops::ik {
namespace {

using graph::AttrIndex;
using graph::NodeId;
using graph::Plug;
using graph::Value;

// ---- setup helpers --------------------------------------------------------------

using scene::Scene;
namespace xform = scene::xform;

Plug plug_of(NodeId node, AttrIndex attr, std::int32_t element = -1) {
  Plug p;
  p.node = node;
  p.attr = attr;
  p.element = element;
  return p;
}

std::string name_of(const graph::Graph& g, NodeId id) {
  const graph::Node* n = g.node(id);
  return n ? n->name() : std::string("<stale node>");
}

// The world-matrix output of a node (any type with the hierarchy role).
Result<Plug> world_plug(const graph::Graph& g, NodeId id, const char* role) {
  const graph::Node* n = g.node(id);
  if (n == nullptr) return error(ErrorCode::kNotFound, std::string(role) + ": no such node (stale handle)");
  if (n->type().world_output() == graph::kNoAttr) {
    return error(ErrorCode::kInvalidArgument,
                 std::string(role) + " '" + n->name() + "' has no world matrix (type " + n->type().name() + ")");
  }
  return plug_of(id, n->type().world_output());
}

Status check_chain(Scene& scene, std::span<const NodeId> chain, std::size_t min_joints, std::size_t max_joints,
                   const char* type) {
  graph::Graph& g = scene.graph();
  if (chain.size() < min_joints || chain.size() > max_joints) {
    const std::string need = min_joints == max_joints ? "exactly " + std::to_string(min_joints)
                                                      : "at least " + std::to_string(min_joints);
    return error(ErrorCode::kInvalidArgument,
                 std::string(type) + ": the chain needs " + need + " joints, got " + std::to_string(chain.size()));
  }
  for (std::size_t i = 0; i < chain.size(); ++i) {
    if (g.node(chain[i]) == nullptr) {
      return error(ErrorCode::kNotFound, std::string(type) + ": chain[" + std::to_string(i) + "] is a stale handle");
    }
    const std::string name = name_of(g, chain[i]);
    if (!scene.is_transform(chain[i])) {
      return error(ErrorCode::kInvalidArgument, std::string(type) + ": chain joint '" + name + "' is not a transform");
    }
    if (i > 0 && g.parent(chain[i]) != chain[i - 1]) {
      return error(ErrorCode::kInvalidArgument, std::string(type) + ": '" + name + "' is not a child of '" +
                                                    name_of(g, chain[i - 1]) + "' (the chain runs parent to child)");
    }
    for (AttrIndex pivot : {xform::kRotatePivot, xform::kRotatePivotTranslate, xform::kScalePivot,
                            xform::kScalePivotTranslate}) {
      if ((std::get<Vec3>(g.evaluate(chain[i], pivot)).array() != 0.0).any()) {
        return error(ErrorCode::kInvalidArgument, std::string(type) + ": '" + name + "." +
                                                      g.node(chain[i])->type().attr(pivot).name +
                                                      "' is not zero; IK joints need zero pivots");
      }
    }
  }
  return Status::ok();
}

// Creates the node, copies the rest data and connects the parent space.
Result<NodeId> create_solver(Scene& scene, const char* type, std::span<const NodeId> chain, std::string name) {
  graph::Graph& g = scene.graph();
  if (name.empty()) name = name_of(g, chain[0]) + "_" + type;
  Result<NodeId> created = g.create_node(type, name);
  if (!created) return created;
  const NodeId ik = *created;
  std::vector<Mat4> rest, offset;
  std::vector<Vec3> orient, axis;
  for (NodeId joint : chain) {
    const graph::NodeType& t = g.node(joint)->type();
    rest.push_back(std::get<Mat4>(g.evaluate(joint, xform::kMatrix)));
    offset.push_back(std::get<Mat4>(g.evaluate(joint, xform::kOffsetParentMatrix)));
    const AttrIndex jo = t.attr_find("jointOrient");
    orient.push_back(jo == graph::kNoAttr ? Vec3(Vec3::Zero()) : std::get<Vec3>(g.evaluate(joint, jo)));
    axis.push_back(std::get<Vec3>(g.evaluate(joint, xform::kRotateAxis)));
  }
  if (Status s = g.set_value(plug_of(ik, ik_attr::kRestMatrix), rest); !s) return s;
  if (Status s = g.set_value(plug_of(ik, ik_attr::kRestOffsetParentMatrix), offset); !s) return s;
  if (Status s = g.set_value(plug_of(ik, ik_attr::kRestJointOrient), orient); !s) return s;
  if (Status s = g.set_value(plug_of(ik, ik_attr::kRestRotateAxis), axis); !s) return s;
  const NodeId parent = g.parent(chain[0]);
  if (parent.is_valid()) {
    Result<Plug> src = world_plug(g, parent, "the chain's parent");
    if (!src) return src.status();
    if (Status s = g.connect(*src, plug_of(ik, ik_attr::kParentMatrix)); !s) return s;
  } else {
    const Mat4 parent_matrix = std::get<Mat4>(g.evaluate(chain[0], xform::kParentMatrix));
    if (Status s = g.set_value(plug_of(ik, ik_attr::kParentMatrix), parent_matrix); !s) return s;
  }
  return ik;
}

Status connect_world(graph::Graph& g, NodeId src, const char* role, NodeId ik, AttrIndex attr,
                     std::int32_t element = -1) {
  Result<Plug> plug = world_plug(g, src, role);
  if (!plug) return plug.status();
  return g.connect(*plug, plug_of(ik, attr, element));
}

// What the solver drives on joint i.
enum Drive : unsigned { kRotation = 1, kTranslation = 2, kScaleShear = 4 };

Status drive(graph::Graph& g, NodeId ik, NodeId joint, std::int32_t i, unsigned what) {
  if (what & kRotation) {
    if (Status s = g.set_value(plug_of(joint, xform::kRotateMode), xform::kQuaternionMode); !s) return s;
    if (Status s = g.connect(plug_of(ik, ik_attr::kOutRotations, i), plug_of(joint, xform::kRotateQuaternion)); !s)
      return s;
  }
  if (what & kTranslation) {
    if (Status s = g.connect(plug_of(ik, ik_attr::kOutTranslations, i), plug_of(joint, xform::kTranslate)); !s)
      return s;
  }
  if (what & kScaleShear) {
    if (Status s = g.connect(plug_of(ik, ik_attr::kOutScales, i), plug_of(joint, xform::kScale)); !s) return s;
    if (Status s = g.connect(plug_of(ik, ik_attr::kOutShears, i), plug_of(joint, xform::kShear)); !s) return s;
  }
  return Status::ok();
}

Vec3 position_of(const Mat4& m) { return m.topRightCorner<3, 1>(); }

// Runs `build` in a transaction; rolls back when it fails.
template <typename Build>
Result<NodeId> in_transaction(graph::Graph& g, std::string label, Build&& build) {
  graph::Transaction transaction(g, std::move(label));
  Result<NodeId> result = build();
  if (!result) transaction.rollback();
  return result;
}

Result<NodeId> setup_chain(Scene& scene, const char* type, std::span<const NodeId> chain, NodeId target,
                           const ChainIkOptions& options) {
  graph::Graph& g = scene.graph();
  return in_transaction(g, std::string("setup ") + type, [&]() -> Result<NodeId> {
    if (Status s = check_chain(scene, chain, 2, std::size_t(-1), type); !s) return s;
    if (!options.limits.empty() && options.limits.size() != chain.size()) {
      return error(ErrorCode::kInvalidArgument, std::string(type) + ": limits must be empty or one per joint (" +
                                                    std::to_string(chain.size()) + "), got " +
                                                    std::to_string(options.limits.size()));
    }
    Result<NodeId> created = create_solver(scene, type, chain, options.name);
    if (!created) return created;
    const NodeId ik = *created;
    namespace a = chain_attr;
    if (Status s = g.set_value(plug_of(ik, a::kTolerance), options.tolerance); !s) return s;
    if (Status s = g.set_value(plug_of(ik, a::kMaxIterations), std::int64_t{options.max_iterations}); !s) return s;
    if (!options.limits.empty()) {
      std::vector<std::int64_t> kinds;
      std::vector<Vec3> axes, references;
      std::vector<double> mins, maxs, halves;
      // Degrees of a radian angle; within [-pi, pi] it stays within [-180, 180].
      auto degrees = [](double r) {
        const double d = math::to_degrees(r);
        return (r >= -math::kPi && r <= math::kPi) ? std::clamp(d, -180.0, 180.0) : d;
      };
      for (const JointLimit& limit : options.limits) {
        kinds.push_back(static_cast<std::int64_t>(limit.kind));
        axes.push_back(limit.axis);
        references.push_back(limit.reference);
        mins.push_back(degrees(limit.min_angle));
        maxs.push_back(degrees(limit.max_angle));
        halves.push_back(degrees(limit.half_angle));
      }
      for (auto [attr, value] : {std::pair<AttrIndex, Value>{a::kLimitType, kinds}, {a::kLimitAxis, axes},
                                 {a::kLimitReference, references}, {a::kLimitMinAngle, mins},
                                 {a::kLimitMaxAngle, maxs}, {a::kLimitHalfAngle, halves}}) {
        if (Status s = g.set_value(plug_of(ik, attr), value); !s) return s.with_context(type);
      }
    }
    if (Status s = connect_world(g, target, "the target", ik, a::kTargetMatrix); !s) return s;
    for (std::size_t i = 0; i + 1 < chain.size(); ++i) {
      if (Status s = drive(g, ik, chain[i], static_cast<std::int32_t>(i), kRotation); !s) return s;
    }
    return ik;
  });
}

}  // namespace

Result<NodeId> setup_two_bone_ik(Scene& scene, std::span<const NodeId> chain, NodeId target, NodeId pole,
                                 const TwoBoneIkOptions& options) {
  graph::Graph& g = scene.graph();
  return in_transaction(g, std::string("setup ") + kIkTwoBoneType, [&]() -> Result<NodeId> {
    if (Status s = check_chain(scene, chain, 3, 3, kIkTwoBoneType); !s) return s;
    const Mat4 start_world = scene.world_matrix(chain[0]);
    const Mat4 mid_world = scene.world_matrix(chain[1]);
    const Mat4 end_world = scene.world_matrix(chain[2]);
    const Vec3 start = position_of(start_world);
    const Vec3 upper = position_of(mid_world) - start;
    const Vec3 lower = position_of(end_world) - position_of(mid_world);
    const Mat3 mid_linear = mid_world.topLeftCorner<3, 3>();
    auto fail = [](const std::string& what) {
      return error(ErrorCode::kInvalidArgument, std::string(kIkTwoBoneType) + ": " + what);
    };

    // The pole direction, from the start joint.
    std::optional<Vec3> pole_direction;
    if (pole.is_valid()) {
      if (!scene.is_transform(pole)) return fail("the pole is not a transform");
      pole_direction = position_of(scene.world_matrix(pole)) - start;
    } else if (options.pole_vector) {
      pole_direction = *options.pole_vector;
    }
    Vec3 bend = upper.cross(lower);
    const bool bent = bend.norm() > 1e-9 * upper.norm() * lower.norm() && detail::normalize_in_place(bend);
    if (!pole_direction && bent) {
      // Toward the mid joint from the start-end line: keep the rest bend.
      Vec3 line = upper + lower;
      if (detail::normalize_in_place(line)) pole_direction = upper - line * line.dot(upper);
    }

    // The hinge, world space, then in the mid joint's space.
    Vec3 mid_axis;
    if (options.mid_axis) {
      mid_axis = *options.mid_axis;
      if (!detail::is_unit(mid_axis)) return fail("mid_axis must be a unit vector");
    } else {
      Vec3 hinge = bend;
      if (!bent) {
        if (!pole_direction) {
          return fail("the chain is straight: give a pole, a pole_vector or a mid_axis to choose the bend");
        }
        hinge = pole_direction->cross(upper);
        if (!detail::normalize_in_place(hinge)) return fail("the pole lies on the line of the straight chain");
      }
      if (!(std::abs(mid_linear.determinant()) > 1e-300)) return fail("the mid joint's world matrix is singular");
      mid_axis = mid_linear.inverse() * hinge;
      if (!detail::normalize_in_place(mid_axis)) return fail("the mid joint's world matrix is singular");
    }
    if (!pole_direction) pole_direction = upper.cross(mid_linear * mid_axis);  // the knee side the hinge implies

    Result<NodeId> created = create_solver(scene, kIkTwoBoneType, chain, options.name);
    if (!created) return created;
    const NodeId ik = *created;
    namespace a = two_bone_attr;
    if (Status s = g.set_value(plug_of(ik, a::kMidAxis), mid_axis); !s) return s;
    if (Status s = connect_world(g, target, "the target", ik, a::kTargetMatrix); !s) return s;
    if (pole.is_valid()) {
      if (Status s = g.set_value(plug_of(ik, a::kUsePoleMatrix), true); !s) return s;
      if (Status s = connect_world(g, pole, "the pole", ik, a::kPoleMatrix); !s) return s;
    } else {
      if (Status s = g.set_value(plug_of(ik, a::kPoleVector), *pole_direction); !s) return s;
    }
    // Scale and shear too: under a non-uniformly scaled parent a rigid turn
    // takes a shear (the solver's outputs hold it; otherwise they are the
    // rest values).
    if (Status s = drive(g, ik, chain[0], 0, kRotation | kScaleShear); !s) return s;
    if (Status s = drive(g, ik, chain[1], 1, kRotation | kTranslation | kScaleShear); !s) return s;
    if (Status s = drive(g, ik, chain[2], 2, kTranslation); !s) return s;
    return ik;
  });
}

Result<NodeId> setup_fabrik_ik(Scene& scene, std::span<const NodeId> chain, NodeId target,
                               const ChainIkOptions& options) {
  return setup_chain(scene, kIkFabrikType, chain, target, options);
}

Result<NodeId> setup_ccd_ik(Scene& scene, std::span<const NodeId> chain, NodeId target,
                            const ChainIkOptions& options) {
  return setup_chain(scene, kIkCcdType, chain, target, options);
}

Result<NodeId> setup_spline_ik(Scene& scene, std::span<const NodeId> chain, std::span<const NodeId> control_points,
                               const SplineIkOptions& options) {
  graph::Graph& g = scene.graph();
  return in_transaction(g, std::string("setup ") + kIkSplineType, [&]() -> Result<NodeId> {
    if (Status s = check_chain(scene, chain, 2, std::size_t(-1), kIkSplineType); !s) return s;
    auto fail = [](const std::string& what) {
      return error(ErrorCode::kInvalidArgument, std::string(kIkSplineType) + ": " + what);
    };
    if (control_points.size() < 2) return fail("the curve needs at least 2 control points");
    // The root joint's rotation frame at rest gives the default axes.
    const Mat4 root_world = scene.world_matrix(chain[0]);
    const Mat3 frame = math::decompose(root_world).rotation.toRotationMatrix();
    Vec3 aim = options.aim_axis.value_or(frame.transpose() *
                                         (position_of(scene.world_matrix(chain[1])) - position_of(root_world)));
    if (!options.aim_axis && !detail::normalize_in_place(aim)) {
      return fail("the first bone has zero length: give aim_axis");
    }
    if (!detail::is_unit(aim)) return fail("aim_axis must be a unit vector");
    Vec3 up;
    if (options.up_axis) {
      up = *options.up_axis;
    } else {
      up = frame.transpose() * options.world_up_vector;
      up -= aim * aim.dot(up);
      if (!detail::normalize_in_place(up)) up = aim.unitOrthogonal();
    }
    Result<NodeId> created = create_solver(scene, kIkSplineType, chain, options.name);
    if (!created) return created;
    const NodeId ik = *created;
    namespace a = spline_attr;
    for (auto [attr, value] : {std::pair<AttrIndex, Value>{a::kAimAxis, aim}, {a::kUpAxis, up},
                               {a::kWorldUpVector, options.world_up_vector}, {a::kStretch, options.stretch},
                               {a::kSquash, options.squash}}) {
      if (Status s = g.set_value(plug_of(ik, attr), value); !s) return s.with_context(kIkSplineType);
    }
    for (std::size_t i = 0; i < control_points.size(); ++i) {
      if (Status s = connect_world(g, control_points[i], "a control point", ik, a::kControlMatrix,
                                   static_cast<std::int32_t>(i));
          !s) {
        return s;
      }
    }
    for (std::size_t i = 0; i < chain.size(); ++i) {
      if (Status s = drive(g, ik, chain[i], static_cast<std::int32_t>(i), kRotation | kTranslation | kScaleShear); !s)
        return s;
    }
    return ik;
  });
}

}  // namespace rigel::ops::ik
