#include "rigel/ephemeral/session.h"

#include <algorithm>
#include <string>

#include "modes/modes.h"
#include "rigel/ephemeral/keying.h"
#include "rigel/math/transform.h"
#include "rigel/scene/transform_types.h"

namespace rigel::ephemeral {
namespace {

using graph::Plug;
using math::Mat3;
using modes::eval_mat;
using modes::lin;
using modes::pos;
namespace xform = scene::xform;

bool is_zero_motion(const Delta& d) {
  return d.translate.isZero(0.0) && d.rotate.vec().isZero(0.0) && d.scale == Vec3::Ones();
}

void plan_mode(Mode mode, modes::Planner& p) {
  switch (mode) {
    case Mode::kForward: return modes::plan_forward(p);
    case Mode::kSuspended: return modes::plan_suspended(p);
    case Mode::kPseudoInverse: return modes::plan_pseudo_inverse(p);
    case Mode::kPseudoInverseLength: return modes::plan_pseudo_inverse_length(p);
    case Mode::kInverse: return modes::plan_inverse(p);
    case Mode::kMagnet: return modes::plan_magnet(p);
    case Mode::kMagnetRadius: return modes::plan_magnet_radius(p);
    case Mode::kBody: return modes::plan_body(p);
  }
}

Status solve_mode(Mode mode, modes::Drag& d, const std::optional<Mat4>& body_pivot) {
  switch (mode) {
    case Mode::kForward: return modes::solve_forward(d);
    case Mode::kSuspended: return modes::solve_suspended(d);
    case Mode::kPseudoInverse: return modes::solve_pseudo_inverse(d);
    case Mode::kPseudoInverseLength: return modes::solve_pseudo_inverse_length(d);
    case Mode::kInverse: return modes::solve_inverse(d);
    case Mode::kMagnet: return modes::solve_magnet(d);
    case Mode::kMagnetRadius: return modes::solve_magnet_radius(d);
    case Mode::kBody: return modes::solve_body(d, *body_pivot);
  }
  return error(ErrorCode::kInvalidArgument, "drag: unknown mode");
}

}  // namespace

const char* mode_name(Mode mode) {
  switch (mode) {
    case Mode::kForward: return "forward";
    case Mode::kSuspended: return "suspended";
    case Mode::kPseudoInverse: return "pseudo-inverse";
    case Mode::kPseudoInverseLength: return "pseudo-inverse-length";
    case Mode::kInverse: return "inverse";
    case Mode::kMagnet: return "magnet";
    case Mode::kMagnetRadius: return "magnet-radius";
    case Mode::kBody: return "body";
  }
  return "unknown";
}

std::optional<Mode> mode_from_name(std::string_view name) {
  for (int m = 0; m < kModeCount; ++m)
    if (name == mode_name(static_cast<Mode>(m))) return static_cast<Mode>(m);
  return std::nullopt;
}

const char* role_name(Role role) {
  switch (role) {
    case Role::kGrabbed: return "grabbed";
    case Role::kChain: return "chain";
    case Role::kFollow: return "follow";
    case Role::kMagnet: return "magnet";
    case Role::kBody: return "body";
    case Role::kKeepWorld: return "keep-world";
  }
  return "unknown";
}

const PlanEntry* Plan::entry_find(NodeId control) const {
  for (const PlanEntry& e : entries)
    if (e.control == control) return &e;
  return nullptr;
}

// The index and the scratch are the modes' (modes/modes.h).
struct Session::Index : modes::Index {};
struct Session::Scratch : modes::Scratch {};

Session::Session(scene::Scene& scene, SessionOptions options)
    : scene_(scene), options_(options), scratch_(std::make_unique<Scratch>()) {
  scene_.graph().add_observer(this);
}

Session::~Session() { scene_.graph().remove_observer(this); }

void Session::set_mode(Mode mode) {
  if (mode != mode_) plan_.reset();
  mode_ = mode;
}

void Session::set_options(const SessionOptions& options) {
  options_ = options;
  plan_.reset();
}

void Session::select(std::vector<NodeId> controls) {
  scene_.graph().select(std::move(controls));
  plan_.reset();
}

void Session::set_body_pivot(const Mat4& world) {
  body_pivot_ = math::rigid_part(world);
  plan_.reset();
}

void Session::clear_body_pivot() {
  body_pivot_.reset();
  plan_.reset();
}

void Session::release() { plan_.reset(); }

void Session::external_change(bool topology) {
  if (writing_) return;
  plan_.reset();
  if (topology) index_.reset();
}

void Session::attribute_changed(const Graph& graph, const graph::Plug& plug) {
  if (writing_) return;
  plan_.reset();
  const graph::Node* n = graph.node(plug.node);
  if (n && n->type().name() == kRigType) index_.reset();
}

Status Session::index_ensure() {
  if (index_) return Status::ok();
  auto index = std::make_unique<Index>();
  if (Status s = modes::index_build(scene_, *index); !s) return s;
  index_ = std::move(index);
  return Status::ok();
}

std::vector<NodeId> Session::grabbed() {
  std::vector<NodeId> out;
  if (!index_ensure()) return out;
  const Graph& graph = scene_.graph();
  std::vector<int> ks;
  for (NodeId id : graph.selection()) {
    int k = index_->find(graph, id);
    if (k >= 0 && std::find(ks.begin(), ks.end(), k) == ks.end()) ks.push_back(k);
  }
  std::sort(ks.begin(), ks.end(), [&](int a, int b) { return index_->ctrls[a].order < index_->ctrls[b].order; });
  for (int k : ks) out.push_back(index_->ctrls[k].id);
  return out;
}

Result<const Plan*> Session::plan() {
  if (!plan_) {
    Result<std::unique_ptr<Plan>> built = plan_build();
    if (!built) return built.status();
    plan_ = std::move(*built);
    gesture_ = Graph::new_merge_key();
    ++plans_built_;
  }
  return static_cast<const Plan*>(plan_.get());
}

// ---- planning: the mode's planner (walkNodes), then what every mode needs ---

Result<std::unique_ptr<Plan>> Session::plan_build() {
  if (Status s = index_ensure(); !s) return s;
  Graph& graph = scene_.graph();
  auto plan = std::make_unique<Plan>();
  plan->mode = mode_;
  plan->grabbed = grabbed();
  if (plan->grabbed.empty()) return error(ErrorCode::kInvalidArgument, "ephemeral: no control is grabbed (select controls of an ephemeral rig)");
  Scratch& sc = *scratch_;
  sc.ctrl.clear();
  sc.entry_of.assign(index_->ctrls.size(), -1);
  modes::Planner planner{graph, *index_, options_, *plan, sc, {}, body_pivot_, plan_body_pivot_};
  for (NodeId id : plan->grabbed) planner.grabbed.push_back(index_->find(graph, id));
  plan_mode(mode_, planner);
  if (Status s = modes::plan_finish(planner); !s) return s;
  return plan;
}

// ---- solving and writing -----------------------------------------------------

Status Session::drag_to(NodeId control, const Mat4& world) {
  if (Status s = index_ensure(); !s) return s;
  Graph& graph = scene_.graph();
  const int k = index_->find(graph, control);
  std::vector<NodeId> g = grabbed();
  if (k < 0 || std::find(g.begin(), g.end(), index_->ctrls[k].id) == g.end())
    return error(ErrorCode::kInvalidArgument, "drag_to: the control is not grabbed");
  const Mat4 current = math::rigid_part(eval_mat(graph, index_->ctrls[k].id, xform::kWorldMatrix));
  const Mat4 target = math::rigid_part(world);
  Delta d;
  d.translate = pos(target) - pos(current);
  d.rotate = Quat(Mat3(lin(target) * lin(current).transpose())).normalized();
  return drag(d);
}

Status Session::drag(const Delta& delta) {
  notes_.clear();
  if (!delta.translate.allFinite() || !delta.rotate.coeffs().allFinite() || !delta.scale.allFinite())
    return error(ErrorCode::kInvalidArgument, "drag: the motion is not finite");
  if (mode_ != Mode::kBody && delta.scale != Vec3::Ones())
    return error(ErrorCode::kInvalidArgument, "drag: scale applies in body mode only");
  if (mode_ == Mode::kBody && (delta.scale.array() <= 0).any())
    return error(ErrorCode::kInvalidArgument, "drag: body scale must be positive");
  if (is_zero_motion(delta)) return Status::ok();
  if (Result<const Plan*> p = plan(); !p) return p.status();
  return solve(delta);
}

// The mode's solver gives every moved control its new world; the channels
// that put them there are computed, then written as one undo step.
Status Session::solve(const Delta& delta) {
  Graph& graph = scene_.graph();
  Scratch& sc = *scratch_;
  const Plan& plan = *plan_;
  const std::size_t n = plan.entries.size();
  std::fill(sc.has_w.begin(), sc.has_w.end(), 0);
  std::fill(sc.has_wn.begin(), sc.has_wn.end(), 0);
  sc.motion.resize(n);
  sc.has_motion.assign(n, 0);
  // The plan's own state: while it lives nothing but its drags edits the
  // scene (anything else drops it), so the world matrices the last drag
  // wrote are the ones the graph would evaluate now (within 1e-12: channels
  // closer than that to their old values are not rewritten), and the drag
  // does not pull the graph for them. Evaluating for display is left to
  // whoever displays.
  if (sc.last_gesture != gesture_) {
    sc.last_gesture = gesture_;
    sc.has_last.assign(n, 0);
    sc.last.resize(n);
  }
  modes::Drag d(graph, *index_, sc, plan, options_, delta, notes_);
  if (Status s = solve_mode(plan.mode, d, plan_body_pivot_); !s) return s;
  bool exact = true;  // every written rotation is a rotation (no projection)
  if (Status s = modes::local_writes(scene_, d, exact); !s) return s;
  // What the next drag of this plan may take as the current world matrices.
  auto remember = [&](bool valid) {
    for (std::size_t e = 0; e < n; ++e) {
      sc.has_last[e] = valid && sc.has_wn[e];
      if (sc.has_last[e]) sc.last[e] = sc.wn[e];
    }
  };
  if (sc.writes.empty()) {
    remember(false);
    return Status::ok();
  }

  graph::Transaction tx(graph, std::string("ephemeral drag (") + mode_name(plan.mode) + ")", gesture_);
  writing_ = true;
  Status status;
  // Keys (keying.h): auto-key first keys the keying group of every keyed
  // control moved at a time with no key, then every keyed channel writes
  // its key at this time (refused, writing nothing, when there is none).
  if (options_.auto_key) {
    std::vector<NodeId> to_key;
    for (const Scratch::Write& wr : sc.writes) {
      const NodeId id = plan.entries[wr.entry].control;
      if (is_keyed(graph, id) && !has_key_now(graph, id)) to_key.push_back(id);
    }
    if (!to_key.empty()) status = set_key(graph, to_key);
  }
  auto connected = [](const graph::Node& node, graph::AttrIndex attr) {
    for (const graph::Connection& c : node.inputs())
      if (c.dst.attr == attr) return true;
    return false;
  };
  auto write = [&](NodeId id, graph::AttrIndex attr, const graph::Value& value) {
    if (connected(*graph.node(id), attr)) {
      exact = false;  // a key evaluated at a time within key_time_tolerance() of it: re-read next time
      return write_channel(graph, id, attr, value, false);
    }
    return graph.set_value(Plug{id, attr, -1}, value);
  };
  for (const Scratch::Write& wr : sc.writes) {
    if (!status) break;
    const NodeId id = plan.entries[wr.entry].control;
    if (wr.set_t) status = write(id, xform::kTranslate, wr.translate);
    if (status && wr.set_r) status = write(id, wr.rotation_attr, wr.rotation);
  }
  if (!status) {
    tx.rollback();
    writing_ = false;
    remember(false);
    return status.with_context("drag");
  }
  writing_ = false;
  remember(exact);
  if (plan.mode == Mode::kBody) {
    plan_body_pivot_ = d.pivot_new;
    if (body_pivot_) body_pivot_ = d.pivot_new;
  }
  return Status::ok();
}

}  // namespace rigel::ephemeral
