#pragma once
// DataReady over libgpiod 1.6 (the v1 API in Debian 12): one line of a gpiochip requested for
// edge events under a consumer label. Event time stamps are CLOCK_MONOTONIC on Linux >= 5.7
// (docs/l3gd20h.md section 7), the clock now_ns() reads.
#include <string>

#include "hw/data_ready.hpp"

struct gpiod_chip;
struct gpiod_line;

namespace headingd::drivers {

struct GpioLineSettings {
  std::string chip = "gpiochip0";  // name (under /dev), path, label or number
  unsigned offset = 0;
  bool falling_edge = false;  // true when INT2 is configured active-low
  std::string consumer = "headingd";
};

class GpiodDataReady final : public DataReady {
 public:
  // Throws std::runtime_error naming the chip, the line and the likely fix.
  explicit GpiodDataReady(const GpioLineSettings& settings);
  ~GpiodDataReady() override;
  GpiodDataReady(const GpiodDataReady&) = delete;
  GpiodDataReady& operator=(const GpiodDataReady&) = delete;

  std::optional<std::int64_t> wait(std::chrono::nanoseconds timeout) override;
  std::int64_t now_ns() const override;
  void sleep(std::chrono::nanoseconds duration) override;
  bool has_edges() const override { return true; }
  std::string describe() const override;

 private:
  GpioLineSettings settings_;
  gpiod_chip* chip_ = nullptr;
  gpiod_line* line_ = nullptr;
};

// No line wired: wake every `period` and let the driver look at the FIFO.
class PollDataReady final : public DataReady {
 public:
  explicit PollDataReady(std::chrono::nanoseconds period) : period_(period) {}
  std::optional<std::int64_t> wait(std::chrono::nanoseconds timeout) override;
  std::int64_t now_ns() const override;
  void sleep(std::chrono::nanoseconds duration) override;
  bool has_edges() const override { return false; }
  std::string describe() const override { return "timed poll"; }

 private:
  std::chrono::nanoseconds period_;
};

}  // namespace headingd::drivers
