// SPDX-License-Identifier: MIT
// The tables of a run report (timing, vehicles, devices, CAN buses, acoustic links) and the
// tail of the DUT's log.
#include <map>

#include "html_text.hpp"
#include "json_get.hpp"
#include "nav/common/version.hpp"
#include "nav/reports/run_folder.hpp"

namespace nav::reports::detail {
namespace {

using json = nlohmann::json;

std::string stats_row(const std::string& what, const json& st, const std::string& extra) {
  return row({html_escape(what), num(get_number(st, "count"), 10), fixed(get_number(st, "p50_ms")),
              fixed(get_number(st, "p99_ms")), fixed(get_number(st, "max_ms")), html_escape(extra)},
             "tnnnnt");
}

/// `run --witness`: each audited line as the witness saw it.
std::string witness_table(const json& w) {
  std::string h =
      "<p class=\"note\">Timing audit (<code>navbench run --witness</code>): "
      "<code>navbench witness</code>, a separate process, stood in the DUT's place and "
      "stamped every byte as it arrived. Lateness is against each message's scheduled wire "
      "time: the bench's when it wrote the first byte, the witness's when it read it. Pacing: "
      "the time between the reads of a message's first and last bytes over the byte time of "
      "the bytes between them (1 = exactly the baud), median over messages.</p><table>\n" +
      header_row({"line", "baud", "messages seen / sent", "bytes as written / sent",
                  "write p50 / p99 / max [ms]", "arrival p50 / p99 / max [ms]",
                  "pacing median"});
  const auto three = [](const json& st) {
    return fixed(get_number(st, "p50_ms")) + " / " + fixed(get_number(st, "p99_ms")) + " / " +
           fixed(get_number(st, "max_ms"));
  };
  for (const auto& l : get_array(w, "lines")) {
    const auto matched = get_number(l, "bytes_matched"), sent = get_number(l, "bytes_sent");
    std::string bytes = num(matched, 10) + " / " + num(sent, 10);
    if (matched != sent || get_number(l, "bytes_seen") != sent) {
      bytes = "<span class=\"lost\">" + bytes + " (" + num(get_number(l, "bytes_seen"), 10) +
              " read)</span>";
    }
    h += row({html_escape(get_string(l, "device", "?")), num(get_number(l, "baud"), 10),
              num(get_number(l, "messages_seen"), 10) + " / " + num(get_number(l, "messages"), 10),
              bytes, three(member(l, "write_lateness")), three(member(l, "arrival_lateness")),
              fixed(get_number(l, "pacing_median"), 4) + " (" +
                  num(get_number(l, "pacing_messages"), 10) + ")"},
             "tnnnnnn");
  }
  return h + "</table>\n";
}

std::string timing(const RunFolder& f) {
  const json& s = f.summary;
  const bool lockstep = get_string(s, "mode", "") == "lockstep";
  std::string h = "<section id=\"timing\"><h2>Timing</h2><table>\n" +
                  header_row({"", "count", "p50 [ms]", "p99 [ms]", "max [ms]", "note"});
  const json& bl = member(s, "bench_lateness");
  h += stats_row("bench lateness", bl,
                 lockstep ? "lockstep: virtual time"
                          : "budget p99 " + fixed(get_number(bl, "budget_p99_ms")) + " ms");
  const json& witness = member(s, "witness");
  if (witness.is_null()) {  // a timing audit has no DUT
    h += stats_row(lockstep ? "DUT compute time" : "DUT latency", member(s, "dut_latency"),
                   lockstep ? "not judged in lockstep" : "trigger's last byte to the answer");
  }
  for (const auto& b : get_array(s, "can_buses")) {
    h += stats_row("CAN " + get_string(b, "interface", "?") + " queueing", member(b, "queueing_delay"),
                   "bus load " + fixed(get_number(b, "bus_load").value_or(0) * 100.0, 2) + " %");
    if (get_number(member(b, "write_lateness"), "count").value_or(0) > 0) {
      h += stats_row("CAN " + get_string(b, "interface", "?") + " write lateness",
                     member(b, "write_lateness"), "");
    }
  }
  if (!witness.is_null()) {
    h += stats_row("witness arrival lateness", member(witness, "arrival_lateness"),
                   "first byte read by the witness − scheduled");
  }
  const json& dut = member(s, "dut");
  h += "</table>";
  if (!witness.is_null()) return h + witness_table(witness) + "</section>\n";
  h += "<p class=\"note\">DUT: " + num(get_number(dut, "answers"), 10) + " solutions for " +
       num(get_number(dut, "triggers_sent"), 10) + " triggers, " +
       num(get_number(dut, "unmatched_answers"), 10) + " naming no trigger, " +
       num(get_number(dut, "malformed_output"), 10) + " malformed lines.</p>\n";
  const auto& examples = get_array(dut, "malformed_examples");
  if (!examples.empty()) {
    h += "<table>\n" + header_row({"malformed at [s]", "why", "what the DUT wrote"});
    for (const auto& m : examples) {
      h += row({fixed(get_number(m, "rx_s")), html_escape(get_string(m, "why", "")),
                "<code>" + html_escape(get_string(m, "text", "")) + "</code>"},
               "n");
    }
    h += "</table>\n";
  }
  const auto& restarts = get_array(dut, "restarts");
  if (!restarts.empty()) {
    h += "<table>\n" + header_row({"DUT off at [s]", "how it ended", "on again at [s]",
                                   "first solution at [s]", "first valid at [s]",
                                   "recovery [s]", "triggers unanswered"});
    for (const auto& r : restarts) {
      h += row({fixed(get_number(r, "off_s")), html_escape(get_string(r, "ended", "")),
                fixed(get_number(r, "on_s")) +
                    (get_bool(r, "started_again").value_or(true) ? "" : " (the run ended first)"),
                fixed(get_number(r, "first_solution_s")),
                fixed(get_number(r, "first_valid_s")), fixed(get_number(r, "recovery_s")),
                num(get_number(r, "triggers_in_gap"), 10)},
               "ntnnnnn");
    }
    h += "</table>\n";
  }
  for (const auto& c : get_array(s, "logs_cut")) {
    h += "<p class=\"note\">" + html_escape(get_string(c, "file", "?")) +
         " was cut at its limit of " + num(get_number(c, "limit_bytes"), 10) + " bytes: " +
         num(get_number(c, "cut_bytes"), 10) +
         " more bytes the DUT wrote were not kept (<code>navbench run --log-limit</code>).</p>\n";
  }
  return h + "</section>\n";
}

std::string error_cell(const json& v, const char* key, const char* field) {
  return fixed(get_number(member(v, key), field));
}

std::string vehicles(const RunFolder& f) {
  const auto& list = get_array(f.summary, "vehicles");
  if (list.empty()) return {};
  std::string h = "<section id=\"vehicles\"><h2>Vehicles</h2><table>\n" +
                  header_row({"vehicle", "DUT status", "solutions / triggers", "distance [m]",
                              "horizontal max / rms [m]", "vertical max [m]", "attitude max [deg]",
                              "endpoint [m]"});
  for (const auto& v : list) {
    const json& dut = member(v, "dut");
    std::string name = html_escape(get_string(v, "name", "?"));
    if (detail::get_bool(v, "primary").value_or(false)) name += " <span class=\"req\">judged</span>";
    h += row({name, html_escape(get_string(dut, "status", "")),
              num(get_number(v, "solutions"), 10) + " / " + num(get_number(dut, "triggers_sent"), 10),
              fixed(get_number(v, "distance_m"), 1),
              error_cell(v, "horizontal_error_m", "max") + " / " + error_cell(v, "horizontal_error_m", "rms"),
              error_cell(v, "vertical_error_m", "max"), error_cell(v, "attitude_error_deg", "max"),
              fixed(get_number(v, "endpoint_error_m"))},
             "ttnnnnnn");
  }
  // The peers' DUTs: what was run.
  for (const auto& p : get_array(f.summary, "peers")) {
    const json& dut = member(p, "dut");
    std::vector<std::string> argv;
    for (const auto& a : get_array(dut, "command")) argv.push_back(a.is_string() ? a.get<std::string>() : a.dump());
    h += "<tr><td colspan=\"8\" class=\"sub\">" + html_escape(get_string(p, "name", "?")) +
         ": <code>" + html_escape(argv_text(argv)) + "</code> &middot; SHA-256 " +
         text_or_missing(get_string(dut, "sha256")) + "</td></tr>\n";
  }
  return h + "</table></section>\n";
}

std::string faults_of(const RunFolder& f, const std::string& device) {
  std::string h;
  for (const auto& fault : get_array(f.summary, "faults")) {
    if (get_string(fault, "device", "") != device) continue;
    if (!h.empty()) h += "<br>";
    h += html_escape(get_string(fault, "kind", "?")) + " " + fixed(get_number(fault, "start_s"), 1) +
         "\u2013" + fixed(get_number(fault, "end_s"), 1) + " s, " +
         num(get_number(fault, "messages_affected"), 10) + " affected";
  }
  return h.empty() ? "\u2014" : h;
}

std::string devices(const RunFolder& f) {
  std::string h = "<section id=\"devices\"><h2>Devices</h2><table>\n" +
                  header_row({"device", "protocol", "port", "baud / bit rate", "messages", "bytes",
                              "dropped bytes", "faults"});
  for (const auto& d : get_array(f.summary, "devices")) {
    const bool can = member(d, "can").is_string();
    const std::string name = get_string(d, "name", "?");
    h += row({html_escape(name), html_escape(get_string(d, "type", "?")),
              "<code>" + html_escape(get_string(d, can ? "can" : "port", "?")) + "</code>",
              num(get_number(d, can ? "bitrate" : "baud"), 10),
              num(get_number(d, can ? "frames" : "messages"), 10) + (can ? " frames" : ""),
              num(get_number(d, "bytes"), 12),
              can ? num(get_number(d, "frames_dropped"), 10) + " frames"
                  : num(get_number(d, "bytes_dropped"), 12),
              faults_of(f, name)},
             "tttnnnnt");
  }
  h += "</table>\n";
  const auto& links = get_array(f.summary, "acoustic_links");
  if (!links.empty()) {
    h += "<h3>Acoustic links</h3><table>\n" +
         header_row({"from", "to", "sent", "delivered", "lost", "out of range", "bytes",
                     "propagation min\u2013max [s]"});
    for (const auto& l : links) {
      h += row({html_escape(get_string(l, "from", "?")), html_escape(get_string(l, "to", "?")),
                num(get_number(l, "packets_sent"), 10), num(get_number(l, "packets_delivered"), 10),
                num(get_number(l, "packets_lost"), 10), num(get_number(l, "packets_out_of_range"), 10),
                num(get_number(l, "bytes_delivered"), 12),
                fixed(get_number(l, "min_propagation_s")) + "\u2013" +
                    fixed(get_number(l, "max_propagation_s"))},
               "ttnnnnnn");
    }
    h += "</table>\n";
  }
  const auto& buses = get_array(f.summary, "can_buses");
  if (!buses.empty()) {
    h += "<h3>CAN buses</h3><table>\n" +
         header_row({"interface", "bit rate", "frames sent", "dropped", "bus load",
                     "error frames to the DUT", "missed while bus-off", "faults"});
    for (const auto& b : buses) {
      const std::string iface = get_string(b, "interface", "?");
      h += row({"<code>" + html_escape(iface) + "</code>", num(get_number(b, "bitrate"), 10),
                num(get_number(b, "frames_sent"), 10), num(get_number(b, "frames_dropped"), 10),
                fixed(get_number(b, "bus_load").value_or(0) * 100.0, 2) + " %",
                num(get_number(b, "error_reports"), 10), num(get_number(b, "frames_withheld"), 10),
                faults_of(f, iface)},
               "tnnnnnnt");
    }
    h += "</table>\n";
  }
  return h + "</section>\n";
}

std::string dut_log(const RunFolder& f) {
  std::string h = "<section id=\"dut-log\"><h2>DUT log</h2>\n";
  if (!f.has_dut_log) return h + "<p class=\"note\">dut.log not recorded.</p></section>\n";
  if (f.dut_log_tail.empty()) return h + "<p class=\"note\">dut.log is empty.</p></section>\n";
  h += "<p class=\"note\">" +
       std::string(f.dut_log_cut ? "The end of dut.log (its last " +
                                       std::to_string(kDutLogTailBytes / 1024) + " KiB)."
                                 : "All of dut.log.") +
       "</p><pre class=\"log\">" + html_escape(f.dut_log_tail) + "</pre></section>\n";
  return h;
}

}  // namespace

std::string run_tables_html(const RunFolder& f) {
  std::string h = timing(f) + vehicles(f) + devices(f) + dut_log(f);
  h += "<footer>Written by navbench " + html_escape(navbench_version()) +
       " from the files of the run folder; the full data are in its CSV and TUM files. Plots: "
       "uPlot (MIT License), embedded.</footer>\n";
  return h;
}

}  // namespace nav::reports::detail
