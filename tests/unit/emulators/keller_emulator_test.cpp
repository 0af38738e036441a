// SPDX-License-Identifier: MIT
// Keller RS-485 emulator: answers to the master's requests against the worked examples of
// protocols.md 6a (byte strings transcribed there, not produced by our encoder), the bus
// rules (init, addresses, resynchronisation) and the stream faults on answers.
#include "nav/emulators/keller_emulator.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <variant>
#include <vector>

#include "nav/common/ensure.hpp"

namespace nav::emulators {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;
namespace kb = protocols::keller;
using protocols::Bytes;
using protocols::ByteSpan;

constexpr double kRho = 1025.0;    ///< [kg/m^3]
constexpr double kG = 9.80665;     ///< [m/s^2]
constexpr std::uint8_t kAddress = 1;

// protocols.md 6a, worked examples.
const Bytes kInitTransparent{0xFA, 0x30, 0x04, 0x43};       ///< F48 to address 250
const Bytes kReadP1{0x01, 0x49, 0x01, 0x50, 0xD6};          ///< F73 P1 to address 1
const Bytes kP1At10mGauge{0x01, 0x49, 0x3F, 0x80, 0xA9, 0xCB, 0x00, 0x4C, 0xBF};  ///< 1.005182 bar

/// A vehicle at rest at depth_m.
TruthTrajectory at_depth(double depth_m) {
  TrajectorySpec spec;
  spec.start_p_n = Vec3{0.0, 0.0, depth_m};
  return *TruthTrajectory::build(spec);
}

/// Seawater gauge sensor, no noise.
KellerConfig gauge_config() {
  KellerConfig c;
  c.address = kAddress;
  c.density_kgpm3 = kRho;
  c.gravity_mps2 = kG;
  c.gauge = true;
  return c;
}

Bytes request(std::uint8_t address, kb::Function f, std::uint8_t data = 0) {
  return kb::encode(kb::Request{address, f, data});
}
Bytes init_request() { return request(kAddress, kb::Function::kInit); }
Bytes p1_request() { return request(kAddress, kb::Function::kReadChannel, 1); }
Bytes tob1_request() { return request(kAddress, kb::Function::kReadChannel, 4); }
Bytes serial_request() { return request(kAddress, kb::Function::kSerialNumber); }

std::vector<WireMessage> feed(KellerEmulator& e, const Bytes& b, Duration t) {
  return e.on_bytes(ByteSpan(b), t);
}

/// The answer decoded by the master-side parser; fails the test unless it is one whole frame.
kb::Response decode(const WireMessage& m) {
  const auto r = kb::parse_response(ByteSpan(m.bytes));
  EXPECT_EQ(r.status, protocols::ParseStatus::kComplete) << r.error;
  EXPECT_EQ(r.consumed, m.bytes.size());
  return r.message ? *r.message : kb::Response{};
}

float channel_value(const WireMessage& m) {
  const kb::Response r = decode(m);
  EXPECT_TRUE(std::holds_alternative<kb::ChannelValue>(r.body));
  if (!std::holds_alternative<kb::ChannelValue>(r.body)) return NAN;
  EXPECT_EQ(std::get<kb::ChannelValue>(r.body).status, 0);
  return std::get<kb::ChannelValue>(r.body).value;
}

void expect_exception(const WireMessage& m, kb::Function f, kb::ExceptionCode code) {
  const kb::Response r = decode(m);
  ASSERT_TRUE(std::holds_alternative<kb::Exception>(r.body));
  EXPECT_EQ(std::get<kb::Exception>(r.body).function, static_cast<std::uint8_t>(f));
  EXPECT_EQ(std::get<kb::Exception>(r.body).code, static_cast<std::uint8_t>(code));
}

TEST(KellerEmulator, WorkedExampleP1At10mOfSeawaterGauge) {
  // GIVEN a gauge sensor at 10.00 m of seawater (rho 1025, g 9.80665)
  const TruthTrajectory truth = at_depth(10.0);
  KellerEmulator e(gauge_config(), truth, {}, 1, 2);
  // WHEN the master initialises it through the transparent address and reads P1
  ASSERT_EQ(feed(e, kInitTransparent, seconds(1)).size(), 1u);
  const auto out = feed(e, kReadP1, seconds(2));
  // THEN the answer is the byte string of protocols.md 6a (1.005182 bar, status 0)
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].bytes, kP1At10mGauge);
  EXPECT_NEAR(channel_value(out[0]), 1.005182, 1e-6);
  EXPECT_NEAR(e.pressure_bar(10.0), 1.005181625, 1e-12);
  EXPECT_FALSE(out[0].trigger_tag.has_value());
  EXPECT_EQ(e.counters().requests, 2u);
  EXPECT_EQ(e.counters().answers, 2u);
  EXPECT_EQ(e.counters().exceptions, 0u);
}

