// SPDX-License-Identifier: MIT
#include "keller_poller.hpp"

#include <type_traits>
#include <variant>

#include "nav/common/units.hpp"

namespace nav::dut {
namespace {

namespace keller = protocols::keller;

constexpr double kPaPerBar = 1e5;  ///< [Pa/bar]

/// The function an answer belongs to (an exception names the function that failed).
std::uint8_t answered_function(const keller::Response& a) {
  return std::visit(
      [](const auto& body) -> std::uint8_t {
        using T = std::decay_t<decltype(body)>;
        if constexpr (std::is_same_v<T, keller::InitInfo>) {
          return static_cast<std::uint8_t>(keller::Function::kInit);
        } else if constexpr (std::is_same_v<T, keller::SerialNumber>) {
          return static_cast<std::uint8_t>(keller::Function::kSerialNumber);
        } else if constexpr (std::is_same_v<T, keller::ChannelValue>) {
          return static_cast<std::uint8_t>(keller::Function::kReadChannel);
        } else if constexpr (std::is_same_v<T, keller::ZeroAck>) {
          return static_cast<std::uint8_t>(keller::Function::kZeroChannel);
        } else {
          return body.function;
        }
      },
      a.body);
}

}  // namespace

double depth_from_p1_bar(double p1_bar, double atmosphere_pa, double density_kgpm3) {
  return (p1_bar * kPaPerBar - atmosphere_pa) / (density_kgpm3 * units::kStandardGravity);
}

KellerPoller::KellerPoller(double poll_period_s, std::uint8_t address)
    : address_(address), schedule_(poll_period_s) {}

protocols::Bytes KellerPoller::request(keller::Function f, std::uint8_t data) {
  ++counts_.requests;
  if (f == keller::Function::kInit) {
    ++counts_.inits;
    init_pending_ = false;
  }
  outstanding_ = f;
  return keller::encode(keller::Request{address_, f, data});
}

protocols::Bytes KellerPoller::start() { return request(keller::Function::kInit, 0); }

protocols::Bytes KellerPoller::on_ahrs(std::uint32_t timer_ticks) {
  if (!schedule_.started()) {
    // The first sample is the origin: the first poll comes one period later, which also
    // leaves the start-up F48 a whole period for its answer.
    schedule_.mark(timer_ticks);
    return {};
  }
  // Wrap-safe (ahrs_period.hpp): a timer that went backwards polls at once.
  if (schedule_.elapsed(timer_ticks)) {
    schedule_.mark(timer_ticks);
    init_since_poll_ = false;
    if (outstanding_) {
      ++counts_.timeouts;
      outstanding_.reset();
    }
    if (init_pending_) return request(keller::Function::kInit, 0);
    return request(keller::Function::kReadChannel, static_cast<std::uint8_t>(keller::Channel::kP1));
  }
  if (init_pending_ && !outstanding_ && !init_since_poll_) {
    init_since_poll_ = true;  // at most one extra F48 per period, whatever the device says
    return request(keller::Function::kInit, 0);
  }
  return {};
}

std::optional<double> KellerPoller::on_answer(const keller::Response& answer) {
  const std::uint8_t function = answered_function(answer);
  const bool matches = outstanding_ && static_cast<std::uint8_t>(*outstanding_) == function;
  if (const auto* e = std::get_if<keller::Exception>(&answer.body)) {
    ++counts_.exceptions;
    if (matches) outstanding_.reset();
    // The device says it lost its initialisation, whatever the request: re-initialise.
    if (e->code == static_cast<std::uint8_t>(keller::ExceptionCode::kNotInitialised)) {
      init_pending_ = true;
    }
    return std::nullopt;
  }
  if (!matches) {
    ++counts_.unexpected;
    return std::nullopt;
  }
  ++counts_.answers;
  outstanding_.reset();
  if (const auto* v = std::get_if<keller::ChannelValue>(&answer.body)) {
    return static_cast<double>(v->value);
  }
  return std::nullopt;
}

std::string KellerPoller::counters_text() const {
  return "requests=" + std::to_string(counts_.requests) +
         " inits=" + std::to_string(counts_.inits) +
         " answers=" + std::to_string(counts_.answers) +
         " exceptions=" + std::to_string(counts_.exceptions) +
         " timeouts=" + std::to_string(counts_.timeouts) +
         " unexpected=" + std::to_string(counts_.unexpected);
}

}  // namespace nav::dut
