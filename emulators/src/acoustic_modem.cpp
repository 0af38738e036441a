// SPDX-License-Identifier: MIT
// Acoustic-modem channel between vehicles: packetization of serial bytes, half-duplex
// transmit queue, travel time from truth, range cut-off and loss. Model, timing diagram and
// random-draw order: nav/emulators/acoustic_modem.hpp.
#include "nav/emulators/acoustic_modem.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <tuple>
#include <utility>

#include "nav/common/ensure.hpp"
#include "nav/emulators/device.hpp"

namespace nav::emulators {
namespace {

constexpr int kMaxIterations = 50;         ///< fixed-point iterations of the travel time
constexpr double kTravelTolerance_s = 1e-10;  ///< below the 1 ns resolution of the result [s]


}  // namespace

AcousticChannel::AcousticChannel(const AcousticModemConfig& cfg,
                                 std::vector<const Truth*> nodes, std::uint64_t seed)
    : cfg_(cfg) {
  NAV_ENSURE(std::isfinite(cfg.bit_rate_bps) && cfg.bit_rate_bps > 0.0,
             "acoustic modem bit_rate_bps must be > 0");
  NAV_ENSURE(std::isfinite(cfg.sound_speed_mps) && cfg.sound_speed_mps > 0.0,
             "acoustic modem sound_speed_mps must be > 0");
  NAV_ENSURE(cfg.latency.count() >= 0, "acoustic modem latency must be >= 0");
  NAV_ENSURE(cfg.max_packet_bytes >= 1, "acoustic modem max_packet_bytes must be >= 1");
  NAV_ENSURE(cfg.packet_gap.count() > 0, "acoustic modem packet_gap must be > 0");
  NAV_ENSURE(cfg.loss_probability >= 0.0 && cfg.loss_probability <= 1.0,
             "acoustic modem loss_probability must be in [0, 1]");
  NAV_ENSURE(cfg.max_range_m > 0.0, "acoustic modem max_range_m must be > 0");
  NAV_ENSURE(!nodes.empty(), "acoustic channel needs at least one node");

  nodes_.resize(nodes.size());
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    NAV_ENSURE(nodes[i] != nullptr, "acoustic channel node trajectory must not be null");
    nodes_[i].truth = nodes[i];
    nodes_[i].rng.seed(device_seed(seed, "acoustic_modem/node" + std::to_string(i)));
  }
  const std::size_t n = nodes_.size();
  links_.resize(n * n);
  for (std::size_t from = 0; from < n; ++from) {
    for (std::size_t to = 0; to < n; ++to) {
      links_[from * n + to].from = from;
      links_[from * n + to].to = to;
    }
  }
}

void AcousticChannel::on_bytes(std::size_t node, protocols::ByteSpan bytes, Duration t) {
  NAV_ENSURE(node < nodes_.size(), "acoustic channel: node index out of range");
  Node& s = nodes_[node];
  NAV_ENSURE(t.count() >= 0, "acoustic channel: on_bytes time must be >= 0");
  NAV_ENSURE(t >= s.last_input, "acoustic channel: on_bytes time went backwards for a node");
  NAV_ENSURE(t >= last_poll_, "acoustic channel: on_bytes time is before the latest poll");
  s.last_input = t;

  if (!s.open.empty() && t >= s.last_byte + cfg_.packet_gap) {
    close_packet(node, s.last_byte + cfg_.packet_gap);
  }
  std::size_t used = 0;
  while (used < bytes.size()) {
    const std::size_t room = cfg_.max_packet_bytes - s.open.size();
    const std::size_t take = std::min(room, bytes.size() - used);
    const auto first = bytes.begin() + static_cast<std::ptrdiff_t>(used);
    s.open.insert(s.open.end(), first, first + static_cast<std::ptrdiff_t>(take));
    s.last_byte = t;
    used += take;
    if (s.open.size() == cfg_.max_packet_bytes) close_packet(node, t);
  }
}

