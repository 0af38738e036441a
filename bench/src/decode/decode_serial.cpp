// SPDX-License-Identifier: MIT
// JSON builders of `navbench decode` for the other serial devices: EBIMU AHRS lines, the Keller
// RS-485 bus, EvoLogics USBL notifications and paper P4's beacon INS frames. Values are converted to SI (deg/s -> rad/s,
// g -> m/s^2, µs -> s).
#include <string>

#include "decode/decode_builders.hpp"
#include "nav/common/units.hpp"
#include "nav/protocols/beacon_ins.hpp"
#include "nav/protocols/ebimu.hpp"
#include "nav/protocols/evologics_usbl.hpp"
#include "nav/protocols/keller_bus.hpp"

namespace nav::bench::detail {
namespace {

using protocols::ParseResult;
using protocols::ParseStatus;

/// values[first .. first + 3) scaled (wire unit -> SI).
json triple(const std::vector<double>& values, std::size_t first, double scale) {
  return json::array({values[first] * scale, values[first + 1] * scale, values[first + 2] * scale});
}

/// An EBIMU line carries no field names; its value count tells the output configuration when
/// that is unambiguous: 3 Euler, 4 quaternion, 9 / 10 either with gyro and accelerometer.
/// 6 / 7 values are orientation plus gyro *or* accelerometer: the rest stays as sent.
json ebimu_json(const protocols::ebimu::Line& line) {
  const auto& v = line.values;
  const std::size_t n = v.size();
  const bool euler = n == 3 || n == 6 || n == 9;
  const bool quaternion = n == 4 || n == 7 || n == 10;
  if (!euler && !quaternion) return json{{"type", "ebimu_values"}, {"values", v}};
  json j{{"type", "ebimu"}};
  const std::size_t rest = euler ? 3 : 4;
  if (euler) {
    j["roll_deg"] = v[0];
    j["pitch_deg"] = v[1];
    j["yaw_deg"] = v[2];
  } else {
    j["quat_wxyz"] = json::array({v[3], v[2], v[1], v[0]});  // sent as z, y, x, w
  }
  if (n - rest == 6) {
    j["rate_radps"] = triple(v, rest, units::kDegToRad);
    j["accel_mps2"] = triple(v, rest + 3, units::kStandardGravity);
  } else if (n - rest == 3) {
    j["rate_or_accel"] = json::array({v[rest], v[rest + 1], v[rest + 2]});  // deg/s or g
  }
  return j;
}

const char* keller_function_name(std::uint8_t f) {
  switch (static_cast<protocols::keller::Function>(f)) {
    case protocols::keller::Function::kInit: return "init";
    case protocols::keller::Function::kSerialNumber: return "serial_number";
    case protocols::keller::Function::kReadChannel: return "read_channel";
    case protocols::keller::Function::kZeroChannel: return "zero_channel";
  }
  return "unknown";
}

/// Name and SI unit suffix of an F73 channel.
std::pair<const char*, const char*> keller_channel(std::uint8_t c) {
  switch (static_cast<protocols::keller::Channel>(c)) {
    case protocols::keller::Channel::kCh0: return {"CH0", ""};
    case protocols::keller::Channel::kP1: return {"P1", "bar"};
    case protocols::keller::Channel::kP2: return {"P2", "bar"};
    case protocols::keller::Channel::kT: return {"T", "degC"};
    case protocols::keller::Channel::kTob1: return {"TOB1", "degC"};
    case protocols::keller::Channel::kTob2: return {"TOB2", "degC"};
  }
  return {"unknown", ""};
}

json keller_request_json(const protocols::keller::Request& r) {
  const auto f = static_cast<std::uint8_t>(r.function);
  json j{{"type", "keller_request"},
         {"address", r.address},
         {"function", f},
         {"function_name", keller_function_name(f)}};
  if (r.function == protocols::keller::Function::kReadChannel) {
    const auto [name, unit] = keller_channel(r.data);
    j["channel"] = r.data;
    j["channel_name"] = name;
    j["unit"] = unit;
  } else if (r.function == protocols::keller::Function::kZeroChannel) {
    j["data"] = r.data;
  }
  return j;
}

/// Visitor building the JSON of a Keller answer body (address added by the caller).
struct KellerAnswerJson {
  std::uint8_t address;
  json operator()(const protocols::keller::InitInfo& i) const {
    return json{{"type", "keller_init"},          {"address", address},
                {"device_class", i.device_class}, {"group", i.group},
                {"firmware_year", i.firmware_year}, {"firmware_week", i.firmware_week},
                {"buffer_size", i.buffer_size},   {"state", i.state}};
  }
  json operator()(const protocols::keller::SerialNumber& s) const {
    return json{{"type", "keller_serial_number"},
                {"address", address},
                {"serial_number", s.serial_number}};
  }
  json operator()(const protocols::keller::ChannelValue& v) const {
    // The answer does not name its channel: the unit (bar for P1/P2, degC for T/TOB1/TOB2)
    // is the "unit" of the keller_request record before it.
    return json{{"type", "keller_channel_value"},
                {"address", address},
                {"value", v.value},
                {"status", v.status}};
  }
  json operator()(const protocols::keller::ZeroAck& z) const {
    return json{{"type", "keller_zero_ack"}, {"address", address}, {"data", z.data}};
  }
  json operator()(const protocols::keller::Exception& e) const {
    return json{{"type", "keller_exception"},
                {"address", address},
                {"function", e.function},
                {"function_name", keller_function_name(e.function)},
                {"code", e.code}};
  }
};

/// Visitor building the JSON of a USBL fix.
struct UsblJson {
  json operator()(const protocols::evologics::UsblLong& u) const {
    return json{{"type", "usbllong"},
                {"current_time_s", u.current_time_s},
                {"measurement_time_s", u.measurement_time_s},
                {"remote_address", u.remote_address},
                {"xyz_m", {u.x_m, u.y_m, u.z_m}},
                {"enu_m", {u.e_m, u.n_m, u.u_m}},
                {"roll_rad", u.roll_rad},
                {"pitch_rad", u.pitch_rad},
                {"yaw_rad", u.yaw_rad},
                {"propagation_time_s", u.propagation_time_us * 1e-6},
                {"rssi_dB", u.rssi_db},
                {"integrity", u.integrity},
                {"accuracy_m", u.accuracy_m}};
  }
  json operator()(const protocols::evologics::UsblAngles& a) const {
    return json{{"type", "usblangles"},
                {"current_time_s", a.current_time_s},
                {"measurement_time_s", a.measurement_time_s},
                {"remote_address", a.remote_address},
                {"local_bearing_rad", a.local_bearing_rad},
                {"local_elevation_rad", a.local_elevation_rad},
                {"bearing_rad", a.bearing_rad},
                {"elevation_rad", a.elevation_rad},
                {"roll_rad", a.roll_rad},
                {"pitch_rad", a.pitch_rad},
                {"yaw_rad", a.yaw_rad},
                {"rssi_dB", a.rssi_db},
                {"integrity", a.integrity},
                {"accuracy_m", a.accuracy_m}};
  }
  json operator()(const protocols::evologics::RelativeAttitude& r) const {
    return json{{"type", "nvbrelatt"},
                {"current_time_s", r.current_time_s},
                {"measurement_time_s", r.measurement_time_s},
                {"remote_address", r.remote_address},
                {"relative_heading_rad", r.relative_heading_rad},
                {"relative_pitch_rad", r.relative_pitch_rad}};
  }
};

}  // namespace

ParseResult<json> parse_ebimu(protocols::ByteSpan b) {
  const auto r = protocols::ebimu::parse(b);
  if (r.status != ParseStatus::kComplete) return with(r, {});
  return with(r, ebimu_json(*r.message));
}

ParseResult<json> parse_keller_bus(protocols::ByteSpan b) {
  namespace keller = protocols::keller;
  const auto req = keller::parse_request(b);
  const auto ans = keller::parse_response(b);
  return first_complete(
      {with(req, req.message ? keller_request_json(*req.message) : json{}),
       with(ans, ans.message ? std::visit(KellerAnswerJson{ans.message->address},
                                          ans.message->body)
                             : json{})});
}

ParseResult<json> parse_evologics_usbl(protocols::ByteSpan b) {
  namespace evo = protocols::evologics;
  const auto r = evo::parse(b);
  if (r.status != ParseStatus::kComplete) return with(r, {});
  json j = std::visit(UsblJson{}, r.message->fix);
  j["framing"] = r.message->framing == evo::Framing::kDataMode ? "data" : "command";
  return with(r, std::move(j));
}

ParseResult<json> parse_beacon_ins(protocols::ByteSpan b) {
  namespace bi = protocols::beacon_ins;
  const auto r = bi::parse(b);
  if (r.status != ParseStatus::kComplete) return with(r, {});
  const bi::Sample& m = *r.message;
  return with(r, json{{"type", "beacon_ins"},
                      {"timer_ticks", m.timer_ticks},
                      {"timer_s", m.timer_ticks / bi::kTimerHz},
                      {"sequence", m.sequence},
                      {"accel_mps2", {m.accel_x_mps2, m.accel_y_mps2, m.accel_z_mps2}},
                      {"yaw_rate_radps", m.yaw_rate_radps},
                      {"pitch_rate_radps", m.pitch_rate_radps},
                      {"heading_rad", m.heading_rad}});
}

}  // namespace nav::bench::detail
