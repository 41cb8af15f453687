#include "core/estimator.hpp"

#include <cmath>

namespace headingd::core {
namespace {

std::variant<PaperEstimator, AutoEstimator> make(const EstimatorSettings& s) {
  if (s.method == Method::Auto) return AutoEstimator(s.segments, s.automatic);
  return PaperEstimator(s.method, s.segments);
}

}  // namespace

std::optional<std::string> validate(const EstimatorSettings& s) {
  if (auto problem = validate(s.segments)) return problem;
  const AutoSettings& a = s.automatic;
  if (!(a.min_segment_s > 0.0) || a.min_segment_s > s.segments.segment_s)
    return "auto.min_segment_s must be positive and at most segment_s";
  if (!(a.k_range > 0.0) || !std::isfinite(a.k_range)) return "auto.k_range must be positive";
  if (!(a.k_mean > 0.0) || !std::isfinite(a.k_mean)) return "auto.k_mean must be positive";
  if (!(a.k_mean_pooled > 0.0) || !std::isfinite(a.k_mean_pooled)) return "auto.k_mean_pooled must be positive";
  if (!(a.bias_walk_dps_rt_s >= 0.0) || !std::isfinite(a.bias_walk_dps_rt_s))
    return "auto.bias_walk_dps_rt_s must be zero or positive";
  if (!(a.block_s > 0.0) || a.block_s > a.min_segment_s)
    return "auto.block_s must be positive and at most min_segment_s";
  if (a.arw_dps_rt_hz && (!(a.arw_dps_rt_hz->array() > 0.0).all() || !a.arw_dps_rt_hz->allFinite()))
    return "auto.arw_dps_rt_hz must be positive on every axis";
  const TemperatureModelSettings& t = a.temperature;
  if (!(t.half_life_s > 0.0)) return "temperature.half_life_s must be positive";
  if (!(t.min_span_c > 0.0) || !(t.quadratic_span_c >= t.min_span_c))
    return "temperature.min_span_c must be positive and at most quadratic_span_c";
  if (t.min_points < 3) return "temperature.min_points must be at least 3";
  return std::nullopt;
}

Estimator::Estimator(const EstimatorSettings& settings) : settings_(settings), impl_(make(settings)) {}

const Estimate& Estimator::update(const Sample& sample) {
  ++samples_;
  return std::visit([&](auto& impl) -> const Estimate& { return impl.update(sample); }, impl_);
}

const Estimate& Estimator::last() const {
  return std::visit([](const auto& impl) -> const Estimate& { return impl.last(); }, impl_);
}

std::uint64_t Estimator::accepted_segments() const {
  if (const auto* a = std::get_if<AutoEstimator>(&impl_)) return a->accepted_segments();
  return std::get<PaperEstimator>(impl_).tracker().accepted_segments();
}

std::uint64_t Estimator::rejected_segments() const {
  if (const auto* a = std::get_if<AutoEstimator>(&impl_)) return a->rejected_segments();
  return std::get<PaperEstimator>(impl_).tracker().rejected_segments();
}

Vec3 Estimator::sigma_still_dps() const {
  if (const auto* a = std::get_if<AutoEstimator>(&impl_)) return a->sigma_still_dps();
  return std::get<PaperEstimator>(impl_).tracker().sigma_still_dps();
}

bool Estimator::in_startup() const { return last().in_startup; }

void Estimator::set_motion_hint(MotionHint hint) {
  if (auto* a = std::get_if<AutoEstimator>(&impl_)) a->set_motion_hint(hint);
}

void Estimator::restore_bias(const Vec3& bias_dps, const Vec3& sigma_dps) {
  if (auto* a = std::get_if<AutoEstimator>(&impl_)) {
    a->set_bias(bias_dps, sigma_dps);
  } else {
    std::get<PaperEstimator>(impl_).set_bias(bias_dps);
  }
}

void Estimator::set_heading(double heading_deg, double variance_deg2) {
  if (auto* a = std::get_if<AutoEstimator>(&impl_)) {
    a->set_heading(heading_deg, variance_deg2);
  } else {
    std::get<PaperEstimator>(impl_).set_heading(heading_deg);
  }
}

}  // namespace headingd::core
