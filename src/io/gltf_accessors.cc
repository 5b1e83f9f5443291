#include "gltf_accessors.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "rigel/graph/graph.h"

#include "gltf_messages.h"

namespace rigel::io::gltf {
namespace {

// An accessor without a buffer view is all zeros: nothing in the file bounds
// its count, so the importer does.
constexpr std::uint64_t kMaxZeroAccessorCount = std::uint64_t{1} << 24;

// Matrix columns start on 4-byte boundaries (glTF 2.0 §3.6.2.4: a MAT2 of
// bytes takes 8 bytes, a MAT3 of bytes 12, a MAT3 of shorts 24).
int matrix_rows(int type) {
  return type == TINYGLTF_TYPE_MAT2 ? 2 : type == TINYGLTF_TYPE_MAT3 ? 3 : type == TINYGLTF_TYPE_MAT4 ? 4 : 0;
}

std::size_t column_stride(int type, std::size_t size) { return (static_cast<std::size_t>(matrix_rows(type)) * size + 3) / 4 * 4; }

}  // namespace

// ---- layout ------------------------------------------------------------------

const char* component_name(int type) {
  switch (type) {
    case kByte: return "BYTE";
    case kUnsignedByte: return "UNSIGNED_BYTE";
    case kShort: return "SHORT";
    case kUnsignedShort: return "UNSIGNED_SHORT";
    case kUnsignedInt: return "UNSIGNED_INT";
    case kFloat: return "FLOAT";
    default: return "?";
  }
}

const char* type_name(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return "SCALAR";
    case TINYGLTF_TYPE_VEC2: return "VEC2";
    case TINYGLTF_TYPE_VEC3: return "VEC3";
    case TINYGLTF_TYPE_VEC4: return "VEC4";
    case TINYGLTF_TYPE_MAT2: return "MAT2";
    case TINYGLTF_TYPE_MAT3: return "MAT3";
    case TINYGLTF_TYPE_MAT4: return "MAT4";
    default: return "?";
  }
}

int component_count(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return 1;
    case TINYGLTF_TYPE_VEC2: return 2;
    case TINYGLTF_TYPE_VEC3: return 3;
    case TINYGLTF_TYPE_VEC4: return 4;
    case TINYGLTF_TYPE_MAT2: return 4;
    case TINYGLTF_TYPE_MAT3: return 9;
    case TINYGLTF_TYPE_MAT4: return 16;
    default: return 0;
  }
}

std::size_t component_size(int component_type) {
  switch (component_type) {
    case kByte:
    case kUnsignedByte: return 1;
    case kShort:
    case kUnsignedShort: return 2;
    case kUnsignedInt:
    case kFloat: return 4;
    default: return 0;
  }
}

std::size_t element_size(int type, int component_type) {
  const std::size_t size = component_size(component_type);
  if (const int rows = matrix_rows(type)) return static_cast<std::size_t>(rows) * column_stride(type, size);
  return static_cast<std::size_t>(component_count(type)) * size;
}

std::size_t component_offset(int type, std::size_t size, int k) {
  if (const int rows = matrix_rows(type)) return static_cast<std::size_t>(k / rows) * column_stride(type, size) + static_cast<std::size_t>(k % rows) * size;
  return static_cast<std::size_t>(k) * size;
}

double read_component(const unsigned char* p, int component_type, bool normalized) {
  switch (component_type) {
    case kByte: {
      const double c = load<std::int8_t>(p);
      return normalized ? std::max(c / 127.0, -1.0) : c;
    }
    case kUnsignedByte: {
      const double c = load<std::uint8_t>(p);
      return normalized ? c / 255.0 : c;
    }
    case kShort: {
      const double c = load<std::int16_t>(p);
      return normalized ? std::max(c / 32767.0, -1.0) : c;
    }
    case kUnsignedShort: {
      const double c = load<std::uint16_t>(p);
      return normalized ? c / 65535.0 : c;
    }
    case kUnsignedInt: return load<std::uint32_t>(p);
    default: return load<float>(p);
  }
}

// ---- reading -------------------------------------------------------------------

