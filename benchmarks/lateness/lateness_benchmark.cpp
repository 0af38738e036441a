// SPDX-License-Identifier: MIT
// The lateness benchmark: how punctual navbench is, measured against the machine's floor and
// against the tools a user would otherwise use (benchmark.hpp). A plain program run by hand
// (benchmarks/lateness/run runs every part):
//
//   lateness_benchmark pairs SCENARIO [--pairs 3] [--floor-seconds S] [--witness] [--out DIR]
//   lateness_benchmark serial [SCENARIO] [--pairs 3] [--out DIR]
//   lateness_benchmark can [SCENARIO] [--pairs 3] [--out DIR]      (inside scripts/with-vcan)
//
// Exit 0 when every run was measured, 2 on bad arguments (or a scenario that writes nothing in
// realtime), 3 when a run, a player or the output folder failed.
#include <cstdio>
#include <ctime>
#include <exception>
#include <filesystem>

#include <CLI/CLI.hpp>

#include "benchmark.hpp"
#include "source_paths.hpp"

int main(int argc, char** argv) {
  using namespace nav::benchmarks;
  CLI::App app{"navbench's lateness benchmark: the bench against the wake-up floor, and against\n"
               "a sleep-paced serial writer and canplayer on the same traces."};
  app.require_subcommand(1);
  Common c;
  c.navbench = (std::filesystem::path(nav::test_paths::binary_dir()) / "navbench").string();
  std::string out;
  const auto common = [&](CLI::App* sub) {
    sub->add_option("--pairs", c.pairs, "Pairs to run (default 3)")->check(CLI::Range(1, 100));
    sub->add_option("--out", out, "Folder for the runs and captures (default "
                                  "runs/lateness-<part>-<UTC time>)");
    sub->add_option("--navbench", c.navbench, "The navbench to measure (default the build's)");
  };
  std::string scenario, serial_scenario = nav::test_paths::source_dir() + "/scenarios/smoke.yaml";
  std::string can_scenario = nav::test_paths::source_dir() + "/scenarios/mixed-can-serial.yaml";
  double floor_seconds = 0.0;
  bool witness = false;
  auto* pairs = app.add_subcommand(
      "pairs", "The wake-up floor, the write floor (a bare writer of the warm-up run's bursts) "
               "and `navbench run SCENARIO` alternately (after a warm-up run that sets the "
               "floors' schedules); the bench's lateness p50/p99/max as ratios to each floor's, "
               "pair by pair, and their medians");
  pairs->add_option("scenario", scenario, "Scenario to run (realtime)")->required()
      ->check(CLI::ExistingFile);
  pairs->add_option("--floor-seconds", floor_seconds,
                    "Length of each floor (default: the scenario's duration)")
      ->check(CLI::PositiveNumber);
  pairs->add_flag("--witness", witness, "Run the scenario as a timing audit (navbench run --witness)");
  common(pairs);
  auto* serial = app.add_subcommand(
      "serial", "One serial trace (the scenario's lockstep capture-tx.log) played by navbench "
                "replay and by a sleep-paced writer, measured by navbench witness");
  serial->add_option("scenario", serial_scenario, "Scenario of the trace (default smoke.yaml)")
      ->check(CLI::ExistingFile);
  common(serial);
  auto* can = app.add_subcommand(
      "can", "One CAN trace (the scenario's lockstep capture-can.log) played on vcan0 by "
             "canplayer and by navbench replay, measured by candump; inside scripts/with-vcan");
  can->add_option("scenario", can_scenario, "Scenario of the trace (default mixed-can-serial.yaml)")
      ->check(CLI::ExistingFile);
  common(can);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);
    return rc == 0 ? 0 : 2;  // bad arguments: 2, as navbench
  }

  const char* part = *pairs ? "pairs" : *serial ? "serial" : "can";
  if (out.empty()) {
    char stamp[32];
    const std::time_t now = std::time(nullptr);
    std::tm tm{};
    ::gmtime_r(&now, &tm);
    std::strftime(stamp, sizeof stamp, "%Y%m%dT%H%M%SZ", &tm);
    out = std::string("runs/lateness-") + part + "-" + stamp;
  }
  c.out = out;
  std::error_code ec;
  std::filesystem::create_directories(c.out, ec);
  if (ec) {
    std::fprintf(stderr, "lateness_benchmark: cannot create %s: %s\n", out.c_str(),
                 ec.message().c_str());
    return 3;
  }
  try {
    if (*pairs) return run_pairs(c, scenario, floor_seconds, witness);
    if (*serial) return run_serial(c, serial_scenario);
    return run_can(c, can_scenario);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "lateness_benchmark %s: %s\n", part, e.what());
    return 3;
  }
}
