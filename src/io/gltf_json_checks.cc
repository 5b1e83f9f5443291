#include "gltf_json_checks.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string_view>

#include "gltf_accessors.h"
#include "gltf_messages.h"
#include "gltf_uri.h"

namespace rigel::io::gltf_importer {
namespace {

namespace fs = std::filesystem;
using namespace gltf;  // layout constants and message places

// Offsets, lengths and counts: a .glb cannot exceed 4 GiB, nor can a buffer.
constexpr std::uint64_t kMaxSize = 0xffffffffull;
constexpr std::uint64_t kMaxInt = 0x7fffffffull;

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

}  // namespace

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

}  // namespace rigel::io::gltf_importer
