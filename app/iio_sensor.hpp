#pragma once
// [sensor] kind = "iio": any gyro a Linux IIO driver owns (hw/iio_gyro).
#include <memory>

#include "app/sensor.hpp"

namespace headingd::app {

std::unique_ptr<Sensor> open_iio(const SensorOptions& options, const SensorHooks& hooks);

}  // namespace headingd::app
