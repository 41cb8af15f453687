#include "app/sensor.hpp"

#include <array>
#include <stdexcept>

#include "app/iio_sensor.hpp"
#include "app/live_source.hpp"

namespace headingd::app {
namespace {

struct SensorKind {
  const char* name;
  std::unique_ptr<Sensor> (*open)(const SensorOptions&, const SensorHooks&);
};

// The registered sensors: one line each.
constexpr std::array kKinds = {
    SensorKind{"l3gd20h", &open_l3gd20h},
    SensorKind{"iio", &open_iio},
};

}  // namespace

std::string unknown_sensor_kind(const std::string& kind) {
  std::string known;
  for (const auto& k : kKinds) {
    if (kind == k.name) return {};
    known += std::string(known.empty() ? "\"" : ", \"") + k.name + "\"";
  }
  return "[sensor] kind is \"" + kind + "\", allowed " + known;
}

std::unique_ptr<Sensor> open_sensor(const SensorOptions& options, const SensorHooks& hooks) {
  for (const auto& k : kKinds)
    if (options.kind == k.name) return k.open(options, hooks);
  throw std::runtime_error(unknown_sensor_kind(options.kind));
}

}  // namespace headingd::app
