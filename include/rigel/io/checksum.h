#pragma once
// The checksum rigel writes beside data it points at (a published rig's
// manifest, a weights file's binary side file): FNV-1a 64 of the bytes,
// as "fnv1a64:" and 16 hex digits. It tells a changed or truncated file
// from the one recorded; it is not a cryptographic hash.

#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>

namespace rigel::io {

class Checksum {
 public:
  void update(std::string_view bytes) {
    for (unsigned char c : bytes) h_ = (h_ ^ c) * 0x100000001b3ull;
  }
  std::string text() const {
    char out[32];
    std::snprintf(out, sizeof out, "fnv1a64:%016llx", static_cast<unsigned long long>(h_));
    return out;
  }

 private:
  std::uint64_t h_ = 0xcbf29ce484222325ull;
};

inline std::string checksum_of(std::string_view bytes) {
  Checksum c;
  c.update(bytes);
  return c.text();
}

}  // namespace rigel::io
