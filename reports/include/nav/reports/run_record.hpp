// SPDX-License-Identifier: MIT
// Everything a finished run knows, as plain data: the report writers' only input.
#pragma once

#include <cstdint>
#include <array>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "nav/common/frames.hpp"
#include "nav/common/time.hpp"

namespace nav::reports {

/// Percentiles of a set of durations [s].
struct Stats {
  std::size_t count = 0;
  double p50_s = 0.0, p99_s = 0.0, max_s = 0.0;
};

/// Nearest-rank percentiles of values [s]; count 0 when empty.
Stats summarize(std::vector<double> values_s);

/// One judged check.
struct CheckResult {
  std::string name;       ///< e.g. "horizontal_error"
  bool judged = true;     ///< false: not applicable in this run (e.g. deadline in lockstep)
  bool passed = false;
  double value = 0.0;     ///< the figure judged (worst error, misses, ...)
  double limit = 0.0;     ///< its limit (an envelope's: its value at distance 0)
  std::string unit;       ///< unit of value and limit ("m", "deg", "misses")
  std::string detail;     ///< one line for the verdict screen
  std::string kind{};     ///< the scenario's kind ("horizontal_error", "deadline", ...)
  std::string req{};      ///< requirement id the check proves (scenario `req`), may be empty
  std::string title{};    ///< the requirement's wording (scenario `title`), may be empty
  /// An error envelope's growth with the distance travelled: limit(t) = limit +
  /// per_distance × distance(t) [unit/m].
  double per_distance = 0.0;
  double after_s = 0.0;   ///< judged from this scenario time on [s]
  double max_latency_s = 0.0;  ///< a deadline's latency limit [s] (other kinds: 0)
  /// Scenario time of the worst sample (largest margin over the envelope, latest solution
  /// of an endpoint, slowest answer of a deadline) [s]; none when nothing was judged.
  std::optional<double> worst_t_s{};
  /// The vehicle whose DUT it judged (the scenario's vehicle name; a peer's results are also
  /// named "<vehicle>.<name>").
  std::string vehicle{};
};

/// One aligned estimate (only solutions with a valid position).
struct AlignedSample {
  double t_s = 0.0;          ///< trigger time of validity (scenario time) [s]
  Vec3 truth_p_n, est_p_n;   ///< NED [m]
  Quat truth_q_nb, est_q_nb; ///< attitude body -> NED
  double distance_m = 0.0;   ///< horizontal distance travelled at t [m]
  /// The covariance the DUT stated with the solution ($PNVBCOV), when it did: position, NED
  /// [m²]; attitude, of the NED rotation vector of R_true R_estᵀ [rad²].
  std::optional<Mat3> cov_p_n, cov_att_n;
  /// Their NEES (eᵀ P⁻¹ e), when stated; NaN for a covariance that is not positive definite.
  std::optional<double> nees_p, nees_att;
};

/// One measurement update the DUT stated with a solution ($PNVBINN), judged without truth.
struct InnovationSample {
  double t_s = 0.0;     ///< time of validity of the trigger its solution answers [s]
  std::string source;   ///< the DUT's name of the measurement
  int dof = 0;          ///< m, the measurement's dimension
  double nis = 0.0;     ///< νᵀ S⁻¹ ν; NaN for an S that is not positive definite
};

/// One trigger and the DUT's answer to it.
struct LatencyRow {
  std::uint64_t tag = 0;          ///< trigger tag the DUT echoes
  double t_valid_s = 0.0;         ///< scenario time of validity [s]
  double wire_end_s = 0.0;        ///< time its last byte was written, since T0 [s]
  std::optional<double> rx_s;     ///< time the answer was received, since T0 [s]
  bool missed = false;            ///< late or unanswered
};

/// Bench lateness of one emitted message.
struct LatenessRow {
  std::string device;
  double scheduled_s = 0.0;  ///< scheduled wire time of the first byte, since T0 [s]
  double actual_s = 0.0;     ///< when it was written, since T0 [s]
  /// `run --witness`: when the witness read its first byte, since T0 [s]; none when the
  /// witness did not see it intact.
  std::optional<double> arrived_s{};
};

/// `run --witness`: one serial line as the timing witness saw it (its scheduled messages; a
/// line that carries answers or deliveries is not audited).
struct WitnessRow {
  std::string device;
  int baud = 0;
  std::size_t messages = 0;         ///< messages the bench wrote
  std::size_t messages_seen = 0;    ///< of them, seen whole and intact by the witness
  std::uint64_t bytes_sent = 0, bytes_seen = 0;
  /// Bytes from the start of the line the witness saw exactly as written; bytes_sent when
  /// everything arrived intact and in order.
  std::uint64_t bytes_matched = 0;
  Stats write_lateness;             ///< the bench's own: first byte written − scheduled
  Stats arrival_lateness;           ///< the witness's: first byte read − scheduled
  /// Median over messages of the time between the reads of its first and last bytes ÷ the
  /// byte time of the bytes between them (10 bits per byte at the baud); none when no
  /// message arrived in more than one read.
  std::optional<double> pacing_median{};
  std::size_t pacing_messages = 0;  ///< messages the median is over
};

/// A truth sample for truth.tum.
struct TruthRow {
  double t_s = 0.0;
  Vec3 p_n;
  Quat q_nb;
  double distance_m = 0.0;  ///< horizontal distance travelled by t [m]
};

/// What a device put on its line in one second of scenario time [k, k + 1) s.
struct DeviceSecond {
  std::uint32_t messages = 0;      ///< messages (CAN: frames) written
  std::uint64_t bytes = 0;         ///< bytes written (CAN: data bytes)
  std::uint64_t bytes_dropped = 0; ///< bytes the line did not take (CAN: of refused frames)
};

struct DeviceRow {
  std::string name, type, port;  ///< port: the path the DUT opened
  int baud = 0;
  std::uint64_t seed = 0;  ///< the device's own engine seed, derived from the scenario seed
  std::size_t messages = 0, bytes = 0, bytes_dropped = 0;
  /// Messages not written because the device was not streaming (a GX3 not yet told to).
  std::size_t suppressed = 0;
  /// A device on the vehicle's CAN bus: port is the interface, baud the bus bit rate,
  /// messages the frames sent, bytes their data bytes, bytes_dropped those of frames the
  /// interface refused (frames_dropped of them).
  bool can = false;
  std::size_t frames_dropped = 0;
  /// Second by second from scenario time 0 (device-rates.csv); empty when not recorded.
  std::vector<DeviceSecond> per_second{};
};

/// One CAN bus of the run (scenario vehicle.can).
struct CanBusRow {
  std::string interface;         ///< e.g. "vcan0"
  double bitrate_bps = 0.0;      ///< [bit/s]
  std::size_t frames_sent = 0;   ///< written to the interface
  std::size_t frames_dropped = 0;  ///< refused by the interface (transmit queue full)
  /// CAN faults: error frames written as the DUT's controller reports (a corrupted frame, a
  /// bus-off, a restart), and frames it missed while bus-off.
  std::size_t error_reports = 0, frames_withheld = 0;
  std::uint64_t frame_bits = 0;  ///< sum of every scheduled frame's bit length, stuffing worst
                                 ///< case and interframe space included [bit]
  double bus_load = 0.0;         ///< busy fraction of [0, duration) (can_bus_load) [-]
  Stats queueing_delay;          ///< slot start - ready time, per frame [s]
  Stats write_lateness;          ///< realtime: actual write - scheduled time (count 0 in lockstep)
};

/// What one scheduled fault of a device did (emulators::FaultRecord plus the device).
struct FaultRow {
  std::string device;            ///< device name
  std::string kind;              ///< "off", "checksum", ... (as in the scenario)
  double start_s = 0.0, end_s = 0.0;  ///< window [s], scenario time
  std::size_t messages_affected = 0;  ///< messages removed or altered
};

/// A file a DUT's command names (an argument that is a regular file's path: its
/// configuration), and its hex SHA-256.
struct DutFile {
  std::string path;
  std::string sha256;
  bool operator==(const DutFile&) const = default;
};

/// A further vehicle of the run (scenario `peers:`) and how its DUT did. Checks are judged on
/// the primary vehicle only.
struct PeerRow {
  std::string name;                      ///< vehicle name
  std::vector<std::string> dut_command;  ///< argv as started
  std::string dut_executable{};          ///< the program started (resolved path)
  std::string dut_sha256{};              ///< hex SHA-256 of that file; empty if unreadable
  std::vector<DutFile> dut_files{};      ///< the files its arguments name, in their order
  std::string dut_status;                ///< as RunRecord::dut_status
  std::size_t triggers_sent = 0, answers = 0;  ///< answers: solutions received
};

/// One directed acoustic link (emulators::LinkStats, modems named "<vehicle>.<device>" for
/// peers, by their device name on the primary vehicle).
struct ModemLinkRow {
  std::string from, to;
  std::uint64_t packets_sent = 0, packets_delivered = 0, packets_lost = 0,
                packets_out_of_range = 0, bytes_delivered = 0;
  double min_propagation_s = 0.0, max_propagation_s = 0.0;  ///< of delivered packets [s]
};

/// One vehicle's truth and its DUT's solutions aligned to it (the primary's drive the checks).
struct VehicleTrack {
  std::string name;
  std::vector<TruthRow> truth;          ///< at the scenario's truth rate
  std::vector<AlignedSample> aligned;   ///< solutions with a valid position, by time
  std::vector<InnovationSample> innovations;  ///< stated innovations, by time
  std::size_t triggers_sent = 0, answers = 0;
  std::string dut_status;
};

/// A piece of the DUT's output the bench could not read as a sentence (the first few).
struct MalformedOutput {
  double rx_s = 0.0;  ///< when it was received, since T0 (as in the receive capture) [s]
  /// Its bytes, nav::escape_bytes(); of a longer piece, the first two thirds and the last third
  /// of kMalformedTextBytes, with "..." between and its length after.
  std::string text;
  std::string why;    ///< the parser's reason (checksum, field count, number, length, ...)
};
/// Bytes of a malformed piece of output kept in MalformedOutput::text.
inline constexpr std::size_t kMalformedTextBytes = 48;
/// Malformed pieces of output a run keeps, the first ones.
inline constexpr std::size_t kMalformedExamples = 5;

/// A restart of the DUT (a `restart` fault of the scenario's dut.faults) and how long the
/// DUT took to give a valid solution again. Times are scenario times [s]: in realtime when a
/// solution arrived, in lockstep the time of validity of the trigger it answered.
struct RestartRow {
  double off_s = 0.0;  ///< its process group killed (SIGKILL), as a power cut
  double on_s = 0.0;   ///< its command started again
  std::string ended;   ///< how the killed process ended ("killed by signal 9 (Killed)")
  bool started_again = true;  ///< false: the run ended (a signal) before on_s
  std::optional<double> first_solution_s;  ///< its first solution after on_s, if any
  std::optional<double> first_valid_s;     ///< its first solution with a valid position
  std::optional<double> recovery_s;        ///< first_valid_s − on_s
  /// Triggers sent between its last solution before the power-off and its first after the
  /// restart: nobody could answer them, and a deadline check does not count them.
  std::size_t triggers_in_gap = 0;
};

/// A log a DUT filled past navbench's limit (`navbench run --log-limit`).
struct LogCut {
  std::string file;              ///< "capture-rx.log", "dut.log", ...
  std::uint64_t limit_bytes = 0;
  std::uint64_t cut_bytes = 0;   ///< what the DUT wrote past the limit, not kept [bytes]
};

/// With fewer messages than this a p99 is one machine hiccup: the median is judged instead.
inline constexpr std::size_t kMinMessagesForP99 = 100;

/// Whether the bench was late: its lateness p99 over the budget or, with fewer than
/// kMinMessagesForP99 messages, its median. False without messages (lockstep).
bool bench_late(const Stats& lateness, double budget_p99_s);

/// "gps checksum 10.0–15.0 s, 4 messages": one fault in one line (verdict screen, junit).
std::string fault_text(const FaultRow& f);

struct RunRecord {
  std::string scenario_name, scenario_file, mode, run_dir;
  std::string scenario_description;
  std::string scenario_sha256;      ///< hex SHA-256 of the scenario file as run
  std::string navbench_version;     ///< nav::navbench_version() of the bench that ran it
  std::string host, kernel;         ///< uname: node name; system, release, version, machine
  /// The scenario's labels (name, value), in file order (summary.json "labels").
  std::vector<std::pair<std::string, std::string>> labels;
  std::uint64_t seed = 0;
  double duration_s = 0.0;
  /// The scenario time a signal stopped the run at (verdict INTERRUPTED); none otherwise.
  std::optional<double> stopped_at_s;
  std::string started_utc;          ///< ISO 8601 wall time of the start
  std::string verdict;              ///< PASS, FAIL, BENCH-LATE, DUT crashed, DUT hung
  int exit_code = 0;
  std::vector<std::string> dut_command;
  std::string dut_executable;       ///< the program started (resolved path)
  std::string dut_sha256;           ///< hex SHA-256 of that file; empty if unreadable
  std::vector<DutFile> dut_files;   ///< the files its arguments name, in their order
  std::string dut_status;           ///< e.g. "alive", "exited with status 1 at t=0.3 s"
  std::size_t triggers_sent = 0, answers = 0, unmatched_answers = 0, malformed_output = 0;
  std::vector<MalformedOutput> malformed_examples;  ///< the first malformed pieces of output
  std::vector<LogCut> logs_cut;                     ///< logs the DUTs filled past the limit
  std::vector<RestartRow> restarts;                 ///< the primary DUT's restart faults
  /// The plane the primary vehicle drives on (vehicle.wall), for the report's view of the
  /// track on it; nullopt for a swimming or rolling vehicle.
  struct Wall {
    double slope_deg = 90.0;    ///< α
    double azimuth_deg = 0.0;   ///< β, direction of x′
    std::array<double, 3> origin_ned_m{};  ///< where on the wall its x′, y′ start (NED)
  };
  std::optional<Wall> wall;
  std::vector<CheckResult> checks;
  Stats bench_lateness;             ///< realtime only (count 0 in lockstep)
  double lateness_budget_p99_s = 0.0;
  /// Messages later than the budget; and whether the bench was judged late (its p99 over
  /// the budget, or with fewer than kMinMessagesForP99 messages its median: bench_late()).
  std::size_t lateness_over_budget = 0;
  bool bench_late = false;
  /// What the reader must know beside the verdict, one line each ("the bench was late, but
  /// ..."); the verdict screen, summary.json `notes` and the report's banner give them.
  std::vector<std::string> notes;
  Stats dut_latency;                ///< realtime: judged latency; lockstep: compute time
  std::vector<DeviceRow> devices;
  std::vector<FaultRow> faults;     ///< every fault of every device, device then file order
  /// Every vehicle, the primary first (its track is the one the checks judged).
  std::vector<VehicleTrack> vehicles;
  std::vector<LatencyRow> latency;
  std::vector<LatenessRow> lateness;
  std::vector<PeerRow> peers;             ///< empty for a single-vehicle scenario
  std::vector<ModemLinkRow> modem_links;  ///< every directed link between two modems
  std::vector<CanBusRow> can_buses;       ///< empty without vehicle.can
  /// `run --witness`: a timing audit (the witness in every DUT's place), its lines.
  bool witness_run = false;
  std::vector<WitnessRow> witness;
  double wall_time_s = 0.0;         ///< how long the run took
  /// CPU time navbench itself used from the start of its play to its end (user + system, all
  /// its threads, not its DUTs) [s]; bench_cpu_s / wall_time_s is its share of one core.
  double bench_cpu_s = 0.0;
};

/// `run --witness`: the arrival lateness of every message the witness saw intact, all lines.
Stats witness_arrival_lateness(const RunRecord& r);

/// Writes summary.json, junit.xml, truth.tum and estimate.tum (the primary vehicle),
/// truth-<vehicle>.tum and estimate-<vehicle>.tum (every vehicle), timeseries.csv,
/// latency.csv, lateness.csv and device-rates.csv into dir. Throws std::runtime_error naming
/// the file on an I/O failure. Strings that are not valid UTF-8 are written with U+FFFD.
void write_reports(const RunRecord& r, const std::string& dir);

/// The files of one vehicle's track in a run folder.
std::string truth_file_name(const std::string& vehicle);     ///< "truth-<vehicle>.tum"
std::string estimate_file_name(const std::string& vehicle);  ///< "estimate-<vehicle>.tum"

/// The one-screen verdict printed at the end of a run.
std::string verdict_text(const RunRecord& r);

}  // namespace nav::reports
