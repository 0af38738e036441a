// SPDX-License-Identifier: MIT
// navd on a live CAN bus (--can vcan0 --dbc fixtures/crawler.dbc), its AHRS and output on
// ptys (navd_pty_harness.hpp). The test is every device on the bus:
//
//   test                                   vcan0                navd (child process)
//   ahrs pty  ── 0xCB 1 ──▶ solution 1 ◀── output pty             (navd is in its loop: the
//                                                                  CAN socket is bound)
//   CanSocket ── N2K singles, a 129029 fast packet from each of two sources (interleaved),
//                wheel encoder frames, garbage (unknown id, short N2K, short wheel, RTR) ─▶
//   cansend   ── one N2K heading and one wheel frame, as an independent sender ──────────▶
//   listener CanSocket: waits until it has every frame (the kernel has delivered them)
//   ahrs pty  ── 0xCB 2 ──▶ solution 2 (navd read the CAN socket in that wake), SIGTERM
//   navd's exit summary: can{iface=vcan0 frames=.. n2k{..} dbc{..} rejects{..}} as sent.
//
// Also: an interface that does not exist (exit 3, one line) and a DBC that disagrees with the
// code (exit 2). ctest runs this binary through scripts/with-vcan (label vcan); run directly
// without vcan0 the vcan cases skip, except under CI (CI=true).
#include <net/if.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "can_test_support.hpp"
#include "nav/protocols/can_frame.hpp"
#include "nav/protocols/dbc.hpp"
#include "nav/protocols/nmea2000.hpp"
#include "nav/protocols/wheel_encoder.hpp"
#include "nav/transport/can_socket.hpp"
#include "navd_pty_harness.hpp"
#include "source_paths.hpp"

