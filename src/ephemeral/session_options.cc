// SessionOptions::validate (session.h): the one range check of the posing
// options, shared by the service layer (and so by the CLI, the server and
// Python).

#include <cmath>
#include <string>

#include "rigel/ephemeral/session.h"

namespace rigel::ephemeral {

namespace {

Status bad(const char* field, std::string message) {
  return Status(ErrorCode::kInvalidArgument, std::string(field) + ": " + std::move(message)).with_field(field);
}

}  // namespace

Status SessionOptions::validate() const {
  if (!(magnet_fraction > 0.0 && magnet_fraction <= 1.0))
    return bad("magnetFraction", "must be a number in (0, 1]");
  if (!(magnet_min_weight >= 0.0 && magnet_min_weight < 1.0))
    return bad("magnetMinWeight", "must be a number in [0, 1)");
  if (!(magnet_radius > 0.0) || !std::isfinite(magnet_radius))
    return bad("magnetRadius", "must be a positive number");
  if (max_chain < 0 || max_chain > kMaxChainLimit)
    return bad("maxChain", "expected a whole number from 0 (no limit) to " + std::to_string(kMaxChainLimit));
  if (fabrik_iterations < 1 || fabrik_iterations > 100000)
    return bad("fabrikIterations", "expected a whole number from 1 to 100000");
  if (!(fabrik_tolerance > 0.0) || !std::isfinite(fabrik_tolerance))
    return bad("fabrikTolerance", "must be a positive number");
  return Status::ok();
}

}  // namespace rigel::ephemeral
