#include "hw/gpiod_data_ready.hpp"

#include <gpiod.h>

#include <cerrno>
#include <cstring>
#include <ctime>
#include <stdexcept>
#include <thread>

#include "hw/linux_i2c_bus.hpp"

namespace headingd::drivers {
namespace {

std::int64_t monotonic_ns() {
  timespec ts{};
  ::clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

void sleep_monotonic(std::chrono::nanoseconds duration) { std::this_thread::sleep_for(duration); }

}  // namespace

GpiodDataReady::GpiodDataReady(const GpioLineSettings& settings) : settings_(settings) {
  // Open by path, number or name directly (gpiod_chip_open_lookup tries them all and leaves
  // the last attempt's errno, which hides a "permission denied"); fall back to a label.
  const std::string& chip = settings_.chip;
  const bool is_number = !chip.empty() && chip.find_first_not_of("0123456789") == std::string::npos;
  errno = 0;
  if (chip.find('/') != std::string::npos) {
    chip_ = ::gpiod_chip_open(chip.c_str());
  } else if (is_number) {
    chip_ = ::gpiod_chip_open_by_number(static_cast<unsigned>(std::stoul(chip)));
  } else {
    chip_ = ::gpiod_chip_open_by_name(chip.c_str());
    if (chip_ == nullptr && errno == ENOENT) {
      chip_ = ::gpiod_chip_open_by_label(chip.c_str());
      if (chip_ == nullptr) errno = ENOENT;
    }
  }
  if (chip_ == nullptr) {
    const int error_number = errno != 0 ? errno : ENOENT;
    const std::string path = settings_.chip.find('/') == std::string::npos ? "/dev/" + settings_.chip : settings_.chip;
    throw std::runtime_error(LinuxI2cBus::open_error("GPIO chip", path, error_number, "gpio"));
  }
  line_ = ::gpiod_chip_get_line(chip_, settings_.offset);
  if (line_ == nullptr) {
    const int error_number = errno;
    ::gpiod_chip_close(chip_);
    throw std::runtime_error("GPIO chip " + settings_.chip + " has no line " + std::to_string(settings_.offset) + ": " +
                             std::strerror(error_number));
  }
  const int result = settings_.falling_edge
                         ? ::gpiod_line_request_falling_edge_events(line_, settings_.consumer.c_str())
                         : ::gpiod_line_request_rising_edge_events(line_, settings_.consumer.c_str());
  if (result < 0) {
    const int error_number = errno;
    ::gpiod_chip_close(chip_);
    throw std::runtime_error(
        "cannot request GPIO " + settings_.chip + " line " + std::to_string(settings_.offset) +
        " for edge events: " + std::strerror(error_number) +
        (error_number == EBUSY ? " (another program or driver holds the line: see gpioinfo)" : ""));
  }
}

GpiodDataReady::~GpiodDataReady() {
  if (line_ != nullptr) ::gpiod_line_release(line_);
  if (chip_ != nullptr) ::gpiod_chip_close(chip_);
}

std::string GpiodDataReady::describe() const {
  return settings_.chip + " line " + std::to_string(settings_.offset) +
         (settings_.falling_edge ? " falling" : " rising");
}

std::optional<std::int64_t> GpiodDataReady::wait(std::chrono::nanoseconds timeout) {
  timespec ts{static_cast<time_t>(timeout.count() / 1'000'000'000), static_cast<long>(timeout.count() % 1'000'000'000)};
  const int ready = ::gpiod_line_event_wait(line_, &ts);
  if (ready < 0) throw std::runtime_error(describe() + ": waiting for an edge: " + std::strerror(errno));
  if (ready == 0) return std::nullopt;
  // Read every queued event (the kernel keeps up to 16) and keep the newest time stamp.
  gpiod_line_event events[16];
  const int count = ::gpiod_line_event_read_multiple(line_, events, 16);
  if (count <= 0) throw std::runtime_error(describe() + ": reading edge events: " + std::strerror(errno));
  const auto& newest = events[count - 1].ts;
  return static_cast<std::int64_t>(newest.tv_sec) * 1'000'000'000 + newest.tv_nsec;
}

std::int64_t GpiodDataReady::now_ns() const { return monotonic_ns(); }
void GpiodDataReady::sleep(std::chrono::nanoseconds duration) { sleep_monotonic(duration); }

std::optional<std::int64_t> PollDataReady::wait(std::chrono::nanoseconds timeout) {
  sleep_monotonic(std::min(period_, timeout));
  return std::nullopt;
}
std::int64_t PollDataReady::now_ns() const { return monotonic_ns(); }
void PollDataReady::sleep(std::chrono::nanoseconds duration) { sleep_monotonic(duration); }

}  // namespace headingd::drivers
