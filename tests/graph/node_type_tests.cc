#include "rigel/graph/node_type.h"

#include <gtest/gtest.h>

#include <string>

#include "graph_test_util.h"

namespace rigel::graph {
namespace {

using testing::in_spec;
using testing::kDoubleT;
using testing::kIntT;
using testing::kMatrixT;
using testing::out_spec;

void noop(ComputeContext&) {}

// A valid type: two inputs, one output, a compute. Each test breaks one thing.
NodeTypeSpec valid_spec(std::string name = "valid") {
  NodeTypeSpec s;
  s.name = std::move(name);
  s.attrs = {in_spec("a", kDoubleT, {"out"}), in_spec("b", kDoubleT), out_spec("out", kDoubleT)};
  s.compute = noop;
  return s;
}

// Adds `spec` to a fresh registry and expects it refused with `code`, the
// message naming `mention` (the type or the attribute at fault).
void expect_refused(NodeTypeSpec spec, ErrorCode code, const std::string& mention, const char* why) {
  Registry registry;
  const std::string name = spec.name;
  Status s = registry.add(std::move(spec));
  EXPECT_FALSE(s.is_ok()) << why;
  EXPECT_EQ(s.code(), code) << why << " (" << s.message() << ")";
  EXPECT_NE(s.message().find(mention), std::string::npos)
      << why << ": the message should name '" << mention << "': " << s.message();
  EXPECT_EQ(registry.find(name), nullptr) << why << ": a refused type must not be registered";
}

TEST(Registry, add__valid_type_is_found_with_its_attributes) {
  Registry registry;
  ASSERT_TRUE(registry.add(valid_spec()).is_ok()) << "the baseline spec is valid";
  const NodeType* t = registry.find("valid");
  ASSERT_NE(t, nullptr) << "a registered type is found by name";
  EXPECT_EQ(t->attr_count(), 4u) << "three attributes declared, and metaParent added last";
  EXPECT_EQ(t->attr_find(kMetaParentAttr), 3) << "every type ends with metaParent";
  EXPECT_EQ(t->attr(3).type.value, ValueType::kMessage);
  EXPECT_EQ(t->attr_find("b"), 1) << "attributes keep declaration order";
  EXPECT_EQ(t->attr_find("missing"), kNoAttr) << "an unknown attribute is kNoAttr";
  ASSERT_EQ(t->affected_outputs(0).size(), 1u) << "'a' affects 'out'";
  EXPECT_EQ(t->affected_outputs(0)[0], 2) << "'a' affects 'out' (index 2)";
  EXPECT_TRUE(t->affected_outputs(1).empty()) << "'b' affects nothing";
  ASSERT_EQ(t->outputs().size(), 1u) << "one output";
  EXPECT_EQ(t->outputs()[0], 2) << "'out' is the output";
  EXPECT_TRUE(t->is_input(0)) << "'a' is an input";
  EXPECT_FALSE(t->is_input(2)) << "'out' is not an input";
  EXPECT_TRUE(std::holds_alternative<double>(t->default_value(0))) << "a monostate default becomes the type's zero";
  EXPECT_EQ(t->parent_input(), kNoAttr) << "no hierarchy roles were declared";
  EXPECT_EQ(t->world_output(), kNoAttr) << "no hierarchy roles were declared";
  EXPECT_EQ(registry.find("nope"), nullptr) << "an unknown type is nullptr";
}

TEST(Registry, type_names__sorted) {
  Registry registry;
  ASSERT_TRUE(registry.add(valid_spec("zeta")).is_ok()) << "valid";
  ASSERT_TRUE(registry.add(valid_spec("alpha")).is_ok()) << "valid";
  EXPECT_EQ(registry.type_names(), (std::vector<std::string>{"alpha", "zeta"})) << "type names are listed sorted";
}

TEST(Registry, add__duplicate_type_is_refused) {
  Registry registry;
  ASSERT_TRUE(registry.add(valid_spec("twice")).is_ok()) << "first registration succeeds";
  const NodeType* first = registry.find("twice");
  NodeTypeSpec again = valid_spec("twice");
  again.attrs.pop_back();
  again.attrs[0].affects.clear();
  Status s = registry.add(std::move(again));
  EXPECT_EQ(s.code(), ErrorCode::kAlreadyExists) << "a second type with the same name is refused: " << s.message();
  EXPECT_EQ(registry.find("twice"), first) << "the first registration stays, unchanged";
  EXPECT_EQ(registry.find("twice")->attr_count(), 4u) << "types never change once added";
}

TEST(Registry, add__invalid_type_name_is_refused) {
  for (const char* bad : {"", "2d", "has space", "dot.name", "dash-name"}) {
    NodeTypeSpec s = valid_spec(bad);
    expect_refused(std::move(s), ErrorCode::kInvalidArgument, "identifier", "a type name must be an identifier");
  }
}

TEST(Registry, add__duplicate_attribute_name_is_refused) {
  NodeTypeSpec s = valid_spec();
  s.attrs.push_back(in_spec("a", kIntT));
  expect_refused(std::move(s), ErrorCode::kInvalidArgument, "'a'", "two attributes named 'a' are refused");
}

TEST(Registry, add__non_identifier_attribute_name_is_refused) {
  for (const char* bad : {"", "1x", "with space", "x.y", "x[0]"}) {
    NodeTypeSpec s = valid_spec();
    s.attrs.push_back(in_spec(bad, kIntT));
    expect_refused(std::move(s), ErrorCode::kInvalidArgument, "not an identifier",
                   "an attribute name must be an identifier");
  }
}

TEST(Registry, add__input_and_output_flags_are_exclusive) {
  {
    NodeTypeSpec s = valid_spec();
    s.attrs[1].flags = kInput | kOutput;
    expect_refused(std::move(s), ErrorCode::kInvalidArgument, "'b'", "an attribute cannot be both input and output");
  }
  {
    NodeTypeSpec s = valid_spec();
    s.attrs[1].flags = kStorable;
    expect_refused(std::move(s), ErrorCode::kInvalidArgument, "'b'", "an attribute must be an input or an output");
  }
}

TEST(Registry, add__default_of_the_wrong_type_is_refused) {
  {
    NodeTypeSpec s = valid_spec();
    s.attrs.push_back(in_spec("count", kIntT, {}, 1.0));
    expect_refused(std::move(s), ErrorCode::kInvalidArgument, "'count'", "a double default for an int is refused");
  }
  {
    NodeTypeSpec s = valid_spec();
    s.attrs.push_back(in_spec("list", {ValueType::kDouble, true}, {}, 1.0));
    expect_refused(std::move(s), ErrorCode::kInvalidArgument, "'list'", "a scalar default for an array is refused");
  }
  {
    NodeTypeSpec s = valid_spec();
    s.attrs.push_back(in_spec("m", kMatrixT, {}, Vec3(1, 2, 3)));
    expect_refused(std::move(s), ErrorCode::kInvalidArgument, "'m'", "a double3 default for a matrix is refused");
  }
}

TEST(Registry, add__enum_default_out_of_range_is_refused) {
  for (std::int64_t bad : {std::int64_t{-1}, std::int64_t{3}}) {
    NodeTypeSpec s = valid_spec();
    AttrSpec e = in_spec("mode", {ValueType::kEnum, false}, {}, bad);
    e.enum_names = {"a", "b", "c"};
    s.attrs.push_back(e);
    expect_refused(std::move(s), ErrorCode::kInvalidArgument, "'mode'",
                   "an enum default must index one of its names");
  }
  {
    NodeTypeSpec s = valid_spec();
    AttrSpec e = in_spec("mode", {ValueType::kEnum, false}, {}, std::int64_t{2});
    e.enum_names = {"a", "b", "c"};
    s.attrs.push_back(e);
    Registry registry;
    EXPECT_TRUE(registry.add(std::move(s)).is_ok()) << "the last name's index is in range";
  }
  {
    NodeTypeSpec s = valid_spec();
    s.attrs.push_back(in_spec("mode", {ValueType::kEnum, false}));
    expect_refused(std::move(s), ErrorCode::kInvalidArgument, "'mode'", "an enum without names is refused");
  }
}

TEST(Registry, add__angle_flag_only_on_doubles) {
  NodeTypeSpec s = valid_spec();
  AttrSpec a = in_spec("turn", kIntT);
  a.flags |= kAngle;
  s.attrs.push_back(a);
  expect_refused(std::move(s), ErrorCode::kInvalidArgument, "'turn'", "an int cannot be an angle");
}

TEST(Registry, add__affects_must_name_an_output) {
  {
    NodeTypeSpec s = valid_spec();
    s.attrs[0].affects = {"b"};
    expect_refused(std::move(s), ErrorCode::kInvalidArgument, "'b'", "an input cannot affect another input");
  }
  {
    NodeTypeSpec s = valid_spec();
    s.attrs[0].affects = {"nothing"};
    expect_refused(std::move(s), ErrorCode::kInvalidArgument, "'nothing'", "affects must name an existing attribute");
  }
  {
    NodeTypeSpec s = valid_spec();
    s.attrs[2].affects = {"out"};
    expect_refused(std::move(s), ErrorCode::kInvalidArgument, "'out'", "an output cannot affect anything");
  }
}

TEST(Registry, add__bad_hierarchy_role_is_refused) {
  auto with_matrices = [] {
    NodeTypeSpec s = valid_spec();
    s.attrs.push_back(in_spec("parentMatrix", kMatrixT, {"world"}));
    s.attrs.push_back(out_spec("world", kMatrixT));
    s.parent_input = "parentMatrix";
    s.world_output = "world";
    return s;
  };
  {
    Registry registry;
    EXPECT_TRUE(registry.add(with_matrices()).is_ok()) << "matrix input and output roles are valid";
    EXPECT_EQ(registry.find("valid")->parent_input(), 3) << "parent input resolved to its index";
    EXPECT_EQ(registry.find("valid")->world_output(), 4) << "world output resolved to its index";
  }
  {
    NodeTypeSpec s = with_matrices();
    s.parent_input = "missing";
    expect_refused(std::move(s), ErrorCode::kInvalidArgument, "'missing'", "the parent input must exist");
  }
  {
    NodeTypeSpec s = with_matrices();
    s.parent_input = "a";
    expect_refused(std::move(s), ErrorCode::kInvalidArgument, "'a'", "the parent input must be a matrix");
  }
  {
    NodeTypeSpec s = with_matrices();
    s.parent_input = "world";
    expect_refused(std::move(s), ErrorCode::kInvalidArgument, "'world'", "the parent input must be an input");
  }
  {
    NodeTypeSpec s = with_matrices();
    s.world_output = "parentMatrix";
    expect_refused(std::move(s), ErrorCode::kInvalidArgument, "'parentMatrix'", "the world output must be an output");
  }
  {
    NodeTypeSpec s = with_matrices();
    s.world_output = "out";
    expect_refused(std::move(s), ErrorCode::kInvalidArgument, "'out'", "the world output must be a matrix");
  }
  {
    NodeTypeSpec s = with_matrices();
    s.attrs.push_back(in_spec("parentArray", {ValueType::kMatrix, true}));
    s.parent_input = "parentArray";
    expect_refused(std::move(s), ErrorCode::kInvalidArgument, "'parentArray'",
                   "the parent input must be a scalar matrix, not an array");
  }
}

TEST(Registry, add__outputs_without_compute_are_refused) {
  NodeTypeSpec s = valid_spec();
  s.compute = nullptr;
  expect_refused(std::move(s), ErrorCode::kInvalidArgument, "compute", "a type with outputs needs a compute");

  NodeTypeSpec inputs_only;
  inputs_only.name = "inputsOnly";
  inputs_only.attrs = {in_spec("a", kDoubleT)};
  Registry registry;
  EXPECT_TRUE(registry.add(std::move(inputs_only)).is_ok()) << "a type with only inputs needs no compute";
}

TEST(Registry, is_identifier__accepts_only_c_identifiers) {
  for (const char* good : {"a", "_", "_a1", "Abc_09", "translateX"}) EXPECT_TRUE(is_identifier(good)) << good;
  for (const char* bad : {"", "1a", "a-b", "a b", "a.b", "é", "a$"}) EXPECT_FALSE(is_identifier(bad)) << bad;
}

}  // namespace
}  // namespace rigel::graph