namespace nav::testing {
namespace {

namespace n2k = protocols::n2k;
namespace wheel = protocols::wheel_encoder;
using protocols::Bytes;
using transport::CanFrame;
using transport::CanSocket;

constexpr const char* kIface = "vcan0";
constexpr double kLatDeg = 36.3833;

std::string crawler_dbc() { return nav::test_paths::source_dir() + "/fixtures/crawler.dbc"; }

using test_support::program_on_path;
using test_support::receive_frames;
using test_support::to_socket;

CanFrame to_socket(const protocols::dbc::Frame& f) {
  CanFrame out;
  out.id = f.id;
  out.extended = f.extended;
  out.dlc = static_cast<std::uint8_t>(f.data.size());
  std::copy(f.data.begin(), f.data.end(), out.data.begin());
  return out;
}

/// Runs a program to its end (at most 10 s); its wait status, -1 if it could not run.
int run_program(const std::vector<std::string>& argv_strings,
                const std::filesystem::path& stderr_path = "/dev/null") {
  std::vector<char*> argv;
  for (const auto& a : argv_strings) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 2, stderr_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                   0644);
  pid_t pid = -1;
  const int rc = ::posix_spawnp(&pid, argv[0], &fa, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0) return -1;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  int status = 0;
  while (::waitpid(pid, &status, WNOHANG) == 0) {
    if (std::chrono::steady_clock::now() > deadline) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      return -1;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return status;
}

n2k::GnssPositionData gnss(double lat_deg, double lon_deg) {
  n2k::GnssPositionData g;
  g.sid = 7;
  g.date_days = 20000;
  g.time_s = 43200.0;
  g.lat_deg = lat_deg;
  g.lon_deg = lon_deg;
  g.altitude_m = -3.0;
  g.method = 1;
  g.satellites = 8;
  return g;
}

TEST(NavdCanVcan, DecodesAndCountsWhatIsSentOnTheBus) {
  REQUIRE_OR_SKIP(::if_nametoindex(kIface) != 0,
                  "no vcan0 here: run through scripts/with-vcan (ctest -L vcan)");
  REQUIRE_OR_SKIP(program_on_path("cansend"), "cansend (can-utils) not on PATH");
  TestPty ahrs, output;
  ASSERT_TRUE(ahrs.ok() && output.ok()) << "openpty failed (is /dev/pts mounted?)";
  auto sender = CanSocket::open(kIface);
  auto listener = CanSocket::open(kIface);
  ASSERT_TRUE(sender && listener) << (sender ? listener.error().detail : sender.error().detail);

  NavdProcess navd("navd-can", "");
  ASSERT_EQ(navd.spawn({"--ahrs", ahrs.path, "--output", output.path, "--can", kIface, "--dbc",
                        crawler_dbc()}),
            0)
      << navd.exe();
  // The GX3 start command, then one solution: navd has opened everything and is polling.
  const Bytes start = ahrs.read_until([](const Bytes& b) { return b.size() >= 4; }, 5000);
  ASSERT_EQ(start.size(), 4u) << navd.stderr_text();
  SolutionReader reader(output);
  ASSERT_TRUE(ahrs.write(ahrs_packet(62500, kLatDeg)));
  ASSERT_TRUE(reader.await(62500)) << navd.stderr_text();

  std::vector<CanFrame> frames;
  auto add_n2k = [&frames](n2k::Header h, const n2k::Message& m, std::uint8_t seq = 0) {
    for (const auto& f : n2k::encode_frames(h, m, seq)) frames.push_back(to_socket(f));
  };
  n2k::VesselHeading heading;
  heading.heading_rad = 0.25;
  heading.reference = n2k::DirectionReference::kTrue;
  n2k::RateOfTurn rot;
  rot.rate_radps = 0.02;
  n2k::Attitude att;
  att.yaw_rad = 0.25;
  att.pitch_rad = 0.01;
  att.roll_rad = 0.02;
  n2k::SpeedWaterReferenced speed;
  speed.water_speed_mps = 0.8;
  n2k::WaterDepth depth;
  depth.depth_m = 25.0;
  n2k::PositionRapidUpdate pos;
  pos.lat_deg = kLatDeg;
  pos.lon_deg = 127.36;
  n2k::CogSogRapidUpdate cogsog;
  cogsog.cog_rad = 1.0;
  cogsog.sog_mps = 0.5;
  for (const n2k::Message& m :
       std::vector<n2k::Message>{heading, rot, att, speed, depth, pos, cogsog}) {
    add_n2k(n2k::Header{2, 0, 0x23}, m);
  }
  // Two GNSS receivers' fast packets, frame by frame interleaved.
  const auto a = n2k::encode_frames(n2k::Header{3, 0, 10}, gnss(kLatDeg, 127.36), 3);
  const auto b = n2k::encode_frames(n2k::Header{3, 0, 20}, gnss(kLatDeg, 127.37), 6);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    frames.push_back(to_socket(a[i]));
    frames.push_back(to_socket(b[i]));
  }
  // Wheel encoders through the DBC navd was given.
  const auto db = protocols::dbc::load(crawler_dbc());
  ASSERT_TRUE(db.has_value()) << db.error().detail;
  const auto codec = wheel::WheelEncoderCodec::from_database(*db);
  ASSERT_TRUE(codec.has_value()) << codec.error().detail;
  for (std::uint32_t k = 0; k < 3; ++k) {
    const auto counter = static_cast<std::uint8_t>(k);
    for (const auto w : {wheel::Wheel::kLeft, wheel::Wheel::kRight}) {
      const auto f = codec->encode(wheel::WheelEncoderSample{w, 100 * k, 0.5, counter, true});
      ASSERT_TRUE(f.has_value()) << f.error().detail;
      frames.push_back(to_socket(*f));
    }
  }
  // Garbage: an 11-bit id of no message, a 127250 too short, a wheel frame too short, RTR.
  CanFrame unknown;
  unknown.id = 0x555;
  unknown.dlc = 2;
  frames.push_back(unknown);
  CanFrame short_n2k = frames.front();  // the heading
  short_n2k.dlc = 3;
  frames.push_back(short_n2k);
  CanFrame short_wheel;
  short_wheel.id = 0x121;
  short_wheel.dlc = 4;
  frames.push_back(short_wheel);
  CanFrame rtr;
  rtr.id = 0x120;
  rtr.rtr = true;
  rtr.dlc = 8;
  frames.push_back(rtr);
  ASSERT_EQ(frames.size(), 7u + 14u + 6u + 4u);

  for (const auto& f : frames) {
    // A vcan queue never fills at this rate; retry briefly if it does.
    auto ok = sender->send(f);
    for (int tries = 0; !ok && ok.error().code == ErrorCode::kTimeout && tries < 100; ++tries) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
      ok = sender->send(f);
    }
    ASSERT_TRUE(ok) << ok.error().detail;
  }
  // can-utils as an independent sender, bytes transcribed by hand: heading 1.5708 rad from
  // source 0x01 (protocols.md 5), and a left wheel frame (crawler.dbc: 1000 counts, 1.5 rad/s,
  // counter 3, valid).
  EXPECT_EQ(run_program({"cansend", kIface, "09F11201#005C3DFF7FFF7FFC"}), 0);
  EXPECT_EQ(run_program({"cansend", kIface, "120#E8030000DC051300"}), 0);
  const std::size_t total = frames.size() + 2;
  ASSERT_EQ(receive_frames(*listener, total, 5.0).size(), total) << "the bus did not carry every frame";

