#include "gltf_container.h"

#include <bit>
#include <cstring>
#include <fstream>

#include "gltf_accessors.h"
#include "gltf_messages.h"
#include "gltf_uri.h"

namespace rigel::io::gltf_importer {
namespace {

namespace fs = std::filesystem;
using gltf::bad;
using gltf::load;

static_assert(std::endian::native == std::endian::little, "glTF buffers are little-endian; so is every target rigel builds for");

constexpr int kMaxJsonDepth = 128;
// Bound on JSON text handed to tinygltf (its length parameter is unsigned int).
constexpr std::uint64_t kMaxFileSize = 0xffffffffull;

constexpr std::uint32_t kGlbMagic = 0x46546C67;  // "glTF"
constexpr std::uint32_t kChunkJson = 0x4E4F534A;
constexpr std::uint32_t kChunkBin = 0x004E4942;

std::uint32_t u32(const std::vector<unsigned char>& bytes, std::size_t at) { return load<std::uint32_t>(bytes.data() + at); }

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

}  // namespace

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

}  // namespace rigel::io::gltf_importer
