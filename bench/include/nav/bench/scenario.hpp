// SPDX-License-Identifier: MIT
// A scenario as loaded and validated from YAML (docs/scenario.md has the schema).
#pragma once

#include <any>
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "nav/common/geodesy.hpp"
#include "nav/common/result.hpp"
#include "nav/common/time.hpp"
#include "nav/emulators/acoustic_modem.hpp"
#include "nav/emulators/device.hpp"
#include "nav/emulators/faults.hpp"
#include "nav/emulators/hand_guided_truth.hpp"
#include "nav/emulators/sea_state_truth.hpp"
#include "nav/emulators/wall_truth.hpp"
#include "nav/emulators/mounted_truth.hpp"
#include "nav/emulators/truth.hpp"

namespace nav::bench {

enum class TimeMode { kRealtime, kLockstep };

/// A fault of a CAN device's frames (its `faults`), or of the DUT's CAN controller
/// (vehicle.can.faults: bus_off). docs/scenario.md, "CAN faults".
struct CanFaultSpec {
  enum class Kind {
    kFrameLoss,  ///< frames never reach the bus (the device's transmit queue lost them)
    kCorrupted,  ///< frames destroyed on the wire: an error reported, the frame sent again
    kBabbling,   ///< the device floods the bus with frames of one dominant identifier
    kBusOff      ///< the DUT's controller is bus-off: it receives nothing until it restarts
  };
  Kind kind = Kind::kFrameLoss;
  Duration from{}, to{};     ///< window [from, to), scenario time
  double probability = 0.0;  ///< frame_loss, corrupted: share of the device's frames hit
  std::uint32_t id = 0;      ///< babbling: its 11-bit identifier (0: the most dominant)
};

/// The scenario name of a CAN fault kind ("frame_loss", ...).
const char* can_fault_name(CanFaultSpec::Kind k);

/// One emulated device on its own serial line, or on the vehicle's CAN bus (vehicle.can).
/// What a device of each `type` is, reads and sends is its kind's business
/// (bench/src/devices/, one file per kind); the spec holds the kind's settings opaquely.
struct DeviceSpec {
  std::string name;     ///< unique in its vehicle; used in "{port:NAME}" and captures
  std::string type;     ///< the scenario `type`, naming its kind ("microstrain-gx3-25", ...)
  std::string port = "pty";  ///< "pty" or a device path such as /dev/ttyUSB0
  int baud = 115200;         ///< line rate [bit/s]; 8N1 = 10 bits per byte
  /// Its `rate` (or its kind's default) [Hz]; 0 for a device that sends only when asked (the
  /// Keller) or when the channel delivers (a modem). For the scenario's size bound.
  double rate_hz = 0.0;
  /// Where it sits on its vehicle (`mount`): it measures in its own axes at its own place
  /// (emulators::MountedTruth). Identity by default: the vehicle's reference point and axes.
  emulators::Mount mount;
  /// The kind's settings, as its reader left them: emulators::Gx3Config for a GX3,
  /// emulators::GpsConfig for a GPS, ... (each kind's file says which).
  std::any settings;
  /// The settings as the kind's type C (std::bad_any_cast if the device is of another kind).
  template <class C>
  C& config() { return std::any_cast<C&>(settings); }
  template <class C>
  const C& config() const { return std::any_cast<const C&>(settings); }
  /// A device on the vehicle's CAN bus: no serial line (port and baud unused). Its kind says
  /// (bench/src/devices/).
  bool on_can() const;
  /// Faults applied to the encoded stream (for a Keller: to its answers), in file order
  /// (windows inside [0, duration)). Measurement faults live in the kind's settings.
  std::vector<emulators::FaultSpec> faults;
  /// A CAN device's frame faults, in file order.
  std::vector<CanFaultSpec> can_faults;
  /// A CAN device's bus (`bus`: its interface): an index into Scenario::can_buses.
  std::uint32_t can_bus = 0;
};

/// A `restart` fault of the DUT (dut.faults): the bench kills its process group with SIGKILL
/// at scenario time `off` (power lost) and starts the same command again at `on`.
struct DutRestart {
  Duration off{};
  Duration on{};
};

/// The DUT and how to talk to it.
struct DutSpec {
  /// argv; "{port:NAME}" is replaced by NAME's port path when the run starts.
  /// "{scenario_dir}" is already replaced here (at load time) by Scenario::dir.
  std::vector<std::string> command;
  std::string output_port = "pty";   ///< where the DUT writes ("pty" or a device path)
  int output_baud = 115200;          ///< [bit/s]
  std::string trigger;               ///< device whose messages the DUT answers
  Duration startup{std::chrono::milliseconds(500)};  ///< wait before scenario time 0
  Duration watchdog{std::chrono::seconds(2)};        ///< no answer this long = hung
  std::vector<DutRestart> restarts;  ///< in time order, windows apart (dut.faults)
  /// `navbench run --witness`: navbench's timing witness stands in the DUT's place. It answers
  /// no trigger, so nothing waits for answers and only a crash is watched; `command` is
  /// unused (the run starts the witness on every serial line of the vehicle).
  bool witness = false;
};

/// One check of the DUT's output against truth.
struct CheckSpec {
  enum class Kind { kHorizontalError, kVerticalError, kAttitudeError, kEndpointError,
                    kDeadline, kDutAlive, kRestartRecovery, kConsistency, kHorizontalErrorAt,
                    kHorizontalErrorRms };
  Kind kind = Kind::kHorizontalError;
  double max = 0.0;  ///< limit [m], [rad]; deadline: latency [s]; restart_recovery: time [s]
  double max_per_distance = 0.0;  ///< envelope grows with distance travelled [m/m] (errors)
  Duration after{0};           ///< judged only from this scenario time on
  std::string input;           ///< deadline: the trigger device
  int max_misses = 0;          ///< deadline: tolerated misses
  std::string name;            ///< display name ("horizontal_error", ...)
  std::string req{};           ///< requirement id it proves (`req`, e.g. "NAV-REQ-012"), or empty
  std::string title{};         ///< the requirement's wording (`title`), or empty
  std::string of{};            ///< consistency: "position", "attitude" or "innovation"
  /// consistency of innovation: the DUT's measurement name ($PNVBINN); empty: every one.
  std::string source{};
  /// The vehicle it judges: empty for the primary (a check without `vehicle`), a vehicle's
  /// name, or "all" (kAllVehicles): one result per vehicle.
  std::string vehicle{};
  Duration at{0};  ///< horizontal_error_at: the scenario time it is judged at
};

/// CheckSpec::vehicle of a check that judges every vehicle.
inline constexpr const char* kAllVehicles = "all";

/// The checks that judge vehicle v (0: the primary, 1 + i: peers[i]) as its results are named:
/// a peer's as "<vehicle>.<name>" (like its devices), the primary's as written; a deadline of
/// `all` on each vehicle's own trigger. In the order of the file.
std::vector<CheckSpec> checks_of_vehicle(const struct Scenario& s, std::size_t v);

/// The scenario name of a check kind ("horizontal_error", ...).
const char* check_kind_name(CheckSpec::Kind k);

/// A statement over the runs of this scenario in a campaign (top-level `campaign: {checks:
/// [...]}`), decided by `navbench campaign` without assuming a distribution
/// (campaign_stats.hpp); a single run does not judge it.
struct CampaignCheckSpec {
  enum class Kind {
    kQuantile,  ///< the quantile of a run check's value is <= limit, with confidence
    kPassRate   ///< the rate of runs that passed (a run check, or every check) is >= min_rate
  };
  Kind kind = Kind::kQuantile;
  std::string name;        ///< display name, unique among the campaign checks
  std::string of;          ///< the run check judged; empty (pass_rate): the run's verdict
  double quantile = 0.0;   ///< kQuantile: q in (0, 1)
  double limit = 0.0;      ///< kQuantile: in the run check's unit (m or deg, as its summary)
  std::string unit;        ///< kQuantile: "m" or "deg"
  double min_rate = 0.0;   ///< kPassRate: in (0, 1)
  double confidence = 0.0; ///< in (0, 1)
  std::string req{};       ///< requirement id, or empty
  std::string title{};     ///< the requirement's wording, or empty
  bool operator==(const CampaignCheckSpec&) const = default;
};

/// The scenario name of a campaign check kind ("quantile", "pass_rate").
const char* campaign_check_kind_name(CampaignCheckSpec::Kind k);

/// A further vehicle (top-level `peers:`): its own path, devices and DUT. Its devices are
/// named here as in its file section; in captures and reports they are "<vehicle_name>.<name>".
struct PeerSpec {
  std::string vehicle_name;
  std::optional<double> seabed_depth_m;
  emulators::TrajectorySpec trajectory;
  std::optional<emulators::HandGuidedSpec> hand_guided;  ///< as Scenario::hand_guided
  std::string hand_guided_location;                      ///< as Scenario::hand_guided_location
  std::optional<emulators::WallSpec> wall;               ///< as Scenario::wall
  std::optional<emulators::SeaSpec> sea;                 ///< as Scenario::sea
  std::string sea_location;                              ///< as Scenario::sea_location
  std::vector<DeviceSpec> devices;
  DutSpec dut;
  std::vector<std::string> segment_locations;  ///< as Scenario::segment_locations
};

/// One of the primary vehicle's CAN buses (vehicle.can: one map, or a list of them).
struct CanBusSpec {
  std::string interface;        ///< SocketCAN interface, e.g. vcan0 or can0
  double bitrate_bps = 250000;  ///< nominal bit rate [bit/s]
  std::vector<CanFaultSpec> faults;  ///< of the DUT's controller (bus_off), in time order
};

/// Top-level `labels`: label name -> value, in file order (summary.json, campaign tables).
using Labels = std::vector<std::pair<std::string, std::string>>;

/// Names a label may not have: the other columns of a campaign's comparison table.
inline constexpr std::array<std::string_view, 15> kReservedLabelNames{
    "scenario",
    "runs",
    "passed",
    "endpoint_error_mean_m",
    "endpoint_error_std_m",
    "endpoint_error_min_m",
    "endpoint_error_max_m",
    "endpoint_horizontal_mean_m",
    "endpoint_horizontal_std_m",
    "endpoint_vertical_mean_m",
    "endpoint_vertical_std_m",
    "mean_position_error_mean_m",
    "mean_position_error_std_m",
    "mean_attitude_error_mean_deg",
    "mean_attitude_error_std_deg"};

struct Scenario {
  std::string file;          ///< path it was loaded from
  std::string dir;           ///< absolute path of the folder holding `file` ("{scenario_dir}")
  std::string name;
  std::string description;
  Labels labels;             ///< top-level `labels`, in file order (may be empty)
  std::uint64_t seed = 0;
  Duration duration{};
  TimeMode mode = TimeMode::kRealtime;
  geodesy::Geodetic datum;
  std::string vehicle_name = "vehicle";
  std::optional<double> seabed_depth_m;  ///< vehicle.seabed: flat seabed depth [m] (DVLs)
  /// vehicle.can: the buses of its CAN devices, in file order (empty: none).
  std::vector<CanBusSpec> can_buses;
  emulators::TrajectorySpec trajectory;
  /// vehicle.hand_guided: the vehicle is a rig moved by hand along its path (the hand-guided
  /// truth kind, hand_guided_truth.hpp); nullopt: it follows the path exactly.
  std::optional<emulators::HandGuidedSpec> hand_guided;
  std::string hand_guided_location;  ///< "file:line:col" of vehicle.hand_guided (errors)
  /// vehicle.wall: the vehicle drives on a plane (the wall truth kind, wall_truth.hpp); its
  /// path is drawn on the plane, `start` is the path's origin on it (NED) and its heading the
  /// direction on the wall from x′ towards y′; nullopt: a swimming or rolling vehicle.
  std::optional<emulators::WallSpec> wall;
  /// vehicle.sea: the vehicle is a craft floating in waves, held on its path by its thrusters
  /// (the sea-state truth kind, sea_state_truth.hpp); nullopt: no waves.
  std::optional<emulators::SeaSpec> sea;
  std::string sea_location;  ///< "file:line:col" of vehicle.sea (errors)
  std::vector<DeviceSpec> devices;
  DutSpec dut;
  std::vector<CheckSpec> checks;
  /// Statements over a campaign's runs of this scenario (top-level `campaign.checks`).
  std::vector<CampaignCheckSpec> campaign_checks;
  /// Further vehicles, each with its own DUT (checks stay on the primary vehicle above).
  std::vector<PeerSpec> peers;
  /// The acoustic channel that joins every acoustic-modem of every vehicle (top-level
  /// `acoustic:`; defaults of AcousticModemConfig when absent).
  emulators::AcousticModemConfig acoustic;
  double truth_rate_hz = 50.0;           ///< truth.tum sample rate [Hz]
  Duration lateness_budget_p99{std::chrono::milliseconds(5)};  ///< bench-late above this
  /// bench.spin: realtime writes sleep to this much before their deadline, then spin to it.
  Duration spin{0};
  /// "file:line:col" of each path segment, parallel to trajectory.segments, so that an error
  /// of TruthTrajectory::build naming "segment i" (0-based) can point into the file.
  std::vector<std::string> segment_locations;
};

/// arg with every "{scenario_dir}" replaced by dir (the placeholder of DUT arguments).
std::string expand_scenario_dir(std::string arg, const std::string& dir);

/// Loads and validates a scenario. On failure the error detail is one line
/// "file:line:col: what was expected".
Result<Scenario> load_scenario(const std::string& path);

}  // namespace nav::bench
