// SPDX-License-Identifier: MIT
// JSON builders of `navbench decode` for the DVLs: NavQuest NQ1, RDI PD0 / PD6, Water Linked
// A50. Wire units are converted to SI (mm/s -> m/s, cm/dm -> m, 0.01 deg -> deg, daPa -> Pa).
#include <cstdio>
#include <string>

#include "decode/decode_builders.hpp"
#include "nav/protocols/navquest_nq1.hpp"
#include "nav/protocols/rdi_pd0.hpp"
#include "nav/protocols/rdi_pd6.hpp"
#include "nav/protocols/waterlinked_a50.hpp"

namespace nav::bench::detail {
namespace {

using protocols::ParseResult;
using protocols::ParseStatus;

/// A result that is malformed over the bytes of a framed message whose fields did not decode.
template <typename M>
ParseResult<json> field_error(const ParseResult<M>& r, const std::string& why) {
  return ParseResult<json>{ParseStatus::kMalformed, r.consumed, std::nullopt, why};
}

/// Values scaled by `scale` (wire unit -> SI).
template <typename T, std::size_t N>
json scaled(const std::array<T, N>& v, double scale) {
  json out = json::array();
  for (const auto& x : v) out.push_back(static_cast<double>(x) * scale);
  return out;
}

const char* nq1_source(protocols::navquest_nq1::VelocityFlag f) {
  switch (f) {
    case protocols::navquest_nq1::VelocityFlag::kBottom: return "bottom";
    case protocols::navquest_nq1::VelocityFlag::kWater: return "water";
    case protocols::navquest_nq1::VelocityFlag::kInvalid: break;
  }
  return "invalid";
}

const char* coordinates_name(protocols::rdi_pd0::Coordinates c) {
  switch (c) {
    case protocols::rdi_pd0::Coordinates::kInstrument: return "instrument";
    case protocols::rdi_pd0::Coordinates::kShip: return "ship";
    case protocols::rdi_pd0::Coordinates::kEarth: return "earth";
    case protocols::rdi_pd0::Coordinates::kBeam: break;
  }
  return "beam";
}

/// "YYYY-MM-DDThh:mm:ss.cc" of a date and time of day.
std::string iso_time(int year, int month, int day, int hour, int minute, int second,
                     int hundredths) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%04d-%02d-%02dT%02d:%02d:%02d.%02d", year, month, day, hour,
                minute, second, hundredths);
  return buf;
}

json pd0_json(const protocols::rdi_pd0::Ensemble& e) {
  namespace pd0 = protocols::rdi_pd0;
  json j{{"type", "pd0_ensemble"}};
  if (const auto& v = e.variable_leader) {
    j["ensemble_number"] = v->ensemble_number;
    const auto& t = v->rtc;
    j["time"] = iso_time(t.year, t.month, t.day, t.hour, t.minute, t.second, t.hundredths);
    j["time_unix_s"] = pd0::unix_seconds(t);
  }
  if (const auto& f = e.fixed_leader) {
    j["firmware"] = std::to_string(f->firmware_version) + "." + std::to_string(f->firmware_revision);
    j["num_beams"] = f->num_beams;
    j["num_cells"] = f->num_cells;
    j["cell_length_m"] = f->cell_length_cm * 0.01;
    j["blank_after_transmit_m"] = f->blank_after_transmit_cm * 0.01;
    j["bin1_distance_m"] = f->bin1_distance_cm * 0.01;
    j["coordinates"] = coordinates_name(pd0::coordinates(*f));
    j["beam_angle_deg"] = or_null(pd0::beam_angle_deg(*f));
    j["looks_up"] = pd0::looks_up(*f);
  }
  if (const auto& v = e.variable_leader) {
    j["bit_result"] = v->bit_result;
    j["speed_of_sound_mps"] = v->speed_of_sound_mps;
    j["transducer_depth_m"] = v->transducer_depth_dm * 0.1;
    j["heading_deg"] = v->heading_cdeg * 0.01;
    j["pitch_deg"] = v->pitch_cdeg * 0.01;
    j["roll_deg"] = v->roll_cdeg * 0.01;
    j["salinity_ppt"] = v->salinity_ppt;
    j["temperature_degC"] = v->temperature_cdegc * 0.01;
    j["pressure_Pa"] = or_null(pd0::pressure_pa(*v));
  }
  j["has_velocity_profile"] = e.velocity.has_value();
  if (const auto& b = e.bottom_track) {
    json ranges = json::array(), velocities = json::array();
    for (std::size_t i = 0; i < 4; ++i) {
      ranges.push_back(or_null(pd0::range_m(b->range_cm[i])));
      velocities.push_back(or_null(pd0::to_mps(b->velocity_mmps[i])));
    }
    const auto vehicle = pd0::vehicle_velocity_mps(*b);
    j["bottom_track"] = json{{"range_m", ranges},
                             {"velocity_mps", velocities},
                             {"vehicle_velocity_mps", vehicle ? json(*vehicle) : json(nullptr)},
                             {"correlation", b->correlation},
                             {"percent_good", b->percent_good}};
  } else {
    j["bottom_track"] = nullptr;
  }
  return j;
}

