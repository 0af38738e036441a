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

/// The frames of bus b's devices on its schedule, in bus order, then what the DUT's controller
/// receives of them (error reports, bus-off); appended to out.can.
void generate_bus(const Scenario& sc, const std::vector<RunDevice>& devices, std::uint32_t b,
                  DeviceStreams& out) {
  const CanBusSpec& bus = sc.can_buses[b];
  std::vector<CanFrameRequest> requests;
  std::vector<CanTxFrame> frames_of_bus;
  for (std::uint32_t d = 0; d < devices.size(); ++d) {
    const auto& dev = devices[d].spec;
    if (!dev.on_can() || dev.can_bus != b) continue;
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
        apply_can_device_faults(std::move(frames), dev.can_faults, bus.bitrate_bps,
                                emulators::device_seed(sc.seed, dev.name + "/faults"),
                                out.stream_faults[d]);
    for (auto& a : attempts) {
      requests.push_back(CanFrameRequest{a.f.t_ready, a.f.frame.id, a.f.frame.extended,
                                         a.f.frame.rtr,
                                         static_cast<std::uint8_t>(a.f.frame.length())});
      CanTxFrame tx{d, std::move(a.f), {}, {}};
      tx.corrupted = a.corrupted;
      frames_of_bus.push_back(std::move(tx));
    }
  }
  out.can_slots[b] = schedule_can_bus(requests, bus.bitrate_bps);
  const double bit_ns = 1e9 / bus.bitrate_bps;
  const auto ifs = Duration(static_cast<Duration::rep>(std::llround(3.0 * bit_ns)));
  for (std::size_t i = 0; i < frames_of_bus.size(); ++i) {
    frames_of_bus[i].slot = out.can_slots[b][i];
    frames_of_bus[i].due = out.can_slots[b][i].end - ifs;
  }
  // Bus order: one frame at a time, so ordering by start orders by due time too.
  std::stable_sort(frames_of_bus.begin(), frames_of_bus.end(),
                   [](const CanTxFrame& x, const CanTxFrame& y) { return x.slot.start < y.slot.start; });
  // What the DUT's controller receives of it: error reports, bus-off.
  apply_can_receiver(frames_of_bus, bus.faults, out.can_bus_faults[b]);
  for (auto& tx : frames_of_bus) {
    tx.bus = b;
    out.can.push_back(std::move(tx));
  }
}

/// Every CAN device's frames, each on its bus's schedule; the buses merged in due order.
void generate_can(const Scenario& sc, const std::vector<RunDevice>& devices,
                  DeviceStreams& out) {
  out.can_times.assign(devices.size(), {});
  out.can_slots.assign(sc.can_buses.size(), {});
  out.can_bus_faults.assign(sc.can_buses.size(), {});
  for (std::uint32_t b = 0; b < sc.can_buses.size(); ++b) generate_bus(sc, devices, b, out);
  // One timeline for the sender: each bus keeps its order (stable), the buses interleave by
  // due time.
  if (sc.can_buses.size() > 1) {
    std::stable_sort(out.can.begin(), out.can.end(),
                     [](const CanTxFrame& x, const CanTxFrame& y) { return x.due < y.due; });
  }
}

}  // namespace

std::vector<RunDevice> run_devices(const Scenario& sc) {
  std::vector<RunDevice> out;
  for (const auto& d : sc.devices) out.push_back({d, d.name, 0, nullptr, nullptr, nullptr});
  for (std::uint32_t p = 0; p < sc.peers.size(); ++p) {
    for (const auto& d : sc.peers[p].devices) {
      RunDevice rd{d, d.name, p + 1, nullptr, nullptr, nullptr};
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
    if (const auto observed = device_kind(rd.spec).observed_vehicle) {
      rd.body = vehicle;
      rd.observed = truths.at(observed(rd.spec));
    }
  }
}

DeviceStreams generate_device_streams(const Scenario& sc, const std::vector<RunDevice>& devices) {
  DeviceStreams out;
  for (const auto& rd : devices) {
    const auto& dev = rd.spec;
    // Only a device with a stream of its own: a polled device's faults act on its answers
    // (its emulator applies them), a modem and a CAN device carry no stream.
    const DeviceKind& kind = device_kind(dev);
    const auto seed = emulators::device_seed(sc.seed, dev.name);
    auto stream = kind.observer_stream
                      ? kind.observer_stream(dev, *rd.truth, *rd.body, *rd.observed, sc.duration,
                                             seed)
                  : kind.stream ? kind.stream(dev, *rd.truth, sc.duration, seed)
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
