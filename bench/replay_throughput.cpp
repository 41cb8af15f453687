// Replay throughput: the whole `headingd replay` path on a file (parse, estimate, write the
// 10 Hz estimates), and the core alone on samples already in memory. Medians of repeated
// runs, since the machine is shared.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "app/replay_command.hpp"
#include "core/estimator.hpp"
#include "core/memory_source.hpp"
#include "io/csv_replay.hpp"
#include "machine.hpp"
#include "pipeline/pipeline.hpp"
#include "sim/gyro_simulator.hpp"

using namespace headingd;

namespace {

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

template <typename F>
double seconds_of(F&& run) {
  const auto start = std::chrono::steady_clock::now();
  run();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

int main(int argc, char** argv) {
  const int repeats = 5;
  std::printf("machine: %s\n", bench::machine_description().c_str());

  // Core alone: the recording's samples (or an hour of the paper's protocol when none is
  // given) in memory, through the estimator.
  std::vector<core::Sample> samples;
  if (argc >= 2) {
    drivers::CsvReplaySource source(argv[1]);
    std::vector<core::Sample> batch(4096);
    while (const std::size_t got = source.read(batch))
      samples.insert(samples.end(), batch.begin(), batch.begin() + static_cast<std::ptrdiff_t>(got));
  } else {
    drivers::GyroSimulator sim(*drivers::build_scenario("paper12h", 1, 1.0), 1);
    drivers::TruthPoint truth;
    samples.resize(sim.scenario().total_samples);
    for (auto& sample : samples) sim.step(sample, truth);
  }
  std::vector<double> core_s;
  core_s.reserve(static_cast<std::size_t>(repeats));
  double sink = 0.0;
  for (int r = 0; r < repeats; ++r) {
    core_s.push_back(seconds_of([&] {
      core::MemorySource source(samples);
      pipeline::PipelineOptions options;
      options.batch = 4096;
      pipeline::Pipeline line(source, std::make_unique<core::Estimator>(), options);
      line.run();
      sink += line.estimator().last().heading_deg;
    }));
  }
  const double core_median = median(core_s);
  std::printf(
      "core through the pipeline (no sinks): %.1f million samples/s, %.1f ns/sample (median of %d runs over %zu "
      "samples)%s\n",
      static_cast<double>(samples.size()) / core_median / 1e6, core_median / static_cast<double>(samples.size()) * 1e9,
      repeats, samples.size(), sink == 0.123 ? " " : "");

  // `replay_throughput FILE core`: the core alone, for a profiler.
  if (argc < 2 || (argc >= 3 && std::string(argv[2]) == "core")) return 0;
  // The reader alone: every sample of the file parsed and checked, nothing estimated.
  std::vector<double> read_s;
  read_s.reserve(3);
  for (int r = 0; r < 3; ++r) {
    read_s.push_back(seconds_of([&] {
      drivers::CsvReplaySource source(argv[1]);
      std::vector<core::Sample> batch(4096);
      while (const std::size_t got = source.read(batch)) sink += batch[got - 1].rate_dps.z();
    }));
  }
  std::printf("reading %s alone (parse and checks): %.2f s (median of 3 runs)%s\n", argv[1], median(read_s),
              sink == 0.123 ? " " : "");
  // Whole replay path on a file, estimates at 10 Hz to /dev/null.
  app::ReplayOptions options;
  options.input = argv[1];
  options.output = "/dev/null";
  options.quiet = true;
  std::vector<double> replay_s;
  const int file_repeats = 3;
  for (int r = 0; r < file_repeats; ++r) {
    int code = 0;
    replay_s.push_back(seconds_of([&] { code = app::run_replay(options); }));
    if (code != 0) {
      std::fprintf(stderr, "replay failed with exit code %d\n", code);
      return code;
    }
  }
  std::printf("replay %s: %.2f s (median of %d runs)\n", argv[1], median(replay_s), file_repeats);
  return 0;
}
