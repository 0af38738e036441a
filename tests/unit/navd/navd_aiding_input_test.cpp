// SPDX-License-Identifier: MIT
// navd's extra inputs (dut/navd/aiding_input.hpp): the --input spec parser (valid and
// invalid forms, one-line errors) and the multi-protocol front end fed garbage, corrupted
// frames and valid frames of every protocol (counts exact, never stalls, stays bounded).
#include "aiding_input.hpp"

#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace nav::dut {
namespace {

namespace nq1 = protocols::navquest_nq1;
namespace pd0 = protocols::rdi_pd0;
namespace pd6 = protocols::rdi_pd6;
namespace a50 = protocols::waterlinked_a50;
namespace ebimu = protocols::ebimu;
namespace evo = protocols::evologics;
namespace nmea = protocols::nmea;
using protocols::Bytes;
using protocols::ByteSpan;

const std::vector<int> kBauds = {4800, 9600, 19200, 38400, 57600, 115200, 230400};
constexpr std::size_t kBound = 16 * 1024;

Bytes bytes_of(const std::string& s) { return Bytes(s.begin(), s.end()); }

Bytes cat(std::initializer_list<Bytes> parts) {
  Bytes out;
  for (const auto& p : parts) out.insert(out.end(), p.begin(), p.end());
  return out;
}

// --- --input spec -------------------------------------------------------------------------

TEST(InputSpec, FullForm) {
  const auto s = parse_input_spec("dvl=pd0:/dev/pts/5@115200", kBauds);
  ASSERT_TRUE(s) << s.error().detail;
  EXPECT_EQ(s->name, "dvl");
  EXPECT_EQ(s->protocol, InputProtocol::kPd0);
  EXPECT_EQ(s->path, "/dev/pts/5");
  EXPECT_EQ(s->baud, 115200);
  EXPECT_EQ(to_string(*s), "dvl=pd0:/dev/pts/5@115200");
}

TEST(InputSpec, DefaultBaudPerProtocol) {
  const auto n = parse_input_spec("gyro=nmea:/dev/ttyUSB1", kBauds);
  ASSERT_TRUE(n) << n.error().detail;
  EXPECT_EQ(n->baud, 9600);
  const auto u = parse_input_spec("usbl_1=usbl:/dev/ttyS0", kBauds);
  ASSERT_TRUE(u) << u.error().detail;
  EXPECT_EQ(u->protocol, InputProtocol::kUsbl);
  EXPECT_EQ(u->baud, 115200);
  const auto k = parse_input_spec("depth=keller:/dev/ttyUSB2", kBauds);
  ASSERT_TRUE(k) << k.error().detail;
  EXPECT_EQ(k->protocol, InputProtocol::kKeller);
  EXPECT_EQ(k->baud, 9600);
}

TEST(InputSpec, EveryProtocolName) {
  const std::vector<std::pair<std::string, InputProtocol>> all = {
      {"nq1", InputProtocol::kNq1},   {"pd0", InputProtocol::kPd0},
      {"pd6", InputProtocol::kPd6},   {"a50", InputProtocol::kA50},
      {"ebimu", InputProtocol::kEbimu}, {"usbl", InputProtocol::kUsbl},
      {"nmea", InputProtocol::kNmea},   {"keller", InputProtocol::kKeller}};
  for (const auto& [name, p] : all) {
    const auto s = parse_input_spec("x=" + name + ":/p", kBauds);
    ASSERT_TRUE(s) << name;
    EXPECT_EQ(s->protocol, p);
    EXPECT_EQ(protocol_name(p), name);
  }
}

TEST(InputSpec, PathMayHoldColons) {
  const auto s = parse_input_spec("dvl=a50:/dev/serial/by-id/usb-FTDI:if00@57600", kBauds);
  ASSERT_TRUE(s) << s.error().detail;
  EXPECT_EQ(s->path, "/dev/serial/by-id/usb-FTDI:if00");
  EXPECT_EQ(s->baud, 57600);
}

TEST(InputSpec, InvalidFormsGiveOneLineErrors) {
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"", "no '='"},
      {"dvl", "no '='"},
      {"=pd0:/p", "empty NAME"},
      {"DVL=pd0:/p", "outside [a-z0-9_-]"},
      {"d v=pd0:/p", "outside [a-z0-9_-]"},
      {std::string(33, 'a') + "=pd0:/p", "longer than 32"},
      {"ahrs=pd0:/p", "reserved"},
      {"gps=nmea:/p", "reserved"},
      {"output=nmea:/p", "reserved"},
      {"dvl=pd0", "no ':'"},
      {"dvl=:/p", "unknown PROTOCOL ''"},
      {"dvl=PD0:/p", "unknown PROTOCOL 'PD0'"},
      {"dvl=modbus:/p", "unknown PROTOCOL 'modbus'"},
      {"dvl=pd0:", "empty PATH"},
      {"dvl=pd0:@9600", "empty PATH"},
      {"dvl=pd0:/p@", "BAUD '' is not a number"},
      {"dvl=pd0:/p@fast", "BAUD 'fast' is not a number"},
      {"dvl=pd0:/p@9600x", "BAUD '9600x' is not a number"},
      {"dvl=pd0:/p@-9600", "unsupported BAUD -9600"},
      {"dvl=pd0:/p@1234", "unsupported BAUD 1234"},
  };
  for (const auto& [text, why] : bad) {
    const auto s = parse_input_spec(text, kBauds);
    ASSERT_FALSE(s) << text;
    EXPECT_NE(s.error().detail.find(why), std::string::npos) << s.error().detail;
    EXPECT_NE(s.error().detail.find("'" + text + "'"), std::string::npos) << s.error().detail;
    EXPECT_EQ(s.error().detail.find('\n'), std::string::npos) << s.error().detail;
  }
}

