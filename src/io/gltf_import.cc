#include "rigel/io/gltf_import.h"

// tinygltf's implementation lives in Debian's shared library; this file only
// declares against it (no TINYGLTF_IMPLEMENTATION).
#include <tiny_gltf.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "rigel/math/transform.h"
#include "rigel/ops/anim/clips.h"
#include "rigel/ops/anim/curve.h"
#include "rigel/ops/anim/nodes.h"
#include "rigel/ops/anim/track.h"
#include "rigel/ops/deform/nodes.h"
#include "rigel/ops/deform/skin.h"
#include "rigel/ops/registry.h"
#include "rigel/scene/transform_types.h"

#include "gltf_materials.h"
#include "gltf_uri.h"

namespace rigel::io {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;
using graph::Graph;
using graph::NodeId;
using graph::Plug;
using math::Mat4;
using math::Quat;
using math::Vec3;

static_assert(std::endian::native == std::endian::little, "glTF buffers are little-endian; so is every target rigel builds for");

// ---- limits and constants --------------------------------------------------------

constexpr int kMaxJsonDepth = 128;
// An accessor without a buffer view is all zeros: nothing in the file bounds
// its count, so the importer does.
constexpr std::uint64_t kMaxZeroAccessorCount = std::uint64_t{1} << 24;
// Offsets, lengths and counts: a .glb cannot exceed 4 GiB, nor can a buffer.
constexpr std::uint64_t kMaxSize = 0xffffffffull;
constexpr std::uint64_t kMaxInt = 0x7fffffffull;
// Bound on JSON text handed to tinygltf (its length parameter is unsigned int).
constexpr std::uint64_t kMaxFileSize = 0xffffffffull;

constexpr int kByte = TINYGLTF_COMPONENT_TYPE_BYTE;
constexpr int kUnsignedByte = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
constexpr int kShort = TINYGLTF_COMPONENT_TYPE_SHORT;
constexpr int kUnsignedShort = TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
constexpr int kUnsignedInt = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
constexpr int kFloat = TINYGLTF_COMPONENT_TYPE_FLOAT;

constexpr std::uint32_t kGlbMagic = 0x46546C67;  // "glTF"
constexpr std::uint32_t kChunkJson = 0x4E4F534A;
constexpr std::uint32_t kChunkBin = 0x004E4942;

// Interpolation of a glTF sampler, and what an animated channel targets.
enum class Path { kTranslation = 0, kRotation = 1, kScale = 2, kWeights = 3 };
constexpr const char* kPathNames[] = {"translation", "rotation", "scale", "weights"};

// ---- messages --------------------------------------------------------------------

Status bad(const std::string& where, const std::string& what) {
  return error(ErrorCode::kParseError, where.empty() ? what : where + ": " + what);
}

std::string at(const std::string& path, std::size_t index) { return path + "[" + std::to_string(index) + "]"; }
std::string dot(const std::string& path, std::string_view key) {
  return path.empty() ? std::string(key) : path + "." + std::string(key);
}

std::string quote_text(std::string_view text, std::size_t limit = 60) {
  std::string out = "'";
  out += text.size() > limit ? std::string(text.substr(0, limit)) + "..." : std::string(text);
  return out + "'";
}

// A short description of a JSON value for "must be ..., not ..." messages.
std::string describe(const Json& v) {
  std::string kind;
  switch (v.type()) {
    case Json::value_t::null: return "null";
    case Json::value_t::boolean: kind = "a boolean"; break;
    case Json::value_t::string: kind = "a string"; break;
    case Json::value_t::array: return "an array of " + std::to_string(v.size());
    case Json::value_t::object: return "an object";
    case Json::value_t::number_float: kind = "a number"; break;
    default: kind = "an integer"; break;
  }
  std::string text = v.dump();
  if (text.size() > 40) text = text.substr(0, 40) + "...";
  return kind + " " + text;
}

std::string number(double v) {
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%.9g", v);
  return buffer;
}

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

// ---- accessor layout ---------------------------------------------------------------

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

// Matrix columns start on 4-byte boundaries (glTF 2.0 §3.6.2.4: a MAT2 of
// bytes takes 8 bytes, a MAT3 of bytes 12, a MAT3 of shorts 24).
int matrix_rows(int type) {
  return type == TINYGLTF_TYPE_MAT2 ? 2 : type == TINYGLTF_TYPE_MAT3 ? 3 : type == TINYGLTF_TYPE_MAT4 ? 4 : 0;
}

std::size_t column_stride(int type, std::size_t size) { return (static_cast<std::size_t>(matrix_rows(type)) * size + 3) / 4 * 4; }

std::size_t element_size(int type, int component_type) {
  const std::size_t size = component_size(component_type);
  if (const int rows = matrix_rows(type)) return static_cast<std::size_t>(rows) * column_stride(type, size);
  return static_cast<std::size_t>(component_count(type)) * size;
}

std::size_t component_offset(int type, std::size_t size, int k) {
  if (const int rows = matrix_rows(type)) return static_cast<std::size_t>(k / rows) * column_stride(type, size) + static_cast<std::size_t>(k % rows) * size;
  return static_cast<std::size_t>(k) * size;
}

template <typename T>
T load(const unsigned char* p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

// One component as a double; normalized integers map to [0, 1] or [-1, 1]
// (glTF 2.0 §3.11: max(c / 127, -1) and so on).
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

// ---- the file: reading, the .glb container -----------------------------------------

struct Source {
  std::vector<unsigned char> bytes;  // the whole file
  bool binary = false;
  std::string_view json;             // the JSON text (a .glb's first chunk)
  bool has_bin = false;              // a .glb with a BIN chunk
  std::size_t bin_offset = 0;        // where the BIN chunk's 8-byte header starts
  std::uint64_t bin_length = 0;      // the BIN chunk's data length
};

std::uint32_t u32(const std::vector<unsigned char>& bytes, std::size_t at) { return load<std::uint32_t>(bytes.data() + at); }

Status read_file(const fs::path& path, std::vector<unsigned char>& out) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (ec || !fs::exists(status)) return error(ErrorCode::kNotFound, "file not found");
  if (!fs::is_regular_file(status)) return error(ErrorCode::kIoError, "not a regular file");
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) return error(ErrorCode::kIoError, "cannot read the file size: " + ec.message());
  if (size > kMaxFileSize) return error(ErrorCode::kUnsupported, "the file is larger than 4 GiB");
  std::ifstream in(path, std::ios::binary);
  if (!in) return error(ErrorCode::kIoError, "cannot open the file");
  out.resize(static_cast<std::size_t>(size));
  if (size > 0 && !in.read(reinterpret_cast<char*>(out.data()), static_cast<std::streamsize>(size)))
    return error(ErrorCode::kIoError, "cannot read the file");
  return Status::ok();
}

// Checks the .glb header and chunks against the file's real size (tinygltf
// 2.7 does not count the BIN chunk's own header, so it is checked here
// first), or finds the JSON text of a .gltf.
Status parse_container(Source& s) {
  const std::vector<unsigned char>& b = s.bytes;
  if (b.size() >= 4 && u32(b, 0) == kGlbMagic) {
    s.binary = true;
    if (b.size() < 12) return bad("", "truncated .glb: " + std::to_string(b.size()) + " bytes, the header alone takes 12");
    const std::uint32_t version = u32(b, 4), length = u32(b, 8);
    if (version != 2) return error(ErrorCode::kUnsupported, ".glb version " + std::to_string(version) + " (rigel reads version 2)");
    if (length > b.size())
      return bad("", "truncated .glb: the header says " + std::to_string(length) + " bytes, the file has " + std::to_string(b.size()));
    if (length < 20) return bad("", "truncated .glb: no room for the JSON chunk (length " + std::to_string(length) + ")");
    const std::uint32_t json_length = u32(b, 12), json_type = u32(b, 16);
    if (json_type != kChunkJson) return bad("", "the first .glb chunk is not JSON");
    const std::uint64_t json_end = 20ull + json_length;
    if (json_end > length)
      return bad("", "truncated .glb: the JSON chunk says " + std::to_string(json_length) + " bytes, " +
                         std::to_string(length - 20) + " are left");
    s.json = std::string_view(reinterpret_cast<const char*>(b.data()) + 20, json_length);
    // The chunk is padded with spaces; some writers pad with NULs, which no
    // JSON parser accepts.
    while (!s.json.empty() && s.json.back() == '\0') s.json.remove_suffix(1);
    if (json_end < length) {
      if (length - json_end < 8) return bad("", "truncated .glb: " + std::to_string(length - json_end) + " stray bytes after the JSON chunk");
      const std::uint32_t bin_length = u32(b, json_end), bin_type = u32(b, json_end + 4);
      if (bin_type != kChunkBin) return bad("", "the second .glb chunk is not BIN");
      if (json_end + 8 + bin_length > length)
        return bad("", "truncated .glb: the BIN chunk says " + std::to_string(bin_length) + " bytes, " +
                           std::to_string(length - json_end - 8) + " are left");
      s.has_bin = true;
      s.bin_offset = static_cast<std::size_t>(json_end);
      s.bin_length = bin_length;
    }
    return Status::ok();
  }
  std::size_t i = 0;
  if (b.size() >= 3 && b[0] == 0xEF && b[1] == 0xBB && b[2] == 0xBF) i = 3;  // a byte-order mark
  while (i < b.size() && (b[i] == ' ' || b[i] == '\t' || b[i] == '\r' || b[i] == '\n')) ++i;
  if (i == b.size() || b[i] != '{') return bad("", "not glTF: neither a .glb (no 'glTF' magic) nor a JSON object");
  s.json = std::string_view(reinterpret_cast<const char*>(b.data()), b.size());
  return Status::ok();
}

// Nesting depth, counted without parsing: deep JSON would make recursive
// readers (tinygltf's extras) overflow the stack.
Status check_json_depth(std::string_view text) {
  int depth = 0;
  bool in_string = false, escaped = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (escaped) escaped = false;
      else if (c == '\\') escaped = true;
      else if (c == '"') in_string = false;
      continue;
    }
    if (c == '"') in_string = true;
    else if (c == '[' || c == '{') {
      if (++depth > kMaxJsonDepth)
        return bad("", "JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels (at byte " + std::to_string(i) + ")");
    } else if (c == ']' || c == '}') --depth;
  }
  return Status::ok();
}

Result<Json> parse_json(std::string_view text) {
  if (Status s = check_json_depth(text); !s) return s;
  try {
    return Json::parse(text.begin(), text.end());
  } catch (const Json::parse_error& e) {
    std::string what = e.what();
    if (const std::size_t cut = what.find("] "); cut != std::string::npos) what = what.substr(cut + 2);
    return bad("", "JSON syntax error: " + what);
  } catch (const std::exception& e) {
    return bad("", std::string("JSON error: ") + e.what());
  }
}

// ---- the JSON, checked before tinygltf reads it -------------------------------------
//
// tinygltf skips members of the wrong type silently (a "skin": "x" would
// make a skinned mesh static) and keeps indices unchecked, so every member
// the importer relies on is checked here, with its path.

const Json* member(const Json& object, const char* key) {
  auto it = object.find(key);
  return it == object.end() ? nullptr : &*it;
}

std::size_t array_count(const Json& doc, const char* key) {
  const Json* v = member(doc, key);
  return v && v->is_array() ? v->size() : 0;
}

Status check_index_value(const Json& v, const std::string& where, std::size_t count, const char* what) {
  if (!v.is_number_integer()) return bad(where, std::string("must be an index (an integer), not ") + describe(v));
  const bool negative = v.is_number_integer() && !v.is_number_unsigned() && v.get<std::int64_t>() < 0;
  if (negative || v.get<std::uint64_t>() >= count)
    return bad(where, std::string(what) + " " + v.dump() + " does not exist (" +
                          (count == 0 ? std::string("there are none") : "there are " + std::to_string(count)) + ")");
  return Status::ok();
}

Status check_index(const Json& o, const char* key, const std::string& path, std::size_t count, const char* what,
                   bool required = false) {
  const Json* v = member(o, key);
  if (!v) return required ? bad(path, std::string("'") + key + "' is missing") : Status::ok();
  return check_index_value(*v, dot(path, key), count, what);
}

Status check_index_array(const Json& o, const char* key, const std::string& path, std::size_t count, const char* what,
                         bool required, bool non_empty) {
  const Json* v = member(o, key);
  const std::string where = dot(path, key);
  if (!v) return required ? bad(path, std::string("'") + key + "' is missing") : Status::ok();
  if (!v->is_array()) return bad(where, "must be an array of indices, not " + describe(*v));
  if (non_empty && v->empty()) return bad(where, "must not be empty");
  for (std::size_t i = 0; i < v->size(); ++i) {
    if (Status s = check_index_value((*v)[i], at(where, i), count, what); !s) return s;
  }
  return Status::ok();
}

