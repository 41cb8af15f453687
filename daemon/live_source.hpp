#pragma once
// Opens the live sensor for `run` and `record`: the L3GD20H on a Linux I2C bus with its
// DRDY/INT2 line on a GPIO (or a timed poll), or the register-level simulator standing in for
// chip, bus and line (hidden option, for tests and demos on machines without hardware).
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "drivers/data_ready.hpp"
#include "drivers/i2c_bus.hpp"
#include "drivers/l3gd20h.hpp"
#include "drivers/l3gd20h_sim.hpp"

namespace headingd::app {

struct SensorOptions {
  std::string bus = "/dev/i2c-1";
  int address = 0x6B;
  int rate_hz = 400;
  int bandwidth = 2;
  int full_scale_dps = 245;
  int watermark = 16;
  std::optional<std::string> gpio_chip;  // unset: timed poll
  unsigned gpio_line = 0;
  bool int2_active_low = false;
  // The simulator instead of hardware: motion scenario, seed, part-to-part rate error.
  std::optional<std::string> simulated_chip;
  std::uint64_t sim_seed = 1;
  double sim_rate_error = 0.0;
  bool sim_realtime = false;       // the simulator runs at the chip's real pace
  double sim_dead_after_s = -1.0;  // the simulated sensor dies after this long
};

class LiveSource {
 public:
  // Throws std::runtime_error (device missing, permission, wrong chip) with a clear message.
  explicit LiveSource(const SensorOptions& options);
  drivers::L3gd20h& driver() { return *driver_; }
  // The simulator standing in for the chip, if one does (soak tests inject faults through it).
  drivers::L3gd20hSimulator* simulator() { return simulator_.get(); }
  std::string header_comment() const;  // '#' lines naming sensor, settings, rate, sensitivity

 private:
  SensorOptions options_;
  std::unique_ptr<drivers::L3gd20hSimulator> simulator_;
  std::unique_ptr<drivers::I2cBus> bus_;
  std::unique_ptr<drivers::DataReady> ready_;
  std::unique_ptr<drivers::L3gd20h> driver_;
};

}  // namespace headingd::app