std::vector<Delivery> AcousticChannel::poll(Duration t) {
  NAV_ENSURE(t.count() >= 0, "acoustic channel: poll time must be >= 0");
  NAV_ENSURE(t >= last_poll_, "acoustic channel: poll time went backwards");
  last_poll_ = t;

  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    const Node& s = nodes_[i];
    if (!s.open.empty() && s.last_byte + cfg_.packet_gap <= t) {
      close_packet(i, s.last_byte + cfg_.packet_gap);
    }
  }

  const auto due_end = std::partition(pending_.begin(), pending_.end(), [t](const Pending& p) {
    return p.delivery.t_deliver <= t;
  });
  std::sort(pending_.begin(), due_end, [](const Pending& a, const Pending& b) {
    return std::tie(a.delivery.t_deliver, a.delivery.from, a.packet_seq, a.delivery.to) <
           std::tie(b.delivery.t_deliver, b.delivery.from, b.packet_seq, b.delivery.to);
  });

  std::vector<Delivery> out;
  out.reserve(static_cast<std::size_t>(due_end - pending_.begin()));
  for (auto it = pending_.begin(); it != due_end; ++it) {
    LinkStats& l = link(it->delivery.from, it->delivery.to);
    if (l.packets_delivered == 0) {
      l.min_propagation = it->propagation;
      l.max_propagation = it->propagation;
    } else {
      l.min_propagation = std::min(l.min_propagation, it->propagation);
      l.max_propagation = std::max(l.max_propagation, it->propagation);
    }
    ++l.packets_delivered;
    l.bytes_delivered += it->delivery.bytes.size();
    out.push_back(std::move(it->delivery));
  }
  pending_.erase(pending_.begin(), due_end);
  return out;
}

std::optional<Duration> AcousticChannel::next_event_time() const {
  std::optional<Duration> next;
  const auto consider = [&next](Duration t) {
    if (!next || t < *next) next = t;
  };
  for (const Node& s : nodes_) {
    if (!s.open.empty()) consider(s.last_byte + cfg_.packet_gap);
  }
  for (const Pending& p : pending_) consider(p.delivery.t_deliver);
  return next;
}

std::vector<LinkStats> AcousticChannel::link_stats() const {
  std::vector<LinkStats> out;
  for (const LinkStats& l : links_) {
    if (l.from != l.to) out.push_back(l);
  }
  return out;
}

void AcousticChannel::close_packet(std::size_t node, Duration t_close) {
  Node& s = nodes_[node];
  NAV_ENSURE(!s.open.empty(), "acoustic channel: closing an empty packet");
  protocols::Bytes bytes = std::move(s.open);
  s.open.clear();
  const std::uint64_t seq = s.packets++;

  // t_0 = max(t_c, previous t_e); T = latency + 8 n / bit_rate; t_e = t_0 + T.
  const Duration t_0 = std::max(t_close, s.tx_free);
  const double bits = 8.0 * static_cast<double>(bytes.size());
  const Duration t_e = t_0 + cfg_.latency + from_seconds(bits / cfg_.bit_rate_bps);
  s.tx_free = t_e;

  for (std::size_t r = 0; r < nodes_.size(); ++r) {
    if (r == node) continue;
    const double u = unit_uniform(s.rng);  // drawn for every receiver, whatever happens
    LinkStats& l = link(node, r);
    ++l.packets_sent;
    const double range_m = travel_range_m(node, r, t_e);
    const double tau_s = range_m / cfg_.sound_speed_mps;
    if (!(range_m <= cfg_.max_range_m)) {
      ++l.packets_out_of_range;
      continue;
    }
    if (u < cfg_.loss_probability) {
      ++l.packets_lost;
      continue;
    }
    Pending p;
    p.propagation = from_seconds(tau_s);
    p.delivery.to = r;
    p.delivery.from = node;
    p.delivery.t_deliver = t_e + p.propagation;  // t_d = t_e + tau
    p.delivery.bytes = bytes;
    p.packet_seq = seq;
    pending_.push_back(std::move(p));
  }
}

double AcousticChannel::travel_range_m(std::size_t from, std::size_t to, Duration t_e) const {
  // c tau = |p_r(t_e + tau) - p_s(t_e)|, iterated on the range r = c tau from
  // r_0 = |p_r(t_e) - p_s(t_e)|. The range itself is returned, so that two stationary
  // vehicles exactly max_range_m apart compare equal, not off by one rounding of c (r / c).
  const Truth& receiver = *nodes_[to].truth;
  const Vec3 p_s = nodes_[from].truth->at(t_e).p_n;
  const double c = cfg_.sound_speed_mps;
  double r = (receiver.at(t_e).p_n - p_s).norm();
  for (int it = 0; it < kMaxIterations; ++it) {
    const double next = (receiver.at(t_e + from_seconds(r / c)).p_n - p_s).norm();
    const double step_s = std::abs(next - r) / c;
    r = next;
    if (step_s < kTravelTolerance_s) break;
  }
  return r;
}

LinkStats& AcousticChannel::link(std::size_t from, std::size_t to) {
  return links_[from * nodes_.size() + to];
}

}  // namespace nav::emulators
