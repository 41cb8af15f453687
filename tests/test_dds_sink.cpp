// The live publication policy (pipeline/dds_sink): a publication that falls due during a
// wake-up goes out at its end, with the newest sample, and the Orientation rate holds. Against
// the register-level chip simulator (simulated time, not paced) and a real DDS node on
// loopback with no subscriber.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "core/estimator.hpp"
#include "dds/dds_node.hpp"
#include "hw/l3gd20h.hpp"
#include "pipeline/dds_sink.hpp"
#include "pipeline/pipeline.hpp"
#include "sim/l3gd20h_sim.hpp"

using namespace headingd;

namespace {

// After the DdsSink: when Orientation messages went out, during a sample or at a batch's end.
class PublicationWatch final : public pipeline::Sink {
 public:
  explicit PublicationWatch(const app::DdsNode& node) : node_(node) {}
  void add(const core::Sample& sample, const core::Estimate&, const core::Estimator&) override {
    batch_t_s_.push_back(sample.t_s);
    note(during_samples);
  }
  void batch_done(const core::Estimator&, const core::SampleSource&) override {
    const std::uint64_t sent = node_.orientation_sent() - seen_;
    note(at_batch_end);
    if (sent > 1) ++batches_with_several;
    // How many of the wake-up's samples are newer than the one a message carried.
    for (const double carried : carried_t_s_) {
      const auto newer = std::count_if(batch_t_s_.begin(), batch_t_s_.end(), [&](double t) { return t > carried; });
      most_samples_behind = std::max(most_samples_behind, static_cast<std::uint64_t>(newer));
    }
    carried_t_s_.clear();
    batch_t_s_.clear();
  }
  std::uint64_t during_samples = 0, at_batch_end = 0, batches_with_several = 0, most_samples_behind = 0;
  std::uint64_t same_sample_twice = 0;

 private:
  void note(std::uint64_t& counter) {
    if (node_.orientation_sent() == seen_) return;
    counter += node_.orientation_sent() - seen_;
    seen_ = node_.orientation_sent();
    const double carried = node_.orientation_sample_t_s();
    if (carried == last_carried_t_s_) ++same_sample_twice;
    last_carried_t_s_ = carried;
    carried_t_s_.push_back(carried);
  }
  const app::DdsNode& node_;
  std::uint64_t seen_ = 0;
  double last_carried_t_s_ = -1.0;
  std::vector<double> batch_t_s_, carried_t_s_;
};

struct Counts {
  double rate_hz = 0.0;
  std::uint64_t during_samples = 0, at_batch_end = 0, batches_with_several = 0, most_samples_behind = 0;
  std::uint64_t same_sample_twice = 0;
};

Counts run_live(int watermark, int domain) {
  app::DdsSettings settings;
  settings.domain_id = domain;
  settings.profiles_xml = std::string(HEADINGD_SOURCE_DIR) + "/config/fastdds-loopback.xml";
  app::DdsNode node(settings);
  drivers::L3gd20hSimulator chip({}, "agv", 3);
  drivers::L3gd20hSettings driver_settings;
  driver_settings.watermark = watermark;
  drivers::L3gd20h driver(chip, chip, driver_settings);
  driver.start();
  pipeline::PipelineOptions options;
  options.duration_s = 60.0;
  pipeline::Pipeline line(driver, std::make_unique<core::Estimator>(), options);
  pipeline::DdsSink publisher(node, driver, pipeline::StampClock::FirstSample);
  PublicationWatch watch(node);
  line.add_sink(publisher);
  line.add_sink(watch);
  const pipeline::Outcome outcome = line.run();
  Counts counts;
  counts.rate_hz = static_cast<double>(node.orientation_sent()) / (outcome.last_t_s - outcome.first_t_s);
  counts.during_samples = watch.during_samples;
  counts.at_batch_end = watch.at_batch_end;
  counts.batches_with_several = watch.batches_with_several;
  counts.most_samples_behind = watch.most_samples_behind;
  counts.same_sample_twice = watch.same_sample_twice;
  return counts;
}

}  // namespace

// Watermark 6 wakes the daemon more often than Orientation is due: every message goes out at a
// wake-up's end (with its newest sample), one per wake-up at most, at 50 Hz.
TEST(DdsSinkLive, WakeUpsShorterThanThePeriodPublishTheNewestSampleAtFiftyHertz) {
  const Counts c = run_live(6, 63);
  EXPECT_NEAR(c.rate_hz, 50.0, 0.5);
  EXPECT_EQ(c.during_samples, 0u);
  EXPECT_GT(c.at_batch_end, 2900u);
  EXPECT_EQ(c.batches_with_several, 0u);
  EXPECT_EQ(c.most_samples_behind, 0u);
  EXPECT_EQ(c.same_sample_twice, 0u);
}

// The default, 8, wakes it every 23.8 ms (9 samples), a little longer than the period: the rate
// holds, each message carries the wake-up's newest sample or, when a wake-up owes two, the one
// before it, and no two messages carry the same sample (their Imu rate windows would be empty).
TEST(DdsSinkLive, DefaultWatermarkPublishesYoungSamplesAtFiftyHertz) {
  ASSERT_EQ(drivers::L3gd20hSettings{}.watermark, 8);
  const Counts c = run_live(8, 65);
  std::printf("watermark 8: %.2f Hz, %llu at a wake-up's end, %llu during it, at most %llu samples behind\n", c.rate_hz,
              static_cast<unsigned long long>(c.at_batch_end), static_cast<unsigned long long>(c.during_samples),
              static_cast<unsigned long long>(c.most_samples_behind));
  EXPECT_NEAR(c.rate_hz, 50.0, 0.5);
  EXPECT_GT(c.at_batch_end, 2000u);
  EXPECT_LE(c.most_samples_behind, 1u);
  EXPECT_EQ(c.same_sample_twice, 0u);
}

// A wake-up longer than the publication period (watermark 16: 45 ms) still keeps the rate:
// the first publication time goes out when its successor falls due, the newest at the end.
TEST(DdsSinkLive, LongWakeUpsKeepTheRate) {
  const Counts c = run_live(16, 64);
  EXPECT_GT(c.rate_hz, 0.95 * 50.0);
  EXPECT_LE(c.rate_hz, 50.5);
  EXPECT_GT(c.at_batch_end, 1200u);  // one per wake-up (about 22 per second)
  EXPECT_GT(c.during_samples, 1200u);
  EXPECT_EQ(c.same_sample_twice, 0u);
}
