#include "gltf_materials.h"
#include "gltf_accessors.h"
#include "gltf_uri.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <set>

#include "rigel/scene/materials.h"

namespace rigel::io::gltf_look {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;
using graph::AttrIndex;
using graph::Graph;
using graph::NodeId;
using graph::Plug;
using graph::Value;
namespace ma = scene::material_attr;
namespace ta = scene::texture_attr;
namespace la = scene::mesh_look_attr;

std::string at(const std::string& path, std::size_t index) { return path + "[" + std::to_string(index) + "]"; }
std::string dot(const std::string& path, std::string_view key) { return path + "." + std::string(key); }

Status bad(const std::string& where, const std::string& what) {
  return error(ErrorCode::kParseError, where + ": " + what);
}

std::string quote(std::string_view text, std::size_t limit = 60) {
  std::string out = "'";
  for (char c : text.substr(0, limit)) out += static_cast<unsigned char>(c) < 0x20 ? '?' : c;
  return out + (text.size() > limit ? "...'" : "'");
}

std::uint64_t pack(NodeId id) { return (std::uint64_t{id.generation} << 32) | id.index; }

// A name the graph accepts (the importer's rule for node names).
using gltf::node_name;

constexpr char kBase64[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

int base64_value(char c) {
  if (c >= 'A' && c <= 'Z') return c - 'A';
  if (c >= 'a' && c <= 'z') return c - 'a' + 26;
  if (c >= '0' && c <= '9') return c - '0' + 52;
  if (c == '+') return 62;
  if (c == '/') return 63;
  return -1;
}

// The MIME type of image bytes, from their signature; empty when unknown.
std::string sniff_mime(std::span<const unsigned char> b) {
  if (b.size() >= 8 && std::memcmp(b.data(), "\x89PNG\r\n\x1a\n", 8) == 0) return "image/png";
  if (b.size() >= 3 && b[0] == 0xFF && b[1] == 0xD8 && b[2] == 0xFF) return "image/jpeg";
  if (b.size() >= 12 && std::memcmp(b.data(), "RIFF", 4) == 0 && std::memcmp(b.data() + 8, "WEBP", 4) == 0) return "image/webp";
  if (b.size() >= 12 && std::memcmp(b.data(), "\xABKTX 20\xBB\r\n\x1a\n", 12) == 0) return "image/ktx2";
  return {};
}

// ---- import ----

struct ImageData {
  std::string name, mime_type;
  std::vector<unsigned char> bytes;
};

// A file named by a relative URI, under the importer's rule for external
// files (gltf_uri::confined_file); anything else is refused without reading it.
Status read_confined(const std::string& base_dir, const std::string& uri, const std::string& where,
                     std::vector<unsigned char>& out) {
  Result<fs::path> folder = gltf_uri::resolved_folder(base_dir, where);
  if (!folder) return folder.status();
  Result<std::string> confined = gltf_uri::confined_file(*folder, base_dir, uri, where);
  if (!confined) return confined.status();
  const fs::path file(*confined);
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(file, ec);
  if (ec) return error(ErrorCode::kIoError, where + ": " + quote(uri) + ": cannot read the file size");
  if (size > kMaxImageBytes)
    return error(ErrorCode::kUnsupported, where + ": " + quote(uri) + " is larger than " +
                                              std::to_string(kMaxImageBytes >> 20) + " MiB");
  std::ifstream in(file, std::ios::binary);
  out.resize(static_cast<std::size_t>(size));
  if (!in || !in.read(reinterpret_cast<char*>(out.data()), static_cast<std::streamsize>(size)))
    return error(ErrorCode::kIoError, where + ": " + quote(uri) + " cannot be read");
  return Status::ok();
}

Result<ImageData> read_image(const Json& image, std::size_t index, const tinygltf::Model& model, const std::string& base_dir) {
  const std::string path = at("images", index);
  ImageData out;
  for (const char* key : {"name", "mimeType", "uri"}) {
    if (image.contains(key) && !image.at(key).is_string()) return bad(dot(path, key), "must be a string");
  }
  if (image.contains("name")) out.name = image.at("name").get<std::string>();
  if (image.contains("mimeType")) out.mime_type = image.at("mimeType").get<std::string>();
  const bool has_view = image.contains("bufferView"), has_uri = image.contains("uri");
  if (has_view == has_uri) return bad(path, "needs exactly one of uri and bufferView");
  if (has_view) {
    // The index was range-checked with the file's JSON; the view against its buffer.
    const Json& v = image.at("bufferView");
    if (!v.is_number_integer() || v.get<std::int64_t>() < 0 ||
        v.get<std::uint64_t>() >= model.bufferViews.size())
      return bad(dot(path, "bufferView"), "not a bufferView of this file");
    const tinygltf::BufferView& view = model.bufferViews[v.get<std::size_t>()];
    const std::vector<unsigned char>& data = model.buffers[static_cast<std::size_t>(view.buffer)].data;
    if (view.byteOffset + view.byteLength > data.size()) return bad(dot(path, "bufferView"), "reaches past its buffer");
    const auto begin = data.begin() + static_cast<std::ptrdiff_t>(view.byteOffset);
    out.bytes.assign(begin, begin + static_cast<std::ptrdiff_t>(view.byteLength));
  } else {
    const std::string uri = image.at("uri").get<std::string>();
    if (uri.rfind("data:", 0) == 0) {
      const std::size_t comma = uri.find(',');
      const std::string header = uri.substr(0, comma == std::string::npos ? 0 : comma);
      if (comma == std::string::npos || header.size() < 12 || header.compare(header.size() - 7, 7, ";base64") != 0)
        return bad(dot(path, "uri"), "unsupported data URI " + quote(uri, 40) + " (base64 expected)");
      Result<std::vector<unsigned char>> bytes = base64_decode(std::string_view(uri).substr(comma + 1));
      if (!bytes) return bytes.status().with_context(dot(path, "uri"));
      out.bytes = std::move(*bytes);
      if (out.mime_type.empty()) out.mime_type = header.substr(5, header.size() - 12);
    } else if (Status s = read_confined(base_dir, uri, dot(path, "uri"), out.bytes); !s) {
      return s;
    }
  }
  if (out.mime_type.empty()) out.mime_type = sniff_mime(out.bytes);
  return out;
}

class LookImporter {
 public:
  LookImporter(scene::Scene& scene, const tinygltf::Model& model, const Json& images, const std::string& base_dir,
               const AccessorReader& read)
      : g_(scene.graph()), m_(model), images_(images), base_dir_(base_dir), read_(read) {}

  Status run(std::span<const MeshSource> meshes) {
    // Which materials the mesh nodes use, checked first.
    std::vector<int> used(m_.materials.size(), 0);
    for (const MeshSource& source : meshes) {
      const tinygltf::Primitive& prim = m_.meshes[source.gltf_mesh].primitives[source.primitive];
      if (prim.material < 0) continue;
      if (static_cast<std::size_t>(prim.material) >= m_.materials.size())
        return bad(dot(primitive_path(source), "material"), "material " + std::to_string(prim.material) + " does not exist");
      used[static_cast<std::size_t>(prim.material)] = 1;
    }
    texture_ids_.assign(m_.textures.size(), NodeId{});
    material_ids_.assign(m_.materials.size(), NodeId{});
    for (std::size_t i = 0; i < m_.materials.size(); ++i) {
      if (used[i]) {
        if (Status s = check_material(i); !s) return s;
      }
    }
    for (std::size_t t = 0; t < m_.textures.size(); ++t) {
      if (texture_used_.count(t)) {
        if (Status s = build_texture(t); !s) return s;
      }
    }
    for (std::size_t i = 0; i < m_.materials.size(); ++i) {
      if (used[i]) {
        if (Status s = build_material(i); !s) return s;
      }
    }
    for (const MeshSource& source : meshes) {
      if (Status s = build_mesh_look(source); !s) return s;
    }
    return Status::ok();
  }

 private:
  static std::string primitive_path(const MeshSource& s) {
    return at(dot(at("meshes", s.gltf_mesh), "primitives"), s.primitive);
  }

  Status set(NodeId node, AttrIndex attr, Value value) { return g_.set_value(Plug{node, attr, -1}, std::move(value)); }
  Status connect(NodeId src, AttrIndex src_attr, NodeId dst, AttrIndex dst_attr) {
    return g_.connect(Plug{src, src_attr, -1}, Plug{dst, dst_attr, -1});
  }

  Status check_texture_info(int index, int tex_coord, const std::string& where) {
    if (index < 0) return Status::ok();
    if (static_cast<std::size_t>(index) >= m_.textures.size())
      return bad(dot(where, "index"), "texture " + std::to_string(index) + " does not exist");
    if (tex_coord < 0) return bad(dot(where, "texCoord"), "must be 0 or more, not " + std::to_string(tex_coord));
    texture_used_.insert(static_cast<std::size_t>(index));
    return Status::ok();
  }

  static Status check_unit(double v, const std::string& where) {
    if (!std::isfinite(v) || v < 0.0 || v > 1.0) return bad(where, "must be in [0, 1]");
    return Status::ok();
  }

  Status check_material(std::size_t i) {
    const tinygltf::Material& mat = m_.materials[i];
    const std::string path = at("materials", i);
    const std::string pbr = dot(path, "pbrMetallicRoughness");
    const auto& p = mat.pbrMetallicRoughness;
    if (p.baseColorFactor.size() != 4) return bad(dot(pbr, "baseColorFactor"), "must hold 4 numbers");
    for (std::size_t k = 0; k < 4; ++k) {
      if (Status s = check_unit(p.baseColorFactor[k], at(dot(pbr, "baseColorFactor"), k)); !s) return s;
    }
    if (Status s = check_unit(p.metallicFactor, dot(pbr, "metallicFactor")); !s) return s;
    if (Status s = check_unit(p.roughnessFactor, dot(pbr, "roughnessFactor")); !s) return s;
    if (!mat.emissiveFactor.empty() && mat.emissiveFactor.size() != 3) return bad(dot(path, "emissiveFactor"), "must hold 3 numbers");
    for (std::size_t k = 0; k < mat.emissiveFactor.size(); ++k) {
      if (!std::isfinite(mat.emissiveFactor[k]) || mat.emissiveFactor[k] < 0.0)
        return bad(at(dot(path, "emissiveFactor"), k), "must be a finite number >= 0");
    }
    if (mat.alphaMode != "OPAQUE" && mat.alphaMode != "MASK" && mat.alphaMode != "BLEND")
      return bad(dot(path, "alphaMode"), quote(mat.alphaMode) + " is not OPAQUE, MASK or BLEND");
    if (!std::isfinite(mat.alphaCutoff) || mat.alphaCutoff < 0.0) return bad(dot(path, "alphaCutoff"), "must be a finite number >= 0");
    if (!std::isfinite(mat.normalTexture.scale)) return bad(dot(dot(path, "normalTexture"), "scale"), "must be finite");
    if (Status s = check_unit(mat.occlusionTexture.strength, dot(dot(path, "occlusionTexture"), "strength")); !s) return s;
    if (Status s = check_texture_info(p.baseColorTexture.index, p.baseColorTexture.texCoord, dot(pbr, "baseColorTexture")); !s) return s;
    if (Status s = check_texture_info(p.metallicRoughnessTexture.index, p.metallicRoughnessTexture.texCoord,
                                      dot(pbr, "metallicRoughnessTexture"));
        !s)
      return s;
    if (Status s = check_texture_info(mat.normalTexture.index, mat.normalTexture.texCoord, dot(path, "normalTexture")); !s) return s;
    if (Status s = check_texture_info(mat.occlusionTexture.index, mat.occlusionTexture.texCoord, dot(path, "occlusionTexture")); !s)
      return s;
    return check_texture_info(mat.emissiveTexture.index, mat.emissiveTexture.texCoord, dot(path, "emissiveTexture"));
  }

  Status build_texture(std::size_t t) {
    const tinygltf::Texture& tex = m_.textures[t];
    const std::string path = at("textures", t);
    const std::size_t image_count = images_.is_array() ? images_.size() : 0;
    std::optional<ImageData> image;
    if (tex.source >= 0) {
      if (static_cast<std::size_t>(tex.source) >= image_count)
        return bad(dot(path, "source"), "image " + std::to_string(tex.source) + " does not exist");
      const auto source = static_cast<std::size_t>(tex.source);
      if (!images_[source].is_object()) return bad(at("images", source), "must be an object");
      Result<ImageData> read = read_image(images_[source], source, m_, base_dir_);
      if (!read) return read.status();
      image = std::move(*read);
    }
    const tinygltf::Sampler* sampler = nullptr;
    if (tex.sampler >= 0) {
      if (static_cast<std::size_t>(tex.sampler) >= m_.samplers.size())
        return bad(dot(path, "sampler"), "sampler " + std::to_string(tex.sampler) + " does not exist");
      sampler = &m_.samplers[static_cast<std::size_t>(tex.sampler)];
    }
    const std::string fallback = "texture_" + std::to_string(t);
    const std::string wanted = !tex.name.empty() ? tex.name : image && !image->name.empty() ? image->name : fallback;
    Result<NodeId> node = g_.create_node(scene::kTextureType, node_name(wanted, fallback));
    if (!node) return node.status().with_context(path);
    Status s = Status::ok();
    if (image) {
      s = set(*node, ta::kImage, base64_encode(image->bytes));
      if (s) s = set(*node, ta::kMimeType, image->mime_type);
      if (s) s = set(*node, ta::kImageName, image->name);
    }
    if (s && sampler) {
      s = set(*node, ta::kMagFilter, std::int64_t{std::max(sampler->magFilter, 0)});
      if (s) s = set(*node, ta::kMinFilter, std::int64_t{std::max(sampler->minFilter, 0)});
      if (s) s = set(*node, ta::kWrapS, std::int64_t{sampler->wrapS});
      if (s) s = set(*node, ta::kWrapT, std::int64_t{sampler->wrapT});
    }
    if (!s) return s.with_context(path);
    texture_ids_[t] = *node;
    return Status::ok();
  }

  Status slot(NodeId material, int index, int tex_coord, AttrIndex texture_attr, AttrIndex tex_coord_attr) {
    if (index < 0) return Status::ok();
    Status s = connect(texture_ids_[static_cast<std::size_t>(index)], ta::kMessage, material, texture_attr);
    if (s && tex_coord != 0) s = set(material, tex_coord_attr, std::int64_t{tex_coord});
    return s;
  }

  Status build_material(std::size_t i) {
    const tinygltf::Material& mat = m_.materials[i];
    const std::string path = at("materials", i);
    const std::string fallback = "material_" + std::to_string(i);
    Result<NodeId> node = g_.create_node(scene::kMaterialType, node_name(mat.name, fallback));
    if (!node) return node.status().with_context(path);
    const NodeId id = *node;
    const auto& p = mat.pbrMetallicRoughness;
    Status s = set(id, ma::kBaseColorFactor, p.baseColorFactor);
    if (s) s = set(id, ma::kMetallicFactor, p.metallicFactor);
    if (s) s = set(id, ma::kRoughnessFactor, p.roughnessFactor);
    if (s) s = set(id, ma::kNormalScale, mat.normalTexture.scale);
    if (s) s = set(id, ma::kOcclusionStrength, mat.occlusionTexture.strength);
    if (s && mat.emissiveFactor.size() == 3)
      s = set(id, ma::kEmissiveFactor, math::Vec3(mat.emissiveFactor[0], mat.emissiveFactor[1], mat.emissiveFactor[2]));
    if (s) s = set(id, ma::kAlphaMode, std::int64_t{mat.alphaMode == "MASK" ? 1 : mat.alphaMode == "BLEND" ? 2 : 0});
    if (s) s = set(id, ma::kAlphaCutoff, mat.alphaCutoff);
    if (s) s = set(id, ma::kDoubleSided, mat.doubleSided);
    if (s) s = slot(id, p.baseColorTexture.index, p.baseColorTexture.texCoord, ma::kBaseColorTexture, ma::kBaseColorTexCoord);
    if (s)
      s = slot(id, p.metallicRoughnessTexture.index, p.metallicRoughnessTexture.texCoord, ma::kMetallicRoughnessTexture,
               ma::kMetallicRoughnessTexCoord);
    if (s) s = slot(id, mat.normalTexture.index, mat.normalTexture.texCoord, ma::kNormalTexture, ma::kNormalTexCoord);
    if (s) s = slot(id, mat.occlusionTexture.index, mat.occlusionTexture.texCoord, ma::kOcclusionTexture, ma::kOcclusionTexCoord);
    if (s) s = slot(id, mat.emissiveTexture.index, mat.emissiveTexture.texCoord, ma::kEmissiveTexture, ma::kEmissiveTexCoord);
    if (!s) return s.with_context(path);
    material_ids_[i] = id;
    return Status::ok();
  }

  Status build_mesh_look(const MeshSource& source) {
    const tinygltf::Primitive& prim = m_.meshes[source.gltf_mesh].primitives[source.primitive];
    const std::string attr_path = dot(primitive_path(source), "attributes");
    for (const auto& [semantic, attr] : {std::pair{"TEXCOORD_0", la::kUv0}, std::pair{"TEXCOORD_1", la::kUv1}}) {
      auto it = prim.attributes.find(semantic);
      if (it == prim.attributes.end()) continue;
      const tinygltf::Accessor& a = m_.accessors[static_cast<std::size_t>(it->second)];
      if (a.type != TINYGLTF_TYPE_VEC2)
        return bad(dot(attr_path, semantic), "accessors[" + std::to_string(it->second) + "] is not VEC2");
      auto values = read_(it->second);
      if (!values) return values.status().with_context(dot(attr_path, semantic));
      if (Status s = set(source.mesh, attr, **values); !s) return s.with_context(dot(attr_path, semantic));
    }
    if (auto it = prim.attributes.find("COLOR_0"); it != prim.attributes.end()) {
      const tinygltf::Accessor& a = m_.accessors[static_cast<std::size_t>(it->second)];
      const bool float_or_normalized = a.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT ||
                                       (a.normalized && (a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                                                         a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT));
      if ((a.type != TINYGLTF_TYPE_VEC3 && a.type != TINYGLTF_TYPE_VEC4) || !float_or_normalized)
        return bad(dot(attr_path, "COLOR_0"), "accessors[" + std::to_string(it->second) +
                                                  "] is not VEC3 or VEC4 of FLOAT or normalized UNSIGNED_BYTE/SHORT");
      auto values = read_(it->second);
      if (!values) return values.status().with_context(dot(attr_path, "COLOR_0"));
      const std::size_t width = a.type == TINYGLTF_TYPE_VEC3 ? 3 : 4;
      std::vector<double> rgba;
      rgba.reserve(a.count * 4);
      for (std::size_t v = 0; v < a.count; ++v) {
        for (std::size_t k = 0; k < width; ++k) rgba.push_back((**values)[v * width + k]);
        if (width == 3) rgba.push_back(1.0);
      }
      if (Status s = set(source.mesh, la::kColors, std::move(rgba)); !s) return s.with_context(dot(attr_path, "COLOR_0"));
    }
    if (prim.material >= 0) {
      if (Status s = connect(material_ids_[static_cast<std::size_t>(prim.material)], ma::kMessage, source.mesh, la::kMaterial); !s)
        return s.with_context(dot(primitive_path(source), "material"));
    }
    return Status::ok();
  }

  Graph& g_;
  const tinygltf::Model& m_;
  const Json& images_;
  const std::string& base_dir_;
  const AccessorReader& read_;
  std::set<std::size_t> texture_used_;
  std::vector<NodeId> texture_ids_, material_ids_;
};

}  // namespace

std::string base64_encode(std::span<const unsigned char> bytes) {
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const std::uint32_t v = (std::uint32_t{bytes[i]} << 16) | (std::uint32_t{bytes[i + 1]} << 8) | bytes[i + 2];
    for (int k = 18; k >= 0; k -= 6) out += kBase64[(v >> k) & 63];
  }
  if (i < bytes.size()) {
    const bool two = i + 1 < bytes.size();
    const std::uint32_t v = (std::uint32_t{bytes[i]} << 16) | (two ? std::uint32_t{bytes[i + 1]} << 8 : 0u);
    out += kBase64[(v >> 18) & 63];
    out += kBase64[(v >> 12) & 63];
    out += two ? kBase64[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

Result<std::vector<unsigned char>> base64_decode(std::string_view text) {
  if (text.size() % 4 != 0)
    return error(ErrorCode::kParseError, "base64 of length " + std::to_string(text.size()) + ", not a multiple of 4");
  std::vector<unsigned char> out;
  out.reserve(text.size() / 4 * 3);
  for (std::size_t i = 0; i < text.size(); i += 4) {
    int v[4];
    int padding = 0;
    for (std::size_t k = 0; k < 4; ++k) {
      const char c = text[i + k];
      const bool last_group = i + 4 == text.size();
      if (c == '=' && last_group && k >= 2 && (k == 3 || text[i + 3] == '=')) {
        v[k] = 0;
        ++padding;
        continue;
      }
      v[k] = base64_value(c);
      if (v[k] < 0 || padding > 0) return error(ErrorCode::kParseError, "not base64 at character " + std::to_string(i + k));
    }
    const std::uint32_t bits = (std::uint32_t(v[0]) << 18) | (std::uint32_t(v[1]) << 12) | (std::uint32_t(v[2]) << 6) | std::uint32_t(v[3]);
    out.push_back(static_cast<unsigned char>(bits >> 16));
    if (padding < 2) out.push_back(static_cast<unsigned char>((bits >> 8) & 0xFF));
    if (padding < 1) out.push_back(static_cast<unsigned char>(bits & 0xFF));
  }
  return out;
}

Status import_looks(scene::Scene& scene, const tinygltf::Model& model, const Json& images, const std::string& base_dir,
                    std::span<const MeshSource> meshes, const AccessorReader& read) {
  LookImporter importer(scene, model, images, base_dir, read);
  return importer.run(meshes);
}

// ---- export ----

int LookWriter::view(const void* data, std::size_t size, int target) {
  return gltf::append_view(model_, bytes_, data, size, target);
}

Result<int> LookWriter::floats(const std::vector<double>& values, int type, int components, const std::string& what) {
  std::vector<float> data(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) {
    data[i] = static_cast<float>(values[i]);
    if (!std::isfinite(data[i]))
      return error(ErrorCode::kInvalidArgument, what + ": value " + std::to_string(values[i]) + " at " + std::to_string(i) +
                                                    " is not a finite 32-bit float");
  }
  return gltf::append_accessor(model_, view(data.data(), data.size() * sizeof(float), TINYGLTF_TARGET_ARRAY_BUFFER),
                               gltf::kFloat, type, values.size() / static_cast<std::size_t>(components));
}

Result<int> LookWriter::texture(NodeId node) {
  if (auto it = textures_.find(pack(node)); it != textures_.end()) return it->second;
  const graph::Node& n = *g_.node(node);
  int index = -1;
  auto text = [&](AttrIndex a) { return std::get<std::string>(g_.evaluate(node, a)); };
  auto integer = [&](AttrIndex a) { return static_cast<int>(std::get<std::int64_t>(g_.evaluate(node, a))); };
  if (n.type().name() != scene::kTextureType) {
    notes_.push_back(n.name() + ": feeds a material's texture but is a " + n.type().name() + ", not a texture; left out");
  } else if (text(ta::kImage).empty()) {
    notes_.push_back(n.name() + ": a texture without an image is left out");
  } else {
    Result<std::vector<unsigned char>> bytes = base64_decode(text(ta::kImage));
    if (!bytes) return bytes.status().with_context(n.name() + ".image");
    std::string mime = text(ta::kMimeType);
    if (mime.empty()) mime = sniff_mime(*bytes);
    if (mime != "image/png" && mime != "image/jpeg") {
      notes_.push_back(n.name() + ": " + (mime.empty() ? std::string("an image of unknown type") : mime) +
                       " is left out (glTF's core images are PNG and JPEG)");
    } else {
      std::string key(bytes->begin(), bytes->end());
      int image = -1;
      if (auto found = images_.find(key); found != images_.end()) {
        image = found->second;
      } else {
        tinygltf::Image img;
        img.name = text(ta::kImageName);
        img.mimeType = mime;
        img.bufferView = view(bytes->data(), bytes->size(), 0);
        model_.images.push_back(std::move(img));
        image = static_cast<int>(model_.images.size()) - 1;
        images_.emplace(std::move(key), image);
      }
      tinygltf::Texture tex;
      tex.name = n.name();
      tex.source = image;
      const auto sampler_key = std::make_tuple(integer(ta::kMagFilter), integer(ta::kMinFilter), integer(ta::kWrapS), integer(ta::kWrapT));
      if (sampler_key != std::make_tuple(0, 0, TINYGLTF_TEXTURE_WRAP_REPEAT, TINYGLTF_TEXTURE_WRAP_REPEAT)) {
        if (auto found = samplers_.find(sampler_key); found != samplers_.end()) {
          tex.sampler = found->second;
        } else {
          tinygltf::Sampler sampler;
          const auto [mag, min, wrap_s, wrap_t] = sampler_key;
          auto one_of = [](int v, std::initializer_list<int> allowed) { return std::find(allowed.begin(), allowed.end(), v) != allowed.end(); };
          sampler.magFilter = one_of(mag, {9728, 9729}) ? mag : -1;
          sampler.minFilter = one_of(min, {9728, 9729, 9984, 9985, 9986, 9987}) ? min : -1;
          sampler.wrapS = one_of(wrap_s, {33071, 33648, 10497}) ? wrap_s : TINYGLTF_TEXTURE_WRAP_REPEAT;
          sampler.wrapT = one_of(wrap_t, {33071, 33648, 10497}) ? wrap_t : TINYGLTF_TEXTURE_WRAP_REPEAT;
          if ((mag != 0 && sampler.magFilter < 0) || (min != 0 && sampler.minFilter < 0) || sampler.wrapS != wrap_s ||
              sampler.wrapT != wrap_t)
            notes_.push_back(n.name() + ": sampler codes that glTF does not define are written as the defaults");
          model_.samplers.push_back(sampler);
          tex.sampler = static_cast<int>(model_.samplers.size()) - 1;
          samplers_.emplace(sampler_key, tex.sampler);
        }
      }
      model_.textures.push_back(std::move(tex));
      index = static_cast<int>(model_.textures.size()) - 1;
    }
  }
  textures_.emplace(pack(node), index);
  return index;
}

Result<int> LookWriter::material(NodeId node) {
  if (auto it = materials_.find(pack(node)); it != materials_.end()) return it->second;
  const graph::Node& n = *g_.node(node);
  if (n.type().name() != scene::kMaterialType) {
    notes_.push_back(n.name() + ": feeds a mesh's material but is a " + n.type().name() + ", not a material; left out");
    materials_.emplace(pack(node), -1);
    return -1;
  }
  auto number = [&](AttrIndex a) { return std::get<double>(g_.evaluate(node, a)); };
  auto integer = [&](AttrIndex a) { return std::get<std::int64_t>(g_.evaluate(node, a)); };
  bool clamped = false;
  auto unit = [&](double v) {
    const double c = std::isfinite(v) ? std::clamp(v, 0.0, 1.0) : 1.0;
    clamped |= c != v;
    return c;
  };
  tinygltf::Material mat;
  mat.name = n.name();
  std::vector<double> base = std::get<std::vector<double>>(g_.evaluate(node, ma::kBaseColorFactor));
  if (base.size() != 4) {
    notes_.push_back(n.name() + ".baseColorFactor: " + std::to_string(base.size()) + " numbers, not 4; written as 1 1 1 1");
    base = {1.0, 1.0, 1.0, 1.0};
  }
  for (double& v : base) v = unit(v);
  mat.pbrMetallicRoughness.baseColorFactor = base;
  mat.pbrMetallicRoughness.metallicFactor = unit(number(ma::kMetallicFactor));
  mat.pbrMetallicRoughness.roughnessFactor = unit(number(ma::kRoughnessFactor));
  const math::Vec3 emissive = std::get<math::Vec3>(g_.evaluate(node, ma::kEmissiveFactor));
  std::vector<double> e = {emissive.x(), emissive.y(), emissive.z()};
  for (double& v : e) v = unit(v);
  if (e != std::vector<double>{0.0, 0.0, 0.0}) mat.emissiveFactor = e;
  const std::int64_t mode = integer(ma::kAlphaMode);
  mat.alphaMode = mode == 1 ? "MASK" : mode == 2 ? "BLEND" : "OPAQUE";
  const double cutoff = number(ma::kAlphaCutoff);
  mat.alphaCutoff = std::isfinite(cutoff) && cutoff >= 0.0 ? cutoff : 0.5;
  mat.doubleSided = std::get<bool>(g_.evaluate(node, ma::kDoubleSided));
  std::vector<int> sets;
  // One texture slot: the texture fed into `attr`, and its uv set.
  auto slot = [&](AttrIndex attr, AttrIndex tex_coord, int& index, int& set) -> Status {
    std::optional<Plug> src = g_.source(Plug{node, attr, -1});
    if (!src) return Status::ok();
    Result<int> t = texture(src->node);
    if (!t) return t.status();
    if (*t < 0) return Status::ok();
    const std::int64_t c = integer(tex_coord);
    if (c < 0 || c > 1) {
      notes_.push_back(n.name() + "." + n.type().attr(tex_coord).name + ": uv set " + std::to_string(c) +
                       " is not one rigel keeps (0 or 1); the texture is left out");
      return Status::ok();
    }
    index = *t;
    set = static_cast<int>(c);
    sets.push_back(set);
    return Status::ok();
  };
  auto& p = mat.pbrMetallicRoughness;
  Status s = slot(ma::kBaseColorTexture, ma::kBaseColorTexCoord, p.baseColorTexture.index, p.baseColorTexture.texCoord);
  if (s) s = slot(ma::kMetallicRoughnessTexture, ma::kMetallicRoughnessTexCoord, p.metallicRoughnessTexture.index,
                  p.metallicRoughnessTexture.texCoord);
  if (s) s = slot(ma::kNormalTexture, ma::kNormalTexCoord, mat.normalTexture.index, mat.normalTexture.texCoord);
  if (s) s = slot(ma::kOcclusionTexture, ma::kOcclusionTexCoord, mat.occlusionTexture.index, mat.occlusionTexture.texCoord);
  if (s) s = slot(ma::kEmissiveTexture, ma::kEmissiveTexCoord, mat.emissiveTexture.index, mat.emissiveTexture.texCoord);
  if (!s) return s;
  if (mat.normalTexture.index >= 0) mat.normalTexture.scale = number(ma::kNormalScale);
  if (mat.occlusionTexture.index >= 0) mat.occlusionTexture.strength = unit(number(ma::kOcclusionStrength));
  if (clamped) notes_.push_back(n.name() + ": factors outside [0, 1] are clamped (glTF's range)");
  model_.materials.push_back(std::move(mat));
  const int index = static_cast<int>(model_.materials.size()) - 1;
  materials_.emplace(pack(node), index);
  material_uv_sets_[index] = std::move(sets);
  return index;
}

Status LookWriter::write(NodeId mesh, int gltf_mesh) {
  const std::string& mesh_name = name(mesh);
  for (tinygltf::Primitive& prim : model_.meshes[static_cast<std::size_t>(gltf_mesh)].primitives) {
    auto position = prim.attributes.find("POSITION");
    if (position == prim.attributes.end()) continue;
    const std::size_t count = model_.accessors[static_cast<std::size_t>(position->second)].count;
    // Per-point arrays: one element per point, else left out (as normals are).
    auto per_point = [&](AttrIndex attr, std::size_t width) -> const std::vector<double>* {
      const auto& values = std::get<std::vector<double>>(g_.evaluate(mesh, attr));
      if (values.empty()) return nullptr;
      if (values.size() != count * width) {
        notes_.push_back(mesh_name + "." + g_.node(mesh)->type().attr(attr).name + ": " + std::to_string(values.size()) +
                         " numbers for " + std::to_string(count) + " points (" + std::to_string(width) +
                         " per point expected) are left out");
        return nullptr;
      }
      return &values;
    };
    int sets = 0;
    if (const std::vector<double>* uv0 = per_point(la::kUv0, 2)) {
      Result<int> a = floats(*uv0, TINYGLTF_TYPE_VEC2, 2, mesh_name + ".uv0");
      if (!a) return a.status();
      prim.attributes["TEXCOORD_0"] = *a;
      sets = 1;
      if (const std::vector<double>* uv1 = per_point(la::kUv1, 2)) {
        Result<int> b = floats(*uv1, TINYGLTF_TYPE_VEC2, 2, mesh_name + ".uv1");
        if (!b) return b.status();
        prim.attributes["TEXCOORD_1"] = *b;
        sets = 2;
      }
    } else if (!std::get<std::vector<double>>(g_.evaluate(mesh, la::kUv1)).empty()) {
      notes_.push_back(mesh_name + ".uv1: left out, because glTF numbers uv sets from 0 and uv0 is not written");
    }
    if (const std::vector<double>* colors = per_point(la::kColors, 4)) {
      std::vector<double> rgba = *colors;
      bool clamped = false;
      for (double& c : rgba) {
        if (c >= 0.0 && c <= 1.0) continue;
        c = std::isfinite(c) ? std::clamp(c, 0.0, 1.0) : 1.0;
        clamped = true;
      }
      if (clamped) notes_.push_back(mesh_name + ".colors: values outside [0, 1] are clamped (glTF's range)");
      bool opaque = true;
      for (std::size_t v = 0; v < count; ++v) opaque &= rgba[4 * v + 3] == 1.0;
      const std::size_t width = opaque ? 3 : 4;  // alpha 1 everywhere: RGB, as most files have it
      std::vector<double> values;
      values.reserve(width * count);
      for (std::size_t v = 0; v < count; ++v)
        for (std::size_t k = 0; k < width; ++k) values.push_back(rgba[4 * v + k]);
      Result<int> a = floats(values, opaque ? TINYGLTF_TYPE_VEC3 : TINYGLTF_TYPE_VEC4, static_cast<int>(width), mesh_name + ".colors");
      if (!a) return a.status();
      prim.attributes["COLOR_0"] = *a;
    }
    std::optional<Plug> src = g_.source(Plug{mesh, la::kMaterial, -1});
    if (!src) continue;
    Result<int> m = material(src->node);
    if (!m) return m.status();
    if (*m < 0) continue;
    const std::vector<int>& needed = material_uv_sets_[*m];
    const auto missing = std::find_if(needed.begin(), needed.end(), [&](int set) { return set >= sets; });
    if (missing != needed.end()) {
      notes_.push_back(mesh_name + ": its material " + name(src->node) + " reads uv set " + std::to_string(*missing) +
                       ", which the mesh lacks; the mesh is written without material");
      continue;
    }
    prim.material = *m;
  }
  return Status::ok();
}

}  // namespace rigel::io::gltf_look
