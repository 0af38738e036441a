// SPDX-License-Identifier: MIT
// A fuzz input as a file, for loaders that take a path (scenarios, navd's config): the bytes
// go into one memory file (memfd) per process, named by its /proc/self/fd path, so nothing
// touches the disk and the loader opens and reads it as it would any file.
#pragma once

#include <sys/mman.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <string>

#include "nav/common/ensure.hpp"

namespace nav::fuzz {

/// The path of a file that holds exactly data[0, size) until the next call.
inline std::string as_file(const std::uint8_t* data, std::size_t size) {
  static const int fd = ::memfd_create("nav-fuzz-input", 0);
  NAV_ENSURE(fd >= 0, "memfd_create failed");
  NAV_ENSURE(::ftruncate(fd, 0) == 0, "ftruncate failed");
  std::size_t done = 0;
  while (done < size) {
    const ssize_t n = ::pwrite(fd, data + done, size - done, static_cast<off_t>(done));
    NAV_ENSURE(n > 0, "pwrite failed");
    done += static_cast<std::size_t>(n);
  }
  return "/proc/self/fd/" + std::to_string(fd);
}

}  // namespace nav::fuzz
