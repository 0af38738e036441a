// SPDX-License-Identifier: MIT
// The three parts of the lateness benchmark (lateness_benchmark.cpp has the command line):
//
//   pairs:  the floors (floor.hpp, write_floor.hpp) and `navbench run SCENARIO` alternately,
//           ratios pair by pair
//   serial: one serial trace played by `navbench replay` and by a plain sleep-paced writer,
//           each measured by `navbench witness` on the far side of its ptys
//   can:    one CAN trace played by canplayer and by `navbench replay` on vcan0, each
//           measured by a candump listener's kernel timestamps
#pragma once

#include <filesystem>
#include <string>

namespace nav::benchmarks {

struct Common {
  std::string navbench;            ///< the navbench program
  std::filesystem::path out;       ///< the benchmark's folder (created)
  int pairs = 3;
};

int run_pairs(const Common& c, const std::string& scenario, double floor_seconds, bool witness);
int run_serial(const Common& c, const std::string& scenario);
int run_can(const Common& c, const std::string& scenario);

}  // namespace nav::benchmarks
