// A replay's fast path (Estimator::advance for the samples no sink wants) changes no output: the
// 10 Hz estimates of a random world (turns, creep, stops, temperature), written once as a replay
// writes them and once with a sink beside them that asks for every sample (so that every sample
// takes update()), are the same bytes, segment verdicts (the `still` column) included.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "core/estimator.hpp"
#include "core/memory_source.hpp"
#include "pipeline/estimates_sink.hpp"
#include "pipeline/pipeline.hpp"
#include "sim/gyro_simulator.hpp"
#include "temp_dir.hpp"

using namespace headingd;

namespace {

class EverySample final : public pipeline::Sink {
 public:
  void add(const core::Sample&, const core::Estimate&, const core::Estimator&) override { ++count; }
  std::size_t count = 0;
};

std::string contents(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::vector<core::Sample> random_world(std::uint64_t seed) {
  drivers::GyroSimulator sim(*drivers::build_scenario("random", seed, 0.25), seed);
  std::vector<core::Sample> samples;
  core::Sample sample;
  drivers::TruthPoint truth;
  while (!sim.done()) {
    sim.step(sample, truth);
    samples.push_back(sample);
  }
  return samples;
}

// Replays `samples` with and without a sink that wants every sample; the two estimate files.
void expect_the_same_bytes(const std::vector<core::Sample>& samples, double rate_hz) {
  test::TempDir dir;
  const auto replay = [&](const std::string& path, EverySample* every) {
    core::MemorySource source(samples);
    pipeline::PipelineOptions options;
    options.batch = 4096;
    pipeline::Pipeline line(source, std::make_unique<core::Estimator>(), options);
    pipeline::EstimatesSink out(path, rate_hz, 0.0, 3.0);
    line.add_sink(out);
    if (every != nullptr) line.add_sink(*every);
    const pipeline::Outcome outcome = line.run();
    EXPECT_EQ(outcome.ending, pipeline::Ending::EndOfInput);
    EXPECT_EQ(outcome.samples, samples.size());
    return out.rows_written();
  };
  EverySample every;
  const std::uint64_t rows_fast = replay(dir.path("fast.csv"), nullptr);
  const std::uint64_t rows_slow = replay(dir.path("slow.csv"), &every);
  EXPECT_EQ(every.count, samples.size());  // the second run did take every sample through update()
  EXPECT_EQ(rows_fast, rows_slow);
  EXPECT_GT(static_cast<double>(rows_fast), 0.9 * 900.0 * rate_hz);  // 15 minutes, less any holes
  const std::string fast = contents(dir.path("fast.csv"));
  EXPECT_EQ(fast, contents(dir.path("slow.csv")));
  EXPECT_NE(fast.find(",1\n"), std::string::npos);  // still segments reached the writer
  EXPECT_NE(fast.find(",0\n"), std::string::npos);
}

}  // namespace

TEST(PipelineFastPath, TheEstimatesAreTheSameBytesWithAndWithout) { expect_the_same_bytes(random_world(5), 10.0); }

TEST(PipelineFastPath, AndSoAreTheyAcrossGapsInTheSamples) {
  // Holes of 0.12-0.66 s every 20 s (lost FIFOs, a chip set up again), between the 1 Hz instants
  // a sink asks for, so that the fast path meets them: update() bridges them, and the fast path
  // must leave each to it.
  std::vector<core::Sample> samples;
  for (const core::Sample& s : random_world(5)) {
    const double in_period_s = std::fmod(s.t_s, 20.0);
    const double hole_s = 0.12 + 0.06 * std::fmod(std::floor(s.t_s / 20.0), 10.0);
    if (in_period_s >= 10.2 && in_period_s < 10.2 + hole_s) continue;
    samples.push_back(s);
  }
  expect_the_same_bytes(samples, 1.0);
  core::Estimator estimator;
  for (const core::Sample& s : samples) estimator.update(s);
  EXPECT_GE(estimator.diagnostics().gaps_bridged, 40u);
}
