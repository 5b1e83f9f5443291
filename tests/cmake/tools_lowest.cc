// Layer probe (tests/cmake): compiled as the tools layer, which sees every
// layer below it, down to base through the layers between.
#include "rigel/base/status.h"
#include "rigel/tools/bake.h"

int rigel_layer_probe_tools_lowest() { return rigel::Status::ok().is_ok() ? 0 : 1; }
