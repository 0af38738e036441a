// SPDX-License-Identifier: MIT
// One report file being written: opened at construction, checked when it closes. Private to
// nav_reports.
#pragma once

#include <charconv>
#include <exception>
#include <fstream>
#include <locale>
#include <stdexcept>
#include <string>

namespace nav::reports::detail {

/// Doubles in fixed notation through std::to_chars: the digits of printf's %.*f without the C
/// library's formatting machinery, which took most of the time of writing a long run's tables
/// (140–190 ms of a P0 run, 48 ms this way). Anything else goes the usual way.
class FixedNumPut : public std::num_put<char> {
 protected:
  iter_type do_put(iter_type out, std::ios_base& str, char fill, double v) const override {
    const auto flags = str.flags();
    if ((flags & std::ios_base::floatfield) != std::ios_base::fixed || str.width() != 0 ||
        (flags & (std::ios_base::showpos | std::ios_base::showpoint | std::ios_base::uppercase))) {
      return std::num_put<char>::do_put(out, str, fill, v);
    }
    char buf[400];
    const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed,
                                 static_cast<int>(str.precision()));
    if (r.ec != std::errc{}) return std::num_put<char>::do_put(out, str, fill, v);
    for (const char* p = buf; p != r.ptr; ++p) *out++ = *p;
    return out;
  }
};

class OutputFile {
 public:
  OutputFile(const std::string& dir, const std::string& name)
      : path_(dir + "/" + name), out_(path_, std::ios::binary) {
    if (!out_) throw std::runtime_error("cannot write " + path_);
    out_.imbue(std::locale(out_.getloc(), new FixedNumPut));
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
