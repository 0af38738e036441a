// SPDX-License-Identifier: MIT
// soak: runs a realistic multi-device scenario at 1x for a long time and reports, per window
// of scenario time, the memory of the bench and of its DUTs and the bench's lateness; the
// figures a long run must keep flat (docs/design-notes.md, "Soak"). Not a test: run by hand.
//
//   ./build/bin/soak [--minutes M] [--window-minutes W] [--scenario FILE] [--out DIR]
//
// Defaults: 60 minutes of scenarios/soak.yaml, 5-minute windows, DIR = runs/soak-<UTC time>.
// The scenario is copied to DIR/scenario.yaml with its top-level `duration:` set to M minutes
// and run with `navbench run` (beside this program) into DIR/run. Every 10 s the resident set
// (VmRSS) of navbench and of every process below it (the DUTs) is sampled. At the end:
// DIR/soak.csv (one row per window) and a table on stdout; RSS growth is from the first
// sample of the second window (the streams and the truth are generated before scenario time 0)
// to the last sample, lateness from DIR/run/lateness.csv, losses from DIR/run/summary.json.
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "nav/reports/run_record.hpp"

extern char** environ;

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct Options {
  double minutes = 60.0, window_minutes = 5.0;
  std::string scenario = "scenarios/soak.yaml";
  std::string out;
};

struct Sample {
  double t_s = 0.0;             ///< since navbench started
  double bench_mb = 0.0, dut_mb = 0.0;
};

