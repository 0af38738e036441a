// SPDX-License-Identifier: MIT
// navbench command line.
#include <cstdio>
#include <string>

#include <CLI/CLI.hpp>

#include "nav/bench/runner.hpp"

int main(int argc, char** argv) {
  using namespace nav::bench;
  CLI::App app{
      "navbench: hardware-in-the-loop bench for underwater navigation estimators.\n"
      "Emulated devices stream their real protocols over serial lines (ptys) to the estimator\n"
      "under test (DUT); its solutions are judged against truth.\n\n"
      "Exit codes: 0 pass, 1 a check failed, 2 usage or scenario error, 3 bench error\n"
      "(including bench-late), 4 DUT crashed or hung."};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("navbench ") + NAV_VERSION);

  RunOptions run;
  std::string mode;
  auto* cmd = app.add_subcommand("run", "Run one scenario and write its run folder");
  cmd->add_option("scenario", run.scenario_path, "Scenario YAML file (see docs/scenario.md)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--mode", mode,
                  "Override the scenario's time mode: realtime (wall clock, deadlines judged) "
                  "or lockstep (virtual time, one barrier per trigger, bit-reproducible)")
      ->check(CLI::IsMember({"realtime", "lockstep"}));
  cmd->add_option("-o,--out", run.out_dir,
                  "Run folder to create (default runs/<scenario>-<UTC time>); must not exist");
  cmd->add_flag("-q,--quiet", run.quiet, "No progress lines on long runs");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);
    return rc == 0 ? 0 : kExitUsage;
  }
  if (!mode.empty()) run.mode = mode == "lockstep" ? TimeMode::kLockstep : TimeMode::kRealtime;
  return run_scenario(run);
}
