#pragma once
// Overlapping Allan deviation of a rate signal sampled at a fixed period, and the noise
// terms read from it (IEEE Std 952 conventions):
//   angle random walk N: the -1/2 slope read at tau = 1 s            (sigma = N / sqrt(tau))
//   bias instability B:  the flat minimum divided by 0.664           (sigma_min = 0.664 B)
//   rate random walk K:  the +1/2 slope read at tau = 3 s            (sigma = K sqrt(tau / 3))
// Computed from the integrated angle, so each cluster time costs one pass over the data.
#include <cstddef>
#include <optional>
#include <span>
#include <vector>

namespace headingd::core {

struct AllanPoint {
  double tau_s;
  double deviation;      // same unit as the rate (dps)
  std::size_t clusters;  // number of overlapping terms averaged
};

// Cluster sizes spread evenly in log(tau), `per_decade` of them, from one sample up to the
// largest size with at least `min_terms` overlapping terms.
std::vector<std::size_t> log_spaced_clusters(std::size_t samples, int per_decade = 10, std::size_t min_terms = 9);

// Overlapping Allan deviation of `rate` (sample period period_s) at each cluster size.
std::vector<AllanPoint> allan_deviation(std::span<const double> rate, double period_s,
                                        std::span<const std::size_t> clusters);

struct NoiseTerms {
  double arw = 0.0;               // N, rate unit * sqrt(s)   (dps/sqrt(Hz))
  double bias_instability = 0.0;  // B, rate unit             (dps)
  double tau_at_minimum_s = 0.0;
  std::optional<double> rate_random_walk;  // K, rate unit / sqrt(s); absent if no +1/2 slope was reached
};

// Reads the terms off a computed curve (needs at least three points).
NoiseTerms read_noise_terms(std::span<const AllanPoint> curve);

}  // namespace headingd::core
