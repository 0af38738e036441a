// SPDX-License-Identifier: MIT
// Keller Series 30/40 pressure transmitter on an RS-485 bus: a polled device answering the
// master's F48/F69/F73/F95 requests (protocols.md section 6a; codec nav/protocols/keller_bus.hpp).
//
// Pressure at the request time t (depth d = p_n.z() of the truth at t, NED down [m]):
//   P_true = p_atm + rho g d      absolute sensor (PA type)                             (K1)
//          = rho g d              gauge sensor (PR type, vented to the atmosphere)
//   P_meas = W(P_true + b_p + s_p n)  b_p = pressure_bias_pa, s_p = pressure_std_pa,     (K2)
//                                 n ~ N(0, 1), W = wrong_at(kPressure, t) (identity when no
//                                 `wrong` fault is active)
//   P1     = (P_meas - P_zero) / 1e5, sent as float32 [bar]                              (K3)
//   P_zero = 0 until an F95 "set zero"; F95 at t stores W(P_true + b_p) at t (the
//            noise-free reading: a model choice, so that P1 reads ~0 at that depth after)
// (K1) inverts the depth conversion of the LSTS/dune Keller driver (Sensors/Keller/Task.cpp),
// depth = P1 * 1e5 / (g rho): with a gauge sensor, or after a zero at the surface, a driver
// using the same rho and g recovers d exactly. 10.00 m at rho 1025 kg/m^3, g 9.80665 m/s^2
// gives 1.005182 bar (the worked example of protocols.md 6a).
//   TOB1   = T + s_T n                T = temperature_degc, s_T = temperature_std_degc [degC]
//
// Requests: every complete request in the received bytes is answered, in order, at
// t_valid = t (the request's end), t_send = t + response_time. Those to another address
// (not cfg.address, not 250) are counted and ignored; an answer always carries cfg.address,
// also to the transparent address 250 (that is how a master learns an unknown address).
//   F48            InitInfo of the config with state = 1 on the first F48 after power-up
//                  (the "just powered up" state DUNE logs), 0 on later ones; initialises
//   not yet F48    any other function: exception 32 (not initialised)
//   F69            cfg.serial_number
//   F73 ch 1 (P1)  (K3) with status 0;  F73 ch 4 (TOB1): temperature;  other: exception 2
//   F95 data 0     stores P_zero, answers data 0;  other data: exception 2
// The codec frames only the four functions above; a request with any other function has no
// known length and is skipped byte by byte as noise (rejected_bytes), never answered.
// The unparsed tail kept for the next call is shorter than the longest request (5 bytes):
// parse_request() says need-more only then, so the buffer is bounded by construction.
//
// Random draws. Device engine (seed): exactly one standard_normal per F73 answer on P1 or
// TOB1, also when the standard deviation is 0 (so enabling noise changes no other draw).
// Fault engine (fault_seed): the draws of faults.cpp, answer by answer, fault by fault, only
// for answers inside the window (start <= t < end):
//   off           none              no answer
//   stuck         none              the last answer (as left by the earlier faults) of a
//                                   request before the window is sent instead; none: no answer
//   garbage       n raw outputs     n random bytes (low 8 bits of each output)
//   slow          none              the i-th answer in the window is kept iff
//                                   i mod round(factor) == 0
//   delayed       none              t_send += delay
//   intermittent  1 uniform u       dropped iff u < probability
//   checksum      1 uniform u       iff u < probability: last byte (CRC low byte) XOR 0xFF
//   truncated     1 uniform u (+1)  iff u < probability and n >= 2: cut to 1 + floor(u'(n-1))
//                                   bytes, in [1, n - 1]
//   byte_loss     1 uniform / byte  each byte dropped iff u < probability; none left: dropped
// Counts (FaultRecord::messages_affected), as in faults.cpp: off, stuck, garbage, delayed
// every answer inside the window; slow, intermittent the answers dropped; checksum,
// truncated, byte_loss the answers actually altered.
#include "nav/emulators/keller_emulator.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>
#include <variant>

#include "nav/common/ensure.hpp"

