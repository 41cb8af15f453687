#include "core/level_slope.hpp"

#include <algorithm>
#include <cmath>

namespace headingd::core {

void LevelSlope::add(double weight_s, double temp_c, const Vec3& level_dps) {
  if (!(weight_s > 0.0) || !std::isfinite(temp_c) || !level_dps.allFinite()) return;
  ++count_;
  sum_w_ += weight_s;
  sum_wt_ += weight_s * temp_c;
  sum_wtt_ += weight_s * temp_c * temp_c;
  sum_wy_ += weight_s * level_dps;
  sum_wty_ += weight_s * temp_c * level_dps;
  sum_wyy_ += weight_s * level_dps.cwiseAbs2();
}

bool LevelSlope::fit(const Vec3& white_dps2_s, Fit& out, double reading_variance_c2) const {
  if (count_ < 3) return false;
  const double mean_t = sum_wt_ / sum_w_;
  const double sxx = sum_wtt_ - sum_wt_ * mean_t;  // sum w (T - mean)^2, s C^2
  // Temperatures read to a hundredth of a degree or so: a spread below that is no spread.
  if (!(sxx > 1e-4 * sum_w_)) return false;
  out.mean_temp_c = mean_t;
  out.temp_variance_c2 = sxx / sum_w_;
  for (Eigen::Index a = 0; a < 3; ++a) {
    const double mean_y = sum_wy_[a] / sum_w_;
    const double sxy = sum_wty_[a] - sum_wt_ * mean_y;
    const double syy = sum_wyy_[a] - sum_wy_[a] * mean_y;
    const double slope = sxy / sxx;
    // Residual variance per unit weight (dps^2 s), on count - 2 degrees of freedom.
    const double rss = std::max(0.0, syy - slope * sxy);
    const double per_weight = std::max(white_dps2_s[a], rss / (count_ - 2));
    out.slope_dps_per_c[a] = slope;
    out.slope_variance[a] = per_weight / sxx + slope * slope * reading_variance_c2 * sum_w_ / sxx;
  }
  return out.slope_dps_per_c.allFinite() && out.slope_variance.allFinite();
}

}  // namespace headingd::core