const char* track_name(protocols::rdi_pd6::Track t) {
  return t == protocols::rdi_pd6::Track::kBottom ? "bottom" : "water";
}

/// Visitor building the JSON of one PD6 line.
struct Pd6Json {
  json operator()(const protocols::rdi_pd6::Attitude& a) const {
    return json{{"type", "pd6_attitude"},
                {"pitch_deg", a.pitch_deg},
                {"roll_deg", a.roll_deg},
                {"heading_deg", a.heading_deg}};
  }
  json operator()(const protocols::rdi_pd6::TimeAndScaling& t) const {
    json j{{"type", "pd6_time_scaling"},
           {"time", iso_time(t.year, t.month, t.day, t.hour, t.minute, t.second, t.hundredths)},
           {"salinity_ppt", t.salinity_ppt},
           {"temperature_degC", t.temperature_degc},
           {"depth_m", t.depth_m},
           {"sound_speed_mps", t.sound_speed_mps},
           {"bit_result", t.bit_result}};
    j["leak"] = t.leak ? json(std::string(1, *t.leak)) : json(nullptr);
    return j;
  }
  json operator()(const protocols::rdi_pd6::InstrumentVelocity& v) const {
    namespace pd6 = protocols::rdi_pd6;
    return json{{"type", "pd6_instrument_velocity"},
                {"track", track_name(v.track)},
                {"velocity_xyz_mps",
                 {or_null(pd6::to_mps(v.xyze_mmps[0])), or_null(pd6::to_mps(v.xyze_mmps[1])),
                  or_null(pd6::to_mps(v.xyze_mmps[2]))}},
                {"error_velocity_mps", or_null(pd6::to_mps(v.xyze_mmps[3]))},
                {"valid", v.valid}};
  }
  json operator()(const protocols::rdi_pd6::ShipVelocity& v) const {
    namespace pd6 = protocols::rdi_pd6;
    return json{{"type", "pd6_ship_velocity"},
                {"track", track_name(v.track)},
                {"transverse_mps", or_null(pd6::to_mps(v.transverse_mmps))},
                {"longitudinal_mps", or_null(pd6::to_mps(v.longitudinal_mmps))},
                {"normal_mps", or_null(pd6::to_mps(v.normal_mmps))},
                {"valid", v.valid}};
  }
  json operator()(const protocols::rdi_pd6::EarthVelocity& v) const {
    namespace pd6 = protocols::rdi_pd6;
    return json{{"type", "pd6_earth_velocity"},
                {"track", track_name(v.track)},
                {"east_mps", or_null(pd6::to_mps(v.east_mmps))},
                {"north_mps", or_null(pd6::to_mps(v.north_mmps))},
                {"up_mps", or_null(pd6::to_mps(v.up_mmps))},
                {"valid", v.valid}};
  }
  json operator()(const protocols::rdi_pd6::Distance& d) const {
    return json{{"type", "pd6_distance"},
                {"track", track_name(d.track)},
                {"east_m", d.east_m},
                {"north_m", d.north_m},
                {"up_m", d.up_m},
                {"range_m", d.range_m},
                {"time_since_good_s", d.time_since_good_s}};
  }
};

