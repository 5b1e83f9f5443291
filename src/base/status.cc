#include "rigel/base/status.h"

namespace rigel {

const char* error_code_name(ErrorCode code) {
  switch (code) {
    case ErrorCode::kOk: return "ok";
    case ErrorCode::kInvalidArgument: return "invalid argument";
    case ErrorCode::kNotFound: return "not found";
    case ErrorCode::kAlreadyExists: return "already exists";
    case ErrorCode::kCycle: return "cycle";
    case ErrorCode::kParseError: return "parse error";
    case ErrorCode::kIoError: return "i/o error";
    case ErrorCode::kUnsupported: return "unsupported";
    case ErrorCode::kFailedPrecondition: return "failed precondition";
  }
  return "unknown";
}

}  // namespace rigel
