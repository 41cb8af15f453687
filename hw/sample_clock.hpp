#pragma once
// Reconstructs sample time stamps from (sample index, time) anchors — the watermark edge's
// kernel time stamp marks when a known sample was produced — and estimates the chip's real
// output rate over a long baseline (the datasheet's "400 Hz" is 378.8 Hz typical, +-15 % part
// to part, so a fixed period would drift seconds per hour).
#include <cstdint>

namespace headingd::drivers {

class SampleClock {
 public:
  explicit SampleClock(double nominal_hz);

  // Sample `index` was produced at t_ns (an edge time stamp, or a poll's read time). A
  // provisional anchor (a rough time, before any edge) places stamps but does not start the
  // baseline the rate is measured over.
  void anchor(std::uint64_t index, std::int64_t t_ns, bool provisional = false);
  // Time stamp of sample `index`, strictly after the previous one handed out.
  std::int64_t stamp(std::uint64_t index);
  double rate_hz() const { return 1e9 / period_ns_; }
  double period_ns() const { return period_ns_; }
  // Forget the history (after the chip was reset: its sample counter starts again).
  void restart();
  bool anchored() const { return has_last_; }

 private:
  double nominal_period_ns_;
  double period_ns_;
  bool has_base_ = false, has_last_ = false, has_mid_ = false;
  std::uint64_t base_index_ = 0, last_index_ = 0, mid_index_ = 0;
  std::int64_t base_ns_ = 0, last_ns_ = 0, mid_ns_ = 0;
  std::int64_t previous_stamp_ns_ = 0;
  bool stamped_ = false;
};

}  // namespace headingd::drivers
