// SPDX-License-Identifier: MIT
// Contract checks. A failed NAV_ENSURE is a bug: it reports and aborts (tests may install a
// handler that throws instead, so GoogleTest reports it).
#pragma once

#include <string>

namespace nav {

/// Called on a failed contract check; the default prints and aborts.
using EnsureHandler = void (*)(const char* file, int line, const char* condition,
                               const std::string& message);

/// Installs a handler and returns the previous one.
EnsureHandler set_ensure_handler(EnsureHandler handler);

[[noreturn]] void ensure_failed(const char* file, int line, const char* condition,
                                const std::string& message);

}  // namespace nav

#define NAV_ENSURE(cond, message)                                \
  do {                                                           \
    if (!(cond)) ::nav::ensure_failed(__FILE__, __LINE__, #cond, (message)); \
  } while (false)
