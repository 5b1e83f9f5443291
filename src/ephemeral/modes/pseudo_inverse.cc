// Pseudo-inverse modes (seed 000 §5.7): the grabbed control's motion spread
// evenly down its chain to the top (which stays), every control re-aimed at
// its child (ops::ik::PseudoInverseJob). The length variant then restores
// every bone's length from the top out.
#include <span>

#include "modes.h"
#include "rigel/ops/ik/pseudo_inverse.h"

namespace rigel::ephemeral::modes {

namespace {

Status solve_chain(Drag& d, const PlanChain& chain, bool keep_lengths) {
  const ChainStart start = chain_start(d, chain, keep_lengths);
  if (start.done) return Status::ok();
  Scratch& sc = d.sc;
  const auto count = static_cast<std::size_t>(start.m);
  ops::ik::PseudoInverseJob job;
  job.positions = std::span<const Vec3>(sc.positions.data(), count);
  job.target = pos(start.target);
  job.keep_lengths = keep_lengths;
  job.solved = std::span<Vec3>(sc.solved.data(), count);
  job.turns = std::span<Mat3>(sc.turns.data(), count);
  if (!job.run()) return error(ErrorCode::kInvalidArgument, "drag: the pseudo-inverse chain is not finite");
  chain_finish(d, chain, start);
  return Status::ok();
}

}  // namespace

void plan_pseudo_inverse(Planner& p) { plan_chains(p); }
void plan_pseudo_inverse_length(Planner& p) { plan_chains(p); }

Status solve_pseudo_inverse(Drag& d) {
  return solve_units(d, [&](const PlanChain& chain) { return solve_chain(d, chain, false); });
}
Status solve_pseudo_inverse_length(Drag& d) {
  return solve_units(d, [&](const PlanChain& chain) { return solve_chain(d, chain, true); });
}

}  // namespace rigel::ephemeral::modes
