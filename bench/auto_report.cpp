// Method `auto` against the paper's best (C) on every simulator scenario and several seeds:
// heading error (the paper's metrics), stillness classification on slow rotation, honesty
// of the reported sigma, and the heading held through a 4 h stop. Runs the simulator and
// both estimators in memory (the same core the replay path uses).
// Usage: auto_report [--seeds 1,2,3] [--scenarios paper12h,creep,thermal,still,agv] [--hours H]
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "core/estimator.hpp"
#include "core/heading_metrics.hpp"
#include "machine.hpp"
#include "pipeline/pipeline.hpp"
#include "sim/simulated_source.hpp"

using namespace headingd;

namespace {

// Rate bands for the classification table, dps.
constexpr std::array<double, 5> kBands{0.02, 0.05, 0.1, 0.2, 0.5001};
constexpr double kCreepThresholdDps = 0.05;

struct Classification {
  // Segments lying wholly in one truth state: still, or turning at a rate in a band.
  std::uint64_t still = 0, still_rejected = 0;
  std::array<std::uint64_t, kBands.size()> moving{}, moving_detected{};
};

// Per-method bookkeeping while a run goes on: a sink beside the estimator it scores, reading
// the truth of each sample from the simulated source.
struct Run final : public pipeline::Sink {
  Run(const drivers::SimulatedSource& simulated, std::uint64_t score_every) : source(simulated), every(score_every) {}
  const drivers::SimulatedSource& source;
  std::uint64_t every;       // score one sample in this many (10 Hz)
  std::uint64_t index = 0;   // of the sample, over the run
  std::size_t in_batch = 0;  // of the sample in the source's last batch
  core::HeadingMetrics metrics;
  std::uint64_t honest = 0, judged = 0;
  Classification classes;
  // Truth over the segment under way.
  std::uint64_t seg_samples = 0, seg_still = 0, seg_moving = 0;
  double seg_min_rate = 1e9, seg_max_rate = 0.0;

  void add(const core::Sample& sample, const core::Estimate& estimate, const core::Estimator& estimator) override;
  void batch_done(const core::Estimator& /*estimator*/, const core::SampleSource& /*source*/) override { in_batch = 0; }
};

void close_segment(Run& run, bool accepted) {
  Classification& c = run.classes;
  if (run.seg_samples >= 200) {  // ignore cut-off fragments (< 0.5 s)
    if (run.seg_still == run.seg_samples) {
      ++c.still;
      c.still_rejected += accepted ? 0 : 1;
    } else if (run.seg_moving == run.seg_samples) {
      for (std::size_t band = 0; band + 1 < kBands.size(); ++band) {
        if (run.seg_min_rate >= kBands[band] && run.seg_max_rate < kBands[band + 1]) {
          ++c.moving[band];
          c.moving_detected[band] += accepted ? 0 : 1;
        }
      }
    }
  }
  run.seg_samples = run.seg_still = run.seg_moving = 0;
  run.seg_min_rate = 1e9;
  run.seg_max_rate = 0.0;
}

void Run::add(const core::Sample& /*sample*/, const core::Estimate& estimate, const core::Estimator& /*estimator*/) {
  const drivers::TruthPoint& truth = source.truth()[in_batch++];
  const bool output = index++ % every == 0;
  if (estimate.closed.closed) close_segment(*this, estimate.closed.accepted);
  ++seg_samples;
  const double rate = std::abs(truth.rate_z_dps);
  if (!truth.moving) ++seg_still;
  if (truth.moving && rate > 0.0) {
    ++seg_moving;
    seg_min_rate = std::min(seg_min_rate, rate);
    seg_max_rate = std::max(seg_max_rate, rate);
  }
  if (!output) return;
  const double error = truth.heading_deg - estimate.heading_deg;
  metrics.add(truth.t_s, error);
  if (std::isfinite(estimate.heading_sigma_deg)) {
    ++judged;
    honest += std::abs(error) <= 2.0 * estimate.heading_sigma_deg + 1e-12 ? 1u : 0u;
  }
}

// One method over one simulated world, through the daemon's pipeline.
Run run_method(const drivers::Scenario& scenario, std::uint64_t seed, core::Method method) {
  drivers::SimulatedSource source(scenario, seed);
  core::EstimatorSettings settings;
  settings.method = method;
  pipeline::Pipeline line(source, std::make_unique<core::Estimator>(settings), {});
  Run run(source, static_cast<std::uint64_t>(scenario.noise.rate_hz / 10.0));
  line.add_sink(run);
  line.run();
  return run;
}

struct Row {
  std::string scenario;
  std::uint64_t seed;
  core::HeadingMetrics c, automatic;
  double honest_fraction;
  std::uint64_t honest, judged;
  Classification c_classes, auto_classes;
};

std::vector<std::string> split(const std::string& text) {
  std::vector<std::string> items;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) items.push_back(item);
  return items;
}

double pct(std::uint64_t part, std::uint64_t whole) {
  return whole ? 100.0 * static_cast<double>(part) / static_cast<double>(whole) : NAN;
}

