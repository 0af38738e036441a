// SPDX-License-Identifier: MIT
#include "run/run_folder.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <system_error>
#include <utility>

namespace nav::bench {
namespace {

namespace fs = std::filesystem;

/// An open folder, closed at scope exit.
struct Fd {
  int fd = -1;
  ~Fd() {
    if (fd >= 0) ::close(fd);
  }
};

int open_dir(const fs::path& p) { return ::open(p.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC); }

}  // namespace

Result<RunFolderClaim> RunFolderClaim::claim(const fs::path& final_dir) {
  const fs::path parent = final_dir.has_parent_path() ? final_dir.parent_path() : fs::path(".");
  std::error_code ec;
  fs::create_directories(parent, ec);
  // A folder that cannot be made is the --out given (read-only, /proc, a file in the way):
  // a usage error, as are the two below.
  if (ec) {
    return fail(ErrorCode::kInvalidArgument,
                "cannot create " + parent.string() + ": " + ec.message() + "; choose another --out");
  }
  // Every decision below is made under the parent's lock: two runs never both decide.
  Fd parent_fd{open_dir(parent)};
  if (parent_fd.fd < 0 || ::flock(parent_fd.fd, LOCK_EX) != 0) {
    return fail(ErrorCode::kIo, "cannot lock " + parent.string() + ": " + std::strerror(errno));
  }
  if (fs::exists(final_dir, ec)) {
    return fail(ErrorCode::kInvalidArgument,
                "run folder " + final_dir.string() + " exists already; choose another --out");
  }
  const fs::path partial = final_dir.string() + ".partial";
  if (fs::exists(partial, ec)) {
    Fd old{open_dir(partial)};
    if (old.fd >= 0 && ::flock(old.fd, LOCK_EX | LOCK_NB) != 0 && errno == EWOULDBLOCK) {
      return fail(ErrorCode::kInvalidArgument,
                  "run folder " + final_dir.string() +
                      " is being written by another run (" + partial.string() +
                      " is locked); choose another --out");
    }
    // Left by a run that died before it finished: nobody holds it.
    fs::remove_all(partial, ec);
    if (ec) return fail(ErrorCode::kIo, "cannot remove " + partial.string() + ": " + ec.message());
  }
  if (::mkdir(partial.c_str(), 0755) != 0) {
    return fail(ErrorCode::kInvalidArgument, "cannot create " + partial.string() + ": " +
                                                 std::strerror(errno) + "; choose another --out");
  }
  const int fd = open_dir(partial);
  if (fd < 0 || ::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    const int e = errno;
    if (fd >= 0) ::close(fd);
    return fail(ErrorCode::kIo, "cannot lock " + partial.string() + ": " + std::strerror(e));
  }
  return RunFolderClaim(partial, fd);
}

RunFolderClaim::RunFolderClaim(RunFolderClaim&& other) noexcept
    : partial_(std::move(other.partial_)), fd_(std::exchange(other.fd_, -1)) {}

RunFolderClaim::~RunFolderClaim() {
  if (fd_ >= 0) ::close(fd_);
}

}  // namespace nav::bench
