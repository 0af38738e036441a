// SPDX-License-Identifier: MIT
// NMEA 0183 VTG, HDT and ZDA (protocols.md section 4; acceptance follows gpsd's
// driver_nmea0183.c). Framing, checksum and the GGA/RMC sentences are in nmea0183.cpp.
//
//   VTG (>= 3.01)  cog_t,T,cog_m,M,sog_kn,N,sog_kmh,K[,mode]
//   VTG (old)      cog_t,cog_m,sog_kn,sog_kmh          -- told apart by field 2 == "T" (gpsd)
//   HDT            heading,T                            -- gpsd keeps 0..360
//   ZDA            hhmmss.ss,dd,mm,yyyy,zh,zm           -- zh signed, e.g. "-1"
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>
#include <utility>

#include "nav/common/ensure.hpp"
#include "nav/protocols/nmea0183.hpp"

namespace nav::protocols::nmea {
namespace {

/// Parses a whole field as a decimal integer (a leading '-' allowed); nullopt otherwise.
std::optional<int> parse_integer(std::string_view field) {
  if (field.empty()) return std::nullopt;
  int v = 0;
  const auto [end, ec] = std::from_chars(field.data(), field.data() + field.size(), v);
  if (ec != std::errc{} || end != field.data() + field.size()) return std::nullopt;
  return v;
}

/// Zero-padded decimal of a non-negative value, at least `width` digits.
std::string padded(int value, int width) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "%0*d", width, value);
  return buf;
}

/// The Sentence is of `type` and has at least `min_fields` fields.
Result<void> check_type(const Sentence& s, std::string_view type, std::size_t min_fields) {
  if (s.type != type) {
    return fail(ErrorCode::kParse,
                "sentence $" + s.talker + s.type + " is not " + std::string(type));
  }
  if (s.fields.size() < min_fields) {
    return fail(ErrorCode::kParse, std::string(type) + " has " + std::to_string(s.fields.size()) +
                                       " fields, needs " + std::to_string(min_fields));
  }
  return {};
}

/// An empty field is nullopt; otherwise it must be a finite number.
Result<std::optional<double>> number_field(const std::string& field, const std::string& name) {
  if (field.empty()) return std::optional<double>{};
  const auto v = parse_number(field);
  if (!v) return fail(ErrorCode::kParse, "field " + name + " '" + field + "' is not a number");
  return std::optional<double>{*v};
}

/// An optional FAA mode field: empty is nullopt, otherwise one upper-case letter.
Result<std::optional<char>> mode_field(const std::string& field) {
  if (field.empty()) return std::optional<char>{};
  if (field.size() != 1 || field[0] < 'A' || field[0] > 'Z') {
    return fail(ErrorCode::kParse, "field mode '" + field + "'");
  }
  return std::optional<char>{field[0]};
}

/// Formats an optional value with `decimals` digits; nullopt is the empty field.
std::string optional_fixed(const std::optional<double>& v, int decimals) {
  return v ? format_fixed(*v, decimals) : std::string{};
}

/// Decodes four numeric fields of a VTG into v (course true, course magnetic, knots, km/h).
Result<void> vtg_values(const Sentence& s, std::size_t i_true, std::size_t i_mag,
                        std::size_t i_kn, std::size_t i_kmh, Vtg& v) {
  auto cog_t = number_field(s.fields[i_true], "course true");
  if (!cog_t) return tl::unexpected(cog_t.error());
  auto cog_m = number_field(s.fields[i_mag], "course magnetic");
  if (!cog_m) return tl::unexpected(cog_m.error());
  auto kn = number_field(s.fields[i_kn], "speed knots");
  if (!kn) return tl::unexpected(kn.error());
  auto kmh = number_field(s.fields[i_kmh], "speed km/h");
  if (!kmh) return tl::unexpected(kmh.error());
  v.cog_true_deg = *cog_t;
  v.cog_mag_deg = *cog_m;
  v.sog_kn = *kn;
  v.sog_kmh = *kmh;
  return {};
}

}  // namespace

Sentence to_sentence(const Vtg& v, std::string talker) {
  if (v.mode) NAV_ENSURE(*v.mode >= 'A' && *v.mode <= 'Z', "VTG mode is an upper-case letter");
  Sentence s{std::move(talker), "VTG", {}};
  s.fields = {optional_fixed(v.cog_true_deg, 2), "T", optional_fixed(v.cog_mag_deg, 2), "M",
              optional_fixed(v.sog_kn, 3),       "N", optional_fixed(v.sog_kmh, 3),     "K"};
  if (v.mode) s.fields.emplace_back(1, *v.mode);
  return s;
}

Sentence to_sentence(const Hdt& h, std::string talker) {
  std::string heading;
  if (h.heading_deg) {
    NAV_ENSURE(std::isfinite(*h.heading_deg), "HDT heading is not finite");
    double deg = std::fmod(*h.heading_deg, 360.0);
    if (deg < 0.0) deg += 360.0;
    heading = format_fixed(deg, 2);
    if (heading == "360.00") heading = "0.00";  // 359.996 rounds up to a full turn
  }
  return Sentence{std::move(talker), "HDT", {heading, "T"}};
}

