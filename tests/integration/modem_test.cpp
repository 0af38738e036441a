// SPDX-License-Identifier: MIT
// Two vehicles, each with its own navd, joined by an acoustic modem link: each navd
// broadcasts $PNVBPOS reports and hears the other's. scenarios/two-vehicles-modem.yaml end to
// end, in lockstep (bit-reproducible, exact delivery times) and in realtime (delivery times
// within a few ms), with packet loss, with a peer that crashes, and with checks on every
// vehicle where only the peer is wrong.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "navbench_cli.hpp"
#include "run_summary.hpp"

namespace nav::testing {
namespace {

namespace fs = std::filesystem;

const std::string kScenario = "scenarios/two-vehicles-modem.yaml";
// The scenario's channel: packet_gap + latency, bit rate, range / sound speed.
constexpr double kGapPlusLatencyS = 0.05 + 0.2;
constexpr double kBitRate = 1000.0;
constexpr double kTravelS = 750.0 / 1500.0;

struct CaptureLine {
  double t_s = 0.0;
  std::string port;
  std::string bytes;  ///< decoded from hex
};

std::vector<CaptureLine> lines_of(const fs::path& file, const std::string& port) {
  std::vector<CaptureLine> out;
  std::ifstream f(file);
  const std::regex re(R"(\((\d+\.\d{9})\) (\S+) ([0-9A-F]+))");
  for (std::string line; std::getline(f, line);) {
    std::smatch m;
    if (!std::regex_match(line, m, re) || m[2] != port) continue;
    CaptureLine c{std::stod(m[1]), m[2], {}};
    const std::string hex = m[3];
    for (std::size_t i = 0; i + 1 < hex.size(); i += 2) {
      c.bytes.push_back(static_cast<char>(std::stoi(hex.substr(i, 2), nullptr, 16)));
    }
    out.push_back(std::move(c));
  }
  return out;
}

const nlohmann::json* link(const nlohmann::json& s, const std::string& from,
                           const std::string& to) {
  if (!s.contains("acoustic_links")) return nullptr;
  for (const auto& l : s["acoustic_links"]) {
    if (l["from"] == from && l["to"] == to) return &l;
  }
  return nullptr;
}

/// Every report one DUT wrote to its modem (`from`; one write per report, read whole in
/// lockstep; in realtime reads are joined per report) arrives on the other modem's line
/// (`to`) after gap + latency + 8 n / bit_rate + range / c, within tol_s. Returns the count.
std::size_t check_deliveries(const fs::path& run, const std::string& from,
                             const std::string& to, double tol_s) {
  // Join the writes into reports (a report ends with LF).
  std::vector<CaptureLine> sent;
  std::string partial;
  double first_t = 0.0;
  for (const auto& c : lines_of(run / "capture-rx.log", from)) {
    if (partial.empty()) first_t = c.t_s;
    partial += c.bytes;
    if (!partial.empty() && partial.back() == '\n') {
      sent.push_back({first_t, from, partial});
      partial.clear();
    }
  }
  const auto delivered = lines_of(run / "capture-tx.log", to);
  EXPECT_GE(sent.size(), 10u) << from;  // one report every 2 s of the 24 s
  // Deliveries due after the end of the run are not written.
  EXPECT_GE(delivered.size() + 1, sent.size());
  EXPECT_LE(delivered.size(), sent.size());
  for (std::size_t i = 0; i < delivered.size() && i < sent.size(); ++i) {
    EXPECT_EQ(delivered[i].bytes, sent[i].bytes) << i;
    const double n = static_cast<double>(sent[i].bytes.size());
    const double expected = kGapPlusLatencyS + 8.0 * n / kBitRate + kTravelS;
    const double delay = delivered[i].t_s - sent[i].t_s;
    EXPECT_NEAR(delay, expected, tol_s) << "packet " << i << ": " << sent[i].bytes;
    EXPECT_EQ(sent[i].bytes.rfind("$PNVBPOS,", 0), 0u) << sent[i].bytes;
  }
  return delivered.size();
}

TEST(NavbenchModem, LockstepIsBitReproducibleWithExactDeliveryTimes) {
  const auto dir = fresh_dir("modem-lockstep");
  const auto scenario = source_path(kScenario);
  const auto a = run_navbench({"run", scenario, "--mode", "lockstep", "--out", "a"}, dir);
  ASSERT_EQ(a.exit_code, 0) << a.out << a.err;
  const auto b = run_navbench({"run", scenario, "--mode", "lockstep", "--out", "b"}, dir);
  ASSERT_EQ(b.exit_code, 0) << b.out << b.err;
  for (const char* f : {"capture-tx.log", "estimate.tum"}) {
    EXPECT_EQ(slurp(dir / "a" / f), slurp(dir / "b" / f)) << f;
  }
  // The receive captures' DUT output lines carry wall-clock read times; what the DUTs wrote
  // to their modems is stamped in scenario time and is reproducible.
  for (const char* port : {"modem", "bravo.modem"}) {
    const auto ra = lines_of(dir / "a" / "capture-rx.log", port);
    const auto rb = lines_of(dir / "b" / "capture-rx.log", port);
    ASSERT_EQ(ra.size(), rb.size()) << port;
    for (std::size_t i = 0; i < ra.size(); ++i) {
      EXPECT_EQ(ra[i].t_s, rb[i].t_s) << port << " " << i;
      EXPECT_EQ(ra[i].bytes, rb[i].bytes) << port << " " << i;
    }
  }
  // Scenario times are exact: the only slack is the channel's 1 ns rounding.
  const std::size_t n = check_deliveries(dir / "a", "bravo.modem", "modem", 2e-6);
  const std::size_t n_back = check_deliveries(dir / "a", "modem", "bravo.modem", 2e-6);
  const auto s = summary(dir / "a");
  ASSERT_EQ(s["peers"].size(), 1u);
  EXPECT_EQ(s["peers"][0]["name"], "bravo");
  EXPECT_NE(s["peers"][0]["dut"]["status"].get<std::string>().find("alive"), std::string::npos);
  EXPECT_EQ(s["peers"][0]["dut"]["answers"], 2400);
  const auto* l = link(s, "bravo.modem", "modem");
  ASSERT_NE(l, nullptr) << s.dump(2);
  EXPECT_EQ((*l)["packets_delivered"].get<std::size_t>(), n);
  EXPECT_EQ((*l)["packets_lost"], 0);
  EXPECT_NEAR((*l)["min_propagation_s"].get<double>(), kTravelS, 1e-6);
  EXPECT_NEAR((*l)["max_propagation_s"].get<double>(), kTravelS, 1e-6);
  const auto* back = link(s, "modem", "bravo.modem");
  ASSERT_NE(back, nullptr);
  EXPECT_EQ((*back)["packets_delivered"].get<std::size_t>(), n_back);
  // Each navd decodes every report delivered to it, from the other's id (its exit stats).
  const auto heard = [&](const char* log, std::size_t count, int peer_id) {
    const std::string text = slurp(dir / "a" / log);
    EXPECT_NE(text.find("received=" + std::to_string(count) + " rejected=0 peers=[" +
                        std::to_string(peer_id) + ":" + std::to_string(count) + "]"),
              std::string::npos) << text;
  };
  heard("dut.log", n, 2);
  heard("dut-bravo.log", n_back, 1);
  bool peer_devices = false;
  for (const auto& d : s["devices"]) peer_devices |= d["name"] == "bravo.ahrs";
  EXPECT_TRUE(peer_devices);
}

TEST(NavbenchModem, RealtimeDeliveriesAreOnTime) {
  const auto dir = fresh_dir("modem-realtime");
  const auto r = run_navbench({"run", source_path(kScenario), "--out", "run"}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("peer bravo: DUT alive"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("acoustic bravo.modem -> modem"), std::string::npos) << r.out;
  check_deliveries(dir / "run", "bravo.modem", "modem", 0.005);
  check_deliveries(dir / "run", "modem", "bravo.modem", 0.005);
  const auto s = summary(dir / "run");
  const auto* l = link(s, "bravo.modem", "modem");
  ASSERT_NE(l, nullptr);
  EXPECT_GE((*l)["packets_delivered"].get<int>(), 10);
}

TEST(NavbenchModem, LossDropsSomePackets) {
  const auto dir = fresh_dir("modem-loss");
  std::string text = slurp(source_path(kScenario));
  const auto at = text.find("  loss: 0\n");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 10, "  loss: 0.5\n");
  {
    std::ofstream f(dir / "lossy.yaml");
    f << text;
  }
  const auto r = run_navbench(
      {"run", (dir / "lossy.yaml").string(), "--mode", "lockstep", "--out", "run"}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const auto s = summary(dir / "run");
  const auto* l = link(s, "bravo.modem", "modem");
  ASSERT_NE(l, nullptr);
  const auto sent = (*l)["packets_sent"].get<int>();
  const auto delivered = (*l)["packets_delivered"].get<int>();
  const auto lost = (*l)["packets_lost"].get<int>();
  EXPECT_GE(sent, 10);
  EXPECT_GT(lost, 0);
  EXPECT_GT(delivered, 0);
  EXPECT_LE(delivered + lost, sent);
  EXPECT_EQ(lines_of(dir / "run" / "capture-tx.log", "modem").size(),
            static_cast<std::size_t>(delivered));
}

TEST(NavbenchModem, PeerThatCrashesIsReportedWithItsVehicleName) {
  const auto dir = fresh_dir("modem-crash");
  std::string text = slurp(source_path(kScenario));
  // The second DUT command is the peer's.
  const std::string navd = "command: [navd,";
  const auto at = text.find(navd, text.find(navd) + 1);
  ASSERT_NE(at, std::string::npos);
  text.replace(at, navd.size(), "command: [false,");
  {
    std::ofstream f(dir / "crash.yaml");
    f << text;
  }
  const auto r = run_navbench(
      {"run", (dir / "crash.yaml").string(), "--mode", "lockstep", "--out", "run"}, dir);
  EXPECT_EQ(r.exit_code, 4) << r.out << r.err;
  EXPECT_NE(r.out.find("VERDICT: DUT crashed"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("peer 'bravo' crashed"), std::string::npos) << r.out;
  const auto s = summary(dir / "run");
  EXPECT_NE(s["peers"][0]["dut"]["status"].get<std::string>().find("crashed"), std::string::npos);
}

/// The scenario with `from` replaced by `to` (once), written into dir as name.
fs::path variant(const fs::path& dir, const std::string& name,
                 const std::vector<std::pair<std::string, std::string>>& edits) {
  std::string text = slurp(source_path(kScenario));
  for (const auto& [from, to] : edits) {
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
  }
  std::ofstream(dir / name) << text;
  return dir / name;
}

TEST(NavbenchModem, EveryVehicleIsJudgedAndOnlyTheWrongPeerFails) {
  // bravo's GPS fixes are 60 m north of the truth for the whole run, alpha's are right: with
  // the horizontal error judged on all vehicles, alpha's passes and bravo's fails the run.
  const auto dir = fresh_dir("modem-judge-all");
  const auto path = variant(
      dir, "all.yaml",
      {{"  - {kind: horizontal_error, max: 10 m, after: 5 s}",
        "  - {kind: horizontal_error, max: 10 m, after: 5 s, vehicle: all}\n"
        "  - {kind: dut_alive, name: bravo_alive, vehicle: bravo}"},
       {"        - {name: gps, type: nmea0183-gps, baud: 9600, rate: 1 Hz}",
        "        - {name: gps, type: nmea0183-gps, baud: 9600, rate: 1 Hz,\n"
        "           faults: [{kind: gps_jump, from: 0 s, to: 23 s, north: 60 m}]}"}});
  const auto r = run_navbench({"run", path.string(), "--mode", "lockstep", "--out", "run"}, dir);
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_NE(r.out.find("FAIL  bravo.horizontal_error"), std::string::npos) << r.out;
  const auto s = summary(dir / "run");
  const auto* alpha = check(s, "horizontal_error");
  const auto* bravo = check(s, "bravo.horizontal_error");
  ASSERT_NE(alpha, nullptr);
  ASSERT_NE(bravo, nullptr);
  EXPECT_TRUE((*alpha)["passed"].get<bool>());
  EXPECT_FALSE((*bravo)["passed"].get<bool>());
  EXPECT_GT((*bravo)["value"].get<double>(), 40.0);
  const auto* alive = check(s, "bravo.bravo_alive");
  ASSERT_NE(alive, nullptr);
  EXPECT_TRUE((*alive)["passed"].get<bool>());
  EXPECT_EQ(s["verdict"], "FAIL");
}

TEST(NavbenchModem, LoaderRefusesBadPeersAndChannels) {
  const auto dir = fresh_dir("modem-loader");
  struct Case {
    std::string file;
    std::vector<std::pair<std::string, std::string>> edits;
    std::string expect;
  };
  const std::vector<Case> cases{
      {"dup.yaml", {{"name: bravo", "name: alpha"}},
       "peers[0].vehicle.name: duplicate vehicle name 'alpha'"},
      {"ref.yaml",
       {{"\"{port:modem}\", --vehicle-id, \"2\"", "\"{port:dvl}\", --vehicle-id, \"2\""}},
       "peers[0].dut.command[8]: '{port:dvl}' names no device"},
      {"one.yaml",
       {{"        - {name: modem, type: acoustic-modem}\n", ""},
        {"--modem, \"{port:modem}\", --vehicle-id, \"2\"", "--vehicle-id, \"2\""}},
       "acoustic: an acoustic channel needs at least two acoustic-modem devices"},
      {"rate.yaml",
       {{"{name: modem, type: acoustic-modem}", "{name: modem, type: acoustic-modem, rate: 1 Hz}"}},
       "unknown key 'rate'"},
      {"vehicle.yaml",
       {{"  - {kind: dut_alive}", "  - {kind: dut_alive, vehicle: charlie}"}},
       "checks[1].vehicle: no vehicle named 'charlie' (the scenario's vehicles: 'alpha', "
       "'bravo'; or all)"},
      {"deadlines.yaml",
       {{"  - {kind: dut_alive}",
         "  - {kind: deadline, max_latency: 50 ms, vehicle: all}\n"
         "  - {kind: deadline, input: ahrs, max_latency: 50 ms, vehicle: bravo, name: d2}"}},
       "only one deadline check per vehicle of vehicle 'bravo'"},
  };
  for (const auto& c : cases) {
    const auto path = variant(dir, c.file, c.edits);
    const auto r = run_navbench({"run", path.string(), "--out", "run"}, dir);
    EXPECT_EQ(r.exit_code, 2) << c.file << r.out << r.err;
    EXPECT_NE(r.err.find(path.string() + ":"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(c.expect), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
}

}  // namespace
}  // namespace nav::testing
