// libFuzzer target: whole recordings through the estimator, with the output invariant as the
// oracle. The input bytes are a method, a sample rate, then samples (time step, three rates,
// temperature) anywhere within what the door lets through; hints and heading fixes are mixed
// in. Every estimate must be finite, or a fault with an infinite sigma: never NaN.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>

#include "core/estimator.hpp"

namespace {

struct Reader {
  const unsigned char* data;
  std::size_t size;
  std::size_t at = 0;
  template <typename T>
  bool take(T& out) {
    if (at + sizeof(T) > size) return false;
    std::memcpy(&out, data + at, sizeof(T));
    at += sizeof(T);
    return true;
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const unsigned char* data, std::size_t size) {
  using namespace headingd::core;
  Reader in{data, size};
  std::uint8_t method_byte = 0, scale_byte = 0;
  if (!in.take(method_byte) || !in.take(scale_byte)) return 0;
  EstimatorSettings settings;
  settings.method = static_cast<Method>(method_byte % 4);
  settings.segments.still_at_start = (method_byte & 0x10) == 0;
  if (!settings.segments.still_at_start) settings.segments.sigma_still_dps = Vec3(0.5, 0.5, 0.1);
  if (validate(settings)) return 0;
  Estimator estimator(settings);
  // Rates span up to the door's limit: full scale from 0.01 to 10000 dps.
  const double full_scale = kMaxPlausibleRateDps * std::pow(10.0, -static_cast<double>(scale_byte % 7));
  double t_s = 0.0;
  Sample sample;
  std::uint16_t step = 0;
  std::int16_t raw[3] = {0, 0, 0};
  std::int8_t temp = 0;
  std::uint8_t extra = 0;
  while (in.take(step) && in.take(raw) && in.take(temp) && in.take(extra)) {
    t_s += (1 + step) * 1e-5;  // 10 us .. 0.65 s between samples
    sample.t_s = t_s;
    for (int a = 0; a < 3; ++a) sample.rate_dps[a] = raw[a] / 32767.0 * full_scale;
    sample.temp_c = temp == -128 ? NAN : temp;
    if (!plausible(sample)) continue;  // the door, as the pipeline has it
    switch (extra) {
      case 1:
        estimator.set_motion_hint(MotionHint::Stopped);
        break;
      case 2:
        estimator.set_motion_hint(MotionHint::Moving);
        break;
      case 3:
        estimator.set_motion_hint(MotionHint::None);
        break;
      case 4:
        estimator.set_heading(raw[0] / 10.0, std::abs(raw[1]) / 100.0);
        break;
      default:
        break;
    }
    const Estimate& e = estimator.update(sample);
    const bool finite = std::isfinite(e.heading_deg) && e.attitude.coeffs().allFinite() && e.bias_dps.allFinite() &&
                        e.rate_dps.allFinite();
    if (!finite) __builtin_trap();
    if (settings.method == Method::Auto && std::isnan(e.heading_sigma_deg)) __builtin_trap();
    if (std::isinf(e.heading_sigma_deg) && !e.fault) __builtin_trap();
  }
  if (const auto problem = implausible(estimator.learned())) {
    const auto l = estimator.learned();
    std::fprintf(stderr, "learned state refused by restore: %s (%g %g %g; last %g; fault %d; samples %llu)\n",
                 problem->c_str(), l.bias_dps.x(), l.bias_dps.y(), l.bias_dps.z(), estimator.last().bias_dps.z(),
                 estimator.fault(), (unsigned long long)estimator.samples());
    __builtin_trap();
  }
  return 0;
}
