// A replay's fast path (Estimator::advance for the samples no sink wants) changes no output: the
// 10 Hz estimates of a random world (turns, creep, stops, temperature), written once as a replay
// writes them and once with a sink beside them that asks for every sample (so that every sample
// takes update()), are the same bytes, segment verdicts (the `still` column) included.
#include <gtest/gtest.h>

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

}  // namespace

TEST(PipelineFastPath, TheEstimatesAreTheSameBytesWithAndWithout) {
  const std::uint64_t seed = 5;
  drivers::GyroSimulator sim(*drivers::build_scenario("random", seed, 0.25), seed);
  std::vector<core::Sample> samples;
  core::Sample sample;
  drivers::TruthPoint truth;
  while (!sim.done()) {
    sim.step(sample, truth);
    samples.push_back(sample);
  }
  test::TempDir dir;
  const auto replay = [&](const std::string& path, EverySample* every) {
    core::MemorySource source(samples);
    pipeline::PipelineOptions options;
    options.batch = 4096;
    pipeline::Pipeline line(source, std::make_unique<core::Estimator>(), options);
    pipeline::EstimatesSink out(path, 10.0, 0.0, 3.0);
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
  EXPECT_GT(rows_fast, 8000u);  // 15 minutes at 10 Hz
  const std::string fast = contents(dir.path("fast.csv"));
  EXPECT_EQ(fast, contents(dir.path("slow.csv")));
  EXPECT_NE(fast.find(",1\n"), std::string::npos);  // still segments reached the writer
  EXPECT_NE(fast.find(",0\n"), std::string::npos);
}
