#include "app/live_source.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "hw/gpiod_data_ready.hpp"
#include "hw/kernel_binding.hpp"
#include "hw/linux_i2c_bus.hpp"
#include "hw/sensor_limits.hpp"

namespace headingd::app {
namespace {

// The simulator's fault times come from hidden test switches, in seconds: negative is off. NaN and
// anything beyond a year (no test waits that long; past 292 years the nanoseconds overflow int64)
// are refused by name rather than cast into undefined behaviour.
std::int64_t fault_time_ns(const char* option, double seconds) {
  constexpr double kYearS = 365.25 * 86400.0;
  if (seconds < 0.0) return -1;
  if (!(seconds <= kYearS))
    throw std::runtime_error(std::string("sensor settings: ") + option + " must be a time in seconds up to a year");
  return static_cast<std::int64_t>(seconds * 1e9);
}

}  // namespace

LiveSource::LiveSource(const SensorOptions& options) : options_(options) {
  if (const auto allowed = drivers::address_not_allowed(options.address))
    throw std::runtime_error("sensor settings: address must be " + *allowed);
  drivers::L3gd20hSettings settings;
  settings.address = static_cast<std::uint8_t>(options.address);
  settings.rate_hz = options.rate_hz;
  settings.bandwidth = options.bandwidth;
  settings.full_scale_dps = options.full_scale_dps;
  settings.watermark = options.watermark;
  settings.int2_active_low = options.int2_active_low;
  if (const auto problem = drivers::validate(settings)) throw std::runtime_error("sensor settings: " + *problem);

  drivers::I2cBus* bus = nullptr;
  drivers::DataReady* ready = nullptr;
  if (options.simulated_chip) {
    drivers::L3gd20hSimSettings sim;
    sim.address = settings.address;
    // The datasheet's ODR tolerance is +-15 %; a factor at or below -1 would stop the simulated clock.
    if (!(std::fabs(options.sim_rate_error) <= 0.5))
      throw std::runtime_error("sensor settings: --sim-rate-error must lie within -0.5..0.5");
    sim.rate_error = options.sim_rate_error;
    simulator_ = std::make_unique<drivers::L3gd20hSimulator>(sim, *options.simulated_chip, options.sim_seed);
    simulator_->set_realtime(options.sim_realtime);
    const auto dead_ns = fault_time_ns("--sim-dead-after", options.sim_dead_after_s);
    const auto nack_ns = fault_time_ns("--sim-nack-at", options.sim_nack_at_s);
    const auto stuck_ns = fault_time_ns("--sim-stuck-at", options.sim_stuck_at_s);
    if (dead_ns >= 0) simulator_->inject_dead_after(dead_ns);
    if (nack_ns >= 0) simulator_->inject_nack_at(nack_ns, 3);
    if (stuck_ns >= 0) simulator_->inject_stuck_at(stuck_ns, 3'000'000'000);
    bus = simulator_.get();
    ready = simulator_.get();
  } else {
    // Before the bus is even opened: a kernel driver that owns the chip is never overridden.
    if (const auto driver = drivers::bound_kernel_driver(drivers::sysfs_root(), options.bus, options.address))
      throw std::runtime_error(drivers::kernel_driver_message(options.bus, options.address, *driver));
    bus_ = std::make_unique<drivers::LinuxI2cBus>(options.bus);
    if (options.gpio_chip) {
      drivers::GpioLineSettings line;
      line.chip = *options.gpio_chip;
      line.offset = options.gpio_line;
      line.falling_edge = options.int2_active_low;
      ready_ = std::make_unique<drivers::GpiodDataReady>(line);
    } else {
      // No interrupt line: look at the FIFO a little faster than it reaches the watermark.
      const double typical_hz = options.rate_hz * 0.947;
      ready_ = std::make_unique<drivers::PollDataReady>(
          std::chrono::nanoseconds(static_cast<std::int64_t>(0.5 * options.watermark / typical_hz * 1e9)));
    }
    bus = bus_.get();
    ready = ready_.get();
  }
  driver_ = std::make_unique<drivers::L3gd20h>(*bus, *ready, settings);
  driver_->start();
}

std::string LiveSource::header_comment() const {
  char text[512];
  std::snprintf(
      text, sizeof text,
      "# sensor: ST L3GD20H at 0x%02x on %s%s\n"
      "# settings: ODR %d Hz nominal, bandwidth code %d, full scale +-%d dps (%.2f mdps/LSB), FIFO dynamic "
      "stream, watermark %d, data-ready %s\n"
      "# recorded by: headingd (record, or run --record); time_s is the driver's reconstructed monotonic time\n",
      options_.address, options_.simulated_chip ? "the simulated bus" : options_.bus.c_str(),
      options_.simulated_chip
          ? (" (simulator, scenario " + *options_.simulated_chip + ", seed " + std::to_string(options_.sim_seed) + ")")
                .c_str()
          : "",
      options_.rate_hz, options_.bandwidth, options_.full_scale_dps, driver_->sensitivity_dps() * 1000.0,
      options_.watermark,
      options_.simulated_chip
          ? "simulated INT2"
          : (options_.gpio_chip ? (*options_.gpio_chip + " line " + std::to_string(options_.gpio_line)).c_str()
                                : "timed poll"));
  return text;
}

std::unique_ptr<Sensor> open_l3gd20h(const SensorOptions& options, const SensorHooks& hooks) {
  auto sensor = std::make_unique<LiveSource>(options);
  sensor->driver().set_stop_flag(hooks.stop);
  if (hooks.log) sensor->driver().set_logger(hooks.log);
  return sensor;
}

}  // namespace headingd::app
