#include "core/sensor_models.hpp"

#include <algorithm>
#include <cmath>

namespace headingd::core {
namespace {
constexpr double kMinSigmaStillDps = 1e-6;
}  // namespace

SensorModels::SensorModels(const BiasSettings& segments, const AutoSettings& settings)
    : segments_(segments),
      settings_(settings),
      temperature_{TemperatureModel(settings.temperature), TemperatureModel(settings.temperature),
                   TemperatureModel(settings.temperature)} {
  if (segments_.sigma_still_dps) sigma_still_dps_ = *segments_.sigma_still_dps;
  if (settings_.arw_dps_rt_hz) white_dps2_s_ = settings_.arw_dps_rt_hz->cwiseAbs2();
}

void SensorModels::learn_from_startup(const SegmentStats& stats, const BlockMeans& blocks, double duration_s) {
  if (!segments_.sigma_still_dps) sigma_still_dps_ = stats.sigma_dps().cwiseMax(kMinSigmaStillDps);
  if (settings_.arw_dps_rt_hz) return;
  pooled_noise_.add(blocks);
  // With too few blocks, fall back to treating samples as white: N^2 = sigma^2 * dt.
  const double dt_s = duration_s / std::max<double>(1.0, stats.count());
  const Vec3 white_floor = stats.sigma_dps().cwiseAbs2() * dt_s;
  white_dps2_s_ = pooled_noise_.known() ? pooled_noise_.density_squared().cwiseMax(white_floor) : white_floor;
}

void SensorModels::learn_from_still(const BlockMeans& blocks) {
  if (settings_.arw_dps_rt_hz) return;
  pooled_noise_.add(blocks);
  if (pooled_noise_.known()) white_dps2_s_ = pooled_noise_.density_squared();
}

void SensorModels::assume_white_if_unknown(const SegmentStats& stats, double duration_s) {
  if (!white_dps2_s_.isZero()) return;
  white_dps2_s_ = stats.sigma_dps().cwiseAbs2() * (duration_s / stats.count());
}

void SensorModels::relearn_after_recovery(const Vec3& sigma_dps) {
  for (auto& model : temperature_) model = TemperatureModel(settings_.temperature);
  if (!segments_.sigma_still_dps) sigma_still_dps_ = sigma_dps.cwiseMax(kMinSigmaStillDps);
}

void SensorModels::add_temperature_point(double mid_t_s, double temp_c, const Vec3& mean_dps, const Vec3& r_dps2) {
  for (std::size_t axis = 0; axis < 3; ++axis) {
    const auto a = static_cast<Eigen::Index>(axis);
    temperature_[axis].add(mid_t_s, temp_c, mean_dps[a], r_dps2[a]);
  }
}

bool SensorModels::temperature_shift(double temp_c, double previous_temp_c, Vec3& shift_dps,
                                     Vec3& variance_dps2) const {
  if (!settings_.use_temperature || !std::isfinite(temp_c) || !std::isfinite(previous_temp_c)) return false;
  const double delta_c = temp_c - previous_temp_c;
  if (delta_c == 0.0) return false;
  shift_dps.setZero();
  variance_dps2.setZero();
  bool any = false;
  for (std::size_t axis = 0; axis < 3; ++axis) {
    const auto& model = temperature_[axis];
    if (!model.ready()) continue;
    const auto a = static_cast<Eigen::Index>(axis);
    shift_dps[a] = model.slope_dps_per_c(temp_c) * delta_c;
    variance_dps2[a] = model.slope_variance() * delta_c * delta_c;
    any = true;
  }
  return any;
}

void SensorModels::track_vibration(const Vec3& rate_dps, double dt_s) {
  const double diff = rate_dps.z() - previous_rate_z_dps_;
  previous_rate_z_dps_ = rate_dps.z();
  const double weight = std::min(1.0, dt_s / settings_.vibration_tau_s);
  diff_var_z_ += weight * (diff * diff - diff_var_z_);
}

Vec3 SensorModels::process_white_dps2_s(double dt_s) const {
  // Vibration is white at the sample rate: half the variance of sample differences, times
  // dt, is its density squared. Still, the chip's own noise (N^2) dominates.
  const double vibration_dps2_s = 0.5 * diff_var_z_ * dt_s;
  return {white_dps2_s_.x(), white_dps2_s_.y(), std::max(white_dps2_s_.z(), vibration_dps2_s)};
}

void SensorModels::restore_noise(const Vec3& sigma_still_dps, const Vec3& arw_dps_rt_hz) {
  if (!segments_.sigma_still_dps && (sigma_still_dps.array() > 0).all()) sigma_still_dps_ = sigma_still_dps;
  if (!settings_.arw_dps_rt_hz && (arw_dps_rt_hz.array() > 0).all()) white_dps2_s_ = arw_dps_rt_hz.cwiseAbs2();
}

}  // namespace headingd::core
