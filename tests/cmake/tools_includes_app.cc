// Layer probe (tests/cmake): compiled as the tools layer, this include of the
// layer just above it (app) must not compile.
#include "rigel/app/workspace.h"
