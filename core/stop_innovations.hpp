#pragma once
// The heading sigma calibrated by the run's own stops (issue 12: an honest sigma per run, not
// only pooled). The first accepted segment after motion, a rejection, the start-up or a restart
// measures how far the bias moved since the filter last measured it. The filter predicted that
// move with its bias variance P (the walk, the temperature's share); the segment's own noise
// adds r. So the squared innovation v^2 has the expectation P + r where the filter is right,
// and v^2 - r estimates the variance the bias really moved by. The ratio of those sums to the
// sums of P over the run's stops says how much too narrow the filter's idea of a drifting bias
// is on this sensor in this world — a temperature coefficient beyond the configured spread, a
// bias that jumps, slow motion taken for a stop — and the heading variance the filter has
// gathered since the last fix is scaled by it. Only widened, never narrowed: that variance also
// holds the white noise's share and the doubt of verdicts, which the stops do not measure (a
// ratio let below 1 narrowed the sigma of `auto_report`'s 4 h `still` seed 2 to 46 % of its
// outputs within 2 sigma, from 99.9 %).
//
// Why this ratio and not the mean normalized innovation v^2 / (P + r): r dominates P on most
// stops (a 3 s mean of a consumer gyro against a bias known to a few mdps), so the normalized
// form stays near 1 where P is many times too small. On issue 12's random worlds 1-200
// (bench/sweep.sh, docs/random-worlds.md "2026-12-04 (night)") this form puts 95.5 % of all
// outputs within 2 sigma and 5 runs below 60 % — a consistent sigma's figures (95.4 %, 5-8) —
// where the filter's own sigma has 87.2 % and 24, and the normalized form 90-91 % and 18-20.
#include <algorithm>
#include <cmath>
#include <cstdint>

namespace headingd::core {

class StopInnovations {
 public:
  // One such segment: its mean less the predicted bias, the filter's bias variance before it,
  // and the variance of the segment's mean from the white noise alone.
  void add(double innovation_dps, double bias_variance, double mean_variance) {
    if (!std::isfinite(innovation_dps) || !std::isfinite(bias_variance) || !std::isfinite(mean_variance) ||
        !(bias_variance > 0.0) || mean_variance < 0.0)
      return;
    excess_ += innovation_dps * innovation_dps - mean_variance;
    predicted_ += bias_variance;
    ++count_;
  }
  // The factor on the heading variance the filter gathers: the stops' excess over what they
  // predicted, with one average stop at the filter's own figure (ratio 1) as the prior, so the
  // first stop moves it half-way; at least 1.
  double variance_scale() const {
    if (count_ == 0) return 1.0;
    const double prior = predicted_ / static_cast<double>(count_);
    return std::max(1.0, (excess_ + prior) / (predicted_ + prior));
  }
  std::uint64_t stops() const { return count_; }

 private:
  double excess_ = 0.0;     // sum of v^2 - r
  double predicted_ = 0.0;  // sum of P
  std::uint64_t count_ = 0;
};

}  // namespace headingd::core
