// SPDX-License-Identifier: MIT
// Measurement faults: the wrong_at composition, the report record, and each generator that
// reads them (GPS jump and speed, DVL bottom-lock loss and velocity, USBL outliers and range),
// decoded with the codecs against truth; outside their windows (and without faults) every
// byte is that of the run without faults, so the faults shift no random draw.
#include "nav/emulators/measurement_faults.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "nav/common/geodesy.hpp"
#include "nav/common/units.hpp"
#include "nav/emulators/device.hpp"
#include "nav/emulators/dvl_emulator.hpp"
#include "nav/emulators/faults.hpp"
#include "nav/emulators/usbl_emulator.hpp"
#include "nav/protocols/evologics_usbl.hpp"
#include "nav/protocols/navquest_nq1.hpp"
#include "nav/protocols/nmea0183.hpp"
#include "nav/protocols/rdi_pd0.hpp"
#include "nav/protocols/rdi_pd6.hpp"
#include "nav/protocols/waterlinked_a50.hpp"

#include "emulator_test_support.hpp"

#include "dvl_decode_support.hpp"

namespace nav::emulators {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;
using units::deg_to_rad;
using MK = MeasurementFault::Kind;
namespace nmea = protocols::nmea;
namespace nq1 = protocols::navquest_nq1;
namespace pd0 = protocols::rdi_pd0;
namespace pd6 = protocols::rdi_pd6;
namespace a50 = protocols::waterlinked_a50;
namespace evo = protocols::evologics;
using protocols::ByteSpan;
using protocols::ParseStatus;

MeasurementFault wrong(Quantity q, double scale, double bias, Duration from, Duration to) {
  MeasurementFault f;
  f.kind = MK::kWrong;
  f.quantity = q;
  f.scale = scale;
  f.bias = bias;
  f.start = from;
  f.end = to;
  return f;
}

MeasurementFault window(MK kind, Duration from, Duration to) {
  MeasurementFault f;
  f.kind = kind;
  f.start = from;
  f.end = to;
  return f;
}

bool inside(Duration t, Duration from, Duration to) { return t >= from && t < to; }

// ---------- pure functions ----------

TEST(MeasurementFaults, Names) {
  EXPECT_STREQ(measurement_fault_name(MK::kWrong), "wrong");
  EXPECT_STREQ(measurement_fault_name(MK::kGpsJump), "gps_jump");
  EXPECT_STREQ(measurement_fault_name(MK::kBottomLockLoss), "bottom_lock_loss");
  EXPECT_STREQ(measurement_fault_name(MK::kUsblOutliers), "usbl_outliers");
  EXPECT_STREQ(quantity_name(Quantity::kAccel), "accel");
  EXPECT_STREQ(quantity_name(Quantity::kGyro), "gyro");
  EXPECT_STREQ(quantity_name(Quantity::kMag), "mag");
  EXPECT_STREQ(quantity_name(Quantity::kAttitude), "attitude");
  EXPECT_STREQ(quantity_name(Quantity::kVelocity), "velocity");
  EXPECT_STREQ(quantity_name(Quantity::kRange), "range");
  EXPECT_STREQ(quantity_name(Quantity::kPressure), "pressure");
}

TEST(MeasurementFaults, WrongAtComposesActiveFaultsOfOneQuantityInListOrder) {
  const double s1 = 0.1, b1 = 1.0, s2 = -0.5, b2 = 2.0;
  std::vector<MeasurementFault> faults{
      wrong(Quantity::kAccel, s1, b1, seconds(1), seconds(3)),
      wrong(Quantity::kAccel, s2, b2, seconds(2), seconds(4)),
      wrong(Quantity::kGyro, 7.0, 7.0, seconds(0), seconds(10)),  // other quantity
      window(MK::kGpsJump, seconds(0), seconds(10)),                 // other kind
  };
  faults[3].scale = 9.0;  // ignored: not a wrong fault
  const double x = 3.0;
  const auto at = [&](double t_s) {
    return wrong_at(faults, Quantity::kAccel, from_seconds(t_s));
  };
  // Before, between and after the windows; ends are exclusive.
  EXPECT_EQ(at(0.5).scale, 0.0);
  EXPECT_EQ(at(0.5).bias, 0.0);
  EXPECT_EQ(at(0.5).apply(x), x);
  EXPECT_DOUBLE_EQ(at(1.0).apply(x), (1 + s1) * x + b1);
  EXPECT_DOUBLE_EQ(at(2.5).apply(x), (1 + s2) * ((1 + s1) * x + b1) + b2);
  EXPECT_DOUBLE_EQ(at(2.5).scale, (1 + s2) * (1 + s1) - 1);
  EXPECT_DOUBLE_EQ(at(2.5).bias, (1 + s2) * b1 + b2);
  EXPECT_DOUBLE_EQ(at(3.0).apply(x), (1 + s2) * x + b2);
  EXPECT_EQ(at(4.0).apply(x), x);
  // The other order composes the other way round.
  std::swap(faults[0], faults[1]);
  EXPECT_DOUBLE_EQ(at(2.5).apply(x), (1 + s1) * ((1 + s2) * x + b2) + b1);
  // Vectors: the scale on every axis, the bias added to each.
  const Vec3 v = at(2.5).apply(Vec3(1.0, -2.0, 0.5));
  for (int i = 0; i < 3; ++i) {
    const double c = Vec3(1.0, -2.0, 0.5)[i];
    EXPECT_DOUBLE_EQ(v[i], (1 + s1) * ((1 + s2) * c + b2) + b1);
  }
  EXPECT_DOUBLE_EQ(wrong_at(faults, Quantity::kGyro, seconds(5)).apply(1.0), 15.0);
  EXPECT_EQ(wrong_at({}, Quantity::kRange, seconds(1)).apply(x), x);
}

TEST(MeasurementFaults, GpsJumpSumsAndBottomLockLossWindows) {
  std::vector<MeasurementFault> faults{window(MK::kGpsJump, seconds(1), seconds(3)),
                                       window(MK::kGpsJump, seconds(2), seconds(4)),
                                       window(MK::kBottomLockLoss, seconds(5), seconds(6))};
  faults[0].jump_n_m = Vec3(1.0, 2.0, 3.0);
  faults[1].jump_n_m = Vec3(10.0, 0.0, -1.0);
  EXPECT_EQ(gps_jump_at(faults, milliseconds(999)), Vec3::Zero());
  EXPECT_EQ(gps_jump_at(faults, seconds(1)), Vec3(1.0, 2.0, 3.0));
  EXPECT_EQ(gps_jump_at(faults, milliseconds(2500)), Vec3(11.0, 2.0, 2.0));
  EXPECT_EQ(gps_jump_at(faults, seconds(3)), Vec3(10.0, 0.0, -1.0));
  EXPECT_EQ(gps_jump_at(faults, seconds(4)), Vec3::Zero());
  EXPECT_FALSE(bottom_lock_lost_at(faults, milliseconds(4999)));
  EXPECT_TRUE(bottom_lock_lost_at(faults, seconds(5)));
  EXPECT_FALSE(bottom_lock_lost_at(faults, seconds(6)));
  EXPECT_FALSE(bottom_lock_lost_at(faults, seconds(2)));  // a jump is no lock loss
}

TEST(MeasurementFaults, RecordCountsMessagesByTimeOfValidity) {
  std::vector<WireMessage> stream;
  for (int k = 0; k < 10; ++k) {
    WireMessage m;
    m.t_valid = milliseconds(500 * k);           // 0, 0.5, ..., 4.5 s
    m.t_send = m.t_valid + milliseconds(2000);  // t_send does not count
    stream.push_back(m);
  }
  const MeasurementFault f = wrong(Quantity::kVelocity, 0.1, 0.0, seconds(1), seconds(3));
  const FaultRecord r = measurement_fault_record(f, stream);
  EXPECT_EQ(r.kind, "wrong");
  EXPECT_DOUBLE_EQ(r.start_s, 1.0);
  EXPECT_DOUBLE_EQ(r.end_s, 3.0);
  EXPECT_EQ(r.messages_affected, 4u);  // 1.0, 1.5, 2.0, 2.5 (3.0 is outside)
  const FaultRecord none =
      measurement_fault_record(window(MK::kUsblOutliers, seconds(10), seconds(20)), stream);
  EXPECT_EQ(none.kind, "usbl_outliers");
  EXPECT_EQ(none.messages_affected, 0u);
  EXPECT_EQ(measurement_fault_record(f, {}).messages_affected, 0u);
}

// ---------- GPS ----------

/// A surface run with a turn (speed 1.5 m/s).
TruthTrajectory surface_truth() { return testing::surface_turn_truth(); }

GpsConfig gps_config(bool noise) {
  GpsConfig cfg;
  if (!noise) cfg.horizontal_std_m = cfg.vertical_std_m = cfg.velocity_std_mps = 0.0;
  cfg.datum_lat_rad = deg_to_rad(36.3833);
  cfg.datum_lon_rad = deg_to_rad(127.36);
  cfg.vtg = true;
  return cfg;
}

/// Every sentence of one epoch.
std::vector<nmea::Sentence> sentences(const WireMessage& m) {
  std::vector<nmea::Sentence> out;
  ByteSpan rest(m.bytes);
  while (!rest.empty()) {
    const auto r = nmea::parse(rest);
    EXPECT_EQ(r.status, ParseStatus::kComplete) << r.error;
    if (r.status != ParseStatus::kComplete || !r.message) break;
    out.push_back(*r.message);
    rest = rest.subspan(r.consumed);
  }
  return out;
}

struct GpsEpoch {
  nmea::Gga gga;
  nmea::Rmc rmc;
  nmea::Vtg vtg;
};

GpsEpoch decode_gps(const WireMessage& m) {
  const auto s = sentences(m);
  GpsEpoch e;
  EXPECT_EQ(s.size(), 3u);
  if (s.size() != 3u) return e;
  const auto gga = nmea::decode_gga(s[0]);
  const auto rmc = nmea::decode_rmc(s[1]);
  const auto vtg = nmea::decode_vtg(s[2]);
  EXPECT_TRUE(gga && rmc && vtg);
  if (gga) e.gga = *gga;
  if (rmc) e.rmc = *rmc;
  if (vtg) e.vtg = *vtg;
  return e;
}

TEST(MeasurementFaultsGps, FixesInsideAJumpWindowAreOffsetByTheJump) {
  GpsConfig cfg = gps_config(false);
  const Duration from = seconds(10), to = seconds(20);
  const Vec3 jump(30.0, -40.0, 5.0);
  MeasurementFault f = window(MK::kGpsJump, from, to);
  f.jump_n_m = jump;
  cfg.measurement_faults = {f};
  const TruthTrajectory truth = surface_truth();
  const geodesy::LocalTangentPlane ltp(
      geodesy::Geodetic{cfg.datum_lat_rad, cfg.datum_lon_rad, cfg.datum_alt_m});
  const auto msgs = generate_gps(cfg, truth, seconds(30), 1);
  ASSERT_EQ(msgs.size(), 30u);
  int jumped = 0;
  for (const WireMessage& m : msgs) {
    const GpsEpoch e = decode_gps(m);
    ASSERT_TRUE(e.gga.lat_deg && e.gga.lon_deg && e.gga.alt_msl_m && e.rmc.lat_deg);
    const Vec3 p_gga = ltp.to_ned(geodesy::Geodetic{deg_to_rad(*e.gga.lat_deg),
                                                    deg_to_rad(*e.gga.lon_deg), *e.gga.alt_msl_m});
    const Vec3 p_rmc = ltp.to_ned(geodesy::Geodetic{deg_to_rad(*e.rmc.lat_deg),
                                                    deg_to_rad(*e.rmc.lon_deg), *e.gga.alt_msl_m});
    const bool in = inside(m.t_valid, from, to);
    jumped += in ? 1 : 0;
    const Vec3 want = truth.at(m.t_valid).p_n + (in ? jump : Vec3::Zero());
    // 1e-5 arcmin (0.02 m) horizontally, 0.1 m altitude resolution.
    EXPECT_NEAR(p_gga.x(), want.x(), 0.03) << to_seconds(m.t_valid);
    EXPECT_NEAR(p_gga.y(), want.y(), 0.03) << to_seconds(m.t_valid);
    EXPECT_NEAR(p_gga.z(), want.z(), 0.06) << to_seconds(m.t_valid);
    EXPECT_NEAR(p_rmc.x(), want.x(), 0.03);
    EXPECT_NEAR(p_rmc.y(), want.y(), 0.03);
    // The jump moves the position only: the speed is the true one.
    EXPECT_NEAR(*e.rmc.sog_kn * units::kKnotToMps, truth.at(m.t_valid).v_n.head<2>().norm(),
                0.001);
  }
  EXPECT_EQ(jumped, 10);
}

TEST(MeasurementFaultsGps, WrongVelocityStepsTheSpeedOverGroundOnly) {
  const Duration from = seconds(5), to = seconds(15);
  const double scale = 0.5, bias = 0.2;
  GpsConfig clean = gps_config(false);
  GpsConfig cfg = clean;
  cfg.measurement_faults = {wrong(Quantity::kVelocity, scale, bias, from, to)};
  const TruthTrajectory truth = surface_truth();
  const auto base = generate_gps(clean, truth, seconds(20), 3);
  const auto msgs = generate_gps(cfg, truth, seconds(20), 3);
  ASSERT_EQ(msgs.size(), base.size());
  for (std::size_t k = 0; k < msgs.size(); ++k) {
    const GpsEpoch e = decode_gps(msgs[k]);
    const GpsEpoch b = decode_gps(base[k]);
    const double speed = truth.at(msgs[k].t_valid).v_n.head<2>().norm();
    const bool in = inside(msgs[k].t_valid, from, to);
    const double want = in ? (1.0 + scale) * speed + bias : speed;
    ASSERT_TRUE(e.rmc.sog_kn && e.vtg.sog_kn && e.vtg.sog_kmh);
    EXPECT_NEAR(*e.rmc.sog_kn * units::kKnotToMps, want, 0.001) << k;
    EXPECT_NEAR(*e.vtg.sog_kn * units::kKnotToMps, want, 0.001) << k;
    EXPECT_NEAR(*e.vtg.sog_kmh / 3.6, want, 0.001) << k;
    EXPECT_EQ(e.rmc.cog_deg, b.rmc.cog_deg) << k;  // the course is not touched
    EXPECT_EQ(e.gga.lat_deg, b.gga.lat_deg) << k;
    if (!in) {
      EXPECT_EQ(msgs[k].bytes, base[k].bytes) << k;
    }
  }
  // A bias that would make the speed negative reports 0.
  cfg.measurement_faults = {wrong(Quantity::kVelocity, 0.0, -10.0, from, to)};
  for (const WireMessage& m : generate_gps(cfg, truth, seconds(20), 3)) {
    if (inside(m.t_valid, from, to)) {
      EXPECT_EQ(decode_gps(m).rmc.sog_kn, 0.0);
    }
  }
}

TEST(MeasurementFaultsGps, NoiseOutsideTheWindowsIsThatOfTheRunWithoutFaults) {
  const GpsConfig clean = gps_config(true);
  GpsConfig cfg = clean;
  MeasurementFault jump = window(MK::kGpsJump, seconds(10), seconds(20));
  jump.jump_n_m = Vec3(100.0, 0.0, 0.0);
  cfg.measurement_faults = {jump, wrong(Quantity::kVelocity, 0.1, 0.3, seconds(30), seconds(40))};
  const TruthTrajectory truth = surface_truth();
  const auto base = generate_gps(clean, truth, seconds(50), 9);
  const auto msgs = generate_gps(cfg, truth, seconds(50), 9);
  ASSERT_EQ(msgs.size(), base.size());
  int differ = 0;
  for (std::size_t k = 0; k < msgs.size(); ++k) {
    const Duration t = msgs[k].t_valid;
    if (inside(t, seconds(10), seconds(20)) || inside(t, seconds(30), seconds(40))) {
      differ += msgs[k].bytes != base[k].bytes ? 1 : 0;
    } else {
      EXPECT_EQ(msgs[k].bytes, base[k].bytes) << k;
    }
  }
  EXPECT_EQ(differ, 20);
  // An empty list is the run without faults, byte for byte.
  GpsConfig empty = clean;
  empty.measurement_faults.clear();
  const auto again = generate_gps(empty, truth, seconds(50), 9);
  ASSERT_EQ(again.size(), base.size());
  for (std::size_t k = 0; k < again.size(); ++k) EXPECT_EQ(again[k].bytes, base[k].bytes);
}

// ---------- DVL ----------

/// Level, constant depth 10 m, 0.5 m/s north-east; roll/pitch motion.
TruthTrajectory dvl_truth() {
  TrajectorySpec spec;
  spec.start_p_n = Vec3(0.0, 0.0, 10.0);
  spec.start_yaw_rad = deg_to_rad(45.0);
  Segment a;
  a.kind = Segment::Kind::kStraight;
  a.length_m = 40.0;
  a.speed_mps = 0.5;
  spec.segments = {a};
  spec.motion = {deg_to_rad(5.0), deg_to_rad(3.0), 7.0};
  auto t = TruthTrajectory::build(spec);
  EXPECT_TRUE(t.has_value());
  return t.value_or(TruthTrajectory{});
}

DvlConfig dvl_config(DvlProtocol protocol, bool noise) {
  DvlConfig cfg;
  cfg.protocol = protocol;
  if (!noise) cfg.velocity_std_mps = 0.0;
  cfg.seabed_depth_m = 30.0;
  return cfg;
}

/// v_b of truth: R_nb^T v_n [m/s].
Vec3 v_b_truth(const TruthSample& s) { return s.q_nb.toRotationMatrix().transpose() * s.v_n; }

pd0::BottomTrack decode_pd0(const WireMessage& m) {
  const auto e = testing::decode_pd0(m);
  EXPECT_TRUE(e.bottom_track.has_value());
  return e.bottom_track.value_or(pd0::BottomTrack{});
}

using testing::decode_a50;
using testing::decode_nq1;
using testing::decode_pd6;
using testing::Pd6Block;

/// True when the ping reports bottom lock (velocity and altitude), as its protocol says it;
/// when not, also checks every flag and invalid value of "no bottom lock".
bool dvl_locked(DvlProtocol protocol, const WireMessage& m) {
  switch (protocol) {
    case DvlProtocol::kRdiPd0: {
      const pd0::BottomTrack bt = decode_pd0(m);
      const bool locked = pd0::vehicle_velocity_mps(bt).has_value();
      if (!locked) {
        EXPECT_EQ(bt.range_cm, (std::array<std::uint32_t, 4>{}));
        for (const auto v : bt.velocity_mmps) EXPECT_EQ(v, pd0::kBadVelocity);
        for (const auto g : bt.percent_good) EXPECT_EQ(g, 0);
      }
      return locked;
    }
    case DvlProtocol::kNavQuestNq1: {
      const nq1::Nq1 q = decode_nq1(m);
      const bool locked = nq1::vehicle_velocity_mps(q).has_value();
      if (!locked) {
        EXPECT_EQ(q.beam_good, (std::array<bool, 4>{}));
        EXPECT_EQ(q.velocity_instrument_flag, nq1::VelocityFlag::kInvalid);
        EXPECT_EQ(q.velocity_earth_flag, nq1::VelocityFlag::kInvalid);
        for (const double alt : q.beam_altitude_m) EXPECT_LT(alt, 0.0);
        EXPECT_LT(q.altitude_m, 0.0);
      }
      return locked;
    }
    case DvlProtocol::kRdiPd6: {
      const Pd6Block b = decode_pd6(m);
      const bool locked = b.bs.valid;
      if (!locked) {
        EXPECT_FALSE(b.bi.valid || b.be.valid);
        EXPECT_EQ(b.bi.xyze_mmps[0], pd6::kBadVelocity);
        EXPECT_EQ(b.bs.longitudinal_mmps, pd6::kBadVelocity);
        EXPECT_EQ(b.be.north_mmps, pd6::kBadVelocity);
        EXPECT_DOUBLE_EQ(b.bd.range_m, 0.0);
      }
      return locked;
    }
    case DvlProtocol::kWaterLinkedA50: {
      const a50::VelocityReport r = decode_a50(m);
      if (!r.valid) {
        EXPECT_DOUBLE_EQ(r.altitude_m, -1.0);
      }
      return r.valid;
    }
  }
  return false;
}

constexpr std::array kDvlProtocols{DvlProtocol::kNavQuestNq1, DvlProtocol::kRdiPd0,
                                   DvlProtocol::kRdiPd6, DvlProtocol::kWaterLinkedA50};

TEST(MeasurementFaultsDvl, NoBottomLockInsideTheWindowForEveryProtocol) {
  const TruthTrajectory truth = dvl_truth();
  const Duration from = seconds(4), to = seconds(8);
  for (const DvlProtocol protocol : kDvlProtocols) {
    SCOPED_TRACE(static_cast<int>(protocol));
    const DvlConfig clean = dvl_config(protocol, true);
    DvlConfig cfg = clean;
    cfg.measurement_faults = {window(MK::kBottomLockLoss, from, to)};
    const auto base = generate_dvl(clean, truth, seconds(12), 5);
    const auto msgs = generate_dvl(cfg, truth, seconds(12), 5);
    ASSERT_EQ(msgs.size(), 60u);
    ASSERT_EQ(base.size(), msgs.size());
    int lost = 0;
    for (std::size_t k = 0; k < msgs.size(); ++k) {
      const bool in = inside(msgs[k].t_valid, from, to);
      lost += in ? 1 : 0;
      EXPECT_EQ(dvl_locked(protocol, msgs[k]), !in) << k;
      // Before the window every byte is the one without the fault; after it, only PD6 :BD
      // remembers the gap (its time since good / distance made good), so compare pings.
      if (msgs[k].t_valid < from) {
        EXPECT_EQ(msgs[k].bytes, base[k].bytes) << k;
      }
    }
    EXPECT_EQ(lost, 20);
  }
  // The same ping without lock as above max altitude: identical bytes, A50 and NQ1 (no state).
  for (const DvlProtocol protocol : {DvlProtocol::kWaterLinkedA50, DvlProtocol::kNavQuestNq1,
                                     DvlProtocol::kRdiPd0}) {
    DvlConfig lost = dvl_config(protocol, false);
    lost.measurement_faults = {window(MK::kBottomLockLoss, seconds(0), seconds(4))};
    DvlConfig high = dvl_config(protocol, false);
    high.max_altitude_m = 5.0;  // altitude ~20 m: above it
    const auto a = generate_dvl(lost, truth, seconds(4), 5);
    const auto b = generate_dvl(high, truth, seconds(4), 5);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t k = 0; k < a.size(); ++k) {
      if (protocol == DvlProtocol::kRdiPd0) {
        // PD0 also carries max_altitude in its bottom-track leader: compare the beams.
        const pd0::BottomTrack x = decode_pd0(a[k]), y = decode_pd0(b[k]);
        EXPECT_EQ(x.velocity_mmps, y.velocity_mmps);
        EXPECT_EQ(x.range_cm, y.range_cm);
        EXPECT_EQ(x.correlation, y.correlation);
        EXPECT_EQ(x.percent_good, y.percent_good);
        EXPECT_EQ(x.rssi, y.rssi);
      } else {
        EXPECT_EQ(a[k].bytes, b[k].bytes) << static_cast<int>(protocol) << " " << k;
      }
    }
  }
}

