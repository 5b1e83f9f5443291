// The hand component (components/hand.h).
#include "rigel/rig/components/hand.h"

#include "aim.h"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

#include "rigel/math/transform.h"
#include "rigel/ops/util/finger.h"
#include "rigel/rig/component.h"
#include "rigel/rig/meta.h"
#include "rigel/scene/transform_types.h"

namespace rigel::rig::components {
namespace {

using graph::AttrIndex;
using graph::Plug;
using graph::Value;
using math::Mat3;
using math::Mat4;
using math::Vec3;
namespace xform = scene::xform;
namespace fa = ops::util::finger_attr;

Vec3 position_of(const Mat4& m) { return m.topRightCorner<3, 1>(); }

// The rotation of an affine matrix, scale and shear removed.

Plug plug(NodeId node, AttrIndex attr, std::int32_t element = -1) { return Plug{node, attr, element}; }

Status fail(BuildContext& ctx, const std::string& what) {
  return error(ErrorCode::kInvalidArgument, ctx.full_name() + " (hand): " + what);
}

struct Finger {
  std::string name;
  std::vector<int> guides;  // guide indices, joint 0 first
  std::vector<NodeId> joints;
  int first_control = 0;  // running index of its joint 0's control
};

struct Hand {
  NodeId joint;
  std::vector<Finger> fingers;
  int control_count = 0;
};

// "index.2" -> ("index", 2); false when the name is not FINGER.N.
bool parse_finger_name(const std::string& text, std::string* finger, int* number) {
  const std::size_t dot = text.rfind('.');
  if (dot == std::string::npos || dot == 0 || dot + 1 == text.size()) return false;
  const char* first = text.data() + dot + 1;
  const char* last = text.data() + text.size();
  auto [end, ec] = std::from_chars(first, last, *number);
  if (ec != std::errc() || end != last || *number < 0) return false;
  *finger = text.substr(0, dot);
  return true;
}

bool is_below(const graph::Graph& g, NodeId node, NodeId ancestor) {
  for (NodeId p = g.parent(node); p.is_valid(); p = g.parent(p))
    if (p == ancestor) return true;
  return false;
}

// The guides read and checked: the hand joint and the fingers.
Result<Hand> read_hand(BuildContext& ctx) {
  graph::Graph& g = ctx.graph();
  Hand hand;
  auto transform_at = [&](int i) -> Result<NodeId> {
    Result<NodeId> j = ctx.guide_joint(i);  // its errors name the component
    if (!j) return j.status();
    if (!ctx.scene().is_transform(*j))
      return fail(ctx, "guide " + std::to_string(i) + ": '" + g.node(*j)->name() + "' is not a transform");
    return j;
  };
  Result<NodeId> joint = transform_at(0);
  if (!joint) return joint.status();
  hand.joint = *joint;
  std::vector<NodeId> used = {hand.joint};
  for (int i = 1; i < ctx.guide_count(); ++i) {
    const std::string& label = ctx.component().guides[i].name;
    const std::string at = "guide " + std::to_string(i) + " ('" + label + "')";
    std::string name;
    int number = 0;
    if (!parse_finger_name(label, &name, &number))
      return fail(ctx, "guide " + std::to_string(i) + " is named '" + label +
                           "'; finger guides are named FINGER.N (thumb.0, thumb.1, index.0, ...)");
    if (number == 0) {
      for (const Finger& f : hand.fingers)
        if (f.name == name)
          return fail(ctx, at + ": finger '" + name + "' is listed twice; list a finger's joints together");
      hand.fingers.push_back(Finger{name, {}, {}, hand.control_count});
    } else if (hand.fingers.empty() || hand.fingers.back().name != name ||
               static_cast<int>(hand.fingers.back().guides.size()) != number) {
      const std::string expected = hand.fingers.empty() || hand.fingers.back().name != name
                                       ? name + ".0"
                                       : name + "." + std::to_string(hand.fingers.back().guides.size());
      return fail(ctx, at + ": expected '" + expected +
                           "' here; a finger's joints come together, numbered 0, 1, 2, ...");
    }
    Result<NodeId> j = transform_at(i);
    if (!j) return j.status();
    for (NodeId u : used)
      if (u == *j) return fail(ctx, at + ": joint '" + g.node(*j)->name() + "' is used by another guide");
    used.push_back(*j);
    Finger& finger = hand.fingers.back();
    if (number == 0 && !is_below(g, *j, hand.joint))
      return fail(ctx, at + ": '" + g.node(*j)->name() + "' does not hang below the hand joint '" +
                           g.node(hand.joint)->name() + "'");
    if (number > 0 && g.parent(*j) != finger.joints.back())
      return fail(ctx, at + ": '" + g.node(*j)->name() + "' is not a child of '" +
                           g.node(finger.joints.back())->name() + "' (" + name + "." + std::to_string(number - 1) +
                           ")");
    finger.guides.push_back(i);
    finger.joints.push_back(*j);
    ++hand.control_count;
  }
  return hand;
}

Result<Vec3> axis_param(BuildContext& ctx) {
  const std::string name = ctx.param_string("bendAxis");
  if (const std::optional<Vec3> axis = axis_named(name)) return *axis;
  return fail(ctx, "bendAxis '" + name + "' is not one of x y z -x -y -z");
}

// The world-space axes of hand.h's file comment, from the rest pose.
struct FingerAxes {
  std::vector<Vec3> bend;             // per finger, unit
  std::vector<double> spread_weight;  // per finger: signed multiple of `spread`
  Vec3 normal = Vec3::UnitZ();        // the hand's normal (spread axis), unit
};

Result<FingerAxes> finger_axes(BuildContext& ctx, const Hand& hand) {
  scene::Scene& scene = ctx.scene();
  Result<Vec3> axis = axis_param(ctx);
  if (!axis) return axis.status();
  const std::size_t count = hand.fingers.size();
  FingerAxes out;
  std::vector<Vec3> base(count), first_bone(count);
  const Vec3 hand_position = position_of(scene.world_matrix(hand.joint));
  for (std::size_t k = 0; k < count; ++k) {
    const Finger& f = hand.fingers[k];
    std::vector<Vec3> p;
    for (NodeId j : f.joints) p.push_back(position_of(scene.world_matrix(j)));
    base[k] = p[0];
    const Vec3 h = rotation_of(scene.world_matrix(f.joints[0])) * *axis;
    // The first bone's direction (for a one-joint finger: from the hand).
    Vec3 d = p.size() > 1 ? Vec3(p[1] - p[0]) : Vec3(p[0] - hand_position);
    d = d.norm() > 1e-12 ? Vec3(d.normalized()) : Vec3(Vec3::Zero());
    first_bone[k] = d;
    Vec3 s = Vec3::Zero();
    double lengths = 0.0;
    for (std::size_t j = 0; j + 2 < p.size(); ++j) {
      const Vec3 u = p[j + 1] - p[j], v = p[j + 2] - p[j + 1];
      s += u.cross(v);
      lengths += u.norm() * v.norm();
    }
    Vec3 b;
    if (lengths > 0.0 && s.norm() > 1e-3 * lengths) {
      b = s.normalized();
      if (b.dot(h) < 0.0) b = -b;
    } else {
      b = h - d * d.dot(h);
      if (b.norm() < 1e-6)
        return fail(ctx, "finger '" + f.name + "' is straight and bendAxis " + ctx.param_string("bendAxis") +
                             " of '" + ctx.graph().node(f.joints[0])->name() + "' lies along its first bone");
      b.normalize();
    }
    out.bend.push_back(b);
  }
  out.spread_weight.assign(count, 0.0);
  if (count < 2) return out;
  int middle = static_cast<int>(count - 1) / 2;
  for (std::size_t k = 0; k < count; ++k)
    if (hand.fingers[k].name == "middle") middle = static_cast<int>(k);
  Vec3 mean = Vec3::Zero(), across = Vec3::Zero();
  bool only_thumbs = true;
  for (std::size_t k = 0; k < count; ++k) {
    mean += base[k] / double(count);
    if (hand.fingers[k].name != "thumb") only_thumbs = false;
  }
  for (std::size_t k = 0; k < count; ++k)
    if (only_thumbs || hand.fingers[k].name != "thumb") across += out.bend[k];
  const Vec3 forward = mean - hand_position;
  Vec3 n = forward.cross(across);
  if (n.norm() <= 1e-6 * forward.norm() * across.norm() || n.norm() < 1e-12)
    n = first_bone[middle].cross(out.bend[middle]);
  if (n.norm() < 1e-12) return fail(ctx, "cannot find the hand's normal (the fingers lie on one line)");
  out.normal = n.normalized();
  for (std::size_t k = 0; k < count; ++k) {
    const int offset = static_cast<int>(k) - middle;
    if (offset == 0) continue;
    // n x d_k is where the end of the first bone goes under a positive turn
    // about n; its dot with the offset from the middle finger's first joint
    // says whether that turn takes the finger away from the middle finger.
    const Vec3 apart = base[k] - base[middle];
    const double side = out.normal.cross(first_bone[k]).dot(apart);
    const double sign = std::abs(side) > 1e-9 * apart.norm() ? (side > 0 ? 1.0 : -1.0) : (offset > 0 ? 1.0 : -1.0);
    out.spread_weight[k] = sign * std::abs(offset);
  }
  return out;
}

// Whether a node of another component drives `joint`'s channels.
bool driven_by_rig(BuildContext& ctx, NodeId joint) {
  const graph::Graph& g = ctx.graph();
  for (AttrIndex a : {xform::kTranslate, xform::kRotate, xform::kRotateQuaternion, xform::kScale, xform::kShear}) {
    std::optional<Plug> source = g.source(plug(joint, a));
    if (!source) continue;
    const NodeId owner = component_of(g, source->node);
    if (owner.is_valid() && owner != ctx.meta()) return true;
  }
  return false;
}

class HandComponent : public ComponentClass {
 public:
  std::string_view type() const override { return "hand"; }
  std::vector<Step> steps(const Component&) const override {
    return {
        Step{"controls", "", "",
             [](BuildContext& ctx) -> Status {
               Result<Hand> hand = read_hand(ctx);
               if (!hand) return hand.status();
               // Controls at their guides (a joint, or off it by the guide's offset);
               // each drives its joint keeping that offset.
               Result<Mat4> hand_place = ctx.guide_world(0);
               if (!hand_place) return hand_place.status();
               Result<NodeId> control = ctx.create_control("hand", -1, 0, *hand_place, ctx.attach_node());
               if (!control) return control.status();
               if (Status s = ctx.publish_hook(0, *control); !s) return s;
               for (const Finger& f : hand->fingers) {
                 NodeId parent = *control;
                 for (std::size_t j = 0; j < f.joints.size(); ++j) {
                   Result<Mat4> place = ctx.guide_world(f.guides[j]);
                   if (!place) return place.status();
                   Result<NodeId> c =
                       ctx.create_control("finger", f.first_control + static_cast<int>(j), f.guides[j], *place, parent);
                   if (!c) return c.status();
                   parent = *c;
                 }
               }
               return Status::ok();
             }},
        Step{"curl", "", "",
             [](BuildContext& ctx) -> Status {
               if (!ctx.param_bool("curlAttributes")) return Status::ok();
               Result<Hand> hand = read_hand(ctx);
               if (!hand) return hand.status();
               if (hand->fingers.empty()) return Status::ok();
               Result<FingerAxes> axes = finger_axes(ctx, *hand);
               if (!axes) return axes.status();
               graph::Graph& g = ctx.graph();
               Result<NodeId> node = ctx.create(ops::util::kFingerCurlType, "fingerCurl");
               if (!node) return node.status();
               std::vector<std::string> names;
               std::vector<std::int64_t> finger;
               std::vector<Mat4> rest;
               std::vector<Vec3> bend, spread;
               std::vector<double> weight;
               const std::vector<NodeId> controls = ctx.nodes("finger");
               if (static_cast<int>(controls.size()) != hand->control_count)
                 return fail(ctx, "the finger controls do not match the guides");
               for (std::size_t k = 0; k < hand->fingers.size(); ++k) {
                 const Finger& f = hand->fingers[k];
                 names.push_back(f.name);
                 for (std::size_t j = 0; j < f.joints.size(); ++j) {
                   const NodeId c = controls[static_cast<std::size_t>(f.first_control) + j];
                   // The axes in the control's rest frame (the joint's).
                   const Mat3 frame = rotation_of(ctx.scene().world_matrix(c));
                   finger.push_back(static_cast<std::int64_t>(k));
                   rest.push_back(std::get<Mat4>(g.node(c)->value(xform::kOffsetParentMatrix)));
                   bend.push_back(frame.transpose() * axes->bend[k]);
                   spread.push_back(j == 0 ? Vec3(frame.transpose() * axes->normal) : Vec3(Vec3::Zero()));
                   weight.push_back(j == 0 ? axes->spread_weight[k] : 0.0);
                 }
               }
               Status s = g.set_value(plug(*node, fa::kFingerNames), Value(names));
               if (s) s = g.set_value(plug(*node, fa::kFingerCurl), Value(std::vector<double>(names.size(), 0.0)));
               if (s) s = g.set_value(plug(*node, fa::kFinger), Value(finger));
               if (s) s = g.set_value(plug(*node, fa::kRestOffsetParentMatrix), Value(rest));
               if (s) s = g.set_value(plug(*node, fa::kBendAxis), Value(bend));
               if (s) s = g.set_value(plug(*node, fa::kSpreadAxis), Value(spread));
               if (s) s = g.set_value(plug(*node, fa::kSpreadWeight), Value(weight));
               for (std::size_t i = 0; s && i < controls.size(); ++i)
                 s = g.connect(plug(*node, fa::kOutOffsetParentMatrix, static_cast<std::int32_t>(i)),
                               plug(controls[i], xform::kOffsetParentMatrix));
               if (!s) return s.with_context(ctx.full_name() + " fingerCurl");
               return Status::ok();
             }},
        Step{"drive", "", "",
             [](BuildContext& ctx) -> Status {
               Result<Hand> hand = read_hand(ctx);
               if (!hand) return hand.status();
               if (!driven_by_rig(ctx, hand->joint))
                 if (Status s = ctx.drive(ctx.node("hand"), hand->joint); !s) return s;
               for (const Finger& f : hand->fingers)
                 for (std::size_t j = 0; j < f.joints.size(); ++j)
                   if (Status s = ctx.drive(ctx.node("finger", f.first_control + static_cast<int>(j)), f.joints[j]); !s)
                     return s;
               return Status::ok();
             }},
    };
  }
};

}  // namespace

Status add_hand_component(ComponentFactory& factory) { return factory.add(std::make_shared<HandComponent>()); }

}  // namespace rigel::rig::components