TEST(InputSpec, NamesMustBeUnique) {
  const auto ok = parse_input_specs({"dvl=pd0:/a", "usbl=usbl:/b@9600"}, kBauds);
  ASSERT_TRUE(ok) << ok.error().detail;
  ASSERT_EQ(ok->size(), 2u);
  EXPECT_EQ((*ok)[1].name, "usbl");
  const auto dup = parse_input_specs({"dvl=pd0:/a", "dvl=nq1:/b"}, kBauds);
  ASSERT_FALSE(dup);
  EXPECT_NE(dup.error().detail.find("already used by 'dvl=pd0:/a@115200'"), std::string::npos)
      << dup.error().detail;
  const auto bad = parse_input_specs({"dvl=pd0:/a", "x"}, kBauds);
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().detail.find("'x'"), std::string::npos);
}

// --- one valid frame of every protocol, and a corrupted one -------------------------------

pd0::Ensemble pd0_ensemble() {
  pd0::Ensemble e;
  pd0::FixedLeader f;
  f.num_beams = 4;
  f.coord_transform = 0x17;  // ship coordinates
  e.fixed_leader = f;
  e.variable_leader = pd0::VariableLeader{};
  pd0::BottomTrack b;
  b.velocity_mmps = {-100, -200, 30, 0};
  b.range_cm = {1000, 1000, 1000, 1000};
  e.bottom_track = b;
  return e;
}

nq1::Nq1 nq1_line() {
  nq1::Nq1 m;
  m.velocity_instrument_mmps = {-500.0, 25.0, 0.0};
  m.velocity_instrument_flag = nq1::VelocityFlag::kBottom;
  m.yaw_deg = 12.5;
  return m;
}

struct Case {
  InputProtocol protocol;
  Bytes good;             ///< one valid frame
  Bytes corrupt;          ///< the same frame, corrupted
  std::string type;       ///< the type it counts as
  bool checksum = false;  ///< corrupt counts as checksum (else framing)
};

/// Flips a character inside the frame at `pos` (from the end if negative).
Bytes corrupted(Bytes b, std::ptrdiff_t pos, std::uint8_t to) {
  const std::size_t i = pos >= 0 ? static_cast<std::size_t>(pos)
                                 : b.size() - static_cast<std::size_t>(-pos);
  b[i] = to;
  return b;
}

