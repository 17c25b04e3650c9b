// The outcome of a request: ok, or an igms.ErrorCode with a message for a person.
#pragma once

#include <string>
#include <utility>

#include "igms/common.pb.h"

namespace igms::net {

struct Status {
  igms::ErrorCode code = igms::ERROR_CODE_UNSPECIFIED;
  std::string message;

  bool ok() const { return code == igms::ERROR_CODE_UNSPECIFIED; }
  static Status Ok() { return {}; }
  static Status Error(igms::ErrorCode code, std::string message) {
    return {code, std::move(message)};
  }
  // "NOT_FOUND: frame 12 was evicted"
  std::string ToString() const { return ok() ? "OK" : igms::ErrorCode_Name(code) + ": " + message; }
};

template <class T>
struct Result {
  Status status;
  T value{};
  bool ok() const { return status.ok(); }
};

}  // namespace igms::net