TEST(KellerEmulator, PressureBarIsAbsoluteOrGauge) {
  const TruthTrajectory truth = at_depth(0.0);
  KellerConfig c = gauge_config();
  c.gauge = false;
  c.atmosphere_pa = 101325.0;
  KellerEmulator absolute(c, truth, {}, 1, 2);
  EXPECT_DOUBLE_EQ(absolute.pressure_bar(0.0), 1.01325);
  EXPECT_NEAR(absolute.pressure_bar(10.0), 1.01325 + 1.005181625, 1e-12);
  KellerEmulator gauge(gauge_config(), truth, {}, 1, 2);
  EXPECT_DOUBLE_EQ(gauge.pressure_bar(0.0), 0.0);
  // DUNE's conversion depth = P1 * 1e5 / (g rho) recovers the depth from a gauge sensor.
  EXPECT_NEAR(gauge.pressure_bar(37.5) * 1e5 / (kG * kRho), 37.5, 1e-12);
}

TEST(KellerEmulator, NotInitialisedUntilF48) {
  const TruthTrajectory truth = at_depth(10.0);
  KellerEmulator e(gauge_config(), truth, {}, 1, 2);
  EXPECT_FALSE(e.initialised());
  // Before F48 every other function gets exception 32.
  auto out = feed(e, p1_request(), seconds(1));
  ASSERT_EQ(out.size(), 1u);
  expect_exception(out[0], kb::Function::kReadChannel, kb::ExceptionCode::kNotInitialised);
  EXPECT_EQ(out[0].bytes[1], 0xC9);  // 0x49 | 0x80
  EXPECT_EQ(out[0].bytes[2], 32);
  out = feed(e, serial_request(), seconds(1));
  ASSERT_EQ(out.size(), 1u);
  expect_exception(out[0], kb::Function::kSerialNumber, kb::ExceptionCode::kNotInitialised);
  out = feed(e, request(kAddress, kb::Function::kZeroChannel, 0), seconds(1));
  ASSERT_EQ(out.size(), 1u);
  expect_exception(out[0], kb::Function::kZeroChannel, kb::ExceptionCode::kNotInitialised);
  EXPECT_EQ(e.counters().exceptions, 3u);

  // F48 answers the config's identification, state 1 (just powered up), then 0.
  out = feed(e, init_request(), seconds(2));
  ASSERT_EQ(out.size(), 1u);
  kb::Response r = decode(out[0]);
  ASSERT_TRUE(std::holds_alternative<kb::InitInfo>(r.body));
  const auto& info = std::get<kb::InitInfo>(r.body);
  const kb::InitInfo expected = KellerConfig{}.init;
  EXPECT_EQ(info.device_class, expected.device_class);
  EXPECT_EQ(info.group, expected.group);
  EXPECT_EQ(info.firmware_year, expected.firmware_year);
  EXPECT_EQ(info.firmware_week, expected.firmware_week);
  EXPECT_EQ(info.state, 1);
  EXPECT_TRUE(e.initialised());
  out = feed(e, init_request(), seconds(3));
  ASSERT_EQ(out.size(), 1u);
  r = decode(out[0]);
  ASSERT_TRUE(std::holds_alternative<kb::InitInfo>(r.body));
  EXPECT_EQ(std::get<kb::InitInfo>(r.body).state, 0);

  // Then P1 and the serial number.
  out = feed(e, p1_request(), seconds(4));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].bytes, kP1At10mGauge);
  out = feed(e, serial_request(), seconds(4));
  ASSERT_EQ(out.size(), 1u);
  r = decode(out[0]);
  ASSERT_TRUE(std::holds_alternative<kb::SerialNumber>(r.body));
  EXPECT_EQ(std::get<kb::SerialNumber>(r.body).serial_number, KellerConfig{}.serial_number);
  EXPECT_EQ(e.counters().exceptions, 3u);
  EXPECT_EQ(e.counters().answers, 7u);
}