Status check_uint(const Json& o, const char* key, const std::string& path, bool required, std::uint64_t min,
                  std::uint64_t max) {
  const Json* v = member(o, key);
  if (!v) return required ? bad(path, std::string("'") + key + "' is missing") : Status::ok();
  const std::string where = dot(path, key);
  if (!v->is_number_integer() || (!v->is_number_unsigned() && v->get<std::int64_t>() < 0))
    return bad(where, "must be a non-negative integer, not " + describe(*v));
  const std::uint64_t value = v->get<std::uint64_t>();
  if (value < min || value > max)
    return bad(where, std::to_string(value) + " is outside [" + std::to_string(min) + ", " + std::to_string(max) + "]");
  return Status::ok();
}

Status check_numbers(const Json& o, const char* key, const std::string& path, std::size_t exact) {
  const Json* v = member(o, key);
  if (!v) return Status::ok();
  const std::string where = dot(path, key);
  if (!v->is_array()) return bad(where, "must be an array of numbers, not " + describe(*v));
  if (exact != 0 && v->size() != exact)
    return bad(where, "must have " + std::to_string(exact) + " numbers, not " + std::to_string(v->size()));
  for (std::size_t i = 0; i < v->size(); ++i) {
    const Json& e = (*v)[i];
    if (!e.is_number()) return bad(at(where, i), "must be a number, not " + describe(e));
    if (!std::isfinite(e.get<double>())) return bad(at(where, i), "must be finite");
  }
  return Status::ok();
}

Status check_string(const Json& o, const char* key, const std::string& path, bool required = false) {
  const Json* v = member(o, key);
  if (!v) return required ? bad(path, std::string("'") + key + "' is missing") : Status::ok();
  if (!v->is_string()) return bad(dot(path, key), "must be a string, not " + describe(*v));
  return Status::ok();
}

Status check_bool(const Json& o, const char* key, const std::string& path) {
  const Json* v = member(o, key);
  if (v && !v->is_boolean()) return bad(dot(path, key), "must be true or false, not " + describe(*v));
  return Status::ok();
}

Status check_object(const Json& o, const char* key, const std::string& path, bool required) {
  const Json* v = member(o, key);
  if (!v) return required ? bad(path, std::string("'") + key + "' is missing") : Status::ok();
  if (!v->is_object()) return bad(dot(path, key), "must be an object, not " + describe(*v));
  return Status::ok();
}

// An array of objects: required or not, and (glTF's schema: minItems 1) not empty.
Status check_objects(const Json& o, const char* key, const std::string& path, bool required) {
  const Json* v = member(o, key);
  const std::string where = dot(path, key);
  if (!v) return required ? bad(path, std::string("'") + key + "' is missing") : Status::ok();
  if (!v->is_array()) return bad(where, "must be an array, not " + describe(*v));
  if (v->empty()) return bad(where, "must not be empty");
  for (std::size_t i = 0; i < v->size(); ++i) {
    if (!(*v)[i].is_object()) return bad(at(where, i), "must be an object, not " + describe((*v)[i]));
  }
  return Status::ok();
}

// A member holding {name: accessor index} (primitive attributes, targets).
Status check_attribute_map(const Json& map, const std::string& where, std::size_t accessors) {
  if (!map.is_object()) return bad(where, "must be an object, not " + describe(map));
  for (auto it = map.begin(); it != map.end(); ++it) {
    if (Status s = check_index_value(it.value(), dot(where, it.key()), accessors, "accessor"); !s) return s;
  }
  return Status::ok();
}

bool is_base64_char(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '+' || c == '/';
}

struct SchemaContext {
  const Source* source = nullptr;
  std::string base_dir;                 // the folder of the file, as tinygltf joins paths
  fs::path folder;                      // that folder, absolute, symbolic links resolved
  std::set<std::string> buffer_files;   // external buffer files tinygltf may read
  bool quantized = false;               // KHR_mesh_quantization in extensionsUsed
};

// The file an external URI (a buffer's) names: the rule is gltf_uri's.
Result<std::string> external_file(const SchemaContext& ctx, const std::string& uri, const std::string& where) {
  return gltf_uri::confined_file(ctx.folder, ctx.base_dir, uri, where);
}

Status check_buffers(const Json& doc, SchemaContext& ctx) {
  const Json* buffers = member(doc, "buffers");
  if (!buffers) return Status::ok();
  for (std::size_t i = 0; i < buffers->size(); ++i) {
    const Json& b = (*buffers)[i];
    const std::string path = at("buffers", i);
    if (Status s = check_uint(b, "byteLength", path, true, 1, kMaxSize); !s) return s;
    if (Status s = check_string(b, "uri", path); !s) return s;
    if (Status s = check_string(b, "name", path); !s) return s;
    const std::uint64_t length = b.at("byteLength").get<std::uint64_t>();
    const Json* uri = member(b, "uri");
    if (!uri) {
      if (!ctx.source->binary) return bad(path, "no uri (only the first buffer of a .glb may leave it out)");
      if (i != 0) return bad(path, "no uri (only the first buffer of a .glb is its BIN chunk)");
      if (!ctx.source->has_bin) return bad(path, "no uri, and the .glb has no BIN chunk");
      if (length > ctx.source->bin_length)
        return bad(path, "byteLength " + std::to_string(length) + " is more than the .glb's BIN chunk (" +
                             std::to_string(ctx.source->bin_length) + " bytes)");
      continue;
    }
    const std::string& text = uri->get_ref<const std::string&>();
    if (text.rfind("data:", 0) == 0) {
      std::string payload;
      for (const char* header : {"data:application/octet-stream;base64,", "data:application/gltf-buffer;base64,"}) {
        if (text.rfind(header, 0) == 0) payload = text.substr(std::strlen(header));
      }
      if (payload.empty())
        return bad(dot(path, "uri"), "unsupported data URI " + quote_text(text, 40) +
                                         " (base64 application/octet-stream or application/gltf-buffer expected)");
      std::size_t padding = 0;
      while (!payload.empty() && payload.back() == '=' && padding < 2) {
        payload.pop_back();
        ++padding;
      }
      for (std::size_t k = 0; k < payload.size(); ++k) {
        if (!is_base64_char(payload[k])) return bad(dot(path, "uri"), "not base64 at character " + std::to_string(k));
      }
      if (payload.size() % 4 == 1) return bad(dot(path, "uri"), "base64 data of a length that no bytes have");
      const std::uint64_t decoded = payload.size() / 4 * 3 + (payload.size() % 4 == 0 ? 0 : payload.size() % 4 - 1);
      if (decoded != length)
        return bad(path, "the data URI holds " + std::to_string(decoded) + " bytes, byteLength says " + std::to_string(length));
      continue;
    }
    Result<std::string> external = external_file(ctx, text, path);
    if (!external) return external.status();
    const std::string& file = *external;
    std::error_code ec;
    const std::uintmax_t size = fs::file_size(fs::path(file), ec);
    if (ec || size != length)
      return bad(path, quote_text(text) + " has " + (ec ? std::string("an unknown size") : std::to_string(size) + " bytes") +
                           ", byteLength says " + std::to_string(length));
    ctx.buffer_files.insert(file);
  }
  return Status::ok();
}

Status check_buffer_views(const Json& doc) {
  const Json* views = member(doc, "bufferViews");
  if (!views) return Status::ok();
  const std::size_t buffers = array_count(doc, "buffers");
  for (std::size_t i = 0; i < views->size(); ++i) {
    const Json& v = (*views)[i];
    const std::string path = at("bufferViews", i);
    if (Status s = check_index(v, "buffer", path, buffers, "buffer", true); !s) return s;
    if (Status s = check_uint(v, "byteOffset", path, false, 0, kMaxSize); !s) return s;
    if (Status s = check_uint(v, "byteLength", path, true, 1, kMaxSize); !s) return s;
    if (Status s = check_uint(v, "byteStride", path, false, 4, 252); !s) return s;
    if (const Json* stride = member(v, "byteStride"); stride && stride->get<std::uint64_t>() % 4 != 0)
      return bad(dot(path, "byteStride"), "must be a multiple of 4, not " + stride->dump());
    const std::uint64_t offset = v.value("byteOffset", std::uint64_t{0});
    const std::uint64_t length = v.at("byteLength").get<std::uint64_t>();
    const std::size_t b = v.at("buffer").get<std::size_t>();
    const std::uint64_t buffer_length = doc.at("buffers").at(b).at("byteLength").get<std::uint64_t>();
    if (offset + length > buffer_length)
      return bad(path, "bytes " + std::to_string(offset) + ".." + std::to_string(offset + length) + " reach past the end of buffer " +
                           std::to_string(b) + " (" + std::to_string(buffer_length) + " bytes)");
  }
  return Status::ok();
}

Status check_accessor_json(const Json& doc) {
  const Json* accessors = member(doc, "accessors");
  if (!accessors) return Status::ok();
  const std::size_t views = array_count(doc, "bufferViews");
  static const std::set<std::string> kTypes = {"SCALAR", "VEC2", "VEC3", "VEC4", "MAT2", "MAT3", "MAT4"};
  for (std::size_t i = 0; i < accessors->size(); ++i) {
    const Json& a = (*accessors)[i];
    const std::string path = at("accessors", i);
    if (Status s = check_index(a, "bufferView", path, views, "bufferView"); !s) return s;
    if (Status s = check_uint(a, "byteOffset", path, false, 0, kMaxSize); !s) return s;
    if (member(a, "byteOffset") && !member(a, "bufferView")) return bad(dot(path, "byteOffset"), "given without a bufferView");
    if (Status s = check_uint(a, "componentType", path, true, 0, 0xffff); !s) return s;
    const int component_type = a.at("componentType").get<int>();
    if (component_size(component_type) == 0)
      return bad(dot(path, "componentType"), std::to_string(component_type) + " is not a glTF component type");
    if (Status s = check_bool(a, "normalized", path); !s) return s;
    if (a.value("normalized", false) && (component_type == kFloat || component_type == kUnsignedInt))
      return bad(dot(path, "normalized"), std::string(component_name(component_type)) + " components cannot be normalized");
    if (Status s = check_uint(a, "count", path, true, 1, kMaxSize); !s) return s;
    if (Status s = check_string(a, "type", path, true); !s) return s;
    if (!kTypes.count(a.at("type").get<std::string>()))
      return bad(dot(path, "type"), quote_text(a.at("type").get<std::string>()) + " is not an accessor type");
    if (Status s = check_object(a, "sparse", path, false); !s) return s;
    if (const Json* sparse = member(a, "sparse")) {
      const std::string sp = dot(path, "sparse");
      // tinygltf keeps the sparse numbers in ints.
      if (Status s = check_uint(*sparse, "count", sp, true, 1, std::min<std::uint64_t>(a.at("count").get<std::uint64_t>(), kMaxInt)); !s)
        return s;
      if (Status s = check_object(*sparse, "indices", sp, true); !s) return s;
      if (Status s = check_object(*sparse, "values", sp, true); !s) return s;
      const Json& indices = sparse->at("indices");
      const Json& values = sparse->at("values");
      if (Status s = check_index(indices, "bufferView", dot(sp, "indices"), views, "bufferView", true); !s) return s;
      if (Status s = check_uint(indices, "byteOffset", dot(sp, "indices"), false, 0, kMaxInt); !s) return s;
      if (Status s = check_uint(indices, "componentType", dot(sp, "indices"), true, 0, 0xffff); !s) return s;
      const int index_type = indices.at("componentType").get<int>();
      if (index_type != kUnsignedByte && index_type != kUnsignedShort && index_type != kUnsignedInt)
        return bad(dot(dot(sp, "indices"), "componentType"), std::to_string(index_type) + " is not UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT");
      if (Status s = check_index(values, "bufferView", dot(sp, "values"), views, "bufferView", true); !s) return s;
      if (Status s = check_uint(values, "byteOffset", dot(sp, "values"), false, 0, kMaxInt); !s) return s;
    }
  }
  return Status::ok();
}

