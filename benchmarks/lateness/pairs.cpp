// SPDX-License-Identifier: MIT
// `lateness_benchmark pairs`: the floor and the bench, alternately, on one machine.
#include <cstdio>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "benchmark.hpp"
#include "child.hpp"
#include "floor.hpp"
#include "lateness_stats.hpp"
#include "write_floor.hpp"

namespace nav::benchmarks {
namespace {

using json = nlohmann::json;

Stats stats_of(const json& j) {
  Stats s;
  s.count = j.value("count", std::size_t{0});
  s.p50_s = j.value("p50_ms", 0.0) * 1e-3;
  s.p99_s = j.value("p99_ms", 0.0) * 1e-3;
  s.max_s = j.value("max_ms", 0.0) * 1e-3;
  return s;
}

struct RunFigures {
  Stats lateness, arrival;
  double duration_s = 0.0, cpu_share = 0.0;
  std::string verdict;
};

RunFigures run_scenario(const Common& c, const std::string& scenario, const std::string& name,
                        bool witness) {
  const auto dir = c.out / name;
  std::vector<std::string> argv = {c.navbench, "run", scenario, "--quiet", "--out", dir.string()};
  if (witness) argv.push_back("--witness");
  run(argv, c.out / (name + "-navbench"), {0, 1});  // a failed check does not void the timing
  std::ifstream in(dir / "summary.json");
  std::ostringstream text;
  text << in.rdbuf();
  const json s = json::parse(text.str());
  RunFigures r;
  r.lateness = stats_of(s.at("bench_lateness"));
  if (s.contains("witness")) r.arrival = stats_of(s["witness"]["arrival_lateness"]);
  r.duration_s = s.value("duration_s", 0.0);
  const double wall = s.value("wall_time_s", 0.0);
  r.cpu_share = wall > 0 ? s.value("bench_cpu_s", 0.0) / wall : 0.0;
  r.verdict = s.value("verdict", "");
  return r;
}

void print_stats(const char* what, const Stats& s) {
  std::printf("  %-22s p50 %8.1f  p99 %8.1f  max %9.1f us  (%zu)\n", what, s.p50_s * 1e6,
              s.p99_s * 1e6, s.max_s * 1e6, s.count);
}

}  // namespace

int run_pairs(const Common& c, const std::string& scenario, double floor_seconds, bool witness) {
  // A first run, not counted: its message rate sets the floor's, and it warms the caches.
  std::printf("warm-up run of %s ...\n", scenario.c_str());
  std::fflush(stdout);
  const RunFigures warm = run_scenario(c, scenario, "warm-up", witness);
  if (warm.lateness.count == 0) {
    std::fprintf(stderr, "lateness_benchmark: %s wrote no message in realtime\n", scenario.c_str());
    return 2;
  }
  const auto period = std::chrono::nanoseconds(static_cast<std::int64_t>(
      warm.duration_s / static_cast<double>(warm.lateness.count) * 1e9));
  const double seconds = floor_seconds > 0 ? floor_seconds : warm.duration_s;
  const auto n = static_cast<std::size_t>(seconds / (static_cast<double>(period.count()) * 1e-9));
  std::printf("floor: %zu wake-ups every %.3f ms (the scenario's message rate), %.0f s\n", n,
              static_cast<double>(period.count()) * 1e-6, seconds);
  const auto lateness_csv =
      reports::read_csv((c.out / "warm-up" / "lateness.csv").string(), {"device"});
  if (!lateness_csv) {
    std::fprintf(stderr, "lateness_benchmark: %s\n", lateness_csv.error().detail.c_str());
    return 2;
  }
  const WriteSchedule bursts = write_schedule(*lateness_csv, seconds);
  std::printf("write floor: the warm-up run's %zu message starts on %zu lines at %zu instants, "
              "%.0f s\n", bursts.messages, bursts.lines.size(), bursts.instants.size(), seconds);
  std::vector<Stats> floors, write_floors, runs, arrivals;
  std::ofstream csv(c.out / "pairs.csv");
  csv << "pair,what,count,p50_us,p99_us,max_us,cpu_share\n";
  const auto row = [&](int i, const char* what, const Stats& s, double cpu) {
    csv << i << ',' << what << ',' << s.count << ',' << s.p50_s * 1e6 << ',' << s.p99_s * 1e6
        << ',' << s.max_s * 1e6 << ',' << cpu << '\n';
  };
  for (int i = 1; i <= c.pairs; ++i) {
    floors.push_back(reports::summarize(wake_up_floor(period, n)));
    write_floors.push_back(reports::summarize(write_floor(bursts, witness)));
    const RunFigures r = run_scenario(c, scenario, "pair-" + std::to_string(i), witness);
    runs.push_back(r.lateness);
    arrivals.push_back(r.arrival);
    std::printf("pair %d (run %s, bench CPU %.1f %% of one core) [us]:\n", i, r.verdict.c_str(),
                r.cpu_share * 100.0);
    print_stats("floor", floors.back());
    print_stats("write floor", write_floors.back());
    print_stats("bench write lateness", r.lateness);
    if (witness) print_stats("witness arrival", r.arrival);
    std::fflush(stdout);
    row(i, "floor", floors.back(), 0.0);
    row(i, "write_floor", write_floors.back(), 0.0);
    row(i, "bench", r.lateness, r.cpu_share);
    if (witness) row(i, "witness", r.arrival, 0.0);
  }
  const PairRatio m = median_ratio(pair_ratios(floors, runs));
  std::printf("median over %d pairs of bench / floor:  p50 %.2f  p99 %.2f  max %.2f\n", c.pairs,
              m.p50, m.p99, m.max);
  const PairRatio w = median_ratio(pair_ratios(write_floors, runs));
  std::printf("median over %d pairs of bench / write floor:  p50 %.2f  p99 %.2f  max %.2f\n",
              c.pairs, w.p50, w.p99, w.max);
  if (witness) {
    const PairRatio a = median_ratio(pair_ratios(floors, arrivals));
    std::printf("median over %d pairs of witness arrival / floor:  p50 %.2f  p99 %.2f  max %.2f\n",
                c.pairs, a.p50, a.p99, a.max);
  }
  std::printf("runs and pairs.csv in %s\n", c.out.c_str());
  return 0;
}

}  // namespace nav::benchmarks
