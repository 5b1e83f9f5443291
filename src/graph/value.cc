#include "rigel/graph/value.h"

#include <bit>
#include <cstring>
#include <sstream>

namespace rigel::graph {
namespace {

constexpr struct {
  ValueType type;
  const char* name;
} kTypeNames[] = {
    {ValueType::kMessage, "message"}, {ValueType::kBool, "bool"},       {ValueType::kInt, "int"},
    {ValueType::kEnum, "enum"},       {ValueType::kDouble, "double"},   {ValueType::kDouble3, "double3"},
    {ValueType::kQuat, "quaternion"}, {ValueType::kMatrix, "matrix"},   {ValueType::kString, "string"},
};

template <typename T>
struct IsVector : std::false_type {};
template <typename E>
struct IsVector<std::vector<E>> : std::true_type {};

bool doubles_identical(const double* a, const double* b, std::size_t n) {
  // An empty std::vector's data() may be null, and memcmp with a null
  // pointer is undefined even for zero bytes.
  return n == 0 || std::memcmp(a, b, n * sizeof(double)) == 0;
}

struct IdenticalVisitor {
  const Value& other;
  bool operator()(std::monostate) const { return true; }
  bool operator()(bool v) const { return v == std::get<bool>(other); }
  bool operator()(std::int64_t v) const { return v == std::get<std::int64_t>(other); }
  bool operator()(double v) const { return std::bit_cast<std::uint64_t>(v) == std::bit_cast<std::uint64_t>(std::get<double>(other)); }
  bool operator()(const Vec3& v) const { return doubles_identical(v.data(), std::get<Vec3>(other).data(), 3); }
  bool operator()(const Quat& v) const { return doubles_identical(v.coeffs().data(), std::get<Quat>(other).coeffs().data(), 4); }
  bool operator()(const Mat4& v) const { return doubles_identical(v.data(), std::get<Mat4>(other).data(), 16); }
  bool operator()(const std::string& v) const { return v == std::get<std::string>(other); }
  bool operator()(const std::vector<bool>& v) const { return v == std::get<std::vector<bool>>(other); }
  bool operator()(const std::vector<std::int64_t>& v) const { return v == std::get<std::vector<std::int64_t>>(other); }
  bool operator()(const std::vector<std::string>& v) const { return v == std::get<std::vector<std::string>>(other); }
  bool operator()(const std::vector<double>& v) const {
    const auto& o = std::get<std::vector<double>>(other);
    return v.size() == o.size() && doubles_identical(v.data(), o.data(), v.size());
  }
  template <typename T>
  bool operator()(const std::vector<T>& v) const {
    const auto& o = std::get<std::vector<T>>(other);
    if (v.size() != o.size()) return false;
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (!IdenticalVisitor{Value(o[i])}(v[i])) return false;
    }
    return true;
  }
};

}  // namespace

std::string type_name(AttrType type) {
  std::string name = "unknown";
  for (const auto& entry : kTypeNames) {
    if (entry.type == type.value) name = entry.name;
  }
  return type.array ? name + "[]" : name;
}

Result<AttrType> type_from_name(std::string_view name) {
  AttrType type;
  if (name.size() > 2 && name.substr(name.size() - 2) == "[]") {
    type.array = true;
    name.remove_suffix(2);
  }
  for (const auto& entry : kTypeNames) {
    if (name == entry.name) {
      type.value = entry.type;
      return type;
    }
  }
  return error(ErrorCode::kInvalidArgument, "unknown attribute type '" + std::string(name) + "'");
}

Value zero_value(AttrType type) {
  if (type.array) {
    switch (type.value) {
      case ValueType::kMessage: return std::monostate{};
      case ValueType::kBool: return std::vector<bool>{};
      case ValueType::kInt:
      case ValueType::kEnum: return std::vector<std::int64_t>{};
      case ValueType::kDouble: return std::vector<double>{};
      case ValueType::kDouble3: return std::vector<Vec3>{};
      case ValueType::kQuat: return std::vector<Quat>{};
      case ValueType::kMatrix: return std::vector<Mat4>{};
      case ValueType::kString: return std::vector<std::string>{};
    }
  }
  switch (type.value) {
    case ValueType::kMessage: return std::monostate{};
    case ValueType::kBool: return false;
    case ValueType::kInt:
    case ValueType::kEnum: return std::int64_t{0};
    case ValueType::kDouble: return 0.0;
    case ValueType::kDouble3: return Vec3(Vec3::Zero());
    case ValueType::kQuat: return Quat(Quat::Identity());
    case ValueType::kMatrix: return Mat4(Mat4::Identity());
    case ValueType::kString: return std::string();
  }
  return std::monostate{};
}