TEST(KellerEmulator, TransparentAddressIsAnsweredWithTheOwnAddress) {
  const TruthTrajectory truth = at_depth(10.0);
  KellerConfig c = gauge_config();
  c.address = 17;
  KellerEmulator e(c, truth, {}, 1, 2);
  ASSERT_EQ(feed(e, kInitTransparent, seconds(0)).size(), 1u);
  const auto out = feed(e, request(250, kb::Function::kReadChannel, 1), seconds(1));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(decode(out[0]).address, 17);
  EXPECT_NEAR(channel_value(out[0]), 1.005182, 1e-6);
}

TEST(KellerEmulator, OtherAddressesAreIgnoredAndCounted) {
  const TruthTrajectory truth = at_depth(10.0);
  KellerEmulator e(gauge_config(), truth, {}, 1, 2);
  EXPECT_TRUE(feed(e, request(2, kb::Function::kInit), seconds(0)).empty());
  EXPECT_TRUE(feed(e, request(0, kb::Function::kInit), seconds(0)).empty());
  EXPECT_TRUE(feed(e, request(249, kb::Function::kReadChannel, 1), seconds(0)).empty());
  EXPECT_EQ(e.counters().other_address, 3u);
  EXPECT_EQ(e.counters().requests, 0u);
  EXPECT_EQ(e.counters().answers, 0u);
  EXPECT_EQ(e.counters().rejected_bytes, 0u);
  EXPECT_FALSE(e.initialised());  // the F48 to address 2 did not initialise this device
}

TEST(KellerEmulator, BadCrcIsIgnoredAndCountedThenTheBusResynchronises) {
  const TruthTrajectory truth = at_depth(10.0);
  KellerEmulator e(gauge_config(), truth, {}, 1, 2);
  ASSERT_EQ(feed(e, init_request(), seconds(0)).size(), 1u);
  Bytes bad = kReadP1;
  bad.back() ^= 0x01;  // 01 49 01 50 D7
  EXPECT_TRUE(feed(e, bad, seconds(1)).empty());
  // The damaged request is skipped byte by byte (bad CRC, then unknown functions 0x01, 0x50,
  // 0xD7); its last byte 0xD7 (215) may be an address, so it is kept as an incomplete tail.
  EXPECT_EQ(e.counters().rejected_bytes, 4u);
  EXPECT_EQ(e.counters().requests, 1u);
  // Noise in front of a good request: the good one is still answered.
  Bytes noisy{0xFF, 0xFE, 0x01};
  noisy.insert(noisy.end(), kReadP1.begin(), kReadP1.end());
  const auto out = feed(e, noisy, seconds(2));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].bytes, kP1At10mGauge);
  // D7 (unknown function 0xFF), FF FE (addresses > 250), 01 (unknown function 0x01).
  EXPECT_EQ(e.counters().rejected_bytes, 4u + 4u);
}

TEST(KellerEmulator, UnknownFunctionIsNoise) {
  // The codec frames only F48/F69/F73/F95: a request with another function is skipped.
  const TruthTrajectory truth = at_depth(10.0);
  KellerEmulator e(gauge_config(), truth, {}, 1, 2);
  Bytes f66{kAddress, 66};
  const std::uint16_t crc = kb::crc16(ByteSpan(f66));
  f66.push_back(static_cast<std::uint8_t>(crc >> 8));
  f66.push_back(static_cast<std::uint8_t>(crc));
  EXPECT_TRUE(feed(e, f66, seconds(0)).empty());
  EXPECT_EQ(e.counters().requests, 0u);
  EXPECT_GE(e.counters().rejected_bytes, 1u);
}

TEST(KellerEmulator, RequestSplitAcrossTwoCalls) {
  const TruthTrajectory truth = at_depth(10.0);
  KellerEmulator e(gauge_config(), truth, {}, 1, 2);
  ASSERT_EQ(feed(e, init_request(), seconds(0)).size(), 1u);
  const Bytes head(kReadP1.begin(), kReadP1.begin() + 3);
  const Bytes tail(kReadP1.begin() + 3, kReadP1.end());
  EXPECT_TRUE(feed(e, head, milliseconds(1000)).empty());
  const auto out = feed(e, tail, milliseconds(1003));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].bytes, kP1At10mGauge);
  EXPECT_EQ(out[0].t_valid, milliseconds(1003));  // the request's end
  EXPECT_EQ(e.counters().rejected_bytes, 0u);
}

