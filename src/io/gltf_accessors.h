// Private to rigel_io: what the glTF importer, the exporter and the look code
// (gltf_materials.h) share. The accessor layout of glTF 2.0 §3.6 (component
// types, element sizes, matrix column padding), reading an accessor into
// doubles with every offset checked against the loaded buffers, writing
// accessors into one buffer, and the names both directions give (animated
// paths, node names).
#pragma once

#include <tiny_gltf.h>

#include <cstdint>
#include <cstring>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "rigel/base/status.h"

namespace rigel::io::gltf {

// ---- layout ------------------------------------------------------------------

constexpr int kByte = TINYGLTF_COMPONENT_TYPE_BYTE;
constexpr int kUnsignedByte = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
constexpr int kShort = TINYGLTF_COMPONENT_TYPE_SHORT;
constexpr int kUnsignedShort = TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
constexpr int kUnsignedInt = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
constexpr int kFloat = TINYGLTF_COMPONENT_TYPE_FLOAT;

// "UNSIGNED_SHORT", "VEC3"; "?" for a number glTF does not define.
const char* component_name(int component_type);
const char* type_name(int type);

// Components per element of an accessor type (MAT4: 16); 0 when unknown.
int component_count(int type);
// Bytes per component; 0 for a number that is not a component type.
std::size_t component_size(int component_type);
// Bytes per element, matrix columns padded to 4 bytes.
std::size_t element_size(int type, int component_type);
// Where component k (column-major for matrices) starts within an element.
std::size_t component_offset(int type, std::size_t size, int k);

// A little-endian value from unaligned bytes.
template <typename T>
T load(const unsigned char* p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

// One component as a double; normalized integers map to [0, 1] or [-1, 1]
// (glTF 2.0 §3.11: max(c / 127, -1) and so on).
double read_component(const unsigned char* p, int component_type, bool normalized);

// ---- reading -------------------------------------------------------------------

// The accessors of a model tinygltf loaded (after the JSON checks: indices
// in range, component types known), read once each.
class AccessorReader {
 public:
  explicit AccessorReader(const tinygltf::Model& model) : m_(model), cache_(model.accessors.size()) {}

  // Every buffer view inside its buffer, every accessor (and its sparse
  // indices and values) inside its buffer view; accessors without a view
  // have a bounded count.
  Status check() const;

  // Every component of accessor `index` as doubles (count x components),
  // normalized integers mapped to [-1, 1] / [0, 1], sparse substitution
  // applied; fails on NaN or infinite floats and bad sparse indices. The
  // values live as long as the reader.
  Result<const std::vector<double>*> read(int index);

  // "accessors[4] is VEC3 of FLOAT (normalized)", for messages.
  std::string summary(int index) const;

 private:
  const tinygltf::Model& m_;
  std::vector<std::optional<std::vector<double>>> cache_;
};

// ---- writing -------------------------------------------------------------------

// Appends `size` bytes to `bytes` (buffer 0) at a 4-byte boundary as a new
// buffer view of `target` (0: none); returns its index.
int append_view(tinygltf::Model& model, std::vector<unsigned char>& bytes, const void* data, std::size_t size, int target);

// Appends an accessor of `count` elements over the whole of buffer view
// `view`; returns its index.
int append_accessor(tinygltf::Model& model, int view, int component_type, int type, std::size_t count);

// Accessors over one buffer, every view 4-byte aligned. Non-finite floats
// are refused: the first one is kept in error() with what was being written.
class BufferWriter {
 public:
  explicit BufferWriter(tinygltf::Model& model) : model_(model) {}

  std::vector<unsigned char>& bytes() { return bytes_; }
  const std::string& error() const { return error_; }

  // `values` flattened, `components` per element; bounds: write min/max.
  int floats(std::span<const double> values, int type, int components, int target, bool bounds, const std::string& what);

  template <typename T>
  int integers(std::span<const T> values, int component_type, int type, std::size_t count, int target) {
    return append_accessor(model_, append_view(model_, bytes_, values.data(), values.size() * sizeof(T), target),
                           component_type, type, count);
  }

  // Float accessors holding the same numbers are written once (baked
  // channels share their times).
  int shared_times(std::span<const double> times, const std::string& what);

 private:
  tinygltf::Model& model_;
  std::vector<unsigned char> bytes_;
  std::string error_;
  std::map<std::vector<float>, int> shared_;
};

// ---- names -----------------------------------------------------------------------

// What an animation channel targets (glTF's target.path).
enum class Path : std::uint8_t { kTranslation, kRotation, kScale, kWeights };

// "translation", "rotation", "scale", "weights".
const char* path_name(Path path);

// A name the graph accepts: whitespace, control characters and brackets
// become '_'; empty names take `fallback`; long names are cut (at a UTF-8
// boundary) so a numeric suffix still fits.
std::string node_name(const std::string& raw, const std::string& fallback);

}  // namespace rigel::io::gltf
