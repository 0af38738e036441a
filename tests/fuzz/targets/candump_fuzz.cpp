// SPDX-License-Identifier: MIT
// candump lines (protocols.md 7) as `navbench decode` and `replay` read a log: line by line,
// both the log format and the screen print. A problem names its 1-based column; a frame line
// written again (format_line, as `record --can` writes) parses back to the same record.
#include "fuzz_support.hpp"
#include "nav/protocols/candump_log.hpp"

namespace {

namespace candump = nav::protocols::candump;

void check(std::string_view line) {
  const candump::LineResult r = candump::parse_line(line);
  switch (r.status) {
    case candump::LineStatus::kIgnored:
      return;
    case candump::LineStatus::kUnsupported:
    case candump::LineStatus::kMalformed:
      NAV_ENSURE(!r.record && r.column >= 1 && r.column <= line.size() + 1,
                 "a bad line's column: " + r.error);
      NAV_ENSURE(r.error.rfind("column " + std::to_string(r.column) + ": ", 0) == 0,
                 "an error that does not start with its column: " + r.error);
      return;
    case candump::LineStatus::kRecord:
      break;
  }
  NAV_ENSURE(r.record.has_value(), "a frame line without its record");
  candump::Record rec = *r.record;
  if (!rec.time) rec.time = candump::Timestamp{};  // a screen-print line: log it at 0
  const std::string text = candump::format_line(rec);
  const candump::LineResult again = candump::parse_line(text);
  NAV_ENSURE(again.status == candump::LineStatus::kRecord && again.record,
             "a written line does not parse: " + text + " (" + again.error + ")");
  const candump::Record& b = *again.record;
  NAV_ENSURE(b.frame == rec.frame && b.interface == rec.interface &&
                 b.direction == rec.direction,
             "a written line parses to another record: " + text);
  NAV_ENSURE(candump::format_line(b) == text, "format_line(parse_line(.)) moves: " + text);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  std::size_t at = 0;
  while (at < text.size()) {
    const auto end = text.find('\n', at);
    const std::size_t stop = end == std::string_view::npos ? text.size() : end + 1;
    check(text.substr(at, stop - at));
    at = stop;
  }
  return 0;
}
