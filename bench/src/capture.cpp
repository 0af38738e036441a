// SPDX-License-Identifier: MIT
#include "nav/bench/capture.hpp"

namespace nav::bench {

void write_capture_line(std::FILE* f, Duration since_t0, const std::string& port,
                        std::span<const std::uint8_t> bytes) {
  const long long ns = since_t0.count();
  const long long a = ns < 0 ? -ns : ns;
  std::fprintf(f, "(%s%lld.%09lld) %s ", ns < 0 ? "-" : "", a / 1'000'000'000,
               a % 1'000'000'000, port.c_str());
  for (const auto b : bytes) std::fprintf(f, "%02X", b);
  std::fputc('\n', f);
}

}  // namespace nav::bench
