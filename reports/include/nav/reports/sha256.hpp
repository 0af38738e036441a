// SPDX-License-Identifier: MIT
// SHA-256 digests (OpenSSL's EVP interface), as lower-case hex.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace nav::reports {

/// Hex SHA-256 of bytes.
std::string sha256_hex(std::string_view bytes);

/// Base64 SHA-256 of bytes (as a Content-Security-Policy source 'sha256-...' names a script).
std::string sha256_base64(std::string_view bytes);

/// Hex SHA-256 of a file's contents, read in blocks; nullopt when it cannot be read.
std::optional<std::string> sha256_file(const std::string& path);

}  // namespace nav::reports
