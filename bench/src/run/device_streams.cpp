// SPDX-License-Identifier: MIT
#include "run/device_streams.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "devices/device_kind.hpp"
#include "nav/emulators/mounted_truth.hpp"
#include "run/can_faults.hpp"

namespace nav::bench::detail {
namespace {

/// Every CAN device's frames on the bus schedule of the scenario's bus.
void generate_can(const Scenario& sc, const std::vector<RunDevice>& devices,
                  DeviceStreams& out) {
  out.can_times.assign(devices.size(), {});
  if (!sc.can) return;
  std::vector<CanFrameRequest> requests;
  for (std::uint32_t d = 0; d < devices.size(); ++d) {
    const auto& dev = devices[d].spec;
    if (!dev.on_can()) continue;
    const auto seed = emulators::device_seed(sc.seed, dev.name);
    auto frames = device_kind(dev).frames(dev, *devices[d].truth, sc.duration, seed);
    for (const auto& f : frames) {
      emulators::WireMessage m;
      m.t_valid = f.t_valid;
      m.t_send = f.t_ready;
      out.can_times[d].push_back(std::move(m));
    }
    // Its frame faults, before the bus: lost, sent twice, a flood added.
    auto attempts =
        apply_can_device_faults(std::move(frames), dev.can_faults, sc.can->bitrate_bps,
                                emulators::device_seed(sc.seed, dev.name + "/faults"),
                                out.stream_faults[d]);
    for (auto& a : attempts) {
      requests.push_back(CanFrameRequest{a.f.t_ready, a.f.frame.id, a.f.frame.extended,
                                         a.f.frame.rtr,
                                         static_cast<std::uint8_t>(a.f.frame.length())});
      CanTxFrame tx{d, std::move(a.f), {}, {}};
      tx.corrupted = a.corrupted;
      out.can.push_back(std::move(tx));
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
  // What the DUT's controller receives of it: error reports, bus-off.
  apply_can_receiver(out.can, sc.can->faults, out.can_bus_faults);
}

}  // namespace

std::vector<RunDevice> run_devices(const Scenario& sc) {
  std::vector<RunDevice> out;
  for (const auto& d : sc.devices) out.push_back({d, d.name, 0, nullptr});
  for (std::uint32_t p = 0; p < sc.peers.size(); ++p) {
    for (const auto& d : sc.peers[p].devices) {
      RunDevice rd{d, d.name, p + 1, nullptr};
      rd.spec.name = sc.peers[p].vehicle_name + "." + d.name;
      out.push_back(std::move(rd));
    }
  }
  return out;
}

void mount_devices(std::vector<RunDevice>& devices, const VehicleTruths& truths) {
  for (auto& rd : devices) {
    const auto& vehicle = truths.at(rd.vehicle);
    rd.truth = rd.spec.mount.is_identity()
                   ? vehicle
                   : std::make_shared<const emulators::MountedTruth>(vehicle, rd.spec.mount);
  }
}

DeviceStreams generate_device_streams(const Scenario& sc, const std::vector<RunDevice>& devices) {
  DeviceStreams out;
  for (const auto& rd : devices) {
    const auto& dev = rd.spec;
    // Only a device with a stream of its own: a polled device's faults act on its answers
    // (its emulator applies them), a modem and a CAN device carry no stream.
    const DeviceKind& kind = device_kind(dev);
    auto stream = kind.stream ? kind.stream(dev, *rd.truth, sc.duration,
                                            emulators::device_seed(sc.seed, dev.name))
                              : std::vector<emulators::WireMessage>{};
    out.stream_faults.emplace_back();
    if (!dev.faults.empty() && kind.link == DeviceKind::Link::kStream) {
      stream = emulators::apply_faults(std::move(stream), dev.faults,
                                       emulators::device_seed(sc.seed, dev.name + "/faults"),
                                       &out.stream_faults.back());
    }
    out.serial.push_back(std::move(stream));
  }
  generate_can(sc, devices, out);
  return out;
}

const std::vector<emulators::MeasurementFault>& measurement_faults(const DeviceSpec& dev) {
  return measurement_faults_of(dev);
}

}  // namespace nav::bench::detail
