// SPDX-License-Identifier: MIT
#include "ahrs_period.hpp"

#include <algorithm>
#include <cmath>

#include "nav/common/ensure.hpp"
#include "nav/protocols/microstrain_gx3.hpp"

namespace nav::dut {

AhrsPeriod::AhrsPeriod(double period_s)
    : period_ticks_(static_cast<std::uint32_t>(
          std::max(1.0, std::round(std::clamp(period_s, 0.0, 3600.0) *
                                   protocols::gx3::kTicksPerSecond)))) {
  NAV_ENSURE(std::isfinite(period_s) && period_s > 0.0 && period_s <= 3600.0,
             "AHRS period must be in (0, 3600] s");
}

}  // namespace nav::dut
