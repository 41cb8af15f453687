#include "core/allan.hpp"

#include <algorithm>
#include <cmath>

namespace headingd::core {

std::vector<std::size_t> log_spaced_clusters(std::size_t samples, int per_decade, std::size_t min_terms) {
  std::vector<std::size_t> sizes;
  if (samples < min_terms + 2) return sizes;
  const std::size_t largest = (samples - min_terms + 1) / 2;
  for (int step = 0;; ++step) {
    const auto m = static_cast<std::size_t>(std::llround(std::pow(10.0, static_cast<double>(step) / per_decade)));
    if (m > largest) break;
    if (sizes.empty() || m != sizes.back()) sizes.push_back(m);
  }
  return sizes;
}

std::vector<AllanPoint> allan_deviation(std::span<const double> rate, double period_s,
                                        std::span<const std::size_t> clusters) {
  const std::size_t n = rate.size();
  // Integrated angle with the mean rate removed (the mean does not change any second
  // difference, and leaving it in would cost digits over long recordings).
  double mean = 0.0;
  for (double x : rate) mean += x;
  mean /= static_cast<double>(std::max<std::size_t>(n, 1));
  std::vector<double> angle(n + 1, 0.0);
  for (std::size_t i = 0; i < n; ++i) angle[i + 1] = angle[i] + (rate[i] - mean) * period_s;

  std::vector<AllanPoint> curve;
  for (const std::size_t m : clusters) {
    if (m == 0 || 2 * m > n) continue;
    const std::size_t terms = n - 2 * m + 1;
    double sum = 0.0;
    for (std::size_t k = 0; k < terms; ++k) {
      const double d = angle[k + 2 * m] - 2.0 * angle[k + m] + angle[k];
      sum += d * d;
    }
    const double tau = static_cast<double>(m) * period_s;
    curve.push_back(AllanPoint{tau, std::sqrt(sum / (2.0 * tau * tau * static_cast<double>(terms))), terms});
  }
  return curve;
}

namespace {

// log-log interpolation of sigma * tau^power at tau (the curve's value on a line of that slope).
double read_at(std::span<const AllanPoint> curve, double tau, double power) {
  const auto value = [&](const AllanPoint& p) { return std::log(p.deviation * std::pow(p.tau_s, power)); };
  if (tau <= curve.front().tau_s) return std::exp(value(curve.front()));
  if (tau >= curve.back().tau_s) return std::exp(value(curve.back()));
  for (std::size_t i = 1; i < curve.size(); ++i) {
    if (curve[i].tau_s >= tau) {
      const double w = std::log(tau / curve[i - 1].tau_s) / std::log(curve[i].tau_s / curve[i - 1].tau_s);
      return std::exp((1.0 - w) * value(curve[i - 1]) + w * value(curve[i]));
    }
  }
  return std::exp(value(curve.back()));
}

}  // namespace

NoiseTerms read_noise_terms(std::span<const AllanPoint> curve) {
  NoiseTerms terms;
  if (curve.size() < 3) return terms;
  terms.arw = read_at(curve, 1.0, 0.5);  // sigma * sqrt(tau) at tau = 1 s
  const auto minimum = std::min_element(
      curve.begin(), curve.end(), [](const AllanPoint& a, const AllanPoint& b) { return a.deviation < b.deviation; });
  terms.bias_instability = minimum->deviation / 0.664;
  terms.tau_at_minimum_s = minimum->tau_s;
  // Rate random walk: past the minimum, the first stretch rising with a slope near +1/2.
  for (auto it = minimum + 1; it + 1 < curve.end(); ++it) {
    const double slope = std::log((it + 1)->deviation / it->deviation) / std::log((it + 1)->tau_s / it->tau_s);
    if (slope > 0.35 && slope < 0.75 && it->clusters >= 30) {
      terms.rate_random_walk = it->deviation * std::sqrt(3.0 / it->tau_s);
      break;
    }
  }
  return terms;
}

}  // namespace headingd::core
