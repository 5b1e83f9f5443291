// Forward (FK) and suspended modes. Forward: the grabbed controls move and
// what they drive follows rigidly over forward and pair relations (a
// grabbed control under another one is carried by it, then applies its own
// motion). Suspended: only the grabbed controls and their pair groups move;
// their children keep their world.
#include "modes.h"

namespace rigel::ephemeral::modes {

namespace {

void plan_grabbed_and_followers(Planner& p, bool forward) {
  std::vector<int> seeds;
  for (int k : p.grabbed) seeds.push_back(p.add(k, Role::kGrabbed, -1));
  p.walk_followers(seeds, forward, true, forward);
}

Status solve_entries(Drag& d) {
  for (int e : d.sc.units) d.move(e);
  return Status::ok();
}

}  // namespace

void plan_forward(Planner& p) { plan_grabbed_and_followers(p, true); }
void plan_suspended(Planner& p) { plan_grabbed_and_followers(p, false); }

Status solve_forward(Drag& d) { return solve_entries(d); }
Status solve_suspended(Drag& d) { return solve_entries(d); }

}  // namespace rigel::ephemeral::modes