TEST(KellerEmulator, TwoRequestsInOneCallAreAnsweredInOrder) {
  const TruthTrajectory truth = at_depth(10.0);
  KellerConfig c = gauge_config();
  c.temperature_degc = 7.5;
  KellerEmulator e(c, truth, {}, 1, 2);
  ASSERT_EQ(feed(e, init_request(), seconds(0)).size(), 1u);
  Bytes both = p1_request();
  const Bytes t = tob1_request();
  both.insert(both.end(), t.begin(), t.end());
  const auto out = feed(e, both, seconds(1));
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].bytes, kP1At10mGauge);
  EXPECT_EQ(channel_value(out[1]), 7.5f);
}

TEST(KellerEmulator, Tob1ReportsTheTemperatureAndOtherChannelsAreBadParameters) {
  const TruthTrajectory truth = at_depth(10.0);
  KellerConfig c = gauge_config();
  c.temperature_degc = 12.25;
  KellerEmulator e(c, truth, {}, 1, 2);
  ASSERT_EQ(feed(e, init_request(), seconds(0)).size(), 1u);
  auto out = feed(e, tob1_request(), seconds(1));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(channel_value(out[0]), 12.25f);
  for (const std::uint8_t channel : std::vector<std::uint8_t>{0, 2, 3, 5, 6, 200}) {
    out = feed(e, request(kAddress, kb::Function::kReadChannel, channel), seconds(1));
    ASSERT_EQ(out.size(), 1u) << int{channel};
    expect_exception(out[0], kb::Function::kReadChannel, kb::ExceptionCode::kBadParameter);
  }
  EXPECT_EQ(e.counters().exceptions, 6u);
}

TEST(KellerEmulator, ZeroMakesP1RelativeToThePressureAtThatMoment) {
  // GIVEN an absolute sensor, first 10 m deep, then diving 5 m deeper
  TrajectorySpec spec;
  spec.start_p_n = Vec3{0.0, 0.0, 10.0};
  Segment dive;
  dive.kind = Segment::Kind::kDepth;
  dive.depth_change_m = 5.0;
  dive.depth_rate_mps = 1.0;
  spec.segments = {dive};
  const TruthTrajectory truth = *TruthTrajectory::build(spec);
  KellerConfig c = gauge_config();
  c.gauge = false;
  KellerEmulator e(c, truth, {}, 1, 2);
  ASSERT_EQ(feed(e, init_request(), seconds(0)).size(), 1u);
  auto out = feed(e, p1_request(), seconds(0));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(channel_value(out[0]), 1.01325 + 1.005182, 1e-6);
  // WHEN the master sets the zero
  out = feed(e, request(kAddress, kb::Function::kZeroChannel, 0), seconds(0));
  ASSERT_EQ(out.size(), 1u);
  const kb::Response ack = decode(out[0]);
  ASSERT_TRUE(std::holds_alternative<kb::ZeroAck>(ack.body));
  EXPECT_EQ(std::get<kb::ZeroAck>(ack.body).data, 0);
  // THEN P1 reads 0 at the same depth and rho g (5 m) once 5 m deeper
  out = feed(e, p1_request(), seconds(0));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(channel_value(out[0]), 0.0f);
  const double t_end_s = to_seconds(truth.path_duration()) + 1.0;
  ASSERT_NEAR(truth.at(from_seconds(t_end_s)).p_n.z(), 15.0, 1e-9);
  out = feed(e, p1_request(), from_seconds(t_end_s));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(channel_value(out[0]), kRho * kG * 5.0 / 1e5, 1e-6);
  // Other F95 data: bad parameter, the zero is kept.
  out = feed(e, request(kAddress, kb::Function::kZeroChannel, 1), from_seconds(t_end_s));
  ASSERT_EQ(out.size(), 1u);
  expect_exception(out[0], kb::Function::kZeroChannel, kb::ExceptionCode::kBadParameter);
  out = feed(e, p1_request(), from_seconds(t_end_s));
  EXPECT_NEAR(channel_value(out.at(0)), kRho * kG * 5.0 / 1e5, 1e-6);
}

TEST(KellerEmulator, ResponseTimeSetsTSend) {
  const TruthTrajectory truth = at_depth(10.0);
  KellerConfig c = gauge_config();
  c.response_time = milliseconds(12);
  KellerEmulator e(c, truth, {}, 1, 2);
  const auto out = feed(e, init_request(), milliseconds(500));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].t_valid, milliseconds(500));
  EXPECT_EQ(out[0].t_send, milliseconds(512));
}

