#include "core/auto_estimator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/units.hpp"

namespace headingd::core {
namespace {

constexpr double kTimeEpsilonS = 1e-9;
constexpr double kMinSigmaStillDps = 1e-6;
// Before anything is known the bias could be anywhere within the chip's zero-rate level
// (datasheet: +-25 dps at 2000 dps full scale; a few dps at 245 dps in practice).
constexpr double kUnknownBiasSigmaDps = 2.0;

}  // namespace

AutoEstimator::AutoEstimator(const BiasSettings& segments, const AutoSettings& settings)
    : segments_(segments),
      settings_(settings),
      temperature_{TemperatureModel(settings.temperature), TemperatureModel(settings.temperature),
                   TemperatureModel(settings.temperature)},
      walk_dps2_per_s_(settings.bias_walk_dps_rt_s * settings.bias_walk_dps_rt_s),
      in_startup_(segments.still_at_start) {
  segment_.blocks = BlockMeans(settings_.block_s);
  if (segments_.sigma_still_dps) sigma_still_dps_ = *segments_.sigma_still_dps;
  if (settings_.arw_dps_rt_hz) white_dps2_s_ = settings_.arw_dps_rt_hz->cwiseAbs2();
  if (!in_startup_) {
    for (auto& filter : filters_) filter.reset(0.0, kUnknownBiasSigmaDps * kUnknownBiasSigmaDps);
  }
}

void AutoEstimator::set_bias(const Vec3& bias_dps, const Vec3& sigma_dps) {
  for (int axis = 0; axis < 3; ++axis) {
    auto state = filters_[static_cast<std::size_t>(axis)].state();
    state.bias_dps = bias_dps[axis];
    state.covariance(1, 1) = sigma_dps[axis] * sigma_dps[axis];
    state.covariance(0, 1) = state.covariance(1, 0) = 0.0;
    filters_[static_cast<std::size_t>(axis)].restore(state);
  }
  in_startup_ = false;
  commit_last_accepted();  // nothing to take back across a bias set from outside
  // A restored bias is not confirmed until a stop after motion agrees with it.
  bias_from_startup_only_ = true;
}

void AutoEstimator::set_heading(double heading_deg, double variance_deg2) {
  if (variance_deg2 <= 0.0) {
    filters_[2].set_angle(heading_deg);
    auto state = filters_[2].state();
    state.covariance(0, 0) = 0.0;
    state.covariance(0, 1) = state.covariance(1, 0) = 0.0;
    filters_[2].restore(state);
  } else {
    filters_[2].measure_angle(heading_deg, variance_deg2);
  }
  // The segment under way must not take this back if it turns out still, nor may a
  // retraction of the segment before it (its states predate the fix).
  segment_.filters_at_start[2] = filters_[2].state();
  commit_last_accepted();
}

void AutoEstimator::begin_segment(double t_s) {
  segment_.stats.reset();
  segment_.blocks.reset();
  segment_.duration_s = 0.0;
  segment_.temp_sum_c = 0.0;
  segment_.temp_count = 0;
  segment_.start_t_s = t_s;
  for (std::size_t axis = 0; axis < 3; ++axis) segment_.filters_at_start[axis] = filters_[axis].state();
  segment_.attitude_at_start = attitude_.attitude();
  segment_.temperature_shift_dps.setZero();
  segment_.temperature_shift_var.setZero();
}

void AutoEstimator::add_to_segment(const Sample& sample, double dt_s) {
  segment_.stats.add(sample.rate_dps);
  segment_.blocks.add(sample.rate_dps, dt_s);
  segment_.duration_s += dt_s;
  if (std::isfinite(sample.temp_c)) {
    segment_.temp_sum_c += sample.temp_c;
    ++segment_.temp_count;
  }
}

bool AutoEstimator::range_gate_trips(const Vec3& rate_dps) const {
  if (segment_.stats.count() == 0) return false;
  const Vec3 low = segment_.stats.min_dps().cwiseMin(rate_dps);
  const Vec3 high = segment_.stats.max_dps().cwiseMax(rate_dps);
  return ((high - low).array() > settings_.k_range * sigma_still_dps_.array()).any();
}

SegmentVerdict AutoEstimator::close_startup() {
  in_startup_ = false;
  SegmentVerdict verdict{.closed = true, .index = segment_index_, .range_ok = true, .mean_ok = true, .accepted = true};
  const auto& stats = segment_.stats;
  if (!segments_.sigma_still_dps) sigma_still_dps_ = stats.sigma_dps().cwiseMax(kMinSigmaStillDps);
  const double duration_s = std::max(segment_.duration_s, kTimeEpsilonS);
  if (!settings_.arw_dps_rt_hz) {
    pooled_noise_.add(segment_.blocks);
    // With too few blocks, fall back to treating samples as white: N^2 = sigma^2 * dt.
    const double dt_s = duration_s / std::max<double>(1.0, stats.count());
    const Vec3 white_floor = stats.sigma_dps().cwiseAbs2() * dt_s;
    white_dps2_s_ = pooled_noise_.known() ? pooled_noise_.density_squared().cwiseMax(white_floor) : white_floor;
  }
  const Vec3 r = white_dps2_s_ / duration_s;
  for (std::size_t axis = 0; axis < 3; ++axis) {
    filters_[axis].reset(stats.mean_dps()[static_cast<Eigen::Index>(axis)], r[static_cast<Eigen::Index>(axis)]);
    if (segment_.temp_count > 0) {
      temperature_[axis].add(segment_.start_t_s + 0.5 * duration_s, segment_.temp_sum_c / segment_.temp_count,
                             stats.mean_dps()[static_cast<Eigen::Index>(axis)], r[static_cast<Eigen::Index>(axis)]);
    }
  }
  ++accepted_;
  last_still_t_s_ = segment_.start_t_s + duration_s;
  bias_from_startup_only_ = true;
  startup_start_t_s_ = segment_.start_t_s;
  return verdict;
}

SegmentVerdict AutoEstimator::close_segment() {
  SegmentVerdict verdict{.closed = true, .index = segment_index_};
  const double duration_s = segment_.duration_s;
  const bool long_enough = duration_s + kTimeEpsilonS >= settings_.min_segment_s && segment_.stats.count() >= 2;
  verdict.range_ok = long_enough;  // the gate held on every sample of the segment
  if (!long_enough) {
    ++cut_;
    previous_.usable = false;
    quiet_.duration_s = 0.0;  // motion: whatever the quiet run was, it has ended
    commit_last_accepted();   // motion came abruptly: the still segment before it stands
    return verdict;
  }
  const Vec3 mean = segment_.stats.mean_dps();
  if (white_dps2_s_.isZero()) {
    // Restored without a start-up segment and no configured density: treat samples as white.
    white_dps2_s_ = segment_.stats.sigma_dps().cwiseAbs2() * (duration_s / segment_.stats.count());
  }
  const Vec3 r = white_dps2_s_ / duration_s;
  bool mean_ok = true;
  for (std::size_t axis = 0; axis < 3; ++axis) {
    const auto a = static_cast<Eigen::Index>(axis);
    const double predicted = filters_[axis].bias_dps();
    const double sd = std::sqrt(filters_[axis].bias_variance() + r[a]);
    mean_ok = mean_ok && std::abs(mean[a] - predicted) <= settings_.k_mean * sd;
  }
  if (previous_.usable) {
    const double pooled_s = duration_s + previous_.duration_s;
    for (Eigen::Index a = 0; a < 3; ++a) {
      const double pooled_mean = (mean[a] * duration_s + previous_.mean_dps[a] * previous_.duration_s) / pooled_s;
      const double sd =
          std::sqrt(previous_.predicted_var[a] + walk_dps2_per_s_ * pooled_s + white_dps2_s_[a] / pooled_s);
      mean_ok = mean_ok && std::abs(pooled_mean - previous_.predicted_dps[a]) <= settings_.k_mean_pooled * sd;
    }
  }
  verdict.mean_ok = mean_ok;
  // A creep keeps its direction: this segment alone fails the mean test against the bias
  // predicted before the first, and the first leans the same way by at least a sigma of its
  // own. (The pooled test is no evidence here: it contains the first segment itself.) Noise
  // leans either way, and an acceptance it would take back stands.
  bool same_lean = false;
  if (previous_.usable) {
    const double first_lean = previous_.mean_dps.z() - previous_.predicted_dps.z();
    const double first_sd = std::sqrt(previous_.predicted_var.z() + white_dps2_s_.z() / previous_.duration_s);
    const double lean = mean.z() - previous_.predicted_dps.z();
    const double sd = std::sqrt(previous_.predicted_var.z() + walk_dps2_per_s_ * (previous_.duration_s + duration_s) +
                                white_dps2_s_.z() / duration_s);
    same_lean = first_lean * lean > 0.0 && std::abs(lean) > settings_.retract_next_lean * sd &&
                std::abs(first_lean) >= settings_.retract_min_lean * first_sd;
  }
  if (!mean_ok && same_lean && hint_ == MotionHint::None && settings_.retract_before_creep)
    retract_last_accepted();
  else
    commit_last_accepted();
  // Kept for the next segment's pooled test, which applies only if no cut comes between.
  previous_.usable = true;
  previous_.mean_dps = mean;
  previous_.duration_s = duration_s;
  for (std::size_t axis = 0; axis < 3; ++axis) {
    previous_.predicted_dps[static_cast<Eigen::Index>(axis)] = filters_[axis].bias_dps();
    previous_.predicted_var[static_cast<Eigen::Index>(axis)] = filters_[axis].bias_variance();
  }
  verdict.accepted = hint_ != MotionHint::Moving && (mean_ok || hint_ == MotionHint::Stopped);
  const double deviation_z = mean.z() - filters_[2].bias_dps();
  const double sd_z = std::sqrt(filters_[2].bias_variance() + r.z());
  if (verdict.accepted) {
    accept_still(mean, r, segment_.start_t_s + duration_s);
    if (hint_ != MotionHint::Stopped) add_verdict_doubt(deviation_z, sd_z, duration_s, true);
    ++accepted_;
    last_accepted_.pending = true;
    for (std::size_t axis = 0; axis < 3; ++axis) last_accepted_.as_still[axis] = filters_[axis].state();
    quiet_.duration_s = 0.0;
  } else {
    if (hint_ != MotionHint::Moving) add_verdict_doubt(deviation_z, sd_z, duration_s, false);
    ++rejected_;
    if (hint_ == MotionHint::None && settings_.recover_after_s > 0.0) follow_quiet_run(mean);
  }
  return verdict;
}

void AutoEstimator::add_verdict_doubt(double deviation_dps, double sd_dps, double duration_s, bool accepted) {
  // Likelihood of the observed deviation if still (Gaussian) and if turning slowly (flat).
  const double z = deviation_dps / sd_dps;
  const double still =
      (1.0 - settings_.creep_prior) * std::exp(-0.5 * z * z) / (sd_dps * std::sqrt(2.0 * std::numbers::pi));
  // Flat, and not cut off beyond the span: a fast turn must never look still by default.
  const double turning = settings_.creep_prior / (2.0 * settings_.creep_span_dps);
  const double p_wrong = (accepted ? turning : still) / (still + turning);
  // The heading takes the posterior mean of the turn over the segment instead of the hard
  // verdict's all or nothing, and the variance of that two-point posterior.
  const double angle_deg = deviation_dps * duration_s;
  const double soft = settings_.soft_verdicts ? p_wrong : 0.0;
  const double correction_deg = accepted ? soft * angle_deg : -soft * angle_deg;
  auto state = filters_[2].state();
  state.angle_deg += correction_deg;
  state.covariance(0, 0) += p_wrong * (1.0 - p_wrong) * angle_deg * angle_deg;
  filters_[2].restore(state);
  attitude_.set_attitude(Eigen::AngleAxisd(deg_to_rad(correction_deg), Vec3::UnitZ()) * attitude_.attitude());
}

void AutoEstimator::track_vibration(const Vec3& rate_dps, double dt_s) {
  const double diff = rate_dps.z() - previous_rate_z_dps_;
  previous_rate_z_dps_ = rate_dps.z();
  const double weight = std::min(1.0, dt_s / settings_.vibration_tau_s);
  diff_var_z_ += weight * (diff * diff - diff_var_z_);
}

void AutoEstimator::accept_still(const Vec3& mean_dps, const Vec3& r_dps2, double end_t_s) {
  // Zero-rate update: the platform did not turn during the segment, so take back what was
  // integrated over it, let only the bias drift, then measure the bias with the mean.
  for (std::size_t axis = 0; axis < 3; ++axis) {
    const auto a = static_cast<Eigen::Index>(axis);
    last_accepted_.as_moving[axis] = filters_[axis].state();
    filters_[axis].restore(segment_.filters_at_start[axis]);
    filters_[axis].let_bias_drift(segment_.duration_s, walk_dps2_per_s_);
    filters_[axis].shift_bias(segment_.temperature_shift_dps[a], segment_.temperature_shift_var[a]);
    filters_[axis].measure_bias(mean_dps[a], r_dps2[a]);
  }
  // The attitude goes back to the segment's start, turned about the vertical by the heading
  // correction the bias measurement made to the time before.
  const double yaw_correction_deg = filters_[2].angle_deg() - segment_.filters_at_start[2].angle_deg;
  attitude_.set_attitude(Eigen::AngleAxisd(deg_to_rad(yaw_correction_deg), Vec3::UnitZ()) * segment_.attitude_at_start);

  last_accepted_.has_temperature = segment_.temp_count > 0;
  if (last_accepted_.has_temperature) {
    last_accepted_.temp_c = segment_.temp_sum_c / segment_.temp_count;
    last_accepted_.mid_t_s = segment_.start_t_s + 0.5 * segment_.duration_s;
    last_accepted_.mean_dps = mean_dps;
    last_accepted_.r_dps2 = r_dps2;
  }
  if (!settings_.arw_dps_rt_hz) {
    pooled_noise_.add(segment_.blocks);
    if (pooled_noise_.known()) white_dps2_s_ = pooled_noise_.density_squared();
  }
  last_accepted_.last_still_before_t_s = last_still_t_s_;
  // Only a stop after motion confirms the start-up level; segments running on from the
  // start-up without a gate trip may be the same turn going on.
  if (motion_since_startup_) bias_from_startup_only_ = false;
  last_still_t_s_ = end_t_s;
}

void AutoEstimator::commit_last_accepted() {
  if (!last_accepted_.pending) return;
  last_accepted_.pending = false;
  if (!last_accepted_.has_temperature) return;
  for (std::size_t axis = 0; axis < 3; ++axis) {
    const auto a = static_cast<Eigen::Index>(axis);
    temperature_[axis].add(last_accepted_.mid_t_s, last_accepted_.temp_c, last_accepted_.mean_dps[a],
                           last_accepted_.r_dps2[a]);
  }
}

void AutoEstimator::retract_last_accepted() {
  if (!last_accepted_.pending) return;
  last_accepted_.pending = false;
  // The filter is linear: what the current segment did to the state judged still, it would
  // have done to the state judged moving. Carry the difference across it (F = [1, -T; 0, 1]).
  const double t_s = segment_.duration_s;
  Eigen::Matrix2d f;
  f << 1.0, -t_s, 0.0, 1.0;
  double yaw_change_deg = 0.0;
  for (std::size_t axis = 0; axis < 3; ++axis) {
    const auto& moving = last_accepted_.as_moving[axis];
    const auto& still = last_accepted_.as_still[axis];
    auto state = filters_[axis].state();
    const double d_bias = moving.bias_dps - still.bias_dps;
    const double d_angle = (moving.angle_deg - still.angle_deg) - t_s * d_bias;
    state.angle_deg += d_angle;
    state.bias_dps += d_bias;
    state.covariance += f * (moving.covariance - still.covariance) * f.transpose();
    state.covariance = 0.5 * (state.covariance + state.covariance.transpose()).eval();
    filters_[axis].restore(state);
    if (axis == 2) yaw_change_deg = d_angle;
  }
  attitude_.set_attitude(Eigen::AngleAxisd(deg_to_rad(yaw_change_deg), Vec3::UnitZ()) * attitude_.attitude());
  --accepted_;
  ++rejected_;
  ++retracted_;
  last_still_t_s_ = last_accepted_.last_still_before_t_s;
}

void AutoEstimator::follow_quiet_run(const Vec3& mean_dps) {
  const double duration_s = segment_.duration_s;
  bool agrees = quiet_.duration_s > 0.0;
  if (agrees) {
    // The same level within the mean test's own scale: a steady signal, not a changing rate.
    const Vec3 run_mean = quiet_.mean_dps();
    for (Eigen::Index a = 0; a < 3; ++a) {
      const double sd = std::sqrt(white_dps2_s_[a] / duration_s + white_dps2_s_[a] / quiet_.duration_s);
      agrees = agrees && std::abs(mean_dps[a] - run_mean[a]) <= settings_.k_mean * sd;
    }
  }
  if (!agrees) {
    quiet_ = QuietRun{};
    quiet_.filters_at_start = segment_.filters_at_start;
    quiet_.attitude_at_start = segment_.attitude_at_start;
  }
  quiet_.duration_s += duration_s;
  quiet_.sum_dps_s += mean_dps * duration_s;
  quiet_.sum_sq_dps2_s += mean_dps.cwiseAbs2() * duration_s;
  quiet_.sigma_dps = segment_.stats.sigma_dps();
  if (quiet_.duration_s + kTimeEpsilonS >= settings_.recover_after_s) recover_bias();
}

void AutoEstimator::recover_bias() {
  // Taken for a stop: the heading goes back to the run's start (a zero-rate update over it),
  // the bias starts again from the run's mean, and the heading's variance takes the whole
  // bias change over the time it was integrated with the old bias, for that is unknown:
  // from the last accepted segment to the run, or from the start when the old bias rests on
  // the start-up alone (that may have been a turn, held as still).
  const Vec3 mean = quiet_.mean_dps();
  // The bias variance: the mean's own noise, plus the spread of the segment means, for a run
  // taken for a stop may still hold some slow motion.
  const Vec3 spread = (quiet_.sum_sq_dps2_s / quiet_.duration_s - mean.cwiseAbs2()).cwiseMax(0.0);
  const Vec3 r = white_dps2_s_ / quiet_.duration_s + spread;
  const double run_start_s = segment_.start_t_s + segment_.duration_s - quiet_.duration_s;
  const double trusted_until_s = bias_from_startup_only_          ? startup_start_t_s_
                                 : std::isfinite(last_still_t_s_) ? last_still_t_s_
                                                                  : run_start_s;
  const double exposed_s = std::max(0.0, run_start_s - trusted_until_s);
  for (std::size_t axis = 0; axis < 3; ++axis) {
    const auto a = static_cast<Eigen::Index>(axis);
    AxisFilter::State state = quiet_.filters_at_start[axis];
    const double change_deg = (mean[a] - state.bias_dps) * exposed_s;
    state.bias_dps = mean[a];
    state.covariance(0, 0) += change_deg * change_deg;
    state.covariance(0, 1) = state.covariance(1, 0) = 0.0;
    state.covariance(1, 1) = r[a];
    filters_[axis].restore(state);
    temperature_[axis] = TemperatureModel(settings_.temperature);  // it learned from the wrong level
  }
  attitude_.set_attitude(quiet_.attitude_at_start);
  if (!segments_.sigma_still_dps) sigma_still_dps_ = quiet_.sigma_dps.cwiseMax(kMinSigmaStillDps);
  last_still_t_s_ = segment_.start_t_s + segment_.duration_s;
  previous_.usable = false;
  quiet_ = QuietRun{};
  bias_from_startup_only_ = false;
  ++recoveries_;
}

void AutoEstimator::follow_temperature(double temp_c) {
  if (!settings_.use_temperature || !std::isfinite(temp_c) || !std::isfinite(previous_temp_c_)) return;
  const double delta_c = temp_c - previous_temp_c_;
  if (delta_c == 0.0) return;
  for (std::size_t axis = 0; axis < 3; ++axis) {
    const auto& model = temperature_[axis];
    if (!model.ready()) continue;
    const double shift = model.slope_dps_per_c(temp_c) * delta_c;
    const double variance = model.slope_variance() * delta_c * delta_c;
    filters_[axis].shift_bias(shift, variance);
    segment_.temperature_shift_dps[static_cast<Eigen::Index>(axis)] += shift;
    segment_.temperature_shift_var[static_cast<Eigen::Index>(axis)] += variance;
  }
}

const Estimate& AutoEstimator::update(const Sample& sample) {
  estimate_.closed = SegmentVerdict{};
  if (!started_) {
    started_ = true;
    if (!std::isfinite(startup_start_t_s_)) startup_start_t_s_ = sample.t_s;
    previous_t_s_ = sample.t_s;
    previous_temp_c_ = sample.temp_c;
    begin_segment(sample.t_s);
    add_to_segment(sample, 0.0);
    fill_estimate(sample);
    return estimate_;
  }
  const double dt_s = sample.t_s - previous_t_s_;
  previous_t_s_ = sample.t_s;

  if (in_startup_) {
    if (sample.t_s - segment_.start_t_s >= segments_.segment_s - kTimeEpsilonS) {
      estimate_.closed = close_startup();
      ++segment_index_;
      begin_segment(sample.t_s);
    } else {
      add_to_segment(sample, dt_s);
      previous_temp_c_ = sample.temp_c;
      fill_estimate(sample);
      return estimate_;
    }
  } else {
    follow_temperature(sample.temp_c);
    const bool full = sample.t_s - segment_.start_t_s >= segments_.segment_s - kTimeEpsilonS;
    const bool trips = !full && range_gate_trips(sample.rate_dps);
    if (full || trips) {
      estimate_.closed = close_segment();
      if (trips) {
        previous_.usable = false;  // motion came between
        motion_since_startup_ = true;
      }
      ++segment_index_;
      begin_segment(sample.t_s);
    }
  }
  previous_temp_c_ = sample.temp_c;

  add_to_segment(sample, dt_s);
  track_vibration(sample.rate_dps, dt_s);
  // Vibration is white at the sample rate: half the variance of sample differences, times
  // dt, is its density squared. Still, the chip's own noise (N^2) dominates.
  const double vibration_dps2_s = 0.5 * diff_var_z_ * dt_s;
  for (std::size_t axis = 0; axis < 3; ++axis) {
    const auto a = static_cast<Eigen::Index>(axis);
    const double white = axis == 2 ? std::max(white_dps2_s_[a], vibration_dps2_s) : white_dps2_s_[a];
    filters_[axis].propagate(sample.rate_dps[a], dt_s, white, walk_dps2_per_s_);
  }
  const Vec3 bias(filters_[0].bias_dps(), filters_[1].bias_dps(), filters_[2].bias_dps());
  attitude_.add(sample.rate_dps - bias, dt_s);
  fill_estimate(sample);
  return estimate_;
}

void AutoEstimator::fill_estimate(const Sample& sample) {
  const Vec3 bias(filters_[0].bias_dps(), filters_[1].bias_dps(), filters_[2].bias_dps());
  estimate_.t_s = sample.t_s;
  estimate_.temp_c = sample.temp_c;
  estimate_.heading_deg = filters_[2].angle_deg();
  estimate_.attitude = attitude_.attitude();
  estimate_.bias_dps = bias;
  estimate_.rate_dps = sample.rate_dps - bias;
  if (in_startup_) {
    estimate_.heading_sigma_deg = 0.0;  // held by assumption: the platform is still
    estimate_.bias_sigma_dps = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  } else {
    estimate_.heading_sigma_deg = std::sqrt(std::max(0.0, filters_[2].angle_variance()));
    for (std::size_t axis = 0; axis < 3; ++axis)
      estimate_.bias_sigma_dps[static_cast<Eigen::Index>(axis)] =
          std::sqrt(std::max(0.0, filters_[axis].bias_variance()));
  }
  estimate_.in_startup = in_startup_;
  estimate_.segment_index = segment_index_;
}

}  // namespace headingd::core