Status check_mesh_json(const Json& doc) {
  const Json* meshes = member(doc, "meshes");
  if (!meshes) return Status::ok();
  const std::size_t accessors = array_count(doc, "accessors"), materials = array_count(doc, "materials");
  for (std::size_t m = 0; m < meshes->size(); ++m) {
    const Json& mesh = (*meshes)[m];
    const std::string path = at("meshes", m);
    if (Status s = check_string(mesh, "name", path); !s) return s;
    if (Status s = check_numbers(mesh, "weights", path, 0); !s) return s;
    if (Status s = check_objects(mesh, "primitives", path, true); !s) return s;
    const Json& primitives = mesh.at("primitives");
    for (std::size_t p = 0; p < primitives.size(); ++p) {
      const Json& prim = primitives[p];
      const std::string pp = at(dot(path, "primitives"), p);
      if (Status s = check_object(prim, "attributes", pp, true); !s) return s;
      if (Status s = check_attribute_map(prim.at("attributes"), dot(pp, "attributes"), accessors); !s) return s;
      if (Status s = check_index(prim, "indices", pp, accessors, "accessor"); !s) return s;
      if (Status s = check_index(prim, "material", pp, materials, "material"); !s) return s;
      if (Status s = check_uint(prim, "mode", pp, false, 0, 6); !s) return s;
      if (Status s = check_objects(prim, "targets", pp, false); !s) return s;
      if (const Json* targets = member(prim, "targets")) {
        for (std::size_t t = 0; t < targets->size(); ++t) {
          if (Status s = check_attribute_map((*targets)[t], at(dot(pp, "targets"), t), accessors); !s) return s;
        }
      }
    }
  }
  return Status::ok();
}

Status check_node_json(const Json& doc) {
  const Json* nodes = member(doc, "nodes");
  if (!nodes) return Status::ok();
  const std::size_t count = nodes->size();
  for (std::size_t i = 0; i < count; ++i) {
    const Json& n = (*nodes)[i];
    const std::string path = at("nodes", i);
    if (Status s = check_string(n, "name", path); !s) return s;
    if (Status s = check_index(n, "camera", path, array_count(doc, "cameras"), "camera"); !s) return s;
    if (Status s = check_index(n, "skin", path, array_count(doc, "skins"), "skin"); !s) return s;
    if (Status s = check_index(n, "mesh", path, array_count(doc, "meshes"), "mesh"); !s) return s;
    // An empty `children` is accepted (the schema asks for one at least;
    // exporters write empty ones and they mean nothing).
    if (Status s = check_index_array(n, "children", path, count, "node", false, false); !s) return s;
    if (Status s = check_numbers(n, "matrix", path, 16); !s) return s;
    if (Status s = check_numbers(n, "translation", path, 3); !s) return s;
    if (Status s = check_numbers(n, "rotation", path, 4); !s) return s;
    if (Status s = check_numbers(n, "scale", path, 3); !s) return s;
    if (Status s = check_numbers(n, "weights", path, 0); !s) return s;
    if (member(n, "matrix") && (member(n, "translation") || member(n, "rotation") || member(n, "scale")))
      return bad(path, "has both 'matrix' and translation/rotation/scale");
  }
  return Status::ok();
}

Status check_skin_json(const Json& doc) {
  const Json* skins = member(doc, "skins");
  if (!skins) return Status::ok();
  const std::size_t nodes = array_count(doc, "nodes");
  for (std::size_t i = 0; i < skins->size(); ++i) {
    const Json& skin = (*skins)[i];
    const std::string path = at("skins", i);
    if (Status s = check_string(skin, "name", path); !s) return s;
    if (Status s = check_index_array(skin, "joints", path, nodes, "node", true, true); !s) return s;
    if (Status s = check_index(skin, "inverseBindMatrices", path, array_count(doc, "accessors"), "accessor"); !s) return s;
    if (Status s = check_index(skin, "skeleton", path, nodes, "node"); !s) return s;
  }
  return Status::ok();
}

Status check_animation_json(const Json& doc) {
  const Json* animations = member(doc, "animations");
  if (!animations) return Status::ok();
  const std::size_t accessors = array_count(doc, "accessors"), nodes = array_count(doc, "nodes");
  for (std::size_t a = 0; a < animations->size(); ++a) {
    const Json& anim = (*animations)[a];
    const std::string path = at("animations", a);
    if (Status s = check_string(anim, "name", path); !s) return s;
    if (Status s = check_objects(anim, "samplers", path, true); !s) return s;
    if (Status s = check_objects(anim, "channels", path, true); !s) return s;
    const Json& samplers = anim.at("samplers");
    for (std::size_t k = 0; k < samplers.size(); ++k) {
      const std::string sp = at(dot(path, "samplers"), k);
      if (Status s = check_index(samplers[k], "input", sp, accessors, "accessor", true); !s) return s;
      if (Status s = check_index(samplers[k], "output", sp, accessors, "accessor", true); !s) return s;
      if (Status s = check_string(samplers[k], "interpolation", sp); !s) return s;
      const std::string interpolation = samplers[k].value("interpolation", std::string("LINEAR"));
      if (interpolation != "LINEAR" && interpolation != "STEP" && interpolation != "CUBICSPLINE")
        return bad(dot(sp, "interpolation"), quote_text(interpolation) + " is not LINEAR, STEP or CUBICSPLINE");
    }
    const Json& channels = anim.at("channels");
    for (std::size_t c = 0; c < channels.size(); ++c) {
      const std::string cp = at(dot(path, "channels"), c);
      if (Status s = check_index(channels[c], "sampler", cp, samplers.size(), "sampler", true); !s) return s;
      if (Status s = check_object(channels[c], "target", cp, true); !s) return s;
      const Json& target = channels[c].at("target");
      const std::string tp = dot(cp, "target");
      if (Status s = check_index(target, "node", tp, nodes, "node"); !s) return s;
      if (Status s = check_string(target, "path", tp, true); !s) return s;
      const std::string what = target.at("path").get<std::string>();
      if (member(target, "node") && what != "translation" && what != "rotation" && what != "scale" && what != "weights")
        return bad(dot(tp, "path"), quote_text(what) + " is not translation, rotation, scale or weights");
    }
  }
  return Status::ok();
}

Status check_json(const Json& doc, SchemaContext& ctx) {
  if (!doc.is_object()) return bad("", "the JSON is not an object");
  if (Status s = check_object(doc, "asset", "", true); !s) return s;
  const Json& asset = doc.at("asset");
  if (Status s = check_string(asset, "version", "asset", true); !s) return s;
  const std::string version = asset.at("version").get<std::string>();
  if (version.rfind("2.", 0) != 0)
    return error(ErrorCode::kUnsupported, "asset.version: " + quote_text(version) + " (rigel reads glTF 2.x)");
  if (Status s = check_string(asset, "minVersion", "asset"); !s) return s;
  if (const Json* min = member(asset, "minVersion"); min && min->get<std::string>() != "2.0")
    return error(ErrorCode::kUnsupported, "asset.minVersion: " + quote_text(min->get<std::string>()) + " (rigel reads glTF 2.0)");
  for (const char* key : {"extensionsUsed", "extensionsRequired"}) {
    const Json* list = member(doc, key);
    if (!list) continue;
    if (!list->is_array()) return bad(key, "must be an array of strings, not " + describe(*list));
    for (std::size_t i = 0; i < list->size(); ++i) {
      if (!(*list)[i].is_string()) return bad(at(key, i), "must be a string, not " + describe((*list)[i]));
      const std::string& name = (*list)[i].get_ref<const std::string&>();
      if (std::string_view(key) == "extensionsUsed" && name == "KHR_mesh_quantization") ctx.quantized = true;
      if (std::string_view(key) == "extensionsRequired" &&
          (name == "KHR_draco_mesh_compression" || name == "EXT_meshopt_compression" || name == "KHR_meshopt_compression"))
        return error(ErrorCode::kUnsupported, at(key, i) + ": " + quote_text(name) + " is not supported (compressed geometry)");
    }
  }
  // glTF's top-level arrays: arrays of objects, never empty (schema: minItems 1).
  for (const char* key : {"accessors", "animations", "buffers", "bufferViews", "cameras", "images", "materials", "meshes",
                          "nodes", "samplers", "scenes", "skins", "textures"}) {
    if (Status s = check_objects(doc, key, "", false); !s) return s;
  }
  if (Status s = check_index(doc, "scene", "", array_count(doc, "scenes"), "scene"); !s) return s;
  if (const Json* scenes = member(doc, "scenes")) {
    for (std::size_t i = 0; i < scenes->size(); ++i) {
      if (Status s = check_index_array((*scenes)[i], "nodes", at("scenes", i), array_count(doc, "nodes"), "node", false, false); !s)
        return s;
    }
  }
  if (const Json* images = member(doc, "images")) {  // never decoded, but tinygltf looks at their views
    for (std::size_t i = 0; i < images->size(); ++i) {
      if (Status s = check_index((*images)[i], "bufferView", at("images", i), array_count(doc, "bufferViews"), "bufferView"); !s)
        return s;
    }
  }
  if (Status s = check_buffers(doc, ctx); !s) return s;
  if (Status s = check_buffer_views(doc); !s) return s;
  if (Status s = check_accessor_json(doc); !s) return s;
  if (Status s = check_mesh_json(doc); !s) return s;
  if (Status s = check_node_json(doc); !s) return s;
  if (Status s = check_skin_json(doc); !s) return s;
  return check_animation_json(doc);
}

// ---- tinygltf ------------------------------------------------------------------------

bool fs_file_exists(const std::string& path, void* user) {
  return static_cast<const SchemaContext*>(user)->buffer_files.count(path) > 0;
}
std::string fs_expand(const std::string& path, void*) { return path; }  // no shell expansion, ever
bool fs_read(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
  if (!fs_file_exists(path, user)) {
    if (err) *err = "not a buffer of this file";
    return false;
  }
  // Checked again as it is read: the file must still resolve inside the folder.
  std::error_code ec;
  const fs::path real = fs::canonical(fs::path(path), ec);
  if (ec || !gltf_uri::inside(static_cast<const SchemaContext*>(user)->folder, real)) {
    if (err) *err = "not inside the glTF file's folder";
    return false;
  }
  std::vector<unsigned char> bytes;
  if (Status s = read_file(real, bytes); !s) {
    if (err) *err = s.message();
    return false;
  }
  *out = std::move(bytes);
  return true;
}
bool fs_write(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  if (err) *err = "the importer writes nothing";
  return false;
}
// Images are never decoded: rigel has no use for textures.
bool ignore_image(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int, void*) {
  return true;
}

// tinygltf's messages, joined on one line and kept short.
std::string one_line(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '\n' || c == '\r') {
      if (!out.empty() && out.back() != ' ') out += "; ";
    } else out += c;
  }
  while (!out.empty() && (out.back() == ' ' || out.back() == ';')) out.pop_back();
  if (out.size() > 400) out = out.substr(0, 400) + "...";
  return out;
}

// Hands the checked JSON to tinygltf, without `images` (nothing of them is
// used, and a broken embedded picture should not stop a rig from loading).
Result<tinygltf::Model> load_model(Json doc, const Source& source, SchemaContext& ctx) {
  doc.erase("images");
  // tinygltf requires target.node; a channel aimed elsewhere by an extension
  // gets -1, which the importer skips.
  if (auto animations = doc.find("animations"); animations != doc.end()) {
    for (Json& animation : *animations) {
      for (Json& channel : animation["channels"]) {
        Json& target = channel["target"];
        if (!target.contains("node")) target["node"] = -1;
      }
    }
  }
  const std::string text = doc.dump();
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(&ignore_image, nullptr);
  tinygltf::FsCallbacks callbacks{};
  callbacks.FileExists = &fs_file_exists;
  callbacks.ExpandFilePath = &fs_expand;
  callbacks.ReadWholeFile = &fs_read;
  callbacks.WriteWholeFile = &fs_write;
  callbacks.user_data = &ctx;
  loader.SetFsCallbacks(callbacks);
  tinygltf::Model model;
  std::string err, warn;
  bool ok = false;
  try {
    if (source.binary) {
      // The same container around the new JSON, and the original BIN chunk.
      std::string padded = text;
      while (padded.size() % 4 != 0) padded += ' ';
      std::vector<unsigned char> glb(20 + padded.size());
      auto put = [&](std::size_t offset, std::uint32_t v) { std::memcpy(glb.data() + offset, &v, 4); };
      put(0, kGlbMagic);
      put(4, 2);
      put(12, static_cast<std::uint32_t>(padded.size()));
      put(16, kChunkJson);
      std::memcpy(glb.data() + 20, padded.data(), padded.size());
      if (source.has_bin) {
        const auto* begin = source.bytes.data() + source.bin_offset;
        glb.insert(glb.end(), begin, begin + 8 + static_cast<std::ptrdiff_t>(source.bin_length));
      }
      if (glb.size() > kMaxFileSize) return error(ErrorCode::kUnsupported, "the .glb would exceed 4 GiB");
      put(8, static_cast<std::uint32_t>(glb.size()));
      ok = loader.LoadBinaryFromMemory(&model, &err, &warn, glb.data(), static_cast<unsigned int>(glb.size()), ctx.base_dir);
    } else {
      if (text.size() > kMaxFileSize) return error(ErrorCode::kUnsupported, "the JSON exceeds 4 GiB");
      ok = loader.LoadASCIIFromString(&model, &err, &warn, text.data(), static_cast<unsigned int>(text.size()), ctx.base_dir);
    }
  } catch (const std::exception& e) {
    return bad("", std::string("tinygltf: ") + e.what());
  }
  if (!ok) return bad("", "tinygltf: " + (err.empty() ? std::string("the file could not be read") : one_line(err)));
  return model;
}

