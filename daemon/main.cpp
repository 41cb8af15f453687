// headingd: one binary, one subcommand per job. Each subcommand's work lives in its own
// *_command.cpp; this file only parses the command line and dispatches.
#include <CLI/CLI.hpp>

#include "daemon/allan_command.hpp"
#include "daemon/exit_codes.hpp"
#include "daemon/replay_command.hpp"
#include "daemon/score_command.hpp"
#include "daemon/simulate_command.hpp"
#include "daemon/version.hpp"

namespace app = headingd::app;

int main(int argc, char** argv) {
  CLI::App cli{"headingd: gyro heading daemon for AGVs (L3GD20H, stationary-segment bias tracking)"};
  cli.set_version_flag("--version", app::kVersion);
  cli.require_subcommand(1);

  app::ReplayOptions replay;
  auto* replay_cmd = cli.add_subcommand("replay", "Replay a recorded IMU file through the estimator");
  replay_cmd->add_option("input", replay.input, "Recording: headingd CSV or EuRoC/ASL imu.csv")->required();
  replay_cmd->add_option("--method", replay.method, "Bias method: auto (default), or the paper's a, b, c");
  replay_cmd->add_option("-o,--output", replay.output, "Estimates CSV ('-' = standard output)");
  replay_cmd->add_option("--output-rate", replay.output_rate_hz, "Rows per second; 0 = every sample")
      ->capture_default_str();
  replay_cmd->add_option("-c,--config", replay.config_path, "TOML configuration file");
  replay_cmd->add_flag("-q,--quiet", replay.quiet, "No summary on stderr");

  app::SimulateOptions simulate;
  auto* simulate_cmd = cli.add_subcommand("simulate", "Simulate a gyro recording with its truth");
  simulate_cmd->add_option("--scenario", simulate.scenario, "paper12h, still, agv, creep or thermal")->required();
  simulate_cmd->add_option("--seed", simulate.seed, "Random seed")->capture_default_str();
  simulate_cmd->add_option("--output-dir", simulate.output_dir, "Directory for imu.csv and truth.csv")->required();
  simulate_cmd->add_option("--hours", simulate.hours, "Length in hours (default: the scenario's own)");

  app::ScoreOptions score;
  auto* score_cmd = cli.add_subcommand("score", "Score an estimates CSV against a truth CSV (paper's metrics)");
  score_cmd->add_option("estimates", score.estimates, "Estimates CSV from replay")->required();
  score_cmd->add_option("truth", score.truth, "truth.csv from simulate")->required();
  score_cmd->add_option("--label", score.label, "Row label")->capture_default_str();
  score_cmd->add_option("--errors", score.errors_output, "Write time_h,error_deg at 1 Hz to this file");
  score_cmd->add_flag("--header", score.header, "Print the table header first");

  app::AllanOptions allan;
  auto* allan_cmd = cli.add_subcommand("allan", "Allan deviation of a still recording; noise terms for the config");
  allan_cmd->add_option("input", allan.input, "Recording: headingd CSV or EuRoC/ASL imu.csv")->required();
  allan_cmd->add_option("--axis", allan.axis, "x, y, z or all")->capture_default_str();
  allan_cmd->add_option("--plot", allan.plot_path, "Draw a log-log plot to this PNG (needs gnuplot)");
  allan_cmd->add_flag("--emit-config", allan.emit_config, "Print the estimator settings as a TOML fragment");
  allan_cmd->add_flag("--still-only", allan.still_only,
                      "Use only the segments the auto estimator accepts as still (cuts out motion)");

  try {
    cli.parse(argc, argv);
  } catch (const CLI::CallForHelp& help) {
    return cli.exit(help);
  } catch (const CLI::CallForAllHelp& help) {
    return cli.exit(help);
  } catch (const CLI::CallForVersion& version) {
    return cli.exit(version);
  } catch (const CLI::ParseError& error) {
    cli.exit(error);
    return app::kExitUsage;
  }

  if (replay_cmd->parsed()) return app::run_replay(replay);
  if (simulate_cmd->parsed()) return app::run_simulate(simulate);
  if (score_cmd->parsed()) return app::run_score(score);
  if (allan_cmd->parsed()) return app::run_allan(allan);
  return app::kExitUsage;
}
