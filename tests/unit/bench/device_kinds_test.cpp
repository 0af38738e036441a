// SPDX-License-Identifier: MIT
// The device registry: every device type has one kind, named as scenarios name it, with its
// keys, defaults, what it puts on the wire and the faults it takes.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>

#include "devices/device_kind.hpp"
#include "devices/wheel_encoders.hpp"
#include "nav/emulators/ebimu_emulator.hpp"
#include "nav/emulators/nmea2000_emulator.hpp"
#include "nav/protocols/dbc.hpp"
#include "nav/protocols/nmea2000.hpp"
#include "nav/protocols/wheel_encoder.hpp"
#include "source_paths.hpp"

namespace nav::bench::detail {
namespace {

using Link = DeviceKind::Link;
using namespace std::chrono_literals;

// Every `type` docs/scenario.md lists.
constexpr const char* kEveryType[] = {"microstrain-gx3-25", "nmea0183-gps", "dvl",
                                      "ebimu-9dof", "evologics-usbl", "iusbl", "keller-rs485",
                                      "acoustic-modem", "nmea2000", "wheel-encoders",
                                      "beacon-ins"};

bool has_key(const DeviceKind& k, const std::string& key) {
  return std::find(k.keys.begin(), k.keys.end(), key) != k.keys.end();
}

TEST(DeviceKinds, EveryTypeHasExactlyOneKindFoundByItsName) {
  ASSERT_EQ(device_kinds().size(), std::size(kEveryType));
  std::set<std::string> names;
  for (const char* t : kEveryType) {
    const DeviceKind* found = find_device_kind(t);
    ASSERT_NE(found, nullptr) << t;
    const DeviceKind& k = *found;
    EXPECT_STREQ(k.name, t);
    EXPECT_TRUE(names.insert(k.name).second) << k.name;
    DeviceSpec d;
    d.name = "x";
    d.type = t;
    EXPECT_EQ(&device_kind(d), &k);
    EXPECT_TRUE(has_key(k, "name") && has_key(k, "type")) << k.name;
    EXPECT_NE(k.read, nullptr) << k.name;
  }
  EXPECT_EQ(find_device_kind("no-such-device"), nullptr);
  DeviceSpec stray;
  stray.type = "no-such-device";
  EXPECT_THROW(device_kind(stray), std::logic_error);  // the scenario reader never makes one
}

TEST(DeviceKinds, WhatEachKindPutsOnTheWireMatchesItsLink) {
  for (const auto* k : device_kinds()) {
    // A stream kind generates from its own vehicle, or (observer_stream) from another too.
    EXPECT_EQ(k->stream != nullptr || k->observer_stream != nullptr, k->link == Link::kStream)
        << k->name;
    EXPECT_FALSE(k->stream != nullptr && k->observer_stream != nullptr) << k->name;
    EXPECT_EQ(k->observer_stream != nullptr, k->resolve_observed != nullptr) << k->name;
    EXPECT_EQ(k->observer_stream != nullptr, k->observed_vehicle != nullptr) << k->name;
    EXPECT_EQ(k->frames != nullptr, k->link == Link::kCan) << k->name;
    // A line's keys: a serial kind has port and baud, a CAN kind neither.
    EXPECT_EQ(has_key(*k, "port"), k->link != Link::kCan) << k->name;
    EXPECT_EQ(has_key(*k, "baud"), k->link != Link::kCan) << k->name;
    DeviceSpec d;
    d.type = k->name;
    EXPECT_EQ(d.on_can(), k->link == Link::kCan) << k->name;
    // A kind that takes measurement faults has the `faults` key and a quantity for `wrong`.
    if (k->measurement_faults) {
      EXPECT_TRUE(has_key(*k, "faults")) << k->name;
      EXPECT_FALSE(k->wrong_quantities.empty()) << k->name;
    }
    // Before its kind has read it, a spec has no settings and no measurement faults.
    EXPECT_TRUE(measurement_faults_of(d).empty()) << k->name;
  }
}

TEST(DeviceKinds, DefaultsAsDocumented) {
  // docs/scenario.md, the device table.
  EXPECT_EQ(gx3_kind().baud, 115200);
  EXPECT_EQ(gx3_kind().rate_hz, 100.0);
  EXPECT_EQ(gps_kind().baud, 9600);
  EXPECT_EQ(gps_kind().rate_hz, 1.0);
  EXPECT_EQ(gps_kind().latency, 50ms);
  EXPECT_EQ(dvl_kind().rate_hz, 5.0);
  EXPECT_EQ(ebimu_kind().rate_hz, 100.0);
  EXPECT_EQ(usbl_kind().baud, 19200);
  EXPECT_EQ(iusbl_kind().baud, 19200);
  EXPECT_EQ(iusbl_kind().rate_hz, 0.5);
  EXPECT_EQ(keller_kind().baud, 9600);
  EXPECT_FALSE(has_key(keller_kind(), "rate"));  // polled: the DUT sets the pace
  EXPECT_EQ(keller_kind().link, Link::kPolled);
  EXPECT_EQ(acoustic_modem_kind().link, Link::kChannel);
  EXPECT_EQ(acoustic_modem_kind().keys,
            (std::vector<std::string>{"name", "type", "port", "baud"}));
  EXPECT_EQ(wheel_encoders_kind().latency, 1ms);
  EXPECT_EQ(beacon_ins_kind().baud, 115200);
  EXPECT_EQ(beacon_ins_kind().rate_hz, 50.0);
  // Only the GX3 streams once commanded.
  for (const auto* k : device_kinds()) {
    EXPECT_EQ(k->commanded, k == &gx3_kind()) << k->name;
  }
  EXPECT_EQ(gps_kind().special_faults,
            (std::vector<emulators::MeasurementFault::Kind>{
                emulators::MeasurementFault::Kind::kGpsJump}));
}

TEST(DeviceKinds, TheKindsWhoseMessagesADutCanNameMayTrigger) {
  // docs/dut-contract.md section 4: a rule per kind, serial or CAN as the kind's link.
  const std::set<const DeviceKind*> triggers{&gx3_kind(), &ebimu_kind(), &nmea2000_kind(),
                                             &wheel_encoders_kind(), &beacon_ins_kind()};
  for (const auto* k : device_kinds()) {
    EXPECT_EQ(k->may_trigger(), triggers.count(k) == 1) << k->name;
    if (!k->may_trigger()) continue;
    EXPECT_NE(k->trigger.rule, nullptr) << k->name;
    EXPECT_EQ(k->trigger.of_frame != nullptr, k->link == Link::kCan) << k->name;
    EXPECT_EQ(k->trigger.of_message != nullptr, k->link == Link::kStream) << k->name;
  }
  EXPECT_EQ(gx3_kind().trigger.wraps_after, 0u);
  EXPECT_EQ(beacon_ins_kind().trigger.wraps_after, 0u);
  EXPECT_EQ(ebimu_kind().trigger.wraps_after, 0u);
  EXPECT_EQ(nmea2000_kind().trigger.wraps_after, 253u);   // SID 0..252
  EXPECT_EQ(wheel_encoders_kind().trigger.wraps_after, 16u);  // a 4-bit MsgCounter
}

emulators::WireMessage message_of(const std::string& text) {
  emulators::WireMessage m;
  m.bytes.assign(text.begin(), text.end());
  return m;
}

TEST(DeviceKinds, BeaconInsTriggerTagIsTheFrameTimerAsSent) {
  DeviceSpec d;
  emulators::WireMessage m;
  m.trigger_tag = 200000;
  EXPECT_EQ(beacon_ins_kind().trigger.of_message(d, m, 3), 200000u);
  m.trigger_tag.reset();  // a frame a fault destroyed
  EXPECT_FALSE(beacon_ins_kind().trigger.of_message(d, m, 3).has_value());
}

TEST(DeviceKinds, Gx3TriggerTagIsThePacketTimerAsSent) {
  DeviceSpec d;
  emulators::WireMessage m;
  m.trigger_tag = 62500;
  EXPECT_EQ(gx3_kind().trigger.of_message(d, m, 7), 62500u);  // lines do not matter
  m.trigger_tag.reset();  // a packet a fault destroyed
  EXPECT_FALSE(gx3_kind().trigger.of_message(d, m, 7).has_value());
}

TEST(DeviceKinds, EbimuTriggerTagIsTheLinesOrdinalOnItsPort) {
  DeviceSpec d;
  d.type = "ebimu-9dof";
  d.settings.emplace<emulators::EbimuConfig>();  // Euler angles only (the default output)
  const auto tag = ebimu_kind().trigger.of_message;
  EXPECT_EQ(tag(d, message_of("*1.00,-2.00,30.00\r\n"), 0), 0u);
  EXPECT_EQ(tag(d, message_of("*1.00,-2.00,30.00\r\n"), 41), 41u);
  // Not a whole line of its configuration: no trigger (the DUT rejects it), but its LF still
  // counts on the line (the caller counts every LF byte).
  EXPECT_FALSE(tag(d, message_of("*1.00,-2.00\r\n"), 3).has_value());
  EXPECT_FALSE(tag(d, message_of("*1.00,-2.00,30.0"), 3).has_value());
  EXPECT_FALSE(tag(d, message_of("\x13\n*1.00,-2.00,30.00\r\n"), 3).has_value());
  d.config<emulators::EbimuConfig>().gyro = true;
  EXPECT_EQ(tag(d, message_of("*1.00,-2.00,30.00,0.10,0.20,0.30\r\n"), 5), 5u);
  EXPECT_FALSE(tag(d, message_of("*1.00,-2.00,30.00\r\n"), 5).has_value());
}

TEST(DeviceKinds, Nmea2000TriggerTagIsPgnAndSidOfItsSingleFramesWithASid) {
  namespace n2k = protocols::n2k;
  DeviceSpec d;
  d.type = "nmea2000";
  d.settings.emplace<emulators::Nmea2000Config>().source = 35;
  const auto tag = nmea2000_kind().trigger.of_frame;
  const std::array<std::uint8_t, 8> payload{7, 0xB2, 0x7A, 0xFF, 0x7F, 0xFF, 0x7F, 0xFD};
  const auto frame = [&](std::uint32_t pgn, std::uint8_t source) {
    return n2k::single_frame(n2k::Header{2, pgn, source, n2k::kBroadcast}, payload);
  };
  EXPECT_EQ(tag(d, frame(n2k::kPgnVesselHeading, 35)), 127250u * 256 + 7);
  EXPECT_EQ(tag(d, frame(n2k::kPgnCogSogRapid, 35)), 129026u * 256 + 7);
  EXPECT_FALSE(tag(d, frame(n2k::kPgnVesselHeading, 36)).has_value());  // another device
  EXPECT_FALSE(tag(d, frame(n2k::kPgnPositionRapid, 35)).has_value());  // no SID
  const auto fast = n2k::encode_frames(n2k::Header{3, n2k::kPgnGnssPosition, 35, n2k::kBroadcast},
                                       n2k::Message{n2k::GnssPositionData{}});
  for (const auto& f : fast) EXPECT_FALSE(tag(d, f).has_value());  // a fast packet
}

TEST(DeviceKinds, WheelEncoderTriggerTagIsIdentifierAndCounter) {
  namespace we = protocols::wheel_encoder;
  auto db = protocols::dbc::load(nav::test_paths::source_dir() + "/fixtures/crawler.dbc");
  ASSERT_TRUE(db.has_value()) << db.error().detail;
  auto codec = we::WheelEncoderCodec::from_database(*db);
  ASSERT_TRUE(codec.has_value()) << codec.error().detail;
  DeviceSpec d;
  d.type = "wheel-encoders";
  d.settings.emplace<WheelEncoders>().codec = std::make_shared<const we::WheelEncoderCodec>(*codec);
  const auto tag = wheel_encoders_kind().trigger.of_frame;
  for (const auto wheel : {we::Wheel::kLeft, we::Wheel::kRight}) {
    we::WheelEncoderSample s;
    s.wheel = wheel;
    s.ticks = 1234;
    s.counter = 9;
    const auto df = codec->encode(s);
    ASSERT_TRUE(df.has_value());
    protocols::can::Frame f;
    f.id = df->id;
    f.extended = df->extended;
    f.dlc = static_cast<std::uint8_t>(df->data.size());
    std::copy(df->data.begin(), df->data.end(), f.data.begin());
    EXPECT_EQ(tag(d, f), std::uint64_t{df->id} * 256 + 9);
    f.id = 0x7FF;  // a frame of no wheel
    EXPECT_FALSE(tag(d, f).has_value());
  }
}

}  // namespace
}  // namespace nav::bench::detail