TEST(MeasurementFaultsDvl, WrongVelocityStepsEveryReportedComponent) {
  const TruthTrajectory truth = dvl_truth();
  const Duration from = seconds(3), to = seconds(6);
  const double scale = 0.2, bias = 0.1;
  const auto want = [&](const WireMessage& m) {
    const Vec3 v = v_b_truth(truth.at(m.t_valid));
    return inside(m.t_valid, from, to) ? Vec3((1 + scale) * v + Vec3::Constant(bias)) : v;
  };
  for (const DvlProtocol protocol : kDvlProtocols) {
    SCOPED_TRACE(static_cast<int>(protocol));
    DvlConfig cfg = dvl_config(protocol, false);
    cfg.measurement_faults = {wrong(Quantity::kVelocity, scale, bias, from, to)};
    const auto msgs = generate_dvl(cfg, truth, seconds(9), 2);
    ASSERT_EQ(msgs.size(), 45u);
    for (const WireMessage& m : msgs) {
      const Vec3 w = want(m);
      const TruthSample s = truth.at(m.t_valid);
      switch (protocol) {
        case DvlProtocol::kWaterLinkedA50: {
          const a50::VelocityReport r = decode_a50(m);
          EXPECT_NEAR(r.vx_mps, w.x(), 1e-3);
          EXPECT_NEAR(r.vy_mps, w.y(), 1e-3);
          EXPECT_NEAR(r.vz_mps, w.z(), 1e-3);
          break;
        }
        case DvlProtocol::kRdiPd0: {
          const auto v = pd0::vehicle_velocity_mps(decode_pd0(m));  // ship: stbd, fwd, up
          ASSERT_TRUE(v.has_value());
          EXPECT_NEAR((*v)[1], w.x(), 1e-3);
          EXPECT_NEAR((*v)[0], w.y(), 1e-3);
          EXPECT_NEAR(-(*v)[2], w.z(), 1e-3);
          break;
        }
        case DvlProtocol::kNavQuestNq1: {
          const nq1::Nq1 q = decode_nq1(m);
          const auto v = nq1::vehicle_velocity_mps(q);
          ASSERT_TRUE(v.has_value());
          for (int i = 0; i < 3; ++i) EXPECT_NEAR((*v)[i], w[i], 1e-4);
          // Earth velocity (of the bottom) consistent with the faulted body velocity.
          const Vec3 earth(q.velocity_earth_mmps[0], q.velocity_earth_mmps[1],
                           q.velocity_earth_mmps[2]);
          const Vec3 v_n = s.q_nb.toRotationMatrix() * w;
          for (int i = 0; i < 3; ++i) EXPECT_NEAR(-earth[i] / 1000.0, v_n[i], 1e-4);
          break;
        }
        case DvlProtocol::kRdiPd6: {
          const Pd6Block b = decode_pd6(m);
          ASSERT_TRUE(b.bs.valid);
          EXPECT_NEAR(b.bs.longitudinal_mmps / 1000.0, w.x(), 1e-3);
          EXPECT_NEAR(b.bs.transverse_mmps / 1000.0, w.y(), 1e-3);
          EXPECT_NEAR(-b.bs.normal_mmps / 1000.0, w.z(), 1e-3);
          EXPECT_EQ(b.bi.xyze_mmps[3], 0);  // error velocity: no noise, the bias cancels
          break;
        }
      }
    }
  }
}

