#include "core/bias_history.hpp"

#include <algorithm>
#include <cmath>

namespace headingd::core {
namespace {
// Two measured points this close (in their combined sigma) are one level.
constexpr double kSameLevelSigmas = 2.0;
}  // namespace

void BiasHistory::measured(double t_s, double bias_dps, double variance_dps2, double heading_deg, bool carried,
                           double held_s) {
  if (!std::isfinite(bias_dps) || !std::isfinite(variance_dps2) || !std::isfinite(heading_deg)) return;
  const Level level{.t_s = t_s,
                    .held_s = std::isfinite(held_s) ? std::max(0.0, held_s) : 0.0,
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
      const double held_before_s = last.held_s;
      last = level;
      last.held_s = std::max(last.held_s, held_before_s);
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

std::optional<BiasHistory::Return> BiasHistory::correction_for_return(double level_dps, double level_variance_dps2,
                                                                      double walk_dps2_per_s, double sigmas,
                                                                      const Mark& until, double until_t_s,
                                                                      double until_heading_deg,
                                                                      double refuting_span_s) const {
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
    if (!(z <= sigmas)) {                         // NaN: no match
      if (past.held_s >= refuting_span_s) break;  // the bias sat elsewhere: no older level
      continue;
    }
    if (!(z <= best_z)) continue;
    best_z = z;
    best = &past;
  }
  if (best == nullptr || !std::isfinite(until_heading_deg)) return std::nullopt;
  // The turn since, had the bias been the level all along, against the turn the heading made.
  const double span_s = until.integrated_s - best->at.integrated_s;
  const double turned_deg = (until.rate_integral_deg - best->at.rate_integral_deg) - level_dps * span_s;
  const double variance_deg2 = std::max(0.0, level_variance_dps2) * span_s * span_s +
                               std::max(0.0, walk_dps2_per_s) * span_s * span_s * span_s / 3.0;
  return Return{.correction_deg = turned_deg - (until_heading_deg - best->heading_deg), .variance_deg2 = variance_deg2};
}

}  // namespace headingd::core
