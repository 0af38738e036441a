// SPDX-License-Identifier: MIT
// The HTML run report made from a run folder's files: content, escaping, embedded data,
// size of a long run, the page's script policy, and a peer vehicle's error plots.
#include <gtest/gtest.h>

#include <chrono>
#include <regex>

#include "nav/reports/html_report.hpp"
#include "nav/reports/sha256.hpp"
#include "report_fixture.hpp"

namespace nav::reports {
namespace {

using namespace testing;

std::string report_of(const RunRecord& r, const std::string& name) {
  const auto dir = fresh_dir(name);
  write_reports(r, dir.string());
  const auto written = write_report(dir.string());
  EXPECT_TRUE(written.has_value()) << (written ? "" : written.error().detail);
  return slurp(dir / "report.html");
}

TEST(RunReport, ShowsVerdictIdentityChecksAndPlots) {
  const std::string html = report_of(synthetic_run(60, 20), "content");
  EXPECT_NE(html.find("<div class=\"verdict\">FAIL</div>"), std::string::npos);
  // The failed check's line in the banner, with its requirement.
  EXPECT_NE(html.find("NAV-REQ-012</span>: max 1.2 m over the limit"), std::string::npos);
  EXPECT_NE(html.find("horizontal error within 1 m after alignment"), std::string::npos);
  for (const char* text : {"testhost", "Linux 6.1.0 x86_64", "/usr/bin/navd", "2026-12-01T00:00:00Z",
                           "navd --ahrs /dev/pts/3", "scenarios/synthetic.yaml"}) {
    EXPECT_NE(html.find(text), std::string::npos) << text;
  }
  EXPECT_NE(html.find(std::string(64, 'a')), std::string::npos);  // scenario sha256
  EXPECT_NE(html.find(std::string(64, 'b')), std::string::npos);  // DUT sha256
  EXPECT_EQ(html.find("class=\"missing\""), std::string::npos);  // nothing "not recorded"
  // Each check links to its plot; the worst time is shown.
  EXPECT_NE(html.find("<a href=\"#plot-check-0\">plot</a>"), std::string::npos);
  EXPECT_NE(html.find("<a href=\"#plot-latency-time\">plot</a>"), std::string::npos);
  EXPECT_NE(html.find("<a href=\"#plot-track\">plot</a>"), std::string::npos);
  EXPECT_NE(html.find("t = 59.00 s"), std::string::npos);

  const auto plots = embedded_plots(html);
  ASSERT_TRUE(plots.is_array());
  for (const char* id : {"plot-track", "plot-depth", "plot-check-0", "plot-vertical_error",
                         "plot-attitude_error", "plot-latency-hist", "plot-latency-time",
                         "plot-lateness-hist", "plot-lateness-time", "plot-device-0",
                         "plot-device-1"}) {
    const auto* p = plot_by_id(plots, id);
    ASSERT_NE(p, nullptr) << id;
    EXPECT_FALSE((*p)["data"].empty()) << id;
    // Every plot has its figure in the page.
    EXPECT_NE(html.find(std::string("data-plot=\"") + id + "\""), std::string::npos) << id;
  }
  // The horizontal error plot: the envelope band and its limit from t = after on.
  const auto& h = *plot_by_id(plots, "plot-check-0");
  EXPECT_EQ(h["series"][1]["label"], "limit");
  EXPECT_EQ(h["series"][1]["fill_to"], 0);  // the allowed envelope, shaded
  const auto& t = h["data"][0];
  const auto& limit = h["data"][2];
  for (std::size_t k = 0; k < t.size(); ++k) {
    if (t[k].get<double>() < 5.0) EXPECT_TRUE(limit[k].is_null());
    else EXPECT_NEAR(limit[k].get<double>(), 1.0 + 0.001 * 20 * 0.05 * t[k].get<double>(), 1e-5);
  }
  // The gps fault window shades the time plots and the gps timeline.
  EXPECT_EQ((*plot_by_id(plots, "plot-check-0"))["windows"][0]["x0"], 2.0);
  EXPECT_EQ((*plot_by_id(plots, "plot-device-1"))["windows"].size(), 1u);
  EXPECT_TRUE((*plot_by_id(plots, "plot-device-0"))["windows"].empty());
}

TEST(RunReport, EmbeddedNumbersRoundTrip) {
  const RunRecord r = synthetic_run(30, 10);
  const auto plots = embedded_plots(report_of(r, "numbers"));
  // The primary's truth, east against north: the file's values to 7 significant digits.
  const auto& track = *plot_by_id(plots, "plot-track");
  const auto& truth = track["data"][0];
  const auto& rows = r.vehicles[0].truth;
  ASSERT_EQ(truth[0].size(), rows.size());  // few samples: nothing thinned
  for (std::size_t k = 0; k < rows.size(); ++k) {
    EXPECT_NEAR(truth[0][k].get<double>(), rows[k].p_n.y(), 1e-6 * std::abs(rows[k].p_n.y()) + 1e-9);
    EXPECT_NEAR(truth[1][k].get<double>(), rows[k].p_n.x(), 1e-6 * std::abs(rows[k].p_n.x()) + 1e-9);
  }
  // A second dump of what was parsed reads the same (numbers survive the trip).
  EXPECT_EQ(nlohmann::json::parse(plots.dump()), plots);
  // Unanswered triggers are nulls in the latency column, not numbers.
  const auto& lat = *plot_by_id(plots, "plot-latency-time");
  EXPECT_TRUE(std::any_of(lat["data"][1].begin(), lat["data"][1].end(),
                          [](const nlohmann::json& v) { return v.is_null(); }));
}

TEST(RunReport, AVehicleOnAWallIsDrawnOnTheWall) {
  // A wall facing South (x′ East, y′ down): the track is along the wall against down it,
  // from the wall's origin, down drawn downwards.
  RunRecord r = synthetic_run(30, 10);
  r.wall = RunRecord::Wall{90.0, 90.0, {1.0, 2.0, 3.0}};
  const auto plots = embedded_plots(report_of(r, "wall"));
  const auto& track = *plot_by_id(plots, "plot-track");
  EXPECT_NE(track["title"].get<std::string>().find("Track on the wall"), std::string::npos);
  EXPECT_EQ(track["y"]["invert"], true);
  const auto& truth = track["data"][0];
  const auto& rows = r.vehicles[0].truth;
  ASSERT_EQ(truth[0].size(), rows.size());
  for (std::size_t k = 0; k < rows.size(); ++k) {
    EXPECT_NEAR(truth[0][k].get<double>(), rows[k].p_n.y() - 2.0, 1e-5) << k;  // x′ = east
    EXPECT_NEAR(truth[1][k].get<double>(), rows[k].p_n.z() - 3.0, 1e-5) << k;  // y′ = down
  }
  // Without a wall: north against east, as ever.
  const auto flat = embedded_plots(report_of(synthetic_run(30, 10), "flat"));
  EXPECT_NE((*plot_by_id(flat, "plot-track"))["title"].get<std::string>().find("north against east"),
            std::string::npos);
}

TEST(RunReport, HostileTextIsEscapedEverywhere) {
  RunRecord r = synthetic_run(10, 10);
  r.scenario_description = "<script>alert(1)</script>";
  r.labels = {{"owner", "</script><img src=x onerror=alert(2)>"}, {"bad", "\xFF\xFE"}};
  r.dut_command = {"navd", "<b onmouseover=alert(3)>"};
  r.checks[0].title = "\"><script>alert(4)</script>";
  r.checks[0].detail = "<i>detail</i>";
  const auto dir = fresh_dir("hostile");
  write_reports(r, dir.string());
  std::ofstream(dir / "dut.log", std::ios::binary) << "ok\n</pre><script>alert(5)</script>\n\xC3(\n";
  ASSERT_TRUE(write_report(dir.string()).has_value());
  const std::string html = slurp(dir / "report.html");
  for (const char* raw : {"<script>alert(1)", "<img src=x", "<b onmouseover", "<script>alert(4)",
                          "<i>detail", "</pre><script>"}) {
    EXPECT_EQ(html.find(raw), std::string::npos) << raw;
  }
  EXPECT_NE(html.find("&lt;script&gt;alert(1)&lt;/script&gt;"), std::string::npos);
  EXPECT_NE(html.find("&lt;/pre&gt;&lt;script&gt;alert(5)"), std::string::npos);
  EXPECT_NE(html.find("\xEF\xBF\xBD"), std::string::npos);  // the bad bytes, replaced
  // Exactly three <script> elements: uPlot, the data, the report's script.
  std::size_t scripts = 0;
  for (auto at = html.find("<script"); at != std::string::npos; at = html.find("<script", at + 1)) ++scripts;
  EXPECT_EQ(scripts, 3u);
  // The summary and junit survive the bad bytes too.
  EXPECT_TRUE(nlohmann::json::parse(slurp(dir / "summary.json")).is_object());
  EXPECT_EQ(slurp(dir / "junit.xml").find("\xFF"), std::string::npos);
}

TEST(RunReport, ScriptPolicyAllowsExactlyItsOwnScripts) {
  const std::string html = report_of(synthetic_run(10, 10), "csp");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(html, m, std::regex("script-src 'sha256-([^']+)' 'sha256-([^']+)'")));
  EXPECT_NE(html.find("default-src 'none'"), std::string::npos);
  std::vector<std::string> bodies;
  for (std::size_t at = html.find("<script>"); at != std::string::npos; at = html.find("<script>", at + 1)) {
    const auto end = html.find("</script>", at);
    bodies.push_back(html.substr(at + 8, end - at - 8));
  }
  ASSERT_EQ(bodies.size(), 2u);
  EXPECT_EQ(sha256_base64(bodies[0]), m[1].str());
  EXPECT_EQ(sha256_base64(bodies[1]), m[2].str());
  EXPECT_NE(bodies[0].find("uPlot"), std::string::npos);
}

TEST(RunReport, TenMinutesAtOneHundredHertzStaysSmall) {
  const RunRecord r = synthetic_run(600, 100);
  const auto dir = fresh_dir("big");
  write_reports(r, dir.string());
  const auto t0 = std::chrono::steady_clock::now();
  ASSERT_TRUE(write_report(dir.string()).has_value());
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const auto size = std::filesystem::file_size(dir / "report.html");
  EXPECT_LT(size, 5u * 1000 * 1000);
  std::printf("report of 600 s at 100 Hz: %.2f MB, written in %.2f s\n", static_cast<double>(size) / 1e6, s);
  // Thinned, yet the worst latency (a spike) is still there.
  const auto plots = embedded_plots(slurp(dir / "report.html"));
  EXPECT_LE((*plot_by_id(plots, "plot-latency-time"))["data"][0].size(), 1000u * 8u);
}

}  // namespace
}  // namespace nav::reports