TEST(MeasurementFaultsDvl, NoiseOutsideTheWindowsIsThatOfTheRunWithoutFaults) {
  const TruthTrajectory truth = dvl_truth();
  for (const DvlProtocol protocol : {DvlProtocol::kRdiPd0, DvlProtocol::kWaterLinkedA50}) {
    DvlConfig clean = dvl_config(protocol, true);
    clean.beam_dropout_probability = 0.2;
    DvlConfig cfg = clean;
    cfg.measurement_faults = {wrong(Quantity::kVelocity, 0.05, -0.02, seconds(2), seconds(4)),
                              window(MK::kBottomLockLoss, seconds(6), seconds(7))};
    const auto base = generate_dvl(clean, truth, seconds(10), 17);
    const auto msgs = generate_dvl(cfg, truth, seconds(10), 17);
    ASSERT_EQ(msgs.size(), base.size());
    for (std::size_t k = 0; k < msgs.size(); ++k) {
      const Duration t = msgs[k].t_valid;
      if (!inside(t, seconds(2), seconds(4)) && !inside(t, seconds(6), seconds(7))) {
        EXPECT_EQ(msgs[k].bytes, base[k].bytes) << k;
      }
    }
    DvlConfig empty = clean;
    empty.measurement_faults.clear();
    const auto again = generate_dvl(empty, truth, seconds(10), 17);
    ASSERT_EQ(again.size(), base.size());
    for (std::size_t k = 0; k < again.size(); ++k) EXPECT_EQ(again[k].bytes, base[k].bytes);
  }
}

