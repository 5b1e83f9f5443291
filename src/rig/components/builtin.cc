#include <cstdio>
#include <cstdlib>

#include "rigel/rig/build_function.h"
#include "rigel/rig/component.h"
#include "rigel/rig/components/basic.h"
#include "rigel/rig/components/limbs.h"
#include "rigel/rig/components/body.h"
#include "rigel/rig/components/foot.h"
#include "rigel/rig/components/face.h"
#include "rigel/rig/components/hand.h"
#include "rigel/rig/components/mechanical.h"
#include "rigel/rig/components/shapes.h"

namespace rigel::rig {

const ComponentFactory& builtin_components() {
  static const ComponentFactory factory = [] {
    ComponentFactory f;
    Status s = components::add_basic_components(f);
    if (s) s = components::add_limb_components(f);
    if (s) s = components::add_body_components(f);
    if (s) s = components::add_foot_component(f);
    if (s) s = components::add_hand_component(f);
    if (s) s = components::add_face_components(f);
    if (s) s = components::add_mechanical_components(f);
    if (s) s = components::add_shape_components(f);
    if (s) s = add_call_component(f);
    if (!s) {
      std::fprintf(stderr, "rigel: built-in component classes: %s\n", s.message().c_str());
      std::abort();
    }
    return f;
  }();
  return factory;
}

}  // namespace rigel::rig
