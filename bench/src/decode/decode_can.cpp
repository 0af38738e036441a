// SPDX-License-Identifier: MIT
// `navbench decode --protocol nmea2000`: a candump log (protocols.md section 7; the `-l` log
// format or candump's screen print) read line by line, NMEA 2000 fast packets reassembled per
// (source, PGN), one JSON object per message:
//
//   {"type":"n2k_vessel_heading","pgn":127250,"prio":2,"src":204,"dst":255,"sid":null,
//    "heading_rad":2.3154,...,"t_s":1502984866.421964,"interface":"slcan0","line":1,"offset":0}
//
// Values in SI with the unit in the name, "not available" as null, "t_s" the log's timestamp
// (of the frame completing a fast packet; null for screen prints without one). PGNs not decoded
// here come out raw ("n2k_raw": pgn and data hex, reassembled when they are fast packets);
// frames that are not N2K (11-bit IDs, RTR, error frames) as "can_frame". Bad lines, CAN FD
// lines, fast packets broken by lost or reordered frames, and payloads too short for their PGN
// become {"type":"error","line":N,"offset":...,"length":...,"error":"..."}.
#include <cstdio>
#include <map>
#include <utility>
#include <string>
#include <string_view>

#include "decode/decode_builders.hpp"
#include "nav/protocols/candump_log.hpp"
#include "nav/protocols/nmea2000.hpp"

