// Layer probe (tests/cmake): compiled as the math layer, which sees its own
// headers and base's.
#include "rigel/base/status.h"
#include "rigel/math/rotation.h"

int rigel_layer_probe_math_own() { return rigel::Status::ok().is_ok() ? 0 : 1; }
