// SPDX-License-Identifier: MIT
#include "run/device_streams.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "nav/emulators/dvl_emulator.hpp"
#include "nav/emulators/ebimu_emulator.hpp"
#include "nav/emulators/usbl_emulator.hpp"
#include "nav/emulators/wheel_encoder_emulator.hpp"

namespace nav::bench::detail {
namespace {

/// A serial device's whole stream before faults, by its type.
std::vector<emulators::WireMessage> generate_stream(const DeviceSpec& dev,
                                                    const emulators::TruthTrajectory& truth,
                                                    Duration duration, std::uint64_t seed) {
  switch (dev.type) {
    case DeviceSpec::Type::kMicrostrainGx3:
      return emulators::generate_gx3(dev.gx3, truth, duration, seed);
    case DeviceSpec::Type::kNmeaGps: return emulators::generate_gps(dev.gps, truth, duration, seed);
    case DeviceSpec::Type::kDvl: return emulators::generate_dvl(dev.dvl, truth, duration, seed);
    case DeviceSpec::Type::kEbimu:
      return emulators::generate_ebimu(dev.ebimu, truth, duration, seed);
    case DeviceSpec::Type::kEvologicsUsbl:
      return emulators::generate_usbl(dev.usbl, truth, duration, seed);
    case DeviceSpec::Type::kKeller:
      return {};  // polled: its answers are made as the DUT's requests arrive
    case DeviceSpec::Type::kAcousticModem:
      return {};  // it writes only what the acoustic channel delivers
    case DeviceSpec::Type::kNmea2000:
    case DeviceSpec::Type::kWheelEncoders:
      return {};  // CAN frames: generate_can()
  }
  throw std::logic_error("unknown device type");
}

/// A CAN device's frames, by its type.
std::vector<emulators::CanWireFrame> generate_can_frames(const DeviceSpec& dev,
                                                         const emulators::TruthTrajectory& truth,
                                                         Duration duration, std::uint64_t seed) {
  return dev.type == DeviceSpec::Type::kNmea2000
             ? emulators::generate_nmea2000(dev.n2k, truth, duration, seed)
             : emulators::generate_wheel_encoders(*dev.wheels, *dev.wheel_codec, truth, duration,
                                                  seed);
}

/// Every CAN device's frames on the bus schedule of the scenario's bus.
void generate_can(const Scenario& sc, const std::vector<RunDevice>& devices,
                  const std::vector<emulators::TruthTrajectory>& truths, DeviceStreams& out) {
  out.can_times.assign(devices.size(), {});
  if (!sc.can) return;
  std::vector<CanFrameRequest> requests;
  for (std::uint32_t d = 0; d < devices.size(); ++d) {
    const auto& dev = devices[d].spec;
    if (!dev.on_can()) continue;
    const auto seed = emulators::device_seed(sc.seed, dev.name);
    for (auto& f : generate_can_frames(dev, truths[devices[d].vehicle], sc.duration, seed)) {
      emulators::WireMessage m;
      m.t_valid = f.t_valid;
      m.t_send = f.t_ready;
      out.can_times[d].push_back(std::move(m));
      requests.push_back(CanFrameRequest{f.t_ready, f.frame.id, f.frame.extended, f.frame.rtr,
                                         static_cast<std::uint8_t>(f.frame.length())});
      out.can.push_back(CanTxFrame{d, std::move(f), {}, {}});
    }
  }
  out.can_slots = schedule_can_bus(requests, sc.can->bitrate_bps);
  const double bit_ns = 1e9 / sc.can->bitrate_bps;
  const auto ifs = Duration(static_cast<Duration::rep>(std::llround(3.0 * bit_ns)));
  for (std::size_t i = 0; i < out.can.size(); ++i) {
    out.can[i].slot = out.can_slots[i];
    out.can[i].due = out.can_slots[i].end - ifs;
  }
  // Bus order: one frame at a time, so ordering by start orders by due time too.
  std::stable_sort(out.can.begin(), out.can.end(), [](const CanTxFrame& a, const CanTxFrame& b) {
    return a.slot.start < b.slot.start;
  });
}

}  // namespace

std::vector<RunDevice> run_devices(const Scenario& sc) {
  std::vector<RunDevice> out;
  for (const auto& d : sc.devices) out.push_back({d, d.name, 0});
  for (std::uint32_t p = 0; p < sc.peers.size(); ++p) {
    for (const auto& d : sc.peers[p].devices) {
      RunDevice rd{d, d.name, p + 1};
      rd.spec.name = sc.peers[p].vehicle_name + "." + d.name;
      out.push_back(std::move(rd));
    }
  }
  return out;
}

DeviceStreams generate_device_streams(const Scenario& sc, const std::vector<RunDevice>& devices,
                                      const std::vector<emulators::TruthTrajectory>& truths) {
  DeviceStreams out;
  for (const auto& rd : devices) {
    const auto& dev = rd.spec;
    auto stream = generate_stream(dev, truths[rd.vehicle], sc.duration,
                                  emulators::device_seed(sc.seed, dev.name));
    out.stream_faults.emplace_back();
    if (!dev.faults.empty() && dev.type != DeviceSpec::Type::kKeller) {
      stream = emulators::apply_faults(std::move(stream), dev.faults,
                                       emulators::device_seed(sc.seed, dev.name + "/faults"),
                                       &out.stream_faults.back());
    }
    out.serial.push_back(std::move(stream));
  }
  generate_can(sc, devices, truths, out);
  return out;
}

const std::vector<emulators::MeasurementFault>& measurement_faults(const DeviceSpec& dev) {
  switch (dev.type) {
    case DeviceSpec::Type::kMicrostrainGx3: return dev.gx3.measurement_faults;
    case DeviceSpec::Type::kNmeaGps: return dev.gps.measurement_faults;
    case DeviceSpec::Type::kDvl: return dev.dvl.measurement_faults;
    case DeviceSpec::Type::kEbimu: return dev.ebimu.measurement_faults;
    case DeviceSpec::Type::kEvologicsUsbl: return dev.usbl.measurement_faults;
    case DeviceSpec::Type::kKeller: return dev.keller.measurement_faults;
    case DeviceSpec::Type::kNmea2000: return dev.n2k.measurement_faults;
    case DeviceSpec::Type::kWheelEncoders:
    case DeviceSpec::Type::kAcousticModem: {
      static const std::vector<emulators::MeasurementFault> kNone;
      return kNone;
    }
  }
  throw std::logic_error("unknown device type");
}

}  // namespace nav::bench::detail
