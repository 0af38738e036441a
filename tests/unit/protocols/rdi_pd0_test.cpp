// SPDX-License-Identifier: MIT
// Teledyne RDI PD0 codec: the real WorkHorse ensemble of protocols.md 3b (checksum 0x6E4F,
// decoded values as the doc states them), re-encoding against its bytes, round trips of an
// emulator-style ensemble, malformed input, unknown data types and random bytes.
#include "nav/protocols/rdi_pd0.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>
#include <vector>

#include "dvl_test_support.hpp"
#include "rdi_pd0_sample.hpp"

namespace nav::protocols::rdi_pd0 {
namespace {

using test_data::kSampleRawData1;
using test_support::drain;

std::uint16_t u16_at(ByteSpan b, std::size_t i) {
  return static_cast<std::uint16_t>(b[i] | b[i + 1] << 8);
}

/// The data types of a raw ensemble in offset-table order, each up to the next higher offset
/// or N; read straight from the bytes, independently of the codec.
std::vector<ByteSpan> raw_sections(ByteSpan ens) {
  const std::size_t n = u16_at(ens, 2);
  std::vector<std::size_t> offsets;
  for (std::size_t i = 0; i < ens[5]; ++i) offsets.push_back(u16_at(ens, 6 + 2 * i));
  std::vector<std::size_t> sorted = offsets;
  std::sort(sorted.begin(), sorted.end());
  std::vector<ByteSpan> out;
  for (const std::size_t off : offsets) {
    const auto next = std::upper_bound(sorted.begin(), sorted.end(), off);
    out.push_back(ens.subspan(off, (next == sorted.end() ? n : *next) - off));
  }
  return out;
}

/// An ensemble as an emulator would send it: fixed + variable leader + bottom track.
Ensemble emulator_ensemble() {
  Ensemble e;
  FixedLeader f;
  f.firmware_version = 51;
  f.firmware_revision = 3;
  f.system_config = 0x4A4B;  // 600 kHz, convex, 30 deg, down-looking
  f.num_beams = 4;
  f.num_cells = 0;
  f.pings_per_ensemble = 1;
  f.coord_transform = 0x17;  // ship coordinates, tilts, 3-beam, bin mapping
  f.heading_alignment_cdeg = -4500;
  f.sensors_available = 0x1D;
  f.serial_number = 0xA1B2C3D4;
  f.beam_angle_deg = 30;
  e.fixed_leader = f;
  VariableLeader v;
  v.ensemble_number = 0x012345;  // needs the MSB byte
  v.rtc = {2024, 2, 29, 23, 59, 58, 99};
  v.speed_of_sound_mps = 1498;
  v.transducer_depth_dm = 123;
  v.heading_cdeg = 35999;
  v.pitch_cdeg = -1234;
  v.roll_cdeg = 567;
  v.salinity_ppt = 35;
  v.temperature_cdegc = -150;
  v.error_status_word = 0x88008180;
  v.pressure_dapa = 123456;
  v.pressure_variance_dapa = 7;
  e.variable_leader = v;
  BottomTrack b;
  b.pings_per_ensemble = 1;
  b.corr_mag_min = 220;
  b.mode = 5;
  b.error_velocity_max_mmps = 1000;
  b.range_cm = {1423, 0, 0x012345, 65535};  // beam 2 bad; beam 3 needs its MSB byte
  b.velocity_mmps = {-58, -137, 12, kBadVelocity};
  b.correlation = {255, 254, 253, 252};
  b.eval_amplitude = {73, 69, 70, 67};
  b.percent_good = {100, 0, 100, 100};
  b.ref_layer_velocity_mmps = {kBadVelocity, kBadVelocity, kBadVelocity, kBadVelocity};
  b.max_tracking_depth_dm = 1250;
  b.rssi = {101, 98, 97, 93};
  e.bottom_track = b;
  return e;
}

TEST(RdiPd0, WorkedExampleFramingAndChecksum) {
  ASSERT_EQ(kSampleRawData1.size(), 754u);
  EXPECT_EQ(u16_at(kSampleRawData1, 2), 752);
  EXPECT_EQ(checksum(ByteSpan(kSampleRawData1).first(752)), 0x6E4F);
  EXPECT_EQ(u16_at(kSampleRawData1, 752), 0x6E4F);
}

TEST(RdiPd0, WorkedExampleDecodesAsTheDocStates) {
  const auto r = parse(kSampleRawData1);
  ASSERT_EQ(r.status, ParseStatus::kComplete) << r.error;
  EXPECT_EQ(r.consumed, 754u);
  const Ensemble& e = *r.message;
  EXPECT_EQ(e.data_type_ids,
            (std::vector<std::uint16_t>{0x0000, 0x0080, 0x0100, 0x0200, 0x0300, 0x0400}));
  EXPECT_FALSE(e.bottom_track.has_value());

  ASSERT_TRUE(e.fixed_leader.has_value());
  const FixedLeader& f = *e.fixed_leader;
  EXPECT_EQ(f.length, 59);
  EXPECT_EQ(f.firmware_version, 50);
  EXPECT_EQ(f.firmware_revision, 40);
  EXPECT_EQ(f.system_config, 0x41C9);
  EXPECT_EQ(f.num_beams, 4);
  EXPECT_EQ(f.num_cells, 30);
  EXPECT_EQ(f.pings_per_ensemble, 10);
  EXPECT_EQ(f.cell_length_cm, 800);
  EXPECT_EQ(f.coord_transform, 0x1F);
  EXPECT_EQ(coordinates(f), Coordinates::kEarth);
  EXPECT_EQ(f.bin1_distance_cm, 881);
  EXPECT_EQ(f.beam_angle_deg, 20);
  EXPECT_EQ(beam_angle_deg(f), 20);  // byte 58; system-config bits 8-9 say 20 deg too
  FixedLeader short_f = f;
  short_f.length = 58;
  EXPECT_EQ(beam_angle_deg(short_f), 20);
  EXPECT_TRUE(looks_up(f));  // a bottom-mounted monitor: system-config bit 7

  ASSERT_TRUE(e.variable_leader.has_value());
  const VariableLeader& v = *e.variable_leader;
  EXPECT_EQ(v.length, 65);
  EXPECT_EQ(v.ensemble_number, 1u);
  EXPECT_EQ(v.rtc.year, 2013);
  EXPECT_EQ(v.rtc.month, 5);
  EXPECT_EQ(v.rtc.day, 22);
  EXPECT_EQ(v.rtc.hour, 18);
  EXPECT_EQ(v.rtc.minute, 12);
  EXPECT_EQ(v.rtc.second, 53);
  EXPECT_EQ(v.rtc.hundredths, 92);
  EXPECT_DOUBLE_EQ(unix_seconds(v.rtc), 1369246373.92);  // 2013-05-22T18:12:53.92Z
  EXPECT_EQ(v.speed_of_sound_mps, 1536);
  EXPECT_EQ(v.heading_cdeg, 5287);       // 52.87 deg
  EXPECT_EQ(v.temperature_cdegc, 2340);  // 23.40 degC
  EXPECT_EQ(v.transducer_depth_dm, 9);
  EXPECT_EQ(v.pitch_cdeg, -4411);
  EXPECT_EQ(v.roll_cdeg, -4461);
  EXPECT_EQ(v.salinity_ppt, 40);
  EXPECT_EQ(v.error_status_word, 0x88008180u);
  EXPECT_EQ(v.pressure_dapa, 552u);
  EXPECT_EQ(v.pressure_variance_dapa, 1692u);
  ASSERT_TRUE(pressure_pa(v).has_value());
  EXPECT_DOUBLE_EQ(*pressure_pa(v), 5520.0);

  // 30 cells x 4 beams, no valid velocity anywhere.
  ASSERT_TRUE(e.velocity.has_value());
  ASSERT_EQ(e.velocity->values.size(), 120u);
  for (const std::int16_t x : e.velocity->values) EXPECT_FALSE(to_mps(x).has_value());
  ASSERT_TRUE(e.correlation && e.echo_intensity && e.percent_good);
  EXPECT_EQ(e.correlation->values[0], 0x2E);
  EXPECT_EQ(e.echo_intensity->values[0], 0x16);
  for (std::size_t c = 0; c < 30; ++c) EXPECT_EQ(e.percent_good->values[c * 4 + 2], 100) << c;
}

TEST(RdiPd0, ReencodingTheWorkedExampleReproducesEveryDataType) {
  const auto r = parse(kSampleRawData1);
  ASSERT_EQ(r.status, ParseStatus::kComplete);
  const Bytes again = encode(*r.message);
  // Same data types, same offsets; we write no reserved bytes before the checksum.
  EXPECT_EQ(again.size(), 752u);
  const std::vector<ByteSpan> want = raw_sections(kSampleRawData1);
  const std::vector<ByteSpan> got = raw_sections(again);
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t i = 0; i < got.size(); ++i) {
    ASSERT_LE(got[i].size(), want[i].size());
    EXPECT_TRUE(std::equal(got[i].begin(), got[i].end(), want[i].begin())) << "data type " << i;
  }
  EXPECT_EQ(want.back().size() - got.back().size(), 2u);  // the two reserved bytes
}

TEST(RdiPd0, EmulatorEnsembleRoundTrips) {
  const Ensemble e = emulator_ensemble();
  const Bytes b = encode(e);
  ASSERT_EQ(b.size(), 6 + 3 * 2 + 59 + 65 + 81 + 2u);
  EXPECT_EQ(checksum(ByteSpan(b).first(b.size() - 2)), u16_at(b, b.size() - 2));
  const auto r = parse(b);
  ASSERT_EQ(r.status, ParseStatus::kComplete) << r.error;
  EXPECT_EQ(r.consumed, b.size());
  EXPECT_EQ(encode(*r.message), b);
  const Ensemble& d = *r.message;
  EXPECT_EQ(d.data_type_ids, (std::vector<std::uint16_t>{0x0000, 0x0080, 0x0600}));
  EXPECT_EQ(d.fixed_leader->serial_number, 0xA1B2C3D4u);
  EXPECT_EQ(d.fixed_leader->heading_alignment_cdeg, -4500);
  EXPECT_EQ(coordinates(*d.fixed_leader), Coordinates::kShip);
  EXPECT_EQ(d.variable_leader->ensemble_number, 0x012345u);
  EXPECT_EQ(d.variable_leader->rtc.year, 2024);
  EXPECT_EQ(d.variable_leader->rtc.day, 29);
  EXPECT_EQ(d.variable_leader->temperature_cdegc, -150);
  EXPECT_EQ(d.bottom_track->range_cm, e.bottom_track->range_cm);
  EXPECT_EQ(d.bottom_track->velocity_mmps, e.bottom_track->velocity_mmps);
  EXPECT_FALSE(range_m(d.bottom_track->range_cm[1]).has_value());
  EXPECT_DOUBLE_EQ(*range_m(d.bottom_track->range_cm[2]), 745.65);
  // Bottom moves past the instrument in PD0: the vehicle's velocity is the opposite.
  const auto vel = vehicle_velocity_mps(*d.bottom_track);
  ASSERT_TRUE(vel.has_value());
  EXPECT_DOUBLE_EQ((*vel)[0], 0.058);
  EXPECT_DOUBLE_EQ((*vel)[1], 0.137);
  EXPECT_DOUBLE_EQ((*vel)[2], -0.012);
  BottomTrack lost = *d.bottom_track;
  lost.velocity_mmps[1] = kBadVelocity;
  EXPECT_FALSE(vehicle_velocity_mps(lost).has_value());

  // Shorter variable leader (46 bytes, as the Explorer DVL capture): no pressure fields.
  Ensemble s = e;
  s.variable_leader->length = 46;
  const auto rs = parse(encode(s));
  ASSERT_EQ(rs.status, ParseStatus::kComplete) << rs.error;
  EXPECT_EQ(rs.message->variable_leader->length, 46);
  EXPECT_EQ(rs.message->variable_leader->rtc.year, 2024);  // two-digit year, pivot at 80
  EXPECT_FALSE(pressure_pa(*rs.message->variable_leader).has_value());
  EXPECT_EQ(rs.message->variable_leader->error_status_word, 0x88008180u);
}

/// A checksummed ensemble around the given data types (raw bytes each).
Bytes frame_types(const std::vector<Bytes>& types) {
  Bytes out(6 + 2 * types.size(), 0);
  out[0] = out[1] = 0x7F;
  out[5] = static_cast<std::uint8_t>(types.size());
  for (std::size_t i = 0; i < types.size(); ++i) {
    out[6 + 2 * i] = static_cast<std::uint8_t>(out.size());
    out[7 + 2 * i] = static_cast<std::uint8_t>(out.size() >> 8);
    out.insert(out.end(), types[i].begin(), types[i].end());
  }
  out[2] = static_cast<std::uint8_t>(out.size());
  out[3] = static_cast<std::uint8_t>(out.size() >> 8);
  const std::uint16_t sum = checksum(out);
  out.push_back(static_cast<std::uint8_t>(sum));
  out.push_back(static_cast<std::uint8_t>(sum >> 8));
  return out;
}

TEST(RdiPd0, UnknownDataTypesAreSkippedByOffset) {
  const Bytes with_bt = encode(emulator_ensemble());
  const std::vector<ByteSpan> types = raw_sections(with_bt);
  const Bytes nav = {0x00, 0x20, 1, 2, 3, 4, 5, 6};  // 0x2000, as in the Explorer capture
  const Bytes b = frame_types(
      {Bytes(types[0].begin(), types[0].end()), nav, Bytes(types[2].begin(), types[2].end())});
  const auto r = parse(b);
  ASSERT_EQ(r.status, ParseStatus::kComplete) << r.error;
  EXPECT_EQ(r.message->data_type_ids, (std::vector<std::uint16_t>{0x0000, 0x2000, 0x0600}));
  EXPECT_TRUE(r.message->bottom_track.has_value());
  EXPECT_FALSE(r.message->variable_leader.has_value());
}

TEST(RdiPd0, MalformedEnsemblesSayWhy) {
  Bytes bad = kSampleRawData1;
  bad[100] ^= 0x01;
  const auto c = parse(bad);
  EXPECT_EQ(c.status, ParseStatus::kMalformed);
  EXPECT_EQ(c.consumed, 1u);
  EXPECT_EQ(c.error, "checksum 0x6E4F != computed 0x6E50");

  const auto junk = parse(Bytes{0x01, 0x02, 0x7F, 0x7F});
  EXPECT_EQ(junk.consumed, 2u);
  EXPECT_EQ(junk.error, "2 byte(s) before 0x7F");
  EXPECT_EQ(parse(Bytes{0x7F, 0x00}).error, "0x7F not followed by 0x7F");
  EXPECT_EQ(parse(Bytes{0x7F, 0x7F, 0x07, 0x00, 0x00, 0x01}).error,
            "byte count 7 cannot hold 1 data type(s)");
  EXPECT_EQ(parse(Bytes{0x7F, 0x7F, 0x20, 0x00, 0x00, 0x01, 0x1F, 0x00}).error,
            "data type offset 31 outside the ensemble of 32 bytes");

  // Checksummed, but a known data type too short to decode: skip the whole ensemble.
  const Bytes short_bt = frame_types({Bytes{0x00, 0x06, 1, 2, 3, 4, 5, 6, 7, 8}});
  const auto s = parse(short_bt);
  EXPECT_EQ(s.status, ParseStatus::kMalformed);
  EXPECT_EQ(s.consumed, short_bt.size());
  EXPECT_EQ(s.error, "bottom track at offset 8 has 10 bytes");
  const auto orphan = parse(frame_types({Bytes{0x00, 0x01, 0, 0x80}}));
  EXPECT_EQ(orphan.error, "profile data type 0x0100 without fixed leader");
}

TEST(RdiPd0, EveryPrefixNeedsMore) {
  for (std::size_t n = 0; n < kSampleRawData1.size(); ++n) {
    const auto r = parse(ByteSpan(kSampleRawData1).first(n));
    EXPECT_EQ(r.status, ParseStatus::kNeedMore) << n;
  }
}

TEST(RdiPd0, StreamResynchronisesAfterNoiseAndACorruptEnsemble) {
  const Bytes good = encode(emulator_ensemble());
  const Bytes corrupt = [&good] {
    Bytes c = good;
    c[40] ^= 0xFF;
    return c;
  }();
  Bytes stream = {0x7F, 0x12, 0x7F};
  for (const Bytes* part : {&good, &corrupt, &kSampleRawData1, &good}) {
    stream.insert(stream.end(), part->begin(), part->end());
  }
  const auto d = drain<Ensemble>(stream, parse);
  const std::size_t g = good.size();
  EXPECT_EQ(d.offsets, (std::vector<std::size_t>{3, 3 + 2 * g, 3 + 2 * g + 754}));
  EXPECT_EQ(d.leftover, 0u);
  const auto at = std::find(d.bad_offsets.begin(), d.bad_offsets.end(), 3 + g);
  ASSERT_NE(at, d.bad_offsets.end());
  EXPECT_EQ(d.errors[static_cast<std::size_t>(at - d.bad_offsets.begin())].rfind("checksum", 0),
            0u);
}

TEST(RdiPd0, RandomBytesNeverStallAndSplicedEnsemblesAreFound) {
  // Noise rich in 0x7F with an ensemble spliced in, then 64 KiB of zeros so that every false
  // header's claimed length arrives (as it would on a live link) and fails its checksum.
  std::mt19937_64 rng(7);
  const Bytes good = encode(emulator_ensemble());
  for (int round = 0; round < 300; ++round) {
    Bytes buf(rng() % 400);
    for (auto& b : buf) b = rng() % 4 == 0 ? 0x7F : static_cast<std::uint8_t>(rng());
    const std::size_t at = rng() % (buf.size() + 1);
    buf.insert(buf.begin() + static_cast<std::ptrdiff_t>(at), good.begin(), good.end());
    buf.resize(buf.size() + 0x10000, 0x00);
    const auto d = drain<Ensemble>(buf, parse);
    bool found = false;
    for (const std::size_t off : d.offsets) found |= off == at;
    EXPECT_TRUE(found) << "round " << round;
    EXPECT_EQ(d.leftover, 0u);
  }
}

}  // namespace
}  // namespace nav::protocols::rdi_pd0
