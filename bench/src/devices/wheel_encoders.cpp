// SPDX-License-Identifier: MIT
// Device kind `wheel-encoders`: a crawler's two wheel encoders on the vehicle's CAN bus, their
// frames laid out by a DBC (loaded and checked against the codec when the scenario loads).
#include <filesystem>
#include <optional>

#include "devices/device_keys.hpp"
#include "devices/device_kind.hpp"
#include "devices/wheel_encoders.hpp"
#include "nav/common/units.hpp"
#include "nav/emulators/wheel_encoder_emulator.hpp"
#include "nav/protocols/dbc.hpp"
#include "nav/protocols/wheel_encoder.hpp"

namespace nav::bench::detail {
namespace {

using namespace std::chrono_literals;

/// A `wheel-encoders` device's keys: the DBC (loaded and checked against the codec here),
/// the drive geometry, slip and noise.
void read_wheels(const MapReader& m, const Scenario& s, Duration latency,
                 std::optional<double> rate_hz, DeviceSpec& d) {
  namespace fs = std::filesystem;
  auto& w = d.settings.emplace<WheelEncoders>();
  emulators::WheelEncoderConfig& c = w.drive;
  c.latency = latency;
  c.rate_hz = rate_hz;
  const Field f = m.required("dbc");
  const std::string written = f.text("a DBC file path such as fixtures/crawler.dbc");
  fs::path path(written);
  if (path.is_relative()) path = fs::path(s.file).parent_path() / path;
  auto db = protocols::dbc::load(path);
  if (!db) f.fail("cannot use DBC " + path.string() + ": " + db.error().detail);
  auto codec = protocols::wheel_encoder::WheelEncoderCodec::from_database(*db);
  if (!codec) {
    f.fail("DBC " + path.string() +
           " does not fit the wheel encoder codec: " + codec.error().detail);
  }
  w.dbc_path = path.string();
  w.codec =
      std::make_shared<const protocols::wheel_encoder::WheelEncoderCodec>(std::move(*codec));
  if (auto v = m.optional("wheel_radius")) c.wheel_radius_m = read_length_positive(*v);
  if (auto v = m.optional("track")) c.track_width_m = read_length_positive(*v);
  if (auto v = m.optional("slip")) {
    const MapReader sl(*v, {"left", "right", "walk"});
    if (auto x = sl.optional("left")) c.slip.left = x->signed_ratio();
    if (auto x = sl.optional("right")) c.slip.right = x->signed_ratio();
    if (auto x = sl.optional("walk")) {
      const std::string t = x->text("a plain number >= 0 [1/sqrt(s)] such as 0.001");
      const auto n = parse_number(t);
      if (!n || *n < 0.0) {
        x->fail("expected a plain number >= 0 [1/sqrt(s)] such as 0.001, got " + quote_value(t));
      }
      c.slip.walk_std = *n;
    }
  }
  if (auto v = m.optional("errors")) {
    const MapReader e(*v, {"speed", "angle"});
    if (auto x = e.optional("angle")) {
      c.angle_std_rad = x->quantity(Dimension::kAngle, Bound::kNonNegative);
    }
    if (auto x = e.optional("speed")) {
      c.speed_std_radps = x->quantity(Dimension::kAngularRate, Bound::kNonNegative);
    }
  }
}

std::size_t read(const DeviceReadContext& c, DeviceSpec& d) {
  read_wheels(c.m, c.s, c.latency,
              c.m.has("rate") ? std::optional<double>(c.rate_hz) : std::nullopt, d);
  return 0;  // on the CAN bus
}

std::vector<emulators::CanWireFrame> frames(const DeviceSpec& d,
                                            const emulators::Truth& truth,
                                            Duration duration, std::uint64_t seed) {
  const auto& w = d.config<WheelEncoders>();
  return emulators::generate_wheel_encoders(w.drive, *w.codec, truth, duration, seed);
}

/// A wheel frame that decodes: identifier * 256 + MsgCounter (the two wheels share their
/// counter values, so the identifier tells them apart).
std::optional<std::uint64_t> trigger_tag(const DeviceSpec& d, const protocols::can::Frame& f) {
  if (f.rtr || f.error || !d.config<WheelEncoders>().codec->wheel_of(f.id, f.extended)) return std::nullopt;
  protocols::dbc::Frame df{f.id, f.extended, {f.data.begin(), f.data.begin() + f.length()}};
  const auto sample = d.config<WheelEncoders>().codec->decode(df);
  if (!sample) return std::nullopt;
  return std::uint64_t{f.id} * 256 + sample->counter;
}

}  // namespace

const DeviceKind& wheel_encoders_kind() {
  static const DeviceKind kind{
      .name = "wheel-encoders",
      .link = DeviceKind::Link::kCan,
      .baud = 115200,  // unused: on the bus (DeviceSpec's default)
      .rate_hz = 0.0,  // its DBC's message cycle unless `rate` is given
      .latency = 1ms,  // WheelEncoderConfig's default
      .keys = {"name", "type", "dbc", "wheel_radius", "track", "slip", "errors", "rate", "latency",
               "faults"},
      .read = &read,
      .frames = &frames,
      .trigger = {"identifier * 256 + MsgCounter of each WheelEncoderLeft/Right frame",
                  16, nullptr, &trigger_tag},
  };
  return kind;
}

}  // namespace nav::bench::detail
