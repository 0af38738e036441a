// SPDX-License-Identifier: MIT
// Decoders shared by the DVL emulator tests: one WireMessage -> what a DUT would see, each
// checking that the message decodes whole.
#pragma once

#include <gtest/gtest.h>

#include <type_traits>
#include <variant>

#include "nav/emulators/device.hpp"
#include "nav/protocols/navquest_nq1.hpp"
#include "nav/protocols/rdi_pd0.hpp"
#include "nav/protocols/rdi_pd6.hpp"
#include "nav/protocols/waterlinked_a50.hpp"

namespace nav::emulators::testing {

namespace nq1 = protocols::navquest_nq1;
namespace pd0 = protocols::rdi_pd0;
namespace pd6 = protocols::rdi_pd6;
namespace a50 = protocols::waterlinked_a50;
using protocols::ByteSpan;
using protocols::ParseStatus;

inline pd0::Ensemble decode_pd0(const WireMessage& m) {
  const auto r = pd0::parse(m.bytes);
  EXPECT_EQ(r.status, ParseStatus::kComplete) << r.error;
  EXPECT_EQ(r.consumed, m.bytes.size());
  return r.message.value_or(pd0::Ensemble{});
}

inline nq1::Nq1 decode_nq1(const WireMessage& m) {
  const auto r = nq1::parse(m.bytes);
  EXPECT_EQ(r.status, ParseStatus::kComplete) << r.error;
  EXPECT_EQ(r.consumed, m.bytes.size());
  return r.message.value_or(nq1::Nq1{});
}

inline a50::VelocityReport decode_a50(const WireMessage& m) {
  const auto r = a50::parse(m.bytes);
  EXPECT_EQ(r.status, ParseStatus::kComplete) << r.error;
  EXPECT_EQ(r.consumed, m.bytes.size());
  const auto v = a50::decode_velocity(r.message.value_or(a50::Packet{}));
  EXPECT_TRUE(v.has_value());
  return v.value_or(a50::VelocityReport{});
}

struct Pd6Block {
  pd6::Attitude sa;
  pd6::TimeAndScaling ts;
  pd6::InstrumentVelocity bi;
  pd6::ShipVelocity bs;
  pd6::EarthVelocity be;
  pd6::Distance bd;
};

inline Pd6Block decode_pd6(const WireMessage& m) {
  Pd6Block b;
  ByteSpan rest(m.bytes);
  int n = 0;
  while (!rest.empty()) {
    const auto r = pd6::parse(rest);
    EXPECT_EQ(r.status, ParseStatus::kComplete) << r.error;
    if (r.status != ParseStatus::kComplete) break;
    std::visit(
        [&](const auto& line) {
          using T = std::decay_t<decltype(line)>;
          if constexpr (std::is_same_v<T, pd6::Attitude>) b.sa = line;
          if constexpr (std::is_same_v<T, pd6::TimeAndScaling>) b.ts = line;
          if constexpr (std::is_same_v<T, pd6::InstrumentVelocity>) b.bi = line;
          if constexpr (std::is_same_v<T, pd6::ShipVelocity>) b.bs = line;
          if constexpr (std::is_same_v<T, pd6::EarthVelocity>) b.be = line;
          if constexpr (std::is_same_v<T, pd6::Distance>) b.bd = line;
        },
        *r.message);
    ++n;
    rest = rest.subspan(r.consumed);
  }
  EXPECT_EQ(n, 6);
  return b;
}

}  // namespace nav::emulators::testing
