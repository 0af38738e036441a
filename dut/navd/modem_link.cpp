// SPDX-License-Identifier: MIT
#include "modem_link.hpp"

#include <algorithm>
#include <cmath>

#include "aiding_input.hpp"
#include "nav/common/units.hpp"
#include "nav/protocols/microstrain_gx3.hpp"

namespace nav::dut {
namespace {

namespace modem = protocols::navd_modem;

tl::unexpected<Error> spec_error(std::string_view text, const std::string& why) {
  return fail(ErrorCode::kInvalidArgument,
              "--modem '" + std::string(text) + "': " + why + " (expected PATH[@BAUD])");
}

}  // namespace

Result<ModemSpec> parse_modem_spec(std::string_view text, const std::vector<int>& bauds) {
  auto port = parse_path_baud(text, bauds, ModemSpec{}.baud);
  if (!port) return spec_error(text, port.error().detail);
  return ModemSpec{std::move(port->path), port->baud};
}

std::optional<modem::Position> position_report(const estimator::NavSolution& nav,
                                               std::uint8_t vehicle_id,
                                               std::uint32_t timer_ticks) {
  if (!nav.position_valid) return std::nullopt;
  modem::Position p;
  p.vehicle_id = vehicle_id;
  p.t_s = static_cast<double>(timer_ticks) / protocols::gx3::kTicksPerSecond;
  p.lat_deg = units::rad_to_deg(nav.position.lat_rad);
  p.lon_deg = units::rad_to_deg(nav.position.lon_rad);
  p.depth_m = -nav.position.alt_m;
  // Conservative isotropic figure: the larger per-axis sigma (equal with GPS aiding).
  p.horizontal_std_m = std::max(nav.p_std_m.x(), nav.p_std_m.y());
  if (!modem::encodable(p)) return std::nullopt;
  return p;
}

ModemLink::ModemLink(std::uint8_t vehicle_id, double period_s, std::size_t max_buffer)
    : vehicle_id_(vehicle_id),
      schedule_(period_s),
      decoder_(&protocols::nmea::parse, static_cast<std::uint8_t>('$'), max_buffer) {}

std::string ModemLink::on_ahrs(std::uint32_t timer_ticks, const estimator::NavSolution& nav) {
  if (!nav.position_valid) return {};
  // The first valid position is reported at once; then one report per period.
  if (schedule_.started() && !schedule_.elapsed(timer_ticks)) return {};
  schedule_.mark(timer_ticks);
  const auto report = position_report(nav, vehicle_id_, timer_ticks);
  if (!report) {
    ++counts_.skipped;
    return {};
  }
  return modem::encode(*report);
}

std::vector<modem::Position> ModemLink::feed(protocols::ByteSpan bytes) {
  std::vector<modem::Position> heard;
  sentences_.clear();
  decoder_.feed(bytes, sentences_);
  for (const auto& s : sentences_) {
    if (s.talker + s.type != modem::kAddress) {
      ++counts_.other;
      continue;
    }
    const auto p = modem::decode(s);
    if (!p) {
      ++counts_.fields;
      continue;
    }
    if (p->vehicle_id == vehicle_id_) {
      ++counts_.own;
      continue;
    }
    ++counts_.received;
    ModemPeer& peer = peers_[p->vehicle_id];
    ++peer.received;
    peer.last = *p;
    heard.push_back(*p);
  }
  return heard;
}

std::uint64_t ModemLink::rejected() const {
  return decoder_.rejects().checksum + decoder_.rejects().framing + counts_.fields;
}

std::string ModemLink::counters_text() const {
  std::string peers;
  for (const auto& [id, peer] : peers_) {
    if (!peers.empty()) peers += ",";
    peers += std::to_string(id) + ":" + std::to_string(peer.received);
  }
  const RejectCounts& r = decoder_.rejects();
  return "sent=" + std::to_string(counts_.sent) + " received=" + std::to_string(counts_.received) +
         " rejected=" + std::to_string(rejected()) + " peers=[" + peers + "]" +
         " dropped=" + std::to_string(counts_.dropped) +
         " skipped=" + std::to_string(counts_.skipped) + " own=" + std::to_string(counts_.own) +
         " other=" + std::to_string(counts_.other) + " rejects{checksum=" +
         std::to_string(r.checksum) + " framing=" + std::to_string(r.framing) +
         " sync_bytes=" + std::to_string(r.sync_bytes) +
         " overflow_bytes=" + std::to_string(r.overflow_bytes) +
         " fields=" + std::to_string(counts_.fields) + "}";
}

}  // namespace nav::dut
