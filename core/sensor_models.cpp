#include "core/sensor_models.hpp"

#include <algorithm>
#include <cmath>

namespace headingd::core {
namespace {
constexpr double kMinSigmaStillDps = 1e-6;
constexpr double kInflatedNoiseRatio = 10.0;
// A slope the drift assumed without a model (1 sigma) puts beyond 3 sigma contradicts it.
constexpr double kEarlySlopePerUnmodelled = 3.0;

AutoSettings with_early_slope(AutoSettings settings) {
  settings.temperature.early_slope_dps_per_c = kEarlySlopePerUnmodelled * settings.unmodelled_bias_per_c_dps;
  return settings;
}
}  // namespace

SensorModels::SensorModels(const BiasSettings& segments, const AutoSettings& settings)
    : segments_(segments),
      settings_(with_early_slope(settings)),
      temperature_{TemperatureModel(settings_.temperature), TemperatureModel(settings_.temperature),
                   TemperatureModel(settings_.temperature)} {
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

bool SensorModels::replace_sigma_still(const Vec3& sigma_dps) {
  if (segments_.sigma_still_dps) return false;
  sigma_still_dps_ = sigma_dps.cwiseMax(kMinSigmaStillDps);
  return true;
}

void SensorModels::relearn_after_recovery(const Vec3& sigma_dps) {
  for (auto& model : temperature_) model = TemperatureModel(settings_.temperature);
  if (!segments_.sigma_still_dps) sigma_still_dps_ = sigma_dps.cwiseMax(kMinSigmaStillDps);
}

void SensorModels::restart_noise_if_inflated(const SegmentStats& stats, const BlockMeans& blocks, double duration_s) {
  if (settings_.arw_dps_rt_hz) return;
  SensorModels fresh(segments_, settings_);
  fresh.learn_from_startup(stats, blocks, duration_s);
  // A variance ratio no chance spread of a few blocks reaches (F beyond 99.9 % for the dof of one segment).
  if (!(white_dps2_s_.array() > kInflatedNoiseRatio * fresh.white_dps2_s_.array()).any()) return;
  pooled_noise_ = fresh.pooled_noise_;
  white_dps2_s_ = fresh.white_dps2_s_;
  if (!segments_.sigma_still_dps) sigma_still_dps_ = fresh.sigma_still_dps_;
}

void SensorModels::add_temperature_point(double mid_t_s, double temp_c, const Vec3& mean_dps, const Vec3& r_dps2,
                                         double run_start_t_s) {
  for (std::size_t axis = 0; axis < 3; ++axis) {
    const auto a = static_cast<Eigen::Index>(axis);
    temperature_[axis].add(mid_t_s, temp_c, mean_dps[a], r_dps2[a], run_start_t_s);
  }
}

void SensorModels::restore_noise(const Vec3& sigma_still_dps, const Vec3& arw_dps_rt_hz) {
  if (!segments_.sigma_still_dps && (sigma_still_dps.array() > 0).all()) sigma_still_dps_ = sigma_still_dps;
  if (!settings_.arw_dps_rt_hz && (arw_dps_rt_hz.array() > 0).all()) white_dps2_s_ = arw_dps_rt_hz.cwiseAbs2();
}

}  // namespace headingd::core