// ---- helpers for names and values ----------------------------------------------------

// A name the graph accepts: whitespace, control characters and brackets
// become '_'; empty names take `fallback`; long names are cut (at a UTF-8
// boundary) so a numeric suffix still fits.
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
  return Graph::is_valid_name(name) ? name : fallback;
}

Quat quat_from_xyzw(const double* v) { return Quat(v[3], v[0], v[1], v[2]); }

// A unique string among `taken`: `wanted`, else wanted + 1, 2, ...
std::string unique_among(const std::string& wanted, std::set<std::string>& taken) {
  std::string name = wanted;
  for (int n = 1; taken.count(name); ++n) name = wanted + std::to_string(n);
  taken.insert(name);
  return name;
}

// ---- the importer -----------------------------------------------------------------------

// One animated channel's keys in one clip, flattened: `width` numbers per key
// (3 for translation/scale, 4 for rotation [x, y, z, w], the morph target
// count for weights).
struct ClipKeys {
  ops::anim::Interpolation interpolation = ops::anim::Interpolation::kLinear;
  std::vector<double> times;
  std::vector<double> values;
  std::vector<double> in_tangents;   // cubic only
  std::vector<double> out_tangents;  // cubic only
};

struct Channel {
  int node = 0;
  Path path = Path::kTranslation;
  std::vector<std::optional<ClipKeys>> clips;  // one per glTF animation
};

// A primitive's data, read once per mesh.
struct PrimitiveData {
  bool make_node = false;  // triangles (or strips, fans) with POSITION
  std::size_t vertex_count = 0;
  std::vector<Vec3> points, normals;
  std::vector<std::int64_t> triangles;
  std::vector<std::vector<Vec3>> target_deltas;
  // Skin data of every JOINTS_n/WEIGHTS_n set, interleaved per vertex:
  // vertex v owns [v * per_vertex, (v + 1) * per_vertex).
  std::vector<int> sets;  // the n of each set, ascending
  std::size_t per_vertex = 0;
  std::vector<std::int64_t> joints;
  std::vector<double> weights;
};

// A skinned primitive's influences as the skinCluster takes them; vertices
// without a weight above zero are bound to one extra joint matrix (index =
// the skin's joint count), the world matrix of the glTF node holding the mesh.
struct SkinBinding {
  std::vector<std::int64_t> offsets, joints;
  std::vector<double> weights;
  std::vector<std::size_t> unweighted;
};

struct MeshData {
  std::vector<PrimitiveData> primitives;
  std::size_t target_count = 0;
};

class Importer {
 public:
  Importer(const tinygltf::Model& model, const GltfImportOptions& options, bool quantized)
      : m_(model), options_(options), quantized_(quantized) {}

  Result<std::unique_ptr<scene::Scene>> run();

  // After run(): the mesh nodes made, with their primitives, and the
  // accessor reader, for the materials and uv sets (gltf_materials.h).
  std::span<const gltf_look::MeshSource> mesh_sources() const { return mesh_sources_; }
  Result<const std::vector<double>*> accessor_values(int accessor) { return read(accessor); }

 private:
  // checks and reading
  Status check_accessors();
  Result<const std::vector<double>*> read(int accessor);
  Status check_hierarchy();
  Status check_skins();
  Status check_nodes();
  Status check_finite_world();
  Status check_scenes();
  Status read_meshes();
  Status read_primitive(std::size_t m, std::size_t p, PrimitiveData& out);
  Result<std::vector<SkinBinding>> bind_skin(std::size_t node);
  Status read_animations();
  Status read_channel(std::size_t a, std::size_t c, ClipKeys& out, std::size_t width, Path path);

  // building
  Status build_nodes();
  Status build_meshes();
  Status build_animations();
  Status build_track(const Channel& channel, NodeId clips);
  Status build_weight_curves(const Channel& channel, NodeId clips);

  Status set(NodeId node, graph::AttrIndex attr, graph::Value value);
  Status connect(NodeId src, graph::AttrIndex src_attr, NodeId dst, graph::AttrIndex dst_attr, std::int32_t element = -1);

  std::string accessor_summary(int index) const {
    const tinygltf::Accessor& a = m_.accessors[static_cast<std::size_t>(index)];
    return "accessors[" + std::to_string(index) + "] is " + type_name(a.type) + " of " + component_name(a.componentType) +
           (a.normalized ? " (normalized)" : "");
  }

  const tinygltf::Model& m_;
  GltfImportOptions options_;
  bool quantized_ = false;
  std::unique_ptr<scene::Scene> scene_;

  std::vector<std::optional<std::vector<double>>> cache_;  // accessor values, read once
  std::vector<int> parent_;         // per node, -1 for a root
  std::vector<int> root_;           // per node, the root of its hierarchy
  std::vector<bool> is_joint_;
  std::vector<std::vector<Mat4>> inverse_bind_;  // per skin, one per joint
  std::vector<MeshData> meshes_;
  std::vector<Channel> channels_;   // sorted by (node, path)
  std::vector<std::string> clip_names_;
  std::vector<double> clip_starts_, clip_ends_;

  std::vector<NodeId> ids_;         // per glTF node
  std::vector<Vec3> rest_translate_, rest_scale_;
  std::vector<Quat> rest_rotate_;
  std::vector<std::vector<NodeId>> blend_shapes_;  // per glTF node
  std::vector<gltf_look::MeshSource> mesh_sources_;
};

Status Importer::set(NodeId node, graph::AttrIndex attr, graph::Value value) {
  return scene_->graph().set_value(Plug{node, attr, -1}, std::move(value));
}

Status Importer::connect(NodeId src, graph::AttrIndex src_attr, NodeId dst, graph::AttrIndex dst_attr, std::int32_t element) {
  return scene_->graph().connect(Plug{src, src_attr, -1}, Plug{dst, dst_attr, element});
}

// ---- accessors ----

