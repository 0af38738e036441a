// SPDX-License-Identifier: MIT
// The device registry, in the manner of gpsd's driver table: one DeviceKind per scenario
// device `type`, each in its own file of this folder, listed once in device_kinds.cpp. A kind
// says what its scenario keys are (and their defaults), how to read them, what it puts on the
// wire and which faults it takes; the bench asks the kind instead of switching on the type.
// docs/adding-a-device.md shows how a kind is added. Private to nav_bench.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "nav/bench/scenario.hpp"
#include "nav/emulators/measurement_faults.hpp"
#include "nav/emulators/nmea2000_emulator.hpp"

namespace nav::bench::detail {

// scenario/yaml_reader.hpp (not included here: the registry's users need only these names).
class Field;
class MapReader;

/// What a kind's reader sees of the device's scenario map.
struct DeviceReadContext {
  const MapReader& m;       ///< the device map, its keys checked against the kind's
  const Field& type_field;  ///< where to point at the device as a whole
  const Scenario& s;        ///< the scenario read so far (datum, vehicle, duration, CAN bus)
  double rate_hz = 0.0;     ///< `rate`, or the kind's default
  Duration latency{0};      ///< `latency`, or the kind's default
};

/// How a DUT names a message of the kind when the device is `dut.trigger`: the
/// `trigger_tag` it echoes in `$PNVBSOL` (docs/dut-contract.md §4). A kind without a rule
/// cannot be the trigger. The bench matches a solution to the latest trigger it sent with
/// that tag, so a tag that wraps (`wraps_after` messages) names its message only while
/// the DUT answers within that many messages of the device.
struct TriggerTagRule {
  /// What the DUT echoes, in words (docs and errors).
  const char* rule = nullptr;
  /// Distinct tags before they repeat, counted in messages of one stream [-]; 0: they do
  /// not repeat within any run.
  std::uint64_t wraps_after = 0;
  /// Serial kinds: the tag of message m, or none when it is no trigger (a fault destroyed
  /// it). lines_before: the LF (0x0A) bytes the device's line carried before m.
  std::optional<std::uint64_t> (*of_message)(const DeviceSpec& d, const emulators::WireMessage& m,
                                             std::uint64_t lines_before) = nullptr;
  /// CAN kinds: the tag of a frame of the device, or none for a frame that is no trigger.
  std::optional<std::uint64_t> (*of_frame)(const DeviceSpec& d,
                                           const protocols::can::Frame& f) = nullptr;
};

struct DeviceKind {
  /// How a device of the kind reaches the DUT.
  enum class Link {
    kStream,   ///< a serial line carrying its own stream
    kPolled,   ///< a serial line carrying answers to the DUT's requests (the Keller)
    kChannel,  ///< a serial line carrying what the acoustic channel delivers (a modem)
    kCan,      ///< frames on the vehicle's CAN bus
  };
  const char* name = nullptr;  ///< the scenario `type` (DeviceSpec::type)
  Link link = Link::kStream;
  int baud = 115200;     ///< default line rate [bit/s] (serial kinds)
  double rate_hz = 0.0;  ///< default `rate` [Hz]; 0 when the kind has no rate
  Duration latency{0};   ///< default `latency`
  /// Every scenario key a device of the kind may have, the common ones included.
  std::vector<std::string> keys{};
  /// Reads the kind's keys into d (its name, port, baud and faults are read by the caller);
  /// returns the worst-case bytes of one message on its line, for the line budget (0: it
  /// sends nothing on a schedule of its own).
  std::size_t (*read)(const DeviceReadContext& c, DeviceSpec& d) = nullptr;
  /// kStream: its messages over [0, duration), before stream faults.
  std::vector<emulators::WireMessage> (*stream)(const DeviceSpec& d,
                                                const emulators::Truth& truth,
                                                Duration duration, std::uint64_t seed) = nullptr;
  /// kStream, a device observing another vehicle (an iUSBL): its messages over
  /// [0, duration) from its own (mounted) truth, its vehicle's body truth and the observed
  /// vehicle's; used instead of `stream`.
  std::vector<emulators::WireMessage> (*observer_stream)(const DeviceSpec& d,
                                                         const emulators::Truth& device,
                                                         const emulators::Truth& body,
                                                         const emulators::Truth& observed,
                                                         Duration duration,
                                                         std::uint64_t seed) = nullptr;
  /// A device observing another vehicle: finds it among the scenario's vehicles (`vehicles`,
  /// primary first; `own` is the device's vehicle) and keeps its index, or fails at the
  /// device's key naming it. Called once every vehicle is read.
  void (*resolve_observed)(DeviceSpec& d, const std::vector<std::string>& vehicles,
                           std::size_t own) = nullptr;
  /// The index (in the order above) of the vehicle a resolved observing device observes.
  std::size_t (*observed_vehicle)(const DeviceSpec& d) = nullptr;
  /// kCan: its frames over [0, duration).
  std::vector<emulators::CanWireFrame> (*frames)(const DeviceSpec& d,
                                                 const emulators::Truth& truth,
                                                 Duration duration, std::uint64_t seed) = nullptr;
  /// Its measurement faults in d's config; null for a kind that takes none.
  std::vector<emulators::MeasurementFault>* (*measurement_faults)(DeviceSpec& d) = nullptr;
  /// The measurement fault kinds it takes besides `wrong` (gps_jump, ...).
  std::vector<emulators::MeasurementFault::Kind> special_faults{};
  /// The quantities a `wrong` fault may act on.
  std::vector<emulators::Quantity> wrong_quantities{};
  /// It streams only once the DUT sent it the set-continuous command (the GX3 handshake).
  bool commanded = false;
  /// How a DUT names its messages as triggers; no rule: it cannot be `dut.trigger`.
  TriggerTagRule trigger{};
  /// Its messages carry a tag a DUT can name in its solutions: it may be the trigger.
  bool may_trigger() const { return trigger.of_message != nullptr || trigger.of_frame != nullptr; }
};

/// The `stream` of a kind whose settings are C and whose emulator is Generate(C, truth,
/// duration, seed).
template <class C, auto Generate>
std::vector<emulators::WireMessage> stream_of(const DeviceSpec& d, const emulators::Truth& truth,
                                              Duration duration, std::uint64_t seed) {
  return Generate(d.config<C>(), truth, duration, seed);
}

/// The `measurement_faults` of a kind whose settings C hold them.
template <class C>
std::vector<emulators::MeasurementFault>* measurement_faults_in(DeviceSpec& d) {
  return &d.config<C>().measurement_faults;
}

/// Every kind, in the order the scenario documentation lists them.
const std::vector<const DeviceKind*>& device_kinds();
/// The kind of a device (of a spec made by the scenario reader: its type is a kind's name).
const DeviceKind& device_kind(const DeviceSpec& d);
/// The kind named by a scenario `type`, or null.
const DeviceKind* find_device_kind(std::string_view name);

/// The measurement faults of a device (an empty list for a kind that takes none).
const std::vector<emulators::MeasurementFault>& measurement_faults_of(const DeviceSpec& d);

// One function per kind, each in its own file (gx3.cpp, gps.cpp, ...).
const DeviceKind& gx3_kind();
const DeviceKind& gps_kind();
const DeviceKind& dvl_kind();
const DeviceKind& ebimu_kind();
const DeviceKind& usbl_kind();
const DeviceKind& iusbl_kind();
const DeviceKind& keller_kind();
const DeviceKind& acoustic_modem_kind();
const DeviceKind& nmea2000_kind();
const DeviceKind& wheel_encoders_kind();
const DeviceKind& beacon_ins_kind();

}  // namespace nav::bench::detail
