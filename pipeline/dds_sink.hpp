#pragma once
// Publishes over DDS (Orientation, Imu, GyroBias, Status) and hands the HeadingCommands that
// arrived to the pipeline. The DDS layer sees an Estimate, the estimator's Diagnostics and a
// StatusReport: plain values built here.
#include <chrono>

#include "dds/dds_node.hpp"
#include "dds/dds_participant.hpp"
#include "pipeline/expendable_sink.hpp"
#include "pipeline/sink.hpp"
#include "pipeline/wall_stamps.hpp"

namespace headingd::pipeline {

// How the estimate's clock becomes wall-clock time for the stamps.
enum class StampClock {
  FirstSample,  // the sample's time mapped to the wall clock (WallStamps): a sensor, or a paced recording
  EachSample,   // now, at every sample (a recording read as fast as possible)
};

class DdsSink final : public Sink, public CommandInbox {
 public:
  DdsSink(app::DdsNode& node, const core::SampleSource& source, StampClock clock,
          app::DuplicatePolicy on_duplicate = app::DuplicatePolicy::Warn, WallStamps::WallClock wall = app::wall_now_s);
  void add(const core::Sample& sample, const core::Estimate& estimate, const core::Estimator& estimator) override;
  void take(std::vector<app::ValidCommand>& out) override { node_.take_commands(out); }
  // A live sensor's publication that fell due in the batch goes out (see newest_of_wakeup_).
  // Another publisher of our topics: logged, counted on Status, and under the refuse policy
  // the run ends (RunRefused) if the other one came first.
  void batch_done(const core::Estimator& estimator, const core::SampleSource& source) override;
  // The run's dropped file outputs, for Status and /diagnostics (not owned; may be null).
  void watch_outputs(const OutputDrops* drops) { drops_ = drops; }

 private:
  app::StatusReport report(const core::Estimate& estimate);
  void log_inbound(const core::Estimator& estimator);

  app::DdsNode& node_;
  const core::SampleSource& source_;
  StampClock clock_;
  app::DuplicatePolicy on_duplicate_;
  WallStamps stamps_;
  WallStamps::WallClock wall_;
  double wall_offset_s_ = 0.0;
  double last_stamp_s_ = 0.0;
  std::uint64_t recoveries_seen_ = 0;
  double degraded_until_s_ = -1.0;  // sample time until which a recent fault shows as DEGRADED
  std::uint64_t samples_ = 0;
  std::uint32_t rivals_ = 0;
  std::uint64_t conflicts_ = 0;
  std::vector<app::Refusal> refusals_;
  core::Vec3 last_rate_dps_ = core::Vec3::Zero();
  std::uint64_t stuck_samples_ = 0;  // samples equal to the one before on all three axes
  const OutputDrops* drops_ = nullptr;
  double first_t_s_ = 0.0;
  std::chrono::steady_clock::time_point started_ = std::chrono::steady_clock::now();
  // A sensor's batch is one wake-up's samples (a FIFO burst): a publication that falls due
  // within it goes out at its end with the newest sample, not with the sample that crossed the
  // publication time, which is up to a watermark older. A wake-up longer than a period owes
  // two: the first goes out with the sample before the one that reaches the second time (two
  // distinct samples, each message's Imu rate the mean of its own samples), the second at the end.
  bool newest_of_wakeup_ = false;
  bool publication_due_ = false;
  double due_since_t_s_ = 0.0;  // the sample at which the pending publication fell due
  core::Estimate previous_;     // the sample before this one, while a publication is pending
  double previous_wall_offset_s_ = 0.0;
};

}  // namespace headingd::pipeline
