// SPDX-License-Identifier: MIT
// End-to-end runs: navbench with navd (or a misbehaving DUT) as a child process over ptys.
#include <filesystem>
#include <algorithm>
#include <regex>
#include <sstream>
#include <tuple>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "navbench_cli.hpp"
#include "run_summary.hpp"

namespace nav::testing {
namespace {

namespace fs = std::filesystem;

TEST(NavbenchRun, RealtimeScenarioWithNavdPasses) {
  const auto dir = fresh_dir("rt-pass");
  const auto r = run_navbench(
      {"run", source_path("tests/integration/scenarios/rt_pass.yaml"), "--out", "run"}, dir);
  ASSERT_TRUE(dut_passed_in_realtime(r, dir / "run"));
  EXPECT_NE(r.out.find("bench lateness  p50"), std::string::npos) << r.out;
  const auto run = dir / "run";
  for (const char* f : {"summary.json", "junit.xml", "truth.tum", "estimate.tum",
                        "timeseries.csv", "latency.csv", "lateness.csv", "capture-tx.log",
                        "capture-rx.log", "dut.log", "scenario.yaml"}) {
    EXPECT_TRUE(fs::exists(run / f)) << f;
  }
  EXPECT_FALSE(fs::exists(dir / "run.partial"));
  const auto s = summary(run);
  EXPECT_EQ(s["verdict"], r.exit_code == 0 ? "PASS" : "BENCH-LATE");
  EXPECT_EQ(s["seed"], 7);
  EXPECT_EQ(s["dut"]["triggers_sent"], 2000);
  EXPECT_GE(s["dut"]["answers"].get<int>(), 1990);
  EXPECT_EQ(s["bench_lateness"]["count"].get<int>(), 2000 + 20);
  // Every emitted message is in the transmit capture, in the documented line format.
  const std::string tx = slurp(run / "capture-tx.log");
  const std::regex line(R"(\(\d+\.\d{9}\) (ahrs|gps) [0-9A-F]+\n)");
  std::size_t lines = 0;
  for (std::sregex_iterator it(tx.begin(), tx.end(), line), end; it != end; ++it) ++lines;
  EXPECT_EQ(lines, 2020u);

  // The captures decode back: every AHRS packet sent, every solution received.
  const auto ahrs = run_navbench({"decode", "--protocol", "microstrain-gx3", "--port", "ahrs",
                                  (run / "capture-tx.log").string()}, dir);
  EXPECT_EQ(ahrs.exit_code, 0) << ahrs.err;
  // 2000 packets and the 8-byte reply to navd's start command.
  EXPECT_NE(ahrs.err.find(": 2001 messages, 0 errors"), std::string::npos) << ahrs.err;
  // navd started the GX3's continuous mode; the bench answered before the first packet.
  EXPECT_NE(slurp(run / "capture-rx.log").find(" ahrs C4C129CB\n"), std::string::npos);
  const auto first_ahrs = tx.find(" ahrs ");
  ASSERT_NE(first_ahrs, std::string::npos);
  EXPECT_EQ(tx.substr(first_ahrs + 6, 4), "C4CB");
  EXPECT_EQ(tx.find('\n', first_ahrs) - (first_ahrs + 6), 16u);  // 8 bytes
  for (const auto& d : s["devices"]) EXPECT_EQ(d["suppressed"].get<int>(), 0) << d["name"];
  const auto out = run_navbench({"decode", "--protocol", "nmea0183", "--port", "output",
                                 (run / "capture-rx.log").string()}, dir);
  EXPECT_EQ(out.exit_code, 0) << out.err;
  // Every solution, the covariance navd states before each one with a position (its GPS
  // Kalman filter's; the Mahony attitude keeps none), and the innovations of its GPS updates.
  const auto count = [&](const std::string& type) {
    std::size_t n = 0;
    for (auto at = out.out.find(type); at != std::string::npos; at = out.out.find(type, at + 1)) ++n;
    return n;
  };
  const std::size_t covariances = count(R"("type":"NVBCOV")");
  const std::size_t innovations = count(R"("type":"NVBINN")");
  EXPECT_GT(covariances, 0u);
  EXPECT_GT(innovations, 0u);
  EXPECT_NE(out.err.find(": " +
                         std::to_string(s["dut"]["answers"].get<std::size_t>() + covariances +
                                        innovations) +
                         " messages, 0 errors"),
            std::string::npos)
      << out.err;
  EXPECT_NE(out.out.find(R"("source":"gps-position","m":3,"nu":[)"), std::string::npos);
  EXPECT_TRUE(fs::exists(run / "innovations.csv"));
  EXPECT_NE(out.out.find(R"({"type":"NVBSOL","talker":"P","input":"AHRS")"), std::string::npos);
  EXPECT_NE(out.out.find(R"("position_m":{"sigma":[)"), std::string::npos);
  EXPECT_NE(out.out.find(R"("attitude_deg":null)"), std::string::npos);
}

TEST(NavbenchRun, LockstepRunsAreBitReproducible) {
  const auto dir = fresh_dir("lockstep");
  const auto scenario = source_path("tests/integration/scenarios/rt_pass.yaml");
  const auto a = run_navbench({"run", scenario, "--mode", "lockstep", "--out", "a"}, dir);
  const auto b = run_navbench({"run", scenario, "--mode", "lockstep", "--out", "b"}, dir);
  ASSERT_EQ(a.exit_code, 0) << a.out << a.err;
  ASSERT_EQ(b.exit_code, 0) << b.out << b.err;
  const std::string ea = slurp(dir / "a" / "estimate.tum");
  EXPECT_GT(ea.size(), 100000u);  // ~1900 solutions with a position
  EXPECT_EQ(ea, slurp(dir / "b" / "estimate.tum"));
  EXPECT_EQ(slurp(dir / "a" / "capture-tx.log"), slurp(dir / "b" / "capture-tx.log"));
  const auto s = summary(dir / "a");
  EXPECT_EQ(s["mode"], "lockstep");
  EXPECT_EQ(s["dut"]["answers"], 2000);
  EXPECT_FALSE((*check(s, "deadline"))["judged"].get<bool>());
}

TEST(NavbenchRun, DutThatExitsAtOnceIsReportedCrashed) {
  const auto dir = fresh_dir("exits");
  const auto r = run_navbench(
      {"run", source_path("tests/integration/scenarios/dut_exits.yaml"), "--out", "run"}, dir);
  EXPECT_EQ(r.exit_code, 4) << r.out << r.err;
  EXPECT_NE(r.out.find("VERDICT: DUT crashed"), std::string::npos) << r.out;
  // A realtime run that wrote nothing has no lateness, and is not called lockstep.
  EXPECT_NE(r.out.find("bench lateness  n/a (no message was written)"), std::string::npos)
      << r.out;
  const auto s = summary(dir / "run");  // the report is still written
  EXPECT_EQ(s["verdict"], "DUT crashed");
  EXPECT_FALSE((*check(s, "dut_alive"))["passed"].get<bool>());
}

TEST(NavbenchRun, DutThatStopsAnsweringIsReportedHung) {
  const auto dir = fresh_dir("hangs");
  const auto r = run_navbench(
      {"run", source_path("tests/integration/scenarios/dut_hangs.yaml"), "--out", "run"}, dir);
  EXPECT_EQ(r.exit_code, 4) << r.out << r.err;
  EXPECT_NE(r.out.find("VERDICT: DUT hung"), std::string::npos) << r.out;
  // The watchdog (1 s) ends the 10 s scenario early: the bench never waits for a hung DUT.
  EXPECT_LT(r.wall_s, 9.0);
  EXPECT_EQ(summary(dir / "run")["verdict"], "DUT hung");
}

// A DUT that never sends the GX3 start command gets no AHRS packets: no trigger is sent, so
// the watchdog (which times answers to triggers) never fires and the DUT is not "hung"; the
// run lasts its whole duration and fails on its error checks ("no solutions"), exit 1.
TEST(NavbenchRun, DutThatNeverStartsTheGx3GetsNoPackets) {
  const auto dir = fresh_dir("silent");
  const auto r = run_navbench(
      {"run", source_path("tests/integration/scenarios/dut_silent.yaml"), "--out", "run"}, dir);
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_NE(r.out.find("VERDICT: FAIL"), std::string::npos) << r.out;
  const auto s = summary(dir / "run");
  EXPECT_EQ(s["verdict"], "FAIL");
  EXPECT_EQ(s["dut"]["triggers_sent"], 0);
  EXPECT_EQ(s["dut"]["answers"], 0);
  EXPECT_NE(s["dut"]["status"].get<std::string>().find("never sent the start command"),
            std::string::npos) << s["dut"]["status"];
  bool ahrs_seen = false;
  for (const auto& d : s["devices"]) {
    if (d["name"] != "ahrs") continue;
    ahrs_seen = true;
    EXPECT_EQ(d["messages"], 0);
    EXPECT_EQ(d["bytes"], 0);
    EXPECT_EQ(d["suppressed"], 300);  // 3 s at 100 Hz
  }
  EXPECT_TRUE(ahrs_seen);
  for (const auto& c : s["checks"]) {
    if (c["name"] != "horizontal_error") continue;
    EXPECT_FALSE(c["passed"].get<bool>());
    EXPECT_NE(c["detail"].get<std::string>().find("no solutions"), std::string::npos);
  }
  EXPECT_EQ(slurp(dir / "run" / "capture-tx.log").find(" ahrs "), std::string::npos);
}

TEST(NavbenchRun, SlowDutGetsItsDeadlineMissesCounted) {
  const auto dir = fresh_dir("slow");
  const auto r = run_navbench(
      {"run", source_path("tests/integration/scenarios/dut_slow.yaml"), "--out", "run"}, dir);
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  const auto s = summary(dir / "run");
  EXPECT_EQ(s["verdict"], "FAIL");
  const auto* d = check(s, "deadline");
  ASSERT_NE(d, nullptr);
  EXPECT_FALSE((*d)["passed"].get<bool>());
  // 400 triggers in 4 s; a DUT taking 50 ms per solution answers about 20 per second, each
  // later than 20 ms, so every trigger is a miss (late or never answered).
  EXPECT_EQ((*d)["value"].get<double>(), 400.0);
  EXPECT_GE(s["dut_latency"]["p50_ms"].get<double>(), 50.0);
}

// The stuck fault repeats AHRS packets that navd answers again: the bench must wait for each
// of those answers, or a GPS fix lands on another copy from run to run.
TEST(NavbenchRun, FaultScenarioLockstepRunsAreBitReproducible) {
  const auto dir = fresh_dir("faults-ls");
  const auto scenario = source_path("scenarios/faults-gps-ahrs.yaml");
  std::string first;
  for (const char* out : {"a", "b", "c"}) {
    const auto r = run_navbench({"run", scenario, "--mode", "lockstep", "--out", out, "-q"}, dir);
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    const std::string e = slurp(dir / out / "estimate.tum");
    if (first.empty()) first = e;
    EXPECT_EQ(e, first) << out;
  }
  // navd answered every copy of the stuck packet (50 copies in 18.5-19 s at 100 Hz).
  EXPECT_EQ(summary(dir / "a")["dut"]["answers"].get<int>() -
                summary(dir / "a")["dut"]["triggers_sent"].get<int>(),
            50);
}

/// Capture lines "(<sec>.<nsec>) <port> <hex>" of one port: their times [s]. Lines before
/// scenario time 0 (negative, written during the DUT's startup) only with before_zero.
std::vector<double> capture_times(const std::string& capture, const std::string& port,
                                  bool before_zero = false);

TEST(NavbenchRun, AllDevicesScenarioPassesInRealtime) {
  const auto dir = fresh_dir("all-devices-rt");
  const auto r = run_navbench(
      {"run", source_path("scenarios/all-devices.yaml"), "--out", "run"}, dir);
  ASSERT_TRUE(dut_passed_in_realtime(r, dir / "run"));
  const auto s = summary(dir / "run");
  ASSERT_EQ(s["devices"].size(), 13u);  // 10 on uuv, 3 on buddy
  for (const auto& d : s["devices"]) {
    EXPECT_GT(d["messages"].get<int>(), 0) << d["name"];
    EXPECT_EQ(d["bytes_dropped"].get<int>(), 0) << d["name"];
  }
  EXPECT_TRUE(s["faults"].empty());
  // Every emulated device is on the wire.
  const std::string tx = slurp(dir / "run" / "capture-tx.log");
  for (const char* port :
       {"ahrs", "gps", "dvl_nq1", "dvl_pd0", "dvl_pd6", "dvl_a50", "imu", "usbl", "depth",
        "modem", "buddy.ahrs", "buddy.gps", "buddy.modem"}) {
    EXPECT_NE(tx.find(std::string(") ") + port + " "), std::string::npos) << port;
  }
  // The Keller answers navd's polls: the F48 at start, then F73 P1 at 5 Hz of AHRS time,
  // each answered once, 5 ms after the request was read.
  const std::string rx = slurp(dir / "run" / "capture-rx.log");
  const auto requests = capture_times(rx, "depth", true);
  const auto answers = capture_times(tx, "depth", true);
  EXPECT_NE(rx.find(") depth FA300443\n"), std::string::npos);  // F48 to address 250
  EXPECT_GE(requests.size(), 120u);
  EXPECT_EQ(answers.size(), requests.size());
  for (std::size_t i = 1; i < std::min(requests.size(), answers.size()); ++i) {
    EXPECT_GE(answers[i] - requests[i], 0.005) << i;
    EXPECT_LT(answers[i] - requests[i], 0.2) << i;  // noisy VM: wide margin
  }
  // navd fuses the depth: the vertical check passes with a 0.5 m limit through the dive.
  EXPECT_TRUE((*check(s, "vertical_error"))["passed"].get<bool>());
  // The two navds hear each other over the acoustic link: a report every 2 s each way.
  ASSERT_EQ(s["acoustic_links"].size(), 2u);
  // None is lost; a report written less than its travel time (about 0.2 s) before the end of
  // the run is still on the water when the run ends.
  for (const auto& l : s["acoustic_links"]) {
    EXPECT_GE(l["packets_delivered"].get<int>(), 11) << l.dump();
    EXPECT_EQ(l["packets_lost"], 0) << l.dump();
    EXPECT_LE(l["packets_sent"].get<int>() - l["packets_delivered"].get<int>(), 1) << l.dump();
  }
  EXPECT_NE(s["peers"][0]["dut"]["status"].get<std::string>().find("alive"), std::string::npos);
}

TEST(NavbenchRun, AllDevicesLockstepRunsAreBitReproducible) {
  const auto dir = fresh_dir("all-devices-ls");
  const auto scenario = source_path("scenarios/all-devices.yaml");
  const auto a = run_navbench({"run", scenario, "--mode", "lockstep", "--out", "a"}, dir);
  const auto b = run_navbench({"run", scenario, "--mode", "lockstep", "--out", "b"}, dir);
  ASSERT_EQ(a.exit_code, 0) << a.out << a.err;
  ASSERT_EQ(b.exit_code, 0) << b.out << b.err;
  const std::string ea = slurp(dir / "a" / "estimate.tum");
  EXPECT_GT(ea.size(), 100000u);
  EXPECT_EQ(ea, slurp(dir / "b" / "estimate.tum"));
  EXPECT_EQ(slurp(dir / "a" / "capture-tx.log"), slurp(dir / "b" / "capture-tx.log"));
  // The DUT's Keller requests too: each read at the same scenario time in both runs (the
  // DUT's output lines in capture-rx.log carry wall-clock times, so only "depth" is compared).
  const auto requests = capture_times(slurp(dir / "a" / "capture-rx.log"), "depth");
  EXPECT_GE(requests.size(), 120u);
  EXPECT_EQ(requests, capture_times(slurp(dir / "b" / "capture-rx.log"), "depth"));
  EXPECT_EQ(summary(dir / "a")["dut"]["answers"], 2500);
  EXPECT_EQ(summary(dir / "a")["peers"][0]["dut"]["answers"], 2500);
}

/// Capture lines "(<sec>.<nsec>) <port> <hex>" of one port: their times [s].
std::vector<double> capture_times(const std::string& capture, const std::string& port,
                                  bool before_zero) {
  std::vector<double> t;
  const std::regex line(before_zero ? R"(\((-?\d+\.\d{9})\) (\S+) [0-9A-F]+\n)"
                                    : R"(\((\d+\.\d{9})\) (\S+) [0-9A-F]+\n)");
  for (std::sregex_iterator it(capture.begin(), capture.end(), line), end; it != end; ++it) {
    if ((*it)[2] == port) t.push_back(std::stod((*it)[1]));
  }
  return t;
}

TEST(NavbenchRun, FaultScenarioReportsEveryFaultAndNavdSurvives) {
  const auto dir = fresh_dir("faults");
  const auto r = run_navbench(
      {"run", source_path("scenarios/faults-gps-ahrs.yaml"), "--out", "run"}, dir);
  ASSERT_TRUE(dut_passed_in_realtime(r, dir / "run"));
  const auto s = summary(dir / "run");
  EXPECT_TRUE((*check(s, "dut_alive"))["passed"].get<bool>());
  // Every fault of the scenario, in device then file order, each with an effect.
  const std::vector<std::pair<std::string, std::string>> expected{
      {"ahrs", "off"},      {"ahrs", "slow"},      {"ahrs", "intermittent"},
      {"ahrs", "checksum"}, {"ahrs", "garbage"},   {"ahrs", "stuck"},
      {"gps", "checksum"},  {"gps", "truncated"},  {"gps", "byte_loss"},
      {"gps", "garbage"},   {"gps", "stuck"},      {"gps", "delayed"},
      {"gps", "off"}};
  ASSERT_EQ(s["faults"].size(), expected.size()) << s["faults"].dump();
  std::size_t removed = 0, damaged = 0;  // GX3 packets never sent / sent but no trigger
  for (std::size_t i = 0; i < expected.size(); ++i) {
    const auto& f = s["faults"][i];
    EXPECT_EQ(f["device"], expected[i].first) << i;
    EXPECT_EQ(f["kind"], expected[i].second) << i;
    EXPECT_GT(f["messages_affected"].get<int>(), 0) << f.dump();
    EXPECT_NE(r.out.find("  FAULT " + expected[i].first + " " + expected[i].second + " "),
              std::string::npos) << r.out;
    if (f["device"] == "ahrs") {
      (i < 3 ? removed : damaged) += f["messages_affected"].get<std::size_t>();
    }
  }
  EXPECT_EQ(s["faults"][0]["start_s"], 4.0);
  EXPECT_EQ(s["faults"][0]["end_s"], 5.0);
  EXPECT_EQ(s["faults"][0]["messages_affected"], 100);
  // Packets damaged or repeated by a fault are sent but are no triggers; navd answers every
  // trigger (it loses no whole packet next to a damaged one).
  EXPECT_EQ(s["dut"]["triggers_sent"].get<std::size_t>(), 2000 - removed - damaged);
  const auto deadline = (*check(s, "deadline"))["detail"].get<std::string>();
  EXPECT_NE(deadline.find("(0 unanswered"), std::string::npos) << deadline;
  // navd answers each repeated (stuck) packet too; those solutions name an earlier trigger.
  EXPECT_GE(s["dut"]["answers"].get<std::size_t>(), s["dut"]["triggers_sent"].get<std::size_t>());
  EXPECT_NE(slurp(dir / "run" / "junit.xml").find("<property name=\"fault\" value=\"ahrs off "),
            std::string::npos);

  // Nothing on the AHRS line inside its `off` window, nor on the GPS line inside its own.
  const std::string tx = slurp(dir / "run" / "capture-tx.log");
  const auto ahrs = capture_times(tx, "ahrs");
  EXPECT_EQ(ahrs.size(), 2000 - removed);
  for (const double t : ahrs) EXPECT_FALSE(t > 4.001 && t < 4.999) << "ahrs at " << t;
  const auto gps = capture_times(tx, "gps");
  EXPECT_FALSE(gps.empty());
  for (const double t : gps) EXPECT_FALSE(t > 16.1 && t < 18.0) << "gps at " << t;
  EXPECT_TRUE(std::any_of(ahrs.begin(), ahrs.end(), [](double t) { return t > 5.0 && t < 5.1; }));
}

/// The values of one numeric field of every decoded JSON line of `type` [field's unit].
std::vector<double> decoded(const std::string& jsonl, const std::string& type,
                            const std::string& field) {
  std::vector<double> v;
  std::istringstream in(jsonl);
  for (std::string line; std::getline(in, line);) {
    const auto j = nlohmann::json::parse(line);
    if (j["type"] == type) v.push_back(j[field].get<double>());
  }
  return v;
}

TEST(NavbenchRun, MeasurementFaultsShowOnTheWireAndNavdSurvives) {
  const auto dir = fresh_dir("faults-measurement");
  const auto r = run_navbench({"run", source_path("scenarios/faults-measurement.yaml"),
                               "--mode", "lockstep", "--out", "run"}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const auto s = summary(dir / "run");
  EXPECT_TRUE((*check(s, "dut_alive"))["passed"].get<bool>());
  EXPECT_EQ(s["dut"]["answers"], 2000);
  // Each fault with the messages it covered: 200 GX3 packets in 2 s, 15 GPS epochs in 3 s,
  // 20 DVL pings in 4 s, 4 USBL fixes in 4 s; the Keller's by the polls it answered (5 Hz).
  const std::vector<std::tuple<std::string, std::string, int>> expected{
      {"ahrs", "wrong", 200},     {"gps", "gps_jump", 15}, {"dvl", "bottom_lock_loss", 20},
      {"usbl", "usbl_outliers", 4}, {"depth", "off", 10},  {"depth", "checksum", 5},
      {"depth", "wrong", 15}};
  ASSERT_EQ(s["faults"].size(), expected.size()) << s["faults"].dump();
  for (std::size_t i = 0; i < expected.size(); ++i) {
    const auto& f = s["faults"][i];
    EXPECT_EQ(f["device"], std::get<0>(expected[i])) << i;
    EXPECT_EQ(f["kind"], std::get<1>(expected[i])) << i;
    EXPECT_EQ(f["messages_affected"], std::get<2>(expected[i])) << f.dump();
  }
  const auto capture = (dir / "run" / "capture-tx.log").string();
  // GPS: 30 m north for the 15 fixes of [5 s, 8 s): consecutive fixes 0.2 s apart move
  // about 0.2 m, except at the two edges of the window, where they jump by about 30 m.
  const auto gps = run_navbench({"decode", "--protocol", "nmea0183", "--port", "gps", capture}, dir);
  ASSERT_EQ(gps.exit_code, 0) << gps.err;
  const auto lat = decoded(gps.out, "GGA", "lat_deg");
  ASSERT_EQ(lat.size(), 100u);
  constexpr double kMetresPerDegLat = 111'000.0;  // near 36 deg N, to 0.1 %
  for (std::size_t k = 1; k < lat.size(); ++k) {
    const double step_m = (lat[k] - lat[k - 1]) * kMetresPerDegLat;
    if (k == 25) EXPECT_NEAR(step_m, 30.0, 2.5) << k;        // fix at 5.0 s: jump on
    else if (k == 40) EXPECT_NEAR(step_m, -30.0, 2.5) << k;  // fix at 8.0 s: jump off
    else EXPECT_LT(std::abs(step_m), 2.5) << k;
  }
  // Keller: P1 at the surface is the atmosphere, 1.01325 bar; +10 kPa = 0.1 bar while wrong.
  const auto keller =
      run_navbench({"decode", "--protocol", "keller-bus", "--port", "depth", capture}, dir);
  const auto p1 = decoded(keller.out, "keller_channel_value", "value");
  ASSERT_GT(p1.size(), 60u);
  EXPECT_EQ(std::count_if(p1.begin(), p1.end(), [](double p) { return p > 1.1; }), 15);
  // No Keller answer inside its off window, though navd keeps polling there.
  const auto answers = capture_times(slurp(dir / "run" / "capture-tx.log"), "depth");
  const auto requests = capture_times(slurp(dir / "run" / "capture-rx.log"), "depth");
  for (const double t : answers) EXPECT_FALSE(t > 14.01 && t < 16.0) << "answer at " << t;
  EXPECT_GE(std::count_if(requests.begin(), requests.end(),
                          [](double t) { return t > 14.0 && t < 16.0; }), 9);
  // navd rejects the answers with a broken CRC and counts the polls they leave unanswered.
  const std::string log = slurp(dir / "run" / "dut.log");
  EXPECT_NE(log.find("timeouts=15"), std::string::npos) << log;
}

/// The "# expect:" and "# line:" header comments of a malformed scenario file.
std::pair<std::string, std::string> expectation(const fs::path& p) {
  const std::string text = slurp(p);
  std::smatch m1, m2;
  std::regex_search(text, m1, std::regex(R"(# expect: (.*))"));
  std::regex_search(text, m2, std::regex(R"(# line: (\d+))"));
  return {m1[1], m2[1]};
}

TEST(NavbenchRun, MalformedScenariosExitTwoWithFileLineAndNoRunFolder) {
  std::size_t n = 0;
  // malformed/: refused while loading; malformed_path/: loads, but its path cannot be built.
  for (const char* folder : {"tests/integration/malformed", "tests/integration/malformed_path"}) {
    for (const auto& e : fs::directory_iterator(source_path(folder))) {
      if (e.path().extension() != ".yaml") continue;
      ++n;
      const auto [expect, line] = expectation(e.path());
      const auto dir = fresh_dir("malformed");
      const auto r = run_navbench({"run", e.path().string(), "--out", "run"}, dir);
      EXPECT_EQ(r.exit_code, 2) << e.path() << r.err;
      // One line: "navbench: FILE:LINE:COL: what was expected".
      const std::string prefix = "navbench: " + e.path().string() + ":" + line + ":";
      EXPECT_EQ(r.err.rfind(prefix, 0), 0u) << r.err;
      EXPECT_NE(r.err.find(expect), std::string::npos) << r.err;
      EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
      EXPECT_FALSE(fs::exists(dir / "run"));
      EXPECT_FALSE(fs::exists(dir / "run.partial"));
      EXPECT_FALSE(fs::exists(dir / "runs"));
    }
  }
  EXPECT_GE(n, 9u);
}

TEST(NavbenchRun, MissingSerialDeviceIsABenchErrorBeforeAnythingStarts) {
  const auto dir = fresh_dir("missing-device");
  const auto r = run_navbench(
      {"run", source_path("tests/integration/scenarios/missing_device.yaml"), "--out", "run"},
      dir);
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_EQ(r.err, "navbench: cannot open /dev/ttyNAVBENCH9: No such file or directory "
                   "(device 'gps')\n");
  EXPECT_FALSE(fs::exists(dir / "run"));
  EXPECT_FALSE(fs::exists(dir / "run.partial"));
}

TEST(NavbenchCli, HelpAndUsageErrors) {
  const auto dir = fresh_dir("cli");
  const auto help = run_navbench({"run", "--help"}, dir);
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.out.find("--mode"), std::string::npos);
  const auto missing = run_navbench({"run", "no-such-file.yaml"}, dir);
  EXPECT_EQ(missing.exit_code, 2);
  const auto none = run_navbench({}, dir);
  EXPECT_EQ(none.exit_code, 2);
  // An empty --out (an unset shell variable) is refused, not taken for the default.
  const auto empty_out = run_navbench(
      {"run", source_path("tests/integration/scenarios/open_in_time.yaml"), "--out", ""}, dir);
  EXPECT_EQ(empty_out.exit_code, 2);
  EXPECT_NE(empty_out.err.find("must not be empty"), std::string::npos) << empty_out.err;
  EXPECT_FALSE(fs::exists(dir / "runs"));
  // A replay speed out of range is named with its range, in one short line.
  const auto speed = run_navbench(
      {"replay", source_path("tests/integration/scenarios/open_in_time.yaml"), "--speed", "0"}, dir);
  EXPECT_EQ(speed.exit_code, 2);
  EXPECT_NE(speed.err.find("0.001"), std::string::npos) << speed.err;
  EXPECT_LT(speed.err.size(), 200u) << speed.err;
  const auto unknown = run_navbench({"frobnicate"}, dir);
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_EQ(unknown.err, "navbench: unknown subcommand 'frobnicate' (one of: run, campaign, "
                         "decode, replay, record, witness, report; see navbench --help)\n");
}

}  // namespace
}  // namespace nav::testing
