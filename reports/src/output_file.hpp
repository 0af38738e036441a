// SPDX-License-Identifier: MIT
// One report file being written: opened at construction, checked when it closes. Private to
// nav_reports.
#pragma once

#include <exception>
#include <fstream>
#include <stdexcept>
#include <string>

namespace nav::reports::detail {

class OutputFile {
 public:
  OutputFile(const std::string& dir, const std::string& name)
      : path_(dir + "/" + name), out_(path_, std::ios::binary) {
    if (!out_) throw std::runtime_error("cannot write " + path_);
    out_.precision(9);
    out_ << std::fixed;
  }
  ~OutputFile() noexcept(false) {
    out_.flush();
    if (!out_ && std::uncaught_exceptions() == 0) throw std::runtime_error("write failed: " + path_);
  }
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;
  std::ofstream& operator*() { return out_; }

 private:
  std::string path_;
  std::ofstream out_;
};

}  // namespace nav::reports::detail
