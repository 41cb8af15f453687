#include "tools/allan_command.hpp"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <vector>

#include "core/allan.hpp"
#include "core/estimator.hpp"
#include "io/atomic_file.hpp"
#include "io/csv_out.hpp"
#include "io/csv_replay.hpp"
#include "pipeline/pipeline.hpp"
#include "service/exit_codes.hpp"
#include "service/input_errors.hpp"
#include "service/standard_output.hpp"
#include "tools/gnuplot.hpp"

namespace headingd::app {
namespace {

constexpr const char* kAxisNames[3] = {"x", "y", "z"};

struct Recording {
  std::array<std::vector<double>, 3> rate_dps;
  double period_s = 0.0;
  double sigma_still_sum[3] = {0, 0, 0};  // per-sample variance summed over 3 s blocks
  std::size_t sigma_blocks = 0;
  std::size_t samples = 0;        // every sample read
  std::size_t samples_still = 0;  // of which in segments the auto estimator accepted as still
};

// Keeps every sample, or with still_only only those in segments the auto estimator accepts
// (turns cut out, the still stretches joined).
class Collector final : public pipeline::Sink {
 public:
  Collector(Recording& rec, bool still_only) : rec_(rec), still_only_(still_only) {}
  void add(const core::Sample& s, const core::Estimate& estimate, const core::Estimator& /*estimator*/) override {
    if (std::isfinite(previous_t_) && periods.size() < 100000) periods.push_back(s.t_s - previous_t_);
    previous_t_ = s.t_s;
    ++rec_.samples;
    // The samples before the one that closes a segment are that segment's.
    if (estimate.closed.closed) {
      const bool still = estimate.closed.accepted && estimate.closed.index == pending_segment_;
      if (still) rec_.samples_still += pending_count_;
      if (still && still_only_)
        for (const auto& p : pending_) keep(p);
      pending_.clear();
      pending_count_ = 0;
    }
    pending_segment_ = estimate.segment_index;
    ++pending_count_;
    if (still_only_)
      pending_.push_back(s);
    else
      keep(s);
  }
  std::vector<double> periods;