// ---------- USBL ----------

/// A vehicle running at 2 m/s, 20 m deep, 150-400 m from the transceiver.
TruthTrajectory usbl_truth() {
  TrajectorySpec spec;
  spec.start_p_n = Vec3{120.0, -80.0, 20.0};
  spec.start_yaw_rad = 0.9;
  spec.max_accel_mps2 = 0.5;
  Segment s;
  s.length_m = 400.0;
  s.speed_mps = 2.0;
  spec.segments = {s};
  return *TruthTrajectory::build(spec);
}

UsblConfig usbl_config(bool noise) {
  UsblConfig cfg;
  cfg.transceiver_p_n = Vec3{5.0, 3.0, 1.0};
  cfg.transceiver_yaw_rad = 0.6;
  if (!noise) cfg.range_std_m = cfg.range_std_fraction = cfg.angle_std_rad = 0.0;
  return cfg;
}

evo::UsblLong decode_long(const WireMessage& m) {
  const auto r = evo::parse(ByteSpan(m.bytes));
  EXPECT_EQ(r.status, ParseStatus::kComplete) << r.error;
  if (!r.message || !std::holds_alternative<evo::UsblLong>(r.message->fix)) {
    ADD_FAILURE() << "not a USBLLONG";
    return evo::UsblLong{};
  }
  return std::get<evo::UsblLong>(r.message->fix);
}