Sentence to_sentence(const Zda& z, std::string talker) {
  NAV_ENSURE(z.time.month >= 1 && z.time.month <= 12 && z.time.day >= 1 && z.time.day <= 31,
             "ZDA needs a date");
  NAV_ENSURE(z.time.year >= 0 && z.time.year <= 9999, "ZDA year out of range");
  if (z.zone_hours) NAV_ENSURE(std::abs(*z.zone_hours) <= 13, "ZDA zone hours out of range");
  if (z.zone_minutes) {
    NAV_ENSURE(*z.zone_minutes >= 0 && *z.zone_minutes <= 59, "ZDA zone minutes out of range");
  }
  // Round date and time together, so 23:59:59.999 becomes midnight of the next day.
  const UtcTime t = UtcTime::from_unix_seconds(z.time.unix_seconds());
  std::string zone_hours;
  if (z.zone_hours) {
    // gpsd's verified example writes "-1"; receivers write "00" for UTC.
    zone_hours = *z.zone_hours < 0 ? "-" + std::to_string(-*z.zone_hours)
                                   : padded(*z.zone_hours, 2);
  }
  Sentence s{std::move(talker), "ZDA", {}};
  s.fields = {format_time_of_day(t),
              padded(t.day, 2),
              padded(t.month, 2),
              padded(t.year, 4),
              zone_hours,
              z.zone_minutes ? padded(*z.zone_minutes, 2) : std::string{}};
  return s;
}

Result<Vtg> decode_vtg(const Sentence& s) {
  if (auto ok = check_type(s, "VTG", 4); !ok) return tl::unexpected(ok.error());
  const auto& f = s.fields;
  Vtg v;
  // gpsd: field 2 == "T" means the form with unit letters. A receiver without a fix may send
  // eight empty fields; that is the same form.
  const bool with_units = f[1] == "T" || f.size() >= 8;
  if (!with_units) {
    if (f.size() != 4) {
      return fail(ErrorCode::kParse, "old-form VTG has " + std::to_string(f.size()) +
                                         " fields, needs 4");
    }
    if (auto ok = vtg_values(s, 0, 1, 2, 3, v); !ok) return tl::unexpected(ok.error());
    return v;
  }
  if (f.size() < 8) {
    return fail(ErrorCode::kParse,
                "VTG with unit letters has " + std::to_string(f.size()) + " fields, needs 8");
  }
  constexpr std::pair<std::size_t, char> kUnits[] = {{1, 'T'}, {3, 'M'}, {5, 'N'}, {7, 'K'}};
  for (const auto& [i, letter] : kUnits) {
    if (!f[i].empty() && f[i] != std::string(1, letter)) {
      return fail(ErrorCode::kParse, "VTG field " + std::to_string(i + 1) + " '" + f[i] +
                                         "' is not the unit letter '" + letter + "'");
    }
  }
  if (auto ok = vtg_values(s, 0, 2, 4, 6, v); !ok) return tl::unexpected(ok.error());
  if (f.size() > 8) {
    auto mode = mode_field(f[8]);
    if (!mode) return tl::unexpected(mode.error());
    v.mode = *mode;
  }
  return v;
}

Result<Hdt> decode_hdt(const Sentence& s) {
  if (auto ok = check_type(s, "HDT", 1); !ok) return tl::unexpected(ok.error());
  const auto& f = s.fields;
  if (f.size() > 1 && !f[1].empty() && f[1] != "T") {
    return fail(ErrorCode::kParse, "HDT reference '" + f[1] + "' is not 'T'");
  }
  auto heading = number_field(f[0], "heading");
  if (!heading) return tl::unexpected(heading.error());
  Hdt h;
  if (*heading) {
    // gpsd accepts 0..360 inclusive; 360 is the same direction as 0.
    if (**heading < 0.0 || **heading > 360.0) {
      return fail(ErrorCode::kParse, "HDT heading '" + f[0] + "' is outside 0..360");
    }
    h.heading_deg = **heading == 360.0 ? 0.0 : **heading;
  }
  return h;
}

Result<Zda> decode_zda(const Sentence& s) {
  if (auto ok = check_type(s, "ZDA", 4); !ok) return tl::unexpected(ok.error());
  const auto& f = s.fields;
  Zda z;
  if (f[0].empty() || !parse_time_of_day(f[0], z.time)) {
    return fail(ErrorCode::kParse, "field time '" + f[0] + "'");
  }
  const auto day = parse_integer(f[1]);
  const auto month = parse_integer(f[2]);
  const auto year = parse_integer(f[3]);
  if (!day || *day < 1 || *day > 31 || f[1].size() != 2) {
    return fail(ErrorCode::kParse, "field day '" + f[1] + "'");
  }
  if (!month || *month < 1 || *month > 12 || f[2].size() != 2) {
    return fail(ErrorCode::kParse, "field month '" + f[2] + "'");
  }
  if (!year || *year < 0 || f[3].size() != 4) {
    return fail(ErrorCode::kParse, "field year '" + f[3] + "'");
  }
  z.time.day = *day;
  z.time.month = *month;
  z.time.year = *year;
  if (f.size() > 4 && !f[4].empty()) {
    const auto zh = parse_integer(f[4]);
    if (!zh || std::abs(*zh) > 13) {
      return fail(ErrorCode::kParse, "field zone hours '" + f[4] + "'");
    }
    z.zone_hours = *zh;
  }
  if (f.size() > 5 && !f[5].empty()) {
    const auto zm = parse_integer(f[5]);
    if (!zm || *zm < 0 || *zm > 59) {
      return fail(ErrorCode::kParse, "field zone minutes '" + f[5] + "'");
    }
    z.zone_minutes = *zm;
  }
  return z;
}

}  // namespace nav::protocols::nmea
