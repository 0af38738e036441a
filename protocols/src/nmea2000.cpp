// SPDX-License-Identifier: MIT
// NMEA 2000 identifiers, the eight navigation PGNs, single frames and fast packets
// (protocols.md section 5; canboat common/common.c getISO11783BitsFromCanId /
// getCanIdFromISO11783Bits, analyzer/analyzer.c fast-packet reassembly,
// database/fieldtypes.yaml resolutions and sentinels).
#include "nav/protocols/nmea2000.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <type_traits>

#include "nav/common/ensure.hpp"

namespace nav::protocols::n2k {
namespace {

constexpr std::uint8_t kPad = 0xFF;  ///< unused bytes and reserved bits

// Resolutions (protocols.md section 5 table) [unit per LSB].
constexpr double kAngleRes = 1e-4;        ///< heading, attitude, COG [rad]
constexpr double kRateRes = 3.125e-8;     ///< rate of turn [rad/s]
constexpr double kSpeedRes = 0.01;        ///< STW, SOG [m/s]
constexpr double kDepthRes = 0.01;        ///< depth [m]
constexpr double kOffsetRes = 0.001;      ///< transducer offset [m]
constexpr double kRangeRes = 10.0;        ///< depth max range [m]
constexpr double kLatLon32Res = 1e-7;     ///< 129025 [deg]
constexpr long double kLatLon64Res = 1e-16L;  ///< 129029 [deg]
constexpr long double kAltitudeRes = 1e-6L;   ///< 129029 [m]
constexpr double kTimeRes = 1e-4;         ///< 129029 time of day [s]
constexpr double kDopRes = 0.01;          ///< HDOP, PDOP [-]
constexpr double kGeoidRes = 0.01;        ///< geoidal separation [m]
constexpr double kAgeRes = 0.01;          ///< reference station age [s]

constexpr std::size_t kGnssFixedLength = 43;  ///< 129029 without reference stations [bytes]
constexpr std::size_t kStationLength = 4;     ///< [bytes]
constexpr std::size_t kMaxStations = (kMaxFastPacketLength - kGnssFixedLength) / kStationLength;

// ---- little-endian access ----------------------------------------------------------------

template <typename T>
T get(ByteSpan p, std::size_t at) {
  using U = std::make_unsigned_t<T>;
  U v = 0;
  for (std::size_t i = 0; i < sizeof(T); ++i) v |= static_cast<U>(U{p[at + i]} << (8 * i));
  return static_cast<T>(v);
}

template <typename T>
void put(Bytes& b, T value) {
  using U = std::make_unsigned_t<T>;
  const auto v = static_cast<U>(value);
  for (std::size_t i = 0; i < sizeof(T); ++i) b.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}

// ---- sentinels ---------------------------------------------------------------------------

/// "Not available" raw value of a field type: all ones (unsigned), max positive (signed).
template <typename T>
constexpr T not_available() {
  return std::numeric_limits<T>::max();
}

/// An identifier / lookup: all ones is not available.
std::optional<std::uint8_t> id_or_null(std::uint8_t raw, std::uint8_t all_ones = 0xFF) {
  return raw == all_ones ? std::nullopt : std::optional<std::uint8_t>(raw);
}

/// A physical quantity: not available (max) and error (max - 1) are nullopt.
template <typename T, typename Res>
std::optional<double> quantity(T raw, Res resolution) {
  if (raw == not_available<T>() || raw == not_available<T>() - 1) return std::nullopt;
  return static_cast<double>(static_cast<Res>(raw) * resolution);
}

/// Raw value of a quantity: nullopt -> not available; else rounded and clamped to the valid
/// range [min, max - 2] (unsigned: [0, max - 2]) so a value never turns into a sentinel.
template <typename T, typename Res>
T to_raw(const std::optional<double>& v, Res resolution) {
  if (!v) return not_available<T>();
  using Wide = std::conditional_t<std::is_same_v<Res, long double>, long double, double>;
  const Wide scaled = std::round(static_cast<Wide>(*v) / static_cast<Wide>(resolution));
  constexpr Wide lo = static_cast<Wide>(std::numeric_limits<T>::min());
  constexpr Wide hi = static_cast<Wide>(std::numeric_limits<T>::max() - 2);
  if (std::isnan(scaled)) return not_available<T>();
  if (scaled <= lo) return std::numeric_limits<T>::min();
  if (scaled >= hi) return static_cast<T>(std::numeric_limits<T>::max() - 2);
  return static_cast<T>(scaled);
}

/// An unsigned angle (heading, COG) wrapped into [0, 2pi) before encoding [rad].
std::optional<double> wrap_2pi(const std::optional<double>& a) {
  if (!a || !std::isfinite(*a)) return a;
  double w = std::fmod(*a, 2.0 * std::numbers::pi);
  if (w < 0.0) w += 2.0 * std::numbers::pi;
  return w;
}

std::uint8_t sid_raw(const std::optional<std::uint8_t>& sid) { return sid.value_or(0xFF); }

Result<Message> too_short(std::uint32_t pgn, std::size_t have, std::size_t need) {
  return fail(ErrorCode::kParse, "PGN " + std::to_string(pgn) + ": payload of " +
                                     std::to_string(have) + " bytes, needs " +
                                     std::to_string(need));
}

// ---- encoders ----------------------------------------------------------------------------

Bytes encode_one(const VesselHeading& m) {
  Bytes b;
  put(b, sid_raw(m.sid));
  put(b, to_raw<std::uint16_t>(wrap_2pi(m.heading_rad), kAngleRes));
  put(b, to_raw<std::int16_t>(m.deviation_rad, kAngleRes));
  put(b, to_raw<std::int16_t>(m.variation_rad, kAngleRes));
  put(b, static_cast<std::uint8_t>(0xFC | (static_cast<std::uint8_t>(m.reference) & 0x3)));
  return b;
}

Bytes encode_one(const RateOfTurn& m) {
  Bytes b;
  put(b, sid_raw(m.sid));
  put(b, to_raw<std::int32_t>(m.rate_radps, kRateRes));
  b.insert(b.end(), 3, kPad);
  return b;
}

Bytes encode_one(const Attitude& m) {
  Bytes b;
  put(b, sid_raw(m.sid));
  put(b, to_raw<std::int16_t>(m.yaw_rad, kAngleRes));
  put(b, to_raw<std::int16_t>(m.pitch_rad, kAngleRes));
  put(b, to_raw<std::int16_t>(m.roll_rad, kAngleRes));
  put(b, kPad);
  return b;
}

Bytes encode_one(const SpeedWaterReferenced& m) {
  Bytes b;
  put(b, sid_raw(m.sid));
  put(b, to_raw<std::uint16_t>(m.water_speed_mps, kSpeedRes));
  put(b, to_raw<std::uint16_t>(m.ground_speed_mps, kSpeedRes));
  put(b, m.speed_type.value_or(0xFF));
  put(b, static_cast<std::uint8_t>(0xF0 | (m.speed_direction.value_or(0xF) & 0xF)));
  put(b, kPad);
  return b;
}

Bytes encode_one(const WaterDepth& m) {
  Bytes b;
  put(b, sid_raw(m.sid));
  put(b, to_raw<std::uint32_t>(m.depth_m, kDepthRes));
  put(b, to_raw<std::int16_t>(m.offset_m, kOffsetRes));
  put(b, to_raw<std::uint8_t>(m.max_range_m, kRangeRes));
  return b;
}

Bytes encode_one(const PositionRapidUpdate& m) {
  Bytes b;
  put(b, to_raw<std::int32_t>(m.lat_deg, kLatLon32Res));
  put(b, to_raw<std::int32_t>(m.lon_deg, kLatLon32Res));
  return b;
}

Bytes encode_one(const CogSogRapidUpdate& m) {
  Bytes b;
  put(b, sid_raw(m.sid));
  put(b, static_cast<std::uint8_t>(0xFC | (static_cast<std::uint8_t>(m.reference) & 0x3)));
  put(b, to_raw<std::uint16_t>(wrap_2pi(m.cog_rad), kAngleRes));
  put(b, to_raw<std::uint16_t>(m.sog_mps, kSpeedRes));
  b.insert(b.end(), 2, kPad);
  return b;
}

Bytes encode_one(const GnssPositionData& m) {
  NAV_ENSURE(m.reference_stations.size() <= kMaxStations,
             "129029 carries at most 45 reference stations");
  Bytes b;
  put(b, sid_raw(m.sid));
  put(b, m.date_days.value_or(0xFFFF));
  put(b, to_raw<std::uint32_t>(m.time_s, kTimeRes));
  put(b, to_raw<std::int64_t>(m.lat_deg, kLatLon64Res));
  put(b, to_raw<std::int64_t>(m.lon_deg, kLatLon64Res));
  put(b, to_raw<std::int64_t>(m.altitude_m, kAltitudeRes));
  put(b, static_cast<std::uint8_t>((m.gnss_type & 0xF) | (m.method & 0xF) << 4));
  put(b, static_cast<std::uint8_t>(0xFC | (m.integrity & 0x3)));
  put(b, m.satellites.value_or(0xFF));
  put(b, to_raw<std::int16_t>(m.hdop, kDopRes));
  put(b, to_raw<std::int16_t>(m.pdop, kDopRes));
  put(b, to_raw<std::int32_t>(m.geoid_separation_m, kGeoidRes));
  put(b, static_cast<std::uint8_t>(m.reference_stations.size()));
  for (const auto& s : m.reference_stations) {
    put(b, static_cast<std::uint16_t>((s.type & 0xF) | (s.id & 0xFFF) << 4));
    put(b, to_raw<std::uint16_t>(s.age_s, kAgeRes));
  }
  return b;
}

// ---- decoders ----------------------------------------------------------------------------

DirectionReference reference_of(std::uint8_t bits) {
  return static_cast<DirectionReference>(bits & 0x3);
}

VesselHeading decode_heading(ByteSpan p) {
  return VesselHeading{id_or_null(p[0]), quantity(get<std::uint16_t>(p, 1), kAngleRes),
                       quantity(get<std::int16_t>(p, 3), kAngleRes),
                       quantity(get<std::int16_t>(p, 5), kAngleRes), reference_of(p[7])};
}

RateOfTurn decode_rate(ByteSpan p) {
  return RateOfTurn{id_or_null(p[0]), quantity(get<std::int32_t>(p, 1), kRateRes)};
}

Attitude decode_attitude(ByteSpan p) {
  return Attitude{id_or_null(p[0]), quantity(get<std::int16_t>(p, 1), kAngleRes),
                  quantity(get<std::int16_t>(p, 3), kAngleRes),
                  quantity(get<std::int16_t>(p, 5), kAngleRes)};
}

SpeedWaterReferenced decode_speed(ByteSpan p) {
  return SpeedWaterReferenced{id_or_null(p[0]), quantity(get<std::uint16_t>(p, 1), kSpeedRes),
                              quantity(get<std::uint16_t>(p, 3), kSpeedRes), id_or_null(p[5]),
                              id_or_null(p[6] & 0xF, 0xF)};
}

WaterDepth decode_depth(ByteSpan p) {
  return WaterDepth{id_or_null(p[0]), quantity(get<std::uint32_t>(p, 1), kDepthRes),
                    quantity(get<std::int16_t>(p, 5), kOffsetRes),
                    quantity(get<std::uint8_t>(p, 7), kRangeRes)};
}

PositionRapidUpdate decode_position(ByteSpan p) {
  return PositionRapidUpdate{quantity(get<std::int32_t>(p, 0), kLatLon32Res),
                             quantity(get<std::int32_t>(p, 4), kLatLon32Res)};
}

CogSogRapidUpdate decode_cog_sog(ByteSpan p) {
  return CogSogRapidUpdate{id_or_null(p[0]), reference_of(p[1]),
                           quantity(get<std::uint16_t>(p, 2), kAngleRes),
                           quantity(get<std::uint16_t>(p, 4), kSpeedRes)};
}

Result<Message> decode_gnss(ByteSpan p) {
  GnssPositionData m;
  m.sid = id_or_null(p[0]);
  const auto date = get<std::uint16_t>(p, 1);
  if (date != 0xFFFF) m.date_days = date;
  m.time_s = quantity(get<std::uint32_t>(p, 3), kTimeRes);
  m.lat_deg = quantity(get<std::int64_t>(p, 7), kLatLon64Res);
  m.lon_deg = quantity(get<std::int64_t>(p, 15), kLatLon64Res);
  m.altitude_m = quantity(get<std::int64_t>(p, 23), kAltitudeRes);
  m.gnss_type = p[31] & 0xF;
  m.method = p[31] >> 4;
  m.integrity = p[32] & 0x3;
  m.satellites = id_or_null(p[33]);
  m.hdop = quantity(get<std::int16_t>(p, 34), kDopRes);
  m.pdop = quantity(get<std::int16_t>(p, 36), kDopRes);
  m.geoid_separation_m = quantity(get<std::int32_t>(p, 38), kGeoidRes);
  const std::size_t stations = p[42] == 0xFF ? 0 : p[42];
  const std::size_t need = kGnssFixedLength + stations * kStationLength;
  if (p.size() < need) return too_short(kPgnGnssPosition, p.size(), need);
  for (std::size_t i = 0; i < stations; ++i) {
    const std::size_t at = kGnssFixedLength + i * kStationLength;
    const auto type_id = get<std::uint16_t>(p, at);
    m.reference_stations.push_back(ReferenceStation{static_cast<std::uint8_t>(type_id & 0xF),
                                                    static_cast<std::uint16_t>(type_id >> 4),
                                                    quantity(get<std::uint16_t>(p, at + 2),
                                                             kAgeRes)});
  }
  return m;
}

/// Bytes a PGN's fields need (reserved bytes at the end not required) [bytes].
std::size_t needed_length(std::uint32_t pgn) {
  switch (pgn) {
    case kPgnVesselHeading: return 8;
    case kPgnRateOfTurn: return 5;
    case kPgnAttitude: return 7;
    case kPgnSpeedWater: return 7;
    case kPgnWaterDepth: return 8;
    case kPgnPositionRapid: return 8;
    case kPgnCogSogRapid: return 6;
    case kPgnGnssPosition: return kGnssFixedLength;
    default: return 0;
  }
}

}  // namespace

bool is_pdu1(std::uint32_t pgn) { return ((pgn >> 8) & 0xFF) < 240; }

std::uint32_t to_can_id(const Header& h) {
  NAV_ENSURE(h.priority <= kMaxPriority, "N2K priority is 3 bits");
  NAV_ENSURE(h.pgn < (1u << 18), "PGN is 18 bits");
  if (is_pdu1(h.pgn)) {
    NAV_ENSURE((h.pgn & 0xFF) == 0, "a PDU1 PGN has a zero low byte");
    return std::uint32_t{h.priority} << 26 | h.pgn << 8 | std::uint32_t{h.destination} << 8 |
           h.source;
  }
  return std::uint32_t{h.priority} << 26 | h.pgn << 8 | h.source;
}

Header from_can_id(std::uint32_t id) {
  Header h;
  h.priority = static_cast<std::uint8_t>((id >> 26) & 0x7);
  const std::uint32_t dp = (id >> 24) & 0x1;
  const std::uint32_t pf = (id >> 16) & 0xFF;
  const std::uint32_t ps = (id >> 8) & 0xFF;
  h.source = static_cast<std::uint8_t>(id & 0xFF);
  if (pf < 240) {
    h.pgn = dp << 16 | pf << 8;
    h.destination = static_cast<std::uint8_t>(ps);
  } else {
    h.pgn = dp << 16 | pf << 8 | ps;
    h.destination = kBroadcast;
  }
  return h;
}

std::uint8_t default_priority(std::uint32_t pgn) {
  switch (pgn) {
    case kPgnVesselHeading:
    case kPgnRateOfTurn:
    case kPgnSpeedWater:
    case kPgnPositionRapid:
    case kPgnCogSogRapid:
      return 2;
    case kPgnAttitude:
    case kPgnWaterDepth:
    case kPgnGnssPosition:
      return 3;
    default:
      return 6;
  }
}

bool decodes(std::uint32_t pgn) { return needed_length(pgn) != 0; }

bool is_fast_packet(std::uint32_t pgn) {
  // canboat database: fast-packet PGNs of the navigation, AIS, system and proprietary ranges.
  static constexpr std::array<std::uint32_t, 52> kFast = {
      126208, 126464, 126720, 126983, 126984, 126985, 126986, 126987, 126988, 126996,
      126998, 127233, 127237, 127489, 127496, 127497, 127498, 127503, 127504, 127506,
      127510, 128275, 128520, 129029, 129038, 129039, 129040, 129041, 129044, 129045,
      129284, 129285, 129301, 129302, 129538, 129540, 129541, 129542, 129545, 129547,
      129549, 129551, 129556, 129792, 129793, 129794, 129795, 129796, 129797, 129798,
      129809, 129810};
  if (pgn >= 130816 && pgn <= 131071) return true;  // proprietary fast-packet range
  return std::find(kFast.begin(), kFast.end(), pgn) != kFast.end();
}

std::uint32_t pgn_of(const Message& m) {
  static constexpr std::array<std::uint32_t, std::variant_size_v<Message>> kPgns = {
      kPgnVesselHeading, kPgnRateOfTurn, kPgnAttitude,    kPgnSpeedWater,
      kPgnWaterDepth,    kPgnPositionRapid, kPgnCogSogRapid, kPgnGnssPosition};
  return kPgns[m.index()];
}

Bytes encode(const Message& m) {
  return std::visit([](const auto& v) { return encode_one(v); }, m);
}

Result<Message> decode(std::uint32_t pgn, ByteSpan p) {
  const std::size_t need = needed_length(pgn);
  if (need == 0) {
    return fail(ErrorCode::kInvalidArgument, "PGN " + std::to_string(pgn) + " not decoded");
  }
  if (p.size() < need) return too_short(pgn, p.size(), need);
  switch (pgn) {
    case kPgnVesselHeading: return decode_heading(p);
    case kPgnRateOfTurn: return decode_rate(p);
    case kPgnAttitude: return decode_attitude(p);
    case kPgnSpeedWater: return decode_speed(p);
    case kPgnWaterDepth: return decode_depth(p);
    case kPgnPositionRapid: return decode_position(p);
    case kPgnCogSogRapid: return decode_cog_sog(p);
    default: return decode_gnss(p);
  }
}

can::Frame single_frame(const Header& h, ByteSpan payload) {
  NAV_ENSURE(payload.size() <= kFrameLength, "a single frame carries at most 8 bytes");
  can::Frame f;
  f.id = to_can_id(h);
  f.extended = true;
  f.dlc = kFrameLength;
  f.data.fill(kPad);
  std::copy(payload.begin(), payload.end(), f.data.begin());
  return f;
}

std::vector<can::Frame> fast_packet_frames(const Header& h, ByteSpan payload,
                                           std::uint8_t sequence) {
  NAV_ENSURE(payload.size() <= kMaxFastPacketLength, "a fast packet carries at most 223 bytes");
  const auto seq = static_cast<std::uint8_t>((sequence & 0x7) << 5);
  std::vector<can::Frame> frames;
  std::array<std::uint8_t, kFrameLength> data{};
  data[0] = seq;
  data[1] = static_cast<std::uint8_t>(payload.size());
  std::size_t taken = std::min<std::size_t>(6, payload.size());
  Bytes first{data[0], data[1]};
  first.insert(first.end(), payload.begin(), payload.begin() + static_cast<long>(taken));
  frames.push_back(single_frame(h, first));
  for (std::uint8_t index = 1; taken < payload.size(); ++index) {
    const std::size_t n = std::min<std::size_t>(7, payload.size() - taken);
    Bytes next{static_cast<std::uint8_t>(seq | index)};
    next.insert(next.end(), payload.begin() + static_cast<long>(taken),
                payload.begin() + static_cast<long>(taken + n));
    frames.push_back(single_frame(h, next));
    taken += n;
  }
  return frames;
}

std::vector<can::Frame> encode_frames(Header h, const Message& m, std::uint8_t sequence) {
  h.pgn = pgn_of(m);
  const Bytes payload = encode(m);
  if (is_fast_packet(h.pgn)) return fast_packet_frames(h, payload, sequence);
  return {single_frame(h, payload)};
}

std::optional<Bytes> FastPacketAssembler::add(std::uint8_t source, std::uint32_t pgn,
                                              ByteSpan data) {
  const auto key = std::make_pair(source, pgn);
  auto it = partial_.find(key);
  if (data.empty()) {
    ++stats_.orphans;
    return std::nullopt;
  }
  const std::uint8_t sequence = data[0] >> 5;
  const std::uint8_t index = data[0] & 0x1F;
  if (it != partial_.end() && std::equal(data.begin(), data.end(), it->second.last_frame.begin(),
                                         it->second.last_frame.end())) {
    ++stats_.duplicates;
    return std::nullopt;
  }
  if (index == 0) {
    if (it != partial_.end()) {  // a new frame 0 restarts: the old message is lost
      ++stats_.discarded;
      partial_.erase(it);
    }
    if (data.size() < 2 || data[1] > kMaxFastPacketLength) {
      ++stats_.discarded;
      return std::nullopt;
    }
    Partial p;
    p.sequence = sequence;
    p.total = data[1];
    const std::size_t n = std::min<std::size_t>({6, p.total, data.size() - 2});
    p.payload.assign(data.begin() + 2, data.begin() + 2 + static_cast<long>(n));
    if (p.payload.size() == p.total) {
      ++stats_.completed;
      return std::move(p.payload);
    }
    if (n < 6) {  // a short frame 0 that does not finish the message
      ++stats_.discarded;
      return std::nullopt;
    }
    p.last_frame.assign(data.begin(), data.end());
    partial_.emplace(key, std::move(p));
    return std::nullopt;
  }
  if (it == partial_.end()) {
    ++stats_.orphans;
    return std::nullopt;
  }
  Partial& p = it->second;
  if (sequence != p.sequence || index != p.next_index) {  // a lost, late or foreign frame
    ++stats_.discarded;
    ++stats_.orphans;
    partial_.erase(it);
    return std::nullopt;
  }
  const std::size_t want = std::min<std::size_t>(7, p.total - p.payload.size());
  if (data.size() - 1 < want) {  // a short frame in the middle: bytes are missing
    ++stats_.discarded;
    partial_.erase(it);
    return std::nullopt;
  }
  p.payload.insert(p.payload.end(), data.begin() + 1, data.begin() + 1 + static_cast<long>(want));
  if (p.payload.size() == p.total) {
    Bytes out = std::move(p.payload);
    partial_.erase(it);
    ++stats_.completed;
    return out;
  }
  p.last_frame.assign(data.begin(), data.end());
  ++p.next_index;
  return std::nullopt;
}

}  // namespace nav::protocols::n2k