Status Importer::check_accessors() {
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

// Every component of accessor `index` as doubles (count x components),
// normalized integers mapped to [-1, 1] / [0, 1], sparse substitution
// applied; fails on NaN or infinite floats and bad sparse indices.
Result<const std::vector<double>*> Importer::read(int index) {
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

// ---- nodes, skins, scenes ----

Status Importer::check_hierarchy() {
  const std::size_t count = m_.nodes.size();
  parent_.assign(count, -1);
  for (std::size_t i = 0; i < count; ++i) {
    const auto& children = m_.nodes[i].children;
    for (std::size_t k = 0; k < children.size(); ++k) {
      const auto c = static_cast<std::size_t>(children[k]);
      if (parent_[c] == static_cast<int>(i))
        return bad(at(dot(at("nodes", i), "children"), k), "node " + std::to_string(c) + " is listed twice");
      if (parent_[c] >= 0)
        return bad(at(dot(at("nodes", i), "children"), k), "node " + std::to_string(c) + " already has parent node " +
                                                               std::to_string(parent_[c]) + " (a node has one parent)");
      parent_[c] = static_cast<int>(i);
    }
  }
  // Cycles: walk up from every node, marking the walk (1) and what is done (2).
  std::vector<std::uint8_t> state(count, 0);
  std::vector<int> walk;
  for (std::size_t start = 0; start < count; ++start) {
    walk.clear();
    int x = static_cast<int>(start);
    while (x >= 0 && state[static_cast<std::size_t>(x)] == 0) {
      state[static_cast<std::size_t>(x)] = 1;
      walk.push_back(x);
      x = parent_[static_cast<std::size_t>(x)];
    }
    if (x >= 0 && state[static_cast<std::size_t>(x)] == 1) {
      // walk holds child -> parent steps; the cycle is its tail from x.
      std::vector<int> cycle(std::find(walk.begin(), walk.end(), x), walk.end());
      std::reverse(cycle.begin(), cycle.end());  // parent -> child
      std::rotate(cycle.begin(), std::min_element(cycle.begin(), cycle.end()), cycle.end());
      std::string text;
      for (int n : cycle) text += std::to_string(n) + " -> ";
      text += std::to_string(cycle.front());
      return bad(at("nodes", static_cast<std::size_t>(cycle.front())), "node is its own ancestor (cycle " + text + ")");
    }
    for (int n : walk) state[static_cast<std::size_t>(n)] = 2;
  }
  root_.assign(count, -1);
  for (std::size_t i = 0; i < count; ++i) {
    walk.clear();
    int x = static_cast<int>(i);
    while (root_[static_cast<std::size_t>(x)] < 0 && parent_[static_cast<std::size_t>(x)] >= 0) {
      walk.push_back(x);
      x = parent_[static_cast<std::size_t>(x)];
    }
    const int root = root_[static_cast<std::size_t>(x)] >= 0 ? root_[static_cast<std::size_t>(x)] : x;
    root_[static_cast<std::size_t>(x)] = root;
    for (int n : walk) root_[static_cast<std::size_t>(n)] = root;
  }
  return Status::ok();
}

Status Importer::check_skins() {
  is_joint_.assign(m_.nodes.size(), false);
  inverse_bind_.resize(m_.skins.size());
  for (std::size_t s = 0; s < m_.skins.size(); ++s) {
    const tinygltf::Skin& skin = m_.skins[s];
    const std::string path = at("skins", s);
    if (skin.joints.size() > ops::kMaxSkinJoints)
      return bad(dot(path, "joints"), std::to_string(skin.joints.size()) + " joints (at most " + std::to_string(ops::kMaxSkinJoints) + ")");
    std::map<int, std::size_t> seen;
    for (std::size_t k = 0; k < skin.joints.size(); ++k) {
      const int j = skin.joints[k];
      if (auto [it, fresh] = seen.emplace(j, k); !fresh)
        return bad(at(dot(path, "joints"), k), "node " + std::to_string(j) + " is also joints[" + std::to_string(it->second) + "]");
      is_joint_[static_cast<std::size_t>(j)] = true;
    }
    const int root = root_[static_cast<std::size_t>(skin.joints[0])];
    for (std::size_t k = 1; k < skin.joints.size(); ++k) {
      const int j = skin.joints[k];
      if (root_[static_cast<std::size_t>(j)] != root)
        return bad(dot(path, "joints"), "the joints have no common root (node " + std::to_string(skin.joints[0]) + " is under root node " +
                                            std::to_string(root) + ", node " + std::to_string(j) + " under root node " +
                                            std::to_string(root_[static_cast<std::size_t>(j)]) + ")");
    }
    if (skin.skeleton >= 0) {
      for (std::size_t k = 0; k < skin.joints.size(); ++k) {
        int x = skin.joints[k];
        while (x >= 0 && x != skin.skeleton) x = parent_[static_cast<std::size_t>(x)];
        if (x < 0)
          return bad(dot(path, "skeleton"), "node " + std::to_string(skin.skeleton) + " is not a common root of the joints (joints[" +
                                                std::to_string(k) + "] = node " + std::to_string(skin.joints[k]) + " is not below it)");
      }
    }
    if (skin.inverseBindMatrices >= 0) {
      const std::string ip = dot(path, "inverseBindMatrices");
      const tinygltf::Accessor& a = m_.accessors[static_cast<std::size_t>(skin.inverseBindMatrices)];
      if (a.type != TINYGLTF_TYPE_MAT4 || a.componentType != kFloat)
        return bad(ip, accessor_summary(skin.inverseBindMatrices) + "; MAT4 of FLOAT expected");
      if (a.count < skin.joints.size())
        return bad(ip, "accessors[" + std::to_string(skin.inverseBindMatrices) + "] has " + std::to_string(a.count) +
                           " matrices for " + std::to_string(skin.joints.size()) + " joints");
    }
  }
  // The matrices themselves (finite, affine) matter where a node skins with them.
  std::vector<bool> used(m_.skins.size(), false);
  for (const tinygltf::Node& n : m_.nodes) {
    if (n.skin >= 0) used[static_cast<std::size_t>(n.skin)] = true;
  }
  for (std::size_t s = 0; s < m_.skins.size(); ++s) {
    const tinygltf::Skin& skin = m_.skins[s];
    std::vector<Mat4>& ibm = inverse_bind_[s];
    ibm.assign(skin.joints.size(), Mat4::Identity());
    if (used[s] && skin.inverseBindMatrices >= 0) {
      const std::string ip = dot(at("skins", s), "inverseBindMatrices");
      auto values = read(skin.inverseBindMatrices);
      if (!values) return values.status().with_context(ip);
      for (std::size_t k = 0; k < skin.joints.size(); ++k) {
        Mat4 matrix = Eigen::Map<const Mat4>((*values)->data() + 16 * k);  // column-major, as glTF
        const double off = std::max({std::abs(matrix(3, 0)), std::abs(matrix(3, 1)), std::abs(matrix(3, 2)), std::abs(matrix(3, 3) - 1.0)});
        if (off > 1e-5)
          return bad(ip, "matrix " + std::to_string(k) + " is not affine (its last row is not 0 0 0 1)");
        matrix.row(3) << 0.0, 0.0, 0.0, 1.0;
        matrix.topRightCorner<3, 1>() *= options_.scale;
        ibm[k] = matrix;
      }
    }
  }
  return Status::ok();
}

Status Importer::check_nodes() {
  const std::size_t count = m_.nodes.size();
  rest_translate_.assign(count, Vec3::Zero());
  rest_scale_.assign(count, Vec3::Ones());
  rest_rotate_.assign(count, Quat::Identity());
  for (std::size_t i = 0; i < count; ++i) {
    const tinygltf::Node& n = m_.nodes[i];
    const std::string path = at("nodes", i);
    if (n.skin >= 0 && n.mesh < 0) return bad(dot(path, "skin"), "a skin needs a mesh on the node");
    if (!n.weights.empty() && n.mesh < 0) return bad(dot(path, "weights"), "morph target weights need a mesh on the node");
    if (n.mesh >= 0) {
      const tinygltf::Mesh& mesh = m_.meshes[static_cast<std::size_t>(n.mesh)];
      if (n.skin >= 0) {
        for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
          if (!mesh.primitives[p].attributes.count("JOINTS_0"))
            return bad(dot(path, "skin"), "meshes[" + std::to_string(n.mesh) + "].primitives[" + std::to_string(p) +
                                              "] has no JOINTS_0 to bind to skins[" + std::to_string(n.skin) + "]");
        }
      }
      const std::size_t targets = mesh.primitives.empty() ? 0 : mesh.primitives[0].targets.size();
      if (!n.weights.empty() && n.weights.size() != targets)
        return bad(dot(path, "weights"), std::to_string(n.weights.size()) + " weights, meshes[" + std::to_string(n.mesh) + "] has " +
                                             std::to_string(targets) + " morph targets");
    }
    if (!n.matrix.empty()) {
      const Mat4 matrix = Eigen::Map<const Mat4>(n.matrix.data());
      if (matrix(3, 0) != 0.0 || matrix(3, 1) != 0.0 || matrix(3, 2) != 0.0 || matrix(3, 3) != 1.0)
        return bad(dot(path, "matrix"), "not an affine transform (last row " + number(matrix(3, 0)) + " " + number(matrix(3, 1)) + " " +
                                            number(matrix(3, 2)) + " " + number(matrix(3, 3)) + ", 0 0 0 1 expected)");
      // m = T R SH S exactly; rest values for animation come from here.
      const math::Decomposed d = math::decompose(matrix);
      rest_translate_[i] = d.translate * options_.scale;
      rest_rotate_[i] = d.rotation;
      rest_scale_[i] = d.scale;
    } else {
      if (!n.translation.empty()) rest_translate_[i] = Vec3(n.translation[0], n.translation[1], n.translation[2]) * options_.scale;
      if (!n.scale.empty()) rest_scale_[i] = Vec3(n.scale[0], n.scale[1], n.scale[2]);
      if (!n.rotation.empty()) {
        const Quat q = quat_from_xyzw(n.rotation.data());
        if (!(q.norm() >= 1e-6)) return bad(dot(path, "rotation"), "not a rotation (a zero quaternion)");
        rest_rotate_[i] = q.normalized();
      }
    }
    if (!rest_translate_[i].allFinite()) return bad(path, "the translation overflows at this scale");
  }
  return check_finite_world();
}

// Numbers that are finite one by one can still overflow together: a matrix
// of 1e308 decomposes into an infinite scale, and a chain of large scales
// multiplies out to infinity. Every node's decomposed transform, local
// matrix and world matrix (and the world matrix's decomposition, which is
// what reports print) must be finite; the first node that breaks it is named.
Status Importer::check_finite_world() {
  const std::size_t count = m_.nodes.size();
  auto finite = [](const math::Decomposed& d) {
    return d.translate.allFinite() && d.rotation.coeffs().allFinite() && d.scale.allFinite() && d.shear.allFinite();
  };
  auto name_of = [&](std::size_t i) {
    return at("nodes", i) + (m_.nodes[i].name.empty() ? std::string() : " (" + quote_text(m_.nodes[i].name) + ")");
  };
  std::vector<Mat4> world(count, Mat4::Identity());
  std::vector<bool> done(count, false);
  std::vector<std::size_t> chain;
  for (std::size_t start = 0; start < count; ++start) {
    chain.clear();
    for (int x = static_cast<int>(start); x >= 0 && !done[static_cast<std::size_t>(x)]; x = parent_[static_cast<std::size_t>(x)])
      chain.push_back(static_cast<std::size_t>(x));
    for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
      const std::size_t i = *it;
      const tinygltf::Node& n = m_.nodes[i];
      Mat4 local = math::trs_matrix(rest_translate_[i], rest_rotate_[i], rest_scale_[i]);
      if (!n.matrix.empty()) {
        local = Eigen::Map<const Mat4>(n.matrix.data());
        local.topRightCorner<3, 1>() *= options_.scale;
        if (!finite(math::decompose(local)))
          return bad(name_of(i), "its matrix overflows when decomposed into translation, rotation, scale and shear");
      }
      if (!local.allFinite()) return bad(name_of(i), "its local transform overflows (numbers beyond a double's range)");
      const int parent = parent_[i];
      world[i] = parent >= 0 ? Mat4(world[static_cast<std::size_t>(parent)] * local) : local;
      if (!world[i].allFinite() || !finite(math::decompose(world[i])))
        return bad(name_of(i), "its world matrix overflows (the transforms down to it multiply out of a double's range)");
      done[i] = true;
    }
  }
  return Status::ok();
}

Status Importer::check_scenes() {
  for (std::size_t s = 0; s < m_.scenes.size(); ++s) {
    const auto& roots = m_.scenes[s].nodes;
    std::set<int> in_scene;
    for (std::size_t k = 0; k < roots.size(); ++k) {
      const int n = roots[k];
      if (parent_[static_cast<std::size_t>(n)] >= 0)
        return bad(at(dot(at("scenes", s), "nodes"), k), "node " + std::to_string(n) + " is not a root (it is a child of node " +
                                                             std::to_string(parent_[static_cast<std::size_t>(n)]) + ")");
      if (!in_scene.insert(n).second) return bad(at(dot(at("scenes", s), "nodes"), k), "node " + std::to_string(n) + " is listed twice");
    }
    for (std::size_t i = 0; i < m_.nodes.size(); ++i) {
      const int skin = m_.nodes[i].skin;
      if (skin < 0 || !in_scene.count(root_[i])) continue;
      const auto& joints = m_.skins[static_cast<std::size_t>(skin)].joints;
      for (std::size_t k = 0; k < joints.size(); ++k) {
        if (!in_scene.count(root_[static_cast<std::size_t>(joints[k])]))
          return bad(at("nodes", i), "its skinned mesh is in scenes[" + std::to_string(s) + "], which does not hold its joints (skins[" +
                                         std::to_string(skin) + "].joints[" + std::to_string(k) + "] = node " +
                                         std::to_string(joints[k]) + ")");
      }
    }
  }
  return Status::ok();
}

// ---- meshes ----

// "JOINTS_12" -> 12; -1 when `name` is not prefix + a decimal number.
int set_index(const std::string& name, std::string_view prefix) {
  if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) return -1;
  const std::string digits = name.substr(prefix.size());
  if (digits.size() > 4 || (digits.size() > 1 && digits[0] == '0')) return -1;
  int n = 0;
  for (char c : digits) {
    if (c < '0' || c > '9') return -1;
    n = n * 10 + (c - '0');
  }
  return n;
}

