// SPDX-License-Identifier: MIT
// navd's refusals of a P4 navigator without its inputs (dut/navd/main.cpp): exit code 2 and
// one line on stderr, before any port is opened (the paths need not exist).
#include <sys/wait.h>

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "source_paths.hpp"

namespace {

struct Outcome {
  int code = -1;
  std::string err;
};

Outcome run_navd(const std::string& args, const std::string& config_text) {
  // Named by the test: ctest runs each test of this binary as its own process, in parallel.
  const std::string dir = ::testing::TempDir();
  const std::string name =
      std::string("navd_p4_cli_") + ::testing::UnitTest::GetInstance()->current_test_info()->name();
  const std::string config = dir + "/" + name + ".yaml";
  const std::string err = dir + "/" + name + ".err";
  std::ofstream(config) << config_text;
  const std::string cmd = nav::test_paths::binary_dir() + "/navd --output /nonexistent/out --config " +
                          config + " " + args + " 2>" + err;
  const int status = std::system(cmd.c_str());
  Outcome o;
  if (WIFEXITED(status)) o.code = WEXITSTATUS(status);
  std::stringstream s;
  s << std::ifstream(err).rdbuf();
  o.err = s.str();
  return o;
}

TEST(NavdP4Cli, RefusesAP4NavigatorWithoutABeaconInputOrWithoutGps) {
  for (const char* name : {"p4-ukf", "p4-dwt-ukf"}) {
    const std::string config = std::string("navigator: ") + name + "\n";
    const Outcome no_beacon = run_navd("--gps /nonexistent/gps", config);
    EXPECT_EQ(no_beacon.code, 2) << no_beacon.err;
    EXPECT_EQ(no_beacon.err, std::string("navd: navigator ") + name +
                                 ": needs an --input NAME=beacon-ins:PATH (the trigger) and no "
                                 "--ahrs (see navd --help)\n");
    const Outcome with_ahrs = run_navd(
        "--ahrs /nonexistent/ahrs --gps /nonexistent/gps --input b=beacon-ins:/nonexistent/b",
        config);
    EXPECT_EQ(with_ahrs.code, 2) << with_ahrs.err;
    EXPECT_NE(with_ahrs.err.find("needs an --input NAME=beacon-ins:PATH"), std::string::npos);
    const Outcome no_gps = run_navd("--input b=beacon-ins:/nonexistent/b", config);
    EXPECT_EQ(no_gps.code, 2) << no_gps.err;
    EXPECT_EQ(no_gps.err, std::string("navd: navigator ") + name +
                              ": needs --gps PATH (the RMC fixes that start and correct it; see "
                              "navd --help)\n");
  }
  // With both, navd gets as far as opening the ports (exit 3: they do not exist).
  const Outcome ok = run_navd("--gps /nonexistent/gps --input b=beacon-ins:/nonexistent/b",
                              "navigator: p4-ukf\n");
  EXPECT_EQ(ok.code, 3) << ok.err;
}

TEST(NavdP4Cli, LocationOfABadKey) {
  const Outcome o = run_navd("--gps g --input b=beacon-ins:b",
                             "navigator: p4-dwt-ukf\np4_dwt_window: 63\n");
  EXPECT_EQ(o.code, 2) << o.err;
  EXPECT_NE(o.err.find("LocationOfABadKey.yaml:2:16: p4_dwt_window: p4_dwt_window must be an "
                       "even"),
            std::string::npos)
      << o.err;
}

}  // namespace
