#include "core/paper_estimator.hpp"

namespace headingd::core {

PaperEstimator::PaperEstimator(Method method, const BiasSettings& settings) : tracker_(method, settings) {}

const Estimate& PaperEstimator::update(const Sample& sample) {
  const bool first = !started_;
  started_ = true;
  const bool was_in_startup = tracker_.in_startup();
  estimate_.closed = tracker_.update(sample);
  const Vec3& bias = tracker_.bias_dps();
  estimate_.rate_dps = sample.rate_dps - bias;

  // While the start-up segment is measured the platform is still by assumption, so the
  // heading is held rather than integrated with a bias not yet known. The sample that
  // closes that segment is the first one integrated.
  const bool hold = was_in_startup && tracker_.in_startup();
  if (!first && !hold) {
    const double dt_s = sample.t_s - previous_t_s_;
    heading_.add(sample.rate_dps.z(), bias.z(), dt_s);
    attitude_.add(estimate_.rate_dps, dt_s);
  }
  previous_t_s_ = sample.t_s;

  estimate_.t_s = sample.t_s;
  estimate_.temp_c = sample.temp_c;
  estimate_.heading_deg = heading_.heading_deg();
  estimate_.attitude = attitude_.attitude();
  estimate_.bias_dps = bias;
  estimate_.in_startup = tracker_.in_startup();
  estimate_.segment_index = tracker_.segment_index();
  return estimate_;
}

}  // namespace headingd::core
