// Heading fixes in the randomized worlds (issue 12): does `auto` learn each world's scale error
// from them? For each seed (`simulate --scenario random`), a fix from the truth (variance
// 0.01 deg^2) at the first stop FIX_EVERY seconds after the last one, given to `auto` twice:
// once with the worlds' scale spread configured (scale_factor_sigma = 0.5 % / sqrt(3), the fixes
// teach the scale) and once with scale_factor_sigma = 0 (nothing learned). Printed per seed: the
// world's scale error, the learned one with its sigma, the median |error| just before a fix for
// both, and the share of 10 Hz outputs within 2 sigma (learning run; errors as directions,
// modulo 360 degrees); then the summary.
// Usage: scale_fixes [SEEDS (200)] [HOURS (2)] [FIX_EVERY_S (600)] [FIRST_SEED (1)]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "core/estimator.hpp"
#include "seed_pool.hpp"
#include "sim/gyro_simulator.hpp"

using namespace headingd;

namespace {

constexpr double kFixVarianceDeg2 = 0.01;
constexpr double kScaleSpread = 0.005;  // the random worlds draw it evenly within +-0.5 %

struct SeedResult {
  std::uint64_t seed = 0;
  double true_scale = 0.0, learned = 0.0, learned_sigma = 0.0;
  std::vector<double> before_fix_learning, before_fix_plain;  // |E| just before each fix, deg
  double within_two_sigma = 0.0;
  std::uint64_t within = 0, outputs = 0;  // the 10 Hz outputs within 2 sigma, of all
};

// A fix names a direction (the estimator takes its equivalent nearest its own heading), so the
// error is scored as a direction too: a run whose bias went wrong by whole turns before a fix
// stays whole turns off in the unwrapped heading, and that is not what a fix can mend.
double direction_error_deg(double truth_deg, double estimate_deg) {
  return std::abs(std::remainder(truth_deg - estimate_deg, 360.0));
}

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

SeedResult run_seed(std::uint64_t seed, double hours, double fix_every_s) {
  drivers::GyroSimulator sim(*drivers::build_scenario("random", seed, hours), seed);
  SeedResult r;
  r.seed = seed;
  r.true_scale = sim.scenario().noise.scale_factor_error;
  core::EstimatorSettings learning_settings, plain_settings;
  learning_settings.automatic.scale_factor_sigma = kScaleSpread / std::sqrt(3.0);
  plain_settings.automatic.scale_factor_sigma = 0.0;
  core::Estimator learning(learning_settings), plain(plain_settings);
  const auto every =
      std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::llround(sim.scenario().noise.rate_hz / 10.0)));
  core::Sample sample;
  drivers::TruthPoint truth;
  double last_fix_s = 0.0;
  std::uint64_t& within = r.within;
  std::uint64_t& outputs = r.outputs;
  for (std::uint64_t i = 0; !sim.done(); ++i) {
    sim.step(sample, truth);
    const core::Estimate& a = learning.update(sample);
    const core::Estimate& b = plain.update(sample);
    if (!truth.moving && !a.in_startup && sample.t_s - last_fix_s >= fix_every_s) {
      r.before_fix_learning.push_back(direction_error_deg(truth.heading_deg, a.heading_deg));
      r.before_fix_plain.push_back(direction_error_deg(truth.heading_deg, b.heading_deg));
      learning.set_heading(truth.heading_deg, kFixVarianceDeg2);
      plain.set_heading(truth.heading_deg, kFixVarianceDeg2);
      last_fix_s = sample.t_s;
    }
    if (i % every != 0) continue;
    const core::Estimate& now = learning.last();
    within += direction_error_deg(truth.heading_deg, now.heading_deg) <= 2.0 * now.heading_sigma_deg;
    ++outputs;
  }
  r.learned = learning.automatic()->scale().estimate();
  r.learned_sigma = learning.automatic()->scale().sigma();
  r.within_two_sigma = outputs > 0 ? static_cast<double>(within) / static_cast<double>(outputs) : 0.0;
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  const long seeds = argc > 1 ? std::strtol(argv[1], nullptr, 10) : 200;
  const double hours = argc > 2 ? std::strtod(argv[2], nullptr) : 2.0;
  const double fix_every_s = argc > 3 ? std::strtod(argv[3], nullptr) : 600.0;
  const long first_seed = argc > 4 ? std::strtol(argv[4], nullptr, 10) : 1;
  if (seeds < 1 || !(hours > 0.0) || !(fix_every_s > 0.0) || first_seed < 1) {
    std::fprintf(stderr, "usage: scale_fixes [SEEDS (200)] [HOURS (2)] [FIX_EVERY_S (600)] [FIRST_SEED (1)]\n");
    return 64;
  }
  const std::vector<SeedResult> results = bench::run_seeds<SeedResult>(
      seeds, first_seed, [&](std::uint64_t seed) { return run_seed(seed, hours, fix_every_s); });

  std::printf("%5s %8s %8s %7s %5s | %12s %12s | %7s\n", "seed", "scale %", "learned", "sigma", "fixes", "|E| learning",
              "|E| plain", "in 2sig");
  std::vector<double> all_learning, all_plain, scale_errors;
  int scale_within = 0, honest = 0, below_60 = 0, above_band = 0;
  std::uint64_t pooled_within = 0, pooled_outputs = 0;
  for (const SeedResult& r : results) {
    std::printf("%5llu %+8.3f %+8.3f %7.3f %5zu | %12.3f %12.3f | %6.1f%%\n", static_cast<unsigned long long>(r.seed),
                100.0 * r.true_scale, 100.0 * r.learned, 100.0 * r.learned_sigma, r.before_fix_learning.size(),
                median(r.before_fix_learning), median(r.before_fix_plain), 100.0 * r.within_two_sigma);
    // The first fix finds what the scale did before anything was learned: not counted.
    all_learning.insert(all_learning.end(),
                        r.before_fix_learning.begin() + std::min<std::ptrdiff_t>(1, std::ssize(r.before_fix_learning)),
                        r.before_fix_learning.end());
    all_plain.insert(all_plain.end(),
                     r.before_fix_plain.begin() + std::min<std::ptrdiff_t>(1, std::ssize(r.before_fix_plain)),
                     r.before_fix_plain.end());
    scale_errors.push_back(std::abs(r.learned - r.true_scale));
    scale_within += std::abs(r.learned - r.true_scale) <= 2.0 * r.learned_sigma;
    honest += r.within_two_sigma >= 0.85 && r.within_two_sigma <= 0.995;
    below_60 += r.within_two_sigma < 0.6;
    above_band += r.within_two_sigma > 0.995;
    pooled_within += r.within;
    pooled_outputs += r.outputs;
  }
  std::printf("\n%ld seeds of %.1f h, a fix from the truth at the first stop %.0f s after the last:\n", seeds, hours,
              fix_every_s);
  std::printf(
      "|E| just before a fix (all but each seed's first), median: %.3f deg learning the scale, %.3f deg not "
      "(%zu fixes)\n",
      median(all_learning), median(all_plain), all_learning.size());
  std::printf("learned scale against the world's: median |error| %.3f %%; within 2 sigma on %d of %ld seeds\n",
              100.0 * median(scale_errors), scale_within, seeds);
  std::printf(
      "sigma honesty with fixes: %d of %ld seeds with 85-99.5 %% of outputs within 2 sigma (%d below 60 %%, %d above "
      "99.5 %%), %.1f %% of all outputs\n",
      honest, seeds, below_60, above_band,
      100.0 * static_cast<double>(pooled_within) / static_cast<double>(std::max<std::uint64_t>(1, pooled_outputs)));
  return 0;
}
