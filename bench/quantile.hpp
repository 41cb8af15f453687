#pragma once
// The q-quantile of a bench's figures (nearest rank below; NaN for none), shared by the benches
// that print spreads of per-run figures.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace headingd::bench {

inline double quantile(std::vector<double> v, double q) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1))];
}

}  // namespace headingd::bench
