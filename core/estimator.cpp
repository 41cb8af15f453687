#include "core/estimator.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace headingd::core {
namespace {

constexpr double kUnknownSigmaRestoredDps = 0.01;
constexpr double kMaxSavedBiasSigmaDps = 100.0;

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
  if (!(a.zero_rate_sigma_dps > 0.0) || a.zero_rate_sigma_dps > 100.0)
    return "auto.zero_rate_sigma_dps must be within (0, 100]";
  if (!(a.scale_factor_sigma >= 0.0) || a.scale_factor_sigma > 0.5)
    return "auto.scale_factor_sigma must be within [0, 0.5]";
  if (!(a.block_s > 0.0) || a.block_s > a.min_segment_s)
    return "auto.block_s must be positive and at most min_segment_s";
  if (a.arw_dps_rt_hz && (!(a.arw_dps_rt_hz->array() > 0.0).all() || !a.arw_dps_rt_hz->allFinite()))
    return "auto.arw_dps_rt_hz must be positive on every axis";
  if (!(a.unmodelled_bias_per_c_dps >= 0.0) || a.unmodelled_bias_per_c_dps > 1.0)
    return "temperature.unmodelled_dps_per_c must be within [0, 1]";
  const TemperatureModelSettings& t = a.temperature;
  if (!(t.half_life_s > 0.0)) return "temperature.half_life_s must be positive";
  if (!(t.min_span_c > 0.0) || !(t.quadratic_span_c >= t.min_span_c))
    return "temperature.min_span_c must be positive and at most quadratic_span_c";
  if (t.min_points < 3) return "temperature.min_points must be at least 3";
  return std::nullopt;
}

LearnedState savable(LearnedState state) {
  // A bias sigma this large says "unknown" as well as any larger one (the chip's zero-rate
  // level is +-25 dps at its widest): capped, so it stays within what a restore accepts.
  state.bias_sigma_dps = state.bias_sigma_dps.cwiseMin(kMaxSavedBiasSigmaDps);
  return state;
}

namespace {
constexpr double kMaxRestoredBiasSigmaDps = 100.0;
}  // namespace

std::optional<std::string> implausible(const LearnedState& s) {
  const auto in = [](const Vec3& v, double lo, double hi) {
    return v.allFinite() && v.minCoeff() >= lo && v.maxCoeff() <= hi;
  };
  if (!in(s.bias_dps, -kMaxPlausibleRateDps, kMaxPlausibleRateDps)) return "bias beyond any gyro's range";
  if (!in(s.bias_sigma_dps, 0.0, kMaxRestoredBiasSigmaDps)) return "bias sigma not within 0..100 dps";
  if (!in(s.sigma_still_dps, 0.0, 100.0)) return "still noise not within 0..100 dps";
  if (!in(s.arw_dps_rt_hz, 0.0, 100.0)) return "noise density not within 0..100 dps/sqrt(Hz)";
  for (std::size_t axis = 0; axis < 3; ++axis) {
    const auto& t = s.temperature_sums[axis];
    if (!t.normal.allFinite() || !t.rhs.allFinite() || !std::isfinite(t.yy) || !std::isfinite(t.weight) || t.weight < 0)
      return "temperature model not finite";
  }
  if (!std::isnan(s.heading_deg) && !(std::abs(s.heading_deg) <= 1e7)) return "heading not finite";
  if (!std::isnan(s.heading_variance_deg2) && !(s.heading_variance_deg2 >= 0.0 && s.heading_variance_deg2 <= 1e6))
    return "heading variance not within 0..1e6 deg^2";
  if (!std::isfinite(s.heading_fix_offset_deg)) return "heading offset not finite";
  const auto temperature_ok = [](double t) {
    return std::isnan(t) || (t >= kMinPlausibleTempC && t <= kMaxPlausibleTempC);
  };
  if (!temperature_ok(s.temp_c) || !temperature_ok(s.bias_measured_temp_c))
    return "temperature not within -60..150 degC";
  if (!std::isnan(s.scale_z_sigma) &&
      !(std::abs(s.scale_z) <= kMaxLearnedScale && s.scale_z_sigma >= 0.0 && s.scale_z_sigma <= 0.5))
    return "z scale factor not within +-0.05 (sigma 0..0.5)";
  return std::nullopt;
}

Estimator::Estimator(const EstimatorSettings& settings) : settings_(settings), impl_(make(settings)) {}

const Estimate& Estimator::update(const Sample& sample) {
  ++samples_;
  if (fault_) {
    fault_estimate_.t_s = sample.t_s;
    return fault_estimate_;
  }
  return checked(std::visit([&](auto& impl) -> const Estimate& { return impl.update(sample); }, impl_));
}

