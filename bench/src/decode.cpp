// SPDX-License-Identifier: MIT
#include "nav/bench/decode.hpp"

#include <charconv>
#include <cstdio>
#include <sstream>

#include "nav/common/units.hpp"
#include "nav/protocols/microstrain_gx3.hpp"
#include "nav/protocols/navd_solution.hpp"
#include "nav/protocols/nmea0183.hpp"

namespace nav::bench {
namespace {

using json = nlohmann::ordered_json;
using protocols::ParseResult;
using protocols::ParseStatus;

/// Carries a parser's status and counts over to a JSON result.
template <typename M>
ParseResult<json> with(const ParseResult<M>& r, json j) {
  ParseResult<json> out{r.status, r.consumed, std::nullopt, r.error};
  if (r.status == ParseStatus::kComplete) out.message = std::move(j);
  return out;
}

json triad(const std::array<float, 3>& v, double scale) {
  return json::array({v[0] * scale, v[1] * scale, v[2] * scale});
}

ParseResult<json> parse_gx3(protocols::ByteSpan b) {
  namespace gx3 = protocols::gx3;
  const auto r = gx3::parse(b);
  if (r.status != ParseStatus::kComplete) return with(r, {});
  const auto& m = *r.message;
  return with(r, json{{"type", "gx3_accel_rate_mag"},
                      {"accel_mps2", triad(m.accel_g, units::kStandardGravity)},
                      {"rate_radps", triad(m.rate_radps, 1.0)},
                      {"mag_uT", triad(m.mag_gauss, units::kGaussToTesla * 1e6)},
                      {"timer_ticks", m.timer_ticks},
                      {"timer_s", m.timer_ticks / gx3::kTicksPerSecond}});
}

std::string time_text(const protocols::nmea::UtcTime& t) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%02d:%02d:%05.2f", t.hour, t.minute, t.second);
  return buf;
}

template <typename T>
void put(json& j, const char* key, const std::optional<T>& v) {
  j[key] = v ? json(*v) : json(nullptr);
}

json nmea_json(const protocols::nmea::Sentence& s) {
  namespace nmea = protocols::nmea;
  json j{{"type", s.type}, {"talker", s.talker}};
  if (s.talker + s.type == protocols::navd::kAddress) {
    auto sol = protocols::navd::decode(s);
    if (!sol) return json{{"type", "error"}, {"error", sol.error().detail}};
    j["input"] = sol->input;
    j["trigger_tag"] = sol->trigger_tag;
    j["seq"] = sol->seq;
    j["position_valid"] = sol->position_valid;
    if (sol->position_valid) {
      j["lat_deg"] = sol->lat_deg;
      j["lon_deg"] = sol->lon_deg;
      j["depth_m"] = sol->depth_m;
      j["velocity_ned_mps"] = {sol->vn_mps, sol->ve_mps, sol->vd_mps};
    }
    j["roll_deg"] = sol->roll_deg;
    j["pitch_deg"] = sol->pitch_deg;
    j["yaw_deg"] = sol->yaw_deg;
    j["status"] = sol->status;
    return j;
  }
  if (s.type == "GGA") {
    auto g = nmea::decode_gga(s);
    if (!g) return json{{"type", "error"}, {"error", g.error().detail}};
    j["time_utc"] = time_text(g->time);
    put(j, "lat_deg", g->lat_deg);
    put(j, "lon_deg", g->lon_deg);
    j["quality"] = g->quality;
    j["satellites"] = g->satellites;
    put(j, "hdop", g->hdop);
    put(j, "alt_msl_m", g->alt_msl_m);
    put(j, "geoid_sep_m", g->geoid_sep_m);
    return j;
  }
  if (s.type == "RMC") {
    auto r = nmea::decode_rmc(s);
    if (!r) return json{{"type", "error"}, {"error", r.error().detail}};
    char date[16];
    std::snprintf(date, sizeof date, "%04d-%02d-%02d", r->time.year, r->time.month, r->time.day);
    j["time_utc"] = time_text(r->time);
    j["date"] = date;
    j["valid"] = r->valid;
    put(j, "lat_deg", r->lat_deg);
    put(j, "lon_deg", r->lon_deg);
    j["sog_mps"] = r->sog_kn ? json(*r->sog_kn * units::kKnotToMps) : json(nullptr);
    put(j, "cog_deg", r->cog_deg);
    j["mode"] = std::string(1, r->mode);
    return j;
  }
  j["fields"] = s.fields;  // a sentence this decoder does not interpret: its raw fields
  return j;
}

ParseResult<json> parse_nmea(protocols::ByteSpan b) {
  const auto r = protocols::nmea::parse_with_limit(b, protocols::navd::kMaxSentence);
  if (r.status != ParseStatus::kComplete) return with(r, {});
  json j = nmea_json(*r.message);
  if (j["type"] == "error") {
    // Framing and checksum were fine, a field was not: report it at this sentence.
    return ParseResult<json>{ParseStatus::kMalformed, r.consumed, std::nullopt,
                             j["error"].get<std::string>()};
  }
  return with(r, std::move(j));
}

}  // namespace