bool value_has_type(const Value& value, AttrType type) {
  return value.index() == zero_value(type).index();
}

bool values_identical(const Value& a, const Value& b) {
  if (a.index() != b.index()) return false;
  return std::visit(IdenticalVisitor{b}, a);
}

std::size_t array_size(const Value& array) {
  return std::visit(
      [](const auto& v) -> std::size_t {
        using T = std::decay_t<decltype(v)>;
        if constexpr (IsVector<T>::value) {
          return v.size();
        } else {
          return 0;
        }
      },
      array);
}

Value array_element(const Value& array, AttrType type, std::size_t index) {
  AttrType element_type{type.value, false};
  return std::visit(
      [&](const auto& v) -> Value {
        using T = std::decay_t<decltype(v)>;
        if constexpr (IsVector<T>::value) {
          if (index < v.size()) return typename T::value_type(v[index]);
        }
        return zero_value(element_type);
      },
      array);
}

void array_set_element(Value& array, AttrType type, std::size_t index, const Value& element) {
  AttrType element_type{type.value, false};
  std::visit(
      [&](auto& v) {
        using T = std::decay_t<decltype(v)>;
        if constexpr (IsVector<T>::value) {
          using E = typename T::value_type;
          if (v.size() <= index) v.resize(index + 1, std::get<E>(zero_value(element_type)));
          v[index] = std::get<E>(element);
        }
      },
      array);
}

bool is_valid_utf8(std::string_view text) {
  std::size_t i = 0;
  while (i < text.size()) {
    auto c = static_cast<unsigned char>(text[i]);
    std::size_t extra;
    std::uint32_t code;
    if (c < 0x80) {
      ++i;
      continue;
    } else if ((c & 0xe0) == 0xc0) {
      extra = 1;
      code = c & 0x1f;
    } else if ((c & 0xf0) == 0xe0) {
      extra = 2;
      code = c & 0x0f;
    } else if ((c & 0xf8) == 0xf0) {
      extra = 3;
      code = c & 0x07;
    } else {
      return false;
    }
    if (i + extra >= text.size()) return false;  // truncated sequence
    for (std::size_t k = 1; k <= extra; ++k) {
      auto d = static_cast<unsigned char>(text[i + k]);
      if ((d & 0xc0) != 0x80) return false;
      code = (code << 6) | (d & 0x3f);
    }
    // Overlong forms, surrogates and code points past U+10FFFF are invalid.
    static constexpr std::uint32_t kMin[] = {0, 0x80, 0x800, 0x10000};
    if (code < kMin[extra] || code > 0x10ffff || (code >= 0xd800 && code <= 0xdfff)) return false;
    i += extra + 1;
  }
  return true;
}

namespace {
void write_doubles(std::ostringstream& out, const double* d, int n) {
  out << '[';
  for (int i = 0; i < n; ++i) out << (i ? ", " : "") << d[i];
  out << ']';
}
}  // namespace

std::string value_to_text(const Value& value) {
  std::ostringstream out;
  out.precision(6);
  std::visit(
      [&](const auto& v) {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, std::monostate>) out << "(message)";
        else if constexpr (std::is_same_v<T, bool>) out << (v ? "true" : "false");
        else if constexpr (std::is_same_v<T, std::int64_t> || std::is_same_v<T, double>) out << v;
        else if constexpr (std::is_same_v<T, Vec3>) write_doubles(out, v.data(), 3);
        else if constexpr (std::is_same_v<T, Quat>) write_doubles(out, v.coeffs().data(), 4);
        else if constexpr (std::is_same_v<T, Mat4>) write_doubles(out, v.data(), 16);
        else if constexpr (std::is_same_v<T, std::string>) out << '"' << v << '"';
        else out << '[' << v.size() << " elements]";
      },
      value);
  return out.str();
}

}  // namespace rigel::graph
