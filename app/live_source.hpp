#pragma once
// Opens the live sensor for `run` and `record`: the L3GD20H on a Linux I2C bus with its
// DRDY/INT2 line on a GPIO (or a timed poll), or the register-level simulator standing in for
// chip, bus and line (hidden option, for tests and demos on machines without hardware).
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "app/sensor.hpp"
#include "hw/data_ready.hpp"
#include "hw/i2c_bus.hpp"
#include "hw/l3gd20h.hpp"
#include "hw/sensor_options.hpp"
#include "sim/l3gd20h_sim.hpp"

namespace headingd::app {

class LiveSource final : public Sensor {
 public:
  // Throws std::runtime_error (device missing, permission, wrong chip) with a clear message.
  explicit LiveSource(const SensorOptions& options);
  drivers::L3gd20h& driver() { return *driver_; }
  core::SampleSource& source() override { return *driver_; }
  // The simulator standing in for the chip, if one does (soak tests inject faults through it).
  drivers::L3gd20hSimulator* simulator() { return simulator_.get(); }
  std::string header_comment() const override;  // '#' lines naming sensor, settings, rate, sensitivity

 private:
  SensorOptions options_;
  std::unique_ptr<drivers::L3gd20hSimulator> simulator_;
  std::unique_ptr<drivers::I2cBus> bus_;
  std::unique_ptr<drivers::DataReady> ready_;
  std::unique_ptr<drivers::L3gd20h> driver_;
};

// [sensor] kind = "l3gd20h" (the default), for the registry in sensor.cpp.
std::unique_ptr<Sensor> open_l3gd20h(const SensorOptions& options, const SensorHooks& hooks);

}  // namespace headingd::app
