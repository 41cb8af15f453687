#include "core/attitude_integrator.hpp"

#include <cmath>

#include "core/units.hpp"

namespace headingd::core {
namespace {

// Below this half-angle (squared; h < 0.026 rad, a turn of 3 degrees in one sample) the
// series for cos(h) and sin(h)/h to h^6 are exact to double precision (the first term left
// out, h^8/8!, is under 1e-17): no libm call for the per-sample rotations, which are a few
// milliradians.
constexpr double kSeriesHalfAngle2 = 7e-4;
// The step is a unit quaternion to rounding, so q drifts from unit length by ~1e-16 per
// sample: normalising every 32nd sample keeps it within ~1e-14 and takes the square root and
// division off the per-sample chain.
constexpr unsigned kNormaliseEvery = 32;

}  // namespace

void AttitudeIntegrator::add(const Vec3& rate_dps, double dt_s) {
  // Written for a short chain of dependent operations (it runs on every sample and the next
  // sample cannot start before it ends): squares and sums in pairs, the series by Estrin's
  // scheme rather than Horner's, the product's sums in pairs.
  const double scale = kRadPerDeg * dt_s;
  const double rx = rate_dps.x() * scale, ry = rate_dps.y() * scale, rz = rate_dps.z() * scale;
  const double wx = rate_dps.x(), wy = rate_dps.y(), wz = rate_dps.z();
  const double h2 = (wx * wx + (wy * wy + wz * wz)) * (0.25 * scale * scale);  // half angle, squared
  double c = 0.0;
  double s = 0.0;  // sin(h) / angle, so that the step's vector part is s * rotation
  if (h2 < kSeriesHalfAngle2) {
    const double h4 = h2 * h2;
    c = (1.0 - 0.5 * h2) + h4 * (1.0 / 24 - h2 * (1.0 / 720));
    s = (0.5 - h2 * (0.5 / 6)) + h4 * (0.5 / 120 - h2 * (0.5 / 5040));
  } else {
    const double angle = 2.0 * std::sqrt(h2);
    c = std::cos(0.5 * angle);
    s = std::sin(0.5 * angle) / angle;
  }
  const double sx = s * rx, sy = s * ry, sz = s * rz;
  // q <- q * step (Hamilton product), written out: no Eigen temporaries on every sample.
  const double w = q_.w(), x = q_.x(), y = q_.y(), z = q_.z();
  q_.w() = (w * c - x * sx) - (y * sy + z * sz);
  q_.x() = (w * sx + x * c) + (y * sz - z * sy);
  q_.y() = (w * sy + y * c) + (z * sx - x * sz);
  q_.z() = (w * sz + z * c) + (x * sy - y * sx);
  if (++since_normalised_ == kNormaliseEvery) {
    since_normalised_ = 0;
    q_.normalize();
  }
}

}  // namespace headingd::core
