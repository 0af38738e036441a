// SPDX-License-Identifier: MIT
// Acoustic-modem channel between vehicles: a pure model (no I/O, no clock) of modems in
// transparent (data) mode. Bytes a DUT writes to its modem's serial line go in (on_bytes);
// timed deliveries of those bytes to the serial lines of every other modem come out (poll).
// The bench owns the ports and the time; it calls on_bytes with what it read from DUT i and
// the scenario time it read it, and calls poll(t) to learn what to write to which DUT and
// when.
//
// Actors and timing of one packet from node s to node r (times are scenario time [ns]):
//
//   DUT s serial   b b b b ......(idle >= packet_gap)
//                          |last byte t_l      |close t_c = t_l + packet_gap
//                                              |   (or t_c = time of the byte that fills
//                                              |    max_packet_bytes)
//   modem s (half-duplex, one packet at a time) |
//                    start t_0 = max(t_c, end of s's previous packet)
//                    |<-- latency -->|<-- 8 n / bit_rate -->| end t_e
//   water                                                    \  last bit travels tau
//   modem r                                                   \____________ t_d = t_e + tau
//   DUT r serial                                                            bytes written
//
// Model equations (n = packet length [bytes], c = sound_speed_mps):
//   t_c   = t_l + packet_gap                      packet ends by serial idle time, or
//   t_c   = t of the byte that makes n = max_packet_bytes
//   t_0   = max(t_c, t_e of the sender's previous packet)   (serial, half-duplex transmitter)
//   T     = latency + 8 n / bit_rate              time the packet occupies the transmitter
//   t_e   = t_0 + T
//   tau   : c tau = |p_r(t_e + tau) - p_s(t_e)|   one-way travel time of the last bit from
//           where the sender was when it left to where the receiver is when it arrives
//           (straight ray, iso-velocity water), solved by fixed-point iteration from
//           tau_0 = |p_r(t_e) - p_s(t_e)| / c (contraction factor |v_r| / c ~ 1e-3;
//           stopped at |d tau| < 1e-10 s, below the 1 ns resolution of t_d)
//   t_d   = t_e + tau = t_0 + latency + 8 n / bit_rate + range / c
//   range = c tau (the path of the last bit); no delivery (out_of_range) when
//           range > max_range_m
//   lost  = u < loss_probability,  u ~ U[0, 1) (53 bits of one raw engine output)
// Two stationary vehicles 1500 m apart, 10 bytes at 1000 bit/s, latency 0.5 s:
// t_d = t_0 + 0.5 s + 0.08 s + 1 s.
//
// Why the range is taken at the end of the transmission and the receiver's motion is solved
// for, rather than the range at t_0: the delivery time is when the last bit arrives, and both
// vehicles move during T + tau. With T up to latency + 8 * 64 / 1000 ~ 1 s, tau up to
// 2000 m / 1500 m/s ~ 1.33 s and AUV speeds up to ~2 m/s, the range at t_0 can be off by up
// to 2 * 2 m/s * 2.33 s ~ 9 m, i.e. ~6 ms of delivery time, and neglecting only the
// receiver's motion during tau still costs up to 2 m/s * 1.33 s ~ 2.7 m ~ 1.8 ms (metres,
// not millimetres). Solving the fixed point removes both for a few extra truth evaluations.
// What remains neglected is the ray bending of a sound-speed profile (straight rays).
//
// Broadcast: every packet a node sends goes to every other node; each reception is decided
// independently (out of range first, then loss). Not modelled (document before relying on
// them): collisions of two packets at one receiver, a receiver being deaf while it transmits
// itself (half-duplex reception), multipath, range- or SNR-dependent loss, bit errors (a
// packet arrives whole or not at all), the receiving modem's own processing delay (part of
// latency).
//
// Randomness: one std::mt19937_64 per sending node, seeded with
// device_seed(seed, "acoustic_modem/node<s>"). For its k-th packet the sender's engine
// gives exactly one draw per other node, in increasing node index, also when the reception
// is out of range and whatever loss_probability is (0 and 1 included). So the outcome of a
// packet depends only on the seed and on the sender's own byte stream (bytes and times):
// not on how often or when the bench calls poll, not on other nodes' traffic, and not on the loss setting except through the comparison. (One engine
// shared by all senders, as first proposed, would hand out draws in the order packets are
// found closed, which depends on the poll cadence.)
//
// Time contract (NAV_ENSURE): t >= 0; each node's on_bytes times never go backwards; poll
// times never go backwards; on_bytes is never given a time earlier than the latest poll (a
// delivery due before an already-polled time would otherwise come out late). Within these
// rules the deliveries do not depend on the poll cadence.
//
// Why the defaults:
//   bit_rate_bps 1000   low-rate acoustic modems used for vehicle-to-vehicle telemetry run
//                       hundreds to a few thousand bit/s of payload: at ranges of a km or
//                       more, absorption limits the usable band to a few to a few tens of kHz
//                       and multipath spreads of tens of ms force long symbols and strong
//                       coding, so the net rate is a small fraction of the bandwidth.
//   sound_speed 1500    nominal sea water (about 1450-1550 m/s with temperature/salinity).
//   latency 0.5 s       preamble, synchronisation and modem processing: order of 0.1-1 s.
//   max_packet 64 B     small acoustic frames; longer messages span several packets.
//   packet_gap 50 ms    several character times at typical modem baud rates (9600-19200:
//                       ~1 ms per byte), far below the time a message takes on the water.
//   max_range 2000 m    a typical low-rate modem's working range is one to a few km.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <random>
#include <type_traits>
#include <vector>