  // One more trigger: navd reads the CAN socket in the wake that brings it (or earlier).
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  ASSERT_TRUE(ahrs.write(ahrs_packet(62500 + 625, kLatDeg)));
  ASSERT_TRUE(reader.await(62500 + 625)) << navd.stderr_text();

  const auto status = navd.terminate();
  ASSERT_TRUE(status.has_value());
  EXPECT_TRUE(WIFEXITED(*status) && WEXITSTATUS(*status) == 0) << *status;
  const std::string err = navd.stderr_text();
  EXPECT_NE(err.find("can=vcan0 dbc=" + crawler_dbc()), std::string::npos) << err;
  const std::string expected =
      "; can{iface=vcan0 frames=" + std::to_string(total) +
      " n2k{127250=2,127251=1,127257=1,128259=1,128267=1,129025=1,129026=1,129029=2,other=0}"
      " dbc{WheelEncoderLeft=4,WheelEncoderRight=3}"
      " rejects{unknown_id=1,rtr=1,error_frames=0,fields=1,fast_packet=0,fast_packet_dup=0,"
      "dbc=1} errors{bus_off=0,restarted=0,protocol=0,controller=0,rx_errors=0}}";
  EXPECT_NE(err.find(expected), std::string::npos) << "expected " << expected << "\nin\n" << err;
  EXPECT_NE(err.find("solutions written=2 "), std::string::npos) << err;
  if (!HasFailure()) navd.remove_dir();
}

TEST(NavdCanVcan, AnInterfaceThatCannotBeOpenedIsOneLineAndExit3) {
  TestPty ahrs, output;
  ASSERT_TRUE(ahrs.ok() && output.ok()) << "openpty failed (is /dev/pts mounted?)";
  const auto dir = std::filesystem::path(::testing::TempDir()) /
                   ("navd-can-noif-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string navd = nav::test_paths::binary_dir() + "/navd";
  const int status = run_program({navd, "--ahrs", ahrs.path, "--output", output.path, "--can",
                                  "nosuchcan0", "--dbc", crawler_dbc()},
                                 dir / "stderr.txt");
  const std::string err = slurp(dir / "stderr.txt");
  ASSERT_TRUE(WIFEXITED(status)) << status;
  EXPECT_EQ(WEXITSTATUS(status), 3) << err;
  EXPECT_NE(err.find("navd: cannot open CAN interface nosuchcan0: "), std::string::npos) << err;
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  std::filesystem::remove_all(dir);
}

TEST(NavdCanVcan, ADbcThatDisagreesWithTheCodeIsExit2) {
  TestPty ahrs, output;
  ASSERT_TRUE(ahrs.ok() && output.ok()) << "openpty failed (is /dev/pts mounted?)";
  const auto dir = std::filesystem::path(::testing::TempDir()) /
                   ("navd-can-baddbc-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::string text = slurp(crawler_dbc());
  const std::string from = "SG_ WheelSpeed : 32|16@1- (0.001,0) [-32.768|32.767] \"rad/s\"";
  const auto at = text.find(from);
  ASSERT_NE(at, std::string::npos);
  text.replace(at, from.size(), "SG_ WheelSpeed : 32|16@1- (0.001,0) [-32.768|32.767] \"rpm\"");
  std::ofstream(dir / "bad.dbc") << text;
  const std::string navd = nav::test_paths::binary_dir() + "/navd";
  const int status = run_program({navd, "--ahrs", ahrs.path, "--output", output.path, "--can",
                                  kIface, "--dbc", (dir / "bad.dbc").string()},
                                 dir / "stderr.txt");
  const std::string err = slurp(dir / "stderr.txt");
  ASSERT_TRUE(WIFEXITED(status)) << status;
  EXPECT_EQ(WEXITSTATUS(status), 2) << err;
  EXPECT_NE(err.find("WheelSpeed"), std::string::npos) << err;
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace nav::testing
