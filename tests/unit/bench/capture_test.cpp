// SPDX-License-Identifier: MIT
// Serial capture lines (nav/bench/capture.hpp): what `record` writes parses back, and lines
// that are not `(<sec>.<nsec>) <port> <hex>` are refused with their line number.
#include "nav/bench/capture.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <string>

namespace nav::bench {
namespace {

using namespace std::string_literals;

std::string written(Duration t, const std::string& port, const protocols::Bytes& bytes) {
  char* buf = nullptr;
  std::size_t len = 0;
  std::FILE* f = ::open_memstream(&buf, &len);
  write_capture_line(f, t, port, bytes);
  std::fclose(f);
  std::string text(buf, len);
  std::free(buf);
  return text;
}

TEST(CaptureLine, WrittenLinesParseBack) {
  const std::string text = written(Duration{-500'000'000}, "ahrs", {0xCB, 0x00}) +
                           "\n" + written(Duration{12'345'678'901}, "gps", {0x24, 0x0D, 0x0A});
  EXPECT_EQ(text, "(-0.500000000) ahrs CB00\n\n(12.345678901) gps 240D0A\n");
  const auto lines = parse_capture(text, "x.log");
  ASSERT_TRUE(lines.has_value()) << lines.error().detail;
  ASSERT_EQ(lines->size(), 2u);
  EXPECT_EQ((*lines)[0].t, Duration{-500'000'000});
  EXPECT_EQ((*lines)[0].port, "ahrs");
  EXPECT_EQ((*lines)[1].line_no, 3u);
  EXPECT_EQ((*lines)[1].bytes, (protocols::Bytes{0x24, 0x0D, 0x0A}));
}

TEST(CaptureLine, MalformedLineNamesItsLine) {
  const auto r = parse_capture("(0.1) a 00\n(0.1) b 0\n", "x.log");
  ASSERT_FALSE(r.has_value());
  EXPECT_EQ(r.error().detail, "x.log:2: expected '(<sec>.<nsec>) <port> <hex>'");
}

// Found by tests/fuzz (capture): a NUL in the port name was taken in, and the line written
// again (write_capture_line) carried the name cut at the NUL.
TEST(CaptureLine, PortNameWithControlBytesIsMalformed) {
  EXPECT_FALSE(parse_capture("(0.1) o\0ut 00\n"s, "x.log").has_value());
  EXPECT_FALSE(parse_capture("(0.1) \x01 00\n"s, "x.log").has_value());
}

// Found by tests/fuzz (capture, UBSan): ten digits of seconds overflowed the nanosecond count.
TEST(CaptureLine, TimeBeyondTheNanosecondRangeIsMalformed) {
  EXPECT_FALSE(parse_capture("(9999999999.5) a 00\n", "x.log").has_value());
  EXPECT_FALSE(parse_capture("(-9999999999.5) a 00\n", "x.log").has_value());
  const auto max = parse_capture("(9223372035.999999999) a 00\n", "x.log");
  ASSERT_TRUE(max.has_value());
  EXPECT_EQ((*max)[0].t, Duration{9'223'372'035'999'999'999});
}

}  // namespace
}  // namespace nav::bench
