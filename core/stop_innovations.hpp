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

// A heading fix measures the heading error itself, whatever its causes: its squared innovation
// less the variance of the parts the factor does not scale (the fix's own, the scale factor's,
// the variance a previous fix left) against the variance the filter gathered since that fix.
// Unlike the stops, the fixes may narrow the sigma: they see every share of it. With a fix every
// 10 minutes on issue 12's random worlds the filter's own sigma is already consistent (94.6 % of
// outputs within 2 sigma) and the stops' factor alone widened it (97.3 %); with the fixes' ratio,
// 95.8 % (bench/scale_fixes, docs/random-worlds.md "2026-12-04 (late)"); weighed by what each fix
// can tell (below), 96.0 % and 151 runs in 85-99.5 % (2026-12-05).
// The fixes' ratio may narrow the gathered variance to this share and no further (0.1 and 0.25 gave
// the same figures on the worlds above: 149 and 148 runs in 85-99.5 %).
inline constexpr double kFixScaleFloor = 0.25;
// A fix further than this many sigma (shown, with the fix's own) from the heading teaches nothing.
inline constexpr double kFixGateSigmas = 10.0;

// How many fully informative fixes the stops' factor weighs as, beside the fixes' own (bench/
// scale_fixes 1-200: 0.25: 151 runs in 85-99.5 %, 0.5: 140, 1: 126; held out 201-400 at 0.25: 139,
// against 141 before the weighting).
inline constexpr double kFixPriorWeight = 0.25;

class FixInnovations {
 public:
  // One fix: its squared innovation less the unscaled variance (`excess`), the variance gathered
  // since the previous fix, and the unscaled variance itself. The excess estimates factor *
  // gathered with a spread of about sqrt(2) (unscaled + gathered): a fix soon after another (a
  // localisation system at 1 Hz: 0.01 deg^2 left by the last fix, 1e-4 gathered) says almost
  // nothing of the factor, one after a long drive says much. Weighted least squares, weight
  // gathered / (unscaled + gathered)^2: a fix with nothing unscaled counts as one; summed as
  // plain ratios, honest 1 Hz fixes had put the factor at 15.
  void add(double excess_deg2, double gathered_deg2, double unscaled_deg2) {
    if (!std::isfinite(excess_deg2) || !std::isfinite(gathered_deg2) || !std::isfinite(unscaled_deg2) ||
        !(gathered_deg2 > 0.0) || unscaled_deg2 < 0.0)
      return;
    const double spread = unscaled_deg2 + gathered_deg2;
    const double weight = gathered_deg2 / (spread * spread);
    excess_ += weight * excess_deg2;
    gathered_ += weight * gathered_deg2;
    ++count_;
  }
  // `prior_scale` (the stops' factor) weighed as kFixPriorWeight fully informative fixes; never below `floor`
  // (a few fixes that happen to land near the heading say little of the variance's size).
  double variance_scale(double prior_scale, double floor) const {
    if (count_ == 0) return prior_scale;
    return std::max(floor, (excess_ + kFixPriorWeight * prior_scale) / (gathered_ + kFixPriorWeight));
  }
  std::uint64_t fixes() const { return count_; }

 private:
  double excess_ = 0.0;    // weighted sum of the excesses
  double gathered_ = 0.0;  // weighted sum of the variances gathered
  std::uint64_t count_ = 0;
};

}  // namespace headingd::core
