// SPDX-License-Identifier: MIT
// junit.xml: one test case per check, for CI dashboards; a check's requirement id and title
// go into its name and a property, so a dashboard shows what each verdict proves.
#include "nav/reports/text.hpp"
#include "output_file.hpp"
#include "writers.hpp"

namespace nav::reports::detail {
namespace {

/// "NAV-REQ-012 horizontal_error: horizontal error within 2 m" (what is set of the three).
std::string case_name(const CheckResult& c) {
  std::string name = c.req.empty() ? c.name : c.req + " " + c.name;
  if (!c.title.empty()) name += ": " + c.title;
  return name;
}

}  // namespace

void write_junit(const RunRecord& r, const std::string& dir) {
  std::size_t failures = 0, skipped = 0;
  for (const auto& c : r.checks) {
    if (!c.judged) ++skipped;
    else if (!c.passed) ++failures;
  }
  OutputFile f(dir, "junit.xml");
  auto& o = f;
  o << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
    << "<testsuites>\n<testsuite name=\"" << xml_escape(r.scenario_name) << "\" tests=\""
    << r.checks.size() << "\" failures=\"" << failures << "\" skipped=\"" << skipped
    << "\" time=\"" << r.wall_time_s << "\">\n"
    << "  <properties><property name=\"seed\" value=\"" << r.seed << "\"/>"
    << "<property name=\"mode\" value=\"" << xml_escape(r.mode) << "\"/>"
    << "<property name=\"verdict\" value=\"" << xml_escape(r.verdict) << "\"/>";
  for (const auto& fr : r.faults) {
    o << "<property name=\"fault\" value=\"" << xml_escape(fault_text(fr)) << "\"/>";
  }
  o << "</properties>\n";
  for (const auto& c : r.checks) {
    o << "  <testcase classname=\"" << xml_escape(r.scenario_name) << "\" name=\""
      << xml_escape(case_name(c)) << "\">";
    if (!c.req.empty() || !c.title.empty()) {
      o << "<properties>";
      if (!c.req.empty()) o << "<property name=\"requirement\" value=\"" << xml_escape(c.req) << "\"/>";
      if (!c.title.empty()) o << "<property name=\"title\" value=\"" << xml_escape(c.title) << "\"/>";
      o << "</properties>";
    }
    if (!c.judged) o << "<skipped message=\"" << xml_escape(c.detail) << "\"/>";
    else if (!c.passed) o << "<failure message=\"" << xml_escape(c.detail) << "\"/>";
    o << "</testcase>\n";
  }
  o << "</testsuite>\n</testsuites>\n";
}

}  // namespace nav::reports::detail
