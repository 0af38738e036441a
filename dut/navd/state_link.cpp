// SPDX-License-Identifier: MIT
#include "state_link.hpp"

namespace nav::dut {

namespace state = protocols::navd_state;

StateLink::StateLink(std::uint8_t vehicle_id, double period_s, std::size_t max_buffer)
    : vehicle_id_(vehicle_id),
      schedule_(period_s),
      decoder_(&state::parse, state::kSync1, max_buffer) {}

protocols::Bytes StateLink::on_ahrs(std::uint32_t timer_ticks,
                                    const std::optional<state::StateReport>& report) {
  if (!report) return {};
  if (schedule_.started() && !schedule_.elapsed(timer_ticks)) return {};
  schedule_.mark(timer_ticks);
  if (!state::encodable(*report)) {
    ++counts_.skipped;
    return {};
  }
  return state::encode(*report);
}

std::vector<state::StateReport> StateLink::feed(protocols::ByteSpan bytes) {
  std::vector<state::StateReport> heard;
  frames_.clear();
  decoder_.feed(bytes, frames_);
  for (const auto& r : frames_) {
    if (r.vehicle_id == vehicle_id_) {
      ++counts_.own;
      continue;
    }
    ++counts_.received;
    ++received_[r.vehicle_id];
    heard.push_back(r);
  }
  return heard;
}

std::string StateLink::counters_text() const {
  std::string peers;
  for (const auto& [id, n] : received_) {
    if (!peers.empty()) peers += ",";
    peers += std::to_string(id) + ":" + std::to_string(n);
  }
  const RejectCounts& r = decoder_.rejects();
  return "format=state sent=" + std::to_string(counts_.sent) +
         " received=" + std::to_string(counts_.received) +
         " rejected=" + std::to_string(r.checksum + r.framing) + " peers=[" + peers + "]" +
         " dropped=" + std::to_string(counts_.dropped) +
         " skipped=" + std::to_string(counts_.skipped) + " own=" + std::to_string(counts_.own) +
         " rejects{crc=" + std::to_string(r.checksum) + " framing=" + std::to_string(r.framing) +
         " sync_bytes=" + std::to_string(r.sync_bytes) +
         " overflow_bytes=" + std::to_string(r.overflow_bytes) + "}";
}

}  // namespace nav::dut
