// SPDX-License-Identifier: MIT
#include "can_input.hpp"

#include <utility>

namespace nav::dut {
namespace {

namespace n2k = protocols::n2k;
namespace wheel = protocols::wheel_encoder;

/// Extended data page bit of a 29-bit identifier: 0 for NMEA 2000 (and J1939 page 0/1).
constexpr std::uint32_t kEdpBit = 1u << 25;

}  // namespace

Result<CanInput> CanInput::with_dbc(protocols::dbc::Database db) {
  CanInput in;
  if (db.find_message(wheel::kLeftMessage) != nullptr ||
      db.find_message(wheel::kRightMessage) != nullptr) {
    auto codec = wheel::WheelEncoderCodec::from_database(db);
    if (!codec) return tl::unexpected(codec.error());
    in.wheels_.emplace(std::move(*codec));
  }
  for (const auto& m : db.messages) in.dbc_counts_[m.name] = 0;
  in.db_.emplace(std::move(db));
  return in;
}

void CanInput::feed(const protocols::can::Frame& frame) {
  ++frames_;
  if (frame.error) {
    ++rejects_.error_frames;
    const auto r = protocols::can::error_report(frame);
    if (r.classes & protocols::can::kErrBusOff) {
      ++errors_.bus_off;
      errors_.bus_is_off = true;
    }
    if (r.classes & protocols::can::kErrRestarted) {
      ++errors_.restarted;
      errors_.bus_is_off = false;
    }
    if (r.classes & protocols::can::kErrProtocol) ++errors_.protocol;
    if (r.classes & protocols::can::kErrController) ++errors_.controller;
    if (r.classes & protocols::can::kErrCounters) errors_.rx_errors = r.rx_errors;
    return;
  }
  if (frame.rtr) {
    ++rejects_.rtr;
    return;
  }
  // The vehicle's DBC first: it may also describe 29-bit frames of its own.
  if (db_) {
    if (const auto* m = db_->find_message(frame.id, frame.extended)) {
      feed_dbc(*m, frame);
      return;
    }
  }
  if (frame.extended && (frame.id & kEdpBit) == 0) {
    feed_n2k(frame);
    return;
  }
  ++rejects_.unknown_id;
}

void CanInput::feed_dbc(const protocols::dbc::Message& m, const protocols::can::Frame& frame) {
  const protocols::ByteSpan payload = frame.payload();
  if (!protocols::dbc::decode(m, payload)) {
    ++rejects_.dbc;
    return;
  }
  if (wheels_) {
    if (const auto w = wheels_->wheel_of(frame.id, frame.extended)) {
      const protocols::dbc::Frame f{frame.id, frame.extended,
                                    protocols::Bytes(payload.begin(), payload.end())};
      const auto sample = wheels_->decode(f);
      if (!sample) {
        ++rejects_.dbc;
        return;
      }
      (*w == wheel::Wheel::kLeft ? last_left_ : last_right_) = *sample;
      wheel_samples_.push_back(*sample);
    }
  }
  ++dbc_counts_[m.name];
}

void CanInput::feed_n2k(const protocols::can::Frame& frame) {
  const n2k::Header h = n2k::from_can_id(frame.id);
  if (!n2k::decodes(h.pgn)) {
    ++n2k_other_;
    return;
  }
  if (!n2k::is_fast_packet(h.pgn)) {
    keep(h.source, h.pgn, frame.payload());
    return;
  }
  const auto before = assembler_.stats();
  const auto whole = assembler_.add(h.source, h.pgn, frame.payload());
  const auto& after = assembler_.stats();
  rejects_.fast_packet +=
      (after.discarded - before.discarded) + (after.orphans - before.orphans);
  rejects_.fast_packet_dup += after.duplicates - before.duplicates;
  if (whole) keep(h.source, h.pgn, *whole);
}

void CanInput::keep(std::uint8_t source, std::uint32_t pgn, protocols::ByteSpan payload) {
  auto m = n2k::decode(pgn, payload);
  if (!m) {
    ++rejects_.fields;
    return;
  }
  ++n2k_counts_[pgn];
  last_n2k_.insert_or_assign(pgn, std::move(*m));
  last_source_[pgn] = source;
}

std::uint64_t CanInput::n2k_count(std::uint32_t pgn) const {
  const auto it = n2k_counts_.find(pgn);
  return it == n2k_counts_.end() ? 0 : it->second;
}

std::uint64_t CanInput::dbc_count(const std::string& message_name) const {
  const auto it = dbc_counts_.find(message_name);
  return it == dbc_counts_.end() ? 0 : it->second;
}

std::optional<std::uint8_t> CanInput::last_source(std::uint32_t pgn) const {
  const auto it = last_source_.find(pgn);
  if (it == last_source_.end()) return std::nullopt;
  return it->second;
}

std::vector<protocols::wheel_encoder::WheelEncoderSample> CanInput::take_wheel_samples() {
  std::vector<protocols::wheel_encoder::WheelEncoderSample> out;
  out.swap(wheel_samples_);
  return out;
}

std::optional<double> CanInput::angle_per_tick(protocols::wheel_encoder::Wheel w) const {
  if (!wheels_) return std::nullopt;
  return wheels_->angle_per_tick(w);
}

std::string CanInput::counters_text() const {
  std::string s = "frames=" + std::to_string(frames_) + " n2k{";
  for (const std::uint32_t pgn : kPgns) {
    s += std::to_string(pgn) + "=" + std::to_string(n2k_count(pgn)) + ",";
  }
  s += "other=" + std::to_string(n2k_other_) + "} dbc{";
  if (db_) {
    bool first = true;
    for (const auto& m : db_->messages) {
      if (!first) s += ",";
      first = false;
      s += m.name + "=" + std::to_string(dbc_count(m.name));
    }
  }
  s += "} rejects{unknown_id=" + std::to_string(rejects_.unknown_id) +
       ",rtr=" + std::to_string(rejects_.rtr) +
       ",error_frames=" + std::to_string(rejects_.error_frames) +
       ",fields=" + std::to_string(rejects_.fields) +
       ",fast_packet=" + std::to_string(rejects_.fast_packet) +
       ",fast_packet_dup=" + std::to_string(rejects_.fast_packet_dup) +
       ",dbc=" + std::to_string(rejects_.dbc) + "} errors{bus_off=" +
       std::to_string(errors_.bus_off) + ",restarted=" + std::to_string(errors_.restarted) +
       ",protocol=" + std::to_string(errors_.protocol) +
       ",controller=" + std::to_string(errors_.controller) +
       ",rx_errors=" + std::to_string(errors_.rx_errors) + "}";
  return s;
}

}  // namespace nav::dut