std::vector<Case> cases() {
  std::vector<Case> out;
  {
    const Bytes g = bytes_of(nq1::encode(nq1_line()));
    // The checksum token ends the line before CR LF: change its last digit.
    const std::uint8_t last = g[g.size() - 3];
    out.push_back({InputProtocol::kNq1, g,
                   corrupted(g, -3, static_cast<std::uint8_t>(last == '9' ? '8' : last + 1)),
                   "res", true});
  }
  {
    const Bytes g = pd0::encode(pd0_ensemble());
    out.push_back({InputProtocol::kPd0, g,
                   corrupted(g, -1, static_cast<std::uint8_t>(g.back() ^ 0x5A)), "ensemble",
                   true});
  }
  {
    pd6::InstrumentVelocity bi;
    bi.xyze_mmps = {100, -50, 3, 1};
    bi.valid = true;
    const Bytes g = bytes_of(pd6::encode(pd6::Line{bi}));
    // No checksum in PD6: a letter in a number field is a framing reject.
    out.push_back({InputProtocol::kPd6, g, corrupted(g, -5, 'x'), "BI", false});
  }
  {
    a50::VelocityReport v;
    v.vx_mps = 0.5;
    v.valid = true;
    v.altitude_m = 3.0;
    const Bytes g = bytes_of(a50::frame(a50::to_packet(v)));
    // "*hh\r\n": change the CRC's last hex digit.
    const std::uint8_t h = g[g.size() - 3];
    out.push_back({InputProtocol::kA50, g,
                   corrupted(g, -3, static_cast<std::uint8_t>(h == '0' ? '1' : '0')), "wrz",
                   true});
  }
  {
    ebimu::Sample s;
    s.euler_deg = std::array<double, 3>{1.5, -2.25, 90.0};
    const Bytes g = bytes_of(ebimu::encode(s));
    out.push_back({InputProtocol::kEbimu, g, corrupted(g, 3, 'z'), "line", false});
  }
  {
    evo::UsblLong l;
    l.remote_address = 3;
    l.x_m = 1.0;
    l.accuracy_m = 0.5;
    const Bytes g = bytes_of(evo::encode(evo::Notification{l, evo::Framing::kDataMode}));
    // "+++AT:<len>:..." with a wrong length: the wrapper no longer fits.
    Bytes c = g;
    c[6] = static_cast<std::uint8_t>(c[6] == '9' ? '8' : c[6] + 1);
    out.push_back({InputProtocol::kUsbl, g, c, "USBLLONG", false});
  }
  {
    nmea::Hdt h;
    h.heading_deg = 123.45;
    const Bytes g = bytes_of(nmea::frame(nmea::to_sentence(h, "HE")));
    const std::uint8_t d = g[g.size() - 3];
    out.push_back({InputProtocol::kNmea, g,
                   corrupted(g, -3, static_cast<std::uint8_t>(d == '0' ? '1' : '0')), "HDT",
                   true});
  }
  return out;
}

const Bytes kGarbage = {0x00, 0x13, 0xFF, 0x80, 'x', '\r', '\n', 0x55};

TEST(AidingInput, EveryProtocolCountsGoodAndRejectsBad) {
  for (const auto& c : cases()) {
    SCOPED_TRACE(std::string(protocol_name(c.protocol)));
    // garbage, good, corrupted, garbage, good: fed whole, and byte by byte.
    const Bytes stream = cat({kGarbage, c.good, c.corrupt, kGarbage, c.good});
    for (std::size_t chunk : {stream.size(), std::size_t{1}, std::size_t{7}}) {
      AidingInput in("x", c.protocol, kBound);
      for (std::size_t off = 0; off < stream.size(); off += chunk) {
        in.feed(ByteSpan(stream).subspan(off, std::min(chunk, stream.size() - off)));
      }
      EXPECT_EQ(in.messages(), 2u) << in.counters_text();
      ASSERT_EQ(in.by_type().count(c.type), 1u) << in.counters_text();
      EXPECT_EQ(in.by_type().at(c.type), 2u);
      const auto r = in.rejects();
      EXPECT_EQ(r.stream.checksum, c.checksum ? 1u : 0u) << in.counters_text();
      if (!c.checksum) {
        EXPECT_GE(r.stream.framing, 1u) << in.counters_text();
      }
      EXPECT_GE(r.stream.sync_bytes, 2 * kGarbage.size() - 2) << in.counters_text();
      EXPECT_EQ(r.stream.overflow_bytes, 0u);
      EXPECT_EQ(r.fields, 0u);
      EXPECT_EQ(in.buffered(), 0u);
      EXPECT_FALSE(std::holds_alternative<std::monostate>(in.last()));
    }
  }
}

TEST(AidingInput, RandomNoiseNeverStallsAndStaysBounded) {
  std::mt19937_64 rng(11);
  std::uniform_int_distribution<int> byte(0, 255);
  for (const auto& c : cases()) {
    SCOPED_TRACE(std::string(protocol_name(c.protocol)));
    AidingInput in("x", c.protocol, kBound);
    for (int round = 0; round < 64; ++round) {
      Bytes noise(1000);
      for (auto& b : noise) b = static_cast<std::uint8_t>(byte(rng));
      in.feed(noise);
      EXPECT_LE(in.buffered(), AidingInput::kPd0BufferBytes);
    }
    // Valid frames after the noise decode within a bounded number of bytes: at most the
    // buffer bound plus one frame (a false start holding on to the bytes behind it).
    const std::uint64_t before = in.messages();
    std::size_t fed = 0;
    while (in.messages() == before && fed < AidingInput::kPd0BufferBytes + 2 * c.good.size()) {
      in.feed(c.good);
      fed += c.good.size();
    }
    EXPECT_GT(in.messages(), before) << in.counters_text();
  }
}