std::size_t Estimator::advance(const Sample* samples, std::size_t count, double until_t_s) {
  auto* automatic = std::get_if<AutoEstimator>(&impl_);
  if (fault_ || automatic == nullptr) return 0;
  const std::size_t taken = automatic->advance(samples, count, until_t_s);
  if (taken == 0) return 0;
  samples_ += taken;
  checked(automatic->last());
  return taken;
}

const Estimate& Estimator::checked(const Estimate& e) {
  // One sum catches any NaN or infinity, summed in pairs so that the adds need not wait for
  // one another. The paper's methods have no sigma (NaN by design).
  const auto& q = e.attitude.coeffs();
  const double sigma = settings_.method == Method::Auto ? e.heading_sigma_deg : 0.0;
  const double sum =
      ((e.heading_deg + sigma) + (q[0] + q[1]) + (q[2] + q[3])) +
      ((e.bias_dps[0] + e.bias_dps[1]) + (e.bias_dps[2] + e.rate_dps[0]) + (e.rate_dps[1] + e.rate_dps[2]));
  if (!std::isfinite(sum)) return enter_fault(e);
  good_heading_deg_ = e.heading_deg;
  good_attitude_ = e.attitude;
  good_bias_dps_ = e.bias_dps;
  if (e.closed.closed) {
    if (LearnedState now = savable(learned_now()); !implausible(now)) good_state_ = now;
  }
  return e;
}

const Estimate& Estimator::enter_fault(const Estimate& poisoned) {
  fault_ = true;
  fault_estimate_ = Estimate{};
  fault_estimate_.t_s = poisoned.t_s;
  fault_estimate_.heading_deg = good_heading_deg_;
  fault_estimate_.attitude = good_attitude_;
  fault_estimate_.bias_dps = good_bias_dps_;
  fault_estimate_.bias_sigma_dps = Vec3::Constant(std::numeric_limits<double>::infinity());
  fault_estimate_.heading_sigma_deg = std::numeric_limits<double>::infinity();
  fault_estimate_.temp_c = std::isfinite(poisoned.temp_c) ? poisoned.temp_c : std::numeric_limits<double>::quiet_NaN();
  fault_estimate_.fault = true;
  return fault_estimate_;
}

