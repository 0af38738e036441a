// SPDX-License-Identifier: MIT
// Faults scheduled by time window on a device's encoded stream (see faults.hpp, design.md
// "Faults").
//
// A message m is inside the window of fault f when f.start <= m.t_valid < f.end. Faults apply
// in the given order, each to the output of the previous one. All randomness comes from ONE
// std::mt19937_64 seeded with `seed`, drawn in this fixed order: fault by fault, message by
// message (stream order), only for messages inside the window:
//   off           no draw            removed
//   stuck         no draw            bytes := those of the last message with t_valid < start
//                                    (greatest t_valid, later one on ties), tag cleared (a
//                                    repeat names a trigger already sent, so it is no new
//                                    trigger) and kept as repeat_of_tag; removed when there
//                                    is none
//   garbage       n raw outputs      bytes := n random bytes (low 8 bits of one raw output
//                                    each), trigger_tag cleared
//   slow          no draw            the i-th message inside the window (i = 0, 1, ...) is
//                                    kept iff i mod k == 0, k = max(1, round(factor))
//   delayed       no draw            t_send += delay, then a stable sort by t_send
//   intermittent  1 uniform u        removed iff u < probability
//   checksum      1 uniform u        iff u < probability: an NMEA-style message ending
//                                    "*hh\r\n" or "*hh\n" gets its last checksum digit replaced
//                                    by another hex digit (value XOR 0xF, case kept), so the
//                                    text still frames but its checksum is wrong; any other
//                                    message gets its last byte XOR 0xFF (the trailing checksum
//                                    / CRC byte of the binary protocols); tag cleared, since a
//                                    DUT must reject the message
//   truncated     1 uniform u, then  iff u < probability and n >= 2: cut to length
//                 1 more if hit      L = 1 + floor(u' (n - 1)) in [1, n - 1], tag cleared
//   byte_loss     1 uniform per byte each byte dropped iff u < probability; the message is
//                                    removed if no byte remains; tag cleared if any dropped
// Uniforms are 53-bit doubles in [0, 1) from one raw output each, so u < 1 always: a
// probability of 1 always hits and 0 never does, and the draws of later messages do not
// depend on the probability.
// messages_affected counts: off, stuck, intermittent, slow, byte_loss the messages removed
// or changed; garbage, delayed every message inside the window (non-empty for garbage);
// checksum, truncated the messages actually altered.
#include "nav/emulators/faults.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <random>

#include "nav/common/ensure.hpp"