TEST(AidingInput, FalsePd0HeaderDoesNotLoseTheEnsemblesBehindIt) {
  // 0x7F7F claiming 65000 bytes with one plausible offset: the codec waits for all of them,
  // then rejects it by checksum and resynchronises one byte on: nothing behind it is lost.
  const Bytes fake = {0x7F, 0x7F, 0xE8, 0xFD, 0x00, 0x01, 0x08, 0x00};
  const Bytes good = pd0::encode(pd0_ensemble());
  const std::size_t n = 65000 / good.size() + 2;
  AidingInput in("dvl", InputProtocol::kPd0, kBound);
  in.feed(fake);
  for (std::size_t i = 0; i < n; ++i) in.feed(good);
  EXPECT_EQ(in.messages(), n) << in.counters_text();
  EXPECT_EQ(in.rejects().stream.checksum, 1u);
  EXPECT_EQ(in.rejects().stream.overflow_bytes, 0u);
  ASSERT_TRUE(in.last_velocity_mps());
  EXPECT_DOUBLE_EQ((*in.last_velocity_mps())[0], 0.1);  // PD0 bottom track negated
  EXPECT_DOUBLE_EQ((*in.last_velocity_mps())[1], 0.2);
}

/// Toy codec: "<x>" is a frame; "<!" starts a frame that never completes.
protocols::ParseResult<char> toy_parse(ByteSpan b) {
  protocols::ParseResult<char> r;
  if (b.empty()) return r;
  if (b[0] != '<' || (b.size() >= 2 && b[1] != '!' && b.size() >= 3 && b[2] != '>')) {
    r.status = protocols::ParseStatus::kMalformed;
    r.consumed = 1;
    r.error = "not a frame";
    return r;
  }
  if (b.size() < 3 || b[1] == '!') return r;  // need more
  r.status = protocols::ParseStatus::kComplete;
  r.consumed = 3;
  r.message = static_cast<char>(b[1]);
  return r;
}

TEST(StreamDecoder, StartPastTheBoundLosesOneByteNotTheFramesBehindIt) {
  StreamDecoder<char> d(&toy_parse, '<', 32);
  std::vector<char> out;
  std::string text = "<!";
  for (int i = 0; i < 50; ++i) text += "<a>";
  const ByteSpan all(reinterpret_cast<const std::uint8_t*>(text.data()), text.size());
  d.feed(all.first(32), out);  // the false start and 10 frames: held, within the bound
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(d.buffered(), 32u);
  for (std::size_t i = 32; i < all.size(); ++i) d.feed(all.subspan(i, 1), out);
  EXPECT_EQ(out.size(), 50u);  // none lost
  EXPECT_EQ(d.rejects().overflow_bytes, 1u);
  EXPECT_EQ(d.rejects().sync_bytes, 1u);  // the '!'
  EXPECT_LE(d.buffered(), 32u);
}

TEST(AidingInput, WellFramedButUndecodableCountsAsFields) {
  AidingInput gps("gps2", InputProtocol::kNmea, kBound);
  nmea::Sentence bad_gga{"GP", "GGA", {"123519", "48xx.038", "N"}};  // too few, bad field
  gps.feed(bytes_of(nmea::frame(bad_gga)));
  gps.feed(bytes_of(nmea::frame(nmea::Sentence{"GP", "GSV", {"1", "1", "00"}})));
  EXPECT_EQ(gps.rejects().fields, 1u);
  EXPECT_EQ(gps.by_type().at("other"), 1u);
  EXPECT_EQ(gps.messages(), 1u);

  AidingInput dvl("dvl", InputProtocol::kA50, kBound);
  dvl.feed(bytes_of(a50::frame(a50::Packet{'r', 'z', {"0.1", "0.2"}})));  // too few options
  dvl.feed(bytes_of(a50::frame(a50::Packet{'r', 'a', {}})));              // an ack
  EXPECT_EQ(dvl.rejects().fields, 1u);
  EXPECT_EQ(dvl.by_type().at("other"), 1u);
  EXPECT_EQ(dvl.counters_text(),
            "messages=1{other=1} rejects{checksum=0 framing=0 sync_bytes=0 overflow_bytes=0 "
            "fields=1}");
}

TEST(AidingInput, KeepsTheLastDvlVelocity) {
  AidingInput in("dvl", InputProtocol::kNq1, kBound);
  in.feed(bytes_of(nq1::encode(nq1_line())));
  ASSERT_TRUE(in.last_velocity_mps());
  EXPECT_DOUBLE_EQ((*in.last_velocity_mps())[0], 0.5);  // NQ1 negated, mm/s -> m/s
  ASSERT_TRUE(std::holds_alternative<nq1::Nq1>(in.last()));
  EXPECT_DOUBLE_EQ(std::get<nq1::Nq1>(in.last()).yaw_deg, 12.5);
}

}  // namespace
}  // namespace nav::dut
