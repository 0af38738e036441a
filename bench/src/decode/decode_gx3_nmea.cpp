// SPDX-License-Identifier: MIT
// `navbench decode` for the MicroStrain GX3 and NMEA 0183 (with navd's $PNVBSOL, $PNVBCOV,
// $PNVBINN and $PNVBPOS):
// one codec message in, one JSON object out (decode/decode_builders.hpp).
#include <charconv>
#include <cstdio>

#include "decode/decode_builders.hpp"
#include "nav/common/units.hpp"
#include "nav/protocols/microstrain_gx3.hpp"
#include "nav/protocols/navd_modem.hpp"
#include "nav/protocols/navd_covariance.hpp"
#include "nav/protocols/navd_innovation.hpp"
#include "nav/protocols/navd_solution.hpp"
#include "nav/protocols/nmea0183.hpp"

namespace nav::bench::detail {
namespace {

using json = nlohmann::ordered_json;
using protocols::ParseResult;
using protocols::ParseStatus;

json triad(const std::array<float, 3>& v, double scale) {
  return json::array({v[0] * scale, v[1] * scale, v[2] * scale});
}

json gx3_accel_rate_mag_json(const protocols::gx3::AccelRateMag& m) {
  return json{{"type", "gx3_accel_rate_mag"},
              {"accel_mps2", triad(m.accel_g, units::kStandardGravity)},
              {"rate_radps", triad(m.rate_radps, 1.0)},
              {"mag_uT", triad(m.mag_gauss, units::kGaussToTesla * 1e6)},
              {"timer_ticks", m.timer_ticks},
              {"timer_s", m.timer_ticks / protocols::gx3::kTicksPerSecond}};
}

json gx3_euler_json(const protocols::gx3::EulerAngles& m) {
  return json{{"type", "gx3_euler_angles"},
              {"roll_rad", m.roll_rad},
              {"pitch_rad", m.pitch_rad},
              {"yaw_rad", m.yaw_rad},
              {"timer_ticks", m.timer_ticks},
              {"timer_s", m.timer_ticks / protocols::gx3::kTicksPerSecond}};
}

json gx3_continuous_json(const protocols::gx3::ContinuousModeReply& m) {
  return json{{"type", "gx3_continuous_mode"},
              {"command", m.command},
              {"timer_ticks", m.timer_ticks},
              {"timer_s", m.timer_ticks / protocols::gx3::kTicksPerSecond}};
}

/// Every GX3 reply parser at this byte; the one that completes wins.
}  // namespace

ParseResult<json> parse_gx3(protocols::ByteSpan b) {
  namespace gx3 = protocols::gx3;
  const auto arm = gx3::parse(b);
  const auto euler = gx3::parse_euler_angles(b);
  const auto cont = gx3::parse_continuous_mode_reply(b);
  return detail::first_complete(
      {with(arm, arm.message ? gx3_accel_rate_mag_json(*arm.message) : json{}),
       with(euler, euler.message ? gx3_euler_json(*euler.message) : json{}),
       with(cont, cont.message ? gx3_continuous_json(*cont.message) : json{})});
}

namespace {

std::string time_text(const protocols::nmea::UtcTime& t) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%02d:%02d:%05.2f", t.hour, t.minute, t.second);
  return buf;
}

std::string date_text(const protocols::nmea::UtcTime& t) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "%04d-%02d-%02d", t.year, t.month, t.day);
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
  if (s.talker + s.type == protocols::navd::kCovarianceAddress) {
    auto cov = protocols::navd::decode_covariance(s);
    if (!cov) return json{{"type", "error"}, {"error", cov.error().detail}};
    j["trigger_tag"] = cov->trigger_tag;
    const auto block = [](const std::optional<protocols::navd::CovarianceBlock>& b) {
      return b ? json{{"sigma", b->sigma}, {"rho", b->rho}} : json(nullptr);
    };
    j["position_m"] = block(cov->position);
    j["velocity_mps"] = block(cov->velocity);
    j["attitude_deg"] = block(cov->attitude);
    return j;
  }
  if (s.talker + s.type == protocols::navd::kInnovationAddress) {
    auto in = protocols::navd::decode_innovation(s);
    if (!in) return json{{"type", "error"}, {"error", in.error().detail}};
    const auto m = static_cast<std::size_t>(in->dof);
    j["trigger_tag"] = in->trigger_tag;
    j["source"] = in->source;
    j["m"] = in->dof;
    j["nu"] = std::vector<double>(in->nu.begin(), in->nu.begin() + static_cast<std::ptrdiff_t>(m));
    j["sigma"] =
        std::vector<double>(in->sigma.begin(), in->sigma.begin() + static_cast<std::ptrdiff_t>(m));
    j["rho"] = std::vector<double>(in->rho.begin(),
                                   in->rho.begin() + static_cast<std::ptrdiff_t>(m * (m - 1) / 2));
    return j;
  }
  if (s.talker + s.type == protocols::navd_modem::kAddress) {
    auto pos = protocols::navd_modem::decode(s);
    if (!pos) return json{{"type", "error"}, {"error", pos.error().detail}};
    j["vehicle_id"] = pos->vehicle_id;
    j["t_s"] = pos->t_s;
    j["lat_deg"] = pos->lat_deg;
    j["lon_deg"] = pos->lon_deg;
    j["depth_m"] = pos->depth_m;
    j["horizontal_std_m"] = pos->horizontal_std_m;
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
    j["time_utc"] = time_text(r->time);
    j["date"] = date_text(r->time);
    j["valid"] = r->valid;
    put(j, "lat_deg", r->lat_deg);
    put(j, "lon_deg", r->lon_deg);
    j["sog_mps"] = r->sog_kn ? json(*r->sog_kn * units::kKnotToMps) : json(nullptr);
    put(j, "cog_deg", r->cog_deg);
    j["mode"] = std::string(1, r->mode);
    return j;
  }
  if (s.type == "VTG") {
    auto v = nmea::decode_vtg(s);
    if (!v) return json{{"type", "error"}, {"error", v.error().detail}};
    put(j, "cog_true_deg", v->cog_true_deg);
    put(j, "cog_mag_deg", v->cog_mag_deg);
    j["sog_mps"] = v->sog_kn ? json(*v->sog_kn * units::kKnotToMps) : json(nullptr);
    j["sog_from_kmh_mps"] = v->sog_kmh ? json(*v->sog_kmh / 3.6) : json(nullptr);
    j["mode"] = v->mode ? json(std::string(1, *v->mode)) : json(nullptr);
    return j;
  }
  if (s.type == "HDT") {
    auto h = nmea::decode_hdt(s);
    if (!h) return json{{"type", "error"}, {"error", h.error().detail}};
    put(j, "heading_deg", h->heading_deg);
    return j;
  }
  if (s.type == "ZDA") {
    auto z = nmea::decode_zda(s);
    if (!z) return json{{"type", "error"}, {"error", z.error().detail}};
    j["time_utc"] = time_text(z->time);
    j["date"] = date_text(z->time);
    j["time_unix_s"] = z->time.unix_seconds();
    put(j, "zone_hours", z->zone_hours);
    put(j, "zone_minutes", z->zone_minutes);
    return j;
  }
  j["fields"] = s.fields;  // a sentence this decoder does not interpret: its raw fields
  return j;
}

}  // namespace

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

}  // namespace nav::bench::detail