namespace nav::bench::detail {
namespace {

namespace n2k = protocols::n2k;
namespace candump = protocols::candump;
using protocols::ParseResult;
using protocols::ParseStatus;

std::string hex(protocols::ByteSpan bytes) {
  std::string out;
  char buf[3];
  for (const auto b : bytes) {
    std::snprintf(buf, sizeof buf, "%02X", b);
    out += buf;
  }
  return out;
}

json reference_json(n2k::DirectionReference r) {
  switch (r) {
    case n2k::DirectionReference::kTrue: return "true";
    case n2k::DirectionReference::kMagnetic: return "magnetic";
    case n2k::DirectionReference::kError: return "error";
    case n2k::DirectionReference::kNull: break;
  }
  return nullptr;
}

/// "YYYY-MM-DD" of a day count since 1970-01-01 (civil_from_days, H. Hinnant).
std::string date_text(int days) {
  const int z = days + 719468;
  const int era = (z >= 0 ? z : z - 146096) / 146097;
  const int doe = z - era * 146097;
  const int yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
  const int doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
  const int mp = (5 * doy + 2) / 153;
  const int d = doy - (153 * mp + 2) / 5 + 1;
  const int m = mp < 10 ? mp + 3 : mp - 9;
  const int y = yoe + era * 400 + (m <= 2 ? 1 : 0);
  char buf[48];
  std::snprintf(buf, sizeof buf, "%04d-%02d-%02d", y, m, d);
  return buf;
}

void fields(json& j, const n2k::VesselHeading& m) {
  j["sid"] = or_null(m.sid);
  j["heading_rad"] = or_null(m.heading_rad);
  j["deviation_rad"] = or_null(m.deviation_rad);
  j["variation_rad"] = or_null(m.variation_rad);
  j["reference"] = reference_json(m.reference);
}

void fields(json& j, const n2k::RateOfTurn& m) {
  j["sid"] = or_null(m.sid);
  j["rate_radps"] = or_null(m.rate_radps);
}

void fields(json& j, const n2k::Attitude& m) {
  j["sid"] = or_null(m.sid);
  j["yaw_rad"] = or_null(m.yaw_rad);
  j["pitch_rad"] = or_null(m.pitch_rad);
  j["roll_rad"] = or_null(m.roll_rad);
}

void fields(json& j, const n2k::SpeedWaterReferenced& m) {
  j["sid"] = or_null(m.sid);
  j["water_speed_mps"] = or_null(m.water_speed_mps);
  j["ground_speed_mps"] = or_null(m.ground_speed_mps);
  j["speed_type"] = or_null(m.speed_type);
  j["speed_direction"] = or_null(m.speed_direction);
}

void fields(json& j, const n2k::WaterDepth& m) {
  j["sid"] = or_null(m.sid);
  j["depth_m"] = or_null(m.depth_m);
  j["offset_m"] = or_null(m.offset_m);
  j["max_range_m"] = or_null(m.max_range_m);
}

void fields(json& j, const n2k::PositionRapidUpdate& m) {
  j["lat_deg"] = or_null(m.lat_deg);
  j["lon_deg"] = or_null(m.lon_deg);
}

void fields(json& j, const n2k::CogSogRapidUpdate& m) {
  j["sid"] = or_null(m.sid);
  j["reference"] = reference_json(m.reference);
  j["cog_rad"] = or_null(m.cog_rad);
  j["sog_mps"] = or_null(m.sog_mps);
}

void fields(json& j, const n2k::GnssPositionData& m) {
  j["sid"] = or_null(m.sid);
  j["date"] = m.date_days ? json(date_text(*m.date_days)) : json(nullptr);
  j["time_of_day_s"] = or_null(m.time_s);
  j["time_unix_s"] = m.date_days && m.time_s ? json(*m.date_days * 86400.0 + *m.time_s)
                                             : json(nullptr);
  j["lat_deg"] = or_null(m.lat_deg);
  j["lon_deg"] = or_null(m.lon_deg);
  j["alt_m"] = or_null(m.altitude_m);
  j["gnss_type"] = m.gnss_type;
  j["method"] = m.method;
  j["integrity"] = m.integrity;
  j["satellites"] = or_null(m.satellites);
  j["hdop"] = or_null(m.hdop);
  j["pdop"] = or_null(m.pdop);
  j["geoid_sep_m"] = or_null(m.geoid_separation_m);
  json stations = json::array();
  for (const auto& s : m.reference_stations) {
    stations.push_back(json{{"type", s.type}, {"id", s.id}, {"age_s", or_null(s.age_s)}});
  }
  j["reference_stations"] = std::move(stations);
}

const char* type_name(const n2k::Message& m) {
  static constexpr const char* kNames[] = {
      "n2k_vessel_heading", "n2k_rate_of_turn", "n2k_attitude",      "n2k_speed_water",
      "n2k_water_depth",    "n2k_position_rapid", "n2k_cog_sog_rapid", "n2k_gnss_position"};
  return kNames[m.index()];
}

json header_json(const char* type, const n2k::Header& h) {
  return json{{"type", type}, {"pgn", h.pgn}, {"prio", h.priority}, {"src", h.source},
              {"dst", h.destination}};
}

/// A whole N2K payload: the decoded message, or "n2k_raw"; an error text when a known PGN's
/// payload is too short.
json message_json(const n2k::Header& h, protocols::ByteSpan payload, std::string* error) {
  if (!n2k::decodes(h.pgn)) {
    json j = header_json("n2k_raw", h);
    j["data"] = hex(payload);
    return j;
  }
  const auto m = n2k::decode(h.pgn, payload);
  if (!m) {
    *error = m.error().detail;
    return json{};
  }
  json j = header_json(type_name(*m), h);
  std::visit([&](const auto& v) { fields(j, v); }, *m);
  return j;
}

/// A frame that is not NMEA 2000 (standard ID, RTR or error frame).
json can_frame_json(const protocols::can::Frame& f) {
  return json{{"type", "can_frame"}, {"id", f.id},       {"extended", f.extended},
              {"rtr", f.rtr},        {"error_frame", f.error}, {"dlc", f.dlc},
              {"data", hex(f.payload())}};
}

bool is_n2k(const protocols::can::Frame& f) { return f.extended && !f.rtr && !f.error; }

void add_record_fields(json& j, const candump::Record& r) {
  j["t_s"] = r.time ? json(r.time->to_seconds()) : json(nullptr);
  j["interface"] = r.interface;
}

}  // namespace

ParseResult<json> parse_nmea2000_line(protocols::ByteSpan b) {
  const std::string_view text(reinterpret_cast<const char*>(b.data()), b.size());
  const std::size_t eol = text.find('\n');
  if (eol == std::string_view::npos) return {};  // need the whole line
  const std::size_t consumed = eol + 1;
  const auto line = candump::parse_line(text.substr(0, eol));
  if (line.status != candump::LineStatus::kRecord) {
    const std::string why = line.status == candump::LineStatus::kIgnored
                                ? std::string("not a frame line")
                                : line.error;
    return ParseResult<json>{ParseStatus::kMalformed, consumed, std::nullopt, why};
  }
  const auto& f = line.record->frame;
  json j;
  if (!is_n2k(f)) {
    j = can_frame_json(f);
  } else {
    const n2k::Header h = n2k::from_can_id(f.id);
    if (n2k::is_fast_packet(h.pgn)) {  // one frame of a fast packet: no state here to join it
      j = header_json("n2k_fast_packet_frame", h);
      j["data"] = hex(f.payload());
    } else {
      std::string error;
      j = message_json(h, f.payload(), &error);
      if (!error.empty()) {
        return ParseResult<json>{ParseStatus::kMalformed, consumed, std::nullopt, error};
      }
    }
  }
  add_record_fields(j, *line.record);
  return ParseResult<json>{ParseStatus::kComplete, consumed, std::move(j), {}};
}

DecodeCounts decode_nmea2000_log(protocols::ByteSpan bytes,
                                 const std::function<void(const json&)>& emit) {
  DecodeCounts counts;
  n2k::FastPacketAssembler fast;
  /// Where each pending fast packet started, for the end-of-input report.
  std::map<std::pair<std::uint8_t, std::uint32_t>, std::pair<std::size_t, std::size_t>> started;
  const std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  const auto error = [&](std::size_t line_no, std::size_t offset, std::size_t length,
                         const std::string& why) {
    emit(json{{"type", "error"}, {"line", line_no}, {"offset", offset}, {"length", length},
              {"error", "line " + std::to_string(line_no) + ": " + why}});
    ++counts.errors;
  };
  std::size_t offset = 0;
  for (std::size_t line_no = 1; offset < text.size(); ++line_no) {
    const std::size_t eol = std::min(text.find('\n', offset), text.size());
    const std::string_view line_text = text.substr(offset, eol - offset);
    const std::size_t line_offset = offset;
    offset = eol + 1;
    const auto line = candump::parse_line(line_text);
    if (line.status == candump::LineStatus::kIgnored) continue;
    if (line.status != candump::LineStatus::kRecord) {
      error(line_no, line_offset, line_text.size(), line.error);
      continue;
    }
    const candump::Record& r = *line.record;
    const auto put = [&](json j) {
      add_record_fields(j, r);
      j["line"] = line_no;
      j["offset"] = line_offset;
      emit(j);
      ++counts.messages;
    };
    if (!is_n2k(r.frame)) {
      put(can_frame_json(r.frame));
      continue;
    }
    const n2k::Header h = n2k::from_can_id(r.frame.id);
    protocols::Bytes payload;
    if (n2k::is_fast_packet(h.pgn)) {
      const auto key = std::make_pair(h.source, h.pgn);
      const std::size_t index = r.frame.length() > 0 ? (r.frame.data[0] & 0x1F) : 0;
      const bool was_pending = fast.in_progress(h.source, h.pgn);
      const auto before = fast.stats();
      auto whole = fast.add(h.source, h.pgn, r.frame.payload());
      const auto& after = fast.stats();
      const std::string what =
          "fast packet PGN " + std::to_string(h.pgn) + " from source " + std::to_string(h.source);
      if (after.discarded > before.discarded && was_pending) {
        const auto [first_line, first_offset] = started[key];
        error(first_line, first_offset, line_offset + line_text.size() - first_offset,
              what + " discarded at line " + std::to_string(line_no) +
                  (index == 0 ? ": restarted by a new frame 0"
                              : ": frame " + std::to_string(index) +
                                    " out of sequence (a frame lost or reordered)"));
      } else if (after.discarded > before.discarded) {
        error(line_no, line_offset, line_text.size(), what + ": bad frame 0");
      } else if (after.orphans > before.orphans) {
        error(line_no, line_offset, line_text.size(),
              what + ": frame " + std::to_string(index) + " without its frame 0");
      }
      if (fast.in_progress(h.source, h.pgn)) {
        const bool restarted = !was_pending || after.discarded > before.discarded;
        if (index == 0 && restarted) started[key] = {line_no, line_offset};
      } else {
        started.erase(key);
      }
      if (!whole) continue;
      payload = std::move(*whole);
    } else {
      payload.assign(r.frame.payload().begin(), r.frame.payload().end());
    }
    std::string why;
    json j = message_json(h, payload, &why);
    if (!why.empty()) {
      error(line_no, line_offset, line_text.size(), why);
      continue;
    }
    put(std::move(j));
  }
  for (const auto& [key, where] : started) {
    error(where.first, where.second, text.size() - where.second,
          "fast packet PGN " + std::to_string(key.second) + " from source " +
              std::to_string(key.first) + " incomplete at end of input");
  }
  return counts;
}

}  // namespace nav::bench::detail