Status AccessorReader::check() const {
  for (std::size_t i = 0; i < m_.bufferViews.size(); ++i) {
    const tinygltf::BufferView& v = m_.bufferViews[i];
    const std::size_t size = m_.buffers[static_cast<std::size_t>(v.buffer)].data.size();
    if (std::uint64_t{v.byteOffset} + v.byteLength > size)
      return bad(at("bufferViews", i), "bytes " + std::to_string(v.byteOffset) + ".." + std::to_string(v.byteOffset + v.byteLength) +
                                           " reach past the end of buffer " + std::to_string(v.buffer) + " (" +
                                           std::to_string(size) + " bytes)");
  }
  for (std::size_t i = 0; i < m_.accessors.size(); ++i) {
    const tinygltf::Accessor& a = m_.accessors[i];
    const std::string path = at("accessors", i);
    const std::uint64_t count = a.count;
    const std::uint64_t size = element_size(a.type, a.componentType);
    if (a.bufferView >= 0) {
      const tinygltf::BufferView& v = m_.bufferViews[static_cast<std::size_t>(a.bufferView)];
      if (v.byteStride != 0 && v.byteStride < size)
        return bad(path, "its elements (" + std::to_string(size) + " bytes) are larger than bufferViews[" +
                             std::to_string(a.bufferView) + "].byteStride " + std::to_string(v.byteStride));
      const std::uint64_t stride = v.byteStride != 0 ? v.byteStride : size;
      const std::uint64_t end = std::uint64_t{a.byteOffset} + stride * (count - 1) + size;
      if (end > v.byteLength)
        return bad(path, std::to_string(count) + " elements need " + std::to_string(end) + " bytes of bufferViews[" +
                             std::to_string(a.bufferView) + "], which has " + std::to_string(v.byteLength));
    } else if (count > kMaxZeroAccessorCount) {
      return bad(path, std::to_string(count) + " elements without a bufferView (at most " +
                           std::to_string(kMaxZeroAccessorCount) + ")");
    }
    if (a.sparse.isSparse) {
      const std::string sp = dot(path, "sparse");
      const std::uint64_t n = static_cast<std::uint64_t>(a.sparse.count);
      const tinygltf::BufferView& iv = m_.bufferViews[static_cast<std::size_t>(a.sparse.indices.bufferView)];
      const std::uint64_t iend = static_cast<std::uint64_t>(a.sparse.indices.byteOffset) + n * component_size(a.sparse.indices.componentType);
      if (iend > iv.byteLength)
        return bad(dot(sp, "indices"), std::to_string(n) + " indices need " + std::to_string(iend) + " bytes of bufferViews[" +
                                           std::to_string(a.sparse.indices.bufferView) + "], which has " + std::to_string(iv.byteLength));
      const tinygltf::BufferView& vv = m_.bufferViews[static_cast<std::size_t>(a.sparse.values.bufferView)];
      const std::uint64_t vend = static_cast<std::uint64_t>(a.sparse.values.byteOffset) + n * size;
      if (vend > vv.byteLength)
        return bad(dot(sp, "values"), std::to_string(n) + " values need " + std::to_string(vend) + " bytes of bufferViews[" +
                                          std::to_string(a.sparse.values.bufferView) + "], which has " + std::to_string(vv.byteLength));
    }
  }
  return Status::ok();
}

Result<const std::vector<double>*> AccessorReader::read(int index) {
  const auto i = static_cast<std::size_t>(index);
  if (cache_[i]) return &*cache_[i];
  const tinygltf::Accessor& a = m_.accessors[i];
  const std::string path = at("accessors", i);
  const int n = component_count(a.type);
  const std::size_t csize = component_size(a.componentType);
  const std::size_t esize = element_size(a.type, a.componentType);
  std::vector<double> out(a.count * static_cast<std::size_t>(n), 0.0);
  auto read_element = [&](const unsigned char* p, std::size_t element) -> Status {
    for (int k = 0; k < n; ++k) {
      const double v = read_component(p + component_offset(a.type, csize, k), a.componentType, a.normalized);
      if (!std::isfinite(v)) return bad(path, std::string(std::isnan(v) ? "NaN" : "an infinite value") + " in element " + std::to_string(element));
      out[element * static_cast<std::size_t>(n) + static_cast<std::size_t>(k)] = v;
    }
    return Status::ok();
  };
  if (a.bufferView >= 0) {
    const tinygltf::BufferView& v = m_.bufferViews[static_cast<std::size_t>(a.bufferView)];
    const unsigned char* base = m_.buffers[static_cast<std::size_t>(v.buffer)].data.data() + v.byteOffset + a.byteOffset;
    const std::size_t stride = v.byteStride != 0 ? v.byteStride : esize;
    for (std::size_t e = 0; e < a.count; ++e) {
      if (Status s = read_element(base + e * stride, e); !s) return s;
    }
  }
  if (a.sparse.isSparse) {
    const auto& sp = a.sparse;
    const tinygltf::BufferView& iv = m_.bufferViews[static_cast<std::size_t>(sp.indices.bufferView)];
    const tinygltf::BufferView& vv = m_.bufferViews[static_cast<std::size_t>(sp.values.bufferView)];
    const unsigned char* ibase = m_.buffers[static_cast<std::size_t>(iv.buffer)].data.data() + iv.byteOffset +
                                 static_cast<std::size_t>(sp.indices.byteOffset);
    const unsigned char* vbase = m_.buffers[static_cast<std::size_t>(vv.buffer)].data.data() + vv.byteOffset +
                                 static_cast<std::size_t>(sp.values.byteOffset);
    const std::size_t isize = component_size(sp.indices.componentType);
    double previous = -1.0;
    for (std::size_t k = 0; k < static_cast<std::size_t>(sp.count); ++k) {
      const double target = read_component(ibase + k * isize, sp.indices.componentType, false);
      if (target <= previous)
        return bad(dot(dot(path, "sparse"), "indices"), "not increasing at " + std::to_string(k));
      if (target >= static_cast<double>(a.count))
        return bad(dot(dot(path, "sparse"), "indices"), "the index at " + std::to_string(k) + " is not below the count " +
                                                            std::to_string(a.count));
      previous = target;
      if (Status s = read_element(vbase + k * esize, static_cast<std::size_t>(target)); !s) return s.with_context("sparse value " + std::to_string(k));
    }
  }
  cache_[i] = std::move(out);
  return &*cache_[i];
}

