// CPU cost of the live path at 400 Hz (378.8 Hz real): the L3GD20H driver reading the
// register-level simulator (whose own work is included, so the driver figure is an upper
// bound), and the auto estimator on top. Thread CPU time, median of 5 runs of 10 simulated
// minutes each; the share of one core is CPU time over simulated (= real) time.
#include <algorithm>
#include <cstdio>
#include <ctime>
#include <vector>

#include "core/estimator.hpp"
#include "core/memory_source.hpp"
#include "hw/l3gd20h.hpp"
#include "machine.hpp"
#include "pipeline/pipeline.hpp"
#include "sim/l3gd20h_sim.hpp"

using namespace headingd;

namespace {

double cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

struct Result {
  double driver_s, estimator_s;
  std::uint64_t samples, wakeups;
  double span_s;
};

Result run_once(double seconds) {
  drivers::L3gd20hSimulator sim({}, "agv", 3);
  drivers::L3gd20h driver(sim, sim, {});
  driver.start();
  std::vector<core::Sample> all;
  all.reserve(static_cast<std::size_t>(seconds * 400));
  std::vector<core::Sample> batch(64);
  const double start = cpu_s();
  while (all.empty() || all.back().t_s - all.front().t_s < seconds) {
    const auto n = driver.read(batch);
    all.insert(all.end(), batch.begin(), batch.begin() + static_cast<long>(n));
  }
  const double driver_s = cpu_s() - start;
  core::MemorySource source(all);
  pipeline::Pipeline line(source, std::make_unique<core::Estimator>(), {});
  const double start_estimator = cpu_s();
  line.run();
  const double estimator_s = cpu_s() - start_estimator;
  if (line.estimator().last().heading_deg == 0.123) std::printf(" ");
  return {driver_s, estimator_s, all.size(), driver.counters().wakeups, all.back().t_s - all.front().t_s};
}

}  // namespace

int main() {
  constexpr double kSeconds = 600.0;
  std::printf("machine: %s\n", bench::machine_description().c_str());
  std::vector<double> drv_wake, drv_sample, est_sample, share;
  Result r{};
  for (int i = 0; i < 5; ++i) {
    r = run_once(kSeconds);
    drv_wake.push_back(r.driver_s / static_cast<double>(r.wakeups) * 1e6);
    drv_sample.push_back(r.driver_s / static_cast<double>(r.samples) * 1e6);
    est_sample.push_back(r.estimator_s / static_cast<double>(r.samples) * 1e6);
    share.push_back((r.driver_s + r.estimator_s) / r.span_s * 100.0);
  }
  std::printf("simulated %.0f s at %.1f Hz: %llu samples, %llu wake-ups (%.1f samples per wake-up)\n", r.span_s,
              static_cast<double>(r.samples) / r.span_s, static_cast<unsigned long long>(r.samples),
              static_cast<unsigned long long>(r.wakeups),
              static_cast<double>(r.samples) / static_cast<double>(r.wakeups));
  std::printf("driver + simulated chip: %.1f us per wake-up, %.2f us per sample (median of 5)\n", median(drv_wake),
              median(drv_sample));
  std::printf("auto estimator:          %.2f us per sample (median of 5)\n", median(est_sample));
  std::printf("together: %.3f %% of one core at 400 Hz (median of 5)\n", median(share));
  return 0;
}