TEST(KellerEmulator, BiasAndWhiteNoiseOnPressureAndTemperature) {
  // 4000 samples: the sample mean is within 5 sigma/sqrt(n) of the bias, the sample std
  // within 10 % of the configured one (its standard error is ~1.1 %: a 9-sigma bound).
  const TruthTrajectory truth = at_depth(10.0);
  KellerConfig c = gauge_config();
  c.pressure_bias_pa = 250.0;
  c.pressure_std_pa = 40.0;
  c.temperature_std_degc = 0.2;
  KellerEmulator e(c, truth, {}, 99, 2);
  ASSERT_EQ(feed(e, init_request(), seconds(0)).size(), 1u);
  constexpr int kN = 4000;
  const double p0_pa = kRho * kG * 10.0;
  double sum = 0.0, sum2 = 0.0, tsum = 0.0, tsum2 = 0.0;
  for (int k = 0; k < kN; ++k) {
    const Duration t = milliseconds(10 * k);
    const double err_pa = channel_value(feed(e, p1_request(), t).at(0)) * 1e5 - p0_pa;
    sum += err_pa;
    sum2 += err_pa * err_pa;
    const double err_degc = channel_value(feed(e, tob1_request(), t).at(0)) - 10.0;
    tsum += err_degc;
    tsum2 += err_degc * err_degc;
  }
  const double mean = sum / kN, sd = std::sqrt(sum2 / kN - mean * mean);
  EXPECT_NEAR(mean, 250.0, 5.0 * 40.0 / std::sqrt(kN) + 0.01);  // + float32 rounding
  EXPECT_NEAR(sd, 40.0, 4.0);
  const double tmean = tsum / kN, tsd = std::sqrt(tsum2 / kN - tmean * tmean);
  EXPECT_NEAR(tmean, 0.0, 5.0 * 0.2 / std::sqrt(kN));
  EXPECT_NEAR(tsd, 0.2, 0.02);
}

TEST(KellerEmulator, SameSeedsGiveTheSameBytes) {
  const TruthTrajectory truth = at_depth(10.0);
  KellerConfig c = gauge_config();
  c.pressure_std_pa = 50.0;
  c.temperature_std_degc = 0.1;
  const std::vector<FaultSpec> faults{
      FaultSpec{FaultSpec::Kind::kByteLoss, seconds(2), seconds(3), 0.2, 2.0, {}}};
  const auto run = [&](std::uint64_t seed, std::uint64_t fault_seed) {
    KellerEmulator e(c, truth, faults, seed, fault_seed);
    std::vector<Bytes> out;
    for (int k = 0; k < 40; ++k) {
      const Duration t = milliseconds(100 * k);
      for (const Bytes& q : {init_request(), p1_request(), tob1_request()}) {
        for (const auto& m : feed(e, q, t)) out.push_back(m.bytes);
      }
    }
    return out;
  };
  EXPECT_EQ(run(5, 6), run(5, 6));
  EXPECT_NE(run(5, 6), run(7, 6));  // other noise
  EXPECT_NE(run(5, 6), run(5, 8));  // other byte loss
}

TEST(KellerEmulator, WrongFaultOnPressure) {
  const TruthTrajectory truth = at_depth(10.0);
  KellerConfig c = gauge_config();
  MeasurementFault w;
  w.kind = MeasurementFault::Kind::kWrong;
  w.quantity = Quantity::kPressure;
  w.start = seconds(2);
  w.end = seconds(4);
  w.bias = 1000.0;  // [Pa]
  w.scale = 0.01;
  c.measurement_faults = {w};
  KellerEmulator e(c, truth, {}, 1, 2);
  ASSERT_EQ(feed(e, init_request(), seconds(0)).size(), 1u);
  const double p0_bar = kRho * kG * 10.0 / 1e5;
  EXPECT_NEAR(channel_value(feed(e, p1_request(), seconds(1)).at(0)), p0_bar, 1e-6);
  EXPECT_NEAR(channel_value(feed(e, p1_request(), seconds(3)).at(0)),
              (1.01 * p0_bar * 1e5 + 1000.0) / 1e5, 1e-6);
  EXPECT_NEAR(channel_value(feed(e, p1_request(), seconds(4)).at(0)), p0_bar, 1e-6);
}

