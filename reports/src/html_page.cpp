// SPDX-License-Identifier: MIT
#include "html_page.hpp"

#include "assets.hpp"
#include "json_get.hpp"
#include "nav/common/version.hpp"
#include "nav/reports/sha256.hpp"
#include "nav/reports/json_text.hpp"
#include "nav/reports/text.hpp"

namespace nav::reports::detail {

std::string figure_html(const nlohmann::json& spec) {
  const std::string id = html_escape(get_string(spec, "id", "plot"));
  std::string h = "<figure class=\"plot\" id=\"" + id + "\"><figcaption>" +
                  html_escape(get_string(spec, "title", "")) + "</figcaption>";
  h += "<div class=\"chart\" data-plot=\"" + id + "\"><p class=\"needs-js\">This plot needs "
       "JavaScript.</p></div>";
  if (const auto note = get_string(spec, "note")) h += "<p class=\"note\">" + html_escape(*note) + "</p>";
  return h + "</figure>\n";
}

std::string render_page(const Page& page) {
  const std::string_view uplot = assets::text(assets::uplot_js, assets::uplot_js_size);
  const std::string_view script = assets::text(assets::report_js, assets::report_js_size);
  std::string h;
  h.reserve(page.body.size() + uplot.size() + script.size() + 4096);
  h += "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  h += "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n";
  h += "<meta http-equiv=\"Content-Security-Policy\" content=\"default-src 'none'; "
       "style-src 'unsafe-inline'; img-src data:; script-src 'sha256-" +
       sha256_base64(uplot) + "' 'sha256-" + sha256_base64(script) + "'\">\n";
  h += "<meta name=\"generator\" content=\"navbench " + html_escape(navbench_version()) + "\">\n";
  h += "<title>" + html_escape(page.title) + "</title>\n<style>";
  h += assets::text(assets::uplot_css, assets::uplot_css_size);
  h += "</style>\n<style>";
  h += assets::text(assets::report_css, assets::report_css_size);
  h += "</style>\n</head>\n<body>\n";
  h += page.body;
  h += "\n<script>";
  h += uplot;
  h += "</script>\n<script type=\"application/json\" id=\"nav-plots\">";
  h += json_for_script(page.plots);
  h += "</script>\n<script>";
  h += script;
  h += "</script>\n</body>\n</html>\n";
  return h;
}

}  // namespace nav::reports::detail
