// SPDX-License-Identifier: MIT
// navbench command line.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <iterator>
#include <string>
#include <string_view>

#include <CLI/CLI.hpp>

#include "campaign/campaign_cli.hpp"
#include "cli_validators.hpp"

#include "nav/bench/decode.hpp"
#include "nav/bench/record.hpp"
#include "nav/bench/replay.hpp"
#include "nav/bench/runner.hpp"
#include "nav/bench/witness.hpp"
#include "nav/common/version.hpp"
#include "nav/reports/html_report.hpp"
#include "nav/reports/json_text.hpp"

namespace {

/// `navbench decode`: prints one JSON object per message; returns the exit code.
int decode_file(const std::string& protocol, const std::string& path, const std::string& port) {
  using namespace nav::bench;
  const ProtocolDecoder* d = find_decoder(protocol);
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    std::fprintf(stderr, "navbench: cannot open %s\n", path.c_str());
    return kExitUsage;
  }
  std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  nav::protocols::Bytes bytes(data.begin(), data.end());
  if (!port.empty()) {
    auto b = bytes_from_capture(data, port, path);
    if (!b) {
      std::fprintf(stderr, "navbench: %s\n", b.error().detail.c_str());
      return kExitUsage;
    }
    bytes = std::move(*b);
  }
  const auto counts = decode_stream(*d, bytes, [](const nlohmann::ordered_json& j) {
    std::cout << nav::reports::dump_json(j) << '\n';
  });
  std::cout.flush();
  std::fprintf(stderr, "navbench: %s: %zu messages, %zu errors in %zu bytes\n", path.c_str(),
               counts.messages, counts.errors, bytes.size());
  return std::cout ? kExitPass : kExitBench;
}

