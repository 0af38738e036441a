// SPDX-License-Identifier: MIT
// Tables of the campaign report from campaign.json: every vehicle of the multi-vehicle cells,
// and every error check's value per cell. Private to nav_reports.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace nav::reports::detail {

/// Every vehicle of the multi-vehicle cells (campaign.json `vehicles`); empty without any.
std::string vehicles_table(const nlohmann::json& campaign);

/// Every error check's value per cell (campaign.json `check_values`); empty without any.
std::string check_values_table(const nlohmann::json& campaign);

}  // namespace nav::reports::detail