// ---- stream faults -------------------------------------------------------------------------

/// Feeds the same requests to a faulted emulator and a clean twin (same seeds): one P1
/// request every 100 ms over [0, 5 s), after an F48 at t = 0.
struct Twin {
  std::vector<WireMessage> faulted, clean;
  std::vector<FaultRecord> records;
};

Twin run_twin(const std::vector<FaultSpec>& faults, const Bytes& in_window_request = {}) {
  const TruthTrajectory truth = at_depth(10.0);
  KellerConfig c = gauge_config();
  c.pressure_std_pa = 30.0;  // answers differ from each other
  KellerEmulator faulted(c, truth, faults, 3, 4);
  KellerEmulator clean(c, truth, {}, 3, 4);
  Twin tw;
  for (int k = 0; k < 50; ++k) {
    const Duration t = milliseconds(100 * k);
    const bool in = !in_window_request.empty() && t >= seconds(2) && t < seconds(3);
    const Bytes q = k == 0 ? init_request() : (in ? in_window_request : p1_request());
    for (auto& m : feed(faulted, q, t)) tw.faulted.push_back(std::move(m));
    for (auto& m : feed(clean, q, t)) tw.clean.push_back(std::move(m));
  }
  tw.records = faulted.fault_records();
  return tw;
}

FaultSpec fault(FaultSpec::Kind k, double probability = 1.0) {
  FaultSpec f;
  f.kind = k;
  f.start = seconds(2);
  f.end = seconds(3);
  f.probability = probability;
  return f;
}

bool in_window(const WireMessage& m) { return m.t_valid >= seconds(2) && m.t_valid < seconds(3); }

/// Answers inside / outside [2 s, 3 s).
std::size_t count_in(const std::vector<WireMessage>& v) {
  std::size_t n = 0;
  for (const auto& m : v) n += in_window(m) ? 1 : 0;
  return n;
}

/// The clean answer with the same request time.
const WireMessage& clean_of(const Twin& tw, const WireMessage& m) {
  for (const auto& c : tw.clean) {
    if (c.t_valid == m.t_valid) return c;
  }
  ADD_FAILURE() << "no clean answer at " << to_seconds(m.t_valid);
  return tw.clean.front();
}

/// Outside the window, the faulted answers equal the clean ones.
void expect_untouched_outside(const Twin& tw) {
  for (const auto& m : tw.faulted) {
    if (in_window(m)) continue;
    EXPECT_EQ(m.bytes, clean_of(tw, m).bytes) << to_seconds(m.t_valid);
    EXPECT_EQ(m.t_send, clean_of(tw, m).t_send);
  }
  EXPECT_EQ(tw.faulted.size() - count_in(tw.faulted), tw.clean.size() - count_in(tw.clean));
}

void expect_record(const Twin& tw, const char* kind, std::size_t affected) {
  ASSERT_EQ(tw.records.size(), 1u);
  EXPECT_EQ(tw.records[0].kind, kind);
  EXPECT_DOUBLE_EQ(tw.records[0].start_s, 2.0);
  EXPECT_DOUBLE_EQ(tw.records[0].end_s, 3.0);
  EXPECT_EQ(tw.records[0].messages_affected, affected);
}

TEST(KellerEmulatorFaults, OffSilencesTheWindow) {
  const Twin tw = run_twin({fault(FaultSpec::Kind::kOff)});
  EXPECT_EQ(count_in(tw.clean), 10u);
  EXPECT_EQ(count_in(tw.faulted), 0u);
  expect_untouched_outside(tw);
  expect_record(tw, "off", 10);
}

TEST(KellerEmulatorFaults, StuckRepeatsTheLastAnswerBeforeTheWindow) {
  // Serial-number requests inside the window get the last P1 answer (t = 1.9 s) instead.
  const Twin tw = run_twin({fault(FaultSpec::Kind::kStuck)}, serial_request());
  const WireMessage* last_before = nullptr;
  for (const auto& m : tw.clean) {
    if (m.t_valid < seconds(2)) last_before = &m;
  }
  ASSERT_NE(last_before, nullptr);
  ASSERT_EQ(count_in(tw.faulted), 10u);
  for (const auto& m : tw.faulted) {
    if (!in_window(m)) continue;
    EXPECT_EQ(m.bytes, last_before->bytes);
    EXPECT_NE(m.bytes, clean_of(tw, m).bytes);  // the clean answer is a serial number
    EXPECT_EQ(m.t_send, clean_of(tw, m).t_send);
  }
  expect_untouched_outside(tw);
  expect_record(tw, "stuck", 10);
}

