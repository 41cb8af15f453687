#include "core/scale_factor.hpp"

#include <algorithm>
#include <cmath>

namespace headingd::core {
namespace {

// Learning only over a turn this large, and never surer than 0.1 % (the datasheet's 0.2 % of
// full scale non-linearity, as 2 sigma).
constexpr double kMinTurnDeg = 30.0;
constexpr double kMinVariance = 0.001 * 0.001;
// An innovation beyond this many sigmas of what the scale and the angle's variance explain came
// from elsewhere (a wrong bias the filter believed): nothing to learn about the scale from it.
constexpr double kGateSigmas = 3.0;

}  // namespace

void ScaleFactor::learn(double innovation_deg, double turned_deg, double angle_variance_deg2,
                        double fix_variance_deg2) {
  // The error left after the correction so far, d, made an error of turned * d: H = -turned.
  if (!(variance_ > 0.0) || std::abs(turned_deg) < kMinTurnDeg) return;
  const double s =
      std::max(0.0, angle_variance_deg2) + turned_deg * turned_deg * variance_ + std::max(0.0, fix_variance_deg2);
  if (innovation_deg * innovation_deg > kGateSigmas * kGateSigmas * s) return;
  const double k = -turned_deg * variance_ / s;
  estimate_ = std::clamp(estimate_ + k * innovation_deg, -kMaxLearnedScale, kMaxLearnedScale);
  variance_ = std::max(kMinVariance, variance_ * (1.0 + k * turned_deg));
  gain_ = 1.0 / (1.0 + estimate_);
  learned_ = true;
}

void ScaleFactor::restore(double estimate, double sigma) {
  estimate_ = std::clamp(estimate, -kMaxLearnedScale, kMaxLearnedScale);
  variance_ = std::clamp(sigma * sigma, std::min(kMinVariance, configured_variance_), configured_variance_);
  gain_ = 1.0 / (1.0 + estimate_);
  learned_ = true;
}

double ScaleFactor::sigma() const { return std::sqrt(variance_); }

}  // namespace headingd::core