std::string AccessorReader::summary(int index) const {
  const tinygltf::Accessor& a = m_.accessors[static_cast<std::size_t>(index)];
  return "accessors[" + std::to_string(index) + "] is " + type_name(a.type) + " of " + component_name(a.componentType) +
         (a.normalized ? " (normalized)" : "");
}

// ---- writing -------------------------------------------------------------------

int append_view(tinygltf::Model& model, std::vector<unsigned char>& bytes, const void* data, std::size_t size, int target) {
  while (bytes.size() % 4 != 0) bytes.push_back(0);
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = bytes.size();
  view.byteLength = size;
  view.target = target;
  const auto* begin = static_cast<const unsigned char*>(data);
  bytes.insert(bytes.end(), begin, begin + size);
  model.bufferViews.push_back(std::move(view));
  return static_cast<int>(model.bufferViews.size()) - 1;
}

int append_accessor(tinygltf::Model& model, int view, int component_type, int type, std::size_t count) {
  tinygltf::Accessor accessor;
  accessor.bufferView = view;
  accessor.componentType = component_type;
  accessor.count = count;
  accessor.type = type;
  model.accessors.push_back(std::move(accessor));
  return static_cast<int>(model.accessors.size()) - 1;
}

int BufferWriter::floats(std::span<const double> values, int type, int components, int target, bool bounds,
                         const std::string& what) {
  std::vector<float> data(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) {
    data[i] = static_cast<float>(values[i]);
    if (!std::isfinite(data[i]) && error_.empty())
      error_ = what + ": value " + number(values[i], 10) + " is not a finite 32-bit float";
  }
  const std::size_t count = components ? values.size() / static_cast<std::size_t>(components) : 0;
  const int index = append_accessor(model_, append_view(model_, bytes_, data.data(), data.size() * sizeof(float), target),
                                    kFloat, type, count);
  if (bounds && count > 0) {
    tinygltf::Accessor& accessor = model_.accessors.back();
    accessor.minValues.assign(static_cast<std::size_t>(components), std::numeric_limits<double>::infinity());
    accessor.maxValues.assign(static_cast<std::size_t>(components), -std::numeric_limits<double>::infinity());
    for (std::size_t i = 0; i < data.size(); ++i) {
      const std::size_t c = i % static_cast<std::size_t>(components);
      accessor.minValues[c] = std::min(accessor.minValues[c], static_cast<double>(data[i]));
      accessor.maxValues[c] = std::max(accessor.maxValues[c], static_cast<double>(data[i]));
    }
  }
  return index;
}

int BufferWriter::shared_times(std::span<const double> times, const std::string& what) {
  std::vector<float> key(times.begin(), times.end());
  if (auto it = shared_.find(key); it != shared_.end()) return it->second;
  const int index = floats(times, TINYGLTF_TYPE_SCALAR, 1, 0, true, what);
  shared_.emplace(std::move(key), index);
  return index;
}

// ---- names -----------------------------------------------------------------------

const char* path_name(Path path) {
  switch (path) {
    case Path::kTranslation: return "translation";
    case Path::kRotation: return "rotation";
    case Path::kScale: return "scale";
    case Path::kWeights: return "weights";
  }
  return "";
}

std::string node_name(const std::string& raw, const std::string& fallback) {
  if (raw.empty()) return fallback;
  std::string name = raw;
  for (char& c : name) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x21 || u == 0x7f || c == '[' || c == ']') c = '_';
  }
  constexpr std::size_t kLimit = 1000;
  if (name.size() > kLimit) {
    std::size_t cut = kLimit;
    while (cut > 0 && (static_cast<unsigned char>(name[cut]) & 0xC0) == 0x80) --cut;
    name.resize(cut);
  }
  return graph::Graph::is_valid_name(name) ? name : fallback;
}

}  // namespace rigel::io::gltf
