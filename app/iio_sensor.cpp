#include "app/iio_sensor.hpp"

#include "hw/iio_gyro.hpp"

namespace headingd::app {
namespace {

class IioSensor final : public Sensor {
 public:
  IioSensor(const drivers::IioSettings& settings, const SensorHooks& hooks) : gyro_(settings) {
    gyro_.set_stop_flag(hooks.stop);
    if (hooks.log) gyro_.set_logger(hooks.log);
  }
  core::SampleSource& source() override { return gyro_; }
  std::string header_comment() const override { return gyro_.header_comment(); }

 private:
  drivers::IioGyro gyro_;
};

}  // namespace

std::unique_ptr<Sensor> open_iio(const SensorOptions& options, const SensorHooks& hooks) {
  return std::make_unique<IioSensor>(options.iio, hooks);
}

}  // namespace headingd::app
