// Layer probe (tests/cmake): compiled as the math layer, this include of a
// higher layer (scene) must not compile.
#include "rigel/scene/scene.h"
