#pragma once
// The one JSON layout of rigel's text files (.rigel scenes, .rig.json
// definitions): made to be read and diffed line by line in version control.
//
//   - objects: one member per line;
//   - arrays of scalars (a vector, a quaternion, a matrix): on one line;
//   - other arrays: one element per line;
//   - with `inline_flat_objects_in_arrays`, an object inside an array whose
//     members are scalars or arrays of scalars (a guide, a control, a key)
//     goes on one line too.
//
// Scalars are written by `scalar` (nlohmann's shortest round-trip text, with
// invalid UTF-8 replaced, when none is given). The text ends with a newline.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace rigel::io {

struct DiffableJsonOptions {
  bool inline_flat_objects_in_arrays = false;
  std::function<std::string(const nlohmann::ordered_json&)> scalar;
};

std::string diffable_json(const nlohmann::ordered_json& value, const DiffableJsonOptions& options = {});

// The same layout written to a stream as it is produced, for documents too
// large to hold as one text (a .rigel scene of thousands of baked frames):
// the writer keeps at most about kChunk bytes of text and hands them to the
// stream in pieces of about that size. A document is written as pieces:
// `text` copies layout text as it is ("{\n", "  \"nodes\": [\n"), `key` writes
// an object's key, `value`
// lays out one value starting `indent` columns in (its first line is not
// padded; `in_array`: it is an element of an array, which decides how an
// object is laid out with `inline_flat_objects_in_arrays`). `write_diffable_json`
// writes a whole value so, newline included: the text of diffable_json().
// The stream's errors are its own (check it after `flush`).
class DiffableJsonWriter {
 public:
  static constexpr std::size_t kChunk = 64 * 1024;

  explicit DiffableJsonWriter(std::ostream& out, DiffableJsonOptions options = {});
  ~DiffableJsonWriter();
  DiffableJsonWriter(const DiffableJsonWriter&) = delete;
  DiffableJsonWriter& operator=(const DiffableJsonWriter&) = delete;

  void text(std::string_view layout);
  void value(const nlohmann::ordered_json& value, int indent, bool in_array);
  // An object's key as the layout writes it (quoted, escaped; no colon).
  void key(const std::string& k);
  // Hands what is held to the stream.
  void flush();

 private:
  void emit(const nlohmann::ordered_json& j, int indent, bool in_array);
  void scalar(const nlohmann::ordered_json& j);
  void pad(int columns) { buffer_.append(static_cast<std::size_t>(columns), ' '); }
  void maybe_flush() {
    if (out_ && buffer_.size() >= kChunk) flush();
  }

  // Holds the whole text, for diffable_json().
  explicit DiffableJsonWriter(DiffableJsonOptions options);
  friend std::string diffable_json(const nlohmann::ordered_json& value, const DiffableJsonOptions& options);

  void number(double v);

  std::ostream* out_ = nullptr;  // null: the text stays in buffer_
  DiffableJsonOptions options_;
  std::string buffer_;
  // The text of recently written doubles, by bit pattern (streamed
  // documents repeat them: every baked curve holds the same key times).
  struct NumberText {
    std::uint64_t bits = 0;
    std::uint8_t size = 0;  // 0: empty
    char text[27];
  };
  std::vector<NumberText> numbers_;
};

void write_diffable_json(std::ostream& out, const nlohmann::ordered_json& value, const DiffableJsonOptions& options = {});

}  // namespace rigel::io
