// SPDX-License-Identifier: MIT
// One report file being written: opened at construction, checked when it closes. Private to
// nav_reports.
//
// Text goes into a buffer written out in large pieces; doubles in fixed notation through
// std::to_chars: the digits of printf's %.*f (9 decimals unless told otherwise) without the C
// library's formatting machinery or an ostream's per-character output, which took most of
// the time of writing a long run's tables (docs/design-notes.md, "Campaign speed").
#pragma once

#include <charconv>
#include <concepts>
#include <exception>
#include <fstream>
#include <stdexcept>
#include <string>
#include <string_view>

namespace nav::reports::detail {

class OutputFile {
 public:
  OutputFile(const std::string& dir, const std::string& name)
      : path_(dir + "/" + name), out_(path_, std::ios::binary) {
    if (!out_) throw std::runtime_error("cannot write " + path_);
    buf_.reserve(kChunk + 512);
  }
  ~OutputFile() noexcept(false) {
    write_out();
    out_.flush();
    if (!out_ && std::uncaught_exceptions() == 0) throw std::runtime_error("write failed: " + path_);
  }
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;

  /// Decimals of the doubles that follow (fixed notation).
  void precision(int decimals) { precision_ = decimals; }

  OutputFile& operator<<(double v) {
    char b[400];
    const auto r = std::to_chars(b, b + sizeof b, v, std::chars_format::fixed, precision_);
    if (r.ec == std::errc{}) {
      append(std::string_view(b, static_cast<std::size_t>(r.ptr - b)));
    } else {
      append(std::to_string(v));  // beyond 400 characters: not a number a run writes
    }
    return *this;
  }
  template <std::integral T>
    requires(!std::same_as<T, char> && !std::same_as<T, bool>)
  OutputFile& operator<<(T v) {
    char b[24];
    const auto r = std::to_chars(b, b + sizeof b, v);
    append(std::string_view(b, static_cast<std::size_t>(r.ptr - b)));
    return *this;
  }
  OutputFile& operator<<(char c) {
    append(std::string_view(&c, 1));
    return *this;
  }
  OutputFile& operator<<(std::string_view s) {
    append(s);
    return *this;
  }
  OutputFile& operator<<(const char* s) { return *this << std::string_view(s); }
  OutputFile& operator<<(const std::string& s) { return *this << std::string_view(s); }

 private:
  static constexpr std::size_t kChunk = 64 * 1024;

  void append(std::string_view s) {
    buf_.append(s);
    if (buf_.size() >= kChunk) write_out();
  }
  void write_out() {
    out_.write(buf_.data(), static_cast<std::streamsize>(buf_.size()));
    buf_.clear();
  }

  std::string path_;
  std::ofstream out_;
  std::string buf_;
  int precision_ = 9;
};

}  // namespace nav::reports::detail