namespace nav::emulators {
namespace {

namespace kb = protocols::keller;
using Kind = FaultSpec::Kind;

constexpr double kPaPerBar = 1e5;  ///< [Pa/bar]
constexpr std::size_t kMaxRequestLength = 5;  ///< F73 / F95 [bytes]


bool inside(Duration t, const FaultSpec& f) { return f.start <= t && t < f.end; }

bool finite_non_negative(double v) { return std::isfinite(v) && v >= 0.0; }

void check_config(const KellerConfig& c) {
  NAV_ENSURE(c.address >= 1 && c.address <= kb::kMaxAddress, "Keller address must be 1..250");
  NAV_ENSURE(std::isfinite(c.density_kgpm3) && c.density_kgpm3 > 0.0,
             "Keller density_kgpm3 must be > 0");
  NAV_ENSURE(std::isfinite(c.gravity_mps2) && c.gravity_mps2 > 0.0,
             "Keller gravity_mps2 must be > 0");
  NAV_ENSURE(finite_non_negative(c.atmosphere_pa), "Keller atmosphere_pa must be >= 0");
  NAV_ENSURE(finite_non_negative(c.pressure_std_pa) && std::isfinite(c.pressure_bias_pa),
             "Keller pressure errors must be finite, std >= 0");
  NAV_ENSURE(std::isfinite(c.temperature_degc) && finite_non_negative(c.temperature_std_degc),
             "Keller temperature must be finite, std >= 0");
  NAV_ENSURE(c.response_time.count() >= 0, "Keller response_time must be >= 0");
}

kb::Exception exception_body(kb::Function f, kb::ExceptionCode code) {
  return kb::Exception{static_cast<std::uint8_t>(f), static_cast<std::uint8_t>(code)};
}

}  // namespace

KellerEmulator::KellerEmulator(const KellerConfig& cfg, const Truth& truth,
                               std::vector<FaultSpec> faults, std::uint64_t seed,
                               std::uint64_t fault_seed)
    : cfg_(cfg),
      truth_(&truth),
      faults_(std::move(faults)),
      affected_(faults_.size(), 0),
      in_window_(faults_.size(), 0),
      stuck_bytes_(faults_.size()),
      has_stuck_(faults_.size(), false),
      rng_(seed),
      fault_rng_(fault_seed) {
  check_config(cfg_);
  for (const auto& f : faults_) check_fault_spec(f);
}

double KellerEmulator::pressure_bar(double depth_m) const {
  const double hydrostatic_pa = cfg_.density_kgpm3 * cfg_.gravity_mps2 * depth_m;  // (K1)
  const double p_pa = cfg_.gauge ? hydrostatic_pa : cfg_.atmosphere_pa + hydrostatic_pa;
  return p_pa / kPaPerBar;
}

kb::Response KellerEmulator::answer(const kb::Request& q, Duration t) {
  kb::Response r;
  r.address = cfg_.address;
  if (q.function == kb::Function::kInit) {
    kb::InitInfo info = cfg_.init;
    info.state = static_cast<std::uint8_t>(initialised_ ? 0 : 1);
    initialised_ = true;
    r.body = info;
    return r;
  }
  if (!initialised_) {
    r.body = exception_body(q.function, kb::ExceptionCode::kNotInitialised);
    return r;
  }
  // Noise-free reading W(P_true + b_p) at t [Pa], for F73 P1 and F95.
  const auto reading_pa = [&](double noise_pa) {
    const double depth_m = truth_->at(t).p_n.z();
    const double p_pa = pressure_bar(depth_m) * kPaPerBar + cfg_.pressure_bias_pa + noise_pa;
    return wrong_at(cfg_.measurement_faults, Quantity::kPressure, t).apply(p_pa);  // (K2)
  };
  switch (q.function) {
    case kb::Function::kSerialNumber:
      r.body = kb::SerialNumber{cfg_.serial_number};
      break;
    case kb::Function::kReadChannel:
      if (q.data == static_cast<std::uint8_t>(kb::Channel::kP1)) {
        const double noise_pa = cfg_.pressure_std_pa * standard_normal(rng_);
        const double p1_bar = (reading_pa(noise_pa) - zero_offset_pa_) / kPaPerBar;  // (K3)
        r.body = kb::ChannelValue{static_cast<float>(p1_bar), 0};
      } else if (q.data == static_cast<std::uint8_t>(kb::Channel::kTob1)) {
        const double t_degc = cfg_.temperature_degc +
                              cfg_.temperature_std_degc * standard_normal(rng_);
        r.body = kb::ChannelValue{static_cast<float>(t_degc), 0};
      } else {
        r.body = exception_body(q.function, kb::ExceptionCode::kBadParameter);
      }
      break;
    case kb::Function::kZeroChannel:
      if (q.data == 0) {
        zero_offset_pa_ = reading_pa(0.0);
        r.body = kb::ZeroAck{0};
      } else {
        r.body = exception_body(q.function, kb::ExceptionCode::kBadParameter);
      }
      break;
    case kb::Function::kInit:
      break;  // answered above
  }
  return r;
}

bool KellerEmulator::apply_faults(WireMessage& m) {
  for (std::size_t i = 0; i < faults_.size(); ++i) {
    const FaultSpec& f = faults_[i];
    if (m.t_valid < f.start) {  // a candidate for a later stuck window
      stuck_bytes_[i] = m.bytes;
      has_stuck_[i] = true;
      continue;
    }
    if (!inside(m.t_valid, f)) continue;
    switch (f.kind) {
      case Kind::kOff:
        ++affected_[i];
        return false;
      case Kind::kStuck:
        ++affected_[i];
        if (!has_stuck_[i]) return false;  // nothing to repeat: the device is silent
        m.bytes = stuck_bytes_[i];
        break;
      case Kind::kGarbage:
        for (auto& byte : m.bytes) byte = static_cast<std::uint8_t>(fault_rng_() & 0xFF);
        if (!m.bytes.empty()) ++affected_[i];
        break;
      case Kind::kSlow: {
        const auto k = static_cast<std::uint64_t>(std::max(1.0, std::round(f.factor)));
        if (in_window_[i]++ % k != 0) {
          ++affected_[i];
          return false;
        }
        break;
      }
      case Kind::kDelayed:
        m.t_send += f.delay;
        ++affected_[i];
        break;
      case Kind::kIntermittent:
        if (unit_uniform(fault_rng_) < f.probability) {
          ++affected_[i];
          return false;
        }
        break;
      case Kind::kChecksum:
        if (unit_uniform(fault_rng_) < f.probability && !m.bytes.empty()) {
          m.bytes.back() ^= 0xFF;  // the CRC's low byte (sent last)
          ++affected_[i];
        }
        break;
      case Kind::kTruncated:
        if (unit_uniform(fault_rng_) < f.probability && m.bytes.size() >= 2) {
          const std::size_t n = m.bytes.size();
          const auto cut = static_cast<std::size_t>(unit_uniform(fault_rng_) *
                                                    static_cast<double>(n - 1));
          m.bytes.resize(1 + std::min(cut, n - 2));  // [1, n - 1]
          ++affected_[i];
        }
        break;
      case Kind::kByteLoss: {
        protocols::Bytes kept;
        kept.reserve(m.bytes.size());
        for (const auto byte : m.bytes) {
          if (unit_uniform(fault_rng_) >= f.probability) kept.push_back(byte);
        }
        if (kept.size() == m.bytes.size()) break;
        ++affected_[i];
        if (kept.empty()) return false;  // every byte lost: no answer at all
        m.bytes = std::move(kept);
        break;
      }
    }
  }
  return true;
}

std::vector<WireMessage> KellerEmulator::on_bytes(protocols::ByteSpan bytes, Duration t) {
  rx_.insert(rx_.end(), bytes.begin(), bytes.end());
  std::vector<WireMessage> out;
  std::size_t pos = 0;
  while (pos < rx_.size()) {
    const auto p = kb::parse_request(protocols::ByteSpan(rx_).subspan(pos));
    if (p.status == protocols::ParseStatus::kNeedMore) break;
    pos += p.consumed;
    if (p.status == protocols::ParseStatus::kMalformed) {
      counters_.rejected_bytes += p.consumed;
      continue;
    }
    const kb::Request& q = *p.message;
    if (q.address != cfg_.address && q.address != kb::kTransparentAddress) {
      ++counters_.other_address;
      continue;
    }
    ++counters_.requests;
    const kb::Response r = answer(q, t);
    ++counters_.answers;
    if (std::holds_alternative<kb::Exception>(r.body)) ++counters_.exceptions;
    WireMessage m;
    m.t_valid = t;
    m.t_send = t + cfg_.response_time;
    m.bytes = kb::encode(r);
    if (apply_faults(m)) out.push_back(std::move(m));
  }
  rx_.erase(rx_.begin(), rx_.begin() + static_cast<std::ptrdiff_t>(pos));
  NAV_ENSURE(rx_.size() < kMaxRequestLength, "Keller receive tail must be shorter than a request");
  return out;
}

std::vector<FaultRecord> KellerEmulator::fault_records() const {
  std::vector<FaultRecord> records;
  records.reserve(faults_.size());
  for (std::size_t i = 0; i < faults_.size(); ++i) {
    const FaultSpec& f = faults_[i];
    records.push_back(
        FaultRecord{fault_name(f.kind), to_seconds(f.start), to_seconds(f.end), affected_[i]});
  }
  return records;
}

}  // namespace nav::emulators
