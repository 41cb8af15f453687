#pragma once
// How to reach the gyro, as the operator writes it in [sensor] or on the command line. A plain
// value: the configuration parser fills it without knowing any driver or simulator.
#include <cstdint>
#include <optional>
#include <string>

#include "hw/iio_device.hpp"

namespace headingd::app {

struct SensorOptions {
  // Which sensor: "l3gd20h" (our own driver over i2c-dev) or "iio" (any gyro a Linux IIO driver owns).
  std::string kind = "l3gd20h";
  drivers::IioSettings iio;  // [sensor.iio]
  std::string bus = "/dev/i2c-1";
  int address = 0x6B;
  int rate_hz = 400;
  int bandwidth = 2;
  int full_scale_dps = 245;
  int watermark = 8;
  std::optional<std::string> gpio_chip;  // unset: timed poll
  unsigned gpio_line = 0;
  bool int2_active_low = false;
  // The simulator instead of hardware: motion scenario, seed, part-to-part rate error.
  std::optional<std::string> simulated_chip;
  std::uint64_t sim_seed = 1;
  double sim_rate_error = 0.0;
  bool sim_realtime = false;       // the simulator runs at the chip's real pace
  double sim_dead_after_s = -1.0;  // the simulated sensor dies after this long
  double sim_nack_at_s = -1.0;     // a burst of NACKs (bus errors) at this time
  double sim_stuck_at_s = -1.0;    // the output stuck for 3 s from this time
};

}  // namespace headingd::app
