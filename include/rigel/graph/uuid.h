#pragma once
// Stable node identity. Names are for people; everything a build or an
// update relies on refers to nodes by UUID (DESIGN.md, Conventions).

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>

namespace rigel::graph {

class Uuid {
 public:
  Uuid() = default;  // the nil UUID
  // A random (version 4) UUID.
  static Uuid generate();
  // Parses the canonical 8-4-4-4-12 hexadecimal form; nullopt otherwise.
  static std::optional<Uuid> parse(std::string_view text);

  bool is_nil() const { return hi_ == 0 && lo_ == 0; }
  std::string str() const;

  friend bool operator==(const Uuid&, const Uuid&) = default;
  friend auto operator<=>(const Uuid&, const Uuid&) = default;
  std::size_t hash() const { return std::hash<std::uint64_t>{}(hi_ ^ (lo_ * 0x9e3779b97f4a7c15ULL)); }

 private:
  Uuid(std::uint64_t hi, std::uint64_t lo) : hi_(hi), lo_(lo) {}
  std::uint64_t hi_ = 0;
  std::uint64_t lo_ = 0;
};

struct UuidHash {
  std::size_t operator()(const Uuid& u) const { return u.hash(); }
};

}  // namespace rigel::graph
