// What every mode's plan has: entries added and walked (walkNodes), the
// controls kept in place under moving ones, and the solve order.
#include <algorithm>

#include "modes.h"

namespace rigel::ephemeral::modes {

int Planner::add(int k, Role role, int driver) {
  std::vector<PlanEntry>& entries = plan.entries;
  const int e = static_cast<int>(entries.size());
  PlanEntry entry;
  entry.control = ix.ctrls[k].id;
  entry.role = role;
  entry.driver = driver;
  entries.push_back(entry);
  sc.ctrl.push_back(k);
  sc.entry_of[k] = e;
  return e;
}

bool Planner::is_not_driven_by(int candidate, int entry) const {
  for (int e = candidate; e >= 0; e = plan.entries[e].driver)
    if (e == entry) return false;
  return true;
}

void Planner::walk_followers(std::vector<int> queue, bool forward, bool pair, bool adopt_grabbed) {
  std::vector<PlanEntry>& entries = plan.entries;
  for (std::size_t q = 0; q < queue.size(); ++q) {
    const int x = queue[q];
    for (const Index::Edge& edge : ix.ctrls[sc.ctrl[x]].out) {
      const bool walked = (edge.kind == RelationKind::kForward && forward) || (edge.kind == RelationKind::kPair && pair);
      if (!walked) continue;
      const int y = sc.entry_of[edge.to];
      if (y < 0) {
        queue.push_back(add(edge.to, Role::kFollow, x));
      } else if (adopt_grabbed && entries[y].role == Role::kGrabbed && entries[y].driver < 0 && is_not_driven_by(x, y)) {
        entries[y].driver = x;
      }
    }
  }
}

std::vector<int> Planner::grabbed_rigs() const {
  std::vector<int> rigs;
  for (int k : grabbed)
    for (int r : ix.rig_group[ix.ctrls[k].rig])
      if (std::find(rigs.begin(), rigs.end(), r) == rigs.end()) rigs.push_back(r);
  return rigs;
}

namespace {

// Solve order: units (an entry, or a chain as a whole) after the entry
// they hang from. Every entry has at most one dependency. A shared chain
// top (a grabbed control its own chain solves, which a chain below then
// turns) is final once every chain it tops is solved: what follows it
// waits for that, the chains it tops only for its own chain.
Status order_units(Planner& p) {
  Plan& plan = p.plan;
  const std::vector<PlanEntry>& entries = plan.entries;
  Scratch& sc = p.sc;
  const int nchains = static_cast<int>(plan.chains.size());
  std::vector<int> units;
  for (std::size_t e = 0; e < entries.size(); ++e)
    if (entries[e].chain < 0) units.push_back(static_cast<int>(e));
  for (int c = 0; c < nchains; ++c) units.push_back(-(c + 1));
  std::vector<std::uint8_t> done(entries.size(), 0);
  std::vector<int> tops_left(entries.size(), 0);
  for (const PlanChain& chain : plan.chains)
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
        const PlanChain& chain = plan.chains[-unit - 1];
        if (chain.anchor >= 0 && !(chain.shared_top ? done[chain.anchor] != 0 : is_final(chain.anchor))) continue;
      }
      emitted[u] = 1;
      progress = true;
      sc.units.push_back(unit);
      if (unit >= 0) {
        done[unit] = 1;
        plan.order.push_back(unit);
      } else {
        const PlanChain& chain = plan.chains[-unit - 1];
        for (std::size_t i = 0; i < chain.entries.size(); ++i) {
          const int e = chain.entries[i];
          if (chain.shared_top && i == 0) {
            --tops_left[e];
            continue;
          }
          done[e] = 1;
          plan.order.push_back(e);
        }
      }
    }
  }
  if (sc.units.size() < units.size())
    return error(ErrorCode::kCycle, "ephemeral: the relations between the grabbed controls form a loop the plan cannot order");
  return Status::ok();
}

}  // namespace

Status plan_finish(Planner& p) {
  std::vector<PlanEntry>& entries = p.plan.entries;
  Scratch& sc = p.sc;
  const Index& ix = p.ix;
  // Hierarchy children of moving controls that the plan does not move keep
  // their world matrices.
  const std::size_t moving = entries.size();
  for (std::size_t e = 0; e < moving; ++e)
    for (int child : ix.ctrls[sc.ctrl[e]].children)
      if (sc.entry_of[child] < 0) p.add(child, Role::kKeepWorld, -1);

  // Followers whose driver is their hierarchy parent are carried by the
  // hierarchy itself: never computed unless needed, never written.
  sc.free.assign(entries.size(), 0);
  for (std::size_t e = 0; e < entries.size(); ++e) {
    const PlanEntry& en = entries[e];
    if (en.role == Role::kFollow && en.driver >= 0 && ix.ctrls[sc.ctrl[e]].parent == sc.ctrl[en.driver] &&
        p.plan.mode != Mode::kBody)
      sc.free[e] = 1;
  }

  if (Status s = order_units(p); !s) return s;

  const std::size_t n = entries.size();
  sc.w.resize(n);
  sc.wn.resize(n);
  sc.has_w.assign(n, 0);
  sc.has_wn.assign(n, 0);
  std::size_t longest = 0;
  for (const PlanChain& chain : p.plan.chains) longest = std::max(longest, chain.entries.size());
  sc.chain_world.resize(longest);
  sc.positions.resize(longest);
  sc.solved.resize(longest);
  sc.lengths.resize(longest);
  sc.corrections.resize(longest);
  sc.turns.resize(longest);
  sc.writes.reserve(n);
  return Status::ok();
}

}  // namespace rigel::ephemeral::modes