TEST(KellerEmulatorFaults, StuckWithoutAnEarlierAnswerIsSilent) {
  const TruthTrajectory truth = at_depth(10.0);
  FaultSpec f = fault(FaultSpec::Kind::kStuck);
  f.start = seconds(0);
  KellerEmulator e(gauge_config(), truth, {f}, 1, 2);
  EXPECT_TRUE(feed(e, init_request(), seconds(0)).empty());
  EXPECT_TRUE(feed(e, p1_request(), seconds(1)).empty());
  EXPECT_EQ(e.fault_records().at(0).messages_affected, 2u);
  EXPECT_EQ(e.counters().answers, 2u);  // counted before the stream faults
}

TEST(KellerEmulatorFaults, GarbageKeepsTheLengthAndDestroysTheFrame) {
  const Twin tw = run_twin({fault(FaultSpec::Kind::kGarbage)});
  ASSERT_EQ(count_in(tw.faulted), 10u);
  for (const auto& m : tw.faulted) {
    if (!in_window(m)) continue;
    EXPECT_EQ(m.bytes.size(), clean_of(tw, m).bytes.size());
    EXPECT_NE(m.bytes, clean_of(tw, m).bytes);
  }
  expect_untouched_outside(tw);
  expect_record(tw, "garbage", 10);
}

TEST(KellerEmulatorFaults, SlowAnswersOneRequestInFactor) {
  FaultSpec f = fault(FaultSpec::Kind::kSlow);
  f.factor = 3.0;
  const Twin tw = run_twin({f});
  // Requests at 2.0, 2.1, ..., 2.9 s: the 1st, 4th, 7th and 10th are answered.
  std::vector<Duration> kept;
  for (const auto& m : tw.faulted) {
    if (in_window(m)) kept.push_back(m.t_valid);
  }
  EXPECT_EQ(kept, (std::vector<Duration>{milliseconds(2000), milliseconds(2300),
                                         milliseconds(2600), milliseconds(2900)}));
  expect_untouched_outside(tw);
  expect_record(tw, "slow", 6);
}

TEST(KellerEmulatorFaults, DelayedShiftsTSend) {
  FaultSpec f = fault(FaultSpec::Kind::kDelayed);
  f.delay = milliseconds(250);
  const Twin tw = run_twin({f});
  ASSERT_EQ(count_in(tw.faulted), 10u);
  for (const auto& m : tw.faulted) {
    if (!in_window(m)) continue;
    EXPECT_EQ(m.t_send, m.t_valid + milliseconds(5) + milliseconds(250));
    EXPECT_EQ(m.bytes, clean_of(tw, m).bytes);
  }
  expect_untouched_outside(tw);
  expect_record(tw, "delayed", 10);
}

TEST(KellerEmulatorFaults, IntermittentDropsWithItsProbability) {
  Twin tw = run_twin({fault(FaultSpec::Kind::kIntermittent, 1.0)});
  EXPECT_EQ(count_in(tw.faulted), 0u);
  expect_record(tw, "intermittent", 10);
  tw = run_twin({fault(FaultSpec::Kind::kIntermittent, 0.0)});
  EXPECT_EQ(count_in(tw.faulted), 10u);
  expect_record(tw, "intermittent", 0);
  tw = run_twin({fault(FaultSpec::Kind::kIntermittent, 0.5)});
  const std::size_t dropped = 10 - count_in(tw.faulted);
  EXPECT_EQ(tw.records.at(0).messages_affected, dropped);
  for (const auto& m : tw.faulted) EXPECT_EQ(m.bytes, clean_of(tw, m).bytes);
  expect_untouched_outside(tw);
}

TEST(KellerEmulatorFaults, ChecksumFlipsTheLastCrcByte) {
  const Twin tw = run_twin({fault(FaultSpec::Kind::kChecksum)});
  ASSERT_EQ(count_in(tw.faulted), 10u);
  for (const auto& m : tw.faulted) {
    if (!in_window(m)) continue;
    Bytes expected = clean_of(tw, m).bytes;
    expected.back() ^= 0xFF;
    EXPECT_EQ(m.bytes, expected);
    const auto r = kb::parse_response(ByteSpan(m.bytes));
    EXPECT_EQ(r.status, protocols::ParseStatus::kMalformed);
    EXPECT_NE(r.error.find("checksum"), std::string::npos) << r.error;
  }
  expect_untouched_outside(tw);
  expect_record(tw, "checksum", 10);
}

