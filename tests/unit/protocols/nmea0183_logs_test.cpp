// SPDX-License-Identifier: MIT
// NMEA 0183 decoder against real receiver logs from gpsd's regression suite
// (fixtures-external/nmea0183, from ntpsec/gpsd test/daemon). Each .log is fed as one byte
// stream; its .chk holds gpsd's output: every sentence echoed, then the JSON reports gpsd
// made from it. We compare the lat/lon and the time of day of each TPV report with our
// decode of the latest GGA/RMC before it. Dates are not compared: the .chk files come from a
// newer gpsd than Debian's and old logs may carry a week-rollover correction.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "fixtures.hpp"
#include "nav/protocols/nmea0183.hpp"

namespace nav::protocols::nmea {
namespace {

using test_support::ExternalFixtureTest;
using test_support::read_bytes;

/// The log without its '#' comment lines, line ends kept as recorded.
Bytes strip_comments(const Bytes& raw) {
  Bytes out;
  std::size_t pos = 0;
  while (pos < raw.size()) {
    const auto lf =
        std::find(raw.begin() + static_cast<std::ptrdiff_t>(pos), raw.end(), std::uint8_t{'\n'});
    const auto end = static_cast<std::size_t>(lf - raw.begin()) + (lf == raw.end() ? 0 : 1);
    if (raw[pos] != '#')
      out.insert(out.end(), raw.begin() + static_cast<std::ptrdiff_t>(pos),
                 raw.begin() + static_cast<std::ptrdiff_t>(end));
    pos = end;
  }
  return out;
}

struct StreamDecode {
  std::vector<Sentence> sentences;
  std::vector<std::string> errors;
  std::size_t leftover = 0;
};

/// Runs parse() as a serial reader would: bytes arrive in chunks of `chunk` into a buffer,
/// complete and malformed results are removed from its front.
StreamDecode decode_stream(const Bytes& bytes, std::size_t chunk) {
  StreamDecode out;
  Bytes buffer;
  for (std::size_t pos = 0; pos < bytes.size(); pos += chunk) {
    const std::size_t n = std::min(chunk, bytes.size() - pos);
    buffer.insert(buffer.end(), bytes.begin() + static_cast<std::ptrdiff_t>(pos),
                  bytes.begin() + static_cast<std::ptrdiff_t>(pos + n));
    while (true) {
      auto r = parse(buffer);
      if (r.status == ParseStatus::kNeedMore) break;
      if (r.status == ParseStatus::kComplete)
        out.sentences.push_back(std::move(*r.message));
      else
        out.errors.push_back(r.error);
      buffer.erase(buffer.begin(), buffer.begin() + static_cast<std::ptrdiff_t>(r.consumed));
    }
  }
  out.leftover = buffer.size();
  return out;
}

struct Fix {
  double lat_deg = 0.0;
  double lon_deg = 0.0;
  double time_of_day_s = 0.0;
};

/// Position and time of a GGA or RMC with a position; decode errors fail the test.
std::optional<Fix> fix_of(const Sentence& s) {
  UtcTime t;
  std::optional<double> lat, lon;
  if (s.type == "GGA") {
    const auto g = decode_gga(s);
    EXPECT_TRUE(g) << g.error().detail;
    if (!g) return std::nullopt;
    t = g->time;
    lat = g->lat_deg;
    lon = g->lon_deg;
  } else if (s.type == "RMC") {
    const auto r = decode_rmc(s);
    EXPECT_TRUE(r) << r.error().detail;
    if (!r) return std::nullopt;
    t = r->time;
    lat = r->lat_deg;
    lon = r->lon_deg;
  }
  if (!lat || !lon) return std::nullopt;
  return Fix{*lat, *lon, t.hour * 3600.0 + t.minute * 60.0 + t.second};
}

/// "2022-10-18T11:32:58.000Z" -> seconds of the day.
double time_of_day(const std::string& iso) {
  return std::stod(iso.substr(11, 2)) * 3600.0 + std::stod(iso.substr(14, 2)) * 60.0 +
         std::stod(iso.substr(17, iso.size() - 18));
}

struct ChkComparison {
  std::size_t echoed = 0;         ///< sentences gpsd echoed
  std::size_t tpv_positions = 0;  ///< TPV reports with lat/lon, all compared
  std::size_t tpv_times = 0;      ///< TPV reports with a time, all compared
  double max_pos_err_deg = 0.0;   ///< largest |lat| or |lon| difference [deg]
};

/// Walks a .chk: echoed sentences must be ours in order (reframed text identical), TPV
/// lat/lon/time must match the latest fix sentence.
ChkComparison compare_with_chk(const std::filesystem::path& chk,
                               const std::vector<Sentence>& ours) {
  ChkComparison c;
  std::ifstream in(chk);
  std::string line;
  std::optional<Fix> last;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    if (line[0] == '$') {
      EXPECT_LT(c.echoed, ours.size()) << "gpsd echoed more sentences than we decoded";
      if (c.echoed >= ours.size()) return c;
      const Sentence& s = ours[c.echoed++];
      const std::string framed = frame(s);
      EXPECT_EQ(framed.substr(0, framed.size() - 2), line);
      if (const auto f = fix_of(s)) last = f;
      continue;
    }
    const auto j = nlohmann::json::parse(line);
    if (j.value("class", "") != "TPV") continue;
    if (j.contains("lat") && j.contains("lon")) {
      EXPECT_TRUE(last.has_value()) << "TPV before any fix sentence: " << line;
      if (!last) continue;
      ++c.tpv_positions;
      const double dlat = std::fabs(j["lat"].get<double>() - last->lat_deg);
      const double dlon = std::fabs(j["lon"].get<double>() - last->lon_deg);
      c.max_pos_err_deg = std::max({c.max_pos_err_deg, dlat, dlon});
      EXPECT_LT(dlat, 1e-6) << line;
      EXPECT_LT(dlon, 1e-6) << line;
    }
    if (j.contains("time") && last) {
      ++c.tpv_times;
      EXPECT_NEAR(time_of_day(j["time"].get<std::string>()), last->time_of_day_s, 1e-3) << line;
    }
  }
  return c;
}

/// Count of non-comment lines, i.e. of sentences in a log, counted independently of parse().
std::size_t count_sentence_lines(const Bytes& stripped) {
  return static_cast<std::size_t>(std::count(stripped.begin(), stripped.end(), '\n'));
}

class NmeaLogs : public ExternalFixtureTest {
 protected:
  /// Decodes <name>.log and checks it against <name>.log.chk.
  ChkComparison check_log(const std::string& name, std::size_t expected_sentences) {
    const auto path = dir() / "nmea0183" / name;
    const Bytes stream = strip_comments(read_bytes(path));
    EXPECT_EQ(count_sentence_lines(stream), expected_sentences);
    const StreamDecode d = decode_stream(stream, 64);
    EXPECT_TRUE(d.errors.empty()) << name << ": " << d.errors.front();
    EXPECT_EQ(d.leftover, 0u);
    EXPECT_EQ(d.sentences.size(), expected_sentences);
    ChkComparison c = compare_with_chk(path.string() + ".chk", d.sentences);
    EXPECT_EQ(c.echoed, expected_sentences) << "gpsd accepted every sentence of " << name;
    return c;
  }
};

TEST_F(NmeaLogs, Garmin15xMatchesGpsd) {
  // 7 one-second cycles of RMC GGA GSA GSV*3 PGRME PGRMV, plus one PGRMT: 57 sentences;
  // NMEA 2.2 RMC (no mode field), whole-second times, 4 decimals of minutes. gpsd reports
  // 33 TPVs, all with position and time.
  const ChkComparison c = check_log("garmin15x.log", 57);
  EXPECT_EQ(c.tpv_positions, 33u);
  EXPECT_EQ(c.tpv_times, 33u);
}

TEST_F(NmeaLogs, TrimbleRtkMatchesGpsd) {
  // 122 GGA/RMC pairs at 10 Hz with 8 decimals of minutes, GP and GN talkers, CRLF ends.
  // gpsd reports 123 TPVs with a position (the first GGA, then one per RMC), 122 with a time
  // (the first GGA has no date yet).
  const ChkComparison c = check_log("nmea-rtk.log", 244);
  EXPECT_EQ(c.tpv_positions, 123u);
  EXPECT_EQ(c.tpv_times, 122u);
}

TEST_F(NmeaLogs, FuzzyArithmeticCasesMatchGpsdToItsPrintedDigits) {
  // gpsd's "fuzzy arithmetic" cases: lat/lon whose ddmm -> degrees conversion once rounded
  // differently on some platforms. gpsd accepts all 28 and prints 9 decimals; our
  // conversion must agree to that printed precision.
  const ChkComparison c = check_log("nmea-fuzzy-cases.log", 28);
  EXPECT_EQ(c.tpv_positions, 15u);  // one per RMC, plus the very first GGA
  EXPECT_EQ(c.tpv_times, 14u);      // the first GGA has no date, so gpsd gives no time
  EXPECT_LE(c.max_pos_err_deg, 5.1e-10);
}

TEST_F(NmeaLogs, ByteAtATimeAndNoisyStreamsGiveTheSameSentences) {
  const Bytes stream = strip_comments(read_bytes(dir() / "nmea0183" / "nmea-rtk.log"));
  const StreamDecode whole = decode_stream(stream, stream.size());
  const StreamDecode bytewise = decode_stream(stream, 1);
  ASSERT_EQ(bytewise.sentences.size(), whole.sentences.size());
  for (std::size_t i = 0; i < whole.sentences.size(); ++i) {
    EXPECT_EQ(frame(bytewise.sentences[i]), frame(whole.sentences[i]));
  }

  // Line noise before every 10th sentence and a sentence cut short before every 7th: the
  // rest still decodes, and every injected defect is reported.
  Bytes noisy;
  std::size_t line_no = 0, defects = 0;
  for (std::size_t pos = 0; pos < stream.size();) {
    const auto lf = std::find(stream.begin() + static_cast<std::ptrdiff_t>(pos), stream.end(),
                              std::uint8_t{'\n'});
    const auto end = static_cast<std::size_t>(lf - stream.begin()) + 1;
    if (line_no % 10 == 3) {
      const Bytes junk = {0x00, 0xFF, 'x', '\r', '\n', 0x7F};
      noisy.insert(noisy.end(), junk.begin(), junk.end());
      ++defects;
    }
    if (line_no % 7 == 5) {
      noisy.insert(noisy.end(), stream.begin() + static_cast<std::ptrdiff_t>(pos),
                   stream.begin() + static_cast<std::ptrdiff_t>(pos + 20));
      ++defects;
    }
    noisy.insert(noisy.end(), stream.begin() + static_cast<std::ptrdiff_t>(pos),
                 stream.begin() + static_cast<std::ptrdiff_t>(end));
    pos = end;
    ++line_no;
  }
  // All in one buffer each defect is one malformed result; read in chunks a run of noise
  // split over two reads can be reported twice, but no sentence is lost.
  const StreamDecode at_once = decode_stream(noisy, noisy.size());
  EXPECT_EQ(at_once.errors.size(), defects);
  const StreamDecode chunked = decode_stream(noisy, 13);
  EXPECT_GE(chunked.errors.size(), defects);
  for (const StreamDecode* d : {&at_once, &chunked}) {
    ASSERT_EQ(d->sentences.size(), whole.sentences.size());
    for (std::size_t i = 0; i < whole.sentences.size(); ++i) {
      EXPECT_EQ(frame(d->sentences[i]), frame(whole.sentences[i]));
    }
  }
}

}  // namespace
}  // namespace nav::protocols::nmea
