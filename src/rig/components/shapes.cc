// blendShapeSliders and corrective (components/shapes.h).
#include "rigel/rig/components/shapes.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "rigel/math/transform.h"
#include "rigel/ops/anim/nodes.h"
#include "rigel/ops/deform/nodes.h"
#include "rigel/ops/util/nodes.h"
#include "rigel/rig/build_context.h"
#include "rigel/rig/component.h"
#include "rigel/scene/transform_types.h"

namespace rigel::rig::components {
namespace {

using graph::Plug;
using graph::Value;
using math::Mat4;
using math::Vec3;
namespace xform = scene::xform;
namespace curve = ops::anim::curve_attr;
namespace bs = ops::blend_shape_attr;

Status fail(BuildContext& ctx, const std::string& what) {
  return error(ErrorCode::kInvalidArgument, ctx.full_name() + " (" + ctx.component().type + "): " + what);
}

// A drivenKey (role, index) from `driver` to `driven` through linear keys
// (times increasing; equal neighbours merged), constant beyond them.
Status driven_key(BuildContext& ctx, std::string_view role, int index, const Plug& driver, const Plug& driven,
                  std::vector<std::pair<double, double>> keys) {
  keys.erase(std::unique(keys.begin(), keys.end(), [](const auto& a, const auto& b) { return a.first == b.first; }),
             keys.end());
  Result<NodeId> node = ctx.create(ops::anim::kDrivenKeyType, role, index);
  if (!node) return node.status();
  std::vector<double> times, values;
  for (const auto& [t, v] : keys) times.push_back(t), values.push_back(v);
  const std::vector<std::int64_t> linear(keys.size(), 1);  // tangent type "linear"
  graph::Graph& g = ctx.graph();
  Status s = g.set_value(Plug{*node, curve::kKeyTimes, -1}, Value(times));
  if (s) s = g.set_value(Plug{*node, curve::kKeyValues, -1}, Value(values));
  if (s) s = g.set_value(Plug{*node, curve::kInTangentType, -1}, Value(linear));
  if (s) s = g.set_value(Plug{*node, curve::kOutTangentType, -1}, Value(linear));
  if (s) s = g.connect(driver, Plug{*node, ops::anim::driven_key_attr::kInput, -1});
  if (s) s = g.connect(Plug{*node, curve::kOutput, -1}, driven);
  return s.is_ok() ? s : s.with_context(ctx.full_name() + " " + std::string(role));
}

// The blendShape node named `name`, or the scene's only one.
Result<NodeId> blend_shape(BuildContext& ctx, const std::string& name) {
  graph::Graph& g = ctx.graph();
  if (!name.empty()) {
    const NodeId id = g.find(name);
    if (!id.is_valid() || g.node(id)->type().name() != ops::kBlendShapeType)
      return fail(ctx, "no blendShape node '" + name + "'");
    return id;
  }
  std::vector<NodeId> found;
  for (NodeId id : g.nodes())
    if (g.node(id)->type().name() == ops::kBlendShapeType) found.push_back(id);
  if (found.size() == 1) return found[0];
  std::string names;
  for (NodeId id : found) names += (names.empty() ? "" : ", ") + g.node(id)->name();
  return fail(ctx, found.empty() ? "the scene has no blendShape node"
                                 : "the scene has several blendShape nodes (" + names + "): name one (blendShape)");
}

std::size_t target_count(const graph::Graph& g, NodeId shape) {
  const auto& offsets = std::get<std::vector<std::int64_t>>(g.node(shape)->value(bs::kTargetOffsets));
  return offsets.empty() ? 0 : offsets.size() - 1;
}

// Target `ref` (a name, else an index) of `shape`.
Result<int> target_index(BuildContext& ctx, NodeId shape, const std::string& ref) {
  const graph::Graph& g = ctx.graph();
  const auto& names = std::get<std::vector<std::string>>(g.node(shape)->value(bs::kTargetNames));
  const auto named = std::find(names.begin(), names.end(), ref);
  if (!ref.empty() && named != names.end()) return static_cast<int>(named - names.begin());
  int index = -1;
  const auto [end, ec] = std::from_chars(ref.data(), ref.data() + ref.size(), index);
  if (ec == std::errc() && end == ref.data() + ref.size() && index >= 0 &&
      static_cast<std::size_t>(index) < target_count(g, shape))
    return index;
  return fail(ctx, "blendShape '" + g.node(shape)->name() + "' has no target '" + ref + "' (" +
                       std::to_string(target_count(g, shape)) + " targets)");
}

// The targets a component names (comma-separated), or every one.
Result<std::vector<int>> targets_of(BuildContext& ctx, NodeId shape) {
  std::vector<int> out;
  std::string list = ctx.param_string("targets");
  if (list.empty()) {
    for (std::size_t t = 0; t < target_count(ctx.graph(), shape); ++t) out.push_back(static_cast<int>(t));
    if (out.empty()) return fail(ctx, "blendShape '" + ctx.graph().node(shape)->name() + "' has no targets");
    return out;
  }
  std::size_t start = 0;
  while (start <= list.size()) {
    const std::size_t comma = std::min(list.find(',', start), list.size());
    std::string ref = list.substr(start, comma - start);
    ref.erase(0, ref.find_first_not_of(' '));
    ref.erase(ref.find_last_not_of(' ') + 1);
    Result<int> t = target_index(ctx, shape, ref);
    if (!t) return t.status();
    out.push_back(*t);
    start = comma + 1;
  }
  return out;
}

double weight_now(const graph::Graph& g, NodeId shape, int target) {
  const auto& w = std::get<std::vector<double>>(g.node(shape)->value(bs::kWeights));
  return static_cast<std::size_t>(target) < w.size() ? w[static_cast<std::size_t>(target)] : 0.0;
}

class BlendShapeSliders : public ComponentClass {
 public:
  std::string_view type() const override { return "blendShapeSliders"; }
  std::vector<Step> steps(const Component&) const override {
    return {
        Step{"sliders", "", "",
             [](BuildContext& ctx) -> Status {
               Result<NodeId> shape = blend_shape(ctx, ctx.param_string("blendShape"));
               if (!shape) return shape.status();
               Result<std::vector<int>> targets = targets_of(ctx, *shape);
               if (!targets) return targets.status();
               Result<Mat4> panel_world = ctx.guide_world(0);
               if (!panel_world) return panel_world.status();
               Result<NodeId> panel = ctx.create_group("panel", -1, math::rigid_part(*panel_world), ctx.attach_node());
               if (!panel) return panel.status();
               if (Status s = ctx.publish_hook(0, *panel); !s) return s;
               const double spacing = ctx.param_double("spacing");
               for (std::size_t k = 0; k < targets->size(); ++k) {
                 Mat4 place = math::rigid_part(*panel_world);
                 place.topRightCorner<3, 1>() += place.topLeftCorner<3, 3>() * Vec3(0, -spacing * double(k), 0);
                 Result<NodeId> slider = ctx.create_control("slider", static_cast<int>(k), 0, place, *panel);
                 if (!slider) return slider.status();
               }
               return Status::ok();
             }},
        Step{"drive", "", "",
             [](BuildContext& ctx) -> Status {
               Result<NodeId> shape = blend_shape(ctx, ctx.param_string("blendShape"));
               if (!shape) return shape.status();
               Result<std::vector<int>> targets = targets_of(ctx, *shape);
               if (!targets) return targets.status();
               const double lo = ctx.param_double("min"), hi = ctx.param_double("max");
               if (!(lo < hi)) return fail(ctx, "min must be below max");
               for (std::size_t k = 0; k < targets->size(); ++k) {
                 const int t = (*targets)[k];
                 const double w0 = std::clamp(weight_now(ctx.graph(), *shape, t), lo, hi);
                 const Plug y{ctx.node("slider", static_cast<int>(k)), xform::kTranslate, -1, 1};
                 if (Status s = driven_key(ctx, "weight", static_cast<int>(k), y, Plug{*shape, bs::kWeights, t},
                                           {{lo - w0, lo}, {0.0, w0}, {hi - w0, hi}});
                     !s)
                   return s;
               }
               return Status::ok();
             }},
    };
  }
};

class Corrective : public ComponentClass {
 public:
  std::string_view type() const override { return "corrective"; }
  std::vector<Step> steps(const Component&) const override {
    return {
        Step{"reader", "", "",
             [](BuildContext& ctx) -> Status {
               Result<NodeId> driver = ctx.guide_joint(0);
               if (!driver) return driver.status();
               const double start = ctx.param_double("startAngle"), end = ctx.param_double("endAngle");
               if (!(start < end)) return fail(ctx, "startAngle must be below endAngle");
               const bool shape = !ctx.param_string("target").empty();
               if (ctx.guide_count() < 2 && !shape)
                 return fail(ctx, "nothing to correct: give a corrective joint (guide 1) or a blend shape target");
               Result<NodeId> reader = ctx.create(ops::util::kPoseReaderType, "reader");
               if (!reader) return reader.status();
               graph::Graph& g = ctx.graph();
               namespace pr = ops::util::pose_reader_attr;
               const std::string axis = ctx.param_string("axis");
               Status s = g.connect(Plug{*driver, xform::kMatrix, -1}, Plug{*reader, pr::kMatrix, -1});
               if (s) s = g.set_value(Plug{*reader, pr::kRestMatrix, -1}, g.evaluate(*driver, xform::kMatrix));
               if (s)
                 s = g.set_value(Plug{*reader, pr::kAxis, -1},
                                 Value(Vec3(axis == "x" ? 1.0 : 0.0, axis == "y" ? 1.0 : 0.0, axis == "z" ? 1.0 : 0.0)));
               return s.is_ok() ? s : s.with_context(ctx.full_name() + " reader");
             }},
        Step{"correct", "", "",
             [](BuildContext& ctx) -> Status {
               const double start = ctx.param_double("startAngle"), end = ctx.param_double("endAngle");
               const Plug angle{ctx.node("reader"), ops::util::pose_reader_attr::kAngle, -1};
               graph::Graph& g = ctx.graph();
               if (ctx.guide_count() > 1) {
                 Result<NodeId> joint = ctx.guide_joint(1);
                 if (!joint) return joint.status();
                 const Vec3 rest = std::get<Vec3>(g.evaluate(*joint, xform::kTranslate));
                 const Vec3 offset = ctx.param_vec3("offset");
                 const char* roles[] = {"offsetX", "offsetY", "offsetZ"};
                 for (std::int8_t k = 0; k < 3; ++k) {
                   if (offset[k] == 0.0) continue;
                   if (Status s = driven_key(ctx, roles[k], -1, angle, Plug{*joint, xform::kTranslate, -1, k},
                                             {{start, rest[k]}, {end, rest[k] + offset[k]}});
                       !s)
                     return s;
                 }
               }
               const std::string target = ctx.param_string("target");
               if (target.empty()) return Status::ok();
               Result<NodeId> shape = blend_shape(ctx, ctx.param_string("blendShape"));
               if (!shape) return shape.status();
               Result<int> t = target_index(ctx, *shape, target);
               if (!t) return t.status();
               return driven_key(ctx, "weight", -1, angle, Plug{*shape, bs::kWeights, *t}, {{start, 0.0}, {end, 1.0}});
             }},
    };
  }
};

}  // namespace

Status add_shape_components(ComponentFactory& factory) {
  if (Status s = factory.add(std::make_shared<BlendShapeSliders>()); !s) return s;
  return factory.add(std::make_shared<Corrective>());
}

}  // namespace rigel::rig::components
