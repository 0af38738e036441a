// SPDX-License-Identifier: MIT
// The command line of `navbench campaign` and of its subcommands plan, run-index and merge
// (CLI11): options, help, and the call of the command chosen. Private to navbench's main.
#pragma once

#include <memory>
#include <optional>

namespace CLI {
class App;
}

namespace nav::bench {

class CampaignCli {
 public:
  /// Adds `campaign` (and its subcommands) to app.
  explicit CampaignCli(CLI::App& app);
  ~CampaignCli();
  CampaignCli(const CampaignCli&) = delete;
  CampaignCli& operator=(const CampaignCli&) = delete;

  /// After app.parse(): the exit code of the campaign command given, or nullopt when the
  /// command line chose another subcommand of navbench.
  std::optional<int> run(int argc, char** argv);

 private:
  struct Parts;
  std::unique_ptr<Parts> p_;
};

}  // namespace nav::bench
