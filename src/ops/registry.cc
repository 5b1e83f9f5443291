#include "rigel/ops/registry.h"

#include <cassert>

#include "rigel/ops/anim/nodes.h"
#include "rigel/ops/constraints/nodes.h"
#include "rigel/ops/deform/nodes.h"
#include "rigel/ops/ik/nodes.h"
#include "rigel/ops/util/nodes.h"
#include "rigel/scene/transform_types.h"

namespace rigel::ops {

Status register_ops_types(graph::Registry& registry) {
  if (Status s = anim::register_anim_types(registry); !s) return s;
  if (Status s = constraints::register_constraint_types(registry); !s) return s;
  if (Status s = register_deform_types(registry); !s) return s;
  if (Status s = ik::register_ik_types(registry); !s) return s;
  if (Status s = util::register_util_types(registry); !s) return s;
  return Status::ok();
}

std::shared_ptr<const graph::Registry> default_registry() {
  static const std::shared_ptr<const graph::Registry> registry = [] {
    auto r = std::make_shared<graph::Registry>();
    Status s = scene::register_scene_types(*r);
    if (s) s = register_ops_types(*r);
    assert(s.is_ok() && "the built-in node types must register");
    (void)s;
    return r;
  }();
  return registry;
}

}  // namespace rigel::ops
