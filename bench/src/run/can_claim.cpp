// SPDX-License-Identifier: MIT
#include "run/can_claim.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace nav::bench {

std::string CanClaim::lock_path(const std::string& interface) {
  return "/tmp/navbench-can-" + interface + ".lock";
}

Result<CanClaim> CanClaim::take(const std::string& interface) {
  const std::string path = lock_path(interface);
  // Anyone may take it: 0666 against the umask, so another user's run waits too.
  const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0666);
  if (fd < 0) {
    return fail(ErrorCode::kIo, "cannot open " + path + " to claim CAN interface " + interface +
                                    ": " + std::strerror(errno));
  }
  (void)::fchmod(fd, 0666);
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    std::fprintf(stderr, "navbench: CAN interface %s is in use by another run (%s); waiting\n",
                 interface.c_str(), path.c_str());
    int r;
    do {
      r = ::flock(fd, LOCK_EX);
    } while (r != 0 && errno == EINTR);
    if (r != 0) {
      const int e = errno;
      ::close(fd);
      return fail(ErrorCode::kIo, "cannot lock " + path + ": " + std::strerror(e));
    }
  }
  return CanClaim(fd);
}

CanClaim::~CanClaim() {
  if (fd_ >= 0) ::close(fd_);
}

}  // namespace nav::bench
