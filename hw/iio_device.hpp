#pragma once
// A Linux IIO gyro as sysfs describes it (Documentation/ABI/testing/sysfs-bus-iio): find the
// device, enable its angular-velocity and timestamp scan elements, pick a trigger and a
// sampling frequency, size and enable the buffer, and learn how to turn a scan into rad/s in
// the vehicle's frame (scale, offset, mount matrix). Everything under a root directory ("/"
// on a real machine) so tests run on a fake tree and never touch /sys.
#include <Eigen/Core>
#include <array>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "hw/iio_scan.hpp"

namespace headingd::drivers {

struct IioSettings {
  std::string root = "/";  // where sys/ and dev/ are
  // "iio:deviceN", a device name ("l3gd20h", "bmi160"), or an of_node compatible ("st,l3gd20h-gyro");
  // empty: the one device that has angular-velocity channels.
  std::string device;
  std::string trigger;                 // empty: keep the current one, else the device's own
  double sampling_frequency_hz = 0.0;  // 0: keep the device's; else the nearest it offers
  int buffer_length = 256;             // scans the kernel buffer holds (about 0.6 s at 400 Hz)
  int watermark = 7;  // scans per wake-up where the kernel supports it: 18.4 ms at 380 Hz, shorter than the 20 ms
                      // publication period
  std::optional<Eigen::Matrix3d> mount;  // overrides the device's mount matrix
  double give_up_s = 30.0;               // gone this long: the sensor is taken for dead
};

class IioError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};
// /sys is mounted read-only (under systemd: the unit's ProtectKernelTunables=). No retry mends
// it, so the daemon says so and exits as for a configuration error (78), which is not restarted.
class IioReadOnlyError : public IioError {
 public:
  using IioError::IioError;
};

// What a set-up device is and how to read it.
struct IioBinding {
  std::string sysfs_dir;  // <root>/sys/bus/iio/devices/iio:deviceN
  std::string dev_node;   // <root>/dev/iio:deviceN
  std::string id;         // iio:deviceN
  std::string name;       // the driver's device name
  std::string trigger;    // the trigger in use ("" for devices with their own FIFO)
  iio::ScanLayout layout{{}};
  std::array<std::size_t, 3> axes{};  // x, y, z: positions in layout.channels()
  std::size_t timestamp = 0;
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();  // rad/s per LSB
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  Eigen::Matrix3d mount = Eigen::Matrix3d::Identity();  // vehicle = mount * device
  double sampling_frequency_hz = 0.0;
  std::string buffer_dir;                      // buffer/ or buffer0/
  std::string temperature_path;                // in_temp_input (m degC) or in_temp_raw; "" when none
  double temp_scale = 1.0, temp_offset = 0.0;  // degC = (raw + offset) * scale / 1000 for _raw
};

// The device directory for `settings.device`, or an IioError naming what was looked for and
// what exists.
std::string find_iio_device(const IioSettings& settings);

// Configures the device and enables its buffer. Throws IioError with what to do: no such
// device, channel or trigger, permission denied (the udev rule), buffer already enabled by
// another consumer.
IioBinding bind_iio_device(const IioSettings& settings);

// Disables the buffer (best effort: the device may be gone).
void release_iio_device(const IioBinding& binding);

// Parses "x0, x1, x2; y0, y1, y2; z0, z1, z2" (the kernel's mount_matrix text).
std::optional<Eigen::Matrix3d> parse_mount_matrix(const std::string& text);

// Reads a sysfs attribute (one line, trailing newline removed); empty when it does not exist.
std::optional<std::string> read_attribute(const std::string& path);

}  // namespace headingd::drivers
