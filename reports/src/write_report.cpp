// SPDX-License-Identifier: MIT
// Writing a report file whole or not at all.
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "nav/reports/atomic_file.hpp"
#include "nav/reports/html_report.hpp"

namespace nav::reports {

namespace fs = std::filesystem;

Result<std::string> write_file_atomically(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp-" + std::to_string(::getpid());
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << text;
    out.flush();
    if (!out) {
      std::error_code ec;
      fs::remove(tmp, ec);
      return fail(ErrorCode::kIo, "cannot write " + tmp);
    }
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    return fail(ErrorCode::kIo, "cannot rename " + tmp + " to " + path + ": " + ec.message());
  }
  return path;
}

FolderKind folder_kind(const std::string& dir) {
  std::error_code ec;
  if (fs::is_regular_file(fs::path(dir) / "campaign.json", ec)) return FolderKind::kCampaign;
  if (fs::is_regular_file(fs::path(dir) / "summary.json", ec)) return FolderKind::kRun;
  return FolderKind::kNeither;
}

Result<std::string> write_report(const std::string& dir, const std::string& out_path) {
  if (folder_kind(dir) == FolderKind::kCampaign) {
    auto c = read_campaign_folder(dir);
    if (!c) return tl::unexpected(c.error());
    const std::string out = out_path.empty() ? (fs::path(dir) / "campaign.html").string() : out_path;
    return write_file_atomically(out, campaign_report_html(*c));
  }
  auto f = read_run_folder(dir);
  if (!f) return tl::unexpected(f.error());
  const std::string out = out_path.empty() ? (fs::path(dir) / "report.html").string() : out_path;
  return write_file_atomically(out, run_report_html(*f));
}

}  // namespace nav::reports