Vec3 xyz(const evo::UsblLong& l) { return Vec3(l.x_m, l.y_m, l.z_m); }

TEST(MeasurementFaultsUsbl, FixesInAnOutlierWindowWithProbabilityOneAreFarFromTruth) {
  const TruthTrajectory truth = usbl_truth();
  const UsblConfig clean = usbl_config(true);
  UsblConfig cfg = clean;
  const Duration from = seconds(20), to = seconds(40);
  MeasurementFault f = window(MK::kUsblOutliers, from, to);
  f.probability = 1.0;
  f.outlier_std_m = 50.0;
  cfg.measurement_faults = {f};
  const auto base = generate_usbl(clean, truth, seconds(60), 4);
  const auto msgs = generate_usbl(cfg, truth, seconds(60), 4);
  ASSERT_EQ(msgs.size(), base.size());
  int outliers = 0;
  double sum_sq = 0.0;
  for (std::size_t i = 0; i < msgs.size(); ++i) {
    ASSERT_EQ(msgs[i].t_valid, base[i].t_valid);
    const double d = (xyz(decode_long(msgs[i])) - xyz(decode_long(base[i]))).norm();
    if (inside(msgs[i].t_valid, from, to)) {
      ++outliers;
      sum_sq += d * d;
      EXPECT_GT(d, 1.0) << i;  // |N(0, 50^2 I3)| < 1 m has probability ~1e-6
      // The propagation time follows the displaced position (self-consistent line).
      const evo::UsblLong l = decode_long(msgs[i]);
      EXPECT_NEAR(l.propagation_time_us, xyz(l).norm() / cfg.sound_speed_mps * 1e6, 1.0);
    } else {
      EXPECT_EQ(msgs[i].bytes, base[i].bytes) << i;
    }
  }
  EXPECT_EQ(outliers, 20);
  // Displacement N(0, std^2) per axis: mean square 3 std^2 (20 fixes: within a factor 2).
  EXPECT_GT(sum_sq / outliers, 1.5 * 50.0 * 50.0);
  EXPECT_LT(sum_sq / outliers, 6.0 * 50.0 * 50.0);

  // Probability 0: no outlier, the bytes of the run without faults.
  cfg.measurement_faults[0].probability = 0.0;
  const auto none = generate_usbl(cfg, truth, seconds(60), 4);
  ASSERT_EQ(none.size(), base.size());
  for (std::size_t i = 0; i < none.size(); ++i) EXPECT_EQ(none[i].bytes, base[i].bytes);
}

