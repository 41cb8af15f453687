#include "core/temperature_trail.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

namespace headingd::core {

void TemperatureTrail::add(const Stop& stop) {
  if (!stop.level_dps.allFinite() || !std::isfinite(stop.temp_c) || !(stop.duration_s > 0.0)) return;
  stops_[next_] = stop;
  next_ = (next_ + 1) % kCapacity;
  count_ = std::min(count_ + 1, kCapacity);
}

const TemperatureTrail::Stop& TemperatureTrail::recent(std::size_t i) const {
  return stops_[(next_ + kCapacity - 1 - i) % kCapacity];
}

std::optional<TemperatureTrail::Line> TemperatureTrail::explain(const Stop& current, const Vec3& white_dps2_s,
                                                                double reading_variance_c2) const {
  if (!current.level_dps.allFinite() || !std::isfinite(current.temp_c) || !(current.duration_s > 0.0))
    return std::nullopt;
  // The longest stretch of latest stops that a line explains: an older stop that was a creep or a
  // slow curve must not hide the line the later ones show.
  for (std::size_t stops = count_; stops + 1 >= std::max<std::size_t>(settings_.min_stops, 3); --stops) {
    if (auto line = fit(stops, current, white_dps2_s, reading_variance_c2)) return line;
  }
  return std::nullopt;
}

std::optional<TemperatureTrail::Line> TemperatureTrail::fit(std::size_t stops, const Stop& current,
                                                            const Vec3& white_dps2_s,
                                                            double reading_variance_c2) const {
  const std::size_t n = stops + 1;
  std::array<Stop, kCapacity + 1> points{};
  points[0] = current;
  for (std::size_t i = 0; i < stops; ++i) points[i + 1] = recent(i);
  // The spread without the coldest stop and without the warmest: one stop far from a cluster of
  // others makes any two levels a line (random world 101: three stops within 0.1 C and one 2 C
  // colder, a creep's level apart, read as -0.053 dps/C).
  std::array<double, kCapacity + 1> temps{};
  for (std::size_t i = 0; i < n; ++i) temps[i] = points[i].temp_c;
  std::sort(temps.begin(), temps.begin() + static_cast<std::ptrdiff_t>(n));
  if (std::min(temps[n - 2] - temps[0], temps[n - 1] - temps[1]) < settings_.min_span_c) return std::nullopt;

  Line line{.coldest_c = temps[0], .warmest_c = temps[n - 1], .stops = n};
  bool steep = false;
  for (Eigen::Index a = 0; a < 3; ++a) {
    const auto variance = [&](std::size_t i, double slope) {
      return white_dps2_s[a] / points[i].duration_s + settings_.floor_dps * settings_.floor_dps +
             slope * slope * reading_variance_c2;
    };
    // Weighted least squares; a second pass takes the temperatures' own error at the slope found.
    double slope = 0.0, mean_t = 0.0, mean_y = 0.0, sxx = 0.0, sw = 0.0;
    for (int pass = 0; pass < 2; ++pass) {
      double swx = 0.0, swy = 0.0, swxx = 0.0, swxy = 0.0;
      sw = 0.0;
      for (std::size_t i = 0; i < n; ++i) {
        const double w = 1.0 / variance(i, slope);
        const double x = points[i].temp_c, y = points[i].level_dps[a];
        sw += w;
        swx += w * x;
        swy += w * y;
        swxx += w * x * x;
        swxy += w * x * y;
      }
      mean_t = swx / sw;
      mean_y = swy / sw;
      sxx = swxx - swx * mean_t;
      if (!(sxx > 0.0)) return std::nullopt;
      slope = (swxy - swx * mean_y) / sxx;
    }
    double chi2 = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const double residual = points[i].level_dps[a] - (mean_y + slope * (points[i].temp_c - mean_t));
      const double normalized2 = residual * residual / variance(i, slope);
      if (normalized2 > settings_.sigmas * settings_.sigmas) return std::nullopt;
      chi2 += normalized2;
    }
    // Scatter beyond the variances assumed widens the line's own (never narrows it).
    const double scale = std::max(1.0, chi2 / static_cast<double>(n - 2));
    const double slope_variance = scale / sxx;
    if (!std::isfinite(slope) || std::abs(slope) > settings_.max_slope_dps_per_c) return std::nullopt;
    // Steep beyond doubt on the heading's axis: the slope less its sigmas still beyond the drift
    // assumed without a model. A line on x or y alone (a tilt axis's level wandering under
    // vibration, random world 87) says nothing the heading needs.
    if (a == 2) steep = std::abs(slope) - settings_.sigmas * std::sqrt(slope_variance) > settings_.min_slope_dps_per_c;
    line.slope_dps_per_c[a] = slope;
    line.slope_variance[a] = slope_variance;
    line.level_dps[a] = mean_y;
    line.level_variance[a] = scale / sw;
    line.mean_temp_c[a] = mean_t;
  }
  if (!steep) return std::nullopt;
  return line;
}

}  // namespace headingd::core
