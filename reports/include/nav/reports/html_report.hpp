// SPDX-License-Identifier: MIT
// The acceptance reports: one self-contained HTML page per run (report.html) and per
// campaign (campaign.html), made from the files of the folder alone, so that any run folder,
// copied from a lab machine or made by an older navbench, can be reported again.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "nav/common/result.hpp"
#include "nav/reports/run_folder.hpp"

namespace nav::reports {

/// The run report of a run folder as read.
std::string run_report_html(const RunFolder& f);

/// A campaign folder: campaign.json and the summary.json of each of its runs.
struct CampaignFolder {
  std::string dir;
  nlohmann::json campaign;               ///< campaign.json
  std::vector<nlohmann::json> summaries; ///< per campaign.json "runs" item; null when missing
};

/// Reads dir/campaign.json and its runs' summaries (a run without one is listed as such).
Result<CampaignFolder> read_campaign_folder(const std::string& dir);

/// The campaign report.
std::string campaign_report_html(const CampaignFolder& c);

/// Which report a folder gets: a campaign folder has campaign.json, a run folder summary.json.
enum class FolderKind { kRun, kCampaign, kNeither };
FolderKind folder_kind(const std::string& dir);

/// Writes the report of the run or campaign folder dir to out_path (empty: dir/report.html
/// or dir/campaign.html) through a temporary file beside it and a rename, so that it is
/// never seen half-written; nothing is written when dir cannot be read. Returns the path.
Result<std::string> write_report(const std::string& dir, const std::string& out_path = {});

}  // namespace nav::reports
