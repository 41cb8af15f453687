#include "core/segment_judge.hpp"

#include <cmath>

namespace headingd::core {

Judgement judge_segment(const SegmentEvidence& s, const PreviousSegment& previous, const AutoSettings& settings) {
  Judgement judgement;
  const Vec3 r = s.white_dps2_s / s.duration_s;
  bool mean_ok = true;
  for (Eigen::Index a = 0; a < 3; ++a) {
    const double sd = std::sqrt(s.predicted_var[a] + r[a]);
    mean_ok = mean_ok && std::abs(s.mean_dps[a] - s.predicted_dps[a]) <= settings.k_mean * sd;
  }
  if (previous.usable) {
    const double pooled_s = s.duration_s + previous.duration_s;
    for (Eigen::Index a = 0; a < 3; ++a) {
      const double pooled_mean = (s.mean_dps[a] * s.duration_s + previous.mean_dps[a] * previous.duration_s) / pooled_s;
      const double sd =
          std::sqrt(previous.predicted_var[a] + s.walk_dps2_per_s * pooled_s + s.white_dps2_s[a] / pooled_s);
      mean_ok = mean_ok && std::abs(pooled_mean - previous.predicted_dps[a]) <= settings.k_mean_pooled * sd;
      if (a == 2) {
        judgement.pooled_deviation_z_dps = pooled_mean - previous.predicted_dps[a];
        judgement.pooled_sd_z_dps = sd;
      }
    }
  }
  judgement.mean_ok = mean_ok;
  // (The pooled test is no evidence of a lean: it contains the first segment itself.) Noise
  // leans either way, and an acceptance it would take back stands.
  if (previous.usable) {
    const double first_lean = previous.mean_dps.z() - previous.predicted_dps.z();
    const double first_sd = std::sqrt(previous.predicted_var.z() + s.white_dps2_s.z() / previous.duration_s);
    const double lean = s.mean_dps.z() - previous.predicted_dps.z();
    const double sd = std::sqrt(previous.predicted_var.z() + s.walk_dps2_per_s * (previous.duration_s + s.duration_s) +
                                s.white_dps2_s.z() / s.duration_s);
    judgement.same_lean = first_lean * lean > 0.0 && std::abs(lean) > settings.retract_next_lean * sd &&
                          std::abs(first_lean) >= settings.retract_min_lean * first_sd;
  }
  return judgement;
}

}  // namespace headingd::core
