// SPDX-License-Identifier: MIT
#include "nav/common/ensure.hpp"

#include <cstdio>
#include <cstdlib>

namespace nav {
namespace {
void default_handler(const char* file, int line, const char* condition,
                     const std::string& message) {
  std::fprintf(stderr, "%s:%d: contract violated: %s: %s\n", file, line, condition,
               message.c_str());
}
EnsureHandler g_handler = &default_handler;
}  // namespace

EnsureHandler set_ensure_handler(EnsureHandler handler) {
  EnsureHandler previous = g_handler;
  g_handler = handler;
  return previous;
}

void ensure_failed(const char* file, int line, const char* condition,
                   const std::string& message) {
  g_handler(file, line, condition, message);
  std::abort();
}

}  // namespace nav
