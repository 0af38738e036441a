// SPDX-License-Identifier: MIT
// The report's web assets, embedded into the binary at build time (cmake/embed.cmake): uPlot
// from npm (node_modules/uplot, installed by scripts/setup) and the report's own script and
// style (reports/web/). Private to nav_reports.
#pragma once

#include <cstddef>
#include <string_view>

namespace nav::reports::assets {

extern const unsigned char uplot_js[];
extern const std::size_t uplot_js_size;
extern const unsigned char uplot_css[];
extern const std::size_t uplot_css_size;
extern const unsigned char report_js[];
extern const std::size_t report_js_size;
extern const unsigned char report_css[];
extern const std::size_t report_css_size;

inline std::string_view text(const unsigned char* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

}  // namespace nav::reports::assets