const Estimate& Estimator::last() const {
  if (fault_) return fault_estimate_;
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

Diagnostics Estimator::diagnostics() const {
  Diagnostics d;
  d.method = settings_.method;
  d.in_startup = in_startup();
  d.samples = samples_;
  d.accepted_segments = accepted_segments();
  d.rejected_segments = rejected_segments();
  d.segment_s = settings_.segments.segment_s;
  d.sigma_still_dps = sigma_still_dps();
  d.heading_fixes = heading_fixes_;
  d.heading_fix_offset_deg = heading_fix_offset_deg_;
  if (const auto* a = std::get_if<AutoEstimator>(&impl_)) {
    if (a->scale().learned()) {
      d.scale_z = a->scale().estimate();
      d.scale_z_sigma = a->scale().sigma();
    }
    d.retracted_segments = a->retracted_segments();
    d.bias_recoveries = a->bias_recoveries();
    d.refused_recoveries = a->refused_recoveries();
    d.refuted_models = a->refuted_temperature_models();
    d.rate_changed_segments = a->rate_changed_segments();
    d.recoveries_taken_back = a->recoveries_taken_back();
    d.saved_bias_restarts = a->saved_bias_restarts();
    d.saved_noise_replaced = a->saved_noise_replaced();
    d.trail_restarts = a->temperature_trail_restarts();
    d.trail_slope_z_dps_per_c = a->last_trail_slope_z_dps_per_c();
    d.returns_mended = a->returns_mended();
    d.last_return_correction_deg = a->last_return_correction_deg();
    d.gaps_bridged = a->gaps_bridged();
    d.gaps_bridged_s = a->gaps_bridged_s();
    d.noise_density_dps_rt_hz = a->noise_density_dps_rt_hz();
    d.last_still_t_s = a->last_still_t_s();
    d.motion_hint = a->motion_hint();
    d.hint_conflicts = a->hint_conflicts();
    d.heading_variance_scale = a->heading_variance_scale();
    d.sigma_stops_weighed = a->stops_weighed();
    d.sigma_fixes_weighed = a->fix_innovations().fixes();
    for (int axis = 0; axis < 3; ++axis) {
      const TemperatureModel& model = a->temperature_model(axis);
      d.temperature[static_cast<std::size_t>(axis)] = {model.ready(), model.slope_dps_per_c(25.0),
                                                       model.weighted_span_c(), model.points()};
    }
  }
  return d;
}

LearnedState Estimator::learned() const {
  // After a fault only what was learned while healthy may be saved; nor is a state that a
  // restart would refuse (a bias beyond any gyro's range after a wild temperature model).
  if (samples_ == 0 && restored_) return *restored_;
  if (fault_) return good_state_;
  LearnedState now = savable(learned_now());
  return implausible(now) ? good_state_ : now;
}

LearnedState Estimator::learned_now() const {
  LearnedState state;
  state.bias_dps = last().bias_dps;
  // A bias without a sigma (the paper's methods, or during start-up) would be restored as
  // exact: give it a modest one.
  state.bias_sigma_dps =
      last().bias_sigma_dps.allFinite() ? last().bias_sigma_dps : Vec3::Constant(kUnknownSigmaRestoredDps);
  if (samples_ > 0 && std::isfinite(last().heading_deg)) {
    state.heading_deg = last().heading_deg;
    const double sigma = last().heading_sigma_deg;
    // The paper's methods give no sigma: the heading is kept, its uncertainty unknown.
    state.heading_variance_deg2 = std::isfinite(sigma) ? sigma * sigma : std::numeric_limits<double>::quiet_NaN();
    state.heading_fix_offset_deg = heading_fix_offset_deg_;
  }
  if (const auto* a = std::get_if<AutoEstimator>(&impl_)) {
    state.sigma_still_dps = a->sigma_still_dps();
    state.arw_dps_rt_hz = a->noise_density_dps_rt_hz();
    if (a->scale().learned()) {
      state.scale_z = a->scale().estimate();
      state.scale_z_sigma = a->scale().sigma();
    }
    for (std::size_t axis = 0; axis < 3; ++axis) {
      state.temperature_sums[axis] = a->temperature_model(static_cast<int>(axis)).sums();
      state.temperature_points[axis] = a->temperature_model(static_cast<int>(axis)).points();
    }
    state.temp_c = a->temperature_now_c();
    state.bias_measured_temp_c = a->bias_measured_temp_c();
  }
  return state;
}

void Estimator::restore(const LearnedState& state, bool with_heading) {
  if (const auto problem = implausible(state)) throw std::invalid_argument("state refused: " + *problem);
  restore_bias(state.bias_dps, state.bias_sigma_dps);
  if (with_heading && std::isfinite(state.heading_deg)) {
    if (auto* a = std::get_if<AutoEstimator>(&impl_))
      a->restore_heading(state.heading_deg,
                         std::isfinite(state.heading_variance_deg2) ? state.heading_variance_deg2 : 0.0);
    else
      std::get<PaperEstimator>(impl_).set_heading(state.heading_deg);
    heading_fix_offset_deg_ = std::isfinite(state.heading_fix_offset_deg) ? state.heading_fix_offset_deg : 0.0;
  }
  if (auto* a = std::get_if<AutoEstimator>(&impl_)) {
    a->set_noise(state.sigma_still_dps, state.arw_dps_rt_hz);
    if (!std::isnan(state.scale_z_sigma)) a->restore_scale(state.scale_z, state.scale_z_sigma);
    for (std::size_t axis = 0; axis < 3; ++axis)
      a->restore_temperature_model(static_cast<int>(axis), state.temperature_sums[axis],
                                   state.temperature_points[axis]);
    a->carry_restored_bias(state.temp_c, state.bias_measured_temp_c);  // after the models it may use
  }
  restored_ = state;
  if (!with_heading) {
    restored_->heading_deg = std::numeric_limits<double>::quiet_NaN();
    restored_->heading_variance_deg2 = std::numeric_limits<double>::quiet_NaN();
    restored_->heading_fix_offset_deg = 0.0;
  }
}

void Estimator::restore_after_restart(const LearnedState& state, bool with_heading) {
  // The sigma learned while running says nothing of what the time down moved (auto only).
  // Checked before the widening: its cap must not let a refused sigma through.
  if (const auto problem = implausible(state)) throw std::invalid_argument("state refused: " + *problem);
  LearnedState widened = state;
  if (method() == Method::Auto) {
    const double turn_on_dps = settings_.automatic.restart_bias_sigma_dps;
    widened.bias_sigma_dps = (state.bias_sigma_dps.array().square() + turn_on_dps * turn_on_dps)
                                 .sqrt()
                                 .min(kMaxRestoredBiasSigmaDps)
                                 .matrix();
  }
  restore(widened, with_heading);
  if (auto* a = std::get_if<AutoEstimator>(&impl_)) a->doubt_restored_level();
}

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
  double jump_deg = 0.0;
  if (auto* a = std::get_if<AutoEstimator>(&impl_)) {
    jump_deg = a->set_heading(heading_deg, variance_deg2);
  } else {
    jump_deg = std::get<PaperEstimator>(impl_).set_heading(heading_deg);
  }
  ++heading_fixes_;
  heading_fix_offset_deg_ += jump_deg;
}

}  // namespace headingd::core
