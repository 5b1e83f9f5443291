// What the chain modes (inverse, pseudo-inverse and its length variant)
// share: each grabbed control's chain up its inverse relations to a top
// that stays (a root, a branch, another grabbed control or chain, or
// max_chain), what the chains carry, and the start and finish of a chain's
// solve.
#include <algorithm>
#include <string>

#include "modes.h"

namespace rigel::ephemeral::modes {

namespace {

// The chain of index control k (grabbed): its members from the top down,
// the control the walk stopped at, and whether the top is a grabbed control
// above that its own chain solves.
PlanChain walk_chain(Planner& p, int k, std::vector<int>& members) {
  const Index& ix = p.ix;
  const std::vector<PlanEntry>& entries = p.plan.entries;
  members.assign(1, k);
  int cur = k;
  PlanChain chain;
  while (true) {
    if (p.options.max_chain > 0 && static_cast<int>(members.size()) >= p.options.max_chain) {
      if (ix.ctrls[cur].parent >= 0) chain.anchor_control = ix.ctrls[ix.ctrls[cur].parent].id;
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
    const int e = p.sc.entry_of[up];
    // Stop below another grabbed control or another chain (each grabbed
    // control is a source, none pushed by another), or below a branch
    // (a spine control that also carries the other arm and the head).
    if (e >= 0) {
      chain.anchor_control = ix.ctrls[up].id;
      // A grabbed control above (not a branch): it is this chain's top
      // as well. Its own chain puts it on its target first; this chain
      // starts there and turns it to aim along, so that both reach
      // their targets and the bones between keep their lengths. (A
      // grabbed branch only carries the chain: turning it would swing
      // its other children.)
      if (entries[e].role == Role::kGrabbed && ix.ctrls[up].forward_out <= 1) {
        members.push_back(up);
        chain.shared_top = true;
      }
      break;
    }
    if (ix.ctrls[up].forward_out > 1) {
      if (members.size() == 1) {
        // Grabbed right below a branch: the branch turns (it is the
        // only way to keep the grabbed control's bone length).
        members.push_back(up);
        if (ix.ctrls[up].parent >= 0) chain.anchor_control = ix.ctrls[ix.ctrls[up].parent].id;
      } else {
        chain.anchor_control = ix.ctrls[up].id;
      }
      break;
    }
    members.push_back(up);
    cur = up;
  }
  std::reverse(members.begin(), members.end());
  return chain;
}

}  // namespace

void plan_chains(Planner& p) {
  std::vector<PlanEntry>& entries = p.plan.entries;
  for (int k : p.grabbed) p.add(k, Role::kGrabbed, -1);
  std::vector<int> members;
  for (int k : p.grabbed) {
    PlanChain chain = walk_chain(p, k, members);
    const int c = static_cast<int>(p.plan.chains.size());
    for (std::size_t i = 0; i < members.size(); ++i) {
      int e = p.sc.entry_of[members[i]];
      if (e < 0) e = p.add(members[i], Role::kChain, -1);
      if (!(chain.shared_top && i == 0)) entries[e].chain = c;
      chain.entries.push_back(e);
    }
    p.plan.chains.push_back(std::move(chain));
  }
  std::vector<int> moved(entries.size());
  for (std::size_t e = 0; e < entries.size(); ++e) moved[e] = static_cast<int>(e);
  p.walk_followers(moved, true, true, false);
  for (PlanChain& chain : p.plan.chains) {
    if (!chain.anchor_control.is_valid()) continue;
    const int k = p.ix.find(p.graph, chain.anchor_control);
    if (k >= 0) chain.anchor = p.sc.entry_of[k];
  }
}

ChainStart chain_start(Drag& d, const PlanChain& chain, bool keeps_lengths) {
  Scratch& sc = d.sc;
  ChainStart start;
  const int m = static_cast<int>(chain.entries.size());
  start.m = m;
  for (int i = 0; i < m; ++i) {
    const int e = chain.entries[i];
    if (i == 0 && chain.shared_top) sc.chain_world[0] = d.new_world(e);  // where its own chain put it
    else sc.chain_world[i] = chain.anchor >= 0 ? d.carry(chain.anchor, d.world(e)) : d.world(e);
  }
  // Every grabbed control's target is its own start plus the one motion,
  // whatever carries the chain's top (README: "moves them all by one
  // world-space motion").
  const int end = chain.entries[m - 1];
  start.target = d.apply(d.world(end), true);
  if (m == 1) {
    start.done = true;
    if (keeps_lengths && chain.anchor_control.is_valid()) {
      // Alone in its chain under a parent (max_chain 1, or the walk
      // stopped at another chain right above): moving it would change
      // its bone's length, so it stays where its parent holds it and
      // only turns.
      const Vec3 held = pos(sc.chain_world[0]);
      d.set_new(end, make(lin(start.target), held));
      if ((pos(start.target) - held).norm() > 1e-12 * std::max(1.0, held.norm())) {
        std::string why = "max_chain 1";
        if (d.options.max_chain != 1) {
          why = "the walk stops at '";
          why += d.node_name(chain.anchor_control);
          why += "'";
        }
        std::string text = "'";
        text += d.entry_name(end);
        text += "' keeps its position: its chain holds no other control (";
        text += why;
        text += "), and moving it would change the length of its bone; only the motion's rotation applies";
        d.note(std::move(text));
      }
    } else {
      d.set_new(end, start.target);
    }
    return start;
  }
  for (int i = 0; i < m; ++i) sc.positions[i] = pos(sc.chain_world[i]);
  return start;
}

void chain_finish(Drag& d, const PlanChain& chain, const ChainStart& start) {
  Scratch& sc = d.sc;
  const int m = start.m;
  for (int i = 0; i + 1 < m; ++i) d.set_new(chain.entries[i], make(sc.turns[i] * lin(sc.chain_world[i]), sc.solved[i]));
  d.set_new(chain.entries[m - 1], make(lin(start.target), sc.solved[m - 1]));
}

}  // namespace rigel::ephemeral::modes