void add(Classification& into, const Classification& c) {
  into.still += c.still;
  into.still_rejected += c.still_rejected;
  for (std::size_t b = 0; b < kBands.size(); ++b) {
    into.moving[b] += c.moving[b];
    into.moving_detected[b] += c.moving_detected[b];
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> seeds{"1", "2", "3"};
  std::vector<std::string> scenarios{"paper12h", "creep", "thermal", "still", "agv"};
  double hours = 0.0;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag == "--seeds")
      seeds = split(argv[i + 1]);
    else if (flag == "--scenarios")
      scenarios = split(argv[i + 1]);
    else if (flag == "--hours" && std::strtod(argv[i + 1], nullptr) > 0.0)
      hours = std::strtod(argv[i + 1], nullptr);
    else {
      std::fprintf(stderr, "usage: auto_report [--seeds 1,2,3] [--scenarios a,b] [--hours H]\n");
      return 64;
    }
  }
  std::printf("machine: %s\n\n", bench::machine_description().c_str());

  std::vector<Row> rows;
  for (const auto& name : scenarios) {
    for (const auto& seed_text : seeds) {
      const auto seed = static_cast<std::uint64_t>(std::stoull(seed_text));
      auto scenario = drivers::build_scenario(name, seed, hours);
      if (!scenario) {
        std::fprintf(stderr, "unknown scenario %s\n", name.c_str());
        return 64;
      }
      const Run c = run_method(*scenario, seed, core::Method::C);
      const Run automatic = run_method(*scenario, seed, core::Method::Auto);
      rows.push_back(Row{name, seed, c.metrics, automatic.metrics, pct(automatic.honest, automatic.judged),
                         automatic.honest, automatic.judged, c.classes, automatic.classes});
      std::fflush(stdout);
    }
  }

  std::printf("Heading error, E = truth - estimate (deg; drift = final |E| per hour)\n");
  std::printf("%-9s %4s %6s | %8s %8s %8s %8s | %8s %8s %8s %8s | %7s %s\n", "scenario", "seed", "hours", "C max",
              "C final", "C RMS", "C drift", "auto max", "final", "RMS", "drift", "|E|<2s", "auto/C max");
  bool never_worse = true;
  for (const auto& r : rows) {
    const double ratio = r.automatic.max_abs_deg() / r.c.max_abs_deg();
    never_worse =
        never_worse && r.automatic.max_abs_deg() <= r.c.max_abs_deg() && r.automatic.rms_deg() <= r.c.rms_deg();
    std::printf("%-9s %4llu %6.1f | %8.2f %8.2f %8.2f %8.3f | %8.2f %8.2f %8.2f %8.3f | %6.1f%% %.2f\n",
                r.scenario.c_str(), static_cast<unsigned long long>(r.seed), r.c.hours(), r.c.max_abs_deg(),
                r.c.final_abs_deg(), r.c.rms_deg(), r.c.drift_deg_per_h(), r.automatic.max_abs_deg(),
                r.automatic.final_abs_deg(), r.automatic.rms_deg(), r.automatic.drift_deg_per_h(), r.honest_fraction,
                ratio);
  }
  std::printf("auto never worse than C (max and RMS) on every scenario and seed: %s\n\n", never_worse ? "yes" : "NO");

  Classification c_all, auto_all;
  for (const auto& r : rows) {
    add(c_all, r.c_classes);
    add(auto_all, r.auto_classes);
  }
  std::printf("Stillness classification, all runs (segments lying wholly in one truth state)\n");
  std::printf("%-28s %10s %12s %10s %12s\n", "truth", "C segs", "C says moving", "auto segs", "auto says moving");
  for (std::size_t b = 0; b + 1 < kBands.size(); ++b) {
    char label[64];
    std::snprintf(label, sizeof label, "turning %.2f-%.2f dps", kBands[b], std::min(kBands[b + 1], 0.5));
    std::printf("%-28s %10llu %11.1f%% %10llu %11.1f%%\n", label, static_cast<unsigned long long>(c_all.moving[b]),
                pct(c_all.moving_detected[b], c_all.moving[b]), static_cast<unsigned long long>(auto_all.moving[b]),
                pct(auto_all.moving_detected[b], auto_all.moving[b]));
  }
  std::uint64_t c_fast = 0, c_fast_hit = 0, a_fast = 0, a_fast_hit = 0;
  for (std::size_t b = 0; b + 1 < kBands.size(); ++b) {
    if (kBands[b] < kCreepThresholdDps) continue;
    c_fast += c_all.moving[b];
    c_fast_hit += c_all.moving_detected[b];
    a_fast += auto_all.moving[b];
    a_fast_hit += auto_all.moving_detected[b];
  }
  std::printf("%-28s %10llu %11.1f%% %10llu %11.1f%%\n", "turning >= 0.05 dps", static_cast<unsigned long long>(c_fast),
              pct(c_fast_hit, c_fast), static_cast<unsigned long long>(a_fast), pct(a_fast_hit, a_fast));
  std::printf("%-28s %10llu %11.1f%% %10llu %11.1f%%   (still segments rejected)\n", "still",
              static_cast<unsigned long long>(c_all.still), pct(c_all.still_rejected, c_all.still),
              static_cast<unsigned long long>(auto_all.still), pct(auto_all.still_rejected, auto_all.still));

  std::uint64_t honest_runs = 0, honest_all = 0, judged_all = 0;
  double lo = 100.0, hi = 0.0;
  for (const auto& r : rows) {
    honest_all += r.honest;
    judged_all += r.judged;
    lo = std::min(lo, r.honest_fraction);
    hi = std::max(hi, r.honest_fraction);
    honest_runs += (r.honest_fraction >= 90.0 && r.honest_fraction <= 99.0) ? 1u : 0u;
  }
  std::printf(
      "\nHonest sigma: |E| <= 2 sigma in %.1f%% .. %.1f%% of output samples per run; %llu of %zu runs within 90-99%%\n",
      lo, hi, static_cast<unsigned long long>(honest_runs), rows.size());
  std::printf("Honest sigma over all runs together: |E| <= 2 sigma in %.1f%% of %llu output samples (target 90-99%%)\n",
              pct(honest_all, judged_all), static_cast<unsigned long long>(judged_all));
  return 0;
}
