// SPDX-License-Identifier: MIT
// `navbench run`: one scenario end to end.
//
//   bench (sender thread)           pty lines            DUT (child)        bench (reader)
//   ---------------------           ---------            -----------        --------------
//   truth -> devices -> schedule
//   t0 = now + startup ------------------------------- opens slave paths
//   at T0 + chunk.t: write(master) --- bytes -------->  decode, estimate
//                                                       write $PNVBSOL --> read, timestamp,
//   realtime: next chunk at its time                                       decode, capture
//   lockstep: after a trigger, wait for the solution naming it (watchdog)
//   stop DUT (SIGTERM, SIGKILL) -> judge -> reports -> rename run folder into place
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "nav/bench/capture_file.hpp"
#include "nav/bench/scenario.hpp"
#include "nav/reports/run_record.hpp"

namespace nav::bench {

/// Exit codes of navbench (design.md).
enum ExitCode : int {
  kExitPass = 0,
  kExitFail = 1,
  kExitUsage = 2,
  kExitBench = 3,
  kExitDut = 4,
};

struct RunOptions {
  std::string scenario_path;
  std::optional<TimeMode> mode;  ///< overrides the scenario's mode
  std::optional<std::uint64_t> seed;  ///< overrides the scenario's seed
  std::string out_dir;           ///< run folder; default runs/<name>-<UTC time>
  bool quiet = false;            ///< no progress lines
  /// A timing audit: `navbench witness` in every DUT's place (realtime; no DUT checks).
  bool witness = false;
  /// Most bytes of each log a DUT fills (capture-rx*.log, dut*.log); 0: no limit.
  std::uint64_t log_limit = kDefaultLogLimit;
  std::string variant;      ///< replaces "{variant}" in the DUT commands (a campaign's variant)
  std::string dut_program;  ///< replaces the primary DUT's program; empty: the scenario's
};

/// Runs a scenario; prints the verdict; returns the exit code.
int run_scenario(const RunOptions& options);

/// Loads a scenario and checks what `run` checks before it opens any line: the schema, every
/// vehicle's path (TruthTrajectory::build) and every DUT program (found beside navbench or in
/// PATH). The error detail is the one line `run` prints before exiting with kExitUsage.
Result<Scenario> preflight_scenario(const std::string& path);
/// The same, with a campaign's DUT variant applied (apply_variant).
Result<Scenario> preflight_scenario(const std::string& path, const std::string& variant,
                                    const std::string& dut_program);

/// A DUT variant applied to a loaded scenario: "{variant}" in every vehicle's DUT command
/// becomes `variant`, and a non-empty `dut_program` replaces the primary DUT's program. An error
/// names the command when it holds "{variant}" and no variant is given.
Result<bool> apply_variant(Scenario& sc, const std::string& variant,
                           const std::string& dut_program);

/// The SHA-256 of every vehicle's DUT program (the primary's first) as a run would start it
/// now; "" for one that cannot be found or read.
std::vector<std::string> dut_sha256s(const Scenario& sc);

/// The files a DUT's arguments name (argv[1...]: each that is a regular file's path, such as
/// its configuration), with their SHA-256, in argument order. Device lines (character
/// devices), missing paths and anything else are not files here.
std::vector<reports::DutFile> dut_argument_files(const std::vector<std::string>& argv);
/// Per vehicle (the primary first), its DUT's command (argv, before its run fills it in).
std::vector<std::vector<std::string>> dut_commands(const Scenario& sc);
/// Per command of dut_commands(), the SHA-256 of the files its arguments name in the run of
/// `seed` (each "{seed}" in them replaced by it first, as the run does).
std::vector<std::vector<std::string>> dut_file_sha256s(
    const std::vector<std::vector<std::string>>& commands, std::uint64_t seed);
/// `arg` with every "{seed}" replaced by the run's seed in decimal.
std::string with_seed(std::string arg, std::uint64_t seed);

}  // namespace nav::bench
