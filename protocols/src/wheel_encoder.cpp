// SPDX-License-Identifier: MIT
// Crawler wheel encoder frames through a DBC (see wheel_encoder.hpp).
#include "nav/protocols/wheel_encoder.hpp"

#include <cmath>
#include <numbers>
#include <string>
#include <utility>

namespace nav::protocols::wheel_encoder {
namespace {

/// What the code needs of a signal; unset fields are free.
struct Requirement {
  std::string_view name;
  std::optional<std::uint32_t> length;   ///< exact length [bits]
  std::uint32_t max_length = 64;         ///< upper bound on the length [bits]
  bool is_signed = false;                ///< required sign
  bool integral = false;                 ///< factor 1, offset 0 (raw = value)
  std::optional<std::string_view> unit;  ///< required unit text
};

std::string bits(std::uint32_t n) { return std::to_string(n) + " bit" + (n == 1 ? "" : "s"); }

Result<dbc::Signal> checked_signal(const dbc::Message& m, const Requirement& req) {
  const dbc::Signal* s = m.find_signal(req.name);
  const std::string where = "DBC message '" + m.name + "' signal '" + std::string(req.name) + "': ";
  if (s == nullptr) return fail(ErrorCode::kNotFound, where + "expected it (SG_), not found");
  const auto incompatible = [&](const std::string& expected, const std::string& found) {
    return fail(ErrorCode::kInvalidArgument, where + "expected " + expected + ", found " + found);
  };
  if (s->mux_role != dbc::MuxRole::kNone)
    return incompatible("a plain signal", "a multiplexed one");
  if (s->value_type != dbc::ValueType::kInteger)
    return incompatible("an integer signal", "an IEEE float");
  if (req.length && s->length != *req.length)
    return incompatible(bits(*req.length), bits(s->length));
  if (s->length > req.max_length) {
    return incompatible("at most " + bits(req.max_length), bits(s->length));
  }
  if (s->is_signed != req.is_signed) {
    return incompatible(req.is_signed ? "signed (-)" : "unsigned (+)",
                        s->is_signed ? "signed (-)" : "unsigned (+)");
  }
  if (req.integral && (s->factor != 1.0 || s->offset != 0.0)) {
    return incompatible("factor 1 and offset 0",
                        "(" + std::to_string(s->factor) + "," + std::to_string(s->offset) + ")");
  }
  if (req.unit && s->unit != *req.unit) {
    return incompatible("unit \"" + std::string(*req.unit) + "\"", "\"" + s->unit + "\"");
  }
  return *s;
}

std::uint8_t value_of(const dbc::Signal& s, ByteSpan data) {
  return static_cast<std::uint8_t>(*dbc::get_raw(s, data));
}

}  // namespace

Result<WheelEncoderCodec::Layout> WheelEncoderCodec::layout_of(const dbc::Database& db,
                                                               std::string_view message_name) {
  const dbc::Message* m = db.find_message(message_name);
  if (m == nullptr) {
    return fail(ErrorCode::kNotFound,
                "DBC: expected message '" + std::string(message_name) + "' (BO_), not found");
  }
  Layout l;
  l.message = *m;
  const std::string where = "DBC message '" + m->name + "': ";
  auto ticks = checked_signal(*m, {kTicksSignal, 32, 64, false, true, kTicksUnit});
  if (!ticks) return tl::unexpected(ticks.error());
  auto speed = checked_signal(*m, {kSpeedSignal, std::nullopt, 64, true, false, kSpeedUnit});
  if (!speed) return tl::unexpected(speed.error());
  auto counter = checked_signal(*m, {kCounterSignal, std::nullopt, 8, false, true, std::nullopt});
  if (!counter) return tl::unexpected(counter.error());
  auto valid = checked_signal(*m, {kValidSignal, 1, 1, false, true, std::nullopt});
  if (!valid) return tl::unexpected(valid.error());
  l.ticks = std::move(*ticks);
  l.speed = std::move(*speed);
  l.counter = std::move(*counter);
  l.valid = std::move(*valid);
  const auto cycle = db.cycle_time(*m);
  if (!cycle) {
    return fail(ErrorCode::kInvalidArgument,
                where + "expected a positive " + std::string(dbc::kCycleTimeAttribute) + " (BA_)");
  }
  l.cycle_time = *cycle;
  const auto cpr = db.number_attribute(*m, kCountsPerRevAttribute);
  if (!cpr || !(*cpr > 0.0)) {
    return fail(ErrorCode::kInvalidArgument,
                where + "expected a positive " + std::string(kCountsPerRevAttribute) + " (BA_)");
  }
  l.counts_per_rev = *cpr;
  return l;
}

Result<WheelEncoderCodec> WheelEncoderCodec::from_database(const dbc::Database& db) {
  auto left = layout_of(db, kLeftMessage);
  if (!left) return tl::unexpected(left.error());
  auto right = layout_of(db, kRightMessage);
  if (!right) return tl::unexpected(right.error());
  WheelEncoderCodec codec;
  codec.left_ = std::move(*left);
  codec.right_ = std::move(*right);
  return codec;
}

Result<dbc::Frame> WheelEncoderCodec::encode(const WheelEncoderSample& sample) const {
  const Layout& l = layout(sample.wheel);
  dbc::Frame f{l.message.id, l.message.extended, Bytes(l.message.dlc, 0)};
  for (const auto& [signal, value] :
       {std::pair<const dbc::Signal*, double>{&l.ticks, static_cast<double>(sample.ticks)},
        {&l.speed, sample.omega},
        {&l.counter, static_cast<double>(sample.counter)},
        {&l.valid, sample.valid ? 1.0 : 0.0}}) {
    if (auto r = dbc::encode(*signal, value, f.data); !r) {
      return fail(ErrorCode::kInvalidArgument,
                  "message '" + l.message.name + "', " + r.error().detail);
    }
  }
  return f;
}

Result<WheelEncoderSample> WheelEncoderCodec::decode(const dbc::Frame& frame) const {
  const auto wheel = wheel_of(frame.id, frame.extended);
  if (!wheel) {
    return fail(ErrorCode::kInvalidArgument,
                "CAN id " + std::to_string(frame.id) + " is not a wheel encoder message");
  }
  const Layout& l = layout(*wheel);
  if (frame.data.size() < l.message.dlc) {
    return fail(ErrorCode::kInvalidArgument,
                "message '" + l.message.name + "': " + std::to_string(frame.data.size()) +
                    " data bytes, DBC says " + std::to_string(l.message.dlc));
  }
  const auto omega = dbc::decode(l.speed, frame.data);
  if (!omega) return tl::unexpected(omega.error());
  WheelEncoderSample s;
  s.wheel = *wheel;
  s.ticks = static_cast<std::uint32_t>(*dbc::get_raw(l.ticks, frame.data));
  s.omega = *omega;
  s.counter = value_of(l.counter, frame.data);
  s.valid = value_of(l.valid, frame.data) != 0;
  return s;
}

std::optional<Wheel> WheelEncoderCodec::wheel_of(std::uint32_t id, bool extended) const {
  for (const Wheel w : {Wheel::kLeft, Wheel::kRight}) {
    const dbc::Message& m = layout(w).message;
    if (m.id == id && m.extended == extended) return w;
  }
  return std::nullopt;
}

const dbc::Message& WheelEncoderCodec::message(Wheel w) const { return layout(w).message; }

std::chrono::milliseconds WheelEncoderCodec::cycle_time(Wheel w) const {
  return layout(w).cycle_time;
}

double WheelEncoderCodec::angle_per_tick(Wheel w) const {
  return 2.0 * std::numbers::pi / layout(w).counts_per_rev;
}

std::uint32_t WheelEncoderCodec::counter_modulus(Wheel w) const {
  return std::uint32_t{1} << layout(w).counter.length;
}

Result<void> check_database(const dbc::Database& db) {
  const auto codec = WheelEncoderCodec::from_database(db);
  if (!codec) return tl::unexpected(codec.error());
  return {};
}

}  // namespace nav::protocols::wheel_encoder
