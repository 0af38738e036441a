// SPDX-License-Identifier: MIT
// One self-contained HTML page: the text (readable without JavaScript), uPlot and the
// report's script and style inline, the plot specifications as JSON. Private to nav_reports.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace nav::reports::detail {

struct Page {
  std::string title;        ///< plain text (escaped here)
  std::string body;         ///< HTML, every text in it already escaped
  nlohmann::json plots;     ///< array of plot specifications (plot_spec.hpp)
};

/// The whole document. Its Content-Security-Policy allows only its own two scripts (by
/// hash) and inline style, and no connection, image or frame: the page cannot reach the
/// network, and a script that found its way into the text would not run.
std::string render_page(const Page& page);

/// "<figure>" placeholders of plot specs: the title, a box the script draws into, the note.
std::string figure_html(const nlohmann::json& spec);

}  // namespace nav::reports::detail