TEST(KellerEmulatorFaults, TruncatedCutsToAShorterPrefix) {
  const Twin tw = run_twin({fault(FaultSpec::Kind::kTruncated)});
  ASSERT_EQ(count_in(tw.faulted), 10u);
  for (const auto& m : tw.faulted) {
    if (!in_window(m)) continue;
    const Bytes& full = clean_of(tw, m).bytes;
    ASSERT_GE(m.bytes.size(), 1u);
    ASSERT_LT(m.bytes.size(), full.size());
    EXPECT_TRUE(std::equal(m.bytes.begin(), m.bytes.end(), full.begin()));
  }
  expect_untouched_outside(tw);
  expect_record(tw, "truncated", 10);
}

TEST(KellerEmulatorFaults, ByteLossDropsBytes) {
  Twin tw = run_twin({fault(FaultSpec::Kind::kByteLoss, 1.0)});
  EXPECT_EQ(count_in(tw.faulted), 0u);  // every byte lost: no answer
  expect_record(tw, "byte_loss", 10);
  tw = run_twin({fault(FaultSpec::Kind::kByteLoss, 0.3)});
  std::size_t shorter = 0;
  for (const auto& m : tw.faulted) {
    if (!in_window(m)) continue;
    const Bytes& full = clean_of(tw, m).bytes;
    ASSERT_LE(m.bytes.size(), full.size());
    // What is left is a subsequence of the clean answer.
    auto it = full.begin();
    for (const auto b : m.bytes) {
      it = std::find(it, full.end(), b);
      ASSERT_NE(it, full.end());
      ++it;
    }
    shorter += m.bytes.size() < full.size() ? 1 : 0;
  }
  const std::size_t vanished = 10 - count_in(tw.faulted);
  EXPECT_GT(shorter + vanished, 0u);
  EXPECT_EQ(tw.records.at(0).messages_affected, shorter + vanished);
  expect_untouched_outside(tw);
}

TEST(KellerEmulatorFaults, OneRecordPerFaultInOrder) {
  FaultSpec slow = fault(FaultSpec::Kind::kSlow);
  slow.start = seconds(4);
  slow.end = seconds(5);
  const Twin tw = run_twin({fault(FaultSpec::Kind::kOff), slow});
  ASSERT_EQ(tw.records.size(), 2u);
  EXPECT_EQ(tw.records[0].kind, "off");
  EXPECT_EQ(tw.records[0].messages_affected, 10u);
  EXPECT_EQ(tw.records[1].kind, "slow");
  EXPECT_DOUBLE_EQ(tw.records[1].start_s, 4.0);
  EXPECT_DOUBLE_EQ(tw.records[1].end_s, 5.0);
  EXPECT_EQ(tw.records[1].messages_affected, 5u);
}

TEST(KellerEmulator, InvalidConfigIsAContractViolation) {
  struct Violation {};
  const auto previous = set_ensure_handler(
      [](const char*, int, const char*, const std::string&) { throw Violation{}; });
  const TruthTrajectory truth = at_depth(1.0);
  const auto make = [&](auto edit, std::vector<FaultSpec> faults = {}) {
    KellerConfig c = gauge_config();
    edit(c);
    return KellerEmulator(c, truth, std::move(faults), 1, 2);
  };
  EXPECT_THROW(make([](KellerConfig& c) { c.address = 0; }), Violation);
  EXPECT_THROW(make([](KellerConfig& c) { c.address = 251; }), Violation);
  EXPECT_THROW(make([](KellerConfig& c) { c.density_kgpm3 = 0.0; }), Violation);
  EXPECT_THROW(make([](KellerConfig& c) { c.pressure_std_pa = -1.0; }), Violation);
  EXPECT_THROW(make([](KellerConfig& c) { c.response_time = milliseconds(-1); }), Violation);
  EXPECT_THROW(make([](KellerConfig&) {}, {fault(FaultSpec::Kind::kIntermittent, 1.5)}),
               Violation);
  EXPECT_NO_THROW(make([](KellerConfig& c) { c.address = 250; }));
  set_ensure_handler(previous);
}

}  // namespace
}  // namespace nav::emulators