TEST(MeasurementFaultsUsbl, OutlierFaultsShiftNoDrawOfTheDeviceOrOfDropouts) {
  const TruthTrajectory truth = usbl_truth();
  UsblConfig clean = usbl_config(true);
  clean.outlier_probability = 0.3;  // the config's own outliers
  clean.dropout_probability = 0.2;
  UsblConfig cfg = clean;
  MeasurementFault f = window(MK::kUsblOutliers, seconds(10), seconds(30));
  f.probability = 0.5;
  cfg.measurement_faults = {f};
  const auto base = generate_usbl(clean, truth, seconds(60), 21);
  const auto msgs = generate_usbl(cfg, truth, seconds(60), 21);
  ASSERT_EQ(msgs.size(), base.size());  // same dropouts
  int differ = 0;
  for (std::size_t i = 0; i < msgs.size(); ++i) {
    ASSERT_EQ(msgs[i].t_valid, base[i].t_valid);
    if (inside(msgs[i].t_valid, seconds(10), seconds(30))) {
      differ += msgs[i].bytes != base[i].bytes ? 1 : 0;
    } else {
      EXPECT_EQ(msgs[i].bytes, base[i].bytes) << i;
    }
  }
  EXPECT_GT(differ, 3);
  EXPECT_LT(differ, 17);
  UsblConfig empty = clean;
  empty.measurement_faults.clear();
  const auto again = generate_usbl(empty, truth, seconds(60), 21);
  ASSERT_EQ(again.size(), base.size());
  for (std::size_t i = 0; i < again.size(); ++i) EXPECT_EQ(again[i].bytes, base[i].bytes);
}