/// VmRSS of a process [MB], 0 when it is gone.
double rss_mb(pid_t pid) {
  std::ifstream f("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(f, line);) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  }
  return 0.0;
}

/// The parent of a process, or 0.
pid_t parent_of(pid_t pid) {
  std::ifstream f("/proc/" + std::to_string(pid) + "/stat");
  std::string s;
  std::getline(f, s);
  const auto paren = s.rfind(')');
  if (paren == std::string::npos) return 0;
  std::istringstream rest(s.substr(paren + 2));
  char state = 0;
  pid_t ppid = 0;
  rest >> state >> ppid;
  return ppid;
}

/// Every process below root (its DUTs and what they started).
std::vector<pid_t> descendants(pid_t root) {
  std::map<pid_t, pid_t> parent;
  for (const auto& e : fs::directory_iterator("/proc")) {
    const std::string name = e.path().filename();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    const pid_t pid = std::stoi(name);
    parent[pid] = parent_of(pid);
  }
  std::vector<pid_t> out;
  for (const auto& [pid, ppid] : parent) {
    for (pid_t p = ppid; p > 1; p = parent.count(p) ? parent[p] : 0) {
      if (p == root) {
        out.push_back(pid);
        break;
      }
    }
  }
  return out;
}

bool parse(int argc, char** argv, Options& o) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    if (a == "--minutes" && has_value) {
      o.minutes = std::stod(argv[++i]);
    } else if (a == "--window-minutes" && has_value) {
      o.window_minutes = std::stod(argv[++i]);
    } else if (a == "--scenario" && has_value) {
      o.scenario = argv[++i];
    } else if (a == "--out" && has_value) {
      o.out = argv[++i];
    } else {
      return false;
    }
  }
  return o.minutes > 0 && o.window_minutes > 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  if (!parse(argc, argv, o)) {
    std::fprintf(stderr,
                 "usage: soak [--minutes M (60)] [--window-minutes W (5)] [--scenario FILE "
                 "(scenarios/soak.yaml)] [--out DIR (runs/soak-<UTC time>)]\n");
    return 2;
  }
  if (o.out.empty()) {
    char stamp[32];
    const std::time_t now = std::time(nullptr);
    std::strftime(stamp, sizeof stamp, "%Y%m%dT%H%M%SZ", std::gmtime(&now));
    o.out = std::string("runs/soak-") + stamp;
  }
  std::ifstream in(o.scenario);
  if (!in) {
    std::fprintf(stderr, "soak: cannot read %s\n", o.scenario.c_str());
    return 2;
  }
  std::stringstream text;
  text << in.rdbuf();
  const std::regex duration_line(R"(^duration:[^\n]*)", std::regex::multiline);
  char duration[64];
  std::snprintf(duration, sizeof duration, "duration: %g s", o.minutes * 60.0);
  fs::create_directories(o.out);
  const fs::path scenario = fs::path(o.out) / "scenario.yaml";
  std::ofstream(scenario) << std::regex_replace(text.str(), duration_line, duration);

  const fs::path navbench = fs::canonical("/proc/self/exe").parent_path() / "navbench";
  std::vector<std::string> args{navbench.string(), "run", scenario.string(), "--out",
                                (fs::path(o.out) / "run").string(), "--quiet"};
  std::vector<char*> cargs;
  for (auto& a : args) cargs.push_back(a.data());
  cargs.push_back(nullptr);
  pid_t bench = -1;
  if (::posix_spawn(&bench, navbench.c_str(), nullptr, nullptr, cargs.data(), environ) != 0) {
    std::fprintf(stderr, "soak: cannot start %s\n", navbench.c_str());
    return 3;
  }
  std::fprintf(stderr, "soak: %g min of %s into %s (pid %d)\n", o.minutes, o.scenario.c_str(),
               o.out.c_str(), static_cast<int>(bench));
  std::vector<Sample> samples;
  const auto start = Clock::now();
  int status = 0;
  while (::waitpid(bench, &status, WNOHANG) == 0) {
    Sample s;
    s.t_s = std::chrono::duration<double>(Clock::now() - start).count();
    s.bench_mb = rss_mb(bench);
    for (const pid_t p : descendants(bench)) s.dut_mb += rss_mb(p);
    samples.push_back(s);
    std::this_thread::sleep_for(std::chrono::seconds(10));
  }

  // Lateness per window of scenario time, from the run's lateness.csv.
  const double window_s = o.window_minutes * 60.0;
  std::map<int, std::vector<double>> late_s;
  std::ifstream csv(fs::path(o.out) / "run/lateness.csv");
  std::string line;
  std::getline(csv, line);  // header: device,scheduled_s,actual_s,lateness_us
  while (std::getline(csv, line)) {
    std::istringstream row(line);
    std::string device, scheduled, actual, lateness;
    std::getline(row, device, ',');
    std::getline(row, scheduled, ',');
    std::getline(row, actual, ',');
    std::getline(row, lateness, ',');
    if (scheduled.empty() || lateness.empty()) continue;
    late_s[static_cast<int>(std::stod(scheduled) / window_s)].push_back(std::stod(lateness) / 1e6);
  }
  // Memory per window of wall time since navbench started (the startup before scenario time 0
  // falls in the first window).
  std::ofstream out(fs::path(o.out) / "soak.csv");
  out << "window,start_min,messages,lateness_p99_ms,lateness_max_ms,bench_rss_mb,dut_rss_mb\n";
  std::printf("%-6s %-9s %-9s %-12s %-12s %-13s %-12s\n", "window", "from min", "messages",
              "p99 [ms]", "max [ms]", "bench [MB]", "DUTs [MB]");
  const int windows = static_cast<int>(std::ceil(o.minutes / o.window_minutes));
  for (int w = 0; w < windows; ++w) {
    const auto st = nav::reports::summarize(late_s[w]);  // the bench's own percentiles
    double bench_mb = 0.0, dut_mb = 0.0;  // the window's last sample
    for (const auto& s : samples) {
      if (s.t_s >= w * window_s && s.t_s < (w + 1) * window_s) {
        bench_mb = s.bench_mb;
        dut_mb = s.dut_mb;
      }
    }
    const double p99 = st.count ? st.p99_s * 1e3 : NAN, max = st.count ? st.max_s * 1e3 : NAN;
    std::printf("%-6d %-9.1f %-9zu %-12.3f %-12.3f %-13.1f %-12.1f\n", w, w * o.window_minutes,
                st.count, p99, max, bench_mb, dut_mb);
    out << w << ',' << w * o.window_minutes << ',' << st.count << ',' << p99 << ',' << max << ','
        << bench_mb << ',' << dut_mb << '\n';
  }
  // Growth: from the first sample of the second window (or the first sample) to the last.
  const Sample* from = samples.empty() ? nullptr : &samples.front();
  for (const auto& s : samples) {
    if (s.t_s >= window_s) {
      from = &s;
      break;
    }
  }
  const auto summary = nlohmann::json::parse(
      std::ifstream(fs::path(o.out) / "run/summary.json"), nullptr, /*allow_exceptions=*/false);
  std::uint64_t dropped = 0;
  if (summary.is_object()) {
    for (const auto& d : summary.value("devices", nlohmann::json::array())) {
      dropped += d.value("bytes_dropped", std::uint64_t{0});
    }
  }
  if (from) {
    std::printf("RSS growth from %.0f s to the end: bench %+.1f MB, DUTs %+.1f MB\n", from->t_s,
                samples.back().bench_mb - from->bench_mb, samples.back().dut_mb - from->dut_mb);
  }
  if (summary.is_object()) {
    std::printf("verdict %s; bytes dropped %llu; solutions %d for %d triggers\n",
                summary.value("verdict", "?").c_str(), static_cast<unsigned long long>(dropped),
                summary["dut"].value("answers", 0), summary["dut"].value("triggers_sent", 0));
  }
  return WIFEXITED(status) && WEXITSTATUS(status) <= 1 ? 0 : 1;
}
