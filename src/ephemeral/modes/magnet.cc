// Magnet modes. Magnet: each hop from a grabbed control (over any relation)
// gets `magnet_fraction` of its driver's motion (pair relations all of it),
// up and down the character, until the share falls below
// `magnet_min_weight`. Magnet radius: every control of the grabbed
// characters within `magnet_radius` of a grabbed control (at plan time)
// gets a smooth falloff share of the nearest one's motion.
#include <algorithm>

#include "modes.h"

namespace rigel::ephemeral::modes {

void plan_magnet(Planner& p) {
  std::vector<PlanEntry>& entries = p.plan.entries;
  std::vector<int> frontier;
  std::vector<double> total;  // cumulative share per entry
  for (int k : p.grabbed) {
    frontier.push_back(p.add(k, Role::kGrabbed, -1));
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
      for (const Index::Edge& edge : p.ix.ctrls[p.sc.ctrl[x]].out) {
        if (p.sc.entry_of[edge.to] >= 0) continue;  // already driven: never double back
        const double share = edge.kind == RelationKind::kPair ? 1.0 : p.options.magnet_fraction;
        const double t = total[x] * share;
        if (t < p.options.magnet_min_weight) continue;
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
      const int e = p.add(next_k[i], Role::kMagnet, next_driver[i]);
      entries[e].weight = next_share[i];
      total.push_back(next_total[i]);
      frontier.push_back(e);
    }
  }
}

void plan_magnet_radius(Planner& p) {
  std::vector<PlanEntry>& entries = p.plan.entries;
  std::vector<Vec3> gp;
  std::vector<int> ge;
  for (int k : p.grabbed) {
    ge.push_back(p.add(k, Role::kGrabbed, -1));
    gp.push_back(pos(eval_mat(p.graph, p.ix.ctrls[k].id, xform::kWorldMatrix)));
  }
  const double radius = p.options.magnet_radius;
  for (int r : p.grabbed_rigs()) {
    for (int k : p.ix.rig_members[r]) {
      if (p.sc.entry_of[k] >= 0) continue;
      const Vec3 at = pos(eval_mat(p.graph, p.ix.ctrls[k].id, xform::kWorldMatrix));
      int best = -1;
      double best_d = 0;
      for (std::size_t g = 0; g < gp.size(); ++g) {
        const double d = (at - gp[g]).norm();
        if (best < 0 || d < best_d) best = static_cast<int>(g), best_d = d;
      }
      if (radius <= 0 || best_d >= radius) continue;
      const double x = best_d / radius;
      const double w = 1.0 - x * x * (3.0 - 2.0 * x);  // smoothstep falloff
      if (w < p.options.magnet_min_weight) continue;
      const int e = p.add(k, Role::kMagnet, ge[best]);
      entries[e].weight = w;
    }
  }
}

namespace {

// A magnet entry: `weight` of its driver's motion, the rotation slerped
// from the identity and turning about the driver's position.
void magnet_move(Drag& d, int e) {
  Scratch& sc = d.sc;
  const PlanEntry& en = d.plan.entries[e];
  const Mat4& dw = d.world(en.driver);
  const Mat4& dn = d.new_world(en.driver);
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
  const Mat4& w = d.world(e);
  d.set_new(e, make(rfm * lin(w), c + en.weight * (pos(dn) - c) + rfm * (pos(w) - c)));
  sc.motion[e] = rf;
  sc.has_motion[e] = 1;
}

Status solve_magnets(Drag& d) {
  for (int e : d.sc.units) {
    if (d.plan.entries[e].role == Role::kMagnet) magnet_move(d, e);
    else d.move(e);
  }
  return Status::ok();
}

}  // namespace

Status solve_magnet(Drag& d) { return solve_magnets(d); }
Status solve_magnet_radius(Drag& d) { return solve_magnets(d); }

}  // namespace rigel::ephemeral::modes
