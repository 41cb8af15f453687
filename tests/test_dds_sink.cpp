// The live publication policy (pipeline/dds_sink): a publication that falls due during a
// wake-up goes out at its end, with the newest sample, and the Orientation rate holds. Against
// the register-level chip simulator (simulated time, not paced) and a real DDS node on
// loopback with no subscriber.
#include <gtest/gtest.h>

#include <memory>
#include <string>

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
  void add(const core::Sample&, const core::Estimate&, const core::Estimator&) override {
    during_samples += node_.orientation_sent() - seen_;
    seen_ = node_.orientation_sent();
  }
  void batch_done(const core::Estimator&, const core::SampleSource&) override {
    const std::uint64_t sent = node_.orientation_sent() - seen_;
    at_batch_end += sent;
    if (sent > 1) ++batches_with_several;
    seen_ = node_.orientation_sent();
  }
  std::uint64_t during_samples = 0, at_batch_end = 0, batches_with_several = 0;

 private:
  const app::DdsNode& node_;
  std::uint64_t seen_ = 0;
};

struct Counts {
  double rate_hz = 0.0;
  std::uint64_t during_samples = 0, at_batch_end = 0, batches_with_several = 0;
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
  return counts;
}

}  // namespace

// The default watermark wakes the daemon more often than Orientation is due: every message goes
// out at a wake-up's end (with its newest sample), one per wake-up at most, at 50 Hz.
TEST(DdsSinkLive, DefaultWatermarkPublishesTheNewestSampleAtFiftyHertz) {
  ASSERT_EQ(drivers::L3gd20hSettings{}.watermark, 6);
  const Counts c = run_live(6, 63);
  EXPECT_NEAR(c.rate_hz, 50.0, 0.5);
  EXPECT_EQ(c.during_samples, 0u);
  EXPECT_GT(c.at_batch_end, 2900u);
  EXPECT_EQ(c.batches_with_several, 0u);
}

// A wake-up longer than the publication period (watermark 16: 45 ms) still keeps the rate:
// the first publication time goes out when its successor falls due, the newest at the end.
TEST(DdsSinkLive, LongWakeUpsKeepTheRate) {
  const Counts c = run_live(16, 64);
  EXPECT_GT(c.rate_hz, 0.95 * 50.0);
  EXPECT_LE(c.rate_hz, 50.5);
  EXPECT_GT(c.at_batch_end, 1200u);  // one per wake-up (about 22 per second)
  EXPECT_GT(c.during_samples, 1200u);
}
