#include "rigel/io/diffable_json.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <ostream>

namespace rigel::io {

namespace {

using Json = nlohmann::ordered_json;

bool is_scalar(const Json& j) { return !j.is_array() && !j.is_object(); }

// A value with nothing nested but arrays of scalars.
bool is_flat(const Json& j) {
  if (is_scalar(j)) return true;
  if (j.is_array()) return std::all_of(j.begin(), j.end(), is_scalar);
  return std::all_of(j.begin(), j.end(), [](const Json& v) { return is_scalar(v) || (v.is_array() && is_flat(v)); });
}

std::string default_scalar(const Json& j) { return j.dump(-1, ' ', false, Json::error_handler_t::replace); }

// A string that nlohmann writes as it is between quotes (printable ASCII,
// no quote or backslash; it escapes below 0x20 and checks UTF-8 above 0x7f).
bool is_plain(const std::string& s) {
  return std::all_of(s.begin(), s.end(), [](char c) {
    const auto u = static_cast<unsigned char>(c);
    return u >= 0x20 && u <= 0x7f && c != '"' && c != '\\';
  });
}

constexpr std::size_t kNumberSlotBits = 16;
constexpr std::size_t kNumberSlots = std::size_t{1} << kNumberSlotBits;

}  // namespace

DiffableJsonWriter::DiffableJsonWriter(std::ostream& out, DiffableJsonOptions options)
    : out_(&out), options_(std::move(options)), numbers_(kNumberSlots) {
  buffer_.reserve(kChunk + kChunk / 4);
}

DiffableJsonWriter::DiffableJsonWriter(DiffableJsonOptions options) : options_(std::move(options)) {}

DiffableJsonWriter::~DiffableJsonWriter() {
  if (out_) flush();
}

void DiffableJsonWriter::flush() {
  if (!out_ || buffer_.empty()) return;
  out_->write(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
  buffer_.clear();
}

void DiffableJsonWriter::text(std::string_view layout) {
  buffer_.append(layout);
  maybe_flush();
}

void DiffableJsonWriter::value(const Json& value, int indent, bool in_array) {
  emit(value, indent, in_array);
  maybe_flush();
}

void DiffableJsonWriter::key(const std::string& k) {
  if (!options_.scalar && is_plain(k)) {
    buffer_ += '"';
    buffer_ += k;
    buffer_ += '"';
  } else {
    scalar(Json(k));
  }
}

// The text of default_scalar() (Json::dump), without a string per scalar:
// numbers go through the same conversions dump uses (nlohmann's own
// shortest round-trip double formatting, so the text is that of dump to
// the byte), strings that need no escaping are copied.
void DiffableJsonWriter::scalar(const Json& j) {
  if (options_.scalar) {
    buffer_ += options_.scalar(j);
    return;
  }
  switch (j.type()) {
    case Json::value_t::number_float: {
      const double v = j.get_ref<const Json::number_float_t&>();
      if (!std::isfinite(v)) break;  // dump writes null
      number(v);
      return;
    }
    case Json::value_t::number_integer:
    case Json::value_t::number_unsigned: {
      char digits[24];
      const auto r = j.is_number_unsigned()
                         ? std::to_chars(digits, digits + sizeof digits, j.get_ref<const Json::number_unsigned_t&>())
                         : std::to_chars(digits, digits + sizeof digits, j.get_ref<const Json::number_integer_t&>());
      buffer_.append(digits, static_cast<std::size_t>(r.ptr - digits));
      return;
    }
    case Json::value_t::boolean:
      buffer_ += j.get_ref<const Json::boolean_t&>() ? "true" : "false";
      return;
    case Json::value_t::string:
      if (const auto& s = j.get_ref<const Json::string_t&>(); is_plain(s)) {
        buffer_ += '"';
        buffer_ += s;
        buffer_ += '"';
        return;
      }
      break;
    default:
      break;
  }
  buffer_ += default_scalar(j);
}

void DiffableJsonWriter::number(double v) {
  char digits[64];
  if (numbers_.empty()) {
    const char* end = nlohmann::detail::to_chars(digits, digits + sizeof digits, v);
    buffer_.append(digits, static_cast<std::size_t>(end - digits));
    return;
  }
  // A direct-mapped memo of the text by bit pattern: the text is a function
  // of the bits, so a hit gives the same bytes as formatting again.
  const auto bits = std::bit_cast<std::uint64_t>(v);
  NumberText& slot = numbers_[(bits * 0x9E3779B97F4A7C15ull) >> (64 - kNumberSlotBits)];
  if (slot.size != 0 && slot.bits == bits) {
    buffer_.append(slot.text, slot.size);
    return;
  }
  const char* end = nlohmann::detail::to_chars(digits, digits + sizeof digits, v);
  const auto size = static_cast<std::size_t>(end - digits);
  buffer_.append(digits, size);
  if (size <= sizeof slot.text) {
    slot.bits = bits;
    slot.size = static_cast<std::uint8_t>(size);
    std::memcpy(slot.text, digits, size);
  }
}

void DiffableJsonWriter::emit(const Json& j, int indent, bool in_array) {
  if (j.is_object() && in_array && options_.inline_flat_objects_in_arrays && is_flat(j)) {
    buffer_ += '{';
    bool first = true;
    for (auto it = j.begin(); it != j.end(); ++it) {
      if (!first) buffer_ += ", ";
      first = false;
      key(it.key());
      buffer_ += ": ";
      emit(it.value(), indent, false);
    }
    buffer_ += '}';
  } else if (j.is_object()) {
    if (j.empty()) {
      buffer_ += "{}";
      return;
    }
    buffer_ += "{\n";
    bool first = true;
    for (auto it = j.begin(); it != j.end(); ++it) {
      if (!first) buffer_ += ",\n";
      first = false;
      pad(indent + 2);
      key(it.key());
      buffer_ += ": ";
      emit(it.value(), indent + 2, false);
      maybe_flush();
    }
    buffer_ += '\n';
    pad(indent);
    buffer_ += '}';
  } else if (j.is_array()) {
    if (j.empty() || std::all_of(j.begin(), j.end(), is_scalar)) {
      buffer_ += '[';
      bool first = true;
      for (const Json& e : j) {
        if (!first) buffer_ += ", ";
        first = false;
        scalar(e);
        maybe_flush();
      }
      buffer_ += ']';
      return;
    }
    buffer_ += "[\n";
    for (std::size_t i = 0; i < j.size(); ++i) {
      pad(indent + 2);
      emit(j[i], indent + 2, true);
      buffer_ += i + 1 < j.size() ? ",\n" : "\n";
      maybe_flush();
    }
    pad(indent);
    buffer_ += ']';
  } else {
    scalar(j);
  }
}

std::string diffable_json(const Json& value, const DiffableJsonOptions& options) {
  DiffableJsonWriter w(options);
  w.emit(value, 0, false);
  w.buffer_ += '\n';
  return std::move(w.buffer_);
}

void write_diffable_json(std::ostream& out, const Json& value, const DiffableJsonOptions& options) {
  DiffableJsonWriter w(out, options);
  w.value(value, 0, false);
  w.text("\n");
  w.flush();
}

}  // namespace rigel::io
