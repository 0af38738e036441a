// SPDX-License-Identifier: MIT
#include "lines/port_users.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <set>
#include <system_error>
#include <utility>

namespace nav::bench {

std::vector<std::string> paths_not_opened_elsewhere(const std::vector<std::string>& paths) {
  namespace fs = std::filesystem;
  // Compared by device and inode: /proc/<pid>/fd/<n> links stat to the file they name.
  std::set<std::pair<dev_t, ino_t>> wanted, seen;
  std::vector<std::pair<std::string, std::pair<dev_t, ino_t>>> ids;
  for (const auto& p : paths) {
    struct stat st {};
    if (::stat(p.c_str(), &st) != 0) continue;
    ids.push_back({p, {st.st_dev, st.st_ino}});
    wanted.insert(ids.back().second);
  }
  const std::string self = std::to_string(::getpid());
  std::error_code ec;
  for (const auto& proc : fs::directory_iterator("/proc", ec)) {
    const std::string pid = proc.path().filename().string();
    if (pid.empty() || pid.find_first_not_of("0123456789") != std::string::npos || pid == self) {
      continue;
    }
    std::error_code e2;
    for (const auto& fd : fs::directory_iterator(proc.path() / "fd", e2)) {
      struct stat st {};
      if (::stat(fd.path().c_str(), &st) != 0) continue;  // gone, or not ours to look at
      const std::pair<dev_t, ino_t> id{st.st_dev, st.st_ino};
      if (wanted.count(id) != 0) seen.insert(id);
    }
  }
  std::vector<std::string> out;
  for (const auto& [path, id] : ids) {
    if (seen.count(id) == 0) out.push_back(path);
  }
  return out;
}

}  // namespace nav::bench
