// Inverse mode: true IK from each grabbed control up to its chain's top,
// bone lengths kept. Three controls: the two-bone solve that keeps the
// current bend plane (a zero drag changes nothing); two: the one bone
// points at the target; more: ops::ik::ChainReachJob (an arc for a straight
// chain, else FABRIK, then exact to rounding). What cannot be reached is
// said in the session's notes.
#include <algorithm>
#include <cstdio>
#include <span>
#include <string>

#include "modes.h"
#include "rigel/ops/ik/chain_reach.h"
#include "rigel/ops/ik/two_bone_keep_plane.h"

namespace rigel::ephemeral::modes {

void plan_inverse(Planner& p) { plan_chains(p); }

namespace {

std::string number(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", v);
  return std::string(buffer);
}

// Says why the grabbed control is not on its target (out of reach, a
// zero-length chain, the one bone of a two-control chain).
void note_miss(Drag& d, const PlanChain& chain, int m, const Vec3& t) {
  const Scratch& sc = d.sc;
  double total = 0;
  for (int i = 0; i + 1 < m; ++i) total += (sc.positions[i + 1] - sc.positions[i]).norm();
  const double miss = (sc.solved[m - 1] - t).norm();
  const double reach_to = (t - sc.positions[0]).norm();
  if (!(miss > 1e-9 * std::max({total, reach_to, 1e-300}))) return;
  const std::string end = d.entry_name(chain.entries[m - 1]);
  const std::string chain_text = "its chain from '" + d.entry_name(chain.entries[0]) + "' (" + std::to_string(m) +
                                 " controls, length " + number(total) + ")";
  if (total <= 1e-12 * reach_to)
    d.note("'" + end + "' cannot move in inverse mode: " + chain_text + " has no length to turn");
  else if (reach_to > total)
    d.note("'" + end + "' is out of reach: the target is " + number(reach_to) + " from the top of " + chain_text +
           "; the chain points at it");
  else
    d.note("'" + end + "' ends " + number(miss) + " from its target: " + chain_text + " cannot reach it");
}

// Three controls: the two-bone solve keeping the bend plane. False when a
// bone has no length (the general solve takes it).
bool solve_two_bone(Drag& d, const PlanChain& chain, const ChainStart& start) {
  Scratch& sc = d.sc;
  ops::ik::TwoBoneKeepPlaneOutput out;
  ops::ik::TwoBoneKeepPlaneJob job;
  job.start_world = &sc.chain_world[0];
  job.mid_world = &sc.chain_world[1];
  job.end_world = &sc.chain_world[2];
  job.target = pos(start.target);
  job.output = &out;
  if (!job.run() || !out.solved) return false;
  const Vec3 s = sc.positions[0];
  sc.solved[0] = s;
  sc.solved[1] = out.mid;
  sc.solved[2] = out.end;
  d.set_new(chain.entries[0], make(out.start_turn * lin(sc.chain_world[0]), s));
  d.set_new(chain.entries[1], make(out.mid_turn * lin(sc.chain_world[1]), out.mid));
  d.set_new(chain.entries[2], make(lin(start.target), out.end));
  return true;
}

Status solve_chain(Drag& d, const PlanChain& chain) {
  const ChainStart start = chain_start(d, chain, true);
  if (start.done) return Status::ok();
  Scratch& sc = d.sc;
  const int m = start.m;
  const Vec3 t = pos(start.target);
  const bool two_bone = m == 3 && solve_two_bone(d, chain, start);
  if (!two_bone) {
    const auto count = static_cast<std::size_t>(m);
    ops::ik::ChainReachJob job;
    job.world = std::span<const Mat4>(sc.chain_world.data(), count);
    job.target = t;
    job.tolerance = d.options.fabrik_tolerance;
    job.max_iterations = d.options.fabrik_iterations;
    job.positions = std::span<Vec3>(sc.solved.data(), count);
    job.lengths = std::span<double>(sc.lengths.data(), count - 1);
    job.corrections = std::span<Quat>(sc.corrections.data(), count);
    job.turns = std::span<Mat3>(sc.turns.data(), count);
    if (!job.run()) return error(ErrorCode::kInvalidArgument, "drag: FABRIK refused the chain (degenerate matrices)");
  }
  note_miss(d, chain, m, t);
  if (!two_bone) chain_finish(d, chain, start);
  return Status::ok();
}

}  // namespace

Status solve_inverse(Drag& d) {
  return solve_units(d, [&](const PlanChain& chain) { return solve_chain(d, chain); });
}

}  // namespace rigel::ephemeral::modes
