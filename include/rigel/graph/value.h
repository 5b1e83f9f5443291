#pragma once
// Attribute values: a closed set of types, each also as an array.

#include <cstdint>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "rigel/base/status.h"
#include "rigel/math/types.h"

namespace rigel::graph {

using math::Mat4;
using math::Quat;
using math::Vec3;

enum class ValueType : std::uint8_t {
  kMessage,  // carries no data: a relation between nodes (metadata network)
  kBool,
  kInt,
  kEnum,     // an int whose values have names (AttrSpec::enum_names)
  kDouble,
  kDouble3,
  kQuat,
  kMatrix,
  kString,
};

// The type of an attribute: a value type, scalar or array.
struct AttrType {
  ValueType value = ValueType::kDouble;
  bool array = false;
  friend bool operator==(const AttrType&, const AttrType&) = default;
};

// "double3", "matrix[]", ...
std::string type_name(AttrType type);
// Parses what type_name() writes.
Result<AttrType> type_from_name(std::string_view name);

// Storage of one attribute value. Message attributes hold monostate; bool,
// int and enum share int-like slots: bool uses `bool`, int and enum use
// int64_t. Quaternions are stored (x, y, z, w) in Eigen's layout.
using Value = std::variant<std::monostate, bool, std::int64_t, double, Vec3, Quat, Mat4, std::string,
                           std::vector<bool>, std::vector<std::int64_t>, std::vector<double>,
                           std::vector<Vec3>, std::vector<Quat>, std::vector<Mat4>,
                           std::vector<std::string>>;

// The zero of a type: false, 0, 0.0, (0,0,0), identity quaternion and
// matrix, "", or an empty array.
Value zero_value(AttrType type);
// True when `value` holds the storage alternative of `type`.
bool value_has_type(const Value& value, AttrType type);
// Bit-for-bit equality (NaN equals the same NaN, 0.0 differs from -0.0).
bool values_identical(const Value& a, const Value& b);

// Arrays: element count (0 for scalars), element access and assignment.
std::size_t array_size(const Value& array);
// The element at `index`, or the element type's zero when out of range.
Value array_element(const Value& array, AttrType type, std::size_t index);
// Sets element `index`, growing the array with zeros as needed. `element`
// must have the element type of `type`.
void array_set_element(Value& array, AttrType type, std::size_t index, const Value& element);

// True when `text` is well-formed UTF-8 (names, tags and strings must be:
// files are JSON).
bool is_valid_utf8(std::string_view text);

// Short human-readable text of a value, for messages and `inspect`.
std::string value_to_text(const Value& value);

}  // namespace rigel::graph