const std::vector<ProtocolDecoder>& protocol_decoders() {
  static const std::vector<ProtocolDecoder> decoders{
      {"microstrain-gx3", "MicroStrain 3DM-GX3-25 binary replies (0xCB)", &parse_gx3,
       std::nullopt},
      {"nmea0183", "NMEA 0183 sentences (GGA, RMC decoded; others as raw fields; $PNVBSOL)",
       &parse_nmea, static_cast<std::uint8_t>('#')},
  };
  return decoders;
}

const ProtocolDecoder* find_decoder(const std::string& name) {
  for (const auto& d : protocol_decoders()) {
    if (d.name == name) return &d;
  }
  return nullptr;
}

DecodeCounts decode_stream(const ProtocolDecoder& d, protocols::ByteSpan bytes,
                           const std::function<void(const json&)>& emit) {
  DecodeCounts counts;
  struct BadRun {
    std::size_t offset = 0, length = 0;
    std::string error;
  } bad;  // consecutive malformed bytes with the same reason, reported once
  const auto flush_bad = [&] {
    if (bad.length == 0) return;
    emit(json{{"type", "error"}, {"offset", bad.offset}, {"length", bad.length},
              {"error", bad.error}});
    ++counts.errors;
    bad = BadRun{};
  };
  const auto at_line_start = [&](std::size_t p) { return p == 0 || bytes[p - 1] == '\n'; };
  std::size_t pos = 0;
  while (pos < bytes.size()) {
    if (d.comment_prefix && bytes[pos] == *d.comment_prefix && at_line_start(pos)) {
      while (pos < bytes.size() && bytes[pos] != '\n') ++pos;
      ++pos;
      continue;
    }
    const auto r = d.parse(bytes.subspan(pos));
    if (r.status == ParseStatus::kComplete) {
      flush_bad();
      json j = *r.message;
      j["offset"] = pos;
      emit(j);
      ++counts.messages;
      pos += r.consumed;
      continue;
    }
    // Need-more at the end of the input is a truncated message: an error too.
    const bool truncated = r.status == ParseStatus::kNeedMore;
    const std::size_t n = truncated ? bytes.size() - pos : std::max<std::size_t>(r.consumed, 1);
    const std::string why = truncated ? "truncated message at end of input" : r.error;
    if (bad.length == 0 || bad.offset + bad.length != pos || bad.error != why) {
      flush_bad();
      bad = BadRun{pos, 0, why};
    }
    bad.length += n;
    pos += n;
  }
  flush_bad();
  return counts;
}

Result<protocols::Bytes> bytes_from_capture(const std::string& text, const std::string& port) {
  protocols::Bytes out;
  std::istringstream in(text);
  std::size_t line_no = 0;
  for (std::string line; std::getline(in, line);) {
    ++line_no;
    if (line.empty()) continue;
    // "(<sec>.<nsec>) <port> <hex>"
    const auto close = line.find(") ");
    const auto space = close == std::string::npos ? close : line.find(' ', close + 2);
    if (line[0] != '(' || space == std::string::npos) {
      return fail(ErrorCode::kParse,
                  "line " + std::to_string(line_no) + ": expected '(<sec>.<nsec>) <port> <hex>'");
    }
    if (line.compare(close + 2, space - close - 2, port) != 0) continue;
    const std::string hex = line.substr(space + 1);
    if (hex.size() % 2 != 0) {
      return fail(ErrorCode::kParse, "line " + std::to_string(line_no) + ": odd number of hex digits");
    }
    for (std::size_t i = 0; i < hex.size(); i += 2) {
      std::uint8_t b = 0;
      const auto [p, ec] = std::from_chars(hex.data() + i, hex.data() + i + 2, b, 16);
      if (ec != std::errc{} || p != hex.data() + i + 2) {
        return fail(ErrorCode::kParse, "line " + std::to_string(line_no) + ": bad hex byte");
      }
      out.push_back(b);
    }
  }
  return out;
}

}  // namespace nav::bench
