// SPDX-License-Identifier: MIT
// The device registry: every device type has one kind, named as scenarios name it, with its
// keys, defaults, what it puts on the wire and the faults it takes.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <stdexcept>
#include <string>

#include "devices/device_kind.hpp"

namespace nav::bench::detail {
namespace {

using Link = DeviceKind::Link;
using namespace std::chrono_literals;

// Every `type` docs/scenario.md lists.
constexpr const char* kEveryType[] = {"microstrain-gx3-25", "nmea0183-gps", "dvl",
                                      "ebimu-9dof", "evologics-usbl", "keller-rs485",
                                      "acoustic-modem", "nmea2000", "wheel-encoders"};

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
    EXPECT_EQ(k->stream != nullptr, k->link == Link::kStream) << k->name;
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
  EXPECT_EQ(keller_kind().baud, 9600);
  EXPECT_FALSE(has_key(keller_kind(), "rate"));  // polled: the DUT sets the pace
  EXPECT_EQ(keller_kind().link, Link::kPolled);
  EXPECT_EQ(acoustic_modem_kind().link, Link::kChannel);
  EXPECT_EQ(acoustic_modem_kind().keys,
            (std::vector<std::string>{"name", "type", "port", "baud"}));
  EXPECT_EQ(wheel_encoders_kind().latency, 1ms);
  // Only the GX3 streams once commanded and only its packets name a trigger.
  for (const auto* k : device_kinds()) {
    EXPECT_EQ(k->commanded, k == &gx3_kind()) << k->name;
    EXPECT_EQ(k->may_trigger, k == &gx3_kind()) << k->name;
  }
  EXPECT_EQ(gps_kind().special_faults,
            (std::vector<emulators::MeasurementFault::Kind>{
                emulators::MeasurementFault::Kind::kGpsJump}));
}

}  // namespace
}  // namespace nav::bench::detail
