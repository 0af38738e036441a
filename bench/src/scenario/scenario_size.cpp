// SPDX-License-Identifier: MIT
// How much a scenario may ask for. A run generates every device's messages and the truth
// table before scenario time 0 and holds them to the end; the DUT's solutions and the
// lateness rows go to files as the run goes and are read back at its end, to be judged and
// aligned to truth (about 0.4 kB per message at that peak, measured on the smoke scenario at
// 10 h in lockstep: 1.6 GB for 3.6 M messages and 1.8 M truth samples). So the scenario's size is
// bounded when it loads, with the figures that make it up, rather than by bad_alloc
// part-way through.
#include <cstdio>
#include <string>

#include "scenario/scenario_sections.hpp"

namespace nav::bench::detail {
namespace {

constexpr double kMaxDurationS = 24.0 * 3600.0;
/// Messages plus truth samples a run may hold: about 2 GB.
constexpr double kMaxPlanned = 5e6;

/// "ahrs 100 Hz, gps 1 Hz" for the devices with a rate.
void name_rates(const std::vector<DeviceSpec>& devices, const std::string& prefix,
                std::string& out, double& hz) {
  for (const auto& d : devices) {
    if (d.rate_hz <= 0.0) continue;
    char buf[64];
    std::snprintf(buf, sizeof buf, "%g Hz", d.rate_hz);
    out += (out.empty() ? "" : ", ") + prefix + d.name + " " + buf;
    hz += d.rate_hz;
  }
}

}  // namespace

void check_size(const Field& duration, const Scenario& s) {
  const double seconds = to_seconds(s.duration);
  if (seconds > kMaxDurationS) {
    duration.fail("expected a duration of at most 24 h (86400 s), got " +
                  quote_value(duration.node().Scalar()));
  }
  std::string rates;
  double hz = 0.0;
  name_rates(s.devices, "", rates, hz);
  for (const auto& p : s.peers) name_rates(p.devices, p.vehicle_name + ".", rates, hz);
  const double vehicles = 1.0 + static_cast<double>(s.peers.size());
  hz += s.truth_rate_hz * vehicles;
  char truth[96];
  std::snprintf(truth, sizeof truth, "%struth %g Hz%s", rates.empty() ? "" : ", ",
                s.truth_rate_hz, vehicles > 1.0 ? " per vehicle" : "");
  rates += truth;
  double planned = hz * seconds;
  // A babbling CAN device's flood: one 8-byte frame per frame time for its window.
  if (!s.can_buses.empty()) {
    for (const auto& d : s.devices) {
      for (const auto& f : d.can_faults) {
        if (f.kind != CanFaultSpec::Kind::kBabbling) continue;
        const double frames =
            to_seconds(f.to - f.from) * s.can_buses[d.can_bus].bitrate_bps / 135.0;
        planned += frames;
        char buf[96];
        std::snprintf(buf, sizeof buf, ", %s babbling %.3g frames", d.name.c_str(), frames);
        rates += buf;
      }
    }
  }
  if (planned > kMaxPlanned) {
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "%g s of %g Hz in all is %.3g messages and truth samples, more than the %.0f "
                  "a run holds in memory: shorten the duration to at most %.0f s or lower the "
                  "rates",
                  seconds, hz, planned, kMaxPlanned, seconds * kMaxPlanned / planned);
    duration.fail(std::string(buf) + " (" + rates + ")");
  }
}

}  // namespace nav::bench::detail
