#include "rigel/graph/uuid.h"

#include <cstdio>
#include <random>

namespace rigel::graph {

Uuid Uuid::generate() {
  thread_local std::mt19937_64 engine = [] {
    std::random_device device;
    std::seed_seq seed{device(), device(), device(), device(), device(), device()};
    return std::mt19937_64(seed);
  }();
  std::uint64_t hi = engine();
  std::uint64_t lo = engine();
  hi = (hi & ~0xf000ULL) | 0x4000ULL;                     // version 4
  lo = (lo & ~(0xc0ULL << 56)) | (0x80ULL << 56);         // variant 10xx
  return Uuid(hi, lo);
}

std::optional<Uuid> Uuid::parse(std::string_view text) {
  if (text.size() != 36) return std::nullopt;
  std::uint64_t parts[2] = {0, 0};
  int nibble = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    char c = text[i];
    if (i == 8 || i == 13 || i == 18 || i == 23) {
      if (c != '-') return std::nullopt;
      continue;
    }
    int v;
    if (c >= '0' && c <= '9') v = c - '0';
    else if (c >= 'a' && c <= 'f') v = c - 'a' + 10;
    else if (c >= 'A' && c <= 'F') v = c - 'A' + 10;
    else return std::nullopt;
    std::uint64_t& part = parts[nibble / 16];
    part = (part << 4) | static_cast<std::uint64_t>(v);
    ++nibble;
  }
  return Uuid(parts[0], parts[1]);
}

std::string Uuid::str() const {
  char buffer[37];
  std::snprintf(buffer, sizeof buffer, "%08x-%04x-%04x-%04x-%012llx", static_cast<unsigned>(hi_ >> 32),
                static_cast<unsigned>((hi_ >> 16) & 0xffff), static_cast<unsigned>(hi_ & 0xffff),
                static_cast<unsigned>(lo_ >> 48), static_cast<unsigned long long>(lo_ & 0xffffffffffffULL));
  return buffer;
}

}  // namespace rigel::graph
