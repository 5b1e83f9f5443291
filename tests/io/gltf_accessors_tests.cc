// The accessor layer the glTF importer, exporter and looks share
// (src/io/gltf_accessors.h, private to rigel_io): glTF 2.0's layout rules,
// accessors written with BufferWriter and read back with AccessorReader, and
// the reader's refusals, each naming the place.
#include <tiny_gltf.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "gltf_accessors.h"

namespace rigel::io::gltf {
namespace {

// A model whose one buffer holds what `writer` wrote.
void finish(tinygltf::Model& model, BufferWriter& writer) {
  tinygltf::Buffer buffer;
  buffer.data = writer.bytes();
  model.buffers.push_back(std::move(buffer));
}

TEST(GltfAccessorLayout, sizes__matrix_columns_start_on_four_byte_boundaries) {
  EXPECT_EQ(element_size(TINYGLTF_TYPE_VEC3, kFloat), 12u);
  EXPECT_EQ(element_size(TINYGLTF_TYPE_MAT4, kFloat), 64u);
  EXPECT_EQ(element_size(TINYGLTF_TYPE_MAT2, kUnsignedByte), 8u) << "glTF 2.0 §3.6.2.4: a MAT2 of bytes takes 8 bytes";
  EXPECT_EQ(element_size(TINYGLTF_TYPE_MAT3, kUnsignedByte), 12u);
  EXPECT_EQ(element_size(TINYGLTF_TYPE_MAT3, kShort), 24u);
  EXPECT_EQ(component_offset(TINYGLTF_TYPE_MAT3, 1, 3), 4u) << "column 1 of a MAT3 of bytes starts at byte 4";
  EXPECT_EQ(component_offset(TINYGLTF_TYPE_VEC3, 4, 2), 8u);
  EXPECT_EQ(component_size(kUnsignedShort), 2u);
  EXPECT_EQ(component_size(1234), 0u) << "a number that is no component type has no size";
  EXPECT_EQ(component_count(TINYGLTF_TYPE_MAT3), 9);
  EXPECT_EQ(component_count(99), 0);
  EXPECT_STREQ(component_name(kUnsignedInt), "UNSIGNED_INT");
  EXPECT_STREQ(type_name(TINYGLTF_TYPE_VEC4), "VEC4");
  EXPECT_STREQ(type_name(99), "?");
}

TEST(GltfAccessorLayout, read_component__normalized_integers_map_to_unit_ranges) {
  const std::int8_t lowest = -128, highest = 127;
  EXPECT_EQ(read_component(reinterpret_cast<const unsigned char*>(&lowest), kByte, true), -1.0)
      << "glTF 2.0 §3.11: max(c / 127, -1)";
  EXPECT_EQ(read_component(reinterpret_cast<const unsigned char*>(&highest), kByte, true), 1.0);
  EXPECT_EQ(read_component(reinterpret_cast<const unsigned char*>(&lowest), kByte, false), -128.0);
  const std::uint16_t top = 65535;
  EXPECT_EQ(read_component(reinterpret_cast<const unsigned char*>(&top), kUnsignedShort, true), 1.0);
}

TEST(GltfAccessors, written_floats_read_back_with_bounds) {
  tinygltf::Model model;
  BufferWriter writer(model);
  const std::vector<double> points = {0.0, 1.0, 2.0, -3.0, 4.5, 5.0};
  const int a = writer.floats(points, TINYGLTF_TYPE_VEC3, 3, TINYGLTF_TARGET_ARRAY_BUFFER, true, "points");
  EXPECT_TRUE(writer.error().empty());
  ASSERT_EQ(model.accessors.size(), 1u);
  EXPECT_EQ(model.accessors[0].count, 2u);
  EXPECT_EQ(model.accessors[0].minValues, (std::vector<double>{-3.0, 1.0, 2.0}));
  EXPECT_EQ(model.accessors[0].maxValues, (std::vector<double>{0.0, 4.5, 5.0}));
  finish(model, writer);
  AccessorReader reader(model);
  ASSERT_TRUE(reader.check().is_ok());
  Result<const std::vector<double>*> values = reader.read(a);
  ASSERT_TRUE(values.is_ok()) << values.status().message();
  EXPECT_EQ(**values, points);
  EXPECT_EQ(*reader.read(a), *values) << "an accessor is read once and kept";
  EXPECT_EQ(reader.summary(a), "accessors[0] is VEC3 of FLOAT");
}

TEST(GltfAccessors, integers_and_views_are_four_byte_aligned) {
  tinygltf::Model model;
  BufferWriter writer(model);
  const std::vector<std::uint8_t> bytes = {1, 2, 3};
  writer.integers(std::span<const std::uint8_t>(bytes), kUnsignedByte, TINYGLTF_TYPE_SCALAR, 3, 0);
  const std::vector<std::uint16_t> shorts = {7, 65534};
  const int s = writer.integers(std::span<const std::uint16_t>(shorts), kUnsignedShort, TINYGLTF_TYPE_SCALAR, 2, 0);
  ASSERT_EQ(model.bufferViews.size(), 2u);
  EXPECT_EQ(model.bufferViews[1].byteOffset, 4u) << "the second view starts after padding to 4 bytes";
  finish(model, writer);
  AccessorReader reader(model);
  ASSERT_TRUE(reader.check().is_ok());
  EXPECT_EQ(**reader.read(s), (std::vector<double>{7.0, 65534.0}));
}

TEST(GltfAccessors, writer__keeps_the_first_non_finite_float_and_shares_equal_times) {
  tinygltf::Model model;
  BufferWriter writer(model);
  const double inf = std::numeric_limits<double>::infinity();
  writer.floats(std::vector<double>{1.0, 1e300}, TINYGLTF_TYPE_SCALAR, 1, 0, false, "hips translation");
  writer.floats(std::vector<double>{inf}, TINYGLTF_TYPE_SCALAR, 1, 0, false, "later");
  EXPECT_EQ(writer.error(), "hips translation: value 1e+300 is not a finite 32-bit float")
      << "the first value out of float range is named with what was written";
  const int t0 = writer.shared_times(std::vector<double>{0.0, 0.5}, "times");
  const int t1 = writer.shared_times(std::vector<double>{0.0, 0.5}, "other times");
  EXPECT_EQ(t0, t1) << "equal times are one accessor";
  EXPECT_NE(writer.shared_times(std::vector<double>{0.0, 1.0}, "times"), t0);
}

TEST(GltfAccessors, reader__refuses_accessors_outside_their_view_and_non_finite_values) {
  tinygltf::Model model;
  BufferWriter writer(model);
  writer.floats(std::vector<double>{1.0, 2.0}, TINYGLTF_TYPE_SCALAR, 1, 0, false, "a");
  finish(model, writer);
  model.accessors[0].count = 3;
  {
    AccessorReader reader(model);
    const Status s = reader.check();
    EXPECT_EQ(s.message(), "accessors[0]: 3 elements need 12 bytes of bufferViews[0], which has 8");
  }
  model.accessors[0].count = 2;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(model.buffers[0].data.data() + 4, &nan, sizeof nan);
  AccessorReader reader(model);
  ASSERT_TRUE(reader.check().is_ok());
  Result<const std::vector<double>*> values = reader.read(0);
  ASSERT_FALSE(values.is_ok());
  EXPECT_EQ(values.status().message(), "accessors[0]: NaN in element 1");
}

TEST(GltfAccessors, reader__applies_sparse_values_and_refuses_indices_not_increasing) {
  tinygltf::Model model;
  BufferWriter writer(model);
  writer.floats(std::vector<double>{0.0, 0.0, 0.0}, TINYGLTF_TYPE_SCALAR, 1, 0, false, "base");
  const std::vector<std::uint8_t> indices = {2, 0};
  const int i = writer.integers(std::span<const std::uint8_t>(indices), kUnsignedByte, TINYGLTF_TYPE_SCALAR, 2, 0);
  const int v = writer.floats(std::vector<double>{5.0, 6.0}, TINYGLTF_TYPE_SCALAR, 1, 0, false, "values");
  finish(model, writer);
  tinygltf::Accessor& a = model.accessors[0];
  a.sparse.isSparse = true;
  a.sparse.count = 1;
  a.sparse.indices.bufferView = model.accessors[static_cast<std::size_t>(i)].bufferView;
  a.sparse.indices.byteOffset = 0;
  a.sparse.indices.componentType = kUnsignedByte;
  a.sparse.values.bufferView = model.accessors[static_cast<std::size_t>(v)].bufferView;
  a.sparse.values.byteOffset = 0;
  {
    AccessorReader reader(model);
    ASSERT_TRUE(reader.check().is_ok());
    EXPECT_EQ(**reader.read(0), (std::vector<double>{0.0, 0.0, 5.0})) << "sparse index 2 takes value 5";
  }
  a.sparse.count = 2;
  AccessorReader reader(model);
  ASSERT_TRUE(reader.check().is_ok());
  Result<const std::vector<double>*> values = reader.read(0);
  ASSERT_FALSE(values.is_ok());
  EXPECT_EQ(values.status().message(), "accessors[0].sparse.indices: not increasing at 1");
}

TEST(GltfNames, node_name__replaces_what_a_name_cannot_hold_and_falls_back) {
  EXPECT_EQ(node_name("left arm[1]", "node_0"), "left_arm_1_");
  EXPECT_EQ(node_name("", "node_3"), "node_3");
  EXPECT_EQ(node_name("\xff\xfe", "node_4"), "node_4") << "text that is not UTF-8 takes the fallback";
  std::string long_name(999, 'a');
  long_name.append("\xc3\xa9" "b");  // 'é' across the 1000-byte cut
  EXPECT_EQ(node_name(long_name, "x"), std::string(999, 'a')) << "long names are cut at a UTF-8 boundary";
  EXPECT_STREQ(path_name(Path::kRotation), "rotation");
  EXPECT_STREQ(path_name(Path::kWeights), "weights");
}

}  // namespace
}  // namespace rigel::io::gltf
