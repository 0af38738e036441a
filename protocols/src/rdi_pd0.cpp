// SPDX-License-Identifier: MIT
// Teledyne RDI PD0 ensemble codec (protocols.md section 3b; offsets past the doc's fixed-leader
// list — bytes 36-58 — and the variable leader's 28-47 / 56-64 follow the RDI PD0 layout and
// are checked against OOI's decode of a real Explorer DVL capture in the unit tests).
//
// Ensemble (all multi-byte fields little-endian):
//   0 0x7F, 1 0x7F, 2-3 N = bytes excluding the checksum, 4 spare, 5 k data types,
//   6.. k u16 offsets from byte 0, data types (each opens with its u16 ID), N-N+1 checksum =
//   sum of bytes 0..N-1 mod 65536.
// A data type runs to the next higher offset (or N); real ensembles may carry reserved bytes
// after the last one, so lengths are lower bounds. One table of offsets per data type
// (fixed_leader_fields, …) serves both directions; fields past a data type's length are
// neither read nor written.
#include "nav/protocols/rdi_pd0.hpp"

#include <algorithm>
#include <chrono>
#include <string>
#include <type_traits>

#include "nav/common/ensure.hpp"

namespace nav::protocols::rdi_pd0 {
namespace {

template <typename T>
T get_le(ByteSpan b, std::size_t offset) {
  using U = std::make_unsigned_t<T>;
  U v = 0;
  for (std::size_t i = 0; i < sizeof(T); ++i) {
    v = static_cast<U>(v | static_cast<U>(static_cast<U>(b[offset + i]) << (8 * i)));
  }
  return static_cast<T>(v);
}

template <typename T>
void put_le(std::span<std::uint8_t> b, std::size_t offset, T value) {
  using U = std::make_unsigned_t<T>;
  const auto v = static_cast<U>(value);
  for (std::size_t i = 0; i < sizeof(T); ++i) {
    b[offset + i] = static_cast<std::uint8_t>(v >> (8 * i));
  }
}

/// Reads fields that lie inside a data type's bytes; others keep their value.
struct Reader {
  ByteSpan bytes;
  template <typename T>
  void operator()(std::size_t offset, T& v) const {
    if (offset + sizeof(T) <= bytes.size()) v = get_le<T>(bytes, offset);
  }
  template <typename T, std::size_t N>
  void operator()(std::size_t offset, std::array<T, N>& a) const {
    for (std::size_t i = 0; i < N; ++i) (*this)(offset + i * sizeof(T), a[i]);
  }
};

/// Writes fields that lie inside a data type's bytes.
struct Writer {
  std::span<std::uint8_t> bytes;
  template <typename T>
  void operator()(std::size_t offset, const T& v) const {
    if (offset + sizeof(T) <= bytes.size()) put_le<T>(bytes, offset, v);
  }
  template <typename T, std::size_t N>
  void operator()(std::size_t offset, const std::array<T, N>& a) const {
    for (std::size_t i = 0; i < N; ++i) (*this)(offset + i * sizeof(T), a[i]);
  }
};

// Byte offsets relative to the data type's ID; FL/VL/BT may be const (Writer) or not (Reader).
template <typename IO, typename FL>
void fixed_leader_fields(const IO& io, FL& f) {
  io(2, f.firmware_version), io(3, f.firmware_revision), io(4, f.system_config);
  io(6, f.simulated), io(7, f.lag_length), io(8, f.num_beams), io(9, f.num_cells);
  io(10, f.pings_per_ensemble), io(12, f.cell_length_cm), io(14, f.blank_after_transmit_cm);
  io(16, f.profiling_mode), io(17, f.low_corr_threshold), io(18, f.code_repetitions);
  io(19, f.percent_good_min), io(20, f.error_velocity_max_mmps);
  io(22, f.tpp_minutes), io(23, f.tpp_seconds), io(24, f.tpp_hundredths);
  io(25, f.coord_transform), io(26, f.heading_alignment_cdeg), io(28, f.heading_bias_cdeg);
  io(30, f.sensor_source), io(31, f.sensors_available), io(32, f.bin1_distance_cm);
  io(34, f.transmit_pulse_length_cm), io(36, f.ref_layer_start_cell);
  io(37, f.ref_layer_end_cell), io(38, f.false_target_threshold), io(39, f.spare);
  io(40, f.transmit_lag_distance_cm), io(42, f.cpu_board_serial), io(50, f.system_bandwidth);
  io(52, f.system_power), io(53, f.base_frequency_index), io(54, f.serial_number);
  io(58, f.beam_angle_deg);
}

// Ensemble number and clock are split over several places; see decode/encode_variable_leader.
template <typename IO, typename VL>
void variable_leader_fields(const IO& io, VL& v) {
  io(12, v.bit_result), io(14, v.speed_of_sound_mps), io(16, v.transducer_depth_dm);
  io(18, v.heading_cdeg), io(20, v.pitch_cdeg), io(22, v.roll_cdeg), io(24, v.salinity_ppt);
  io(26, v.temperature_cdegc), io(28, v.mpt_minutes), io(29, v.mpt_seconds);
  io(30, v.mpt_hundredths), io(31, v.heading_std_deg), io(32, v.pitch_std_ddeg);
  io(33, v.roll_std_ddeg), io(34, v.adc), io(42, v.error_status_word), io(46, v.reserved);
  io(48, v.pressure_dapa), io(52, v.pressure_variance_dapa), io(56, v.spare);
}

// Ranges are split into LSB16 (16-23) and MSB (77-80); see decode/encode_bottom_track.
template <typename IO, typename BT>
void bottom_track_fields(const IO& io, BT& b) {
  io(2, b.pings_per_ensemble), io(4, b.delay_before_reacquire), io(6, b.corr_mag_min);
  io(7, b.eval_amp_min), io(8, b.percent_good_min), io(9, b.mode);
  io(10, b.error_velocity_max_mmps), io(12, b.reserved), io(24, b.velocity_mmps);
  io(32, b.correlation);
  io(36, b.eval_amplitude), io(40, b.percent_good), io(44, b.ref_layer_min_dm);
  io(46, b.ref_layer_near_dm), io(48, b.ref_layer_far_dm), io(50, b.ref_layer_velocity_mmps);
  io(58, b.ref_layer_correlation), io(62, b.ref_layer_echo_intensity);
  io(66, b.ref_layer_percent_good), io(70, b.max_tracking_depth_dm), io(72, b.rssi);
  io(76, b.gain);
}

constexpr std::size_t kY2kClockOffset = 57;  ///< VL: century, year, month, …, hundredths

std::uint8_t u8(int v) { return static_cast<std::uint8_t>(v); }

/// A data type of `length` bytes opening with its ID.
Bytes section(std::uint16_t id, std::uint16_t length) {
  Bytes s(length, 0);
  put_le<std::uint16_t>(s, 0, id);
  return s;
}

Bytes encode_fixed_leader(const FixedLeader& f) {
  NAV_ENSURE(f.length >= kFixedLeaderMinLength, "PD0 fixed leader shorter than 42 bytes");
  Bytes s = section(kFixedLeaderId, f.length);
  fixed_leader_fields(Writer{s}, f);
  return s;
}

Bytes encode_variable_leader(const VariableLeader& v) {
  NAV_ENSURE(v.length >= kVariableLeaderMinLength, "PD0 variable leader shorter than 42 bytes");
  NAV_ENSURE(v.ensemble_number < (1u << 24), "PD0 ensemble number has 24 bits");
  const RtcTime& t = v.rtc;
  NAV_ENSURE(t.year >= 1980 && t.year <= 2079, "PD0 RTC year outside 1980..2079");
  Bytes s = section(kVariableLeaderId, v.length);
  const Writer io{s};
  io(2, static_cast<std::uint16_t>(v.ensemble_number & 0xFFFF));
  io(11, static_cast<std::uint8_t>(v.ensemble_number >> 16));
  const std::array<std::uint8_t, 7> rtc = {u8(t.year % 100), u8(t.month),  u8(t.day),
                                           u8(t.hour),       u8(t.minute), u8(t.second),
                                           u8(t.hundredths)};
  io(4, rtc);
  io(kY2kClockOffset, u8(t.year / 100));
  io(kY2kClockOffset + 1, rtc);
  variable_leader_fields(io, v);
  return s;
}

Bytes encode_bottom_track(const BottomTrack& b) {
  NAV_ENSURE(b.length >= kBottomTrackMinLength, "PD0 bottom track shorter than 77 bytes");
  Bytes s = section(kBottomTrackId, b.length);
  const Writer io{s};
  bottom_track_fields(io, b);
  for (std::size_t i = 0; i < 4; ++i) {
    NAV_ENSURE(b.range_cm[i] < (b.length >= 81 ? (1u << 24) : (1u << 16)),
               "PD0 bottom-track range does not fit its bytes");
    io(16 + 2 * i, static_cast<std::uint16_t>(b.range_cm[i] & 0xFFFF));
    io(77 + i, static_cast<std::uint8_t>(b.range_cm[i] >> 16));
  }
  return s;
}

template <typename T>
Bytes encode_profile(std::uint16_t id, const Profile<T>& p, const Ensemble& e) {
  NAV_ENSURE(e.fixed_leader.has_value(), "PD0 profile data needs a fixed leader");
  const std::size_t n = std::size_t{e.fixed_leader->num_cells} * e.fixed_leader->num_beams;
  NAV_ENSURE(p.values.size() == n, "PD0 profile size != num_cells x num_beams");
  Bytes s = section(id, static_cast<std::uint16_t>(2 + n * sizeof(T)));
  for (std::size_t i = 0; i < n; ++i) put_le<T>(s, 2 + i * sizeof(T), p.values[i]);
  return s;
}

FixedLeader decode_fixed_leader(ByteSpan s) {
  FixedLeader f;
  f.length = static_cast<std::uint16_t>(s.size());
  fixed_leader_fields(Reader{s}, f);
  return f;
}

VariableLeader decode_variable_leader(ByteSpan s) {
  VariableLeader v;
  v.length = static_cast<std::uint16_t>(s.size());
  const Reader io{s};
  variable_leader_fields(io, v);
  v.ensemble_number = std::uint32_t{get_le<std::uint16_t>(s, 2)} | std::uint32_t{s[11]} << 16;
  RtcTime& t = v.rtc;
  t.year = s[4] >= 80 ? 1900 + s[4] : 2000 + s[4];
  t.month = s[5], t.day = s[6], t.hour = s[7], t.minute = s[8], t.second = s[9];
  t.hundredths = s[10];
  if (s.size() >= kY2kClockOffset + 8) {  // the Y2K clock carries the century
    const ByteSpan y2k = s.subspan(kY2kClockOffset, 8);
    t.year = y2k[0] * 100 + y2k[1];
    t.month = y2k[2], t.day = y2k[3], t.hour = y2k[4], t.minute = y2k[5], t.second = y2k[6];
    t.hundredths = y2k[7];
  }
  return v;
}

BottomTrack decode_bottom_track(ByteSpan s) {
  BottomTrack b;
  b.length = static_cast<std::uint16_t>(s.size());
  bottom_track_fields(Reader{s}, b);
  for (std::size_t i = 0; i < 4; ++i) {
    const std::uint32_t msb = s.size() >= 81 ? s[77 + i] : 0u;
    b.range_cm[i] = std::uint32_t{get_le<std::uint16_t>(s, 16 + 2 * i)} | msb << 16;
  }
  return b;
}

template <typename T>
Profile<T> decode_profile(ByteSpan s, std::size_t n) {
  Profile<T> p;
  p.values.resize(n);
  for (std::size_t i = 0; i < n; ++i) p.values[i] = get_le<T>(s, 2 + i * sizeof(T));
  return p;
}

std::string hex16(std::uint16_t v) {
  static constexpr char kDigits[] = "0123456789ABCDEF";
  std::string s = "0x";
  for (int shift = 12; shift >= 0; shift -= 4) s.push_back(kDigits[(v >> shift) & 0xF]);
  return s;
}

ParseResult<Ensemble> malformed(std::size_t consumed, std::string error) {
  ParseResult<Ensemble> r;
  r.status = ParseStatus::kMalformed;
  r.consumed = consumed;
  r.error = std::move(error);
  return r;
}

/// Decodes the data types of a checksummed ensemble; an error text when one is unusable.
std::string decode_data_types(ByteSpan ens, const std::vector<std::uint16_t>& offsets,
                              Ensemble& e) {
  std::vector<std::uint16_t> sorted = offsets;
  std::sort(sorted.begin(), sorted.end());
  const auto extent = [&](std::uint16_t off) {
    const auto next = std::upper_bound(sorted.begin(), sorted.end(), off);
    return ens.subspan(off, (next == sorted.end() ? ens.size() : *next) - off);
  };
  for (const std::uint16_t off : offsets) {  // the fixed leader first: profiles need it
    if (get_le<std::uint16_t>(ens, off) != kFixedLeaderId) continue;
    const ByteSpan s = extent(off);
    if (s.size() < kFixedLeaderMinLength)
      return "fixed leader of " + std::to_string(s.size()) + " bytes";
    e.fixed_leader = decode_fixed_leader(s);
  }
  const std::size_t cells_x_beams =
      e.fixed_leader ? std::size_t{e.fixed_leader->num_cells} * e.fixed_leader->num_beams : 0;
  for (const std::uint16_t off : offsets) {
    const std::uint16_t id = get_le<std::uint16_t>(ens, off);
    e.data_type_ids.push_back(id);
    const ByteSpan s = extent(off);
    const auto too_short = [&](const char* what) {
      return std::string(what) + " at offset " + std::to_string(off) + " has " +
             std::to_string(s.size()) + " bytes";
    };
    const bool profile =
        id == kVelocityId || id == kCorrelationId || id == kEchoIntensityId || id == kPercentGoodId;
    if (profile && !e.fixed_leader)
      return "profile data type " + hex16(id) + " without fixed leader";
    const std::size_t need = 2 + cells_x_beams * (id == kVelocityId ? 2 : 1);
    if (profile && s.size() < need) return too_short("profile data type");
    if (id == kVariableLeaderId) {
      if (s.size() < kVariableLeaderMinLength) return too_short("variable leader");
      e.variable_leader = decode_variable_leader(s);
    } else if (id == kBottomTrackId) {
      if (s.size() < kBottomTrackMinLength) return too_short("bottom track");
      e.bottom_track = decode_bottom_track(s);
    } else if (id == kVelocityId) {
      e.velocity = decode_profile<std::int16_t>(s, cells_x_beams);
    } else if (id == kCorrelationId) {
      e.correlation = decode_profile<std::uint8_t>(s, cells_x_beams);
    } else if (id == kEchoIntensityId) {
      e.echo_intensity = decode_profile<std::uint8_t>(s, cells_x_beams);
    } else if (id == kPercentGoodId) {
      e.percent_good = decode_profile<std::uint8_t>(s, cells_x_beams);
    }  // the fixed leader is done; anything else is skipped by its offset
  }
  return {};
}

}  // namespace

std::uint16_t checksum(ByteSpan bytes) {
  std::uint32_t sum = 0;
  for (const std::uint8_t b : bytes) sum += b;
  return static_cast<std::uint16_t>(sum & 0xFFFFu);
}

Bytes encode(const Ensemble& e) {
  std::vector<Bytes> types;
  if (e.fixed_leader) types.push_back(encode_fixed_leader(*e.fixed_leader));
  if (e.variable_leader) types.push_back(encode_variable_leader(*e.variable_leader));
  if (e.velocity) types.push_back(encode_profile(kVelocityId, *e.velocity, e));
  if (e.correlation) types.push_back(encode_profile(kCorrelationId, *e.correlation, e));
  if (e.echo_intensity) types.push_back(encode_profile(kEchoIntensityId, *e.echo_intensity, e));
  if (e.percent_good) types.push_back(encode_profile(kPercentGoodId, *e.percent_good, e));
  if (e.bottom_track) types.push_back(encode_bottom_track(*e.bottom_track));
  NAV_ENSURE(!types.empty(), "PD0 ensemble without data types");

  Bytes out(6 + 2 * types.size(), 0);
  out[0] = kHeaderId;
  out[1] = kHeaderId;
  out[5] = static_cast<std::uint8_t>(types.size());
  for (std::size_t i = 0; i < types.size(); ++i) {
    put_le<std::uint16_t>(out, 6 + 2 * i, static_cast<std::uint16_t>(out.size()));
    out.insert(out.end(), types[i].begin(), types[i].end());
  }
  NAV_ENSURE(out.size() <= 0xFFFF, "PD0 ensemble longer than 65535 bytes");
  put_le<std::uint16_t>(out, 2, static_cast<std::uint16_t>(out.size()));
  const std::uint16_t sum = checksum(out);
  out.push_back(static_cast<std::uint8_t>(sum & 0xFF));
  out.push_back(static_cast<std::uint8_t>(sum >> 8));
  return out;
}

ParseResult<Ensemble> parse(ByteSpan buffer) {
  if (buffer.empty()) return {};  // kNeedMore
  if (buffer[0] != kHeaderId) {
    const auto next = std::find(buffer.begin() + 1, buffer.end(), kHeaderId);
    const auto n = static_cast<std::size_t>(next - buffer.begin());
    return malformed(n, std::to_string(n) + " byte(s) before 0x7F");
  }
  // Reject a false 0x7F7F from the header alone, before waiting for up to 64 KiB.
  if (buffer.size() < 2) return {};
  if (buffer[1] != kHeaderId) return malformed(1, "0x7F not followed by 0x7F");
  if (buffer.size() < 6) return {};
  const std::uint16_t n = get_le<std::uint16_t>(buffer, 2);
  const std::size_t k = buffer[5];
  if (k == 0 || 6 + 2 * k + 2 * k > n) {
    return malformed(1, "byte count " + std::to_string(n) + " cannot hold " + std::to_string(k) +
                            " data type(s)");
  }
  if (buffer.size() < 6 + 2 * k) return {};
  std::vector<std::uint16_t> offsets(k);
  for (std::size_t i = 0; i < k; ++i) {
    offsets[i] = get_le<std::uint16_t>(buffer, 6 + 2 * i);
    if (offsets[i] < 6 + 2 * k || offsets[i] + 2u > n) {
      return malformed(1, "data type offset " + std::to_string(offsets[i]) +
                              " outside the ensemble of " + std::to_string(n) + " bytes");
    }
  }
  const std::size_t total = std::size_t{n} + 2;
  if (buffer.size() < total) return {};
  const ByteSpan ens = buffer.first(n);
  const std::uint16_t received = get_le<std::uint16_t>(buffer, n);
  const std::uint16_t computed = checksum(ens);
  if (received != computed) {
    return malformed(1, "checksum " + hex16(received) + " != computed " + hex16(computed));
  }

  Ensemble e;
  if (std::string error = decode_data_types(ens, offsets, e); !error.empty()) {
    return malformed(total, error);
  }
  ParseResult<Ensemble> r;
  r.status = ParseStatus::kComplete;
  r.consumed = total;
  r.message = std::move(e);
  return r;
}

Coordinates coordinates(const FixedLeader& f) {
  return static_cast<Coordinates>((f.coord_transform >> 3) & 0x3);
}

std::optional<int> beam_angle_deg(const FixedLeader& f) {
  if (f.length >= 59) return f.beam_angle_deg;
  static constexpr std::array<int, 3> kAngles = {15, 20, 30};
  const unsigned code = (f.system_config >> 8) & 0x3u;
  if (code == 3) return std::nullopt;
  return kAngles[code];
}

bool looks_up(const FixedLeader& f) { return (f.system_config & 0x80u) != 0; }

std::optional<double> to_mps(std::int16_t mmps) {
  if (mmps == kBadVelocity) return std::nullopt;
  return mmps / 1000.0;
}

std::optional<double> range_m(std::uint32_t range_cm) {
  if (range_cm == 0) return std::nullopt;
  return range_cm / 100.0;
}

std::optional<std::array<double, 3>> vehicle_velocity_mps(const BottomTrack& b) {
  std::array<double, 3> v{};
  for (std::size_t i = 0; i < 3; ++i) {
    if (b.velocity_mmps[i] == kBadVelocity) return std::nullopt;
    v[i] = -b.velocity_mmps[i] / 1000.0;
  }
  return v;
}

std::optional<double> pressure_pa(const VariableLeader& v) {
  if (v.length < 52) return std::nullopt;
  return v.pressure_dapa * 10.0;
}

double unix_seconds(const RtcTime& t) {
  using namespace std::chrono;
  const sys_days date = year_month_day{year{t.year}, month{static_cast<unsigned>(t.month)},
                                       day{static_cast<unsigned>(t.day)}};
  const auto whole =
      date.time_since_epoch().count() * 86400LL + t.hour * 3600LL + t.minute * 60LL + t.second;
  return static_cast<double>(whole) + t.hundredths / 100.0;
}

}  // namespace nav::protocols::rdi_pd0