namespace nav::reports {
namespace {

using namespace testing;

TEST(RunReport, EveryPeerHasItsErrorPlotsWithItsChecksEnvelope) {
  // GIVEN a run with a peer 'bravo' whose estimate is 3 m east of its truth, judged by its
  // own horizontal_error check
  RunRecord r = synthetic_run(60, 20);
  VehicleTrack bravo;
  bravo.name = "bravo";
  bravo.dut_status = r.dut_status;
  for (const auto& s : r.vehicles.front().aligned) {
    AlignedSample b = s;
    b.truth_p_n += Vec3(0.0, 80.0, 0.0);
    b.est_p_n = b.truth_p_n + Vec3(0.0, 3.0, 0.5);
    bravo.aligned.push_back(b);
    bravo.truth.push_back({b.t_s, b.truth_p_n, b.truth_q_nb, b.distance_m});
  }
  r.vehicles.push_back(bravo);
  CheckResult h{"bravo.horizontal_error", true, true, 3.0, 5.0, "m", "max 3.0 m"};
  h.kind = "horizontal_error";
  h.vehicle = "bravo";
  r.checks.push_back(h);
  const std::string html = report_of(r, "peer-errors");
  const auto plots = embedded_plots(html);
  // THEN its horizontal error plot has the check's envelope and its error, linked from the
  // check; its vertical error is plotted without one
  const std::string id = "plot-check-" + std::to_string(r.checks.size() - 1);
  const auto* p = plot_by_id(plots, id);
  ASSERT_NE(p, nullptr) << id;
  EXPECT_EQ((*p)["title"], "bravo: Horizontal error: check bravo.horizontal_error");
  EXPECT_EQ((*p)["series"][1]["label"], "limit");
  double largest = 0.0;
  for (const auto& v : (*p)["data"][1]) {
    if (v.is_number()) largest = std::max(largest, v.get<double>());
  }
  EXPECT_NEAR(largest, 3.0, 1e-3);
  EXPECT_NE(html.find("<a href=\"#" + id + "\">plot</a>"), std::string::npos);
  const auto* vertical = plot_by_id(plots, "plot-bravo-vertical_error");
  ASSERT_NE(vertical, nullptr);
  EXPECT_EQ((*vertical)["series"].size(), 1u);  // the error only: no check, no envelope
}

}  // namespace
}  // namespace nav::reports
