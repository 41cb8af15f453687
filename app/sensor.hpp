#pragma once
// The live sensors `run` and `record` can open, by [sensor] kind. Each kind is one file pair
// (an opener and its Sensor) and one line in the table in sensor.cpp.
#include <atomic>
#include <functional>
#include <memory>
#include <string>

#include "core/sample_source.hpp"
#include "hw/sensor_options.hpp"

namespace headingd::app {

// Where a sensor's warnings go and what ends its waits.
struct SensorHooks {
  const std::atomic<bool>* stop = nullptr;
  std::function<void(int priority, const std::string& key, const std::string& text)> log;
};

// An opened live sensor.
class Sensor {
 public:
  virtual ~Sensor() = default;
  virtual core::SampleSource& source() = 0;
  // '#' lines for a recording's head: what the sensor is and how it is set up.
  virtual std::string header_comment() const = 0;
};

// Opens the sensor `options.kind` names. Throws std::runtime_error with a clear message (no such
// device, permission, wrong chip, unknown kind).
std::unique_ptr<Sensor> open_sensor(const SensorOptions& options, const SensorHooks& hooks);
// Empty when `kind` is registered; else the message naming the known kinds.
std::string unknown_sensor_kind(const std::string& kind);

}  // namespace headingd::app