#include "nav/common/time.hpp"
#include "nav/emulators/truth.hpp"
#include "nav/protocols/parse.hpp"

namespace nav::emulators {

/// Parameters of one acoustic channel (the same for every modem on it).
struct AcousticModemConfig {
  double bit_rate_bps = 1000.0;    ///< acoustic payload rate [bit/s] (> 0)
  double sound_speed_mps = 1500.0; ///< speed of sound, iso-velocity water [m/s] (> 0)
  Duration latency{std::chrono::milliseconds(500)};  ///< preamble + processing per packet,
                                                     ///< occupies the transmitter [ns] (>= 0)
  std::size_t max_packet_bytes = 64;  ///< a packet closes when it holds this many [bytes]
                                      ///< (>= 1)
  Duration packet_gap{std::chrono::milliseconds(50)};  ///< serial idle time that closes a
                                                       ///< packet [ns] (> 0)
  double loss_probability = 0.0;   ///< chance one reception of a packet is lost [-] ([0, 1])
  double max_range_m = 2000.0;     ///< no delivery beyond this range [m] (> 0; may be +inf)
};

/// Bytes to write to one node's serial line (its DUT's modem port).
struct Delivery {
  std::size_t to = 0;      ///< receiving node (index into the constructor's nodes)
  std::size_t from = 0;    ///< sending node
  Duration t_deliver{};    ///< scenario time the last bit reaches the receiver [ns]
  protocols::Bytes bytes;  ///< the packet, exactly as the sender's DUT wrote it
};

/// Counters of one directed link from -> to. packets_sent = packets_delivered +
/// packets_lost + packets_out_of_range + packets in flight (decided, not yet due).
struct LinkStats {
  std::size_t from = 0;                   ///< sending node
  std::size_t to = 0;                     ///< receiving node
  std::uint64_t packets_sent = 0;         ///< packets the sender put on the water
  std::uint64_t packets_delivered = 0;    ///< returned by poll
  std::uint64_t packets_lost = 0;         ///< lost by the loss draw (in range)
  std::uint64_t packets_out_of_range = 0; ///< range > max_range_m (not counted as lost)
  std::uint64_t bytes_delivered = 0;      ///< payload bytes returned by poll [bytes]
  Duration min_propagation{};  ///< smallest travel time tau of a delivered packet [ns]
                               ///< (0 while nothing was delivered)
  Duration max_propagation{};  ///< largest travel time tau of a delivered packet [ns]
                               ///< (0 while nothing was delivered)
};

/// The channel: one modem per node, each on a vehicle with a truth trajectory.
class AcousticChannel {
 public:
  /// nodes[i] is the truth of modem i (its vehicle's, moved to its mount; not owned; must
  /// outlive the channel; non-null). Checks the config by NAV_ENSURE.
  AcousticChannel(const AcousticModemConfig& cfg, std::vector<const Truth*> nodes,
                  std::uint64_t seed);
  /// The same, from the truths of one kind (e.g. TruthTrajectory).
  template <class Kind>
    requires std::is_base_of_v<Truth, Kind>
  AcousticChannel(const AcousticModemConfig& cfg, const std::vector<const Kind*>& nodes,
                  std::uint64_t seed)
      : AcousticChannel(cfg, std::vector<const Truth*>(nodes.begin(), nodes.end()), seed) {}

  /// Serial bytes written by node's DUT, read at scenario time t [ns]. Closes the node's
  /// open packet first if packet_gap elapsed since its last byte (at last byte +
  /// packet_gap), then appends, closing a packet at t each time it reaches
  /// max_packet_bytes.
  void on_bytes(std::size_t node, protocols::ByteSpan bytes, Duration t);

  /// Closes the packets whose gap elapsed by t, and returns every delivery due at or before
  /// t not returned yet, in order of (t_deliver, from, sender's packet number, to).
  std::vector<Delivery> poll(Duration t);

  /// Earliest time something happens without new bytes: an open packet's gap elapses or a
  /// delivery falls due [ns]; nullopt when nothing is pending. A lockstep bench polls then.
  std::optional<Duration> next_event_time() const;

  /// Counters of every directed link, ordered by (from, to), from != to.
  std::vector<LinkStats> link_stats() const;

  /// Number of nodes (modems).
  std::size_t node_count() const { return nodes_.size(); }

 private:
  /// A delivery decided but not yet returned, with its ordering key.
  struct Pending {
    Delivery delivery;
    std::uint64_t packet_seq = 0;  ///< sender's packet number
    Duration propagation{};        ///< tau [ns]
  };

  /// Per-node transmitter state.
  struct Node {
    const Truth* truth = nullptr;
    std::mt19937_64 rng;            ///< loss draws of this node's packets
    protocols::Bytes open;          ///< bytes of the packet being assembled
    Duration last_byte{};           ///< time of the newest byte in `open` [ns]
    Duration last_input{};          ///< time of the latest on_bytes call [ns]
    Duration tx_free{};             ///< end of the last packet on the water [ns]
    std::uint64_t packets = 0;      ///< packets closed so far
  };

  /// Closes node's open packet at t_close and decides its receptions.
  void close_packet(std::size_t node, Duration t_close);
  /// Path length c tau of the last bit leaving `from` at t_e to `to` [m].
  double travel_range_m(std::size_t from, std::size_t to, Duration t_e) const;
  LinkStats& link(std::size_t from, std::size_t to);

  AcousticModemConfig cfg_;
  std::vector<Node> nodes_;
  std::vector<Pending> pending_;
  std::vector<LinkStats> links_;  ///< index from * N + to (diagonal unused)
  Duration last_poll_{};          ///< time of the latest poll [ns]
};

}  // namespace nav::emulators
