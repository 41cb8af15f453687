// headingd: one binary, one subcommand per job. Each subcommand's work lives in its own
// *_command.cpp; this file only parses the command line and dispatches.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "app/batch_replay.hpp"
#include "app/replay_command.hpp"
#include "app/run_command.hpp"
#include "core/version.hpp"
#include "service/exit_codes.hpp"
#include "service/log.hpp"
#include "service/signals.hpp"
#include "tools/allan_command.hpp"
#include "tools/echo_command.hpp"
#include "tools/plot_command.hpp"
#include "tools/score_command.hpp"
#include "tools/simulate_command.hpp"

namespace app = headingd::app;

namespace {

void add_sensor_options(CLI::App* cmd, app::SensorOptions& s) {
  cmd->add_option("--bus", s.bus, "I2C adapter device")->capture_default_str();
  cmd->add_option("--address", s.address, "7-bit address: 0x6A (SA0 low) or 0x6B")->capture_default_str();
  cmd->add_option("--rate", s.rate_hz, "Nominal output rate, Hz: 100, 200, 400, 800")->capture_default_str();
  cmd->add_option("--bandwidth", s.bandwidth, "Bandwidth code 0..3 (at 400 Hz: 20, 25, 50, 110 Hz)")
      ->capture_default_str();
  cmd->add_option("--full-scale", s.full_scale_dps, "Full scale, dps: 245, 500, 2000")->capture_default_str();
  cmd->add_option("--watermark", s.watermark, "FIFO watermark, samples (1..30)")->capture_default_str();
  cmd->add_option("--gpio-chip", s.gpio_chip, "gpiochip of the DRDY/INT2 line (name, path or number); none: poll");
  cmd->add_option("--gpio-line", s.gpio_line, "Line offset of DRDY/INT2 on that chip")->capture_default_str();
  cmd->add_flag("--int2-active-low", s.int2_active_low, "DRDY/INT2 active low (falling edges)");
  // Hidden: the register-level simulator in place of chip, bus and line.
  cmd->add_option("--simulated-chip", s.simulated_chip)->group("");
  cmd->add_option("--sim-seed", s.sim_seed)->group("");
  cmd->add_option("--sim-rate-error", s.sim_rate_error)->group("");
  cmd->add_flag("--sim-realtime", s.sim_realtime)->group("");
  cmd->add_option("--sim-dead-after", s.sim_dead_after_s)->group("");
  cmd->add_option("--sim-nack-at", s.sim_nack_at_s)->group("");
  cmd->add_option("--sim-stuck-at", s.sim_stuck_at_s)->group("");
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App cli{"headingd: gyro heading daemon for AGVs (L3GD20H, stationary-segment bias tracking)"};
  cli.set_version_flag("--version", app::kVersion);
  cli.require_subcommand(1);

  app::ReplayOptions replay;
  auto* replay_cmd = cli.add_subcommand("replay", "Replay a recorded IMU file through the estimator");
  std::vector<std::string> replay_inputs;
  replay_cmd
      ->add_option("input", replay_inputs,
                   "Recording(s): headingd CSV or EuRoC/ASL imu.csv, plain, .zst or .gz; several, or a directory: "
                   "each on its own, one summary table; '-' = standard input (one recording, plain or compressed)")
      ->required();
  app::BatchOptions batch;
  auto* jobs_option = replay_cmd->add_option("--jobs", batch.jobs, "With several recordings: how many at once");
  auto* output_dir_option =
      replay_cmd->add_option("--output-dir", batch.output_dir,
                             "With several recordings: estimates go here (with -r, in the folders they were found in)");
  replay_cmd->add_flag("-r,--recursive", batch.recursive,
                       "Directories: their recordings at every depth, not one level");
  auto* summary_option =
      replay_cmd->add_option("--summary-csv", batch.summary_csv, "With several recordings: the table as CSV too");
  bool join = false;
  replay_cmd->add_flag("--join", join,
                       "Several recordings (or a directory's: a rolling series in the order its files' headers "
                       "give, others by name) as one run, the estimator carrying on from each file into the next; "
                       "with several folders, each folder's runs of the recorder a table row each");
  replay_cmd->add_option("--method", replay.method, "Bias method: auto (default), or the paper's a, b, c");
  replay_cmd->add_option("-o,--output", replay.output, "Estimates CSV ('-' = standard output)");
  replay_cmd->add_option("--output-rate", replay.output_rate_hz, "Rows per second; 0 = every sample")
      ->capture_default_str();
  replay_cmd->add_option("-c,--config", replay.config_path, "TOML configuration file");
  replay_cmd->add_flag("-q,--quiet", replay.quiet, "No summary on stderr");
  replay.publish = true;
  replay_cmd->add_flag("!--no-dds", replay.publish, "Do not publish over DDS (offline mode)");
  replay_cmd->add_option("--speed", replay.speed, "max, realtime, or a factor of real time")->capture_default_str();
  replay_cmd->add_option("--wait-subscribers", replay.wait_subscribers_s,
                         "Wait up to this many seconds for an orientation subscriber before starting");
  replay_cmd->add_option("--linger", replay.linger_s,
                         "Stay this many seconds after the end (late joiners get the latest)");

  std::string replay_plot;
  replay_cmd->add_option("--plot", replay_plot,
                         "Then draw the estimates with `plot` to this .png/.svg (needs -o FILE)");

  app::SimulateOptions simulate;
  auto* simulate_cmd = cli.add_subcommand("simulate", "Simulate a gyro recording with its truth");
  simulate_cmd->add_option("--scenario", simulate.scenario, app::scenario_names())->required();
  simulate_cmd->add_option("--seed", simulate.seed, "Random seed")->capture_default_str();
  simulate_cmd->add_option("--output-dir", simulate.output_dir, "Directory for imu.csv and truth.csv")->required();
  simulate_cmd->add_option("--hours", simulate.hours, "Length in hours (default: the scenario's own)");
  simulate_cmd->add_option("--bias-per-c", simulate.bias_per_c_dps,
                           "Zero-rate change with temperature on every axis, dps/C (default: the scenario's; "
                           "the L3GD20H datasheet's typical figure is +-0.04)");

  app::ScoreOptions score;
  auto* score_cmd = cli.add_subcommand("score", "Score an estimates CSV against a truth CSV (paper's metrics)");
  score_cmd->add_option("estimates", score.estimates, "Estimates CSV from replay")->required();
  score_cmd
      ->add_option(
          "truth", score.truth,
          "truth.csv from simulate, or an orientation truth (time_s,qw,qx,qy,qz[,moving]: motion capture, BROAD; "
          "EuRoC/ASL ground truth)")
      ->required();
  score_cmd->add_option("--label", score.label, "Row label (default: the estimates file's name)");
  score_cmd->add_option("--errors", score.errors_output, "Write time_h,error_deg at 1 Hz to this file");
  score_cmd->add_flag("--header", score.header, "Print the table header first");
  score_cmd->add_option("--recording", score.recording,
                        "The recording replayed: adds the floor (true bias removed while truly moving) and the "
                        "excess over it");

  app::PlotOptions plot;
  auto* plot_cmd = cli.add_subcommand("plot", "Draw heading (+-2 sigma), error against a truth, bias and temperature");
  plot_cmd->add_option("estimates", plot.estimates, "Estimates CSV from replay or run")->required();
  plot_cmd->add_option(
      "--truth", plot.truth,
      "truth.csv from simulate: the truth and the error; or an orientation truth (motion capture, EuRoC): the error");
  plot_cmd->add_option("--recording", plot.recording, "The recording: the sensor temperature");
  plot_cmd->add_option("-o,--output", plot.output, "Picture to write: .png or .svg")->required();

  app::AllanOptions allan;
  auto* allan_cmd = cli.add_subcommand("allan", "Allan deviation of a still recording; noise terms for the config");
  allan_cmd->add_option("input", allan.input, "Recording: headingd CSV or EuRoC/ASL imu.csv")->required();
  allan_cmd->add_option("--axis", allan.axis, "x, y, z or all")->capture_default_str();
  allan_cmd->add_option("--plot", allan.plot_path, "Draw a log-log plot to this PNG (needs gnuplot)");
  allan_cmd->add_flag("--emit-config", allan.emit_config, "Print the estimator settings as a TOML fragment");
  allan_cmd->add_flag("--still-only", allan.still_only,
                      "Use only the segments the auto estimator accepts as still (cuts out motion)");

  app::RunOptions run;
  auto* run_cmd = cli.add_subcommand("run", "Read the gyro ([sensor] kind: L3GD20H or IIO) and estimate heading, live");
  add_sensor_options(run_cmd, run.sensor);
  run_cmd->add_option("-c,--config", run.config_path, "TOML configuration file");
  run_cmd->add_option("--method", run.method, "Bias method: auto (default), or the paper's a, b, c");
  run_cmd->add_option("-o,--output", run.output, "Estimates CSV ('-' = standard output)");
  run_cmd->add_option("--output-rate", run.output_rate_hz, "Rows per second; 0 = every sample")->capture_default_str();
  run_cmd->add_option("--record", run.record_path, "Also record the samples to this native CSV");
  run_cmd->add_option("--record-dir", run.record_dir,
                      "Keep the last hours of samples here, a series of .csv.zst recordings (overrides [record] dir)");
  run_cmd->add_option("--record-split-hours", run.record_split_hours, "With --record-dir: hours per file (default 1)")
      ->check(CLI::Range(0.001, 168.0));
  run_cmd->add_option("--record-keep-hours", run.record_keep_hours, "With --record-dir: hours kept (default 48)")
      ->check(CLI::Range(0.0, 87600.0));
  run_cmd->add_option("--duration", run.duration_s, "Stop after this many seconds (default: at SIGINT/SIGTERM)");
  run_cmd->add_option("--state", run.state_path, "Persisted bias file (overrides [state] path)");
  run_cmd->add_flag("!--no-dds", run.publish, "Do not publish over DDS");
  run_cmd->add_option("--recording", run.recording, "Read this recording instead of the sensor (same pipeline)");
  run_cmd->add_option("--speed", run.speed, "With --recording: max, realtime, or a factor of real time")
      ->capture_default_str();

  app::RunOptions record;
  std::string record_output;
  double record_duration_s = 0.0;
  auto* record_cmd = cli.add_subcommand("record", "Record what the sensor delivers, as a CSV that replays");
  add_sensor_options(record_cmd, record.sensor);
  record_cmd->add_option("-c,--config", record.config_path, "TOML configuration file (its [sensor] section)");
  record_cmd->add_option("-o,--output", record_output, "Native CSV to write")->required();
  record_cmd->add_option("--duration", record_duration_s, "Stop after this many seconds (default: at SIGINT/SIGTERM)");

  app::EchoOptions echo;
  auto* echo_cmd = cli.add_subcommand("echo", "Subscribe to headingd's topics and print one line per message");
  echo_cmd->add_option("topics", echo.topics, "orientation, imu, bias, status, command (default: the first four)");
  echo_cmd->add_flag("--json", echo.json, "One JSON object per line");
  echo_cmd->add_option("--count", echo.count, "Exit after this many messages (exit 69 if --timeout comes first)");
  echo_cmd->add_option("--timeout", echo.timeout_s, "Exit after this many seconds");
  echo_cmd->add_flag("--reliable", echo.reliable, "Reliable orientation/imu reader (needs orientation_reliable)");
  echo_cmd->add_option("-c,--config", echo.config_path, "TOML configuration file (its [dds] section)");

  app::CommandOptions command;
  auto* command_cmd = cli.add_subcommand("command", "Send a HeadingCommand to a running headingd");
  command_cmd->add_option("kind", command.kind, "set-heading, stopped, moving or clear")->required();
  command_cmd->add_option("--heading-deg", command.heading_deg, "For set-heading: the heading, deg");
  command_cmd->add_option("--variance-deg2", command.variance_deg2, "Its variance, deg^2 (0: exact)");
  command_cmd->add_option("--heading-rad", command.heading_rad)->group("");  // raw, for tests
  command_cmd->add_option("--stamp-offset", command.stamp_offset_s)->group("");
  command_cmd->add_option("-c,--config", command.config_path, "TOML configuration file (its [dds] section)");
  command_cmd->add_option("--wait", command.wait_s, "Seconds to wait for headingd to listen")->capture_default_str();

  try {
    cli.parse(argc, argv);
  } catch (const CLI::CallForHelp& help) {
    return cli.exit(help);
  } catch (const CLI::CallForAllHelp& help) {
    return cli.exit(help);
  } catch (const CLI::CallForVersion& version) {
    return cli.exit(version);
  } catch (const CLI::ParseError& error) {
    // A wrong option in a unit's ExecStart: the journal files CLI11's message as an error too.
    if (app::stderr_is_journal()) std::fputs("<3>", stderr);
    cli.exit(error);
    return app::kExitUsage;
  }

  if (replay_cmd->parsed()) {
    const bool batch_options =
        jobs_option->count() > 0 || output_dir_option->count() > 0 || summary_option->count() > 0;
    if (join) {
      if (std::find(replay_inputs.begin(), replay_inputs.end(), "-") != replay_inputs.end()) {
        std::fprintf(stderr, "headingd: --join replays files: '-' does not apply\n");
        return app::kExitUsage;
      }
      const std::vector<app::FoundRecording> found = app::expand_inputs(replay_inputs, batch.recursive, true);
      if (found.empty()) return app::kExitNoInput;
      // One folder's recordings: one run, one replay (-o, --plot). Several folders (a fleet's
      // rolling series, `-r`), or the batch's options: a row per folder, each joined.
      if (batch_options || app::group_by_folder(found).size() > 1) {
        if (!replay_plot.empty() || replay.output != "-") {
          std::fprintf(stderr,
                       "headingd: --join over several folders replays each as one run: -o and --plot do not "
                       "apply (see --output-dir)\n");
          return app::kExitUsage;
        }
        batch.found = found;
        batch.join = true;
        batch.output_rate_hz = replay.output_rate_hz;
        if (const int code = app::batch_settings(replay.config_path, replay.method, batch.settings)) return code;
        return app::run_batch_replay(batch);
      }
      for (const auto& f : found) replay.joined.push_back(f.path);
      replay_inputs = {replay.joined.front()};
    }
    // A directory holding one recording (what `simulate --output-dir` writes, beside its truth),
    // asked for one replay's outputs (-o, --plot): that recording, replayed as the file itself.
    // Without them a directory stays a batch whatever it holds: a fleet's script gets its table
    // on the day only one vehicle's file is there too.
    const bool single_outputs = !replay_plot.empty() || replay.output != "-";
    if (replay_inputs.size() == 1 && std::filesystem::is_directory(replay_inputs.front()) && !batch_options &&
        single_outputs) {
      const std::vector<app::FoundRecording> found = app::expand_inputs(replay_inputs, batch.recursive);
      if (found.empty()) return app::kExitNoInput;
      replay_inputs.clear();
      for (const auto& f : found) replay_inputs.push_back(f.path);
    }
    const bool many =
        !join && (replay_inputs.size() > 1 || std::filesystem::is_directory(replay_inputs.front()) || batch_options);
    if (many) {
      if (!replay_plot.empty() || replay.output != "-") {
        std::fprintf(
            stderr,
            "headingd: with several recordings, -o and --plot do not apply (see --output-dir); nothing is published\n");
        return app::kExitUsage;
      }
      batch.inputs = replay_inputs;
      batch.output_rate_hz = replay.output_rate_hz;
      if (const int code = app::batch_settings(replay.config_path, replay.method, batch.settings)) return code;
      return app::run_batch_replay(batch);
    }
    replay.input =
        replay_inputs.front() == "-" ? std::string("/dev/stdin") : replay_inputs.front();  // `zstdcat … | replay -`
    if (!replay_plot.empty() && replay.output == "-") {
      std::fprintf(stderr, "headingd: replay --plot needs the estimates in a file: add -o FILE\n");
      return app::kExitUsage;
    }
    const int code = app::run_replay(replay);
    if (code != app::kExitOk || replay_plot.empty()) return code;
    return app::run_plot({replay.output, std::nullopt,
                          replay.joined.empty() ? std::optional<std::string>(replay.input) : std::nullopt,
                          replay.joined, replay_plot});
  }
  if (simulate_cmd->parsed()) return app::run_simulate(simulate);
  if (plot_cmd->parsed()) return app::run_plot(plot);
  if (score_cmd->parsed()) return app::run_score(score);
  if (allan_cmd->parsed()) return app::run_allan(allan);
  const auto given = [](const CLI::App* cmd, app::RunOptions& options) {
    for (const auto* option : cmd->get_options())
      if (option->count() > 0)
        for (const auto& name : option->get_lnames()) options.sensor_given.insert("--" + name);
  };
  if (run_cmd->parsed()) {
    // A daemon can be stopped while it is still opening its sensor and joining DDS (systemd
    // stops a unit whenever it likes): from here on SIGTERM ends it through the same shutdown.
    app::install_stop_signals();
    given(run_cmd, run);
    return app::run_live(run);
  }
  if (echo_cmd->parsed()) return app::run_echo(echo);
  if (command_cmd->parsed()) return app::run_command(command);
  if (record_cmd->parsed()) {
    app::install_stop_signals();
    given(record_cmd, record);
    return app::run_record(record, record_output, record_duration_s);
  }
  return app::kExitUsage;
}