namespace nav::emulators {
namespace {

using Kind = FaultSpec::Kind;


bool inside(const WireMessage& m, const FaultSpec& f) {
  return f.start <= m.t_valid && m.t_valid < f.end;
}

int hex_value(std::uint8_t c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}

/// Index of the last checksum digit of an NMEA-style "*hh\r\n" / "*hh\n" ending, if any.
std::optional<std::size_t> nmea_checksum_digit(const protocols::Bytes& b) {
  const std::size_t n = b.size();
  std::size_t eol = 0;  // length of the line ending
  if (n >= 5 && b[n - 2] == '\r' && b[n - 1] == '\n') {
    eol = 2;
  } else if (n >= 4 && b[n - 1] == '\n') {
    eol = 1;
  } else {
    return std::nullopt;
  }
  const std::size_t star = n - eol - 3;
  if (b[star] != '*' || hex_value(b[star + 1]) < 0 || hex_value(b[star + 2]) < 0) {
    return std::nullopt;
  }
  return star + 2;
}

/// Another hex digit for c (value XOR 0xF), in c's case.
std::uint8_t other_hex_digit(std::uint8_t c) {
  const int v = hex_value(c) ^ 0xF;
  const bool lower = c >= 'a' && c <= 'f';
  if (v < 10) return static_cast<std::uint8_t>('0' + v);
  return static_cast<std::uint8_t>((lower ? 'a' : 'A') + (v - 10));
}

/// Corrupts the checksum of a non-empty message (see the table above).
void corrupt_checksum(protocols::Bytes& b) {
  if (const auto digit = nmea_checksum_digit(b)) {
    b[*digit] = other_hex_digit(b[*digit]);
  } else {
    b.back() ^= 0xFF;
  }
}


/// Applies one fault; returns the number of messages affected.
std::size_t apply_one(std::vector<WireMessage>& msgs, const FaultSpec& f,
                      std::mt19937_64& rng) {
  std::vector<WireMessage> out;
  out.reserve(msgs.size());
  std::size_t affected = 0;

  switch (f.kind) {
    case Kind::kOff:
      for (auto& m : msgs) {
        if (inside(m, f)) {
          ++affected;
        } else {
          out.push_back(std::move(m));
        }
      }
      break;

    case Kind::kStuck: {
      std::optional<std::size_t> last;  // index of the message copied
      for (std::size_t i = 0; i < msgs.size(); ++i) {
        if (msgs[i].t_valid < f.start && (!last || msgs[i].t_valid >= msgs[*last].t_valid)) {
          last = i;
        }
      }
      const std::optional<WireMessage> copied =
          last ? std::optional<WireMessage>(msgs[*last]) : std::nullopt;
      for (auto& m : msgs) {
        if (!inside(m, f)) {
          out.push_back(std::move(m));
          continue;
        }
        ++affected;
        if (!copied) continue;  // nothing to repeat: the device is silent
        m.bytes = copied->bytes;
        m.repeat_of_tag = copied->trigger_tag ? copied->trigger_tag : copied->repeat_of_tag;
        m.trigger_tag.reset();
        out.push_back(std::move(m));
      }
      break;
    }

    case Kind::kGarbage:
      for (auto& m : msgs) {
        if (inside(m, f)) {
          for (auto& byte : m.bytes) byte = static_cast<std::uint8_t>(rng() & 0xFF);
          if (!m.bytes.empty()) ++affected;
          m.trigger_tag.reset();
        }
        out.push_back(std::move(m));
      }
      break;

    case Kind::kSlow: {
      const auto k = static_cast<std::size_t>(std::max(1.0, std::round(f.factor)));
      std::size_t i = 0;
      for (auto& m : msgs) {
        if (inside(m, f) && i++ % k != 0) {
          ++affected;
        } else {
          out.push_back(std::move(m));
        }
      }
      break;
    }

    case Kind::kDelayed:
      for (auto& m : msgs) {
        if (inside(m, f)) {
          m.t_send += f.delay;
          ++affected;
        }
        out.push_back(std::move(m));
      }
      std::stable_sort(out.begin(), out.end(), [](const WireMessage& a, const WireMessage& b) {
        return a.t_send < b.t_send;
      });
      break;

    case Kind::kIntermittent:
      for (auto& m : msgs) {
        if (inside(m, f) && unit_uniform(rng) < f.probability) {
          ++affected;
        } else {
          out.push_back(std::move(m));
        }
      }
      break;

    case Kind::kChecksum:
      for (auto& m : msgs) {
        if (inside(m, f) && unit_uniform(rng) < f.probability && !m.bytes.empty()) {
          corrupt_checksum(m.bytes);
          m.trigger_tag.reset();
          ++affected;
        }
        out.push_back(std::move(m));
      }
      break;

    case Kind::kTruncated:
      for (auto& m : msgs) {
        if (inside(m, f) && unit_uniform(rng) < f.probability && m.bytes.size() >= 2) {
          const std::size_t n = m.bytes.size();
          const auto cut = static_cast<std::size_t>(unit_uniform(rng) * static_cast<double>(n - 1));
          m.bytes.resize(1 + std::min(cut, n - 2));  // [1, n - 1]
          m.trigger_tag.reset();
          ++affected;
        }
        out.push_back(std::move(m));
      }
      break;

    case Kind::kByteLoss:
      for (auto& m : msgs) {
        if (!inside(m, f)) {
          out.push_back(std::move(m));
          continue;
        }
        protocols::Bytes kept;
        kept.reserve(m.bytes.size());
        for (const auto byte : m.bytes) {
          if (unit_uniform(rng) >= f.probability) kept.push_back(byte);
        }
        if (kept.size() == m.bytes.size()) {
          out.push_back(std::move(m));
          continue;
        }
        ++affected;
        if (kept.empty()) continue;  // every byte lost: no message at all
        m.bytes = std::move(kept);
        m.trigger_tag.reset();
        out.push_back(std::move(m));
      }
      break;
  }
  msgs = std::move(out);
  return affected;
}

}  // namespace

const char* fault_name(FaultSpec::Kind k) {
  switch (k) {
    case Kind::kOff: return "off";
    case Kind::kStuck: return "stuck";
    case Kind::kGarbage: return "garbage";
    case Kind::kSlow: return "slow";
    case Kind::kDelayed: return "delayed";
    case Kind::kIntermittent: return "intermittent";
    case Kind::kChecksum: return "checksum";
    case Kind::kTruncated: return "truncated";
    case Kind::kByteLoss: return "byte_loss";
  }
  return "unknown";
}

void check_fault_spec(const FaultSpec& f) {
  NAV_ENSURE(f.start <= f.end, "fault window end must not precede its start");
  switch (f.kind) {
    case Kind::kIntermittent:
    case Kind::kChecksum:
    case Kind::kTruncated:
    case Kind::kByteLoss:
      NAV_ENSURE(std::isfinite(f.probability) && f.probability >= 0.0 && f.probability <= 1.0,
                 "fault probability must be in [0, 1]");
      break;
    case Kind::kSlow:
      NAV_ENSURE(std::isfinite(f.factor) && f.factor > 0.0 && f.factor < 1e9,
                 "slow fault factor must be finite and > 0");
      break;
    case Kind::kDelayed:
      NAV_ENSURE(f.delay.count() >= 0, "delayed fault delay must be >= 0");
      break;
    case Kind::kOff:
    case Kind::kStuck:
    case Kind::kGarbage:
      break;
  }
}

std::vector<WireMessage> apply_faults(std::vector<WireMessage> messages,
                                      const std::vector<FaultSpec>& faults, std::uint64_t seed,
                                      std::vector<FaultRecord>* records) {
  for (const auto& f : faults) check_fault_spec(f);
  if (records != nullptr) records->clear();
  std::mt19937_64 rng(seed);
  for (const auto& f : faults) {
    const std::size_t affected = apply_one(messages, f, rng);
    if (records != nullptr) {
      records->push_back(FaultRecord{fault_name(f.kind), to_seconds(f.start), to_seconds(f.end),
                                     affected});
    }
  }
  return messages;
}

}  // namespace nav::emulators
