#pragma once
// Where the z bias estimate has been, for a restart that returns to a level it left.
//
// A restart (a long quiet run under a bias that no stop agrees with) says the bias in force
// was wrong, not since when. When the restarted level is one a stop had measured before, and
// the estimate left it since (creeps taken for stops, a temperature model walking off, a
// restart onto a creep's level), the likeliest story is that the bias never moved. Then the
// heading since that stop is the raw z rate less that level, integrated over all of it — the
// creeps taken for stops were motion, the stops still — and the estimate owes the difference.
// This keeps the levels stops measured (the latest time at each) with the raw rate's integral
// and the heading at that moment, so that difference is a few subtractions.
#include <array>
#include <cstddef>
#include <limits>
#include <optional>

namespace headingd::core {

class BiasHistory {
 public:
  // A moment: the integral of the raw z rate so far, and the time it covers.
  struct Mark {
    double rate_integral_deg = 0.0;
    double integrated_s = 0.0;
  };

  // One sample (inline: it runs on every sample).
  void integrate(double rate_dps, double dt_s) {
    now_.rate_integral_deg += rate_dps * dt_s;
    now_.integrated_s += dt_s;
  }
  Mark mark() const { return now_; }

  // A stop measured the bias: `bias_dps` with `variance_dps2` at `t_s`, the heading then
  // `heading_deg`. Consecutive points at one level keep only the latest. `carried`: the estimate
  // is carried between measurements by something other than the bias (a temperature model);
  // then a point is at the level only when it agrees with the level's first point, for a model
  // with a wrong slope would otherwise drag one level along the whole way and lose the stops it
  // left. Not otherwise: a bias drifting for real, measured stop by stop, has no level to return to.
  // `held_s`: how long the stop this point ends had been held still (its accepted segments back
  // to back so far, a restart's quiet run and what followed it).
  void measured(double t_s, double bias_dps, double variance_dps2, double heading_deg, bool carried = false,
                double held_s = 0.0);
  // A heading fix: the headings kept no longer compare with the ones to come.
  void forget() { count_ = next_ = 0; }

  // For a restart at `level_dps` (variance `level_variance_dps2`) whose quiet run began at
  // `until`, time `until_t_s`, heading `until_heading_deg`: the heading correction (deg, to add)
  // had the bias been that level since the measured level agreeing with it best, within `sigmas`
  // of their spread plus a bias walk of `walk_dps2_per_s` over the time between (the nearest, not
  // the latest: a creep's level passing near it by chance agrees less). None: no level agrees.
  // Only back to the newest level that disagrees and ended a stop held still for `refuting_span_s`
  // or more (a temperature model that carries the bias splits one stop into many levels):
  // the story "the bias never moved, every level between was a creep" does not hold across a
  // stop at another level held longer than any creep (the caller's bar), so the bias did move (a
  // day-long run whose bias follows the temperature up and down returns to old levels by chance,
  // hours apart).
  // The correction and its variance: the level's own (times the time since, squared) and the bias
  // walk's integral over that time (q T^3 / 3), which the story "it never moved" leaves out — a
  // match the walk made possible over hours tells little about the heading.
  struct Return {
    double correction_deg = 0.0;
    double variance_deg2 = 0.0;
  };
  std::optional<Return> correction_for_return(double level_dps, double level_variance_dps2, double walk_dps2_per_s,
                                              double sigmas, const Mark& until, double until_t_s,
                                              double until_heading_deg,
                                              double refuting_span_s = std::numeric_limits<double>::infinity()) const;

 private:
  struct Level {
    double t_s = 0.0;     // the level's latest point
    double held_s = 0.0;  // the longest stop held still that reaches into it
    double bias_dps = 0.0;
    double variance_dps2 = 0.0;
    double heading_deg = 0.0;
    Mark at;
    // The level's first point: a carried point joins the level only if it agrees with this.
    double first_bias_dps = 0.0;
    double first_variance_dps2 = 0.0;
  };
  static constexpr std::size_t kLevels = 256;  // distinct levels kept, the oldest dropped
  std::array<Level, kLevels> levels_{};
  std::size_t count_ = 0, next_ = 0;
  Mark now_;
};

}  // namespace headingd::core
