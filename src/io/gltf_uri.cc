#include "gltf_uri.h"

#include <algorithm>
#include <cctype>
#include <string_view>

namespace rigel::io::gltf_uri {
namespace fs = std::filesystem;

namespace {

Status bad(const std::string& where, const std::string& what) {
  return error(ErrorCode::kParseError, where + ": " + what);
}

std::string uri_text(std::string_view text, std::size_t limit = 60) {
  std::string out = "'";
  out += text.size() > limit ? std::string(text.substr(0, limit)) + "..." : std::string(text);
  return out + "'";
}

}  // namespace

std::string url_decode(const std::string& text) {
  auto hex = [](unsigned char c) -> unsigned char {
    if (c >= '0' && c <= '9') return static_cast<unsigned char>(c - '0');
    if (c >= 'a' && c <= 'f') return static_cast<unsigned char>(c - 'a' + 10);
    if (c >= 'A' && c <= 'F') return static_cast<unsigned char>(c - 'A' + 10);
    return 0;
  };
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '+') out += ' ';
    else if (text[i] == '%' && text.size() > i + 2) {
      out += static_cast<char>((hex(static_cast<unsigned char>(text[i + 1])) << 4) | hex(static_cast<unsigned char>(text[i + 2])));
      i += 2;
    } else out += text[i];
  }
  return out;
}

std::string join_path(const std::string& dir, const std::string& file) {
  if (dir.empty()) return file;
  return dir.back() == '/' ? dir + file : dir + "/" + file;
}

bool inside(const fs::path& folder, const fs::path& path) {
  auto f = folder.begin(), p = path.begin();
  for (; f != folder.end(); ++f, ++p) {
    if (p == path.end() || *f != *p) return false;
  }
  return p != path.end();
}

Result<fs::path> resolved_folder(const std::string& base_dir, const std::string& where) {
  std::error_code ec;
  fs::path folder = fs::weakly_canonical(base_dir.empty() ? fs::current_path(ec) : fs::path(base_dir), ec);
  if (ec) return error(ErrorCode::kIoError, where + ": cannot resolve the file's folder: " + ec.message());
  return folder;
}

Result<std::string> confined_file(const fs::path& folder, const std::string& base_dir, const std::string& uri,
                                  const std::string& where) {
  const std::string decoded = url_decode(uri);
  if (decoded.empty()) return bad(where, "an empty uri");
  if (decoded.find('\0') != std::string::npos) return bad(where, "uri " + uri_text(uri) + " holds a NUL character");
  // RFC 3986: scheme = ALPHA *( ALPHA / DIGIT / "+" / "-" / "." ) ":"
  const std::size_t colon = uri.find(':');
  if (colon != std::string::npos && colon > 0 && std::isalpha(static_cast<unsigned char>(uri[0]))) {
    const bool scheme = std::all_of(uri.begin(), uri.begin() + static_cast<std::ptrdiff_t>(colon), [](char c) {
      return std::isalnum(static_cast<unsigned char>(c)) || c == '+' || c == '-' || c == '.';
    });
    if (scheme)
      return error(ErrorCode::kUnsupported, where + ": uri " + uri_text(uri) +
                                                " has a scheme; rigel reads data: URIs and relative file names only");
  }
  const fs::path relative = fs::path(decoded).lexically_normal();
  if (decoded.front() == '/' || relative.is_absolute())
    return bad(where, "uri " + uri_text(uri) + " is an absolute path; only names relative to the glTF file's folder are read");
  if (relative.empty() || *relative.begin() == ".." || relative == ".")
    return bad(where, "uri " + uri_text(uri) + " reaches outside the glTF file's folder");
  const std::string file = join_path(base_dir, decoded);
  std::error_code ec;
  const fs::path real = fs::canonical(fs::path(file), ec);
  if (ec) return error(ErrorCode::kNotFound, where + ": missing (uri " + uri_text(uri) + " not found)");
  if (!inside(folder, real))
    return bad(where, "uri " + uri_text(uri) + " leads outside the glTF file's folder (through a symbolic link)");
  const fs::file_status status = fs::status(real, ec);
  if (ec || !fs::is_regular_file(status)) return error(ErrorCode::kNotFound, where + ": uri " + uri_text(uri) + " is not a file");
  return file;
}

}  // namespace rigel::io::gltf_uri
