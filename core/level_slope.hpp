#pragma once
// How a steady level follows temperature within one run of segments: the weighted regression of
// the segments' mean rates on their mean temperatures, per axis. A quiet run that is a creep
// holds the creep's rate on top of the bias; the rate is the same in every segment, so the
// slope is the bias's own slope against temperature even when the level is not the bias. That
// is what lets a run the estimator rejects still test the temperature model (AutoEstimator),
// and what tells the temperature model that one stop shows a steep slope (TemperatureModel).
#include <cstdint>

#include "core/sample.hpp"

namespace headingd::core {

class LevelSlope {
 public:
  // One segment: its mean rate (dps) at its mean temperature (degC), weighted by its length (s).
  void add(double weight_s, double temp_c, const Vec3& level_dps);

  struct Fit {
    Vec3 slope_dps_per_c = Vec3::Zero();
    Vec3 slope_variance = Vec3::Zero();  // (dps/C)^2
    double mean_temp_c = 0.0;
    double temp_variance_c2 = 0.0;  // the temperatures' weighted variance about mean_temp_c
  };
  // The slope and its variance, the noise taken as the larger of the residuals' and
  // `white_dps2_s` (N^2: a segment of length d has mean variance N^2 / d). False with fewer than
  // three segments or no temperature spread. `reading_variance_c2`: the variance of each
  // temperature's own error (1/12 for readings rounded to whole degrees, TemperatureReading):
  // an error in the temperatures scales the slope by as much relative to their spread, and the
  // residuals do not show it when it changes slowly (errors in variables).
  bool fit(const Vec3& white_dps2_s, Fit& out, double reading_variance_c2 = 0.0) const;

 private:
  std::uint32_t count_ = 0;
  double sum_w_ = 0.0, sum_wt_ = 0.0, sum_wtt_ = 0.0;
  Vec3 sum_wy_ = Vec3::Zero(), sum_wty_ = Vec3::Zero(), sum_wyy_ = Vec3::Zero();
};

}  // namespace headingd::core
