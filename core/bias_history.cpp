#include "core/bias_history.hpp"

#include <algorithm>
#include <cmath>

namespace headingd::core {
namespace {
// Two measured points this close (in their combined sigma) are one level.
constexpr double kSameLevelSigmas = 2.0;
}  // namespace

void BiasHistory::measured(double t_s, double bias_dps, double variance_dps2, double heading_deg, bool carried) {
  if (!std::isfinite(bias_dps) || !std::isfinite(variance_dps2) || !std::isfinite(heading_deg)) return;
  const Level level{.t_s = t_s,
                    .bias_dps = bias_dps,
                    .variance_dps2 = std::max(0.0, variance_dps2),
                    .heading_deg = heading_deg,
                    .at = now_,
                    .first_bias_dps = bias_dps,
                    .first_variance_dps2 = std::max(0.0, variance_dps2)};
  if (count_ > 0) {
    Level& last = levels_[(next_ + kLevels - 1) % kLevels];
    // Carried: against the level's first point. Else against its latest, which the level then
    // becomes: stops that measure a bias drifting for real leave no level behind to return to.
    const double anchor_dps = carried ? last.first_bias_dps : last.bias_dps;
    const double anchor_variance = carried ? last.first_variance_dps2 : last.variance_dps2;
    const double sd = std::sqrt(anchor_variance + level.variance_dps2);
    if (std::abs(anchor_dps - bias_dps) <= kSameLevelSigmas * sd) {
      const double first_bias = last.first_bias_dps, first_variance = last.first_variance_dps2;
      last = level;
      if (carried) {
        last.first_bias_dps = first_bias;
        last.first_variance_dps2 = first_variance;
      }
      return;
    }
  }
  levels_[next_] = level;
  next_ = (next_ + 1) % kLevels;
  count_ = std::min(count_ + 1, kLevels);
}

std::optional<double> BiasHistory::correction_for_return(double level_dps, double level_variance_dps2,
                                                         double walk_dps2_per_s, double sigmas, const Mark& until,
                                                         double until_t_s, double until_heading_deg) const {
  // The level that agrees best, in sigmas.
  const Level* best = nullptr;
  double best_z = sigmas;
  for (std::size_t i = 1; i <= count_; ++i) {
    const Level& past = levels_[(next_ + kLevels - i) % kLevels];
    if (past.t_s > until_t_s) continue;
    const double since_s = until_t_s - past.t_s;
    const double sd = std::sqrt(past.variance_dps2 + std::max(0.0, level_variance_dps2) + walk_dps2_per_s * since_s);
    // The level spans its first point to its latest (a stop's estimate converges, a carried one
    // walks): either end agreeing is a return to it.
    const double z = std::min(std::abs(past.bias_dps - level_dps), std::abs(past.first_bias_dps - level_dps)) / sd;
    if (!(z <= best_z)) continue;  // NaN: no match
    best_z = z;
    best = &past;
  }
  if (best == nullptr || !std::isfinite(until_heading_deg)) return std::nullopt;
  // The turn since, had the bias been the level all along, against the turn the heading made.
  const double turned_deg =
      (until.rate_integral_deg - best->at.rate_integral_deg) - level_dps * (until.integrated_s - best->at.integrated_s);
  return turned_deg - (until_heading_deg - best->heading_deg);
}

}  // namespace headingd::core
