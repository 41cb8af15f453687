#include "sim/own_model_world.hpp"

#include <cmath>
#include <random>
#include <vector>

#include "core/axis_filter.hpp"

namespace headingd::drivers {

namespace {

constexpr double kStepS = 0.1;             // the filter's step and the scored output rate, 10 Hz
constexpr int kStepsPerSegment = 30;       // a 3 s still segment measures the bias
constexpr double kInitialBiasSigma = 0.5;  // dps: the filter's prior, and the truth drawn from it

struct Leg {
  double duration_s;
  double rate_dps;  // the true turn rate; 0 for a stop
  bool still;
};

// The random scenario's motion (sim/scenarios.cpp, build_random) without what the filter's
// model leaves out (vibration, a conveyor: neither changes the integrated errors here).
std::vector<Leg> draw_legs(std::mt19937_64& rng, double duration_s) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const auto between = [&](double lo, double hi) { return lo + (hi - lo) * unit(rng); };
  const auto log_between = [&](double lo, double hi) { return lo * std::pow(hi / lo, unit(rng)); };
  const auto sign = [&] { return unit(rng) < 0.5 ? -1.0 : 1.0; };
  std::vector<Leg> legs;
  double elapsed_s = 0.0;
  const auto add = [&](double d, double rate, bool still) {
    legs.push_back({d, rate, still});
    elapsed_s += d;
  };
  if (unit(rng) < 0.15) add(between(2.0, 20.0), sign() * log_between(0.05, 20.0), false);
  add(log_between(3.0, 60.0), 0.0, true);
  while (elapsed_s < duration_s) {
    const int pieces = 1 + static_cast<int>(unit(rng) * 6.0);
    for (int piece = 0; piece < pieces; ++piece) {
      const double kind = unit(rng);
      if (kind < 0.45) {
        add(between(3.0, 60.0), between(-0.3, 0.3), false);
      } else if (kind < 0.85) {
        const double rate_dps = log_between(2.0, 60.0);
        add(between(5.0, 180.0) / rate_dps, sign() * rate_dps, false);
      } else {
        add(between(10.0, 120.0), sign() * log_between(0.02, 0.5), false);
      }
    }
    add(log_between(1.0, 1800.0), 0.0, true);
  }
  return legs;
}

}  // namespace

OwnModelRun run_in_own_model_world(std::uint64_t seed, const OwnModelSettings& settings) {
  std::mt19937_64 rng(seed * 0x9E3779B97F4A7C15ULL + 29);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const auto log_between = [&](double lo, double hi) { return lo * std::pow(hi / lo, unit(rng)); };

  const double noise_dps_rt_hz = log_between(0.004, 0.02);
  const double walk_dps_rt_s = log_between(1e-5, 1e-4);
  const double white = noise_dps_rt_hz * noise_dps_rt_hz;
  const double walk = walk_dps_rt_s * walk_dps_rt_s;
  const double segment_variance = white / (kStepsPerSegment * kStepS);
  const double scale_error = settings.scale_sigma * gauss(rng);
  double bias_dps = kInitialBiasSigma * gauss(rng);
  const std::vector<Leg> legs = draw_legs(rng, settings.hours * 3600.0);

  core::AxisFilter filter;
  filter.reset(0.0, kInitialBiasSigma * kInitialBiasSigma);
  core::AxisFilter::Plain state = filter.plain();
  double true_angle_deg = 0.0;
  const auto total_steps = static_cast<long long>(std::llround(settings.hours * 3600.0 / kStepS));
  long long step = 0;
  OwnModelRun run;
  for (const Leg& leg : legs) {
    const auto leg_steps = static_cast<long long>(leg.duration_s / kStepS);
    for (long long i = 0; i < leg_steps && step < total_steps; ++i, ++step) {
      // The measured rate exactly as the filter models it: white noise of density N (variance
      // N^2 / dt per step, so N^2 dt in the angle), the bias, the scale error on the true rate.
      const double noise = noise_dps_rt_hz / std::sqrt(kStepS) * gauss(rng);
      const double measured = (1.0 + scale_error) * leg.rate_dps + bias_dps + noise;
      core::AxisFilter::propagate(state, measured, kStepS, white, settings.filter_walk_factor * walk);
      true_angle_deg += leg.rate_dps * kStepS;
      bias_dps += walk_dps_rt_s * std::sqrt(kStepS) * gauss(rng);
      if (leg.still && (i + 1) % kStepsPerSegment == 0) {
        filter.set_plain(state);
        filter.measure_bias(bias_dps + std::sqrt(segment_variance) * gauss(rng), segment_variance);
        state = filter.plain();
      }
      // The scale's share as the estimator adds it: its sigma times the net turn.
      const double scale_share = settings.scale_sigma * true_angle_deg;
      const double variance = state.p00 + scale_share * scale_share;
      if (!(variance > 0.0)) continue;
      const double error = state.angle_deg - true_angle_deg;
      ++run.samples;
      if (error * error <= 4.0 * variance) ++run.within_two;
      run.nees_sum += error * error / variance;
    }
  }
  return run;
}

}  // namespace headingd::drivers
