#pragma once
// The chip's data-ready line (L3GD20H DRDY/INT2, carrying the FIFO watermark). Implemented
// with libgpiod 1.6 edge events, by a timed poll when no line is wired, and by the simulator.
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>

namespace headingd::drivers {

class DataReady {
 public:
  virtual ~DataReady() = default;
  // Waits for the line's active edge. Returns the time stamp (ns, this source's monotonic
  // clock) of the latest edge seen, or nullopt on timeout. Throws std::runtime_error on failure.
  virtual std::optional<std::int64_t> wait(std::chrono::nanoseconds timeout) = 0;
  // Now, on the same clock as the edge time stamps, and a pause on that clock (the simulator's
  // clock only moves when asked, so the driver's waits go through here).
  virtual std::int64_t now_ns() const = 0;
  virtual void sleep(std::chrono::nanoseconds duration) = 0;
  // True when edges are real interrupts (time stamps mark the watermark crossing); false for
  // a timed poll, whose time stamps only bound when samples arrived.
  virtual bool has_edges() const = 0;
  virtual std::string describe() const = 0;
};

}  // namespace headingd::drivers
