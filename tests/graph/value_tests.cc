#include "rigel/graph/value.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "graph_test_util.h"
#include "rigel/graph/uuid.h"

namespace rigel::graph {
namespace {

constexpr ValueType kAllValueTypes[] = {ValueType::kMessage, ValueType::kBool,   ValueType::kInt,
                                        ValueType::kEnum,    ValueType::kDouble, ValueType::kDouble3,
                                        ValueType::kQuat,    ValueType::kMatrix, ValueType::kString};

TEST(Value, zero_value__scalars_are_the_documented_zeros) {
  EXPECT_TRUE(std::holds_alternative<std::monostate>(zero_value({ValueType::kMessage, false})))
      << "a message carries no data";
  EXPECT_EQ(std::get<bool>(zero_value({ValueType::kBool, false})), false) << "the zero bool is false";
  EXPECT_EQ(std::get<std::int64_t>(zero_value({ValueType::kInt, false})), 0) << "the zero int is 0";
  EXPECT_EQ(std::get<std::int64_t>(zero_value({ValueType::kEnum, false})), 0) << "an enum's zero is its first name";
  const double d = std::get<double>(zero_value({ValueType::kDouble, false}));
  EXPECT_EQ(d, 0.0) << "the zero double is 0";
  EXPECT_FALSE(std::signbit(d)) << "the zero double is +0.0, not -0.0";
  EXPECT_EQ(std::get<Vec3>(zero_value({ValueType::kDouble3, false})), Vec3::Zero()) << "double3 zero is (0,0,0)";
  EXPECT_TRUE(std::get<Quat>(zero_value({ValueType::kQuat, false})).coeffs().isApprox(Quat::Identity().coeffs()))
      << "the zero quaternion is the identity rotation, not all zeros";
  EXPECT_EQ(std::get<Quat>(zero_value({ValueType::kQuat, false})).w(), 1.0) << "identity quaternion has w = 1";
  EXPECT_EQ(std::get<Mat4>(zero_value({ValueType::kMatrix, false})), Mat4::Identity()) << "the zero matrix is identity";
  EXPECT_EQ(std::get<std::string>(zero_value({ValueType::kString, false})), "") << "the zero string is empty";
}

TEST(Value, zero_value__arrays_are_empty_and_have_their_type) {
  for (ValueType t : kAllValueTypes) {
    const AttrType type{t, true};
    const Value zero = zero_value(type);
    EXPECT_EQ(array_size(zero), 0u) << type_name(type) << ": the zero of an array is empty";
    EXPECT_TRUE(value_has_type(zero, type)) << type_name(type) << ": zero_value must hold the type's storage";
    const AttrType scalar{t, false};
    EXPECT_TRUE(value_has_type(zero_value(scalar), scalar)) << type_name(scalar) << ": zero_value must hold the storage";
    if (t != ValueType::kMessage) {
      EXPECT_FALSE(value_has_type(zero_value(scalar), type))
          << type_name(type) << ": a scalar must not pass for its array type";
    }
  }
}

TEST(Value, value_has_type__int_and_enum_share_storage_but_double_does_not) {
  EXPECT_TRUE(value_has_type(Value(std::int64_t{2}), {ValueType::kEnum, false})) << "enums are stored as int64";
  EXPECT_TRUE(value_has_type(Value(std::int64_t{2}), {ValueType::kInt, false})) << "ints are stored as int64";
  EXPECT_FALSE(value_has_type(Value(2.0), {ValueType::kInt, false})) << "a double is not an int";
  EXPECT_FALSE(value_has_type(Value(true), {ValueType::kInt, false})) << "bool has its own slot";
  EXPECT_FALSE(value_has_type(Value(Vec3(1, 2, 3)), {ValueType::kQuat, false})) << "double3 is not a quaternion";
}

TEST(Value, values_identical__compares_bits) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(values_identical(Value(nan), Value(nan))) << "the same NaN is identical to itself (unlike ==)";
  EXPECT_FALSE(values_identical(Value(0.0), Value(-0.0))) << "0.0 and -0.0 compare equal but are not identical";
  EXPECT_TRUE(values_identical(Value(1.5), Value(1.5))) << "equal doubles are identical";
  EXPECT_FALSE(values_identical(Value(1.0), Value(std::nextafter(1.0, 2.0)))) << "one ulp apart is different";

  EXPECT_TRUE(values_identical(Value(Vec3(nan, 1, 2)), Value(Vec3(nan, 1, 2)))) << "NaN inside a double3";
  EXPECT_FALSE(values_identical(Value(Vec3(0, 1, 2)), Value(Vec3(-0.0, 1, 2)))) << "-0.0 inside a double3";
  Mat4 a = Mat4::Identity(), b = Mat4::Identity();
  a(2, 3) = nan;
  b(2, 3) = nan;
  EXPECT_TRUE(values_identical(Value(a), Value(b))) << "NaN inside a matrix";
  b(1, 0) = -0.0;
  EXPECT_FALSE(values_identical(Value(a), Value(b))) << "-0.0 inside a matrix";
  EXPECT_FALSE(values_identical(Value(Quat(1, 0, 0, 0)), Value(Quat(-1, 0, 0, 0))))
      << "q and -q are the same rotation but not identical values";

