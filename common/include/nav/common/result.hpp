// SPDX-License-Identifier: MIT
// Expected failures as values (tl::expected), contract violations as NAV_ENSURE.
#pragma once

#include <string>
#include <system_error>
#include <utility>

#include <tl/expected.hpp>

namespace nav {

/// Kinds of expected runtime failure.
enum class ErrorCode {
  kInvalidArgument,  ///< a value out of its domain
  kParse,            ///< malformed input text or bytes
  kChecksum,         ///< a frame whose checksum does not match
  kIo,               ///< an operating-system call failed
  kTimeout,          ///< nothing arrived in time
  kNotFound,         ///< a file, device or program is missing
};

/// An expected failure: what went wrong and where, as one line.
struct Error {
  ErrorCode code;
  std::string detail;
};

/// Builds an Error from an errno-style code, naming the operation that failed.
inline Error io_error(const std::string& what, int errno_value) {
  return Error{ErrorCode::kIo, what + ": " + std::generic_category().message(errno_value)};
}

/// Result of an operation that can fail in an expected way.
template <typename T>
using Result = tl::expected<T, Error>;

/// The failing alternative of a Result.
inline tl::unexpected<Error> fail(ErrorCode code, std::string detail) {
  return tl::unexpected<Error>(Error{code, std::move(detail)});
}

}  // namespace nav
