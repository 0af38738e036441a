// SPDX-License-Identifier: MIT
// The campaign report's filter consistency section: the Monte-Carlo averaged NEES of each
// scenario whose DUT stated a covariance ($PNVBCOV) and NIS of each measurement it stated
// innovations of ($PNVBINN), with their 95 % bounds, as a table and a plot each. Private to
// nav_reports.
#pragma once

#include <cstddef>
#include <string>

#include <nlohmann/json.hpp>

namespace nav::reports::detail {

/// The section from campaign.json's "nees" and "nis"; empty when both are. Plot specs go to
/// specs, numbered from plot_no.
std::string consistency_section(const nlohmann::json& campaign, nlohmann::json& specs,
                                std::size_t& plot_no);

}  // namespace nav::reports::detail
