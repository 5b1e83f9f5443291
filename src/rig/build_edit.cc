// Rig edit mode (build.h): entering and leaving it, reading moved controls
// as moved guides, and committing those edits.
#include <charconv>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <string>

#include "build_internal.h"
#include "rigel/math/rotation.h"
#include "rigel/math/transform.h"
#include "rigel/rig/build.h"
#include "rigel/rig/component.h"
#include "rigel/rig/meta.h"

namespace rigel::rig {

using namespace detail;

namespace {

// A guide that stands at `world`: values, or the offset from its joint at
// `joint_world` (rotation in XYZ degrees; shear is dropped).
void place_guide(Guide& guide, const Mat4& world, const std::optional<Mat4>& joint_world) {
  const Mat4 m = joint_world ? Mat4(math::affine_inverse(*joint_world) * world) : world;
  const math::TransformParts parts = math::decompose_to_parts(m, math::RotateOrder::kXYZ);
  // Rounded to 1e-10 (of a metre, a degree): a turn of 90 degrees is written
  // 90, not 90.00000000000001, and clean files diff cleanly.
  auto clean = [](math::Vec3 v) {
    for (int k = 0; k < 3; ++k) v[k] = std::round(v[k] * 1e10) / 1e10 + 0.0;  // + 0.0: no -0
    return v;
  };
  guide.translate = clean(parts.translate);
  guide.rotate = clean(math::to_degrees(parts.rotate));
  guide.scale = clean(parts.scale);
}

// A control stands at its guide when its rest is the guide's place within this.
constexpr double kAtGuide = 1e-7;

}  // namespace

Status Build::set_edit_mode(bool on) {
  if (on == options_.edit_mode) return Status::ok();
  graph::Transaction tx(scene_.graph(), on ? "enter rig edit mode" : "leave rig edit mode");
  const int target = position_;
  Status s = go_to(0);
  if (s) {
    // With the metaRoot gone, the mode is ours to choose; the rig's own step
    // writes it on the new metaRoot.
    options_.edit_mode = on;
    s = go_to(target);
  }
  if (!s) {
    tx.rollback();
    options_.edit_mode = !on;
    (void)sync();
  }
  return s;
}


Result<Edits> Build::edits() {
  if (Status s = sync(); !s) return s;
  const NodeId root = this->root();
  if (!root.is_valid() || position_ != static_cast<int>(plan_.size()))
    return error(ErrorCode::kInvalidArgument, "edit " + definition_.name + ": the rig is not fully built");
  if (!options_.edit_mode)
    return error(ErrorCode::kInvalidArgument, "edit " + definition_.name +
                                                  ": the rig is not in edit mode (build it in edit mode: rigel build --edit-mode)");
  graph::Graph& g = scene_.graph();
  struct Made {
    std::size_t component;
    int guide;
    NodeId node;
    Mat4 now, rest;
  };
  std::vector<Made> controls;
  std::vector<NodeId> all;
  for (std::size_t i = 0; i < components_.size(); ++i) {
    const ComponentClass* cls = factory_.find(components_[i]->type);
    if (cls && !cls->editable()) continue;
    const NodeId meta = find_component(g, root, components_[i]->rig_id);
    for (NodeId m : meta_members(g, meta)) {
      if (!is_control(g, m)) continue;
      const std::string* tag = g.node(m)->tag_find(kTagGuide);
      int guide = -1;
      if (tag) std::from_chars(tag->data(), tag->data() + tag->size(), guide);
      controls.push_back(Made{i, guide, m, scene_.world_matrix(m), Mat4::Identity()});
      all.push_back(m);
    }
  }
  // Rest poses: every control zeroed, then rolled back. The joints' rest too.
  std::map<std::pair<std::size_t, int>, Mat4> joint_rest;
  g.begin_transaction("edit: rest pose");
  Status s;
  for (NodeId m : all)
    if (s) s = zero_channels(g, m);
  if (s) {
    for (Made& c : controls) c.rest = scene_.world_matrix(c.node);
    for (std::size_t i = 0; i < components_.size(); ++i)
      for (std::size_t k = 0; k < components_[i]->guides.size(); ++k) {
        const std::string& joint = components_[i]->guides[k].joint;
        const NodeId j = joint.empty() ? NodeId{} : g.find(joint);
        if (scene_.is_transform(j)) joint_rest[{i, static_cast<int>(k)}] = scene_.world_matrix(j);
      }
  }
  g.rollback_transaction();
  if (!s) return s.with_context("edit " + definition_.name);

  Edits out;
  out.definition = definition_;
  // Components by rigId in the copy (components_ points into definition_).
  std::map<std::pair<std::size_t, int>, const Made*> mover;
  for (const Made& c : controls) {
    if (math::is_near(c.now, c.rest, 1e-9)) continue;
    bool at_guide = c.guide >= 0 && c.guide < static_cast<int>(components_[c.component]->guides.size());
    if (at_guide) {
      // Only a control that stands at its guide stands for it.
      const Guide& guide = components_[c.component]->guides[static_cast<std::size_t>(c.guide)];
      auto jr = joint_rest.find({c.component, c.guide});
      if (!guide.joint.empty() && jr == joint_rest.end()) {
        at_guide = false;
      } else {
        const Mat4 place = guide.joint.empty() ? guide_values(guide) : Mat4(jr->second * guide_values(guide));
        // Limb controls stand at the place's rigid part (components/limbs.cc).
        at_guide = math::is_near(c.rest, place, kAtGuide) || math::is_near(c.rest, math::rigid_part(place), kAtGuide);
      }
    }
    if (!at_guide) {
      out.ignored.push_back(g.node(c.node)->name());
      continue;
    }
    auto [it, fresh] = mover.emplace(std::make_pair(c.component, c.guide), &c);
    if (fresh) continue;
    // Two moved controls of one guide must agree on the move.
    const Mat4 a = c.now * math::affine_inverse(c.rest);
    const Mat4 b = it->second->now * math::affine_inverse(it->second->rest);
    if (!math::is_near(a, b, 1e-9))
      return error(ErrorCode::kInvalidArgument, "edit " + definition_.name + ": '" + g.node(it->second->node)->name() +
                                                    "' and '" + g.node(c.node)->name() + "' both stand for guide " +
                                                    std::to_string(c.guide) + " of " + components_[c.component]->full_name() +
                                                    " and were moved differently; move one of them");
  }
  std::set<std::size_t> changed;
  for (const auto& [key, c] : mover) {
    const Component& before = *components_[key.first];
    Component* after = out.definition.find_by_rig_id(before.rig_id);
    if (!after) continue;
    Guide& guide = after->guides[static_cast<std::size_t>(key.second)];
    auto jr = joint_rest.find(key);
    const std::optional<Mat4> joint = jr == joint_rest.end() ? std::nullopt : std::optional<Mat4>(jr->second);
    const Mat4 was = joint ? Mat4(*joint * guide_values(guide)) : guide_values(guide);
    place_guide(guide, c->now * math::affine_inverse(c->rest) * was, joint);
    changed.insert(key.first);
  }
  for (std::size_t i : changed) {
    Component* after = out.definition.find_by_rig_id(components_[i]->rig_id);
    after->version = next_version(after->version);
    out.changed.push_back(after->rig_id);
  }
  if (!changed.empty()) out.definition.version = next_version(out.definition.version);
  return out;
}

Result<Edits> Build::commit_edits(const std::string& definition_path, bool leave_edit_mode) {
  Result<Edits> e = edits();
  if (!e) return e;
  graph::Graph& g = scene_.graph();
  const Definition before = definition_;
  graph::Transaction tx(g, "commit rig edits " + definition_.name);
  Status s;
  if (!e->changed.empty()) {
    Result<std::vector<std::string>> rebuilt = rebuild_changed(e->definition, Rebuild::kChanged);
    if (!rebuilt) s = rebuilt.status();
    if (s && !definition_path.empty()) {
      definition_.source = definition_path;
      const NodeId root = this->root();
      s = g.set_value(Plug{root, g.node(root)->type().attr_find("definitionPath"), -1}, Value(definition_path));
    }
  }
  if (s && leave_edit_mode) s = set_edit_mode(false);
  if (!s) {
    tx.rollback();
    definition_ = before;
    (void)replan();
    (void)sync();
    return s;
  }
  return e;
}

}  // namespace rigel::rig