TEST(MeasurementFaultsUsbl, WrongRangeStepsTheSlantRangeAndPropagationTime) {
  const TruthTrajectory truth = usbl_truth();
  const UsblConfig clean = usbl_config(false);
  UsblConfig cfg = clean;
  const Duration from = seconds(5), to = seconds(10);
  const double scale = 0.1, bias = 3.0;
  cfg.measurement_faults = {wrong(Quantity::kRange, scale, bias, from, to)};
  const auto base = generate_usbl(clean, truth, seconds(15), 1);
  const auto msgs = generate_usbl(cfg, truth, seconds(15), 1);
  ASSERT_EQ(msgs.size(), base.size());
  int stepped = 0;
  for (std::size_t i = 0; i < msgs.size(); ++i) {
    const evo::UsblLong a = decode_long(msgs[i]);
    const evo::UsblLong b = decode_long(base[i]);
    EXPECT_EQ(msgs[i].t_valid, base[i].t_valid);  // the acoustic timing is not changed
    if (!inside(msgs[i].t_valid, from, to)) {
      EXPECT_EQ(msgs[i].bytes, base[i].bytes) << i;
      continue;
    }
    ++stepped;
    const double r = xyz(b).norm();
    EXPECT_NEAR(xyz(a).norm(), (1 + scale) * r + bias, 2e-4) << i;
    // Same direction: only the range changed.
    EXPECT_NEAR((xyz(a).normalized() - xyz(b).normalized()).norm(), 0.0, 1e-6);
    EXPECT_NEAR(a.propagation_time_us,
                ((1 + scale) * r + bias) / cfg.sound_speed_mps * 1e6, 1.0);
    EXPECT_EQ(a.rssi_db, b.rssi_db);
    EXPECT_EQ(a.accuracy_m, b.accuracy_m);
  }
  EXPECT_EQ(stepped, 5);
}

}  // namespace
}  // namespace nav::emulators
