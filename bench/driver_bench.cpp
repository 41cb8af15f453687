// CPU cost of the live path at 400 Hz (378.8 Hz real): the L3GD20H driver reading the
// register-level simulator (whose own work is included, so the driver figure is an upper
// bound), the IIO source reading a fake IIO tree's FIFO (poll + read + decode, one
// watermark's worth of scans per wake-up, as the kernel hands them over; the writer's work is
// on another thread and not counted), and the auto estimator on top. Thread CPU time, median of 5 runs of 10 simulated
// minutes each; the share of one core is CPU time over simulated (= real) time.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <thread>
#include <vector>

#include "core/estimator.hpp"
#include "core/memory_source.hpp"
#include "hw/iio_gyro.hpp"
#include "hw/l3gd20h.hpp"
#include "machine.hpp"
#include "pipeline/pipeline.hpp"
#include "sim/gyro_simulator.hpp"
#include "sim/iio_fake.hpp"
#include "sim/l3gd20h_sim.hpp"

using namespace headingd;

namespace {

// Both sources compared at watermark 16, one burst size for both (the defaults are smaller, a
// wake-up per publication or more: see bench/sample_age.sh).
const drivers::L3gd20hSettings kWatermark16 = [] {
  drivers::L3gd20hSettings settings;
  settings.watermark = 16;
  return settings;
}();

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
  drivers::L3gd20h driver(sim, sim, kWatermark16);
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

struct IioResult {
  double reader_s;
  std::uint64_t samples, wakeups;
};

// The IIO source on a fake st_gyro tree: the writer hands over `watermark` scans, waits until
// the reader has taken them, and hands over the next, so every wake-up reads one watermark.
IioResult run_iio_once(double seconds, int watermark, bool paced = false) {
  char pattern[] = "/tmp/headingd-driver-bench-XXXXXX";
  const std::string root = ::mkdtemp(pattern);
  drivers::FakeIioTree tree({root, drivers::FakeIioLayout::St16, 0});
  tree.create();
  drivers::IioSettings settings;
  settings.root = root;
  settings.watermark = watermark;
  drivers::IioGyro gyro(settings);
  const auto total = static_cast<std::uint64_t>(seconds * 378.8);
  std::atomic<std::uint64_t> consumed{0};
  std::thread writer([&] {
    auto scenario = *drivers::build_scenario("agv", 3, seconds / 3600.0);
    drivers::GyroSimulator sim(scenario, 3);
    drivers::FakeIioWriter out(tree);
    const std::size_t bytes = tree.layout().scan_bytes();
    std::vector<std::uint8_t> burst(bytes * static_cast<std::size_t>(watermark));
    const auto start = std::chrono::steady_clock::now();
    for (std::uint64_t written = 0; written < total;) {
      if (paced)  // the kernel hands a watermark over when its last scan has been measured
        std::this_thread::sleep_until(
            start + std::chrono::duration<double>(static_cast<double>(written + static_cast<std::uint64_t>(watermark)) /
                                                  378.8));
      for (int k = 0; k < watermark; ++k, ++written) {
        core::Sample s;
        drivers::TruthPoint t;
        sim.step(s, t);
        tree.encode(s.rate_dps, static_cast<std::int64_t>(static_cast<double>(written) * 1e9 / 378.8),
                    std::span(burst).subspan(static_cast<std::size_t>(k) * bytes, bytes));
      }
      out.write(burst);
      if (!paced)
        for (auto seen = consumed.load(); seen < written; seen = consumed.load()) consumed.wait(seen);
    }
  });
  std::vector<core::Sample> batch(64);
  std::uint64_t samples = 0;
  const double start = cpu_s();
  while (samples < total) {
    samples += gyro.read(batch);
    consumed = samples;
    if (!paced) consumed.notify_one();
  }
  const double reader_s = cpu_s() - start;
  writer.join();
  IioResult r{reader_s, samples, gyro.counters().wakeups};
  gyro.close();
  std::filesystem::remove_all(root);
  return r;
}

// The L3GD20H driver on the simulator at the chip's real pace: it sleeps until its FIFO reaches
// the watermark, as on hardware it sleeps on the INT2 line. Thread CPU time per sample.
double l3gd20h_paced_us(double seconds) {
  drivers::L3gd20hSimulator sim({}, "agv", 3);
  sim.set_realtime(true);
  drivers::L3gd20h driver(sim, sim, kWatermark16);
  driver.start();
  std::vector<core::Sample> batch(64);
  std::uint64_t samples = 0;
  double first = -1.0, last = 0.0;
  const double start = cpu_s();
  while (first < 0 || last - first < seconds) {
    const auto n = driver.read(batch);
    if (n == 0) continue;
    if (first < 0) first = batch[0].t_s;
    last = batch[n - 1].t_s;
    samples += n;
  }
  return (cpu_s() - start) / static_cast<double>(samples) * 1e6;
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
  std::vector<double> iio_sample, iio_wake, iio16_sample, iio16_per_wake;
  IioResult iio{};
  for (int i = 0; i < 5; ++i) {
    iio = run_iio_once(kSeconds, 8);
    iio_sample.push_back(iio.reader_s / static_cast<double>(iio.samples) * 1e6);
    iio_wake.push_back(iio.reader_s / static_cast<double>(iio.wakeups) * 1e6);
    const IioResult same = run_iio_once(kSeconds, 16);
    iio16_sample.push_back(same.reader_s / static_cast<double>(same.samples) * 1e6);
    iio16_per_wake.push_back(static_cast<double>(same.samples) / static_cast<double>(same.wakeups));
  }
  std::printf(
      "IIO source (fake st_gyro tree, FIFO, watermark 8): %.1f us per wake-up, %.2f us per "
      "sample (median of 5)\n",
      median(iio_wake), median(iio_sample));
  std::printf(
      "IIO source at watermark 16 (as the L3GD20H here): %.2f us per sample, %.1f samples per wake-up "
      "(median of 5)\n",
      median(iio16_sample), median(iio16_per_wake));
  std::printf("IIO / L3GD20H reading cost per sample: %.2f at the same watermark (16), %.2f with IIO at 8\n",
              median(iio16_sample) / median(drv_sample), median(iio_sample) / median(drv_sample));
  // At the real pace both sleep between wake-ups and pay for being woken, as on hardware.
  constexpr double kPacedSeconds = 20.0;
  std::vector<double> paced_l3g, paced_iio16, paced_iio8;
  for (int i = 0; i < 3; ++i) {
    paced_l3g.push_back(l3gd20h_paced_us(kPacedSeconds));
    const IioResult r16 = run_iio_once(kPacedSeconds, 16, true);
    paced_iio16.push_back(r16.reader_s / static_cast<double>(r16.samples) * 1e6);
    const IioResult r8 = run_iio_once(kPacedSeconds, 8, true);
    paced_iio8.push_back(r8.reader_s / static_cast<double>(r8.samples) * 1e6);
  }
  std::printf(
      "at the real pace (%.0f s runs, median of 3): L3GD20H %.2f us per sample (watermark 16); IIO %.2f us "
      "(watermark 16), %.2f us (watermark 8)\n",
      kPacedSeconds, median(paced_l3g), median(paced_iio16), median(paced_iio8));
  std::printf(
      "IIO / L3GD20H reading cost per sample at the real pace: %.2f at the same watermark (16), %.2f with IIO "
      "at 8\n",
      median(paced_iio16) / median(paced_l3g), median(paced_iio8) / median(paced_l3g));
  std::printf("auto estimator:          %.2f us per sample (median of 5)\n", median(est_sample));
  std::printf("together: %.3f %% of one core at 400 Hz (median of 5)\n", median(share));
  return 0;
}
