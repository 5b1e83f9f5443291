// Over 800 lines: Session::solve and plan_build split by mode with issue 15
// (its own two-bone solver and decomposition move to ops and scene).
#include "rigel/ephemeral/session.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <span>
#include <string>
#include <unordered_map>

#include "rigel/ephemeral/keying.h"
#include "rigel/math/rotation.h"
#include "rigel/math/transform.h"
#include "rigel/ops/ik/fabrik.h"
#include "rigel/scene/transform_types.h"

namespace rigel::ephemeral {
namespace {

using graph::Plug;
using math::Mat3;
namespace xform = scene::xform;

Vec3 pos(const Mat4& m) { return m.topRightCorner<3, 1>(); }
Mat3 lin(const Mat4& m) { return m.topLeftCorner<3, 3>(); }
Mat4 make(const Mat3& linear, const Vec3& translation) {
  Mat4 out = Mat4::Identity();
  out.topLeftCorner<3, 3>() = linear;
  out.topRightCorner<3, 1>() = translation;
  return out;
}

// The smallest rotation taking direction `from` to `to` (identity when
// either is degenerate).
Mat3 swing(const Vec3& from, const Vec3& to) {
  const double a = from.norm(), b = to.norm();
  if (a < 1e-300 || b < 1e-300) return Mat3::Identity();
  return Quat::FromTwoVectors(from / a, to / b).normalized().toRotationMatrix();
}

// Orthonormal frame with x along `x` and z along `z` (z perpendicular to x).
Mat3 frame(const Vec3& x, const Vec3& z) {
  Mat3 f;
  const Vec3 xn = x.normalized(), zn = z.normalized();
  f.col(0) = xn;
  f.col(1) = zn.cross(xn);
  f.col(2) = zn;
  return f;
}

// The axis of `r` (a chain top's world rotation) most perpendicular to the
// unit direction `u`: where a straight chain bends (x before y before z on
// ties).
Vec3 straight_pole(const Mat3& r, const Vec3& u) {
  int best = 0;
  for (int c = 1; c < 3; ++c)
    if (std::abs(r.col(c).normalized().dot(u)) < std::abs(r.col(best).normalized().dot(u))) best = c;
  return r.col(best).normalized();
}

// The unit vector perpendicular to unit `u` nearest `toward` (any
// perpendicular when `toward` is along `u`).
Vec3 perpendicular(const Vec3& u, const Vec3& toward) {
  Vec3 w = toward - toward.dot(u) * u;
  if (w.norm() <= 1e-9 * std::max(1.0, toward.norm())) w = u.unitOrthogonal();
  return w.normalized();
}

// Lays joints 1..n of `p` (bone i from p[i] to p[i + 1], length len[i];
// p[0] stays) on a circular arc in the plane of unit `u` (toward the
// target) and unit `w` (perpendicular: the side the arc bulges to), every
// joint turning by the same angle, chosen by bisection so that the chord
// is `d` (straight when d is the chain's length or more).
void lay_arc(std::span<Vec3> p, std::span<const double> len, const Vec3& u, const Vec3& w, double d) {
  const std::size_t n = len.size();
  auto planar = [&](double turn, std::size_t upto) {
    Eigen::Vector2d q = Eigen::Vector2d::Zero();
    for (std::size_t i = 0; i < upto; ++i) q += len[i] * Eigen::Vector2d(std::cos(turn * i), std::sin(turn * i));
    return q;
  };
  double lo = 0, hi = 2 * std::numbers::pi / static_cast<double>(n);
  if (planar(hi, n).norm() >= d) {
    lo = hi;
  } else {
    for (int it = 0; it < 200 && hi - lo > 1e-17; ++it) {
      const double mid = 0.5 * (lo + hi);
      (planar(mid, n).norm() > d ? lo : hi) = mid;
    }
  }
  const Eigen::Vector2d chord = planar(lo, n);
  const Eigen::Vector2d c = chord.norm() > 0 ? Eigen::Vector2d(chord.normalized()) : Eigen::Vector2d(1, 0);
  const Eigen::Vector2d side(-c.y(), c.x());
  // The bulge toward +w.
  const double sign = planar(lo, n / 2 > 0 ? n / 2 : 1).dot(side) < 0 ? -1.0 : 1.0;
  for (std::size_t i = 1; i <= n; ++i) {
    const Eigen::Vector2d q = planar(lo, i);
    p[i] = p[0] + q.dot(c) * u + sign * q.dot(side) * w;
  }
}

// Places joints i + 1 .. j of `p` (bone k from p[k] to p[k + 1], length
// len[k]; p[i] stays) so that p[j] lands on `t` whenever the bones reach it
// (as near as they get otherwise), exactly to rounding. The range splits at
// its middle joint into two halves; the middle joint is placed by the
// two-bone rule in the current bend plane (toward `pole` when straight),
// each half turns rigidly about its start onto its new ends, and a half
// whose end-to-end span must change for the target to be reached (stretched
// toward its length, or folded toward its shortest span, each half in
// proportion to its room) is solved the same way.
void reach(std::span<Vec3> p, std::span<const double> len, int i, int j, const Vec3& t, const Vec3& pole) {
  const int n = j - i;
  if (n <= 0) return;
  const Vec3 s = p[i];
  const Vec3 tv = t - s;
  const double d = tv.norm();
  if (n == 1) {
    if (d > 1e-300) p[j] = s + len[i] * tv / d;
    return;
  }
  const int k = i + n / 2;
  double la = 0, lb = 0, max_a = 0, max_b = 0;
  for (int x = i; x < k; ++x) la += len[x], max_a = std::max(max_a, len[x]);
  for (int x = k; x < j; ++x) lb += len[x], max_b = std::max(max_b, len[x]);
  const double min_a = std::max(0.0, 2 * max_a - la), min_b = std::max(0.0, 2 * max_b - lb);
  const double a = (p[k] - s).norm(), b = (p[j] - p[k]).norm();
  double a2 = a, b2 = b;
  if (d >= la + lb) {
    a2 = la;
    b2 = lb;
  } else if (d > a + b) {
    const double room = (la - a) + (lb - b);
    const double f = room > 0 ? std::clamp((d - a - b) / room, 0.0, 1.0) : 0.0;
    a2 = a + f * (la - a);
    b2 = b + f * (lb - b);
  } else if (d < std::abs(a - b)) {
    if (a >= b) {
      const double room = (a - min_a) + (lb - b);
      const double f = room > 0 ? std::clamp((a - b - d) / room, 0.0, 1.0) : 0.0;
      a2 = a - f * (a - min_a);
      b2 = b + f * (lb - b);
    } else {
      const double room = (b - min_b) + (la - a);
      const double f = room > 0 ? std::clamp((b - a - d) / room, 0.0, 1.0) : 0.0;
      b2 = b - f * (b - min_b);
      a2 = a + f * (la - a);
    }
  }
  const double scale = std::max(la + lb, 1e-300);
  Vec3 u = tv;
  if (d <= 1e-12 * scale) u = p[j] - s;
  if (u.norm() <= 1e-12 * scale) u = p[k] - s;
  u = u.norm() > 1e-300 ? Vec3(u.normalized()) : perpendicular(pole, Vec3::UnitX());
  Vec3 w = (p[k] - s) - (p[k] - s).dot(u) * u;
  w = w.norm() > 1e-9 * scale ? Vec3(w.normalized()) : perpendicular(u, pole);
  const double dc = std::clamp(d, std::abs(a2 - b2), a2 + b2);
  const double cos_a = a2 > 0 && dc > 0 ? std::clamp((a2 * a2 + dc * dc - b2 * b2) / (2 * a2 * dc), -1.0, 1.0) : 1.0;
  const double sin_a = std::sqrt(std::max(0.0, 1 - cos_a * cos_a));
  const Vec3 qk = s + a2 * (cos_a * u + sin_a * w);
  const Vec3 old_k = p[k];
  const Mat3 ra = swing(old_k - s, qk - s);
  for (int x = i + 1; x <= k; ++x) p[x] = s + ra * (p[x] - s);
  if (k - i >= 2 && a2 != a) reach(p, len, i, k, qk, pole);
  const Vec3 new_k = p[k];
  const Mat3 rb = swing(p[j] - old_k, t - new_k);
  for (int x = k + 1; x <= j; ++x) p[x] = new_k + rb * (p[x] - old_k);
  if (j - k >= 2 && b2 != b) reach(p, len, k, j, t, pole);
}

const Mat4& eval_mat(Graph& graph, NodeId id, graph::AttrIndex attr) { return std::get<Mat4>(graph.evaluate(id, attr)); }

bool is_zero_motion(const Delta& d) {
  return d.translate.isZero(0.0) && d.rotate.vec().isZero(0.0) && d.scale == Vec3::Ones();
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

// ---- the index: controls of every rig, their hierarchy and relations -------

struct Session::Index {
  struct Edge {
    int to;
    RelationKind kind;
  };
  struct Ctrl {
    NodeId id;
    int parent = -1;  // hierarchy parent, when it is an indexed control or a joint one drives
    // The hierarchy parent is a joint that `parent` drives (a character
    // rigged under another one's joint): it moves rigidly with `parent`.
    bool parent_via_joint = false;
    std::vector<int> children;
    std::vector<Edge> out;
    int order = 0;  // position in Scene::hierarchy()
    int rig = 0;
    int forward_out = 0;
  };
  std::vector<Ctrl> ctrls;
  std::unordered_map<std::uint32_t, int> by_index;  // NodeId.index -> ctrl (controls and the joints they drive)
  std::vector<std::vector<int>> rig_members;
  std::vector<std::vector<int>> rig_group;  // rig -> the rigs merged with it (itself included)

  int find(const Graph& graph, NodeId id) const {
    auto it = by_index.find(id.index);
    if (it == by_index.end() || !graph.node(id)) return -1;
    const Ctrl& c = ctrls[it->second];
    if (c.id == id) return it->second;
    // A joint driven by this control.
    for (const graph::Connection& conn : graph.node(c.id)->outputs())
      if (conn.dst.node == id) return it->second;
    return -1;
  }
};

struct Session::Scratch {
  std::vector<int> ctrl;           // entry -> index control
  std::vector<int> entry_of;       // index control -> entry (-1)
  std::vector<int> units;          // solve order: >= 0 entry, < 0 chain -(c + 1)
  std::vector<std::uint8_t> free;  // follower of its hierarchy parent: never written
  std::vector<Mat4> w, wn;
  std::vector<std::uint8_t> has_w, has_wn, has_motion;
  std::vector<Mat4> last;  // world matrices the last drag of this plan wrote
  std::vector<std::uint8_t> has_last;
  std::uint64_t last_gesture = 0;
  std::vector<Quat> motion;  // magnet: each driver's rotation this drag
  std::vector<Mat4> chain_world;
  std::vector<Vec3> positions, solved;
  std::vector<double> lengths;
  std::vector<Quat> corrections;
  struct Write {
    int entry;
    Vec3 translate;
    Quat rotation;  // rotateQuaternion controls
    Vec3 euler;     // rotate (degrees), Euler controls
    bool set_t, set_r;
  };
  std::vector<Write> writes;
};

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
  Graph& graph = scene_.graph();
  auto index = std::make_unique<Index>();
  std::unordered_map<std::uint32_t, int> order;
  {
    std::vector<NodeId> h = scene_.hierarchy();
    for (std::size_t i = 0; i < h.size(); ++i) order[h[i].index] = static_cast<int>(i);
  }
  std::vector<NodeId> rigs = rigs_find(graph);
  for (std::size_t r = 0; r < rigs.size(); ++r) {
    index->rig_members.emplace_back();
    for (NodeId c : rig_controls(graph, rigs[r])) {
      if (index->by_index.count(c.index)) continue;  // listed by an earlier rig
      Index::Ctrl ctrl;
      ctrl.id = c;
      ctrl.rig = static_cast<int>(r);
      auto it = order.find(c.index);
      ctrl.order = it == order.end() ? 0 : it->second;
      const int k = static_cast<int>(index->ctrls.size());
      index->by_index[c.index] = k;
      index->rig_members.back().push_back(k);
      index->ctrls.push_back(std::move(ctrl));
    }
  }
  for (Index::Ctrl& c : index->ctrls) {
    NodeId p = graph.parent(c.id);
    auto it = p.is_valid() ? index->by_index.find(p.index) : index->by_index.end();
    if (it != index->by_index.end() && index->ctrls[it->second].id == p) {
      c.parent = it->second;
    }
    // Joints this control drives map to it (selecting a joint grabs its control).
    for (const graph::Connection& conn : graph.node(c.id)->outputs())
      if (conn.src.attr == xform::kTranslate) index->by_index.emplace(conn.dst.node.index, index->by_index[c.id.index]);
  }
  // A control whose parent is a joint driven by a control (the root of a
  // second character rigged under the first one's joints) moves with that
  // control: it is its parent for the plan, so it is carried once and kept
  // in place when the plan leaves it out.
  for (std::size_t k = 0; k < index->ctrls.size(); ++k) {
    Index::Ctrl& c = index->ctrls[k];
    if (c.parent >= 0) continue;
    const NodeId p = graph.parent(c.id);
    const int driver = p.is_valid() ? index->find(graph, p) : -1;
    if (driver >= 0 && driver != static_cast<int>(k) && index->ctrls[driver].id != p) {
      c.parent = driver;
      c.parent_via_joint = true;
    }
  }
  for (std::size_t k = 0; k < index->ctrls.size(); ++k)
    if (index->ctrls[k].parent >= 0) index->ctrls[index->ctrls[k].parent].children.push_back(static_cast<int>(k));
  std::vector<Relation> all;
  for (NodeId rig : rigs) {
    Result<std::vector<Relation>> rel = relations(graph, rig);
    if (!rel) return rel.status();
    all.insert(all.end(), rel->begin(), rel->end());
  }
  for (const Relation& r : carrier_relations(graph)) all.push_back(r);
  // Merged characters (keying.h) move together in body mode.
  index->rig_group.resize(rigs.size());
  for (std::size_t r = 0; r < rigs.size(); ++r)
    for (NodeId m : merged_rigs(graph, rigs[r]))
      for (std::size_t q = 0; q < rigs.size(); ++q)
        if (rigs[q] == m) index->rig_group[r].push_back(static_cast<int>(q));
  {
    for (const Relation& r : all) {
      int f = index->find(graph, r.from), t = index->find(graph, r.to);
      if (f < 0 || t < 0 || index->ctrls[f].id != r.from || index->ctrls[t].id != r.to) continue;
      index->ctrls[f].out.push_back(Index::Edge{t, r.kind});
      if (r.kind == RelationKind::kForward) ++index->ctrls[f].forward_out;
    }
  }
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

// ---- planning (walkNodes) ----------------------------------------------------

Result<std::unique_ptr<Plan>> Session::plan_build() {
  if (Status s = index_ensure(); !s) return s;
  Graph& graph = scene_.graph();
  const Index& ix = *index_;
  Scratch& sc = *scratch_;
  auto plan = std::make_unique<Plan>();
  plan->mode = mode_;
  plan->grabbed = grabbed();
  if (plan->grabbed.empty()) return error(ErrorCode::kInvalidArgument, "ephemeral: no control is grabbed (select controls of an ephemeral rig)");

  sc.ctrl.clear();
  sc.entry_of.assign(ix.ctrls.size(), -1);
  std::vector<PlanEntry>& entries = plan->entries;
  auto add = [&](int k, Role role, int driver) {
    const int e = static_cast<int>(entries.size());
    PlanEntry entry;
    entry.control = ix.ctrls[k].id;
    entry.role = role;
    entry.driver = driver;
    entries.push_back(entry);
    sc.ctrl.push_back(k);
    sc.entry_of[k] = e;
    return e;
  };
  // isNotDrivenByNode (seed 001): `candidate` may drive `entry` only if
  // `entry` is not already upstream of it.
  auto is_not_driven_by = [&](int candidate, int entry) {
    for (int e = candidate; e >= 0; e = entries[e].driver)
      if (e == entry) return false;
    return true;
  };
  auto edge_ok = [](RelationKind kind, bool forward, bool inverse, bool pair, bool magnet) {
    switch (kind) {
      case RelationKind::kForward: return forward;
      case RelationKind::kInverse: return inverse;
      case RelationKind::kPair: return pair;
      case RelationKind::kMagnet: return magnet;
    }
    return false;
  };
  // walkNodes: breadth first from `queue`, over the relation kinds allowed,
  // adding followers. Reaching a grabbed control without a driver makes the
  // walker its driver (forward mode: a grabbed control under another one is
  // carried by it, then applies its own motion).
  auto walk_followers = [&](std::vector<int> queue, bool forward, bool pair, bool adopt_grabbed) {
    for (std::size_t q = 0; q < queue.size(); ++q) {
      const int x = queue[q];
      for (const Index::Edge& edge : ix.ctrls[sc.ctrl[x]].out) {
        if (!edge_ok(edge.kind, forward, false, pair, false)) continue;
        const int y = sc.entry_of[edge.to];
        if (y < 0) {
          queue.push_back(add(edge.to, Role::kFollow, x));
        } else if (adopt_grabbed && entries[y].role == Role::kGrabbed && entries[y].driver < 0 && is_not_driven_by(x, y)) {
          entries[y].driver = x;
        }
      }
    }
  };

  std::vector<int> grabbed_k;
  for (NodeId id : plan->grabbed) grabbed_k.push_back(ix.find(graph, id));
  const Mode mode = mode_;
  switch (mode) {
    case Mode::kForward:
    case Mode::kSuspended: {
      std::vector<int> seeds;
      for (int k : grabbed_k) seeds.push_back(add(k, Role::kGrabbed, -1));
      walk_followers(seeds, mode == Mode::kForward, true, mode == Mode::kForward);
      break;
    }
    case Mode::kBody: {
      std::vector<int> rigs;
      for (int k : grabbed_k)
        for (int r : ix.rig_group[ix.ctrls[k].rig])
          if (std::find(rigs.begin(), rigs.end(), r) == rigs.end()) rigs.push_back(r);
      for (int k : grabbed_k) add(k, Role::kBody, -1);
      for (int r : rigs)
        for (int k : ix.rig_members[r])
          if (sc.entry_of[k] < 0) add(k, Role::kBody, -1);
      if (!body_pivot_) plan_body_pivot_ = math::rigid_part(eval_mat(graph, ix.ctrls[grabbed_k[0]].id, xform::kWorldMatrix));
      else plan_body_pivot_ = body_pivot_;
      break;
    }
    case Mode::kMagnet: {
      std::vector<int> frontier;
      std::vector<double> total;  // cumulative share per entry
      for (int k : grabbed_k) {
        frontier.push_back(add(k, Role::kGrabbed, -1));
        total.push_back(1.0);
      }
      while (!frontier.empty()) {
        // chooseDriver (seed 001): of the controls of this level that reach
        // y, prefer the strongest (already constrained, nearest a grabbed
        // control), then the first constrained.
        std::vector<int> next_k;
        std::vector<int> next_driver;
        std::vector<double> next_share, next_total;
        for (int x : frontier) {
          for (const Index::Edge& edge : ix.ctrls[sc.ctrl[x]].out) {
            if (sc.entry_of[edge.to] >= 0) continue;  // already driven: never double back
            const double share = edge.kind == RelationKind::kPair ? 1.0 : options_.magnet_fraction;
            const double t = total[x] * share;
            if (t < options_.magnet_min_weight) continue;
            auto it = std::find(next_k.begin(), next_k.end(), edge.to);
            if (it == next_k.end()) {
              next_k.push_back(edge.to);
              next_driver.push_back(x);
              next_share.push_back(share);
              next_total.push_back(t);
            } else if (t > next_total[it - next_k.begin()]) {
              const auto i = it - next_k.begin();
              next_driver[i] = x;
              next_share[i] = share;
              next_total[i] = t;
            }
          }
        }
        frontier.clear();
        for (std::size_t i = 0; i < next_k.size(); ++i) {
          const int e = add(next_k[i], Role::kMagnet, next_driver[i]);
          entries[e].weight = next_share[i];
          total.push_back(next_total[i]);
          frontier.push_back(e);
        }
      }
      break;
    }
    case Mode::kMagnetRadius: {
      std::vector<Vec3> gp;
      std::vector<int> ge;
      for (int k : grabbed_k) {
        ge.push_back(add(k, Role::kGrabbed, -1));
        gp.push_back(pos(eval_mat(graph, ix.ctrls[k].id, xform::kWorldMatrix)));
      }
      const double radius = options_.magnet_radius;
      std::vector<int> rigs;
      for (int k : grabbed_k)
        for (int r : ix.rig_group[ix.ctrls[k].rig])
          if (std::find(rigs.begin(), rigs.end(), r) == rigs.end()) rigs.push_back(r);
      for (int r : rigs) {
        for (int k : ix.rig_members[r]) {
          if (sc.entry_of[k] >= 0) continue;
          const Vec3 p = pos(eval_mat(graph, ix.ctrls[k].id, xform::kWorldMatrix));
          int best = -1;
          double best_d = 0;
          for (std::size_t g = 0; g < gp.size(); ++g) {
            const double d = (p - gp[g]).norm();
            if (best < 0 || d < best_d) best = static_cast<int>(g), best_d = d;
          }
          if (radius <= 0 || best_d >= radius) continue;
          const double x = best_d / radius;
          const double w = 1.0 - x * x * (3.0 - 2.0 * x);  // smoothstep falloff
          if (w < options_.magnet_min_weight) continue;
          const int e = add(k, Role::kMagnet, ge[best]);
          entries[e].weight = w;
        }
      }
      break;
    }
    case Mode::kPseudoInverse:
    case Mode::kPseudoInverseLength:
    case Mode::kInverse: {
      for (int k : grabbed_k) add(k, Role::kGrabbed, -1);
      for (int k : grabbed_k) {
        // Walk inverse relations up from the grabbed control to the top.
        std::vector<int> members{k};
        int cur = k;
        NodeId stop;
        bool shared_top = false;
        while (true) {
          if (options_.max_chain > 0 && static_cast<int>(members.size()) >= options_.max_chain) {
            if (ix.ctrls[cur].parent >= 0) stop = ix.ctrls[ix.ctrls[cur].parent].id;
            break;
          }
          int up = -1;
          for (const Index::Edge& edge : ix.ctrls[cur].out) {
            if (edge.kind != RelationKind::kInverse) continue;
            if (std::find(members.begin(), members.end(), edge.to) != members.end()) continue;
            up = edge.to;
            break;
          }
          if (up < 0) break;  // a root: the top stays where it is
          const int e = sc.entry_of[up];
          // Stop below another grabbed control or another chain (each grabbed
          // control is a source, none pushed by another), or below a branch
          // (a spine control that also carries the other arm and the head).
          if (e >= 0) {
            stop = ix.ctrls[up].id;
            // A grabbed control above (not a branch): it is this chain's top
            // as well. Its own chain puts it on its target first; this chain
            // starts there and turns it to aim along, so that both reach
            // their targets and the bones between keep their lengths. (A
            // grabbed branch only carries the chain: turning it would swing
            // its other children.)
            if (entries[e].role == Role::kGrabbed && ix.ctrls[up].forward_out <= 1) {
              members.push_back(up);
              shared_top = true;
            }
            break;
          }
          if (ix.ctrls[up].forward_out > 1) {
            if (members.size() == 1) {
              // Grabbed right below a branch: the branch turns (it is the
              // only way to keep the grabbed control's bone length).
              members.push_back(up);
              if (ix.ctrls[up].parent >= 0) stop = ix.ctrls[ix.ctrls[up].parent].id;
            } else {
              stop = ix.ctrls[up].id;
            }
            break;
          }
          members.push_back(up);
          cur = up;
        }
        std::reverse(members.begin(), members.end());
        PlanChain chain;
        chain.anchor_control = stop;
        chain.shared_top = shared_top;
        const int c = static_cast<int>(plan->chains.size());
        for (std::size_t i = 0; i < members.size(); ++i) {
          int e = sc.entry_of[members[i]];
          if (e < 0) e = add(members[i], Role::kChain, -1);
          if (!(shared_top && i == 0)) entries[e].chain = c;
          chain.entries.push_back(e);
        }
        plan->chains.push_back(std::move(chain));
      }
      std::vector<int> moved(entries.size());
      for (std::size_t e = 0; e < entries.size(); ++e) moved[e] = static_cast<int>(e);
      walk_followers(moved, true, true, false);
      for (PlanChain& chain : plan->chains) {
        if (!chain.anchor_control.is_valid()) continue;
        const int k = ix.find(graph, chain.anchor_control);
        if (k >= 0) chain.anchor = sc.entry_of[k];
      }
      break;
    }
  }
  // Hierarchy children of moving controls that the plan does not move keep
  // their world matrices.
  const std::size_t moving = entries.size();
  for (std::size_t e = 0; e < moving; ++e)
    for (int child : ix.ctrls[sc.ctrl[e]].children)
      if (sc.entry_of[child] < 0) add(child, Role::kKeepWorld, -1);

  // Followers whose driver is their hierarchy parent are carried by the
  // hierarchy itself: never computed unless needed, never written.
  sc.free.assign(entries.size(), 0);
  for (std::size_t e = 0; e < entries.size(); ++e) {
    const PlanEntry& en = entries[e];
    if (en.role == Role::kFollow && en.driver >= 0 && ix.ctrls[sc.ctrl[e]].parent == sc.ctrl[en.driver] &&
        mode != Mode::kBody)
      sc.free[e] = 1;
  }

  // Solve order: units (an entry, or a chain as a whole) after the entry
  // they hang from. Every entry has at most one dependency. A shared chain
  // top (a grabbed control its own chain solves, which a chain below then
  // turns) is final once every chain it tops is solved: what follows it
  // waits for that, the chains it tops only for its own chain.
  const int nchains = static_cast<int>(plan->chains.size());
  std::vector<int> units;
  for (std::size_t e = 0; e < entries.size(); ++e)
    if (entries[e].chain < 0) units.push_back(static_cast<int>(e));
  for (int c = 0; c < nchains; ++c) units.push_back(-(c + 1));
  std::vector<std::uint8_t> done(entries.size(), 0);
  std::vector<int> tops_left(entries.size(), 0);
  for (const PlanChain& chain : plan->chains)
    if (chain.shared_top) ++tops_left[chain.entries[0]];
  auto is_final = [&](int e) { return done[e] && tops_left[e] == 0; };
  sc.units.clear();
  std::vector<std::uint8_t> emitted(units.size(), 0);
  bool progress = true;
  while (progress && sc.units.size() < units.size()) {
    progress = false;
    for (std::size_t u = 0; u < units.size(); ++u) {
      if (emitted[u]) continue;
      const int unit = units[u];
      if (unit >= 0) {
        const int dep = entries[unit].driver;
        if (dep >= 0 && !is_final(dep)) continue;
      } else {
        const PlanChain& chain = plan->chains[-unit - 1];
        if (chain.anchor >= 0 && !(chain.shared_top ? done[chain.anchor] != 0 : is_final(chain.anchor))) continue;
      }
      emitted[u] = 1;
      progress = true;
      sc.units.push_back(unit);
      if (unit >= 0) {
        done[unit] = 1;
        plan->order.push_back(unit);
      } else {
        const PlanChain& chain = plan->chains[-unit - 1];
        for (std::size_t i = 0; i < chain.entries.size(); ++i) {
          const int e = chain.entries[i];
          if (chain.shared_top && i == 0) {
            --tops_left[e];
            continue;
          }
          done[e] = 1;
          plan->order.push_back(e);
        }
      }
    }
  }
  if (sc.units.size() < units.size())
    return error(ErrorCode::kCycle, "ephemeral: the relations between the grabbed controls form a loop the plan cannot order");

  const std::size_t n = entries.size();
  sc.w.resize(n);
  sc.wn.resize(n);
  sc.has_w.assign(n, 0);
  sc.has_wn.assign(n, 0);
  std::size_t longest = 0;
  for (const PlanChain& chain : plan->chains) longest = std::max(longest, chain.entries.size());
  sc.chain_world.resize(longest);
  sc.positions.resize(longest);
  sc.solved.resize(longest);
  sc.lengths.resize(longest);
  sc.corrections.resize(longest);
  sc.writes.reserve(n);
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

Status Session::solve(const Delta& delta) {
  Graph& graph = scene_.graph();
  const Index& ix = *index_;
  Scratch& sc = *scratch_;
  Plan& plan = *plan_;
  std::vector<PlanEntry>& entries = plan.entries;
  const std::size_t n = entries.size();
  std::fill(sc.has_w.begin(), sc.has_w.end(), 0);
  std::fill(sc.has_wn.begin(), sc.has_wn.end(), 0);
  sc.motion.resize(n);
  sc.has_motion.assign(n, 0);
  const Quat rot = delta.rotate.normalized();
  const Mat3 rot_m = rot.toRotationMatrix();
  auto node_name = [&](NodeId id) { return graph.node(id) ? graph.node(id)->name() : std::string("?"); };
  auto entry_name = [&](int e) { return node_name(entries[e].control); };
  auto number = [](double v) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.6g", v);
    return std::string(buffer);
  };
  auto note = [&](std::string text) { notes_.push_back(std::move(text)); };

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
  auto world = [&](int e) -> const Mat4& {
    if (!sc.has_w[e]) {
      sc.w[e] = sc.has_last[e] ? sc.last[e] : eval_mat(graph, entries[e].control, xform::kWorldMatrix);
      sc.has_w[e] = 1;
    }
    return sc.w[e];
  };
  // The new world of entry e's hierarchy parent: the parent control's new
  // world; a joint driven by a control moves rigidly with it (a character
  // rigged under another one's joint); a parent outside the plan stays.
  auto parent_new_world = [&](auto& new_world_fn, int e) -> Mat4 {
    const Index::Ctrl& c = ix.ctrls[sc.ctrl[e]];
    const int pe = c.parent >= 0 ? sc.entry_of[c.parent] : -1;
    if (pe < 0) return eval_mat(graph, entries[e].control, xform::kParentMatrix);
    if (!c.parent_via_joint) return new_world_fn(new_world_fn, pe);
    return Mat4(new_world_fn(new_world_fn, pe) * math::affine_inverse(world(pe)) *
                eval_mat(graph, entries[e].control, xform::kParentMatrix));
  };
  Mat4 pivot_motion = Mat4::Identity();
  Mat4 pivot_new = Mat4::Identity();
  if (plan.mode == Mode::kBody) {
    const Mat4& p = *plan_body_pivot_;
    pivot_new = make(rot_m * lin(p), pos(p) + delta.translate);
    pivot_motion = pivot_new * math::scale_matrix(delta.scale) * math::affine_inverse(p);
  }
  // Body motion: every control turns by the pivot's rotation exactly (its
  // own linear part kept as it is, so local rotations do not change and are
  // not rewritten); the pivot's scale moves positions only.
  auto body_world = [&](int e) {
    const Mat4& w = world(e);
    return make(rot_m * lin(w), (pivot_motion * w.col(3)).head<3>());
  };
  // New world of an entry; free followers are composed through the
  // hierarchy, and body entries that the hierarchy carries are computed
  // when asked for (a control kept in place under one of them).
  auto new_world = [&](auto& self, int e) -> const Mat4& {
    if (!sc.has_wn[e]) {
      if (entries[e].role == Role::kBody) {
        sc.wn[e] = body_world(e);
      } else {
        const graph::Node& node = *graph.node(entries[e].control);
        sc.wn[e] = parent_new_world(self, e) * std::get<Mat4>(node.value(xform::kOffsetParentMatrix)) *
                   eval_mat(graph, entries[e].control, xform::kMatrix);
      }
      sc.has_wn[e] = 1;
    }
    return sc.wn[e];
  };
  auto set_new = [&](int e, const Mat4& m) {
    sc.wn[e] = m;
    sc.has_wn[e] = 1;
  };
  // Temporary parenting (seed 001): the driver's motion, concatenated
  // without scale or shear.
  auto carry = [&](int driver, const Mat4& w) {
    const Mat4 motion = new_world(new_world, driver) * math::affine_inverse(world(driver));
    return math::concat_without_scale_shear(motion, w);
  };
  auto apply = [&](const Mat4& base, bool translate) {
    return make(rot_m * lin(base), pos(base) + (translate ? delta.translate : Vec3::Zero()));
  };

  const bool body_rigid = plan.mode == Mode::kBody && delta.scale == Vec3::Ones();
  for (int unit : sc.units) {
    if (unit < 0) {
      const PlanChain& chain = plan.chains[-unit - 1];
      const int m = static_cast<int>(chain.entries.size());
      for (int i = 0; i < m; ++i) {
        const int e = chain.entries[i];
        if (i == 0 && chain.shared_top) sc.chain_world[0] = new_world(new_world, e);  // where its own chain put it
        else sc.chain_world[i] = chain.anchor >= 0 ? carry(chain.anchor, world(e)) : world(e);
      }
      // Every grabbed control's target is its own start plus the one motion,
      // whatever carries the chain's top (README: "moves them all by one
      // world-space motion").
      const int end = chain.entries[m - 1];
      const Mat4 target = apply(world(end), true);
      const bool keeps_lengths = plan.mode == Mode::kInverse || plan.mode == Mode::kPseudoInverseLength;
      if (m == 1) {
        if (keeps_lengths && chain.anchor_control.is_valid()) {
          // Alone in its chain under a parent (max_chain 1, or the walk
          // stopped at another chain right above): moving it would change
          // its bone's length, so it stays where its parent holds it and
          // only turns.
          const Vec3 held = pos(sc.chain_world[0]);
          set_new(end, make(lin(target), held));
          if ((pos(target) - held).norm() > 1e-12 * std::max(1.0, held.norm())) {
            std::string why = "max_chain 1";
            if (options_.max_chain != 1) {
              why = "the walk stops at '";
              why += node_name(chain.anchor_control);
              why += "'";
            }
            note("'" + entry_name(end) + "' keeps its position: its chain holds no other control (" + why +
                 "), and moving it would change the length of its bone; only the motion's rotation applies");
          }
        } else {
          set_new(end, target);
        }
        continue;
      }
      for (int i = 0; i < m; ++i) sc.positions[i] = pos(sc.chain_world[i]);
      const Vec3 t = pos(target);
      bool solved = false;
      if (plan.mode == Mode::kInverse && m == 3) {
        // Analytic two-bone keeping the current bend plane: the knee keeps
        // pointing where it points now, so a drag of zero changes nothing.
        const Vec3 s = sc.positions[0], mid = sc.positions[1], end_p = sc.positions[2];
        const double a = (mid - s).norm(), b = (end_p - mid).norm();
        const double scale = std::max(a + b, 1e-300);
        if (a > 1e-12 * scale && b > 1e-12 * scale) {
          const Vec3 se = end_p - s;
          const Vec3 u0 = se.norm() > 1e-12 * scale ? Vec3(se.normalized()) : Vec3((mid - s).normalized());
          Vec3 k = (mid - s) - (mid - s).dot(u0) * u0;
          // Straight: bend toward the start control's axis most
          // perpendicular to the chain.
          if (k.norm() <= 1e-9 * scale) k = perpendicular(u0, straight_pole(lin(sc.chain_world[0]), u0));
          const Vec3 kh = k.normalized();
          const Vec3 n_old = u0.cross(kh).normalized();
          const Vec3 tv = t - s;
          const double d = tv.norm();
          const Vec3 u = d > 1e-12 * scale ? Vec3(tv / d) : u0;
          Vec3 w = kh - kh.dot(u) * u;
          if (w.norm() < 1e-9) w = n_old.cross(u);
          w.normalize();
          const double dc = std::clamp(d, std::abs(a - b), a + b);
          const double cos_a = dc > 0 ? std::clamp((a * a + dc * dc - b * b) / (2 * a * dc), -1.0, 1.0) : 1.0;
          const double sin_a = std::sqrt(std::max(0.0, 1 - cos_a * cos_a));
          const Vec3 mid_new = s + a * (cos_a * u + sin_a * w);
          const Vec3 end_new = s + dc * u;
          const Vec3 n_new = u.cross(w).normalized();
          const Mat3 rs = frame(mid_new - s, n_new) * frame(mid - s, n_old).transpose();
          const Mat3 rm = frame(end_new - mid_new, n_new) * frame(end_p - mid, n_old).transpose();
          sc.solved[0] = s;
          sc.solved[1] = mid_new;
          sc.solved[2] = end_new;
          set_new(chain.entries[0], make(rs * lin(sc.chain_world[0]), s));
          set_new(chain.entries[1], make(rm * lin(sc.chain_world[1]), mid_new));
          set_new(chain.entries[2], make(lin(target), end_new));
          solved = true;
        }
      }
      if (!solved && plan.mode == Mode::kInverse) {
        if (m == 2) {
          const Vec3 s = sc.positions[0];
          const double a = (sc.positions[1] - s).norm();
          const Vec3 tv = t - s;
          sc.solved[0] = s;
          sc.solved[1] = tv.norm() > 1e-300 ? Vec3(s + a * tv.normalized()) : sc.positions[1];
        } else {
          for (int i = 0; i + 1 < m; ++i) sc.lengths[i] = (sc.positions[i + 1] - sc.positions[i]).norm();
          const std::span<Vec3> p(sc.solved.data(), m);
          const std::span<const double> len(sc.lengths.data(), m - 1);
          const Vec3 s = sc.positions[0];
          double total = 0;
          for (double l : len) total += l;
          const double scale = std::max(total, 1e-300);
          Vec3 u0 = sc.positions[m - 1] - s;
          if (u0.norm() <= 1e-12 * scale) u0 = sc.positions[1] - s;
          u0 = u0.norm() > 1e-300 ? Vec3(u0.normalized()) : Vec3::UnitX();
          bool straight = true;
          for (int i = 1; i < m && straight; ++i) {
            const Vec3 r = sc.positions[i] - s;
            straight = (r - r.dot(u0) * u0).norm() <= 1e-9 * scale;
          }
          const Vec3 pole = straight_pole(lin(sc.chain_world[0]), u0);
          const Vec3 tv = t - s;
          const double d = tv.norm();
          if (straight && total > 0) {
            // FABRIK cannot bend a straight chain out of its line (it folds
            // it along the line) and crawls near full reach: lay it on an
            // arc toward the target, bulging toward the pole.
            const Vec3 u = d > 1e-12 * scale ? Vec3(tv / d) : u0;
            p[0] = s;
            lay_arc(p, len, u, perpendicular(u, pole), d);
          } else {
            ops::ik::FabrikJob job;
            job.world = std::span<const Mat4>(sc.chain_world.data(), m);
            job.target = t;
            job.tolerance = options_.fabrik_tolerance;
            job.max_iterations = options_.fabrik_iterations;
            job.positions = p;
            job.corrections = std::span<Quat>(sc.corrections.data(), m);
            if (!job.run()) return error(ErrorCode::kInvalidArgument, "drag: FABRIK refused the chain (degenerate matrices)");
          }
          // Exact to rounding: FABRIK stops at its tolerance or iteration
          // limit; the arc is as exact as its bisection.
          if ((p[m - 1] - t).norm() > 1e-13 * scale) reach(p, len, 0, m - 1, t, pole);
        }
      } else if (!solved) {
        // Pseudo-inverse: the grabbed control's motion spread evenly down to
        // the top (which stays): control i of m moves by i / (m - 1) of it.
        const Vec3 dp = t - sc.positions[m - 1];
        for (int i = 0; i < m; ++i) sc.solved[i] = sc.positions[i] + dp * (static_cast<double>(i) / (m - 1));
        if (plan.mode == Mode::kPseudoInverseLength) {
          for (int i = 1; i < m; ++i) {
            const double len = (sc.positions[i] - sc.positions[i - 1]).norm();
            const Vec3 dir = sc.solved[i] - sc.solved[i - 1];
            sc.solved[i] = sc.solved[i - 1] + (dir.norm() > 1e-300 ? Vec3(dir.normalized() * len)
                                                                    : Vec3(sc.positions[i] - sc.positions[i - 1]));
          }
        }
      }
      if (plan.mode == Mode::kInverse) {
        // Say why the grabbed control is not on its target (out of reach, a
        // zero-length chain, the one bone of a two-control chain).
        double total = 0;
        for (int i = 0; i + 1 < m; ++i) total += (sc.positions[i + 1] - sc.positions[i]).norm();
        const double miss = (sc.solved[m - 1] - t).norm();
        const double reach_to = (t - sc.positions[0]).norm();
        if (miss > 1e-9 * std::max({total, reach_to, 1e-300})) {
          const std::string chain_text = "its chain from '" + entry_name(chain.entries[0]) + "' (" + std::to_string(m) +
                                         " controls, length " + number(total) + ")";
          if (total <= 1e-12 * reach_to)
            note("'" + entry_name(end) + "' cannot move in inverse mode: " + chain_text + " has no length to turn");
          else if (reach_to > total)
            note("'" + entry_name(end) + "' is out of reach: the target is " + number(reach_to) + " from the top of " +
                 chain_text + "; the chain points at it");
          else
            note("'" + entry_name(end) + "' ends " + number(miss) + " from its target: " + chain_text +
                 " cannot reach it");
        }
      }
      if (solved) continue;
      // Every control but the grabbed one re-aims at its child.
      for (int i = 0; i + 1 < m; ++i) {
        const Mat3 r = swing(sc.positions[i + 1] - sc.positions[i], sc.solved[i + 1] - sc.solved[i]);
        set_new(chain.entries[i], make(r * lin(sc.chain_world[i]), sc.solved[i]));
      }
      set_new(chain.entries[m - 1], make(lin(target), sc.solved[m - 1]));
      continue;
    }
    const int e = unit;
    const PlanEntry& en = entries[e];
    switch (en.role) {
      case Role::kGrabbed:
        if (en.driver >= 0) {
          set_new(e, apply(carry(en.driver, world(e)), false));
        } else {
          set_new(e, apply(world(e), true));
          sc.motion[e] = rot;  // its rotation, for magnet followers
          sc.has_motion[e] = 1;
        }
        break;
      case Role::kFollow:
        if (!sc.free[e]) set_new(e, carry(en.driver, world(e)));
        break;
      case Role::kMagnet: {
        const Mat4& dw = world(en.driver);
        const Mat4& dn = new_world(new_world, en.driver);
        // The driver's rotation: recorded when it moved (grabbed or magnet),
        // else taken from its matrices once.
        if (!sc.has_motion[en.driver]) {
          const Mat3 r = lin(math::rigid_part(dn * math::affine_inverse(dw)));
          sc.motion[en.driver] = Quat(r).normalized();
          sc.has_motion[en.driver] = 1;
        }
        const Quat& dq = sc.motion[en.driver];
        const Quat rf = dq.vec().squaredNorm() == 0 ? Quat::Identity() : Quat::Identity().slerp(en.weight, dq);
        const Mat3 rfm = rf.toRotationMatrix();
        const Vec3 c = pos(dw);
        const Mat4& w = world(e);
        set_new(e, make(rfm * lin(w), c + en.weight * (pos(dn) - c) + rfm * (pos(w) - c)));
        sc.motion[e] = rf;
        sc.has_motion[e] = 1;
        break;
      }
      case Role::kBody:
        // Rigid: only the roots are needed (the hierarchy carries the rest,
        // also across characters: a control under a joint of another one).
        if (!body_rigid || ix.ctrls[sc.ctrl[e]].parent < 0 || sc.entry_of[ix.ctrls[sc.ctrl[e]].parent] < 0)
          set_new(e, body_world(e));
        break;
      case Role::kKeepWorld:
        set_new(e, world(e));
        break;
      case Role::kChain:
        break;  // solved with its chain
    }
  }

  // Local channels of everything that moved, computed before any write.
  // A rigid body motion is carried by the hierarchy below the roots.
  sc.writes.clear();
  bool exact = true;  // every written rotation is a rotation (no projection)
  for (std::size_t e = 0; e < n; ++e) {
    if (sc.free[e]) continue;
    if (body_rigid && entries[e].role == Role::kBody && ix.ctrls[sc.ctrl[e]].parent >= 0 &&
        sc.entry_of[ix.ctrls[sc.ctrl[e]].parent] >= 0)
      continue;
    const int k = sc.ctrl[e];
    const graph::Node& node = *graph.node(entries[e].control);
    const int parent = ix.ctrls[k].parent;
    const int pe = parent >= 0 ? sc.entry_of[parent] : -1;
    const Mat4 parent_world = parent_new_world(new_world, static_cast<int>(e));
    // local = (parent_world * offset)^-1 * world, in 3x3 + translation.
    const Mat4& offset = std::get<Mat4>(node.value(xform::kOffsetParentMatrix));
    const Mat3 po_inverse = (lin(parent_world) * lin(offset)).inverse();
    const Vec3 po_t = lin(parent_world) * pos(offset) + pos(parent_world);
    const Mat4& world_new = new_world(new_world, static_cast<int>(e));
    const Vec3 t = po_inverse * (pos(world_new) - po_t);
    const Vec3& t0 = std::get<Vec3>(node.value(xform::kTranslate));
    const bool same_t = (t - t0).norm() <= 1e-12 * std::max(1.0, t0.norm());
    if (entries[e].role == Role::kBody && pe >= 0 && entries[pe].role == Role::kBody) {
      // Control and parent both turned by the pivot's rotation: the local
      // rotation is unchanged, only the translation is new.
      if (!same_t) sc.writes.push_back(Scratch::Write{static_cast<int>(e), t, Quat::Identity(), Vec3::Zero(), true, false});
      continue;
    }
    const Vec3& scale = std::get<Vec3>(node.value(xform::kScale));
    const Vec3& shear = std::get<Vec3>(node.value(xform::kShear));
    const Vec3& rotate_axis = std::get<Vec3>(node.value(xform::kRotateAxis));
    Mat3 rotation = po_inverse * lin(world_new);
    if (shear == Vec3::Zero() && rotate_axis == Vec3::Zero()) {
      rotation = rotation * scale.cwiseInverse().asDiagonal();  // local = R * S
    } else {
      math::TransformParts rest;
      rest.scale = scale;
      rest.shear = shear;
      rest.rotate_axis = math::to_radians(rotate_axis);
      rotation = rotation * lin(math::compose(rest)).inverse();  // local = R * (RA * SH * S)
    }
    if (!(rotation.transpose() * rotation).isIdentity(1e-10)) exact = false;
    Scratch::Write write{static_cast<int>(e), same_t ? t0 : t, Quat::Identity(), Vec3::Zero(), !same_t, false};
    if (xform::is_quaternion_mode(node)) {
      const Quat& q0 = std::get<Quat>(node.value(xform::kRotateQuaternion));
      Quat qs = Quat(rotation).normalized();
      if (qs.dot(q0) < 0) qs.coeffs() = -qs.coeffs();  // sign-continuous
      write.set_r = (q0.normalized().conjugate() * qs).vec().norm() > 1e-13;
      write.rotation = qs;
    } else {
      const auto order = static_cast<math::RotateOrder>(std::get<std::int64_t>(node.value(xform::kRotateOrder)));
      const Vec3& r0 = std::get<Vec3>(node.value(xform::kRotate));
      const Vec3 previous = math::to_radians(r0);
      write.euler = math::to_degrees(math::euler_closest(math::matrix_to_euler(rotation, order), previous, order));
      // 1e-11 degrees ~ 2e-13 rad, the quaternion test's threshold.
      write.set_r = (write.euler - r0).cwiseAbs().maxCoeff() > 1e-11;
    }
    if (write.set_t || write.set_r) sc.writes.push_back(write);
  }
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
      const NodeId id = entries[wr.entry].control;
      if (is_keyed(graph, id) && !has_key_now(graph, id)) to_key.push_back(id);
    }
    if (!to_key.empty()) status = set_key(graph, to_key);
  }
  auto connected = [](const graph::Node& node, graph::AttrIndex attr) {
    for (const graph::Connection& c : node.inputs())
      if (c.dst.attr == attr) return true;
    return false;
  };
  auto write = [&](NodeId id, graph::AttrIndex attr, graph::Value value) {
    if (connected(*graph.node(id), attr)) {
      exact = false;  // a key evaluated at a time within key_time_tolerance() of it: re-read next time
      return write_channel(graph, id, attr, value, false);
    }
    return graph.set_value(Plug{id, attr, -1}, std::move(value));
  };
  for (const Scratch::Write& wr : sc.writes) {
    if (!status) break;
    const NodeId id = entries[wr.entry].control;
    const graph::Node& node = *graph.node(id);
    if (wr.set_t) status = write(id, xform::kTranslate, wr.translate);
    if (!status) break;
    if (!wr.set_r) continue;
    if (xform::is_quaternion_mode(node))
      status = write(id, xform::kRotateQuaternion, wr.rotation);
    else
      status = write(id, xform::kRotate, wr.euler);
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
    plan_body_pivot_ = pivot_new;
    if (body_pivot_) body_pivot_ = pivot_new;
  }
  return Status::ok();
}

}  // namespace rigel::ephemeral
