#include "rigel/rig/version.h"

#include <algorithm>
#include <charconv>
#include <optional>
#include <vector>

namespace rigel::rig {
namespace {

std::vector<std::string_view> split_dots(std::string_view v) {
  std::vector<std::string_view> out;
  std::size_t start = 0;
  while (true) {
    std::size_t dot = v.find('.', start);
    out.push_back(v.substr(start, dot == std::string_view::npos ? std::string_view::npos : dot - start));
    if (dot == std::string_view::npos) break;
    start = dot + 1;
  }
  return out;
}

std::optional<unsigned long long> number(std::string_view s) {
  if (s.empty()) return std::nullopt;
  unsigned long long n = 0;
  auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), n);
  if (ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
  return n;
}

}  // namespace

int compare_versions(std::string_view a, std::string_view b) {
  const auto pa = split_dots(a), pb = split_dots(b);
  for (std::size_t i = 0; i < std::max(pa.size(), pb.size()); ++i) {
    const std::string_view x = i < pa.size() ? pa[i] : "0";
    const std::string_view y = i < pb.size() ? pb[i] : "0";
    const auto nx = number(x), ny = number(y);
    if (nx && ny) {
      if (*nx != *ny) return *nx < *ny ? -1 : 1;
    } else if (int c = x.compare(y); c != 0) {
      return c < 0 ? -1 : 1;
    }
  }
  return 0;
}

std::string bump_version(std::string_view version) {
  auto parts = split_dots(version);
  std::string out;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    if (i) out += '.';
    if (i + 1 == parts.size()) {
      if (auto n = number(parts[i])) {
        out += std::to_string(*n + 1);
      } else {
        out += std::string(parts[i]) + ".1";
      }
    } else {
      out += parts[i];
    }
  }
  return out.empty() ? "1" : out;
}

std::string next_version(std::string_view version) {
  std::size_t end = version.size();
  std::size_t begin = end;
  while (begin > 0 && version[begin - 1] >= '0' && version[begin - 1] <= '9') --begin;
  if (begin == end) return std::string(version) + (version.empty() ? "1" : ".1");
  std::string digits(version.substr(begin));
  // Add one to the decimal digits (any length).
  int carry = 1;
  for (std::size_t i = digits.size(); i-- > 0 && carry;) {
    const int d = digits[i] - '0' + carry;
    digits[i] = static_cast<char>('0' + d % 10);
    carry = d / 10;
  }
  if (carry) digits.insert(digits.begin(), '1');
  return std::string(version.substr(0, begin)) + digits;
}

}  // namespace rigel::rig