Status Importer::read_primitive(std::size_t m, std::size_t p, PrimitiveData& out) {
  const tinygltf::Primitive& prim = m_.meshes[m].primitives[p];
  const std::string path = at(dot(at("meshes", m), "primitives"), p);
  const std::string attr_path = dot(path, "attributes");
  const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;

  // Counts: every attribute has POSITION's (or, without POSITION, the first one's).
  auto position = prim.attributes.find("POSITION");
  const auto reference = position != prim.attributes.end() ? position : prim.attributes.begin();
  if (reference == prim.attributes.end()) return bad(attr_path, "no attributes");
  const std::size_t count = m_.accessors[static_cast<std::size_t>(reference->second)].count;
  out.vertex_count = count;
  for (const auto& [name, index] : prim.attributes) {
    const std::size_t n = m_.accessors[static_cast<std::size_t>(index)].count;
    if (n != count)
      return bad(dot(attr_path, name), "accessor " + std::to_string(index) + " has " + std::to_string(n) + " elements, " +
                                           reference->first + " has " + std::to_string(count));
  }

  using Allowed = std::vector<std::pair<int, bool>>;
  auto require = [&](const std::string& where, int index, int type, const Allowed& allowed, const char* expected) -> Status {
    const tinygltf::Accessor& a = m_.accessors[static_cast<std::size_t>(index)];
    bool ok = a.type == type;
    if (ok) {
      ok = false;
      for (const auto& [component, normalized] : allowed) ok |= a.componentType == component && a.normalized == normalized;
    }
    return ok ? Status::ok() : bad(where, accessor_summary(index) + "; " + expected + " expected");
  };
  // KHR_mesh_quantization lets positions, normals and morph deltas be integers.
  const Allowed kPositionTypes = quantized_ ? Allowed{{kFloat, false}, {kByte, false}, {kByte, true}, {kUnsignedByte, false},
                                                       {kUnsignedByte, true}, {kShort, false}, {kShort, true},
                                                       {kUnsignedShort, false}, {kUnsignedShort, true}}
                                             : Allowed{{kFloat, false}};
  const Allowed kNormalTypes = quantized_ ? Allowed{{kFloat, false}, {kByte, true}, {kShort, true}} : Allowed{{kFloat, false}};

  if (position != prim.attributes.end()) {
    if (Status s = require(dot(attr_path, "POSITION"), position->second, TINYGLTF_TYPE_VEC3, kPositionTypes, "VEC3 of FLOAT"); !s) return s;
    auto values = read(position->second);
    if (!values) return values.status().with_context(dot(attr_path, "POSITION"));
    out.points.resize(count);
    for (std::size_t v = 0; v < count; ++v) out.points[v] = Vec3((**values)[3 * v], (**values)[3 * v + 1], (**values)[3 * v + 2]) * options_.scale;
  }
  if (auto normal = prim.attributes.find("NORMAL"); normal != prim.attributes.end()) {
    if (Status s = require(dot(attr_path, "NORMAL"), normal->second, TINYGLTF_TYPE_VEC3, kNormalTypes, "VEC3 of FLOAT"); !s) return s;
    auto values = read(normal->second);
    if (!values) return values.status().with_context(dot(attr_path, "NORMAL"));
    out.normals.resize(count);
    for (std::size_t v = 0; v < count; ++v) out.normals[v] = Vec3((**values)[3 * v], (**values)[3 * v + 1], (**values)[3 * v + 2]);
  }

  // Skin sets: JOINTS_n and WEIGHTS_n in pairs.
  std::set<int> joint_sets, weight_sets;
  for (const auto& [name, index] : prim.attributes) {
    if (const int n = set_index(name, "JOINTS_"); n >= 0) joint_sets.insert(n);
    if (const int n = set_index(name, "WEIGHTS_"); n >= 0) weight_sets.insert(n);
  }
  for (int n : joint_sets) {
    if (!weight_sets.count(n)) return bad(attr_path, "JOINTS_" + std::to_string(n) + " has no WEIGHTS_" + std::to_string(n));
  }
  for (int n : weight_sets) {
    if (!joint_sets.count(n)) return bad(attr_path, "WEIGHTS_" + std::to_string(n) + " has no JOINTS_" + std::to_string(n));
  }
  out.sets.assign(joint_sets.begin(), joint_sets.end());
  out.per_vertex = 4 * out.sets.size();
  out.joints.assign(count * out.per_vertex, 0);
  out.weights.assign(count * out.per_vertex, 0.0);
  for (std::size_t k = 0; k < out.sets.size(); ++k) {
    const std::string jn = "JOINTS_" + std::to_string(out.sets[k]), wn = "WEIGHTS_" + std::to_string(out.sets[k]);
    const int ja = prim.attributes.at(jn), wa = prim.attributes.at(wn);
    if (Status s = require(dot(attr_path, jn), ja, TINYGLTF_TYPE_VEC4, Allowed{{kUnsignedByte, false}, {kUnsignedShort, false}},
                           "VEC4 of UNSIGNED_BYTE or UNSIGNED_SHORT");
        !s)
      return s;
    if (Status s = require(dot(attr_path, wn), wa, TINYGLTF_TYPE_VEC4, Allowed{{kFloat, false}, {kUnsignedByte, true}, {kUnsignedShort, true}},
                           "VEC4 of FLOAT, or of normalized UNSIGNED_BYTE or UNSIGNED_SHORT");
        !s)
      return s;
    auto joints = read(ja);
    if (!joints) return joints.status().with_context(dot(attr_path, jn));
    auto weights = read(wa);
    if (!weights) return weights.status().with_context(dot(attr_path, wn));
    for (std::size_t v = 0; v < count; ++v) {
      for (std::size_t c = 0; c < 4; ++c) {
        const double w = (**weights)[4 * v + c];
        if (w < 0.0) return bad(dot(attr_path, wn), "element " + std::to_string(v) + " has a negative weight");
        out.joints[v * out.per_vertex + 4 * k + c] = static_cast<std::int64_t>((**joints)[4 * v + c]);
        out.weights[v * out.per_vertex + 4 * k + c] = w;
      }
    }
  }

  // Morph targets: dense POSITION deltas.
  out.target_deltas.resize(prim.targets.size());
  for (std::size_t t = 0; t < prim.targets.size(); ++t) {
    const std::string tp = at(dot(path, "targets"), t);
    for (const auto& [name, index] : prim.targets[t]) {
      const std::size_t n = m_.accessors[static_cast<std::size_t>(index)].count;
      if (n != count)
        return bad(dot(tp, name), "accessor " + std::to_string(index) + " has " + std::to_string(n) + " elements, " + reference->first +
                                      " has " + std::to_string(count));
    }
    out.target_deltas[t].assign(count, Vec3::Zero());
    if (auto delta = prim.targets[t].find("POSITION"); delta != prim.targets[t].end()) {
      if (Status s = require(dot(tp, "POSITION"), delta->second, TINYGLTF_TYPE_VEC3, kPositionTypes, "VEC3 of FLOAT"); !s) return s;
      auto values = read(delta->second);
      if (!values) return values.status().with_context(dot(tp, "POSITION"));
      for (std::size_t v = 0; v < count; ++v)
        out.target_deltas[t][v] = Vec3((**values)[3 * v], (**values)[3 * v + 1], (**values)[3 * v + 2]) * options_.scale;
    }
  }

  // Indices, checked for every mode; triangles for the surface modes.
  std::vector<std::int64_t> indices;
  if (prim.indices >= 0) {
    const std::string ip = dot(path, "indices");
    if (Status s = require(ip, prim.indices, TINYGLTF_TYPE_SCALAR, Allowed{{kUnsignedByte, false}, {kUnsignedShort, false}, {kUnsignedInt, false}},
                           "SCALAR of UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT");
        !s)
      return s;
    auto values = read(prim.indices);
    if (!values) return values.status().with_context(ip);
    indices.resize((*values)->size());
    for (std::size_t k = 0; k < indices.size(); ++k) {
      const double v = (**values)[k];
      if (v >= static_cast<double>(count))
        return bad(ip, "element " + std::to_string(k) + " is not below the vertex count " + std::to_string(count));
      indices[k] = static_cast<std::int64_t>(v);
    }
  } else {
    indices.resize(count);
    for (std::size_t k = 0; k < count; ++k) indices[k] = static_cast<std::int64_t>(k);
  }
  const bool surface = mode == TINYGLTF_MODE_TRIANGLES || mode == TINYGLTF_MODE_TRIANGLE_STRIP || mode == TINYGLTF_MODE_TRIANGLE_FAN;
  if (mode == TINYGLTF_MODE_TRIANGLES && indices.size() % 3 != 0)
    return bad(prim.indices >= 0 ? dot(path, "indices") : path,
               std::to_string(indices.size()) + (prim.indices >= 0 ? " indices" : " vertices (no indices)") + " do not make whole triangles");
  out.make_node = surface && position != prim.attributes.end();
  if (!out.make_node) return Status::ok();
  if (mode == TINYGLTF_MODE_TRIANGLES) {
    out.triangles = std::move(indices);
  } else if (indices.size() >= 3) {
    out.triangles.reserve(3 * (indices.size() - 2));
    for (std::size_t i = 0; i + 2 < indices.size(); ++i) {
      // glTF 2.0 §3.7.2.1: strips alternate the winding, fans turn around vertex 0.
      if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
        const bool odd = i % 2 == 1;
        out.triangles.insert(out.triangles.end(), {indices[i], indices[odd ? i + 2 : i + 1], indices[odd ? i + 1 : i + 2]});
      } else {
        out.triangles.insert(out.triangles.end(), {indices[i + 1], indices[i + 2], indices[0]});
      }
    }
  }
  return Status::ok();
}

Status Importer::read_meshes() {
  meshes_.resize(m_.meshes.size());
  for (std::size_t m = 0; m < m_.meshes.size(); ++m) {
    const tinygltf::Mesh& mesh = m_.meshes[m];
    MeshData& data = meshes_[m];
    data.primitives.resize(mesh.primitives.size());
    data.target_count = mesh.primitives.empty() ? 0 : mesh.primitives[0].targets.size();
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
      if (mesh.primitives[p].targets.size() != data.target_count)
        return bad(dot(at(dot(at("meshes", m), "primitives"), p), "targets"),
                   std::to_string(mesh.primitives[p].targets.size()) + " morph targets, primitives[0] has " + std::to_string(data.target_count));
      if (Status s = read_primitive(m, p, data.primitives[p]); !s) return s;
    }
    if (!mesh.weights.empty() && mesh.weights.size() != data.target_count)
      return bad(dot(at("meshes", m), "weights"),
                 std::to_string(mesh.weights.size()) + " weights for " + std::to_string(data.target_count) + " morph targets");
  }
  return Status::ok();
}

// The node's mesh against its skin: joint indices (where the weight is not
// zero) below the joint count, and a weight on every vertex; then the
// skinCluster's own validation, so that it will skin and not pass through.
Result<std::vector<SkinBinding>> Importer::bind_skin(std::size_t node) {
  const tinygltf::Node& n = m_.nodes[node];
  const auto skin_index = static_cast<std::size_t>(n.skin);
  const std::size_t joint_count = m_.skins[skin_index].joints.size();
  const auto m = static_cast<std::size_t>(n.mesh);
  std::vector<SkinBinding> result(meshes_[m].primitives.size());
  for (std::size_t p = 0; p < meshes_[m].primitives.size(); ++p) {
    const PrimitiveData& prim = meshes_[m].primitives[p];
    const std::string path = at(dot(at("meshes", m), "primitives"), p);
    const std::string user = " (skins[" + std::to_string(skin_index) + "], used by nodes[" + std::to_string(node) + "])";
    SkinBinding& b = result[p];
    b.offsets = {0};
    for (std::size_t v = 0; v < prim.vertex_count; ++v) {
      for (std::size_t k = 0; k < prim.per_vertex; ++k) {
        const double w = prim.weights[v * prim.per_vertex + k];
        if (w == 0.0) continue;
        const std::int64_t j = prim.joints[v * prim.per_vertex + k];
        if (j < 0 || static_cast<std::size_t>(j) >= joint_count)
          return bad(dot(dot(path, "attributes"), "JOINTS_" + std::to_string(prim.sets[k / 4])),
                     "element " + std::to_string(v) + " has a joint index not below the joint count " +
                         std::to_string(joint_count) + user);
        b.joints.push_back(j);
        b.weights.push_back(w);
      }
      if (static_cast<std::size_t>(b.offsets.back()) == b.joints.size()) {
        // No weight above zero: bound to the glTF node that holds the mesh
        // (one more joint matrix, after the skin's own).
        b.unweighted.push_back(v);
        b.joints.push_back(static_cast<std::int64_t>(joint_count));
        b.weights.push_back(1.0);
      }
      b.offsets.push_back(static_cast<std::int64_t>(b.joints.size()));
    }
    ops::SkinBuildOptions build;
    build.joint_count = joint_count + (b.unweighted.empty() ? 0 : 1);
    if (Result<ops::Skin> skin = ops::build_skin({b.offsets, b.joints, b.weights}, build); !skin) return skin.status().with_context(path);
    if (!b.unweighted.empty() && options_.warnings) {
      std::string list;
      for (std::size_t k = 0; k < b.unweighted.size() && k < 10; ++k) list += (k ? ", " : "") + std::to_string(b.unweighted[k]);
      if (b.unweighted.size() > 10) list += ", ... (" + std::to_string(b.unweighted.size()) + " in all)";
      options_.warnings->push_back(path + ": vertices " + list + " have no joint weight above zero" + user +
                                   "; they follow the mesh's node " + quote_text(scene_->graph().node(ids_[node])->name()) +
                                   " instead of a joint");
    }
  }
  return result;
}

// ---- animations ----

Status Importer::read_channel(std::size_t a, std::size_t c, ClipKeys& out, std::size_t width, Path path) {
  const tinygltf::Animation& anim = m_.animations[a];
  const tinygltf::AnimationChannel& channel = anim.channels[c];
  const auto sampler_index = static_cast<std::size_t>(channel.sampler);
  const tinygltf::AnimationSampler& sampler = anim.samplers[sampler_index];
  const std::string sp = at(dot(at("animations", a), "samplers"), sampler_index);
  using ops::anim::Interpolation;
  out.interpolation = sampler.interpolation == "STEP" ? Interpolation::kStep
                      : sampler.interpolation == "CUBICSPLINE" ? Interpolation::kCubicSpline
                                                               : Interpolation::kLinear;
  const tinygltf::Accessor& input = m_.accessors[static_cast<std::size_t>(sampler.input)];
  if (input.type != TINYGLTF_TYPE_SCALAR || input.componentType != kFloat)
    return bad(dot(sp, "input"), accessor_summary(sampler.input) + "; SCALAR of FLOAT expected");
  auto times = read(sampler.input);
  if (!times) return times.status().with_context(dot(sp, "input"));
  out.times = **times;
  for (std::size_t k = 1; k < out.times.size(); ++k) {
    if (!(out.times[k] > out.times[k - 1]))
      return bad(dot(sp, "input"), "times not increasing at key " + std::to_string(k));
  }
  const tinygltf::Accessor& output = m_.accessors[static_cast<std::size_t>(sampler.output)];
  const std::string op = dot(sp, "output");
  const bool float_only = path == Path::kTranslation || path == Path::kScale;
  const int type = path == Path::kWeights ? TINYGLTF_TYPE_SCALAR : path == Path::kRotation ? TINYGLTF_TYPE_VEC4 : TINYGLTF_TYPE_VEC3;
  const bool type_ok = output.type == type && (output.componentType == kFloat ||
                                               (!float_only && output.normalized && output.componentType != kUnsignedInt));
  if (!type_ok)
    return bad(op, accessor_summary(sampler.output) + "; " + type_name(type) + " of FLOAT" + (float_only ? "" : " or normalized integers") +
                       " expected for " + kPathNames[static_cast<int>(path)]);
  const bool cubic = out.interpolation == Interpolation::kCubicSpline;
  const std::size_t per_key = path == Path::kWeights ? width : 1;
  const std::size_t expected = out.times.size() * per_key * (cubic ? 3 : 1);
  if (output.count != expected)
    return bad(op, "accessors[" + std::to_string(sampler.output) + "] has " + std::to_string(output.count) + " elements, " +
                       std::to_string(out.times.size()) + " keys need " + std::to_string(expected));
  auto values = read(sampler.output);
  if (!values) return values.status().with_context(op);
  const std::vector<double>& v = **values;
  const std::size_t keys = out.times.size();
  const double scale = path == Path::kTranslation ? options_.scale : 1.0;
  auto take = [&](std::vector<double>& dst, std::size_t key, std::size_t part) {
    // cubic: key k holds in-tangent, value, out-tangent, each `width` numbers
    const std::size_t base = (cubic ? (3 * key + part) : key) * width;
    for (std::size_t w = 0; w < width; ++w) dst.push_back(v[base + w] * scale);
  };
  for (std::size_t k = 0; k < keys; ++k) {
    take(out.values, k, 1);
    if (cubic) {
      take(out.in_tangents, k, 0);
      take(out.out_tangents, k, 2);
    }
    if (path == Path::kRotation) {
      const Quat q = quat_from_xyzw(out.values.data() + 4 * k);
      if (!(q.norm() >= 1e-6)) return bad(op, "key " + std::to_string(k) + " is not a rotation (a zero quaternion)");
    }
  }
  for (const std::vector<double>* list : {&out.values, &out.in_tangents, &out.out_tangents}) {
    for (double x : *list) {
      if (!std::isfinite(x)) return bad(op, "the translation overflows at this scale");
    }
  }
  return Status::ok();
}