 private:
  void keep(const core::Sample& s) {
    for (int a = 0; a < 3; ++a) rec_.rate_dps[static_cast<std::size_t>(a)].push_back(s.rate_dps[a]);
  }
  Recording& rec_;
  bool still_only_;
  std::vector<core::Sample> pending_;
  double previous_t_ = NAN;
  std::uint64_t pending_segment_ = 0;
  std::size_t pending_count_ = 0;
};

// Reads the recording through the pipeline; throws what stopped it (InputError at a bad line).
Recording read_recording(drivers::CsvReplaySource& source, bool still_only) {
  Recording rec;
  pipeline::PipelineOptions options;
  options.batch = 4096;
  pipeline::Pipeline line(source, std::make_unique<core::Estimator>(), options);
  Collector collector(rec, still_only);
  line.add_sink(collector);
  const pipeline::Outcome outcome = line.run();
  if (outcome.exception) std::rethrow_exception(outcome.exception);
  std::vector<double>& periods = collector.periods;
  if (!periods.empty()) {
    std::nth_element(periods.begin(), periods.begin() + static_cast<long>(periods.size() / 2), periods.end());
    rec.period_s = periods[periods.size() / 2];
  }
  // Per-sample sigma of still data: the mean variance within 3 s blocks.
  const auto block = static_cast<std::size_t>(std::max(2.0, std::round(3.0 / std::max(rec.period_s, 1e-6))));
  for (std::size_t start = 0; start + block <= rec.rate_dps[0].size(); start += block) {
    for (int a = 0; a < 3; ++a) {
      const auto& x = rec.rate_dps[static_cast<std::size_t>(a)];
      double mean = 0.0, sq = 0.0;
      for (std::size_t i = start; i < start + block; ++i) mean += x[i];
      mean /= static_cast<double>(block);
      for (std::size_t i = start; i < start + block; ++i) sq += (x[i] - mean) * (x[i] - mean);
      rec.sigma_still_sum[a] += sq / static_cast<double>(block - 1);
    }
    ++rec.sigma_blocks;
  }
  return rec;
}

// Draws the curves with gnuplot (tools/gnuplot: data in a private directory under fixed names,
// the script ours, the picture written to `path` by us). Empty when drawn, else why not.
std::optional<std::string> draw_plot(const std::string& path, const std::vector<int>& axes,
                                     const std::array<std::vector<core::AllanPoint>, 3>& curves) {
  std::string data;
  char line[64];
  for (int a : axes) {
    for (const auto& p : curves[static_cast<std::size_t>(a)]) {
      std::snprintf(line, sizeof line, "%.9g %.9g\n", p.tau_s, p.deviation);
      data += line;
    }
    data += "\n\n";
  }
  std::string script =
      "set terminal pngcairo size 800,560 font ',10'\nset output 'allan.png'\nset logscale xy\n"
      "set grid xtics ytics mxtics mytics\nset xlabel 'cluster time tau [s]'\n"
      "set ylabel 'Allan deviation [deg/s]'\nset title 'Allan deviation'\nplot ";
  for (std::size_t i = 0; i < axes.size(); ++i)
    script += std::string(i ? ", " : "") + "'allan.dat' index " + std::to_string(i) +
              " with linespoints pt 7 ps 0.5 title '" + kAxisNames[axes[i]] + "'";
  script += "\n";
  return draw_with_gnuplot({{"allan.dat", data}}, script, "allan.png", path);
}

}  // namespace

int run_allan(const AllanOptions& options) {
  std::vector<int> axes;
  if (options.axis == "all")
    axes = {0, 1, 2};
  else if (options.axis == "x")
    axes = {0};
  else if (options.axis == "y")
    axes = {1};
  else if (options.axis == "z")
    axes = {2};
  else {
    std::fprintf(stderr, "headingd: --axis: '%s' is not x, y, z or all\n", options.axis.c_str());
    return kExitUsage;
  }

  Recording rec;
  if (const int code = report_input_errors([&] {
        drivers::CsvReplaySource source(options.input);
        rec = read_recording(source, options.still_only);
      }))
    return code;
  // A curve of a recording that mostly moves measures the motion, not the sensor: say so.
  if (!options.still_only && rec.samples > 0 && 10 * (rec.samples - rec.samples_still) > rec.samples)
    std::fprintf(stderr,
                 "headingd: %s: %.0f %% of the samples lie outside the segments the auto estimator took for "
                 "still; motion shapes the curve below (--still-only keeps the still ones)\n",
                 options.input.c_str(),
                 100.0 * static_cast<double>(rec.samples - rec.samples_still) / static_cast<double>(rec.samples));
  const std::size_t n = rec.rate_dps[0].size();
  const auto clusters = core::log_spaced_clusters(n);
  if (clusters.size() < 3 || !(rec.period_s > 0.0)) {
    std::fprintf(stderr, "headingd: %s: too few%s samples for an Allan analysis (%zu)\n", options.input.c_str(),
                 options.still_only ? " still" : "", n);
    return kExitDataError;
  }

  std::array<std::vector<core::AllanPoint>, 3> curves;
  std::array<core::NoiseTerms, 3> terms;
  for (int a : axes) {
    const auto i = static_cast<std::size_t>(a);
    curves[i] = core::allan_deviation(rec.rate_dps[i], rec.period_s, clusters);
    terms[i] = core::read_noise_terms(curves[i]);
  }

  std::printf("# Allan deviation of %s: %zu%s samples, period %.6f s (%.1f h)\n", options.input.c_str(), n,
              options.still_only ? " still" : "", rec.period_s, static_cast<double>(n) * rec.period_s / 3600.0);
  std::printf("%12s", "tau_s");
  for (int a : axes) std::printf(" %14s", (std::string("adev_") + kAxisNames[a] + "_dps").c_str());
  std::printf("\n");
  for (std::size_t k = 0; k < curves[static_cast<std::size_t>(axes[0])].size(); ++k) {
    std::printf("%12.4f", curves[static_cast<std::size_t>(axes[0])][k].tau_s);
    for (int a : axes) std::printf(" %14.6e", curves[static_cast<std::size_t>(a)][k].deviation);
    std::printf("\n");
  }
  std::printf("\n");
  for (int a : axes) {
    const auto& t = terms[static_cast<std::size_t>(a)];
    std::printf(
        "%s: angle random walk %.5f dps/sqrt(Hz) (%.3f deg/sqrt(h)); bias instability %.5f dps (%.2f deg/h) "
        "at tau %.*f s; rate random walk ",
        kAxisNames[a], t.arw, t.arw * 60.0, t.bias_instability, t.bias_instability * 3600.0,
        // A minimum at milliseconds (motion in the recording) printed as "tau 0 s" before.
        t.tau_at_minimum_s < 1.0 ? 4 : (t.tau_at_minimum_s < 10.0 ? 2 : 0), t.tau_at_minimum_s);
    if (t.rate_random_walk)
      std::printf("%.3g dps/sqrt(s)\n", *t.rate_random_walk);
    else
      std::printf("not reached (recording too short)\n");
  }

  if (options.emit_config) {
    // Only what `--config` accepts is printed as a setting (positive and finite, the bias walk
    // within [0, 1]); a figure this recording cannot give is printed as a comment saying why.
    const auto usable = [](double v, double hi) { return std::isfinite(v) && v > 0.0 && v <= hi; };
    std::printf("\n# headingd estimator settings from this recording's noise\n[estimator]\n");
    std::array<double, 3> sigma{};
    bool sigma_ok = rec.sigma_blocks > 0;
    for (std::size_t a = 0; a < 3; ++a) {
      sigma[a] = rec.sigma_blocks ? std::sqrt(rec.sigma_still_sum[a] / static_cast<double>(rec.sigma_blocks)) : 0.0;
      sigma_ok = sigma_ok && usable(sigma[a], 100.0);
    }
    if (sigma_ok)
      std::printf("sigma_still_dps = [%.6g, %.6g, %.6g]\n", sigma[0], sigma[1], sigma[2]);
    else
      std::printf("# sigma_still_dps: not measurable here (no still stretch with noise on every axis)\n");
    std::printf("\n[estimator.auto]\n");
    if (axes.size() != 3)
      std::printf("# arw_dps_rt_hz needs all three axes (--axis all)\n");
    else if (usable(terms[0].arw, 10.0) && usable(terms[1].arw, 10.0) && usable(terms[2].arw, 10.0))
      std::printf("arw_dps_rt_hz = [%.6g, %.6g, %.6g]\n", terms[0].arw, terms[1].arw, terms[2].arw);
    else
      std::printf("# arw_dps_rt_hz: not measurable here (a noiseless or too short axis)\n");
    // The bias may wander by the bias instability within the time the curve's minimum takes:
    // a random walk of density K reaches sigma = K sqrt(tau / 3) at tau.
    const auto& z = terms[static_cast<std::size_t>(axes.back())];
    const double walk = z.rate_random_walk.value_or(z.bias_instability * 0.664 * std::sqrt(3.0 / z.tau_at_minimum_s));
    if (usable(walk, 1.0))
      std::printf("bias_walk_dps_rt_s = %.6g\n", walk);
    else
      std::printf(
          "# bias_walk_dps_rt_s: %.3g from this recording is outside what a still gyro does (0, 1]; "
          "keep the default\n",
          walk);
  }

  if (options.plot_path) {
    if (const auto problem = draw_plot(*options.plot_path, axes, curves)) {
      std::fprintf(stderr, "headingd: could not draw %s: %s\n", options.plot_path->c_str(), problem->c_str());
      return kExitCantCreate;
    }
    std::fprintf(stderr, "headingd allan: plot written to %s\n", options.plot_path->c_str());
  }
  return finish_standard_output();
}

}  // namespace headingd::app
