#pragma once
// A world drawn from the very model the angle/bias filter assumes (core/axis_filter.hpp): white
// rate noise, a bias random walk, stops whose 3 s segments measure the bias, and, if asked, a
// scale error per run times the net turn. In such a world the filter's sigma is right by
// construction (pooled over many runs, 95.4 % of samples lie within 2 sigma), so the share of
// one run's samples within 2 sigma shows what per-run honesty any estimator can reach there,
// not what ours reaches on a sensor (issue 12, must-show 4; bench/honesty_limit.sh).
#include <cstdint>

namespace headingd::drivers {

struct OwnModelSettings {
  double hours = 2.0;
  double scale_sigma = 0.0;  // the per-run scale error's sigma (fraction); 0: no scale error
  // The bias random walk the filter is told, as a multiple of the world's: 1 is its own model;
  // any other value makes a filter whose sigma is wrong (for tests that must see it).
  double filter_walk_factor = 1.0;
};

struct OwnModelRun {
  std::uint64_t samples = 0;     // 10 Hz outputs scored (sigma above zero)
  std::uint64_t within_two = 0;  // of those, |E| <= 2 sigma
  double nees_sum = 0.0;         // sum of E^2 / sigma^2 over those
  double share_within() const {
    return samples == 0 ? 0.0 : static_cast<double>(within_two) / static_cast<double>(samples);
  }
};

// One run: the sensor (noise 0.004-0.02 dps/sqrt(Hz), rate random walk 1e-5-1e-4 dps/sqrt(s),
// the initial bias), the motion (as the random scenario's: stops of 1 s-30 min, drives, turns,
// creeps; sometimes a start while moving) and every noise draw come from the seed.
OwnModelRun run_in_own_model_world(std::uint64_t seed, const OwnModelSettings& settings);

}  // namespace headingd::drivers
