#include "internal.h"

namespace rigel::app::internal {

namespace fs = std::filesystem;

Status conflict(const Status& s, const std::string& field) {
  if (s) return s;
  const ErrorCode code = s.code() == ErrorCode::kNotFound || s.code() == ErrorCode::kParseError ||
                                 s.code() == ErrorCode::kIoError
                             ? s.code()
                             : ErrorCode::kFailedPrecondition;
  return Status(code, s.message()).with_field(field.empty() ? s.field() : field);
}

Status make_parent(const fs::path& file, const std::string& field) {
  std::error_code ec;
  const fs::file_status st = fs::status(file, ec);
  if (fs::exists(st) && !fs::is_regular_file(st)) {
    return Status(ErrorCode::kInvalidArgument,
                  field + ": '" + file.string() + "' is " + (fs::is_directory(st) ? "a folder" : "not a file"))
        .with_field(field);
  }
  if (file.has_parent_path()) {
    fs::create_directories(file.parent_path(), ec);
    if (ec) {
      return Status(ErrorCode::kFailedPrecondition,
                    field + ": cannot make " + file.parent_path().string() + ": " + ec.message())
          .with_field(field);
    }
  }
  return Status::ok();
}

Status saved(const Status& s, const std::string& field) {
  if (s) return s;
  const bool keep = s.code() == ErrorCode::kNotFound || s.code() == ErrorCode::kParseError;
  return Status(keep ? s.code() : ErrorCode::kFailedPrecondition, s.message()).with_field(field);
}

}  // namespace rigel::app::internal
