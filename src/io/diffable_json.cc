#include "rigel/io/diffable_json.h"

#include <algorithm>

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

class Writer {
 public:
  explicit Writer(const DiffableJsonOptions& options) : options_(options) {}

  void emit(const Json& j, int indent, bool in_array) {
    const std::string pad(static_cast<std::size_t>(indent), ' ');
    if (j.is_object() && in_array && options_.inline_flat_objects_in_arrays && is_flat(j)) {
      out += "{";
      bool first = true;
      for (auto it = j.begin(); it != j.end(); ++it) {
        out += first ? "" : ", ";
        first = false;
        out += scalar(Json(it.key())) + ": ";
        emit(it.value(), indent, false);
      }
      out += "}";
    } else if (j.is_object()) {
      if (j.empty()) {
        out += "{}";
        return;
      }
      out += "{\n";
      bool first = true;
      for (auto it = j.begin(); it != j.end(); ++it) {
        if (!first) out += ",\n";
        first = false;
        out += pad + "  " + scalar(Json(it.key())) + ": ";
        emit(it.value(), indent + 2, false);
      }
      out += "\n" + pad + "}";
    } else if (j.is_array()) {
      if (j.empty() || std::all_of(j.begin(), j.end(), is_scalar)) {
        out += "[";
        for (std::size_t i = 0; i < j.size(); ++i) out += (i ? ", " : "") + scalar(j[i]);
        out += "]";
        return;
      }
      out += "[\n";
      for (std::size_t i = 0; i < j.size(); ++i) {
        out += pad + "  ";
        emit(j[i], indent + 2, true);
        out += i + 1 < j.size() ? ",\n" : "\n";
      }
      out += pad + "]";
    } else {
      out += scalar(j);
    }
  }

  std::string out;

 private:
  std::string scalar(const Json& j) const { return options_.scalar ? options_.scalar(j) : default_scalar(j); }

  const DiffableJsonOptions& options_;
};

}  // namespace

std::string diffable_json(const Json& value, const DiffableJsonOptions& options) {
  Writer w(options);
  w.emit(value, 0, false);
  w.out += "\n";
  return std::move(w.out);
}

}  // namespace rigel::io
