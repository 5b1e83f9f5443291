#pragma once
// Status and Result: how rigel reports bad data and API misuse (STYLE.md §5).
// A failure carries a message that names the place (file:line, node.attr,
// request field). Internal invariants use assert instead.

#include <cassert>
#include <optional>
#include <string>
#include <utility>
#include <variant>

namespace rigel {

// Kinds of failure. Boundaries (CLI, HTTP, Python) map them to exit codes,
// status codes and exception types.
enum class ErrorCode {
  kOk = 0,
  kInvalidArgument,  // the caller passed something unusable (bad name, wrong type)
  kNotFound,         // a node, attribute, plug or file that does not exist
  kAlreadyExists,    // a name or connection that is already taken
  kCycle,            // a connection that would close a cycle
  kParseError,       // a file that is not well-formed
  kIoError,          // the operating system refused a read or write
  kUnsupported,      // a version or feature this build does not know
  kFailedPrecondition,  // well-formed, but the scene cannot do it in its state (nothing selected, nothing to undo)
};

const char* error_code_name(ErrorCode code);

class [[nodiscard]] Status {
 public:
  Status() = default;
  Status(ErrorCode code, std::string message) : code_(code), message_(std::move(message)) {}

  static Status ok() { return {}; }

  bool is_ok() const { return code_ == ErrorCode::kOk; }
  explicit operator bool() const { return is_ok(); }
  ErrorCode code() const { return code_; }
  const std::string& message() const { return message_; }

  // Prepends a location ("scene.rigel: nodes[3]") to the message.
  Status with_context(const std::string& where) const {
    if (is_ok()) return *this;
    Status s(code_, where + ": " + message_);
    s.field_ = field_;
    return s;
  }

  // The input at fault, named as the API names it ("controls", "to.q",
  // "magnetFraction"): the service layer (app) sets it, and each driver
  // spells it its own way (an HTTP answer's "field", a CLI option, a Python
  // argument). Empty when no one input is to blame.
  const std::string& field() const { return field_; }
  Status with_field(std::string field) const {
    Status s = *this;
    if (!is_ok()) s.field_ = std::move(field);
    return s;
  }

 private:
  ErrorCode code_ = ErrorCode::kOk;
  std::string message_;
  std::string field_;
};

inline Status error(ErrorCode code, std::string message) { return Status(code, std::move(message)); }

// A value or a failure.
template <typename T>
class [[nodiscard]] Result {
 public:
  Result(T value) : value_(std::move(value)) {}               // NOLINT: implicit on purpose
  Result(Status status) : status_(std::move(status)) {        // NOLINT
    assert(!status_.is_ok() && "a Result built from a Status must hold a failure");
  }

  bool is_ok() const { return value_.has_value(); }
  explicit operator bool() const { return is_ok(); }
  const Status& status() const { return status_; }

  T& value() & { assert(is_ok()); return *value_; }
  const T& value() const& { assert(is_ok()); return *value_; }
  T&& value() && { assert(is_ok()); return std::move(*value_); }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  T& operator*() & { return value(); }
  const T& operator*() const& { return value(); }

 private:
  std::optional<T> value_;
  Status status_;
};

}  // namespace rigel
