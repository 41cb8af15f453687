#pragma once
// What `run`, `replay` and `record` share once their source is open: the pipeline with its
// sinks, built in start-up order, run, taken down in reverse, summarised. The commands differ
// only in the source they open and the defaults they give these options.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/estimator.hpp"
#include "core/sample_source.hpp"
#include "dds/dds_settings.hpp"
#include "pipeline/rolling_recording_sink.hpp"

namespace headingd::app {

struct JobOptions {
  // For a recording: how much of it has been read (a progress line on a terminal); unset for a sensor.
  std::function<std::optional<double>()> progress;
  std::string command;  // names the summary: "run", "replay", "record"
  core::EstimatorSettings settings = core::kDefaultEstimatorSettings;
  std::vector<std::string> input_paths;  // the recordings read, if any: never written to
  std::optional<std::string> output;     // estimates CSV ("-": standard output)
  double output_rate_hz = 10.0;
  std::optional<std::string> record_path;  // native CSV of the samples
  std::string record_comments;             // its '#' provenance lines
  pipeline::RollingSettings rolling;       // the last hours of samples, a series of recordings (dir "" = none)
  std::optional<std::string> state_path;
  double state_save_interval_s = 60.0;
  bool state_restore_heading = true;
  bool publish = false;  // DDS
  // With DDS on, a file output (recording, estimates) that cannot be written is dropped and the
  // run goes on publishing (pipeline/expendable_sink): `run`. Otherwise it ends the run (exit 73).
  bool files_expendable = false;
  DdsSettings dds;
  double speed_factor = 0.0;  // recordings: 0 as fast as possible, else a factor of real time
  std::size_t batch = 64;
  double duration_s = 0.0;          // 0: to the end, or a signal
  double wait_subscribers_s = 0.0;  // before the first sample
  double linger_s = 0.0;            // after the last
  bool quiet = false;               // no summary
  // SIGHUP reloads this file (estimator settings and log level); the method option still wins.
  std::optional<std::string> config_path;
  std::optional<std::string> method;
};

// Sets the output rate and the pacing from --output-rate and --speed; 0, or the exit code
// after saying on stderr what is wrong.
int set_rate_and_speed(double output_rate_hz, const std::string& speed, JobOptions& job);

// Runs the job to its end; returns the process exit code (0 also after a signal; 65 bad input,
// 73 output failure, 74 a dead sensor, 70 DDS could not start).
int run_job(core::SampleSource& source, const JobOptions& options);

}  // namespace headingd::app
