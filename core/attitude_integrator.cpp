#include "core/attitude_integrator.hpp"

#include <algorithm>
#include <array>
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

// Written for a short chain of dependent operations: squares and sums in pairs, the series by
// Estrin's scheme rather than Horner's.
[[gnu::always_inline]] inline AttitudeIntegrator::Step AttitudeIntegrator::step_of(double x_dps, double y_dps,
                                                                                   double z_dps, double dt_s) {
  const double scale = kRadPerDeg * dt_s;
  const double h2 = (x_dps * x_dps + (y_dps * y_dps + z_dps * z_dps)) * (0.25 * scale * scale);  // half angle^2
  double c = 0.0;
  double s = 0.0;  // sin(h) / angle, so that the step's vector part is s * rotation
  if (h2 < kSeriesHalfAngle2) [[likely]] {
    const double h4 = h2 * h2;
    c = (1.0 - 0.5 * h2) + h4 * (1.0 / 24 - h2 * (1.0 / 720));
    s = (0.5 - h2 * (0.5 / 6)) + h4 * (0.5 / 120 - h2 * (0.5 / 5040));
  } else {
    const double angle = 2.0 * std::sqrt(h2);
    c = std::cos(0.5 * angle);
    s = std::sin(0.5 * angle) / angle;
  }
  return {c, s * (x_dps * scale), s * (y_dps * scale), s * (z_dps * scale)};
}

void AttitudeIntegrator::add_all(const Turn* turns, std::size_t count) {
  // The rotations of a block first, then their products: q <- q * step (Hamilton product),
  // written out with its sums in pairs, on local copies of q. This is the chain every sample
  // waits on; nothing else stands in it.
  constexpr std::size_t kBlock = 64;
  std::array<Step, kBlock> steps;
  double w = q_.w(), x = q_.x(), y = q_.y(), z = q_.z();
  double vx = vertical_turn_deg_.x(), vy = vertical_turn_deg_.y(), vz = vertical_turn_deg_.z();
  for (std::size_t from = 0; from < count; from += kBlock) {
    const std::size_t n = std::min(kBlock, count - from);
    for (std::size_t i = 0; i < n; ++i) {
      const Turn& t = turns[from + i];
      steps[i] = step_of(t.x_dps, t.y_dps, t.z_dps, t.dt_s);
    }
    for (std::size_t i = 0; i < n; ++i) {
      // The vertical in body coordinates (the third row of the rotation q makes), at the step's
      // start; nothing in the chain waits on these sums.
      const Turn& t = turns[from + i];
      vx += 2.0 * (x * z - w * y) * (t.x_dps * t.dt_s);
      vy += 2.0 * (y * z + w * x) * (t.y_dps * t.dt_s);
      vz += (1.0 - 2.0 * (x * x + y * y)) * (t.z_dps * t.dt_s);
      const double c = steps[i].c, sx = steps[i].sx, sy = steps[i].sy, sz = steps[i].sz;
      const double w1 = (w * c - x * sx) - (y * sy + z * sz);
      const double x1 = (w * sx + x * c) + (y * sz - z * sy);
      const double y1 = (w * sy + y * c) + (z * sx - x * sz);
      const double z1 = (w * sz + z * c) + (x * sy - y * sx);
      w = w1, x = x1, y = y1, z = z1;
      if (++since_normalised_ == kNormaliseEvery) [[unlikely]] {
        since_normalised_ = 0;
        Eigen::Quaterniond q(w, x, y, z);
        q.normalize();
        w = q.w(), x = q.x(), y = q.y(), z = q.z();
      }
    }
  }
  q_ = Eigen::Quaterniond(w, x, y, z);
  vertical_turn_deg_ = Vec3(vx, vy, vz);
}

}  // namespace headingd::core