Status Importer::read_animations() {
  std::map<std::pair<int, int>, std::size_t> index;  // (node, path) -> channels_ entry
  std::set<std::string> names;
  for (std::size_t a = 0; a < m_.animations.size(); ++a) {
    const tinygltf::Animation& anim = m_.animations[a];
    const std::string path = at("animations", a);
    clip_names_.push_back(unique_among(anim.name.empty() ? "animation_" + std::to_string(a) : anim.name, names));
    // The clip spans every key of the animation's samplers.
    double start = std::numeric_limits<double>::infinity(), end = -start;
    std::map<std::pair<int, int>, std::size_t> seen;  // in this animation: (node, path) -> channel
    for (std::size_t c = 0; c < anim.channels.size(); ++c) {
      const tinygltf::AnimationChannel& channel = anim.channels[c];
      if (channel.target_node < 0) continue;  // an extension's target
      const std::string cp = at(dot(path, "channels"), c);
      const std::string& name = channel.target_path;
      const Path what = name == "translation" ? Path::kTranslation
                        : name == "rotation"  ? Path::kRotation
                        : name == "scale"     ? Path::kScale
                                              : Path::kWeights;
      const auto node = static_cast<std::size_t>(channel.target_node);
      const std::pair<int, int> key{channel.target_node, static_cast<int>(what)};
      if (auto [it, fresh] = seen.emplace(key, c); !fresh)
        return bad(cp, "node " + std::to_string(node) + " " + name + " is also animated by channels[" + std::to_string(it->second) + "]");
      std::size_t width = what == Path::kRotation ? 4 : 3;
      if (what == Path::kWeights) {
        const int mesh = m_.nodes[node].mesh;
        width = mesh < 0 ? 0 : meshes_[static_cast<std::size_t>(mesh)].target_count;
        if (width == 0) return bad(dot(cp, "target"), "node " + std::to_string(node) + " has no morph targets to animate");
      }
      ClipKeys keys;
      if (Status s = read_channel(a, c, keys, width, what); !s) return s;
      auto [it, fresh] = index.emplace(key, channels_.size());
      if (fresh) channels_.push_back(Channel{channel.target_node, what, std::vector<std::optional<ClipKeys>>(m_.animations.size())});
      channels_[it->second].clips[a] = std::move(keys);
    }
    for (const tinygltf::AnimationSampler& sampler : anim.samplers) {
      // Times of unused samplers count too; an unreadable one fails here.
      const tinygltf::Accessor& input = m_.accessors[static_cast<std::size_t>(sampler.input)];
      if (input.type != TINYGLTF_TYPE_SCALAR || input.componentType != kFloat) continue;
      auto times = read(sampler.input);
      if (!times) return times.status().with_context(dot(path, "samplers"));
      for (double t : **times) {
        start = std::min(start, t);
        end = std::max(end, t);
      }
    }
    if (!(start <= end)) start = end = 0.0;
    clip_starts_.push_back(start);
    clip_ends_.push_back(end);
  }
  std::sort(channels_.begin(), channels_.end(), [](const Channel& x, const Channel& y) {
    return std::pair(x.node, static_cast<int>(x.path)) < std::pair(y.node, static_cast<int>(y.path));
  });
  return Status::ok();
}

// ---- building ----

Status Importer::build_nodes() {
  Graph& g = scene_->graph();
  const std::size_t count = m_.nodes.size();
  ids_.resize(count);
  blend_shapes_.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    const tinygltf::Node& n = m_.nodes[i];
    const std::string path = at("nodes", i);
    Result<NodeId> id = g.create_node(is_joint_[i] ? scene::kJointType : scene::kTransformType,
                                      node_name(n.name, "node_" + std::to_string(i)));
    if (!id) return id.status().with_context(path);
    ids_[i] = *id;
    namespace x = scene::xform;
    Status s = set(*id, x::kTranslate, rest_translate_[i]);
    if (s) s = set(*id, x::kRotateMode, x::kQuaternionMode);
    if (s) s = set(*id, x::kRotateQuaternion, rest_rotate_[i]);
    if (s) s = set(*id, x::kScale, rest_scale_[i]);
    if (s && !n.matrix.empty()) s = set(*id, x::kShear, math::decompose(Eigen::Map<const Mat4>(n.matrix.data())).shear);
    if (!s) return s.with_context(path);
  }
  for (std::size_t i = 0; i < count; ++i) {
    if (parent_[i] < 0) continue;
    if (Status s = g.set_parent(ids_[i], ids_[static_cast<std::size_t>(parent_[i])]); !s) return s.with_context(at("nodes", i));
  }
  return Status::ok();
}

Status Importer::build_meshes() {
  Graph& g = scene_->graph();
  namespace sc = ops::skin_cluster_attr;
  namespace bs = ops::blend_shape_attr;
  namespace ma = scene::mesh_attr;
  for (std::size_t i = 0; i < m_.nodes.size(); ++i) {
    const tinygltf::Node& n = m_.nodes[i];
    if (n.mesh < 0) continue;
    std::vector<SkinBinding> bindings;
    if (n.skin >= 0) {
      Result<std::vector<SkinBinding>> bound = bind_skin(i);
      if (!bound) return bound.status();
      bindings = std::move(*bound);
    }
    const auto mi = static_cast<std::size_t>(n.mesh);
    const tinygltf::Mesh& mesh = m_.meshes[mi];
    const MeshData& data = meshes_[mi];
    const std::string node_path = at("nodes", i);
    const std::string& owner = g.node(ids_[i])->name();
    std::vector<double> weights(data.target_count, 0.0);
    if (!n.weights.empty()) weights = n.weights;
    else if (!mesh.weights.empty()) weights = mesh.weights;
    for (std::size_t p = 0; p < data.primitives.size(); ++p) {
      const PrimitiveData& prim = data.primitives[p];
      if (!prim.make_node) continue;
      std::string name = node_name(mesh.name, owner + "_mesh");
      // append, not "_" + ...: GCC 12 warns falsely (-Wrestrict) on that form.
      if (data.primitives.size() > 1) name.append("_").append(std::to_string(p));
      const std::string where = node_path + ": meshes[" + std::to_string(mi) + "].primitives[" + std::to_string(p) + "]";
      const bool skinned = n.skin >= 0;
      Result<NodeId> mesh_id = scene_->create(scene::kMeshType, name, skinned ? NodeId{} : ids_[i]);
      if (!mesh_id) return mesh_id.status().with_context(where);
      mesh_sources_.push_back({*mesh_id, mi, p});
      const std::string& mesh_name = g.node(*mesh_id)->name();
      Status s = set(*mesh_id, ma::kTriangles, prim.triangles);
      // The glTF node holding the mesh: the exporter writes the mesh back on
      // it, so a round trip keeps the node tree (gltf_export.h).
      if (s) s = g.set_tag(*mesh_id, kTagGltfNode, g.node(ids_[i])->name());
      // Where the points come from: the file, a blendShape, a skinCluster.
      NodeId points_src;
      graph::AttrIndex points_attr = 0;
      if (s && data.target_count > 0) {
        Result<NodeId> shape = g.create_node(ops::kBlendShapeType, mesh_name + "_blendShape");
        if (!shape) return shape.status().with_context(where);
        std::vector<Vec3> deltas;
        std::vector<std::int64_t> offsets = {0};
        for (const auto& target : prim.target_deltas) {
          deltas.insert(deltas.end(), target.begin(), target.end());
          offsets.push_back(static_cast<std::int64_t>(deltas.size()));
        }
        s = set(*shape, bs::kBasePoints, prim.points);
        if (s) s = set(*shape, bs::kTargetDeltas, std::move(deltas));
        if (s) s = set(*shape, bs::kTargetOffsets, std::move(offsets));
        if (s) s = set(*shape, bs::kWeights, weights);
        points_src = *shape;
        points_attr = bs::kOutPoints;
        blend_shapes_[i].push_back(*shape);
      }
      if (s && skinned) {
        const auto skin_index = static_cast<std::size_t>(n.skin);
        const auto& joints = m_.skins[skin_index].joints;
        Result<NodeId> skin = g.create_node(ops::kSkinClusterType, mesh_name + "_skinCluster");
        if (!skin) return skin.status().with_context(where);
        SkinBinding& binding = bindings[p];
        std::vector<Mat4> bind_pre = inverse_bind_[skin_index];
        if (!binding.unweighted.empty()) bind_pre.push_back(Mat4::Identity());
        if (points_src.is_valid()) s = connect(points_src, points_attr, *skin, sc::kBindPoints);
        else s = set(*skin, sc::kBindPoints, prim.points);
        if (s) s = set(*skin, sc::kBindNormals, prim.normals);
        if (s) s = set(*skin, sc::kBindPreMatrices, std::move(bind_pre));
        if (s) s = set(*skin, sc::kInfluenceOffsets, std::move(binding.offsets));
        if (s) s = set(*skin, sc::kInfluenceJoints, std::move(binding.joints));
        if (s) s = set(*skin, sc::kInfluenceWeights, std::move(binding.weights));
        if (s) s = set(*skin, sc::kNormalizeWeights, true);
        for (std::size_t k = 0; s && k < joints.size(); ++k)
          s = connect(ids_[static_cast<std::size_t>(joints[k])], scene::xform::kWorldMatrix, *skin, sc::kJointMatrices,
                      static_cast<std::int32_t>(k));
        if (s && !binding.unweighted.empty())
          s = connect(ids_[i], scene::xform::kWorldMatrix, *skin, sc::kJointMatrices, static_cast<std::int32_t>(joints.size()));
        if (s) s = connect(*skin, sc::kOutPoints, *mesh_id, ma::kPoints);
        if (s) s = connect(*skin, sc::kOutNormals, *mesh_id, ma::kNormals);
      } else if (s) {
        if (points_src.is_valid()) s = connect(points_src, points_attr, *mesh_id, ma::kPoints);
        else s = set(*mesh_id, ma::kPoints, prim.points);
        if (s) s = set(*mesh_id, ma::kNormals, prim.normals);
      }
      if (!s) return s.with_context(where);
    }
  }
  return Status::ok();
}

// Keys of several clips in one curve need one interpolation; when the clips
// of a channel disagree they are converted (see the header).
ClipKeys to_cubic(const ClipKeys& keys, std::size_t width) {
  ClipKeys out = keys;
  out.interpolation = ops::anim::Interpolation::kCubicSpline;
  const std::size_t n = keys.times.size();
  out.in_tangents.assign(n * width, 0.0);
  out.out_tangents.assign(n * width, 0.0);
  for (std::size_t k = 0; k + 1 < n; ++k) {
    const double span = keys.times[k + 1] - keys.times[k];
    for (std::size_t w = 0; w < width; ++w) {
      const double slope = (keys.values[(k + 1) * width + w] - keys.values[k * width + w]) / span;
      out.out_tangents[k * width + w] = slope;
      out.in_tangents[(k + 1) * width + w] = slope;
    }
  }
  return out;
}

