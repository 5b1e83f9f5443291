#pragma once
// Utility node types (Maya's math nodes), for rigs that wire matrices and
// values between operators.
//
//   inverseMatrix  inputMatrix, offsetMatrix (matrix inputs) ->
//                  outputMatrix = (inputMatrix * offsetMatrix)^-1
//                  Connect a transform's parent worldMatrix to inputMatrix and
//                  set offsetMatrix to its offsetParentMatrix: the output is
//                  the parent-space inverse a constraint's parentInverseMatrix
//                  needs, following the parent as it moves. A singular input
//                  gives the identity and says so in `error`.

#include "rigel/base/status.h"
#include "rigel/graph/node_type.h"

namespace rigel::ops::util {

inline constexpr const char* kInverseMatrixType = "inverseMatrix";

Status register_util_types(graph::Registry& registry);

}  // namespace rigel::ops::util