  EXPECT_TRUE(values_identical(Value(std::vector<double>{nan, 1.0}), Value(std::vector<double>{nan, 1.0})))
      << "NaN inside a double array";
  EXPECT_FALSE(values_identical(Value(std::vector<double>{0.0}), Value(std::vector<double>{-0.0})))
      << "-0.0 inside a double array";
  EXPECT_TRUE(values_identical(Value(std::vector<double>{}), Value(std::vector<double>{})))
      << "two empty double arrays are identical (and comparing them is defined behaviour)";
  EXPECT_FALSE(values_identical(Value(std::vector<double>{1.0}), Value(std::vector<double>{1.0, 0.0})))
      << "arrays of different sizes differ";
  EXPECT_TRUE(values_identical(Value(std::vector<Vec3>{Vec3(nan, 0, 0)}), Value(std::vector<Vec3>{Vec3(nan, 0, 0)})))
      << "NaN inside a double3 array";
  EXPECT_FALSE(values_identical(Value(std::vector<Mat4>{Mat4::Identity()}), Value(std::vector<Mat4>{})))
      << "matrix arrays of different sizes differ";

  EXPECT_FALSE(values_identical(Value(std::int64_t{1}), Value(1.0))) << "different storage types are never identical";
  EXPECT_FALSE(values_identical(Value(true), Value(std::int64_t{1}))) << "bool and int differ";
  EXPECT_TRUE(values_identical(Value(std::monostate{}), Value(std::monostate{}))) << "messages are all alike";
  EXPECT_TRUE(values_identical(Value(std::string("a")), Value(std::string("a")))) << "equal strings";
  EXPECT_FALSE(values_identical(Value(std::string("a")), Value(std::string("A")))) << "strings are case-sensitive";
}

TEST(Value, array_element__out_of_range_reads_the_element_zero) {
  const AttrType type{ValueType::kDouble, true};
  Value array = std::vector<double>{1.0, 2.0};
  EXPECT_EQ(array_size(array), 2u) << "two elements";
  EXPECT_EQ(std::get<double>(array_element(array, type, 1)), 2.0) << "in range reads the element";
  EXPECT_EQ(std::get<double>(array_element(array, type, 7)), 0.0) << "out of range reads the zero";

  const AttrType quats{ValueType::kQuat, true};
  Value q = zero_value(quats);
  EXPECT_EQ(std::get<Quat>(array_element(q, quats, 0)).w(), 1.0) << "a missing quaternion reads as identity";
  EXPECT_EQ(array_size(Value(3.0)), 0u) << "a scalar has no elements";
}

TEST(Value, array_set_element__grows_with_zeros) {
  const AttrType type{ValueType::kDouble, true};
  Value array = zero_value(type);
  array_set_element(array, type, 3, Value(7.0));
  ASSERT_EQ(array_size(array), 4u) << "setting element 3 of an empty array grows it to 4";
  EXPECT_TRUE(values_identical(array, Value(std::vector<double>{0.0, 0.0, 0.0, 7.0})))
      << "the new elements before the one set are zeros";
  array_set_element(array, type, 1, Value(-2.0));
  EXPECT_TRUE(values_identical(array, Value(std::vector<double>{0.0, -2.0, 0.0, 7.0})))
      << "setting inside the array overwrites without growing";

  const AttrType matrices{ValueType::kMatrix, true};
  Value m = zero_value(matrices);
  Mat4 t = Mat4::Identity();
  t(0, 3) = 5.0;
  array_set_element(m, matrices, 2, Value(t));
  ASSERT_EQ(array_size(m), 3u) << "matrix array grows to 3";
  EXPECT_EQ(std::get<Mat4>(array_element(m, matrices, 0)), Mat4::Identity()) << "matrix padding is identity";
  EXPECT_EQ(std::get<Mat4>(array_element(m, matrices, 2)), t) << "the matrix set is read back";

  const AttrType bools{ValueType::kBool, true};
  Value b = zero_value(bools);
  array_set_element(b, bools, 2, Value(true));
  EXPECT_TRUE(values_identical(b, Value(std::vector<bool>{false, false, true}))) << "bool arrays grow with false";

  const AttrType enums{ValueType::kEnum, true};
  Value e = zero_value(enums);
  array_set_element(e, enums, 1, Value(std::int64_t{2}));
  EXPECT_TRUE(values_identical(e, Value(std::vector<std::int64_t>{0, 2}))) << "enum arrays are int64 arrays";

  const AttrType strings{ValueType::kString, true};
  Value s = zero_value(strings);
  array_set_element(s, strings, 1, Value(std::string("x")));
  EXPECT_TRUE(values_identical(s, Value(std::vector<std::string>{"", "x"}))) << "string arrays grow with \"\"";
}

TEST(Value, type_name__round_trips_every_type) {
  for (ValueType t : kAllValueTypes) {
    for (bool array : {false, true}) {
      const AttrType type{t, array};
      const std::string name = type_name(type);
      Result<AttrType> back = type_from_name(name);
      ASSERT_TRUE(back.is_ok()) << "'" << name << "' should parse back: " << back.status().message();
      EXPECT_EQ(*back, type) << "'" << name << "' should parse to the type that wrote it";
      EXPECT_EQ(array, name.size() > 2 && name.substr(name.size() - 2) == "[]") << name << ": arrays end in []";
    }
  }
  EXPECT_EQ(type_name({ValueType::kDouble3, false}), "double3") << "documented spelling";
  EXPECT_EQ(type_name({ValueType::kMatrix, true}), "matrix[]") << "documented spelling";
}

TEST(Value, type_from_name__refuses_unknown_names) {
  for (const char* bad : {"", "[]", "Double", "double[][]", "double []", "float", "double3[", "vector"}) {
    Result<AttrType> r = type_from_name(bad);
    EXPECT_FALSE(r.is_ok()) << "'" << bad << "' is not a type name";
    if (!r.is_ok()) {
      EXPECT_EQ(r.status().code(), ErrorCode::kInvalidArgument) << "bad names are invalid arguments";
    }
  }
}

TEST(Value, value_to_text__is_short_and_readable) {
  EXPECT_EQ(value_to_text(Value(true)), "true") << "bools as words";
  EXPECT_EQ(value_to_text(Value(std::int64_t{-3})), "-3") << "ints as numbers";
  EXPECT_EQ(value_to_text(Value(1.5)), "1.5") << "doubles as numbers";
  EXPECT_EQ(value_to_text(Value(Vec3(1, 2, 3))), "[1, 2, 3]") << "double3 as a list";
  EXPECT_EQ(value_to_text(Value(std::string("hi"))), "\"hi\"") << "strings quoted";
  EXPECT_EQ(value_to_text(Value(std::vector<double>{1, 2})), "[2 elements]") << "arrays by size";
  EXPECT_EQ(value_to_text(Value(std::monostate{})), "(message)") << "messages";
}

// ---- Uuid ------------------------------------------------------------------

TEST(Uuid, generate__is_unique_version_4) {
  std::set<std::string> seen;
  for (int i = 0; i < 10000; ++i) {
    const Uuid u = Uuid::generate();
    const std::string s = u.str();
    EXPECT_FALSE(u.is_nil()) << "a generated uuid is never nil";
    EXPECT_EQ(s[14], '4') << s << ": version nibble must be 4";
    EXPECT_NE(std::string("89ab").find(s[19]), std::string::npos) << s << ": variant must be 10xx";
    EXPECT_TRUE(seen.insert(s).second) << s << " was generated twice";
  }
}

TEST(Uuid, parse__round_trips_str) {
  for (int i = 0; i < 1000; ++i) {
    const Uuid u = Uuid::generate();
    std::optional<Uuid> back = Uuid::parse(u.str());
    ASSERT_TRUE(back.has_value()) << u.str() << " should parse";
    EXPECT_EQ(*back, u) << "parse(str()) must give the same uuid";
  }
  const std::string text = "0123abcd-4567-89ef-0123-456789abcdef";
  ASSERT_TRUE(Uuid::parse(text).has_value()) << "the canonical form parses";
  EXPECT_EQ(Uuid::parse(text)->str(), text) << "str() writes the canonical lower-case form";
  EXPECT_EQ(Uuid::parse("0123ABCD-4567-89EF-0123-456789ABCDEF")->str(), text) << "upper case parses too";
  EXPECT_TRUE(Uuid::parse("00000000-0000-0000-0000-000000000000")->is_nil()) << "the nil uuid parses";
  EXPECT_EQ(Uuid().str(), "00000000-0000-0000-0000-000000000000") << "default is nil";
}

TEST(Uuid, parse__refuses_malformed_text) {
  for (const char* bad : {"", "0123abcd-4567-89ef-0123-456789abcde", "0123abcd-4567-89ef-0123-456789abcdef0",
                          "0123abcd-4567-89ef-0123-456789abcdeg", "0123abcd+4567-89ef-0123-456789abcdef",
                          "0123abcd4567-89ef-0123-456789abcdef-", "{123abcd-4567-89ef-0123-456789abcde}",
                          " 123abcd-4567-89ef-0123-456789abcdef"}) {
    EXPECT_FALSE(Uuid::parse(bad).has_value()) << "'" << bad << "' is not a canonical uuid";
  }
}

}  // namespace
}  // namespace rigel::graph