ClipKeys to_linear(const ClipKeys& keys, std::size_t width, bool rotation) {
  using ops::anim::Interpolation;
  if (keys.interpolation == Interpolation::kLinear) return keys;
  ClipKeys out;
  out.interpolation = Interpolation::kLinear;
  const std::size_t n = keys.times.size();
  auto push = [&](double t, const double* v) {
    out.times.push_back(t);
    out.values.insert(out.values.end(), v, v + width);
  };
  constexpr int kSamples = 16;
  std::vector<double> sample(width);
  for (std::size_t k = 0; k < n; ++k) {
    const double* v = keys.values.data() + k * width;
    push(keys.times[k], v);
    if (k + 1 == n) break;
    const double t0 = keys.times[k], t1 = keys.times[k + 1], span = t1 - t0;
    if (keys.interpolation == Interpolation::kStep) {
      const double hold = t1 - 1e-4 * span;  // hold the value up to just before the next key
      if (hold > t0 && hold < t1) push(hold, v);
      continue;
    }
    const double* next = keys.values.data() + (k + 1) * width;
    for (int j = 1; j < kSamples; ++j) {
      const double s = static_cast<double>(j) / kSamples;
      const double s2 = s * s, s3 = s2 * s;
      const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
      for (std::size_t w = 0; w < width; ++w)
        sample[w] = h00 * v[w] + h10 * span * keys.out_tangents[k * width + w] + h01 * next[w] + h11 * span * keys.in_tangents[(k + 1) * width + w];
      if (rotation) {
        double norm = 0.0;
        for (double c : sample) norm += c * c;
        norm = std::sqrt(norm);
        if (norm > 0.0)
          for (double& c : sample) c /= norm;
      }
      const double t = t0 + s * span;
      if (t > out.times.back() && t < t1) push(t, sample.data());
    }
  }
  return out;
}

Status Importer::build_track(const Channel& channel, NodeId clips) {
  using ops::anim::Interpolation;
  namespace ta = ops::anim::track_attr;
  Graph& g = scene_->graph();
  const bool rotation = channel.path == Path::kRotation;
  const std::size_t width = rotation ? 4 : 3;
  const auto node = static_cast<std::size_t>(channel.node);

  std::set<Interpolation> used;
  for (const auto& clip : channel.clips) {
    if (clip) used.insert(clip->interpolation);
  }
  Interpolation interpolation = *used.begin();
  if (used.size() > 1) {
    const bool exact_cubic = !rotation && !used.count(Interpolation::kStep);
    interpolation = exact_cubic ? Interpolation::kCubicSpline : Interpolation::kLinear;
  }
  std::vector<double> times;
  std::vector<double> values, in_tangents, out_tangents;
  std::vector<std::int64_t> offsets = {0};
  for (const auto& clip : channel.clips) {
    if (clip) {
      const ClipKeys keys = clip->interpolation == interpolation          ? *clip
                            : interpolation == Interpolation::kCubicSpline ? to_cubic(*clip, width)
                                                                           : to_linear(*clip, width, rotation);
      times.insert(times.end(), keys.times.begin(), keys.times.end());
      values.insert(values.end(), keys.values.begin(), keys.values.end());
      in_tangents.insert(in_tangents.end(), keys.in_tangents.begin(), keys.in_tangents.end());
      out_tangents.insert(out_tangents.end(), keys.out_tangents.begin(), keys.out_tangents.end());
    }
    offsets.push_back(static_cast<std::int64_t>(times.size()));
  }

  const std::string& owner = g.node(ids_[node])->name();
  const char* suffix = rotation ? "_rotate" : channel.path == Path::kScale ? "_scale" : "_translate";
  Result<NodeId> curve = g.create_node(rotation ? ops::anim::kAnimCurveQuatType : ops::anim::kAnimCurveVec3Type, owner + suffix);
  if (!curve) return curve.status();
  Status s;
  if (rotation) {
    auto quats = [](const std::vector<double>& v) {
      std::vector<Quat> out(v.size() / 4);
      for (std::size_t k = 0; k < out.size(); ++k) out[k] = quat_from_xyzw(v.data() + 4 * k);
      return out;
    };
    s = set(*curve, ta::kKeyValues, quats(values));
    if (s) s = set(*curve, ta::kInTangents, quats(in_tangents));
    if (s) s = set(*curve, ta::kOutTangents, quats(out_tangents));
    if (s) s = set(*curve, ta::kRestValue, rest_rotate_[node]);
  } else {
    auto vecs = [](const std::vector<double>& v) {
      std::vector<Vec3> out(v.size() / 3);
      for (std::size_t k = 0; k < out.size(); ++k) out[k] = Vec3(v[3 * k], v[3 * k + 1], v[3 * k + 2]);
      return out;
    };
    s = set(*curve, ta::kKeyValues, vecs(values));
    if (s) s = set(*curve, ta::kInTangents, vecs(in_tangents));
    if (s) s = set(*curve, ta::kOutTangents, vecs(out_tangents));
    if (s) s = set(*curve, ta::kRestValue, channel.path == Path::kScale ? rest_scale_[node] : rest_translate_[node]);
  }
  if (s) s = set(*curve, ta::kKeyTimes, std::move(times));
  if (s) s = set(*curve, ta::kInterpolation, std::int64_t{static_cast<std::int64_t>(interpolation)});
  if (s) s = set(*curve, ta::kClipOffsets, std::move(offsets));
  if (s) s = connect(clips, ops::anim::clips_attr::kActiveClip, *curve, ta::kClip);
  namespace x = scene::xform;
  const graph::AttrIndex target = rotation ? x::kRotateQuaternion : channel.path == Path::kScale ? x::kScale : x::kTranslate;
  if (s) s = connect(*curve, ta::kOutput, ids_[node], target);
  return s;
}

Status Importer::build_weight_curves(const Channel& channel, NodeId clips) {
  using ops::anim::Interpolation;
  using ops::anim::TangentType;
  namespace ca = ops::anim::curve_attr;
  namespace aa = ops::anim::anim_curve_attr;
  Graph& g = scene_->graph();
  const auto node = static_cast<std::size_t>(channel.node);
  if (blend_shapes_[node].empty()) return Status::ok();  // no surface to deform
  const tinygltf::Node& n = m_.nodes[node];
  const tinygltf::Mesh& mesh = m_.meshes[static_cast<std::size_t>(n.mesh)];
  const std::size_t targets = meshes_[static_cast<std::size_t>(n.mesh)].target_count;
  const std::string& owner = g.node(ids_[node])->name();
  bool any_cubic = false;
  for (const auto& clip : channel.clips) any_cubic |= clip && clip->interpolation == Interpolation::kCubicSpline;
  for (std::size_t t = 0; t < targets; ++t) {
    std::vector<double> times, values, in_slopes, out_slopes;
    std::vector<std::int64_t> in_types, out_types, offsets = {0};
    for (const auto& clip : channel.clips) {
      if (clip) {
        const TangentType type = clip->interpolation == Interpolation::kStep     ? TangentType::kStep
                                 : clip->interpolation == Interpolation::kLinear ? TangentType::kLinear
                                                                                 : TangentType::kFixed;
        for (std::size_t k = 0; k < clip->times.size(); ++k) {
          times.push_back(clip->times[k]);
          values.push_back(clip->values[k * targets + t]);
          in_types.push_back(static_cast<std::int64_t>(type));
          out_types.push_back(static_cast<std::int64_t>(type));
          const bool cubic = clip->interpolation == Interpolation::kCubicSpline;
          in_slopes.push_back(cubic ? clip->in_tangents[k * targets + t] : 0.0);
          out_slopes.push_back(cubic ? clip->out_tangents[k * targets + t] : 0.0);
        }
      }
      offsets.push_back(static_cast<std::int64_t>(times.size()));
    }
    if (!any_cubic) {  // no fixed tangents: the slope arrays stay empty
      in_slopes.clear();
      out_slopes.clear();
    }
    const double rest = !n.weights.empty() ? n.weights[t] : !mesh.weights.empty() ? mesh.weights[t] : 0.0;
    Result<NodeId> curve = g.create_node(ops::anim::kAnimCurveType, owner + "_weight" + std::to_string(t));
    if (!curve) return curve.status();
    Status s = set(*curve, ca::kKeyTimes, std::move(times));
    if (s) s = set(*curve, ca::kKeyValues, std::move(values));
    if (s) s = set(*curve, ca::kInTangentType, std::move(in_types));
    if (s) s = set(*curve, ca::kOutTangentType, std::move(out_types));
    if (s) s = set(*curve, ca::kInSlope, std::move(in_slopes));
    if (s) s = set(*curve, ca::kOutSlope, std::move(out_slopes));
    if (s) s = set(*curve, aa::kClipOffsets, std::move(offsets));
    if (s) s = set(*curve, aa::kRestValue, rest);
    if (s) s = connect(clips, ops::anim::clips_attr::kActiveClip, *curve, aa::kClip);
    for (NodeId shape : blend_shapes_[node]) {
      if (s) s = connect(*curve, ca::kOutput, shape, ops::blend_shape_attr::kWeights, static_cast<std::int32_t>(t));
    }
    if (!s) return s;
  }
  return Status::ok();
}

Status Importer::build_animations() {
  if (m_.animations.empty()) return Status::ok();
  Graph& g = scene_->graph();
  namespace ka = ops::anim::clips_attr;
  Result<NodeId> clips = g.create_node(ops::anim::kAnimClipsType, "clips");
  if (!clips) return clips.status();
  Status s = set(*clips, ka::kClipNames, clip_names_);
  if (s) s = set(*clips, ka::kClipStarts, clip_starts_);
  if (s) s = set(*clips, ka::kClipEnds, clip_ends_);
  if (s) s = set(*clips, ka::kActive, std::int64_t{0});
  if (!s) return s.with_context("animations");
  for (const Channel& channel : channels_) {
    const std::string where = "nodes[" + std::to_string(channel.node) + "]." + kPathNames[static_cast<int>(channel.path)] + " animation";
    s = channel.path == Path::kWeights ? build_weight_curves(channel, *clips) : build_track(channel, *clips);
    if (!s) return s.with_context(where);
  }
  return Status::ok();
}

Result<std::unique_ptr<scene::Scene>> Importer::run() {
  cache_.resize(m_.accessors.size());
  if (Status s = check_accessors(); !s) return s;
  if (Status s = check_hierarchy(); !s) return s;
  if (Status s = check_skins(); !s) return s;
  if (Status s = check_nodes(); !s) return s;
  if (Status s = check_scenes(); !s) return s;
  if (Status s = read_meshes(); !s) return s;
  if (Status s = read_animations(); !s) return s;
  scene_ = std::make_unique<scene::Scene>(options_.registry ? options_.registry : ops::default_registry());
  if (Status s = build_nodes(); !s) return s;
  if (Status s = build_meshes(); !s) return s;
  if (Status s = build_animations(); !s) return s;
  scene_->graph().clear_history();
  return std::move(scene_);
}

}  // namespace

Result<std::unique_ptr<scene::Scene>> import_gltf(const std::filesystem::path& path, const GltfImportOptions& options) {
  const std::string where = path.string();
  if (!(options.scale > 0.0) || !std::isfinite(options.scale))
    return error(ErrorCode::kInvalidArgument, where + ": glTF import: scale must be a positive number");
  try {
    Source source;
    if (Status s = read_file(path, source.bytes); !s) return s.with_context(where);
    if (Status s = parse_container(source); !s) return s.with_context(where);
    Result<Json> doc = parse_json(source.json);
    if (!doc) return doc.status().with_context(where);
    SchemaContext ctx;
    ctx.source = &source;
    // tinygltf's GetBaseDir: the text before the last separator.
    const std::size_t slash = where.find_last_of('/');
    ctx.base_dir = slash == std::string::npos ? std::string() : slash == 0 ? std::string("/") : where.substr(0, slash);
    std::error_code ec;
    Result<fs::path> folder = gltf_uri::resolved_folder(ctx.base_dir, where);
    if (!folder) return folder.status();
    ctx.folder = std::move(*folder);
    if (Status s = check_json(*doc, ctx); !s) return s.with_context(where);
    const Json images = doc->contains("images") ? doc->at("images") : Json();  // tinygltf never sees them
    Result<tinygltf::Model> model = load_model(std::move(*doc), source, ctx);
    if (!model) return model.status().with_context(where);
    Importer importer(*model, options, ctx.quantized);
    Result<std::unique_ptr<scene::Scene>> scene = importer.run();
    if (!scene) return scene.status().with_context(where);
    if (Status s = gltf_look::import_looks(**scene, *model, images, ctx.base_dir, importer.mesh_sources(),
                                           [&](int a) { return importer.accessor_values(a); });
        !s)
      return s.with_context(where);
    (*scene)->graph().clear_history();
    return scene;
  } catch (const std::bad_alloc&) {
    return error(ErrorCode::kIoError, where + ": out of memory");
  } catch (const std::exception& e) {
    return error(ErrorCode::kParseError, where + ": " + e.what());
  }
}

}  // namespace rigel::io