/// `navbench report`: returns the exit code.
int write_report_file(const std::string& dir, const std::string& out) {
  const auto written = nav::reports::write_report(dir, out);
  if (!written) {
    std::fprintf(stderr, "navbench: report: %s\n", written.error().detail.c_str());
    return written.error().code == nav::ErrorCode::kIo ? nav::bench::kExitBench
                                                       : nav::bench::kExitUsage;
  }
  std::printf("%s\n", written->c_str());
  return nav::bench::kExitPass;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace nav::bench;
  CLI::App app{
      "navbench: hardware-in-the-loop bench for underwater navigation estimators.\n"
      "Emulated devices stream their real protocols over serial lines (ptys) to the estimator\n"
      "under test (DUT); its solutions are judged against truth.\n\n"
      "Exit codes: 0 pass, 1 a check failed, 2 usage or scenario error, 3 bench error\n"
      "(including bench-late), 4 DUT crashed or hung."};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("navbench ") + nav::navbench_version());

  RunOptions run;
  std::string mode;
  std::uint64_t seed = 0;
  auto* cmd = app.add_subcommand("run", "Run one scenario and write its run folder");
  cmd->add_option("scenario", run.scenario_path, "Scenario YAML file (see docs/scenario.md)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--mode", mode,
                  "Override the scenario's time mode: realtime (wall clock, deadlines judged) "
                  "or lockstep (virtual time, one barrier per trigger, bit-reproducible)")
      ->check(CLI::IsMember({"realtime", "lockstep"}));
  using cli::kUnsignedInteger;
  const CLI::Validator& not_empty = cli::kNotEmpty;
  cmd->add_option("-o,--out", run.out_dir,
                  "Run folder to create (default runs/<scenario>-<UTC time>); must not exist")
      ->check(not_empty);
  auto* seed_opt = cmd->add_option(
      "--seed", seed,
      "Override the scenario's seed (unsigned 64-bit, 0 to 18446744073709551615): every "
      "device's random engine is seeded from it and the device name; summary.json and the "
      "reports give the seed used")
      ->transform(kUnsignedInteger);
  cmd->add_option("--variant", run.variant,
                  "A DUT variant's name: replaces {variant} in the DUT commands (a campaign's "
                  "--variant)")
      ->check(not_empty);
  cmd->add_option("--dut-program", run.dut_program,
                  "Run this program as the DUT instead of the scenario's (its arguments stay)")
      ->check(CLI::ExistingFile);
  cmd->add_flag("-q,--quiet", run.quiet, "No progress lines on long runs");
  cmd->add_flag("--witness", run.witness,
                "Timing audit: `navbench witness` takes every DUT's place (realtime only; no "
                "solutions, so no DUT checks); the report gives the arrival lateness the witness "
                "saw next to the bench's write lateness, and the byte pacing of each line");
  std::uint64_t log_limit_mib = kDefaultLogLimit >> 20;
  cmd->add_option("--log-limit", log_limit_mib,
                  "Most MiB of each log a DUT fills (capture-rx.log, dut.log; default " +
                      std::to_string(kDefaultLogLimit >> 20) +
                      ", 0: no limit); what is past it is counted, not kept")
      ->check(CLI::Range(std::uint64_t{0}, std::uint64_t{1} << 30));

  CampaignCli campaign(app);

  std::string protocol, file, port;
  std::vector<std::string> names;
  std::string described = "Wire protocol:";
  for (const auto& d : protocol_decoders()) {
    names.push_back(d.name);
    described += "\n  " + d.name + ": " + d.description;
  }
  auto* dec = app.add_subcommand(
      "decode", "Decode a byte stream: one JSON object per message, fields named with their "
                "unit; bad bytes reported with their offset");
  dec->add_option("--protocol", protocol, described)->required()->check(CLI::IsMember(names));
  dec->add_option("file", file, "Raw byte stream, a navbench capture with --port, or (nmea2000) a candump log")
      ->required()
      ->check(CLI::ExistingFile);
  dec->add_option("--port", port,
                  "Read FILE as a navbench capture (capture-tx.log / capture-rx.log) and decode "
                  "the bytes of this port (a device name, or 'output')");

  ReplayOptions replay;
  bool replay_dut = false;
  auto* rep = app.add_subcommand(
      "replay", "Play a navbench capture (e.g. a run's capture-tx.log) onto serial lines, or a "
                "candump log (candump -l) onto CAN interfaces, with its recorded timing, "
                "optionally to a DUT whose output is captured");
  rep->add_option("capture", replay.capture_path,
                  "Capture file: (<sec>.<nsec>) <port> <hex> lines, or a candump log: "
                  "(<sec>.<usec>) <iface> <id>#<data> lines")
      ->required()
      ->check(CLI::ExistingFile);
  rep->add_option("--port", replay.ports,
                  "NAME=PATH[@BAUD]: play port NAME onto this serial line (default baud 115200); "
                  "ports not mapped get a pty, printed as 'NAME: /dev/pts/N'")
      ->allow_extra_args(false);
  rep->add_option("--can", replay.can_maps,
                  "LOGNAME=IFACE: play the candump log's interface LOGNAME onto the CAN "
                  "interface IFACE (default: the interface of the same name)")
      ->allow_extra_args(false);
  rep->add_option("--format", replay.format,
                  "auto (default: a candump log when its first line is one), navbench or candump")
      ->check(CLI::IsMember({"auto", "navbench", "candump"}));
  rep->add_option("--speed", replay.speed,
                  "Time scale from 0.001 to 1000: 2 plays twice as fast (default 1)")
      ->check(CLI::Range(0.001, 1000.0));
  rep->add_option("--startup", replay.startup_s,
                  "Seconds to wait after printing the ptys (and starting the DUT) before "
                  "playing (default 1)")
      ->check(CLI::NonNegativeNumber);
  rep->add_flag("--dut", replay_dut,
                "Start a DUT: --dut -- ARGV... ({port:NAME} and {port:output} are replaced by "
                "the line paths, {can:LOGNAME} by the CAN interface); it is stopped with SIGTERM "
                "at the end");
  rep->add_option("--out-capture", replay.out_capture,
                  "With --dut: capture of the DUT's output (default replay-rx.log)");
  rep->add_option("--dut-log", replay.dut_log,
                  "With --dut: the DUT's stdout and stderr (default replay-dut.log)");
  rep->add_option("dut_argv", replay.dut_argv, "The DUT's argv, after --dut --");

  RecordOptions record;
  auto* rec = app.add_subcommand(
      "record", "Record serial ports (or pty slaves) into a navbench capture, timestamped on "
                "CLOCK_MONOTONIC from the start, or CAN interfaces (--can) into a candump -l log "
                "with the kernel's receive times; ends after --duration or on SIGINT/SIGTERM");
  rec->add_option("ports", record.ports, "NAME=PATH@BAUD, one per port");
  rec->add_option("--can", record.can_interfaces,
                  "CAN interface to record (repeatable) into a candump -l log: "
                  "(<epoch sec>.<usec>) <iface> <id>#<data>, as canplayer replays it")
      ->allow_extra_args(false);
  rec->add_option("--duration", record.duration_s, "Seconds to record (default: until a signal)")
      ->check(CLI::NonNegativeNumber);
  rec->add_option("-o,--out", record.out_path,
                  "Capture (or candump log) to write (written as FILE.partial, renamed at the end)")
      ->required();

  WitnessOptions witness;
  std::int64_t witness_t0 = 0;
  auto* wit = app.add_subcommand(
      "witness",
      "Timing witness: open the DUT's side of serial lines (pty slaves, or real ports wired "
      "back by loopback cable) and write every read into a navbench capture, stamped on "
      "CLOCK_MONOTONIC as it arrives; `navbench run --witness` starts one in the DUT's place");
  wit->add_option("ports", witness.ports, "NAME=PATH@BAUD, one per line")->required();
  wit->add_option("-o,--out", witness.out_path,
                  "Capture to write (written as FILE.partial, renamed at the end)")
      ->required();
  wit->add_option("--duration", witness.duration_s,
                  "Seconds to witness (default: until SIGINT/SIGTERM or every line hung up)")
      ->check(CLI::NonNegativeNumber);
  auto* witness_t0_opt = wit->add_option(
      "--t0-ns", witness_t0,
      "Stamp times relative to this CLOCK_MONOTONIC instant [ns] (default: the witness's "
      "start); `navbench run --witness` gives its scenario time 0");
  wit->add_flag("-q,--quiet", witness.quiet, "No summary line");
  wit->footer(
      "Runs at SCHED_FIFO priority 30 with its memory locked when permitted (as root), so that\n"
      "a read is stamped as soon as its bytes arrive.\n\n"
      "Exit codes: 0 done, 2 bad arguments, 3 a line cannot be opened or the capture cannot\n"
      "be written.");

  std::string report_dir, report_out;
  auto* rpt = app.add_subcommand(
      "report", "Write the HTML report of a run folder (report.html) or of a campaign folder "
                "(campaign.html) again, from the folder's files alone");
  rpt->add_option("dir", report_dir,
                  "A run folder (what `navbench run` writes) or a campaign folder (what "
                  "`navbench campaign` writes)")
      ->required();
  rpt->add_option("-o,--out", report_out,
                  "HTML file to write (default DIR/report.html, or DIR/campaign.html for a "
                  "campaign); written to a temporary file beside it and renamed");
  rpt->footer(
      "The page is self-contained: it opens from file:// with no network, its plots are drawn\n"
      "by the uPlot embedded in it, and it prints on A4. A run made by an older navbench gets\n"
      "a report too; what its folder lacks is marked \"not recorded\".\n\n"
      "Exit codes: 0 written; 2 DIR is not a run or campaign folder, or one of its files is\n"
      "damaged (nothing is written); 3 the report cannot be written.");

  // An unknown word where the subcommand goes is named (CLI11 would say only that a
  // subcommand is required).
  if (argc > 1 && argv[1][0] != '-') {
    std::string known;
    bool found = false;
    for (const auto* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
      known += (known.empty() ? "" : ", ") + sub->get_name();
      found = found || sub->get_name() == argv[1];
    }
    if (!found) {
      std::fprintf(stderr,
                   "navbench: unknown subcommand '%s' (one of: %s; see navbench --help)\n",
                   argv[1], known.c_str());
      return kExitUsage;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);
    return rc == 0 ? 0 : kExitUsage;
  }
  if (*dec) return decode_file(protocol, file, port);
  if (*rep) {
    if (replay_dut != !replay.dut_argv.empty()) {
      std::fprintf(stderr, "navbench: replay: give the DUT as --dut -- ARGV...\n");
      return kExitUsage;
    }
    return replay_capture(replay);
  }
  if (*rec) return record_ports(record);
  if (*wit) {
    if (witness_t0_opt->count() > 0) witness.t0_ns = witness_t0;
    return run_witness(witness);
  }
  if (*rpt) return write_report_file(report_dir, report_out);
  if (const auto rc = campaign.run(argc, argv)) return *rc;
  if (seed_opt->count() > 0) run.seed = seed;
  run.log_limit = log_limit_mib << 20;
  if (!mode.empty()) run.mode = mode == "lockstep" ? TimeMode::kLockstep : TimeMode::kRealtime;
  return run_scenario(run);
}