/// JSON of one A50 packet; a report whose options do not decode is an error.
Result<json> a50_json(const protocols::waterlinked_a50::Packet& p) {
  namespace a50 = protocols::waterlinked_a50;
  if (p.direction == 'r' && p.command == 'z') {
    const auto v = a50::decode_velocity(p);
    if (!v) return tl::unexpected(v.error());
    return json{{"type", "a50_velocity"},
                {"velocity_mps", {v->vx_mps, v->vy_mps, v->vz_mps}},
                {"valid", v->valid},
                {"altitude_m", v->altitude_m},
                {"fom_mps", v->fom_mps},
                {"covariance_m2ps2", v->covariance},
                {"time_of_validity_unix_s", static_cast<double>(v->time_of_validity_us) * 1e-6},
                {"time_of_transmission_unix_s",
                 static_cast<double>(v->time_of_transmission_us) * 1e-6},
                {"time_since_last_s", v->time_since_last_ms * 1e-3},
                {"status", v->status}};
  }
  if (p.direction == 'r' && p.command == 'u') {
    const auto t = a50::decode_transducer(p);
    if (!t) return tl::unexpected(t.error());
    return json{{"type", "a50_transducer"},     {"id", t->id},
                {"velocity_mps", t->velocity_mps}, {"distance_m", t->distance_m},
                {"rssi_dBm", t->rssi_dbm},        {"nsd_dBm", t->nsd_dbm}};
  }
  if (p.direction == 'r' && p.command == 'p') {
    const auto r = a50::decode_position(p);
    if (!r) return tl::unexpected(r.error());
    return json{{"type", "a50_position"}, {"time_unix_s", r->time_stamp_s},
                {"x_m", r->x_m},          {"y_m", r->y_m},
                {"z_m", r->z_m},          {"pos_std_m", r->pos_std_m},
                {"roll_deg", r->roll_deg}, {"pitch_deg", r->pitch_deg},
                {"yaw_deg", r->yaw_deg},  {"status", r->status}};
  }
  if (p.direction == 'r' && p.command == 'x') {
    const auto v = a50::decode_legacy_velocity(p);
    if (!v) return tl::unexpected(v.error());
    return json{{"type", "a50_legacy_velocity"},
                {"time_since_last_s", v->time_since_last_ms * 1e-3},
                {"velocity_mps", {v->vx_mps, v->vy_mps, v->vz_mps}},
                {"fom_mps", v->fom_mps},
                {"altitude_m", v->altitude_m},
                {"valid", v->valid},
                {"status", v->status}};
  }
  if (p.direction == 'r' && p.command == 't') {
    const auto t = a50::decode_legacy_transducer(p);
    if (!t) return tl::unexpected(t.error());
    return json{{"type", "a50_legacy_transducer"}, {"distance_m", t->distance_m}};
  }
  // Commands and replies this decoder does not interpret: their raw options.
  return json{{"type", "a50_packet"},
              {"direction", std::string(1, p.direction)},
              {"command", std::string(1, p.command)},
              {"options", p.options}};
}

}  // namespace

ParseResult<json> parse_navquest_nq1(protocols::ByteSpan b) {
  namespace nq1 = protocols::navquest_nq1;
  const auto r = nq1::parse(b);
  if (r.status != ParseStatus::kComplete) return with(r, {});
  const auto& m = *r.message;
  const auto vehicle = nq1::vehicle_velocity_mps(m);
  return with(r, json{{"type", "nq1"},
                      {"error_code", m.error_code},
                      {"beam_good", m.beam_good},
                      {"beam_altitude_m", m.beam_altitude_m},
                      {"bottom_radial_mps", scaled(m.bottom_radial_mmps, 1e-3)},
                      {"water_radial_mps", scaled(m.water_radial_mmps, 1e-3)},
                      {"water_credit", m.water_credit},
                      {"velocity_instrument_mps", scaled(m.velocity_instrument_mmps, 1e-3)},
                      {"velocity_instrument_source", nq1_source(m.velocity_instrument_flag)},
                      {"velocity_earth_mps", scaled(m.velocity_earth_mmps, 1e-3)},
                      {"velocity_earth_source", nq1_source(m.velocity_earth_flag)},
                      {"water_velocity_instrument_mps",
                       scaled(m.water_velocity_instrument_mmps, 1e-3)},
                      {"water_velocity_instrument_source",
                       nq1_source(m.water_velocity_instrument_flag)},
                      {"water_velocity_earth_mps", scaled(m.water_velocity_earth_mmps, 1e-3)},
                      {"water_velocity_earth_source", nq1_source(m.water_velocity_earth_flag)},
                      {"vehicle_velocity_mps", vehicle ? json(*vehicle) : json(nullptr)},
                      {"roll_deg", m.roll_deg},
                      {"pitch_deg", m.pitch_deg},
                      {"yaw_deg", m.yaw_deg},
                      {"altitude_m", m.altitude_m},
                      {"temperature_degC", m.temperature_degc},
                      {"pressure_raw", m.pressure},  // unit not documented by LinkQuest
                      {"salinity_ppt", m.salinity_ppt},
                      {"sound_speed_mps", m.sound_speed_mps}});
}

ParseResult<json> parse_rdi_pd0(protocols::ByteSpan b) {
  const auto r = protocols::rdi_pd0::parse(b);
  if (r.status != ParseStatus::kComplete) return with(r, {});
  return with(r, pd0_json(*r.message));
}

ParseResult<json> parse_rdi_pd6(protocols::ByteSpan b) {
  const auto r = protocols::rdi_pd6::parse(b);
  if (r.status != ParseStatus::kComplete) return with(r, {});
  return with(r, std::visit(Pd6Json{}, *r.message));
}

ParseResult<json> parse_waterlinked_a50(protocols::ByteSpan b) {
  const auto r = protocols::waterlinked_a50::parse(b);
  if (r.status != ParseStatus::kComplete) return with(r, {});
  auto j = a50_json(*r.message);
  if (!j) return field_error(r, j.error().detail);
  return with(r, std::move(*j));
}

}  // namespace nav::bench::detail
